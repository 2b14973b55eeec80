#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""Seed corpora of the fuzz targets (tests/fuzz/README), written to OUTDIR/TARGET/.

Built from what the tree already holds: the spec vectors (tests/data/vectors.txt,
doc/PROTOCOL.md 7), the serial-tap captures and the CSV files of
tests/data and examples/, plus the address and value forms of doc/ARCHITECTURE.md 7 and
df1_value_format(3). Each seed carries the target's leading option bytes (see
the comment at the top of each tests/fuzz/fuzz_TARGET.c). The inputs of past
findings are kept in tests/fuzz/found/TARGET-WHAT.hex and become seeds as
they are.

usage: seeds.py OUTDIR
"""
import hashlib
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.normpath(os.path.join(HERE, "..", ".."))
DATA = os.path.join(TOP, "tests", "data")

DLE, STX, ETX, SOH = 0x10, 0x02, 0x03, 0x01


def vectors():
    """(name, check, wire bytes) of every vector line."""
    out = []
    with open(os.path.join(DATA, "vectors.txt")) as f:
        for line in f:
            if not line.strip() or line.startswith("#"):
                continue
            parts = [p.strip() for p in line.split("|")]
            out.append((parts[0], parts[1], bytes.fromhex(parts[2])))
    return out


def app_bytes(wire):
    """The de-stuffed app bytes of a frame (DLE STX or DLE SOH STN DLE STX), or None."""
    if wire[:2] == bytes([DLE, STX]):
        i = 2
    elif wire[:2] == bytes([DLE, SOH]):
        i = 3 if wire[2] != DLE else 4
        if wire[i:i + 2] != bytes([DLE, STX]):
            return None
        i += 2
    else:
        return None
    out = bytearray()
    while i < len(wire) - 1:
        if wire[i] == DLE:
            if wire[i + 1] == ETX:
                return bytes(out)
            out.append(wire[i + 1])
            i += 2
        else:
            out.append(wire[i])
            i += 1
    return None


def pcap_payloads(path):
    """Record payloads after the 12-byte RTAC serial header, in order."""
    with open(path, "rb") as f:
        b = f.read()
    out, pos = [], 24
    while pos + 16 <= len(b):
        incl = struct.unpack_from("<I", b, pos + 8)[0]
        rec = b[pos + 16:pos + 16 + incl]
        out.append(rec[12:])
        pos += 16 + incl
    return out


def read(path):
    with open(path, "rb") as f:
        return f.read()


def found():
    """(target, bytes) of each tests/fuzz/found/TARGET-WHAT.hex: '#' lines are
    comments, the rest is the input in hex (whitespace ignored)."""
    d = os.path.join(HERE, "found")
    out = []
    for name in sorted(os.listdir(d)) if os.path.isdir(d) else []:
        if not name.endswith(".hex"):
            continue
        with open(os.path.join(d, name)) as f:
            text = "".join(line for line in f if not line.startswith("#"))
        out.append((name.split("-", 1)[0], bytes.fromhex("".join(text.split()))))
    return out


class Corpus:
    def __init__(self, outdir):
        self.outdir = outdir
        self.count = {}

    def add(self, target, data):
        d = os.path.join(self.outdir, target)
        os.makedirs(d, exist_ok=True)
        name = hashlib.sha1(data).hexdigest()[:16]
        with open(os.path.join(d, name), "wb") as f:
            f.write(data)
        self.count[target] = self.count.get(target, 0) + 1


# the address list of fuzz_value.c, in its order
VALUE_ADDRS = ["N7:0", "B3:0", "B3:0/5", "F8:0", "L10:0", "L10:0/31", "ST9:0", "A11:0",
               "T4:0", "T4:0.ACC", "T4:0.PRE", "T4:0/DN", "C5:0", "C5:0/OV", "C5:0.ACC", "R6:0",
               "R6:0.LEN", "R6:0/ER", "S2:1/5", "S:0", "I1:0", "I1:0.1/3", "O0:0", "O:0/15",
               "$N7:0", "$F8:2", "N7:0/15", "T4:0.ACC/3"]

ADDRESSES = ["N7:0", "N10:255", "F8:3", "B3:0/5", "B3/21", "T4:0.ACC", "T4:0.PRE", "T4:0/DN",
             "C5:1.ACC", "C5:1/OV", "R6:0.LEN", "R6:0.POS", "S:1/5", "S2:0", "I:0/3", "I1:0.1/3",
             "O:0", "ST9:0", "L10:0", "A11:0", "$N7:0", "N7:999", "N999:0", "N300:300",
             "B3:0/15", "L10:0/31", "T4:1", "ST9:2", "F8:0", "N7:0.1", "I:1.255/15"]

VALUES = ["0", "1", "-1", "32767", "-32768", "0x7FFF", "0xFFFF", "65535", "2147483647",
          "-2147483648", "1.5", "-0", "0.1", "1e-45", "3.4028235e+38", "inf", "-inf",
          "PRE=100 ACC=42 EN=1 TT=0 DN=1", "CU=1 CD=0 DN=0 OV=0 UN=0 UA=0 PRE=10 ACC=3",
          "EN=0 EU=0 DN=0 EM=0 ER=0 UL=0 IN=0 FD=0 LEN=8 POS=2", "CTL=0x8000 PRE=1 ACC=2",
          "hello", "a, #b", ""]

TABLE_FILES = [
    "# df1sim --data\nN7:0=1,2,3\nB3:1/5=1,0\nT4:0=PRE=500 ACC=0 EN=1\n"
    "ST9:0=\"a, \\\"quoted\\\" string\"\nF8:0=-1.25,inf\nN20:300=5\n",
    "ST9:2=\"\\x41\\x42\"\nC5:0=PRE=10 ACC=3 CU=1\nR6:0=LEN=8 POS=2\nL10:0=70000\n",
    "\xef\xbb\xbfN7:0=41,42\n",
    "N7:0=9\nN7:1=5\n",
]


def chunk(c, data):
    return bytes([c, len(data)]) + data


def eip_msg(cmd, data=b"", session=0):
    return struct.pack("<HHII8sI", cmd, len(data), session, 0, b"ctx-fuzz", 0) + data


def eip_rr(cip, session=1):
    return eip_msg(0x6F, struct.pack("<IHHHHHH", 0, 10, 2, 0, 0, 0xB2, len(cip)) + cip, session)


def eip_unit(conn, seq, cip, session=1):
    return eip_msg(0x70, struct.pack("<IHHHHIHHH", 0, 0, 2, 0xA1, 4, conn, 0xB1, len(cip) + 2, seq) + cip,
                   session)


def eip_conversations(pcccs):
    """Whole sessions: register, identity, PCCC direct, routed and connected, close."""
    session = 0x00010203       # fuzz_eip's session handle
    reqid = b"\x07\x4d\x00\x78\x56\x34\x12"
    cm = b"\x02\x20\x06\x24\x01"
    reg = eip_msg(0x65, b"\x01\x00\x00\x00")
    path = b"\x01\x00\x20\x02\x24\x01"
    fo = (b"\x54" + cm + b"\x0a\x0e" + struct.pack("<IIHHI", 0, 0x11223344, 7, 0x4D, 0x87654321) +
          b"\x03\x00\x00\x00" + struct.pack("<IHIH", 2000000, 0x43F4, 2000000, 0x43F4) + b"\xa3\x03" + path)
    fc = b"\x4e" + cm + b"\x0a\x0e" + struct.pack("<HHI", 7, 0x4D, 0x87654321) + b"\x03\x00" + path
    # the O->T id eip_session gives the first connection of this session
    ot = ((session << 16) ^ 1 ^ 0x80000000) & 0xFFFFFFFF
    out = [eip_msg(0x63) + eip_msg(0x04) + reg + eip_msg(0x65, b"\x02\x00\x00\x00")]
    for p in pcccs[:40]:
        ex = b"\x4b\x02\x20\x67\x24\x01" + reqid + p
        pad = b"\x00" if len(ex) % 2 else b""
        us = b"\x52" + cm + b"\x0a\x0e" + struct.pack("<H", len(ex)) + ex + pad + b"\x01\x00\x02\x03"
        out.append(reg + eip_rr(ex, session) + eip_rr(us, session) + eip_rr(fo, session) +
                   eip_unit(ot, 1, ex, session) + eip_rr(fc, session) + eip_msg(0x66, b"", session))
    out.append(reg + eip_rr(b"\x0e\x03\x20\x01\x24\x01\x30\x07", session) +
               eip_rr(b"\x01\x02\x20\x01\x24\x01", session) + eip_msg(0x99) +
               eip_msg(0x6F, b"", session)[:4] + b"\xf0\xff" + eip_msg(0x6F, b"", session)[6:])
    return out


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    cp = Corpus(sys.argv[1])
    vecs = vectors()
    apps = [(n, a) for n, _, w in vecs if (a := app_bytes(w)) is not None]
    caps = [os.path.join(DATA, f) for f in sorted(os.listdir(DATA)) if f.endswith(".pcap")]
    tap = b"".join(pcap_payloads(os.path.join(DATA, "serial-tap-slc-full-duplex.pcap")))

    # frame: [check, options, chunking] + wire bytes; every mode on every vector
    for opts in (0x00, 0x01, 0x10, 0x20, 0x12, 0x04, 0x08):
        for name, check, wire in vecs:
            cp.add("frame", bytes([1 if check == "bcc" else 0, opts, 0x5A]) + wire)
        for ck in (0, 1, 2):
            cp.add("frame", bytes([ck, opts, 0xC3]) +
                   b"".join(w for _, c, w in vecs if c == ("bcc" if ck != 0 else "crc")))
    cp.add("frame", bytes([2, 0x20, 0x11]) + tap[:4000])

    # pccc_reply: [file type] + app bytes (N 8, F 9, T 5, ST 10)
    for name, a in apps:
        ft = 9 if "F8" in name or "1.5" in name else 5 if "T4" in name else 8
        cp.add("pccc_reply", bytes([ft]) + a)

    # pccc_command: [PLC type] + command app bytes (0 SLC, 3 PLC-5, 4 PLC-2)
    for name, a in apps:
        if len(a) < 3 or a[2] & 0x40:
            continue
        plcs = [4] if "plc2" in name else [3] if ("plc5" in name or name.startswith("KE")) else [0, 1, 3]
        for p in plcs:
            cp.add("pccc_command", bytes([p]) + a)

    for a in ADDRESSES:
        cp.add("addr", a.encode())
    for i, a in enumerate(VALUE_ADDRS):
        for v in VALUES:
            cp.add("value", bytes([i]) + v.encode())

    nets = [os.path.join(DATA, f) for f in ("net_valid.csv", "net_invalid.csv")]
    nets.append(os.path.join(TOP, "examples", "network.csv"))
    for p in nets:
        cp.add("net_csv", read(p))
    cp.add("net_csv", b"Station,Mode\n")
    maps = [os.path.join(DATA, f) for f in ("map_valid.csv", "map_invalid.csv")]
    maps.append(os.path.join(TOP, "examples", "map.csv"))
    for p in maps:
        for strict in (0, 1):
            cp.add("map_csv", bytes([strict]) + read(p))

    for t in TABLE_FILES:
        for p in (0, 1, 3):
            cp.add("table_file", bytes([p]) + t.encode("latin-1"))

    # mon_read: [options] + a pcap or a raw dump
    for p in caps:
        for o in (0x01, 0x02, 0x41, 0x12):
            cp.add("mon_read", bytes([o]) + read(p))
    cp.add("mon_read", bytes([0x02]) + b"".join(w for _, _, w in vecs))
    cp.add("mon_read", bytes([0x41]) + tap[:2000])

    # link: [line, op, count, options] + responder chunks. Full duplex: ACK and
    # the reply at once; half duplex: ACK the message, then the reply to a poll.
    for line in (0x00, 0x02, 0x01, 0x03, 0x0C, 0x0D, 0x10, 0x04):
        half = line & 1
        for op in range(20):
            cnt = 9                      # count 10; TNS 0909
            data = bytes([0]) + bytes(range(20)) * 2
            if half:
                body = chunk(0x00, bytes([DLE, 0x06])) + chunk(0x13 if op == 12 else 0x03, data)
                body += chunk(0x00, b"") + chunk(0x10, b"")
            else:
                body = chunk(0x07, data) + chunk(0x00, b"")
            cp.add("link", bytes([line, op, cnt, 0]) + body)
    for _, a in apps:                    # replies as the vectors have them
        cp.add("link", bytes([0x02, 0, 9, 0]) + chunk(0x05, a))

    # poll: [line, plan, count] + a reply to every command
    for line in (0x00, 0x02, 0x01, 0x0C, 0x10, 0x40):
        reply = bytes([0]) + bytes(range(1, 90))
        if line & 1:
            body = (chunk(0x00, bytes([DLE, 0x06])) + chunk(0x03, reply) + chunk(0x80, b"")) * 8
        else:
            body = (chunk(0x07, reply) + chunk(0x80, b"")) * 8
        for plan in (0x00, 0x13, 0x21):
            cp.add("poll", bytes([line, plan, 4]) + body)

    # eip: [options] + encapsulation messages (a session's conversation), the
    # PCCC commands of the vectors carried in Execute PCCC
    for opt in (0, 1, 2):
        for conv in eip_conversations([a[2:] for _, a in apps if len(a) > 6 and not a[2] & 0x40]):
            cp.add("eip", bytes([opt]) + conv)

    # gw_set: [tag: address index | Count index << 4 | current value 64] + a .../set
    # payload as df1gw(1) documents them, and the hostile ones of its tests
    sets = [b"5", b"-32768", b"{\"value\": 12, \"id\": \"w1\"}", b"[1, 2, 3]", b"1.5", b"true", b"0",
            b"\"STRING 1\"", b"{\"PRE\": 500, \"DN\": true}", b"{\"value\": {\"ACC\": 3}, \"id\": 17}",
            b"1e400", b"[[[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]]", b"{\"value\": 1, \"value\": 2}",
            b"{\"value\": 1, \"id\": \"a\\u0000b\"}", b"\"\\u00ff\\u0100\"", b"NaN", b"[1, 2, 3, 4, 5]"]
    for tag in (0x00, 0x01, 0x02, 0x03, 0x44, 0x15, 0x26, 0x07, 0x08, 0x39, 0x80, 0x91, 0x88):
        for p in sets:
            cp.add("gw_set", bytes([tag]) + p)

    # telnet: what an RFC 2217 device server sends (doc/PROTOCOL.md 9): its
    # answers to the client's offers and settings, data with 255 doubled,
    # and a DF1 frame of the vectors as data
    iac = b"\xff"
    answers = [iac + b"\xfd\x2c", iac + b"\xfb\x00", iac + b"\xfd\x00", iac + b"\xfe\x2c",
               iac + b"\xfa\x2c\x65\x00\x00\x25\x80" + iac + b"\xf0",
               iac + b"\xfa\x2c\x66\x08" + iac + b"\xf0", iac + b"\xfa\x2c\x67\x03" + iac + b"\xf0",
               iac + b"\xfa\x2c\x70\x03" + iac + b"\xf0", iac + b"\xf1", b"\x10\x06" + iac + iac + b"\x10\x03"]
    for a in answers:
        cp.add("telnet", a)
    cp.add("telnet", b"".join(answers))
    for _, _, w in vecs[:8]:
        cp.add("telnet", bytes(w).replace(iac, iac + iac))
    # spb_cmd: [tag as gw_set's] + DCMD payloads in the protobuf wire format
    # of tools/df1gw/spb.proto: a metric per value kind, by name, member and alias
    def pb_varint(x):
        out = b""
        while True:
            b7 = x & 0x7F
            x >>= 7
            if x:
                out += bytes([b7 | 0x80])
            else:
                return out + bytes([b7])

    def pb_len(field, data):
        return pb_varint(field << 3 | 2) + pb_varint(len(data)) + data

    def pb_int(field, x):
        return pb_varint(field << 3) + pb_varint(x)

    def metric(name, datatype, value, alias=None):
        m = pb_len(1, name.encode()) if name is not None else b""
        if alias is not None:
            m += pb_int(2, alias)
        return pb_len(2, m + pb_int(4, datatype) + value)

    f32 = struct.pack("<f", 1.5)
    metrics = [
        metric("t", 2, pb_int(10, 5)), metric("t/ACC", 2, pb_int(10, 7)), metric("t/DN", 11, pb_int(14, 1)),
        metric("t", 9, pb_varint(12 << 3 | 5) + f32), metric("t", 11, pb_int(14, 1)),
        metric("t", 12, pb_len(15, b"hi")), metric(None, 3, pb_int(10, 0xFFFFFFFF), alias=(1 << 16) | 3),
        metric("t", 3, pb_int(10, 70000)), metric("t", 22, pb_len(16, b"\x01\x00\x02\x00")),
        metric("t/3/ACC", 2, pb_int(10, 9)), metric("Node Control/Rebirth", 11, pb_int(14, 1)),
    ]
    for tag in (0x00, 0x01, 0x02, 0x03, 0x44, 0x15, 0x26, 0x08, 0x39):
        for mt in metrics:
            cp.add("spb_cmd", bytes([tag]) + pb_int(1, 1700000000000) + mt)
        cp.add("spb_cmd", bytes([tag]) + b"".join(metrics))

    # http: requests a client sends to df1gw --http (df1gw(1) HEALTH): each
    # path it serves by GET and HEAD, methods it refuses, HTTP/1.0, keep-alive
    # with two requests, a body by length and chunked, and a malformed line
    paths = [b"/", b"/index.html", b"/app.js", b"/chart.js", b"/app.css", b"/metrics", b"/api/status", b"/nothing",
             b"/metrics?x=1", b"/%2e%2e/etc/passwd"]
    for p in paths:
        cp.add("http", b"GET " + p + b" HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
        cp.add("http", b"HEAD " + p + b" HTTP/1.0\r\n\r\n")
    cp.add("http", b"POST /api/status HTTP/1.1\r\nHost: a\r\nContent-Length: 5\r\n\r\nhello")
    cp.add("http", b"PUT /metrics HTTP/1.1\r\nHost: a\r\nTransfer-Encoding: chunked\r\n\r\n"
                   b"5\r\nhello\r\n0\r\n\r\n")
    cp.add("http", b"GET /metrics HTTP/1.1\r\nHost: a\r\nConnection: keep-alive\r\n\r\n"
                   b"GET /api/status HTTP/1.1\r\nHost: a\r\nConnection: close\r\n\r\n")
    cp.add("http", b"GET / HTTP/1.1\r\nHost: a\r\nExpect: 100-continue\r\nContent-Length: 3\r\n\r\nabc")
    cp.add("http", b"\r\nGET /metrics HTTP/1.1\r\nHost: a\r\n\r\n")
    cp.add("http", b"GET /metrics HTTP/9.9\r\n\r\n")
    cp.add("http", b"GET\r\n\r\n")

    # every input a fuzz run has reported, byte for byte (tests/fuzz/found)
    for target, data in found():
        cp.add(target, data)

    for t in sorted(cp.count):
        print("seeds: %-13s %d" % (t, cp.count[t]))


if __name__ == "__main__":
    main()
