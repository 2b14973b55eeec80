#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
# mqtt_noack.py - a broker that never acknowledges, for store and forward's
# test (tests/integration/it_df1gw_buffer.sh): MQTT 3.1.1 written from the
# specification's packet layouts, nothing else.
#   mqtt_noack.py PORT CLIENT_ID SECONDS LOG
# Listens on 127.0.0.1:PORT (prints "listening" when it does). A client whose
# CONNECT carries CLIENT_ID gets CONNACK, SUBACK and PINGRESP, never a PUBACK:
# each PUBLISH it sends is written to LOG as "TOPIC PAYLOAD" (mosquitto_sub -v's
# form); after SECONDS the connection is closed and the program ends. Any
# other client is closed at once (it tries again later).
import os
import socket
import sys
import threading
import time

from mqtt_wire import read_packet as packet


def client_id(body):
    n = int.from_bytes(body[0:2], "big")          # protocol name
    p = 2 + n + 1 + 1 + 2                         # level, flags, keepalive
    m = int.from_bytes(body[p:p + 2], "big")
    return body[p + 2:p + 2 + m].decode("utf-8", "replace")


def serve(c, want, seconds, log):
    try:
        h, body = packet(c)
        if h >> 4 != 1 or client_id(body) != want:
            c.close()
            return
        c.sendall(b"\x20\x02\x00\x00")
        end = time.time() + seconds
        c.settimeout(0.1)
        out = open(log, "a", buffering=1)
        while time.time() < end:
            try:
                h, body = packet(c)
            except socket.timeout:
                continue
            t = h >> 4
            if t == 3:                            # PUBLISH: logged, never acknowledged
                n = int.from_bytes(body[0:2], "big")
                topic = body[2:2 + n].decode("utf-8", "replace")
                p = 2 + n + (2 if (h >> 1) & 3 else 0)
                out.write("%s %s\n" % (topic, body[p:].decode("utf-8", "replace")))
            elif t == 8:                          # SUBSCRIBE: granted QoS 1 for each
                k = (len(body) - 2) // 4 or 1
                c.sendall(bytes([0x90, 2 + k]) + body[0:2] + b"\x01" * k)
            elif t == 12:                         # PINGREQ
                c.sendall(b"\xd0\x00")
            elif t == 14:                         # DISCONNECT
                break
        c.close()
        os._exit(0)
    except (EOFError, OSError):
        c.close()


def main(argv):
    if len(argv) != 5:
        print("usage: mqtt_noack.py PORT CLIENT_ID SECONDS LOG", file=sys.stderr)
        return 2
    s = socket.socket()
    s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    s.bind(("127.0.0.1", int(argv[1])))
    s.listen(8)
    print("listening", flush=True)
    while True:
        c, _ = s.accept()
        threading.Thread(target=serve, args=(c, argv[2], float(argv[3]), argv[4]), daemon=True).start()


if __name__ == "__main__":
    sys.exit(main(sys.argv))
