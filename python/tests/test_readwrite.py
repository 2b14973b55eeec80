# SPDX-License-Identifier: MPL-2.0
"""Reads and writes of every file type against df1sim, on a pty and over TCP, both
duplex modes and the radio modem, BCC and CRC. Expected values are df1sim(1)'s documented initial
table (N7:n = n, F8:n = n + 0.5, L10:n = n * 65536 + n, T/C PRE 100, ST "STRING n",
the rest 0) and what was written; the --log frame log shows what was sent."""
import pytest

import libdf1

LINKS = [
    ("pty", "full", "crc"), ("pty", "full", "bcc"), ("pty", "half", "crc"), ("pty", "half", "bcc"),
    ("tcp", "full", "crc"), ("tcp", "half", "bcc"),
    ("pty", "radio", "crc"), ("tcp", "radio", "bcc"),
]


@pytest.fixture(params=LINKS, ids=["-".join(p) for p in LINKS])
def line(request, sim_factory):
    transport, duplex, check = request.param
    s = sim_factory("--duplex", duplex, "--check", check, tcp=transport == "tcp")
    with libdf1.open(s.target, duplex=duplex, check=check, timeout_ms=2000) as plc:
        yield s, plc


def test_read_every_file_type(line):
    s, plc = line
    assert plc.read("N7:0") == 0
    assert plc.read("N7:3") == 3
    assert plc.read("N7:0", 10) == list(range(10))
    assert plc.read("F8:2") == 2.5
    assert plc.read("F8:0", 3) == [0.5, 1.5, 2.5]
    assert plc.read("L10:1") == 65537
    assert plc.read("ST9:4") == "STRING 4"
    assert plc.read("B3:0") == 0
    assert plc.read("B3:0/5") is False
    assert plc.read("B3/21", 3) == [False, False, False]
    assert plc.read("S2:0") == 0
    assert plc.read("A11:0") == 0
    assert plc.read("O:0") == 0
    assert plc.read("I:0") == 0
    t = plc.read("T4:1")
    assert isinstance(t, libdf1.Timer) and (t.pre, t.acc, t.en, t.tt, t.dn) == (100, 0, False, False, False)
    c = plc.read("C5:2")
    assert isinstance(c, libdf1.Counter) and (c.pre, c.acc, c.cu, c.ov) == (100, 0, False, False)
    r = plc.read("R6:0")
    assert isinstance(r, libdf1.Control) and (r.len, r.pos, r.en, r.dn) == (0, 0, False, False)
    assert plc.read("T4:1.PRE") == 100
    assert plc.read("T4:1/DN") is False
    assert plc.read("C5:0.ACC") == 0
    assert plc.read("R6:0.LEN") == 0
    # every read was one command answered (a reply sent again is not logged again)
    assert len(s.wait_log(21)) == 21


def test_write_every_file_type(line):
    s, plc = line
    plc.write("N7:5", 1234)
    plc.write("N7:10", [-1, -32768, 32767])
    plc.write("F8:1", -2.25)
    plc.write("L10:2", -100000)
    plc.write("ST9:1", "Hello, world")
    plc.write("B3:1/5", True)
    plc.write("T4:2", libdf1.Timer(pre=500, acc=7, en=True, dn=True))
    plc.write("C5:3", libdf1.Counter(pre=-3, acc=4, cu=True, ov=True))
    plc.write("R6:1", libdf1.Control(len=10, pos=2, en=True, in_=True))
    plc.write("T4:0.ACC", 42)
    assert plc.read("N7:5") == 1234
    assert plc.read("N7:10", 3) == [-1, -32768, 32767]
    assert plc.read("F8:1") == -2.25
    assert plc.read("L10:2") == -100000
    assert plc.read("ST9:1") == "Hello, world"
    assert plc.read("B3:1") == 1 << 5
    assert plc.read("B3:1/5") is True
    assert plc.read("T4:2") == libdf1.Timer(pre=500, acc=7, en=True, dn=True)
    assert plc.read("C5:3") == libdf1.Counter(pre=-3, acc=4, cu=True, ov=True)
    assert plc.read("R6:1") == libdf1.Control(len=10, pos=2, en=True, in_=True)
    assert plc.read("T4:0.ACC") == 42
    # a timer's named bits are the control word's bits 15 (EN) and 13 (DN)
    assert plc.read("T4:2").ctl == 0xA000
    # a bit write leaves the other bits of its word alone
    plc.write("B3:1/0", True)
    plc.write("B3:1/5", False)
    assert plc.read("B3:1") == 1
    # each write went out once (SLC protected typed logical write 0F/AA, masked 0F/AB)
    assert len(s.wait_log(1, "addr=N7:5", "cmd=0F/AA")) == 1
    assert len(s.wait_log(1, "addr=N7:10", "cmd=0F/AA", "count=3")) == 1
    assert len(s.wait_log(3, "addr=B3:1", "cmd=0F/AB")) == 3


