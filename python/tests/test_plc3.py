# SPDX-License-Identifier: MPL-2.0
"""A PLC-3 through the binding: plc="plc3" takes a PLC-3's address text and moves
words with word range read/write and bit write (doc/PROTOCOL.md 4.2a), against
df1sim --plc plc3, checked in df1sim's --log."""
import libdf1


def test_plc3_read_write(sim_factory):
    s = sim_factory("--plc", "plc3", data="N3:173=42\nF2:10=1.5\n")
    with libdf1.open(s.target, plc="plc3") as plc:
        assert plc.read("N3:173") == 42
        assert plc.read("F2:10") == 1.5
        plc.write("N3:174", -7)
        assert plc.read("N3:173", 2) == [42, -7]
        plc.write("B5:173/15", True)          # octal bit 15 = bit 13
        assert plc.read("B5:173") == 1 << 13
        plc.write("T4.PRE", 300)
        assert plc.read("T4.PRE") == 300
        plc.write("H8:99", 123456789)
        assert plc.read("H8:99") == 123456789
    assert len(s.wait_log(1, "cmd=0F/02", "addr=B5:173")) == 1
    assert len(s.wait_log(1, "cmd=0F/00", "addr=T4.PRE")) == 1
    assert len(s.wait_log(2, "cmd=0F/01", "addr=N3:173")) == 2


def test_plc3_address_errors(sim_factory):
    s = sim_factory("--plc", "plc3")
    with libdf1.open(s.target, plc="plc3") as plc:
        for bad in ("B5:0/18", "T4:2.ACC", "R6:0"):
            try:
                plc.read(bad)
            except libdf1.AddressError:
                pass
            else:
                raise AssertionError("%s was accepted" % bad)
    assert s.log_lines("cmd=0F/01") == []
