# SPDX-License-Identifier: MPL-2.0
"""Diagnostics against df1sim: diagnostic status (the processor df1sim(1) documents
for --processor), echo, link test, counters by doc/REQUIREMENTS.md 004 mnemonic matched to the
frame log, station discovery in half duplex (who answers) and full duplex."""
import pytest

import libdf1


@pytest.mark.parametrize("args,plc,code,name", [
    ((), "slc", 0x5B, "SLC 5/04"),
    (("--processor", "ml1400"), "micrologix", 0x9F, "MicroLogix 1400"),
    (("--plc", "plc5"), "plc5", 0x15, "PLC-5/40"),
])
def test_diag_status(sim_factory, args, plc, code, name):
    s = sim_factory(*args)
    with libdf1.open(s.target, plc=plc) as p:
        d = p.diag_status()
    assert (d.type_code, d.name) == (code, name)
    assert d.mode_text in ("run", "remote run")      # a PLC-5 reports its keyswitch too
    assert isinstance(d.raw, bytes) and len(d.raw) > 0
    assert len(s.wait_log(1, "cmd=06/03")) == 1


def test_change_mode_shows_in_diag_status(sim):
    with libdf1.open(sim.target) as p:
        p.change_mode(1)
        assert p.diag_status().mode_text == "program"
        p.change_mode(6)
        assert p.diag_status().mode_text == "run"


@pytest.mark.parametrize("duplex", ["full", "half"])
def test_echo_and_link_test(sim_factory, duplex):
    s = sim_factory("--duplex", duplex)
    with libdf1.open(s.target, duplex=duplex, timeout_ms=100, enq_retries=1, nak_retries=1) as p:
        assert p.echo(b"hello, plc") == 10
        assert p.link_test() is None
        s.silence()
        with pytest.raises(libdf1.CommunicationError):
            p.link_test()
    assert len(s.wait_log(1, "cmd=06/00")) == 1


@pytest.mark.parametrize("duplex", ["full", "half"])
def test_counters_match_the_frame_log(sim_factory, duplex):
    s = sim_factory("--duplex", duplex)
    with libdf1.open(s.target, duplex=duplex) as p:
        p.counters_reset()
        for i in range(7):
            p.read("N7:%d" % i)
        c = p.counters()
    lines = s.wait_log(7)
    assert len(lines) == 7
    assert c["CNT_CMD_MSGS_SENT"] == 7 and c["CNT_REPLY_MSGS_RCVD"] == 7
    assert c["CNT_NAKS_RCVD"] == 0 and c["CNT_COMMAND_TIMEOUTS"] == 0
    assert c["CRD_CHAR_SENT"] > 0 and c["CRD_CHAR_RECV"] > 0
    if duplex == "half":
        assert c["CNT_POLL_MSGS_SENT"] >= 7
    # every counter of the catalog, by mnemonic
    ids = {}
    i = 0
    while True:
        e = libdf1.lib.df1_catalog_at(i)
        if e == libdf1.ffi.NULL:
            break
        if e.severity == libdf1.lib.DF1_SEV_COUNTER:
            ids[libdf1.ffi.string(e.mnemonic).decode()] = e.id
        i += 1
    assert set(c) == set(ids) and len(c) == 29


def test_discovery_half_duplex(sim_factory):
    s = sim_factory("--duplex", "half", "--station", "1,3")
    with libdf1.open(s.target, duplex="half", timeout_ms=100) as p:
        probed = p.discover(0, 4)
        assert [st.station for st in probed] == [0, 1, 2, 3, 4]
        answered = p.stations(0, 4)
    assert [st.station for st in answered] == [1, 3]
    for st in answered:
        assert st.identified and st.error is None and st.status.name == "SLC 5/04"
    silent = [st for st in probed if not st.answered]
    assert [st.station for st in silent] == [0, 2, 4]
    assert all(isinstance(st.error, libdf1.Df1Error) for st in silent)


def test_discovery_stops_when_asked_and_passes_exceptions(sim):
    with libdf1.open(sim.target) as p:
        seen = p.discover(1, 10, progress=lambda st: st.station == 2)
        assert [st.station for st in seen] == [1, 2]

        def boom(st):
            raise KeyError("from the callback")
        with pytest.raises(KeyError):
            p.discover(1, 3, progress=boom)


def test_discovery_full_duplex_no_peer(sim):
    with libdf1.open(sim.target, timeout_ms=100, enq_retries=1) as p:
        sim.silence()
        with pytest.raises(libdf1.CommunicationError):
            p.stations(1, 3)