def test_read_many_fewest_transactions(line):
    s, plc = line
    plc.counters_reset()
    got = plc.read_many(["N7:0", "N7:1,4", "F8:3", "T4:0.ACC", ("B3:0/5", 2), "T4:0/DN"])
    assert got == {"N7:0": 0, "N7:1,4": [1, 2, 3, 4], "F8:3": 3.5, "T4:0.ACC": 0,
                   ("B3:0/5", 2): [False, False], "T4:0/DN": False}
    # one block per file: N7, F8, T4, B3
    assert plc.last_reads == 4
    assert plc.counters()["CNT_CMD_MSGS_SENT"] == 4


def test_read_many_one_bad_address_does_not_hide_the_others(sim):
    with libdf1.open(sim.target) as plc:
        got = plc.read_many(["N7:0", "N99:0", "F8:0"], errors="return")
        assert got["N7:0"] == 0 and got["F8:0"] == 0.5
        assert isinstance(got["N99:0"], libdf1.PlcError) and got["N99:0"].ext_sts == 0x06
        with pytest.raises(libdf1.PlcError) as ei:
            plc.read_many(["N7:0", "N99:0"])
        assert ei.value.results == {"N7:0": 0}


@pytest.mark.parametrize("family,plc_name,cmd", [("plc5", "plc5", "0F/68"), ("micrologix", "micrologix", "0F/A2"),
                                                 ("slc502", "slc502", "0F/A2")])
def test_plc_types(sim_factory, family, plc_name, cmd):
    s = sim_factory("--plc", family)
    with libdf1.open(s.target, plc=plc_name) as plc:
        assert plc.read("N7:0", 5) == [0, 1, 2, 3, 4]
        assert plc.read("F8:1") == 1.5
        assert plc.read("T4:0").pre == 100
        if family == "slc502":
            # an 84-byte string element does not fit an 82-byte packet
            with pytest.raises(libdf1.Df1Error) as ei:
                plc.read("ST9:2")
            assert ei.value.name == "DF1_E_NOTSUP"
        else:
            assert plc.read("ST9:2") == "STRING 2"
        plc.write("N7:1", -7)
        assert plc.read("N7:1") == -7
        if family == "micrologix":
            assert plc.read("L10:3") == 3 * 65536 + 3
    assert len(s.wait_log(1, "cmd=" + cmd, "addr=N7:0", "count=5")) == 1


def test_plc2(sim_factory):
    s = sim_factory(data="N9:0=11,22,33\n")
    with libdf1.open(s.target, plc="plc2") as plc:
        assert plc.read("N9:0", 3) == [11, 22, 33]


def test_large_read_is_split(sim):
    with libdf1.open(sim.target) as plc:
        assert plc.read("N7:0", 200) == list(range(200))
    # 236 data bytes a read on an SLC 5/03+: 118 words, then 82
    assert len(sim.wait_log(1, "addr=N7:0", "count=118")) == 1
    assert len(sim.wait_log(1, "addr=N7:118", "count=82")) == 1


def test_raw_and_command(sim):
    with libdf1.open(sim.target) as plc:
        assert plc.read_raw("N7:1", 4) == b"\x01\x00\x02\x00"
        assert plc.write_raw("N7:1", b"\x34\x12") == 2
        assert plc.read("N7:1") == 0x1234
        # 06/00 echo as a raw PCCC command: FNC 00, data back
        assert plc.command(0x06, b"\x00abc") == b"abc"
