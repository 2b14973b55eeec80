#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
# mqtt_burst.py - publish many messages at once, for df1gw's write burst test
# (tests/integration/it_df1gw_writes.sh): MQTT 3.1.1 written from the
# specification's packet layouts, nothing else.
#   mqtt_burst.py PORT FILE
# Each line of FILE is "TOPIC PAYLOAD". Connects to 127.0.0.1:PORT, sends
# every line as a QoS 1 PUBLISH in one write, then waits (30 s at most) for
# the broker's PUBACK of each; exits 0 when all came, 1 otherwise.
import socket
import struct
import sys

from mqtt_wire import read_packet


def varint(n):
    b = bytearray()
    while True:
        d = n % 128
        n //= 128
        b.append(d | (0x80 if n else 0))
        if not n:
            return bytes(b)


def packet(kind, body):
    return bytes([kind]) + varint(len(body)) + body


def string(s):
    s = s.encode()
    return struct.pack(">H", len(s)) + s


def main():
    port, path = int(sys.argv[1]), sys.argv[2]
    with open(path) as f:
        msgs = [line.rstrip("\n").split(" ", 1) for line in f if line.strip()]
    s = socket.create_connection(("127.0.0.1", port), 5)
    s.settimeout(30)
    # CONNECT: protocol "MQTT" level 4, clean session, keepalive 60 s
    s.sendall(packet(0x10, string("MQTT") + bytes([4, 0x02]) + struct.pack(">H", 60) + string("df1burst")))
    h, body = read_packet(s)
    if h >> 4 != 2 or len(body) < 2 or body[1] != 0:
        print("mqtt_burst: CONNECT refused", file=sys.stderr)
        return 1
    out = bytearray()
    for i, (topic, payload) in enumerate(msgs):
        pid = i % 65535 + 1
        out += packet(0x32, string(topic) + struct.pack(">H", pid) + payload.encode())
    s.sendall(out)
    acked = 0
    try:
        while acked < len(msgs):
            h, body = read_packet(s)
            if h >> 4 == 4:
                acked += 1
    except (EOFError, OSError):
        pass
    s.sendall(packet(0xE0, b""))
    s.close()
    if acked < len(msgs):
        print("mqtt_burst: %d of %d acknowledged" % (acked, len(msgs)), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
