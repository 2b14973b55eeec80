# SPDX-License-Identifier: MPL-2.0
# mqtt_wire.py - reading MQTT 3.1.1 packets off a socket, written from the
# specification's fixed header (a type byte, a variable-length remaining
# length): what the test brokers and clients of tests/support share
# (mqtt_burst.py, mqtt_noack.py).


def read_exact(s, n):
    """n bytes from socket s; EOFError when it closes first."""
    b = b""
    while len(b) < n:
        c = s.recv(n - len(b))
        if not c:
            raise EOFError
        b += c
    return b


def read_packet(s):
    """One packet: (its first byte, its body)."""
    h = read_exact(s, 1)[0]
    mult, length = 1, 0
    while True:
        d = read_exact(s, 1)[0]
        length += (d & 0x7F) * mult
        mult *= 128
        if not d & 0x80:
            break
    return h, read_exact(s, length) if length else b""
