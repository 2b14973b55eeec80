#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""Helpers of tests/integration/it_wireshark.sh (the DF1 dissector, contrib/wireshark/df1.lua).

  wireshark_helper.py fields
        the tshark -e fields `compare` reads, one per line
  wireshark_helper.py compare DF1MON.json TSHARK.tsv
        df1mon -f json --read FILE against tshark -T fields -e (the fields
        above, -E aggregator=US) on the same FILE: the same symbols in the same
        order per direction, and for each the same kind, check verdict, stations,
        command, function, TNS, STS, EXT STS, address, size and values. Prints
        each difference and "N symbols compared"; exit 1 on any difference.
  wireshark_helper.py pcap OUT RECORD...
        write a pcap of link type 250 (RTAC serial): one record per argument
        (or per stdin line with "-"), "[rx:|tx:]HEX BYTES" (or crc:HEX,
        bcc:HEX: a frame with those app bytes, stuffed, with its check), each
        after a 12-byte RTAC header (time, event type: tx 03, rx 04).
  wireshark_helper.py random SEED COUNT crc|bcc
        records (for `pcap OUT -`) of COUNT random PCCC frames, some corrupted,
        split at random over records of both directions.
  wireshark_helper.py tcp OUT RECORD...
        the same as a TCP conversation (Ethernet, IPv4, handshake first) from
        127.0.0.1:40000 to 127.0.0.2:2101: "c:" records from the client, "s:"
        from the server ("cr:", "sr:" the same side's last segment again, a
        retransmission); HEX, or crc:HEX / bcc:HEX for a frame around app bytes.
  wireshark_helper.py tap LINK SIM TAP_TX TAP_RX
        a serial tap between two tools: a pty whose slave is linked at LINK
        (df1read opens it) relayed both ways to the pty SIM (df1sim --pty),
        each direction also copied into a FIFO (TAP_TX: LINK->SIM, TAP_RX:
        SIM->LINK) for `df1mon --sniff -d TAP_TX --sniff-b TAP_RX`. Prints
        "ready" once the taps are open; ends on SIGTERM, closing the FIFOs.
"""
import json
import random
import os
import select
import signal
import struct
import sys
import termios
import tty

US = "\x1f"
FIELDS = ["frame.number", "df1.dir", "df1.symbol", "df1.check_ok", "df1.stn", "df1.master",
          "df1.dst", "df1.src", "df1.cmd", "df1.fnc", "df1.tns", "df1.sts", "df1.ext_sts",
          "df1.addr", "df1.size", "df1.value", "df1.tcr.ctl", "df1.tcr.pre", "df1.tcr.acc",
          "df1.error_id", "df1.embedded"]


def num(text):
    """A tshark number: decimal, 0x hex, or a boolean."""
    t = text.strip()
    if t in ("True", "true"):
        return 1
    if t in ("False", "false"):
        return 0
    return int(t, 0)


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


class Lists:
    """Each field's occurrences of one direction, in record order, consumed in turn."""

    def __init__(self):
        self.v = {k: [] for k in FIELDS}
        self.at = {k: 0 for k in FIELDS}

    def take(self, field, where, errors):
        i = self.at[field]
        if i >= len(self.v[field]):
            errors.append("%s: tshark has no more %s" % (where, field))
            return None
        self.at[field] = i + 1
        return self.v[field][i]

    def left(self):
        return {k: len(v) - self.at[k] for k, v in self.v.items() if len(v) > self.at[k]}


def read_tshark(path):
    dirs = {}
    for line in open(path, encoding="utf-8", errors="replace"):
        cols = line.rstrip("\n").split("\t")
        cols += [""] * (len(FIELDS) - len(cols))
        row = dict(zip(FIELDS, cols))
        if not row["df1.symbol"]:
            continue
        d = row["df1.dir"].split(US)
        if len(set(d)) != 1:
            raise SystemExit("record %s: symbols of two directions" % row["frame.number"])
        lists = dirs.setdefault(d[0], Lists())
        for k in FIELDS:
            if row[k] != "" and k != "frame.number":
                lists.v[k].extend(row[k].split(US))
    return dirs


