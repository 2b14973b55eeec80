#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""multidrop - an RS-485 multidrop line for the tests: N ptys joined so that
what any one of them writes reaches all the others (not itself: a 4-wire
line, no echo). Each pty's device path is linked as PREFIX.0 .. PREFIX.N-1;
"ready" is printed on stdout when they are all there. Runs until killed.

    multidrop.py PREFIX N
"""
import os
import pty
import select
import sys
import termios
import tty


def main():
    prefix, n = sys.argv[1], int(sys.argv[2])
    masters = []
    keep = []
    for i in range(n):
        m, s = pty.openpty()
        tty.setraw(s)
        attrs = termios.tcgetattr(s)
        attrs[3] &= ~termios.ECHO
        termios.tcsetattr(s, termios.TCSANOW, attrs)
        link = "%s.%d" % (prefix, i)
        if os.path.lexists(link):
            os.unlink(link)
        os.symlink(os.ttyname(s), link)
        masters.append(m)
        keep.append(s)  # held open: a pty whose other side closes gives EIO
    print("ready", flush=True)
    while True:
        readable, _, _ = select.select(masters, [], [])
        for m in readable:
            try:
                data = os.read(m, 4096)
            except OSError:
                continue
            for other in masters:
                if other != m:
                    os.write(other, data)


if __name__ == "__main__":
    main()
