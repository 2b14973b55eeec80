#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""fdx_master: a full-duplex DF1 master that paces its own bytes as a UART at
BAUD (10 bits a character, each byte at its own due time, never behind
schedule by more than it is late), for df1sim's full-duplex UART test
(tests/integration/it_df1sim_fdx.sh). Frames are built here from the DF1
manual's rules (doc/PROTOCOL.md 1, 2.1: DLE STX, DLE-doubled application
bytes, DLE ETX, CRC-16 over them and ETX), independently of libdf1.

It sends PAIRS pairs of SLC commands (doc/PROTOCOL.md 4.5): a protected typed
logical write (0F AA) of 100 words to N7:0 (a long command, a short reply),
then a read (0F A2) of the same 100 words (a short command, a long reply);
each message waits for the DLE ACK of the one before, as full duplex
requires, and each reply is ACKed. Values written by pair k are 1000 k + i,
checked in the read's reply.

usage: fdx_master.py DEVICE|tcp:PORT BAUD PAIRS
prints: "elapsed S tx N rx N" (seconds; characters each way), exit 0, or the
reason and exit 1.
"""
import os
import select
import socket
import sys
import termios
import time
import tty

DLE, STX, ETX, ACK, NAK = 0x10, 0x02, 0x03, 0x06, 0x15


def crc16(data):
    c = 0
    for x in data + bytes([ETX]):
        c ^= x
        for _ in range(8):
            c = (c >> 1) ^ 0xA001 if c & 1 else c >> 1
    return bytes([c & 0xFF, c >> 8])


def frame(app):
    body = app.replace(bytes([DLE]), bytes([DLE, DLE]))
    return bytes([DLE, STX]) + body + bytes([DLE, ETX]) + crc16(app)


def words(vals):
    return b"".join((v & 0xFFFF).to_bytes(2, "little") for v in vals)


def messages(pairs):
    out, tns = [], 0x100
    for k in range(1, pairs + 1):
        vals = [1000 * k + i for i in range(100)]
        hdr = bytes([1, 0, 0x0F, 0]) + tns.to_bytes(2, "little")
        out.append(("w", k, tns, frame(hdr + bytes([0xAA, 200, 7, 0x89, 0, 0]) + words(vals))))
        tns += 1
        hdr = bytes([1, 0, 0x0F, 0]) + tns.to_bytes(2, "little")
        out.append(("r", k, tns, frame(hdr + bytes([0xA2, 200, 7, 0x89, 0, 0]))))
        tns += 1
    return out


class Parser:
    """Received bytes into ("ack",), ("nak",) and ("frame", app) events."""

    def __init__(self):
        self.buf = bytearray()

    def feed(self, data):
        self.buf += data
        ev = []
        while True:
            b = self.buf
            i = b.find(bytes([DLE]))
            if i < 0 or i + 1 >= len(b):
                return ev
            del b[:i]
            sym = b[1]
            if sym in (ACK, NAK):
                ev.append(("ack",) if sym == ACK else ("nak",))
                del b[:2]
                continue
            if sym != STX:
                del b[:2]
                continue
            app, j, end = bytearray(), 2, None
            while j + 1 < len(b):
                if b[j] == DLE and b[j + 1] == DLE:
                    app.append(DLE)
                    j += 2
                elif b[j] == DLE and b[j + 1] == ETX:
                    end = j + 2
                    break
                else:
                    app.append(b[j])
                    j += 1
            if end is None or end + 2 > len(b):
                return ev
            if bytes(b[end:end + 2]) != crc16(bytes(app)):
                raise SystemExit("bad CRC in a reply")
            ev.append(("frame", bytes(app)))
            del b[:end + 2]


def main():
    dev, baud, pairs = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    if dev.startswith("tcp:"):
        s = socket.create_connection(("127.0.0.1", int(dev[4:])))
        s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        fd = s.fileno()
    else:
        fd = os.open(dev, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(fd)
        termios.tcflush(fd, termios.TCIOFLUSH)
    os.set_blocking(fd, False)
    char = 10.0 / baud
    msgs = messages(pairs)
    pending = {m[2]: m for m in msgs}
    out = bytearray()       # bytes queued on our UART
    due = 0.0               # when the next byte may leave
    nxt, awaiting_ack, tx, rx = 0, False, 0, 0
    parser = Parser()
    start = time.monotonic()
    deadline = start + 60
    while pending or out or nxt < len(msgs) or awaiting_ack:
        now = time.monotonic()
        if now > deadline:
            raise SystemExit("timed out: %d replies missing" % len(pending))
        if not awaiting_ack and not out and nxt < len(msgs):
            out += msgs[nxt][3]
            nxt += 1
            awaiting_ack = True
        while out and due <= now:       # our UART: one byte per character time
            os.write(fd, bytes(out[:1]))
            del out[:1]
            tx += 1
            due = max(due, now - char) + char
        wait = max(0.0, due - now) if out else 0.5
        r, _, _ = select.select([fd], [], [], wait)
        if not r:
            continue
        data = os.read(fd, 4096)
        if not data:
            raise SystemExit("the simulator closed the line")
        rx += len(data)
        for ev in parser.feed(data):
            if ev[0] == "nak":
                raise SystemExit("NAK from the simulator")
            if ev[0] == "ack":
                awaiting_ack = False
                continue
            app = ev[1]
            tns = int.from_bytes(app[4:6], "little")
            m = pending.pop(tns, None)
            if m is None or app[2] != 0x4F or app[3] != 0:
                raise SystemExit("unexpected reply %s" % app.hex())
            if m[0] == "r" and app[6:] != words([1000 * m[1] + i for i in range(100)]):
                raise SystemExit("pair %d: read back other values" % m[1])
            out += bytes([DLE, ACK])
    print("elapsed %.3f tx %d rx %d" % (time.monotonic() - start, tx, rx))


if __name__ == "__main__":
    main()