def same_value(want, got, tcr, where, errors):
    if isinstance(want, dict):
        for key, field in (("ctl", "df1.tcr.ctl"), ("pre", "df1.tcr.pre"), ("acc", "df1.tcr.acc")):
            g = tcr.take(field, where, errors)
            if g is not None and num(g) != want[key]:
                errors.append("%s: %s %s, df1mon %s" % (where, field, g, want[key]))
        return
    if want is None:
        ok = got in ("inf", "-inf", "nan")
    elif isinstance(want, bool) or isinstance(want, int):
        ok = got == str(int(want))
    elif isinstance(want, float):
        try:
            ok = f32(float(got)) == f32(want)
        except ValueError:
            ok = False
    else:
        ok = got == want
    if not ok:
        errors.append("%s: value %r, df1mon %r" % (where, got, want))


def compare(mon_path, ts_path):
    dirs = read_tshark(ts_path)
    mon = {}
    for line in open(mon_path, encoding="utf-8"):
        line = line.strip()
        if line:
            s = json.loads(line)
            mon.setdefault(s.get("dir"), []).append(s)
    errors = []
    if None in mon and len(dirs) > 1:
        errors.append("df1mon saw one direction, tshark %d" % len(dirs))
    count = 0
    for mdir, syms in mon.items():
        tdir = mdir if mdir else (next(iter(dirs)) if dirs else None)
        ts = dirs.get(tdir)
        if ts is None:
            errors.append("direction %s: no DF1 symbol in tshark's output" % mdir)
            continue
        for s in syms:
            count += 1
            where = "symbol %d (%s %s)" % (s["n"], tdir, s["kind"])

            def eq(field, want, conv=num):
                got = ts.take(field, where, errors)
                if got is not None and want is not None and conv(got) != want:
                    errors.append("%s: %s %s, df1mon %s" % (where, field, got, want))

            eq("df1.symbol", s["kind"], str)
            eq("df1.dir", tdir, str)
            if s["kind"] in ("FRAME", "POLL") or "check_ok" in s:
                eq("df1.check_ok", 1 if s.get("check_ok") else 0)
            if s["kind"] == "POLL":
                eq("df1.stn", s["station"])
            elif s["kind"] == "ERROR":
                if "station" in s:
                    eq("df1.stn", s["station"])
                    if s["error_id"] != 2507:   # not a poll's: a master message's
                        eq("df1.master", 1)
                eq("df1.error_id", s["error_id"])
            elif s["kind"] in ("ACK", "NAK") and s.get("embedded"):
                eq("df1.embedded", 1)
            if s["kind"] != "FRAME":
                continue
            if s.get("master"):
                eq("df1.master", 1)
                eq("df1.stn", s["station"])
            if "dst" not in s:
                continue
            eq("df1.dst", s["dst"])
            eq("df1.src", s["src"])
            eq("df1.cmd", int(s["cmd"], 16))
            eq("df1.sts", int(s.get("sts", "00"), 16))
            eq("df1.tns", int(s["tns"], 16))
            if "fnc" in s:
                eq("df1.fnc", int(s["fnc"], 16))
            if "ext_sts" in s:
                eq("df1.ext_sts", int(s["ext_sts"], 16))
            if "address" in s:
                eq("df1.addr", s["address"], str)
            if "size" in s:
                eq("df1.size", s["size"])
            for want in s.get("values", []):
                got = ts.take("df1.value", where, errors)
                if got is not None:
                    same_value(want, got, ts, where, errors)
        left = ts.left()
        if left:
            errors.append("direction %s: tshark has more than df1mon: %s" % (tdir, left))
    for d in dirs:
        if d not in mon and not (None in mon and len(dirs) == 1):
            errors.append("direction %s: only tshark has it" % d)
    for e in errors[:40]:
        print("DIFF " + e)
    print("%d symbols compared, %d differences" % (count, len(errors)))
    return 1 if errors or count == 0 else 0


