#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""pty_join - two pseudo-terminals joined back to back like a null-modem
cable: what the program on one end writes, the program on the other end
reads. Two of our own tools (a half-duplex master and a slave station) can
then talk over a serial line without hardware.

    pty_join.py LINK_A LINK_B

makes LINK_A and LINK_B symbolic links to the two terminals, prints
"ready" on stdout, and copies bytes both ways until SIGTERM.
"""
import os
import select
import signal
import sys
import tty


def main():
    links = sys.argv[1:3]
    if len(links) != 2:
        sys.stderr.write("usage: pty_join.py LINK_A LINK_B\n")
        return 2
    ends = [os.openpty(), os.openpty()]
    for (master, slave), link in zip(ends, links):
        tty.setraw(slave)  # no echo, no line discipline until a program sets its own
        if os.path.lexists(link):
            os.unlink(link)
        os.symlink(os.ttyname(slave), link)
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    print("ready", flush=True)
    masters = [ends[0][0], ends[1][0]]
    while not stop:
        try:
            ready, _, _ = select.select(masters, [], [], 0.5)
        except InterruptedError:
            continue
        for i, fd in enumerate(masters):
            if fd not in ready:
                continue
            try:
                data = os.read(fd, 4096)
            except OSError:  # the other program closed its end for a moment
                continue
            if data:
                os.write(masters[1 - i], data)
    for link in links:
        if os.path.islink(link):
            os.unlink(link)
    return 0


if __name__ == "__main__":
    sys.exit(main())
