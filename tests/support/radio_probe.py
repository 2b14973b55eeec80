#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""radio_probe - writes and reads on the nodes of tests/support/radio_channel.py
for it_radio_channel.sh: opens the pty of each node named, runs the steps in
order, then reads on until the channel has been quiet for IDLE seconds
(default 1; at most 20 s in all) and reports what each node received.

    radio_probe.py PREFIX NODE[,NODE...] STEP... [--idle S]

STEP: send:NODE:HEX   NODE writes these bytes (hex, no spaces) in one write
      pause:MS        wait MS ms, reading meanwhile

Output (times in seconds since the first step, 6 decimals):
    tx NODE TIME                        one per send, when it was written
    rx NODE COUNT FIRST LAST HEX        one per node: the bytes it read, when
                                        the first and the last arrived
                                        ("- -" and "-" when nothing came)
"""
import os
import select
import sys
import time
import tty


def main():
    args = sys.argv[1:]
    idle = 1.0
    if "--idle" in args:
        i = args.index("--idle")
        idle = float(args[i + 1])
        del args[i:i + 2]
    prefix, names, steps = args[0], args[1].split(","), args[2:]
    fds = {}
    for n in names:
        fd = os.open("%s.%s" % (prefix, n), os.O_RDWR | os.O_NOCTTY)
        tty.setraw(fd)
        fds[n] = fd
    got = {n: bytearray() for n in names}
    first, last = {}, {}
    t0 = time.monotonic()
    limit = t0 + 20.0

    def read_until(deadline):
        while True:
            now = time.monotonic()
            if now >= deadline or now >= limit:
                return
            r, _, _ = select.select(list(fds.values()), [], [], deadline - now)
            now = time.monotonic() - t0
            for n, fd in fds.items():
                if fd in r:
                    data = os.read(fd, 4096)
                    if data:
                        first.setdefault(n, now)
                        last[n] = now
                        got[n] += data

    for step in steps:
        kind, _, rest = step.partition(":")
        if kind == "send":
            node, _, hexs = rest.partition(":")
            os.write(fds[node], bytes.fromhex(hexs))
            print("tx %s %.6f" % (node, time.monotonic() - t0))
        elif kind == "pause":
            read_until(time.monotonic() + float(rest) / 1000.0)
        else:
            sys.stderr.write("radio_probe: unknown step '%s'\n" % step)
            return 2
    # quiet for `idle` seconds: nothing more is on its way
    while True:
        before = sum(len(g) for g in got.values())
        read_until(time.monotonic() + idle)
        if sum(len(g) for g in got.values()) == before or time.monotonic() >= limit:
            break
    for n in names:
        if got[n]:
            print("rx %s %d %.6f %.6f %s" % (n, len(got[n]), first[n], last[n], got[n].hex()))
        else:
            print("rx %s 0 - - -" % n)
    return 0


if __name__ == "__main__":
    sys.exit(main())