def crc16(data):
    """CRC-16/ARC (doc/PROTOCOL.md 1.5), computed bit by bit."""
    crc = 0
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def frame(check, app):
    """DLE STX, app bytes with 10h doubled, DLE ETX, BCC or CRC (low byte first)."""
    body = app.replace(b"\x10", b"\x10\x10")
    if check == "bcc":
        return b"\x10\x02" + body + b"\x10\x03" + bytes([(-sum(app)) & 0xFF])
    c = crc16(app + b"\x03")
    return b"\x10\x02" + body + b"\x10\x03" + bytes([c & 0xFF, c >> 8])


def record_bytes(r):
    """HEX, or crc:HEX / bcc:HEX: a frame around those app bytes."""
    for check in ("crc", "bcc"):
        if r.startswith(check + ":"):
            return frame(check, bytes.fromhex(r[4:]))
    return bytes.fromhex(r)


def lines_or(records):
    if records == ["-"]:
        return [l.strip() for l in sys.stdin if l.strip() and not l.startswith("#")]
    return records


def pcap(out, records):
    records = lines_or(records)
    with open(out, "wb") as f:
        f.write(struct.pack("<IHHiIII", 0xA1B2C3D4, 2, 4, 0, 0, 65535, 250))
        t = 1700000000
        for i, r in enumerate(records):
            event = 0x04
            if r.startswith("tx:"):
                event, r = 0x03, r[3:]
            elif r.startswith("rx:"):
                r = r[3:]
            data = record_bytes(r)
            sec, usec = t + i, 1000 * i
            hdr = struct.pack(">II", sec, usec) + bytes([event, 0]) + b"\0\0"
            f.write(struct.pack("<IIII", sec, usec, len(hdr) + len(data), len(hdr) + len(data)))
            f.write(hdr + data)
    return 0


def random_records(seed, count, check):
    """Frames of random PCCC commands and replies (every CMD/FNC libdf1 knows,
    random fields and data), some with a flipped check byte, split at random
    points over records of both directions, with ACK/NAK/ENQ between: the
    dissector and df1mon must still agree on every symbol."""
    r = random.Random(seed)
    heads = [(0x0F, f) for f in (0x00, 0x01, 0x02, 0x26, 0x3A, 0x67, 0x68, 0x80, 0xA1, 0xA2,
                                 0xA9, 0xAA, 0xAB, 0x55)]
    heads += [(0x06, f) for f in range(8)] + [(c, None) for c in (0, 1, 2, 5, 8, 0x0B)]
    for _ in range(count):
        d = r.choice(["rx", "tx"])
        c, f = r.choice(heads)
        reply = r.random() < 0.4
        app = bytes([r.randint(0, 3), r.randint(0, 3), c | (0x40 if reply else 0),
                     r.choice([0, 0, 0, 0x10, 0xF0]) if reply else 0, r.randint(0, 5), 0])
        if f is not None and not reply:
            app += bytes([f])
        if f in (0xA1, 0xA2, 0xA9, 0xAA, 0xAB) and not reply:
            app += bytes([r.choice([2, 4, 6, 84, 8]), r.choice([3, 7, 8, 9, 0xFF]),
                          r.choice([0x85, 0x86, 0x87, 0x88, 0x89, 0x8A, 0x8D, 0x91, 0x84, 0x8B, 0x80])])
            if app[-2] == 0xFF:
                app += bytes([r.randint(0, 255), r.randint(0, 3)])
        app += bytes(r.randint(0, 255) for _ in range(r.randint(0, 30)))
        w = frame(check, app)
        if r.random() < 0.1:
            w = w[:-1] + bytes([w[-1] ^ 1])
        while w:
            k = r.randint(1, len(w))
            print(d + ":" + w[:k].hex())
            w = w[k:]
        if r.random() < 0.3:
            print(("tx:" if d == "rx" else "rx:") + r.choice(["1006", "1015", "1005"]))
    return 0


