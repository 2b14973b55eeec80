#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""eip_probe.py - a small EtherNet/IP client of its own for tests/integration/it_eip_sim.sh.

    eip_probe.py HOST:PORT CHECK [ARGS...]

Builds every message from the layouts of df1-eip(7) (ODVA Vol. 2 ch. 2-3, Vol. 1
ch. 3, Rockwell 1756-PM020), independently of lib/eip/eip_codec.c, and checks the
replies. Exit 0 when the check holds; else 1 with what differed on stderr.
Every wait is bounded by a socket timeout (10 s); nothing sleeps.
"""
import socket
import struct
import sys

TIMEOUT = 10.0
CTX = b"\x01\x02\x03\x04\x05\x06\x07\x08"
REQID = b"\x07\x4d\x00\x78\x56\x34\x12"     # length 7, vendor 0x004D, serial 0x12345678


class Fail(Exception):
    pass


def want(what, got, expect):
    if got != expect:
        raise Fail("%s: got %r, expected %r" % (what, got, expect))


def encap(cmd, data=b"", session=0, status=0, ctx=CTX, options=0, length=None):
    n = len(data) if length is None else length
    return struct.pack("<HHII8sI", cmd, n, session, status, ctx, options) + data


class Conn:
    def __init__(self, addr):
        host, port = addr.rsplit(":", 1)
        self.addr = (host, int(port))
        self.s = socket.create_connection(self.addr, timeout=TIMEOUT)
        self.session = 0

    def send(self, b):
        self.s.sendall(b)

    def recv_exact(self, n):
        out = b""
        while len(out) < n:
            chunk = self.s.recv(n - len(out))
            if not chunk:
                raise Fail("connection closed after %d of %d bytes" % (len(out), n))
            out += chunk
        return out

    def reply(self):
        h = self.recv_exact(24)
        cmd, n, session, status, ctx, options = struct.unpack("<HHII8sI", h)
        return cmd, session, status, ctx, self.recv_exact(n)

    def closed(self):
        """True if the server closed the connection (EOF before any byte)."""
        try:
            return self.s.recv(1) == b""
        except ConnectionResetError:
            return True

    def register(self):
        self.send(encap(0x65, b"\x01\x00\x00\x00"))
        cmd, session, status, ctx, data = self.reply()
        want("RegisterSession reply command", cmd, 0x65)
        want("RegisterSession status", status, 0)
        want("RegisterSession context", ctx, CTX)
        want("RegisterSession data", data, b"\x01\x00\x00\x00")
        if session == 0:
            raise Fail("RegisterSession: session handle 0")
        self.session = session
        return session

    def rr(self, cip, session=None):
        """SendRRData with null address + unconnected data; returns the CIP reply."""
        data = struct.pack("<IHH", 0, 10, 2) + struct.pack("<HH", 0, 0) + struct.pack("<HH", 0xB2, len(cip)) + cip
        self.send(encap(0x6F, data, self.session if session is None else session))
        cmd, session, status, ctx, data = self.reply()
        want("SendRRData reply command", cmd, 0x6F)
        want("SendRRData status", status, 0)
        want("SendRRData context", ctx, CTX)
        iface, timeout, count = struct.unpack_from("<IHH", data)
        want("item count", count, 2)
        t0, l0 = struct.unpack_from("<HH", data, 8)
        want("address item", (t0, l0), (0, 0))
        t1, l1 = struct.unpack_from("<HH", data, 12)
        want("data item type", t1, 0xB2)
        want("data item length", l1, len(data) - 16)
        return data[16:]

    def unit(self, conn_id, seq, cip):
        data = struct.pack("<IHH", 0, 0, 2) + struct.pack("<HHI", 0xA1, 4, conn_id)
        data += struct.pack("<HHH", 0xB1, len(cip) + 2, seq) + cip
        self.send(encap(0x70, data, self.session))

    def unit_reply(self):
        cmd, session, status, ctx, data = self.reply()
        want("SendUnitData reply command", cmd, 0x70)
        want("SendUnitData status", status, 0)
        iface, timeout, count = struct.unpack_from("<IHH", data)
        want("item count", count, 2)
        t0, l0, cid = struct.unpack_from("<HHI", data, 8)
        want("address item", (t0, l0), (0xA1, 4))
        t1, l1, seq = struct.unpack_from("<HHH", data, 16)
        want("data item type", t1, 0xB1)
        return cid, seq, data[22:]


def cip_status(reply):
    """(service, general status, extended status words, data) of a CIP reply."""
    if len(reply) < 4:
        raise Fail("CIP reply of %d bytes" % len(reply))
    ext = reply[3]
    words = list(struct.unpack_from("<%dH" % ext, reply, 4))
    return reply[0], reply[2], words, reply[4 + 2 * ext:]


def pccc_request(pccc):
    """Execute PCCC: service 4B, path class 67 instance 1, requester ID, PCCC."""
    return b"\x4b\x02\x20\x67\x24\x01" + REQID + pccc


def pccc_reply(cip):
    svc, st, ext, data = cip_status(cip)
    want("Execute PCCC reply service", svc, 0xCB)
    want("Execute PCCC general status", st, 0)
    want("requester ID echoed", data[:7], REQID)
    return data[7:]


def slc_read(tns, size, file_no, ftype, elem, sub=0):
    return struct.pack("<BBHBBBBBB", 0x0F, 0, tns, 0xA2, size, file_no, ftype, elem, sub)


def slc_write(tns, file_no, ftype, elem, data, sub=0):
    return struct.pack("<BBHBBBBBB", 0x0F, 0, tns, 0xAA, len(data), file_no, ftype, elem, sub) + data


def unconnected_send(embedded, route):
    pad = b"\x00" if len(embedded) % 2 else b""
    return (b"\x52\x02\x20\x06\x24\x01" + b"\x0a\x0e" + struct.pack("<H", len(embedded)) + embedded + pad +
            struct.pack("<BB", len(route) // 2, 0) + route)


def forward_open(conn_serial, to_id, path=b"\x01\x00\x20\x02\x24\x01", large=False):
    params = struct.pack("<I", 0x42000000 | 500) if large else struct.pack("<H", 0x4200 | 500)
    body = (b"\x0a\x0e" + struct.pack("<II", 0, to_id) + struct.pack("<HHI", conn_serial, 0x4D, 0x87654321) +
            b"\x03\x00\x00\x00" + struct.pack("<I", 2000000) + params + struct.pack("<I", 2000000) + params +
            b"\xa3" + struct.pack("<B", len(path) // 2) + path)
    return (b"\x5b" if large else b"\x54") + b"\x02\x20\x06\x24\x01" + body


def forward_close(conn_serial, path=b"\x01\x00\x20\x02\x24\x01"):
    return (b"\x4e\x02\x20\x06\x24\x01\x0a\x0e" + struct.pack("<HHI", conn_serial, 0x4D, 0x87654321) +
            struct.pack("<BB", len(path) // 2, 0) + path)


def parse_identity(data, port):
    count, itype, ilen = struct.unpack_from("<HHH", data)
    want("ListIdentity item count", count, 1)
    want("ListIdentity item type", itype, 0x0C)
    want("ListIdentity item length", ilen, len(data) - 6)
    item = data[6:]
    version, = struct.unpack_from("<H", item)
    family, sport = struct.unpack_from(">HH", item, 2)
    want("encapsulation version", version, 1)
    want("sin_family (network order)", family, 2)
    want("sin_port (network order)", sport, port)
    vendor, dtype, pcode, major, minor, status, serial, nlen = struct.unpack_from("<HHHBBHIB", item, 18)
    name = item[33:33 + nlen].decode()
    state = item[33 + nlen]
    return {"vendor": vendor, "device_type": dtype, "name": name, "state": state, "major": major,
            "minor": minor, "serial": serial}


# ----------------------------------------------------------------------------
# Checks
# ----------------------------------------------------------------------------

def check_register(addr):
    c = Conn(addr)
    c.register()
    # a second RegisterSession on the same connection: 0x0001, session kept
    c.send(encap(0x65, b"\x01\x00\x00\x00"))
    cmd, session, status, ctx, data = c.reply()
    want("second RegisterSession status", status, 0x0001)
    # version 2: unsupported, the reply names version 1
    d = Conn(addr)
    d.send(encap(0x65, b"\x02\x00\x00\x00"))
    cmd, session, status, ctx, data = d.reply()
    want("RegisterSession version 2 status", status, 0x0069)
    want("highest version supported", data[:2], b"\x01\x00")
    # UnRegisterSession: no reply, the connection closed
    c.send(encap(0x66, session=c.session))
    want("connection closed after UnRegisterSession", c.closed(), True)


def check_identity_tcp(addr, name):
    c = Conn(addr)
    c.send(encap(0x63))
    cmd, session, status, ctx, data = c.reply()
    want("ListIdentity status", status, 0)
    want("ListIdentity context", ctx, CTX)
    ident = parse_identity(data, c.addr[1])
    want("product name", ident["name"], name)
    if ident["vendor"] == 1:
        raise Fail("ListIdentity claims vendor 1 (Rockwell)")
    want("device type", ident["device_type"], 0x0E)
    # the Identity object says the same (Get_Attribute_Single, attribute 7)
    c.register()
    svc, st, ext, d = cip_status(c.rr(b"\x0e\x03\x20\x01\x24\x01\x30\x07"))
    want("Get_Attribute_Single reply", (svc, st), (0x8E, 0))
    want("attribute 7 (product name)", d[1:1 + d[0]].decode(), name)
    svc, st, ext, d = cip_status(c.rr(b"\x01\x02\x20\x01\x24\x01"))
    want("Get_Attributes_All reply", (svc, st), (0x81, 0))
    want("Get_Attributes_All vendor", struct.unpack_from("<H", d)[0], ident["vendor"])
    want("Get_Attributes_All name", d[15:15 + d[14]].decode(), name)
    svc, st, ext, d = cip_status(c.rr(b"\x0e\x03\x20\x01\x24\x01\x30\x63"))
    want("attribute 99: attribute not supported", st, 0x14)


def check_identity_udp(addr, name):
    host, port = addr.rsplit(":", 1)
    u = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    u.settimeout(TIMEOUT)
    u.sendto(encap(0x63), (host, int(port)))
    data, peer = u.recvfrom(2048)
    cmd, n, session, status, ctx, options = struct.unpack_from("<HHII8sI", data)
    want("UDP ListIdentity reply command", cmd, 0x63)
    want("UDP ListIdentity status", status, 0)
    want("UDP ListIdentity length", n, len(data) - 24)
    ident = parse_identity(data[24:], int(port))
    want("UDP product name", ident["name"], name)


def check_services(addr):
    c = Conn(addr)
    c.send(encap(0x04))
    cmd, session, status, ctx, data = c.reply()
    want("ListServices status", status, 0)
    count, itype, ilen, version, flags = struct.unpack_from("<HHHHH", data)
    want("ListServices item", (count, itype, ilen, version), (1, 0x100, 20, 1))
    if not flags & 0x20:
        raise Fail("ListServices: CIP over TCP flag (bit 5) not set: 0x%04X" % flags)
    want("service name", data[10:26].rstrip(b"\0"), b"Communications")


def check_malformed(addr):
    # unknown command: status 0x0001, the connection stays usable
    c = Conn(addr)
    c.send(encap(0x99, b"abcd"))
    cmd, session, status, ctx, data = c.reply()
    want("unknown command reply command", cmd, 0x99)
    want("unknown command status", status, 0x0001)
    c.send(encap(0x00, b"xy"))              # NOP: no reply at all
    c.register()                            # the next reply is RegisterSession's
    # wrong session handle: 0x0064
    c.send(encap(0x6F, struct.pack("<IHH", 0, 0, 0), c.session ^ 0x5A5A0000))
    cmd, session, status, ctx, data = c.reply()
    want("wrong session handle status", status, 0x0064)
    # truncated CPF: the data item says 50 bytes, 4 follow: 0x0003
    cpf = struct.pack("<IHH", 0, 0, 2) + struct.pack("<HH", 0, 0) + struct.pack("<HH", 0xB2, 50) + b"\x4b\x02\x20\x67"
    c.send(encap(0x6F, cpf, c.session))
    cmd, session, status, ctx, data = c.reply()
    want("truncated CPF status", status, 0x0003)
    # SendRRData before RegisterSession on a new connection: 0x0064
    d = Conn(addr)
    d.send(encap(0x6F, struct.pack("<IHH", 0, 0, 0), 0x1234))
    cmd, session, status, ctx, data = d.reply()
    want("unregistered SendRRData status", status, 0x0064)
    # a request with a non-zero status is discarded, the next one answered
    c.send(encap(0x04, status=5))
    c.send(encap(0x04))
    cmd, session, status, ctx, data = c.reply()
    want("after a discarded request: ListServices", (cmd, status), (0x04, 0))
    # the old connection still reads
    reply = pccc_reply(c.rr(pccc_request(slc_read(0x0101, 2, 7, 0x89, 1))))
    want("read after the errors", reply, b"\x4f\x00\x01\x01\x01\x00")
    # bad length (more than the server takes): 0x0065, then the connection is closed
    c.send(encap(0x6F, b"", c.session, length=0xFFF0))
    cmd, session, status, ctx, data = c.reply()
    want("bad length status", status, 0x0065)
    want("connection closed after bad length", c.closed(), True)


def check_cip_errors(addr):
    c = Conn(addr)
    c.register()
    svc, st, ext, d = cip_status(c.rr(b"\x4c\x02\x20\x67\x24\x01" + REQID))
    want("service 4C to class 67: service not supported", (svc, st), (0xCC, 0x08))
    svc, st, ext, d = cip_status(c.rr(b"\x01\x02\x20\x99\x24\x01"))
    want("class 99: path destination unknown", (svc, st), (0x81, 0x05))
    svc, st, ext, d = cip_status(c.rr(b"\x4b\x02\x20\x67\x24\x02" + REQID + b"\x06\x00\x01\x00\x03"))
    want("PCCC instance 2: path destination unknown", st, 0x05)
    svc, st, ext, d = cip_status(c.rr(b"\x4b\x02\xe0\x67\x24\x01" + REQID))
    want("unknown segment type: path segment error", st, 0x04)
    svc, st, ext, d = cip_status(c.rr(b"\x4b\x09\x20\x67"))
    want("path size past the end: path size invalid", st, 0x26)
    svc, st, ext, d = cip_status(c.rr(b"\x4b\x02\x20\x67\x24\x01\x07\x4d\x00"))
    want("short requester ID: not enough data", st, 0x13)
    svc, st, ext, d = cip_status(c.rr(b"\x4e\x02\x20\x06\x24\x01\x0a\x0e\x09\x00\x4d\x00\x01\x00\x00\x00\x00\x00"))
    want("Forward Close of no connection", (svc, st, ext), (0xCE, 0x01, [0x0107]))


def check_read_write(addr):
    c = Conn(addr)
    c.register()
    # N7:0-2 (2-byte elements): df1sim's default N7:n = n
    r = pccc_reply(c.rr(pccc_request(slc_read(0x1234, 6, 7, 0x89, 0))))
    want("N7:0 x3", r, b"\x4f\x00\x34\x12" + struct.pack("<hhh", 0, 1, 2))
    # F8:1 = 1.5 (4-byte float)
    r = pccc_reply(c.rr(pccc_request(slc_read(0x1235, 4, 8, 0x8A, 1))))
    want("F8:1", r, b"\x4f\x00\x35\x12" + struct.pack("<f", 1.5))
    r = pccc_reply(c.rr(pccc_request(slc_write(0x1236, 7, 0x89, 20, struct.pack("<h", -1234)))))
    want("write N7:20 reply", r, b"\x4f\x00\x36\x12")
    r = pccc_reply(c.rr(pccc_request(slc_read(0x1237, 2, 7, 0x89, 20))))
    want("N7:20 read back", r, b"\x4f\x00\x37\x12" + struct.pack("<h", -1234))
    # no such file: STS F0 EXT STS passed as the PLC gives it (06: not usable)
    r = pccc_reply(c.rr(pccc_request(slc_read(0x1238, 2, 77, 0x89, 0))))
    if r[:4] != b"\x4f\xf0\x38\x12":
        raise Fail("N77:0: expected STS F0 and an EXT STS, got %s" % r.hex())
    # diagnostic status: a MicroLogix 1400's processor
    r = pccc_reply(c.rr(pccc_request(b"\x06\x00\x39\x12\x03")))
    want("diag status reply head", r[:4], b"\x46\x00\x39\x12")


def check_connected(addr, large):
    c = Conn(addr)
    c.register()
    svc, st, ext, d = cip_status(c.rr(forward_open(7, 0x11223344, large=large)))
    want("Forward Open reply", (svc, st), (0xDB if large else 0xD4, 0))
    ot_id, to_id, serial, vendor, oserial = struct.unpack_from("<IIHHI", d)
    want("T->O id echoed", to_id, 0x11223344)
    want("serials echoed", (serial, vendor, oserial), (7, 0x4D, 0x87654321))
    # the same Forward Open again: duplicate
    svc, st, ext, d = cip_status(c.rr(forward_open(7, 0x55555555, large=large)))
    want("duplicate Forward Open", (st, ext), (0x01, [0x0100]))
    for seq in (1, 2):
        c.unit(ot_id, seq, pccc_request(slc_read(0x4400 + seq, 2, 7, 0x89, 3)))
        cid, rseq, cip = c.unit_reply()
        want("reply on the T->O id", cid, 0x11223344)
        want("sequence count echoed", rseq, seq)
        want("connected read N7:3", pccc_reply(cip), struct.pack("<BBH", 0x4F, 0, 0x4400 + seq) + b"\x03\x00")
    svc, st, ext, d = cip_status(c.rr(forward_close(7)))
    want("Forward Close reply", (svc, st), (0xCE, 0))
    # the closed connection's id: no reply; the next message is answered
    c.unit(ot_id, 3, pccc_request(slc_read(0x4403, 2, 7, 0x89, 3)))
    c.send(encap(0x04))
    cmd, session, status, ctx, data = c.reply()
    want("after SendUnitData on a closed connection: ListServices", cmd, 0x04)


def check_routed(addr, station, value, other):
    """Write N7:9 = value to `station` through Unconnected Send (port 2, link
    station), read it back there, and see that `other` (the default station)
    kept its own N7:9."""
    c = Conn(addr)
    c.register()
    route = struct.pack("BB", 2, station)
    r = pccc_reply(c.rr(unconnected_send(pccc_request(slc_write(0x5501, 7, 0x89, 9, struct.pack("<h", value))),
                                         route)))
    want("routed write reply", r, b"\x4f\x00\x01\x55")
    r = pccc_reply(c.rr(unconnected_send(pccc_request(slc_read(0x5502, 2, 7, 0x89, 9)), route)))
    want("routed read back", r, b"\x4f\x00\x02\x55" + struct.pack("<h", value))
    r = pccc_reply(c.rr(pccc_request(slc_read(0x5503, 2, 7, 0x89, 9))))
    want("default station %d N7:9 (direct)" % other, r, b"\x4f\x00\x03\x55" + struct.pack("<h", 9))
    r = pccc_reply(c.rr(unconnected_send(pccc_request(slc_read(0x5504, 2, 7, 0x89, 9)), b"\x01\x00")))
    want("route to port 1 (the bridge itself): default station", r, b"\x4f\x00\x04\x55" + struct.pack("<h", 9))
    # a station not served: connection failure, unconnected request timed out
    svc, st, ext, d = cip_status(c.rr(unconnected_send(pccc_request(slc_read(0x5505, 2, 7, 0x89, 9)), b"\x02\x63")))
    want("station 99 not served", (svc, st, ext), (0xD2, 0x01, [0x0204]))
    # port 5 does not exist
    svc, st, ext, d = cip_status(c.rr(unconnected_send(pccc_request(slc_read(0x5506, 2, 7, 0x89, 9)), b"\x05\x01")))
    want("route to port 5", (svc, st, ext), (0xD2, 0x01, [0x0311]))


def check_others_served(addr):
    """A client that stops halfway through a header does not hold up others."""
    a = Conn(addr)
    a.register()
    a.send(encap(0x6F, b"", a.session)[:10])
    b = Conn(addr)
    b.register()
    r = pccc_reply(b.rr(pccc_request(slc_read(0x6601, 2, 7, 0x89, 4))))
    want("second client's read", r, b"\x4f\x00\x01\x66\x04\x00")
    a.send(encap(0x04)[:0])   # nothing: a still waits for the rest of its header


def check_refused(addr):
    c = Conn(addr)
    c.send(encap(0x63))
    want("a client outside the allow list is closed", c.closed(), True)


def check_read_only(addr):
    c = Conn(addr)
    c.register()
    r = pccc_reply(c.rr(pccc_request(slc_write(0x7701, 7, 0x89, 30, struct.pack("<h", 555)))))
    want("write refused: STS 60 (command protection)", r, b"\x4f\x60\x01\x77")
    r = pccc_reply(c.rr(pccc_request(slc_read(0x7702, 2, 7, 0x89, 30))))
    want("N7:30 unchanged", r, b"\x4f\x00\x02\x77" + struct.pack("<h", 30))
    r = pccc_reply(c.rr(pccc_request(b"\x0f\x00\x03\x77\x80\x01")))
    want("mode change refused", r, b"\x4f\x60\x03\x77")


def check_no_answer(addr):
    c = Conn(addr)
    c.register()
    svc, st, ext, d = cip_status(c.rr(pccc_request(slc_read(0x8801, 2, 7, 0x89, 0))))
    want("a silent station: connection failure, timed out", (svc, st, ext), (0xCB, 0x01, [0x0204]))


CHECKS = {
    "register": check_register,
    "identity-tcp": check_identity_tcp,
    "identity-udp": check_identity_udp,
    "services": check_services,
    "malformed": check_malformed,
    "cip-errors": check_cip_errors,
    "read-write": check_read_write,
    "connected": lambda a: check_connected(a, False),
    "connected-large": lambda a: check_connected(a, True),
    "routed": lambda a, st, v, o: check_routed(a, int(st), int(v), int(o)),
    "others-served": check_others_served,
    "refused": check_refused,
    "read-only": check_read_only,
    "no-answer": check_no_answer,
}


def main():
    if len(sys.argv) < 3 or sys.argv[2] not in CHECKS:
        sys.stderr.write("usage: eip_probe.py HOST:PORT (%s) [ARGS]\n" % "|".join(CHECKS))
        return 2
    addr = sys.argv[1]
    if addr.startswith("eip://"):
        addr = addr[6:]
    try:
        CHECKS[sys.argv[2]](addr, *sys.argv[3:])
    except (Fail, OSError, struct.error, IndexError, UnicodeDecodeError) as e:
        sys.stderr.write("eip_probe %s: %s\n" % (sys.argv[2], e))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
