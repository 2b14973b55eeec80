# SPDX-License-Identifier: MPL-2.0
"""The poll engine from Python: changes with value, quality, reason and time; a
silenced station goes UNCERTAIN, then BAD when offline (doc/REQUIREMENTS.md 000), and comes
back GOOD; a write queued from another thread executes exactly once (df1sim's
--log frame log)."""
import threading

import pytest

import libdf1
from libdf1 import Quality, Reason


def _until(poller, pred, timeout=20.0):
    """Changes until pred(change) holds (bounded)."""
    seen = []
    for ch in poller.changes(timeout=timeout):
        seen.append(ch)
        if pred(ch):
            return seen
    raise AssertionError("condition not met; changes: %r" % seen)


def test_first_scan_reports_every_tag(sim):
    with libdf1.open(sim.target) as plc:
        poller = plc.poller(tags=["N7:3", "F8:1", "N7:0,4", libdf1.Tag("T4:0", name="timer"),
                                  libdf1.Tag("B3:0/5", name="bit", scan_ms=0)])
        assert poller.tags == ["N7:3", "F8:1", "N7:0,4", "timer", "bit"]
        got = {}
        for ch in poller.changes(timeout=20):
            got[ch.tag] = ch
            if len(got) == 5:
                break
        assert got["N7:3"].value == 3 and got["F8:1"].value == 1.5 and got["N7:0,4"].value == [0, 1, 2, 3]
        assert got["timer"].value == libdf1.Timer(pre=100) and got["bit"].value is False
        for ch in got.values():
            assert ch.quality is Quality.GOOD and ch.reason is Reason.NONE and ch.timestamp is not None
            tag, value, quality, reason, ts = ch     # a tuple of five
        st = poller.state("N7:3")
        assert st.value == 3 and st.quality == "GOOD" and st.reads >= 1
        # the N7 tags were coalesced into one block read
        assert poller.stats()["blocks"] == 4


@pytest.mark.parametrize("duplex,check", [("full", "crc"), ("half", "bcc")])
def test_silenced_station_goes_uncertain_then_bad_and_comes_back(sim_factory, duplex, check):
    sim = sim_factory("--duplex", duplex, "--check", check)
    with libdf1.open(sim.target, duplex=duplex, check=check, timeout_ms=100, enq_retries=1,
                     nak_retries=1) as plc:
        poller = plc.poller(tags=[libdf1.Tag("N7:1", scan_ms=0)], watchdog_ms=1000, absolute_retries=5)
        _until(poller, lambda c: c.quality == "GOOD" and c.value == 1)
        sim.silence()
        seen = _until(poller, lambda c: c.quality == "BAD")
        qualities = [(c.quality, c.reason) for c in seen]
        # doc/REQUIREMENTS.md 002/000: the first scan's attempt and two retries fail (3), later scans one
        # attempt each; more than 5 in a row: offline. Until then the last good value
        # is UNCERTAIN (comm failure), then BAD (station offline)
        assert (Quality.UNCERTAIN, Reason.COMM_FAILURE) in qualities
        assert qualities[-1] == (Quality.BAD, Reason.STATION_OFFLINE)
        assert seen[-1].value == 1          # the last good value is kept
        assert poller.station_health(1)["state"] == "offline"
        sim.restore()
        # an offline station is retried every watchdog_ms / 2; answering, it is read at once
        back = _until(poller, lambda c: c.quality == "GOOD")
        assert back[-1].value == 1 and back[-1].reason is Reason.NONE
        assert poller.station_health(1)["state"] == "ok"


def test_write_from_another_thread_executes_exactly_once(sim):
    with libdf1.open(sim.target) as plc:
        poller = plc.poller(tags=[libdf1.Tag("N7:5", access="readwrite", scan_ms=0)])
        _until(poller, lambda c: c.value == 5)
        futures = []
        t = threading.Thread(target=lambda: futures.append(poller.write("N7:5", 1234)))
        t.start()
        t.join()
        fut = futures[0]
        seen = _until(poller, lambda c: c.value == 1234)
        assert fut.done() and fut.result() is None and fut.write_id > 0
        assert seen[-1].quality == "GOOD"
        # drain a few more scans: the write is never sent again
        for _ in poller.changes(timeout=0.3):
            pass
    lines = sim.wait_log(1, "addr=N7:5", "cmd=0F/AA")
    assert len(lines) == 1, lines


def test_failed_write_ends_once_with_the_error(sim):
    with libdf1.open(sim.target, timeout_ms=100, enq_retries=1) as plc:
        poller = plc.poller(tags=[libdf1.Tag("N7:6", access="readwrite", scan_ms=0)])
        _until(poller, lambda c: c.value == 6)
        sim.silence()
        fut = poller.write("N7:6", 66)
        for _ in poller.changes(timeout=20):
            if fut.done():
                break
        with pytest.raises(libdf1.CommunicationError):
            fut.result(timeout=0)
    assert sim.log_lines("addr=N7:6", "cmd=0F/AA") == []