def tcp_pcap(out, records):
    """Ethernet / IPv4 / TCP between 127.0.0.1:40000 (c:) and 127.0.0.2:2101 (s:)."""
    records = lines_or(records)
    ends = {"c": [b"\x7f\x00\x00\x01", 40000, 1000], "s": [b"\x7f\x00\x00\x02", 2101, 5000]}

    def seg(f, i, who, flags, data):
        a, b = ends[who], ends["s" if who == "c" else "c"]
        tcp = struct.pack(">HHIIBBHHH", a[1], b[1], a[2], b[2], 0x50, flags, 65535, 0, 0) + data
        ip = struct.pack(">BBHHHBBH4s4s", 0x45, 0, 20 + len(tcp), i, 0, 64, 6, 0, a[0], b[0])
        eth = b"\x02\x00\x00\x00\x00\x02\x02\x00\x00\x00\x00\x01\x08\x00"
        pkt = eth + ip + tcp
        f.write(struct.pack("<IIII", 1700000000 + i, 0, len(pkt), len(pkt)) + pkt)
        a[2] += len(data) + (1 if flags & 0x03 else 0)

    with open(out, "wb") as f:
        f.write(struct.pack("<IHHiIII", 0xA1B2C3D4, 2, 4, 0, 0, 65535, 1))
        seg(f, 0, "c", 0x02, b"")            # SYN
        seg(f, 1, "s", 0x12, b"")            # SYN ACK
        seg(f, 2, "c", 0x10, b"")            # ACK
        for i, r in enumerate(records):
            who, r = r.split(":", 1)
            if who.endswith("r"):         # a retransmission of that side's last segment
                who = who[0]
                ends[who][2] -= len(record_bytes(r))
            seg(f, 3 + i, who, 0x18, record_bytes(r))
    return 0


def raw(fd):
    attrs = termios.tcgetattr(fd)
    tty.setraw(fd)
    attrs = termios.tcgetattr(fd)
    attrs[3] &= ~termios.ECHO
    termios.tcsetattr(fd, termios.TCSANOW, attrs)


def tap(link, sim, tap_tx, tap_rx):
    stop = []
    signal.signal(signal.SIGTERM, lambda *a: stop.append(1))
    master, slave = os.openpty()
    raw(slave)
    # the slave stays open here too, so the master sees no hangup between tools
    if os.path.lexists(link):
        os.unlink(link)
    os.symlink(os.ttyname(slave), link)
    s = os.open(sim, os.O_RDWR | os.O_NOCTTY)
    raw(s)
    tx = os.open(tap_tx, os.O_WRONLY)
    rx = os.open(tap_rx, os.O_WRONLY)
    print("ready", flush=True)
    try:
        while not stop:
            try:
                r, _, _ = select.select([master, s], [], [], 0.5)
            except InterruptedError:
                continue
            for fd in r:
                try:
                    b = os.read(fd, 4096)
                except OSError:
                    b = b""
                if not b:
                    continue
                if fd == master:
                    os.write(s, b)
                    os.write(tx, b)
                else:
                    os.write(master, b)
                    os.write(rx, b)
    finally:
        os.close(tx)
        os.close(rx)
        os.unlink(link)
    return 0


def main(argv):
    if len(argv) >= 2 and argv[1] == "fields":
        print("\n".join(FIELDS))
        return 0
    if len(argv) == 4 and argv[1] == "compare":
        return compare(argv[2], argv[3])
    if len(argv) >= 3 and argv[1] == "pcap":
        return pcap(argv[2], argv[3:])
    if len(argv) == 5 and argv[1] == "random":
        return random_records(int(argv[2]), int(argv[3]), argv[4])
    if len(argv) >= 3 and argv[1] == "tcp":
        return tcp_pcap(argv[2], argv[3:])
    if len(argv) == 6 and argv[1] == "tap":
        return tap(*argv[2:])
    sys.stderr.write(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
