#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""eip_flood.py - idle EtherNet/IP clients against a server's limits, for
tests/integration/it_eip_limits.sh.

    eip_flood.py HOST:PORT SESSIONS SILENT WAIT_S

Opens SESSIONS connections that each register a session (RegisterSession,
df1-eip(7)) and then say nothing, then SILENT connections that never send a
byte, and holds them all. Then a new client registers a session: it must be
served (status 0, a session handle) while the others are still held; prints
"served". Then waits up to WAIT_S seconds for the server to close every held
connection and prints "closed N of M". Exit 0 when the new client was served
and every held connection was closed; 1 with what failed on stderr. Messages
are built here from the encapsulation layout, independently of lib/eip; every
wait is a select() with a deadline.
"""
import select
import socket
import struct
import sys
import time


def register(s):
    s.sendall(struct.pack("<HHII8sI", 0x65, 4, 0, 0, b"flood\0\0\0", 0) + struct.pack("<HH", 1, 0))
    got = b""
    while len(got) < 28:
        part = s.recv(28 - len(got))
        if not part:
            raise OSError("closed before the RegisterSession reply")
        got += part
    cmd, _, session, status = struct.unpack_from("<HHII", got)
    if cmd != 0x65 or status != 0 or session == 0:
        raise OSError("RegisterSession: command %#x status %#x session %#x" % (cmd, status, session))


def main():
    host, port = sys.argv[1].rsplit(":", 1)
    sessions, silent, wait_s = int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
    addr = (host, int(port))
    held = []
    for i in range(sessions + silent):
        s = socket.create_connection(addr, timeout=10)
        if i < sessions:
            register(s)
        held.append(s)
    new = socket.create_connection(addr, timeout=10)
    try:
        register(new)
    except OSError as e:
        print("a new client with %d idle connections held: %s" % (len(held), e), file=sys.stderr)
        return 1
    print("served", flush=True)
    new.close()
    deadline = time.monotonic() + wait_s
    open_ = list(held)
    while open_ and time.monotonic() < deadline:
        r, _, _ = select.select(open_, [], [], max(0.0, deadline - time.monotonic()))
        for s in r:
            try:
                data = s.recv(64)
            except OSError:
                data = b""
            if not data:
                open_.remove(s)
    print("closed %d of %d" % (len(held) - len(open_), len(held)), flush=True)
    return 0 if not open_ else 1


if __name__ == "__main__":
    sys.exit(main())