def test_write_checks_values_at_once(sim):
    with libdf1.open(sim.target) as plc:
        poller = plc.poller(tags=[libdf1.Tag("N7:7", access="readwrite"), "N7:8"])
        with pytest.raises(libdf1.Df1ValueError) as ei:
            poller.write("N7:7", 70000)
        assert ei.value.name == "DF1_E_RANGE"
        with pytest.raises(libdf1.Df1ValueError) as ei:
            poller.write("N7:8", 1)          # read-only tag
        assert ei.value.name == "DF1_E_INVAL"
        with pytest.raises(libdf1.Df1ValueError):
            poller.write("no such tag", 1)


def test_map_file(tmp_path, sim):
    m = tmp_path / "tags.csv"
    m.write_text("Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms\n"
                 "Speed,Read,INT,1,SLC,N7:2,1,0\n"
                 "Temps,Read,FLOAT,1,SLC,F8:0,3,0\n"
                 "Broken,Read,INT,1,SLC,N7:x,1,0\n")
    with libdf1.open(sim.target) as plc:
        poller = plc.poller(map=str(m))
        assert poller.tags == ["Speed", "Temps"]
        assert [i.catalog_id for i in poller.issues] == [2503]
        got = {}
        for ch in poller.changes(timeout=20):
            got[ch.tag] = ch.value
            if len(got) == 2:
                break
        assert got == {"Speed": 2, "Temps": [0.5, 1.5, 2.5]}
        with pytest.raises(libdf1.ConfigError) as ei:
            plc.poller(map=str(m), strict=True)
        assert ei.value.catalog_id == 2503


def test_type_column(tmp_path, sim):
    # libdf1(7) "Mapping file": REAL on a word is a float, DINT an int, an empty
    # Type the address's own; FLOAT on a bit, INT on a whole timer and no Type at
    # all are bad rows with their item numbers, the same as df1gw and df1mon say
    m = tmp_path / "typed.csv"
    m.write_text("Tag,Command,Type,Station,PLC_Type,Address\n"
                 "Real,Read,REAL,1,SLC,N7:3\n"
                 "Wide,Read,DINT,1,SLC,N7:4\n"
                 "Own,Read,,1,SLC,N7:3\n"
                 "B1,Read,FLOAT,1,SLC,B3:0/5\n"
                 "T1,Read,INT,1,SLC,T4:0\n"
                 "W,Read,WHATEVER,1,SLC,N7:0\n")
    with libdf1.open(sim.target) as plc:
        poller = plc.poller(map=str(m))
        assert poller.tags == ["Real", "Wide", "Own"]
        assert [(i.item, i.catalog_id) for i in poller.issues] == [(4, 0), (5, 0), (6, 0)]
        assert "Item: 4, Type FLOAT does not fit B3:0/5: a bit is BOOL" in poller.issues[0].text
        assert "a whole timer is TIMER" in poller.issues[1].text
        got = {}
        for ch in poller.changes(timeout=20):
            got[ch.tag] = ch.value
            if len(got) == 3:
                break
        assert got == {"Real": 3.0, "Wide": 4, "Own": 3}
        assert isinstance(got["Real"], float) and isinstance(got["Own"], int)
        with pytest.raises(libdf1.Df1ValueError):
            poller.add(libdf1.Tag("T4:0", name="acc", type="INT"))
        with pytest.raises(libdf1.Df1ValueError):
            poller.add(libdf1.Tag("N7:0", name="junk", type="WHATEVER"))
        assert poller.add(libdf1.Tag("F8:1", name="f", type="float")) >= 0
        # a write to a REAL tag on a word: a whole number goes through, 2.5 does not fit
        poller.add(libdf1.Tag("N7:8", name="w", type="REAL", access="readwrite"))
        done = poller.write("w", 12.0)
        while not done.done():
            poller.poll(0.2)
        assert done.result(timeout=0) is None and plc.read("N7:8") == 12
        with pytest.raises(libdf1.Df1ValueError):
            poller.write("w", 2.5)


def test_poll_in_a_thread_write_and_read_from_another(sim):
    # the usual shape: a thread runs the engine; the main thread writes through the
    # queue (waiting on the Future) and reads directly, taking turns on the handle
    with libdf1.open(sim.target) as plc:
        poller = plc.poller(tags=[libdf1.Tag("N7:9", access="readwrite", scan_ms=0)])
        stop = threading.Event()
        seen = []

        def run():
            while not stop.is_set():
                for ch in poller.changes(timeout=0.2):
                    seen.append(ch)

        t = threading.Thread(target=run)
        t.start()
        try:
            assert poller.write("N7:9", 99).result(timeout=20) is None
            assert plc.read("N7:9") == 99
            assert poller.write("N7:9", [-9]).result(timeout=20) is None
            assert plc.read("N7:9") == -9
        finally:
            stop.set()
            t.join(30)
        assert not t.is_alive()
    assert len(sim.wait_log(2, "addr=N7:9", "cmd=0F/AA")) == 2
    assert any(ch.value == 99 for ch in seen) or any(ch.value == -9 for ch in seen)
