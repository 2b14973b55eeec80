#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""eipgw_probe.py - EtherNet/IP checks of df1gw --eip for tests/integration/it_df1gw_eip.sh,
on the raw-socket client of tests/support/eip_probe.py (its messages are built
from the layouts of df1-eip(7), not from libdf1's code).

    eipgw_probe.py HOST:PORT CHECK [ARGS...]

    identity NAME                ListIdentity over TCP: vendor 0, product NAME
    write STATION ELEM VALUE     N7:ELEM = VALUE (STATION -: no route path), reply 4F 00 TNS
    read STATION ELEM VALUE      N7:ELEM reads VALUE
    no-answer                    a PCCC reply with STS 30h and the client's TNS
    read-only ELEM               a write refused with STS 60h, a mode change too
    writes STATION ELEM0 N TAG   N writes N7:ELEM0.. = TAG*1000+i in one session;
                                 prints "ELEM ok|noanswer" per write (faults allowed)
Exit 0 when the check holds, 1 with what differed on stderr. Every wait is
bounded by eip_probe's socket timeout; nothing sleeps.
"""
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import eip_probe as ep  # noqa: E402


def request(c, station, pccc):
    req = ep.pccc_request(pccc)
    if station != "-":
        req = ep.unconnected_send(req, struct.pack("BB", 2, int(station)))
    return ep.pccc_reply(c.rr(req))


def session(addr):
    c = ep.Conn(addr)
    c.register()
    return c


def check_identity(addr, name):
    c = ep.Conn(addr)
    c.send(ep.encap(0x63))
    cmd, sess, status, ctx, data = c.reply()
    ep.want("ListIdentity reply", (cmd, status), (0x63, 0))
    ident = ep.parse_identity(data, int(addr.rsplit(":", 1)[1]))
    ep.want("vendor (none claimed)", ident["vendor"], 0)
    ep.want("product name", ident["name"], name)


def check_write(addr, station, elem, value):
    c = session(addr)
    r = request(c, station, ep.slc_write(0x3101, 7, 0x89, int(elem), struct.pack("<h", int(value))))
    ep.want("write reply", r, b"\x4f\x00\x01\x31")


def check_read(addr, station, elem, value):
    c = session(addr)
    r = request(c, station, ep.slc_read(0x3202, 2, 7, 0x89, int(elem)))
    ep.want("N7:%s" % elem, r, b"\x4f\x00\x02\x32" + struct.pack("<h", int(value)))


def check_no_answer(addr):
    c = session(addr)
    r = request(c, "-", ep.slc_read(0x3303, 2, 7, 0x89, 0))
    ep.want("no controller: STS 30h, the client's TNS", r, b"\x4f\x30\x03\x33")


def check_read_only(addr, elem):
    c = session(addr)
    r = request(c, "-", ep.slc_write(0x3404, 7, 0x89, int(elem), struct.pack("<h", 777)))
    ep.want("write refused: STS 60h", r, b"\x4f\x60\x04\x34")
    r = request(c, "-", b"\x0f\x00\x05\x34\x80\x01")
    ep.want("mode change refused", r, b"\x4f\x60\x05\x34")
    r = request(c, "-", ep.slc_read(0x3406, 2, 7, 0x89, int(elem)))
    ep.want("a read still passes", r[:2], b"\x4f\x00")


def check_writes(addr, station, elem0, n, tag):
    c = session(addr)
    for i in range(int(n)):
        elem = int(elem0) + i
        tns = (int(tag) << 8 | i) & 0xFFFF
        value = int(tag) * 1000 + i
        r = request(c, station, ep.slc_write(tns, 7, 0x89, elem, struct.pack("<h", value)))
        head = struct.pack("<BBH", 0x4F, 0, tns)
        if r == head:
            print("%d ok" % elem)
        elif r == struct.pack("<BBH", 0x4F, 0x30, tns):
            print("%d noanswer" % elem)
        else:
            raise ep.Fail("write N7:%d: reply %s" % (elem, r.hex()))


CHECKS = {
    "identity": check_identity,
    "write": check_write,
    "read": check_read,
    "no-answer": check_no_answer,
    "read-only": check_read_only,
    "writes": check_writes,
}


def main():
    if len(sys.argv) < 3 or sys.argv[2] not in CHECKS:
        sys.stderr.write("usage: eipgw_probe.py HOST:PORT (%s) [ARGS]\n" % "|".join(CHECKS))
        return 2
    addr = sys.argv[1]
    if addr.startswith("eip://"):
        addr = addr[6:]
    try:
        CHECKS[sys.argv[2]](addr, *sys.argv[3:])
    except (ep.Fail, OSError) as e:
        sys.stderr.write("eipgw_probe %s: %s\n" % (sys.argv[2], e))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
