#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""eip_pycomm3.py - pycomm3's SLCDriver (PyPI) as an independent EtherNet/IP
client for tests/integration/it_eip_sim.sh: RegisterSession, Forward Open, Execute PCCC in
SendUnitData, Forward Close, as pycomm3 sends them.

    eip_pycomm3.py available                 exit 0 if pycomm3 imports
    eip_pycomm3.py HOST:PORT read ADDR...    one line per address: ADDR=VALUE
    eip_pycomm3.py HOST:PORT write ADDR=VALUE...
    eip_pycomm3.py HOST:PORT processor       the diagnostic status' processor type

Values: integers, floats (with a dot), "text" for ST, true/false for bits,
lists as a,b,c for ADDR{N}. Exit 1 with pycomm3's error on stderr when a tag
comes back with an error.
"""
import sys


def parse_value(text):
    if text.startswith('"') and text.endswith('"'):
        return text[1:-1]
    if text in ("true", "false"):
        return text == "true"
    if "," in text:
        return [parse_value(t) for t in text.split(",")]
    if "." in text:
        return float(text)
    return int(text)


def show(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, list):
        return ",".join(show(x) for x in v)
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, str):
        return '"%s"' % v
    return str(v)


def main():
    if len(sys.argv) >= 2 and sys.argv[1] == "available":
        try:
            import pycomm3  # noqa: F401
        except ImportError:
            return 1
        return 0
    from pycomm3 import SLCDriver
    addr, op, args = sys.argv[1], sys.argv[2], sys.argv[3:]
    if addr.startswith("eip://"):
        addr = addr[6:]
    status = 0
    with SLCDriver(addr) as plc:
        if op == "read":
            for a in args:
                tag = plc.read(a)
                if tag.error:
                    sys.stderr.write("%s: %s\n" % (a, tag.error))
                    status = 1
                else:
                    print("%s=%s" % (a, show(tag.value)))
        elif op == "write":
            for aw in args:
                a, v = aw.split("=", 1)
                tag = plc.write((a, parse_value(v)))
                if tag.error:
                    sys.stderr.write("%s: %s\n" % (a, tag.error))
                    status = 1
        elif op == "processor":
            print(plc.get_processor_type())
        else:
            sys.stderr.write("unknown operation %s\n" % op)
            status = 2
    return status


if __name__ == "__main__":
    sys.exit(main())
