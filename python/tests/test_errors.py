# SPDX-License-Identifier: MPL-2.0
"""Errors from a real line map to the right exception and catalog ID (doc/REQUIREMENTS.md 004):
no ACK after the ENQ retries 2520, no ACK in half duplex 2519 then the inactive
station 2509, no reply in time 2508, a PLC's error status with its EXT STS, bad
checks counted, bad values refused before anything is sent."""
import pytest

import libdf1


def test_no_ack_full_duplex_is_2520_enq_limit(sim):
    with libdf1.open(sim.target, timeout_ms=100, enq_retries=1) as plc:
        sim.silence()
        with pytest.raises(libdf1.CommunicationError) as ei:
            plc.read("N7:0")
    e = ei.value
    assert isinstance(e, TimeoutError)
    assert (e.catalog_id, e.mnemonic, e.name) == (2520, "NTC_ENQ_LIMIT_EXCEEDED", "DF1_E_ENQ_LIMIT")
    assert (e.station, e.address) == (1, "N7:0")
    assert str(e).startswith("N7:0: station 1: [2520] NTC_ENQ_LIMIT_EXCEEDED: ")


def test_no_ack_half_duplex_then_inactive_station(sim_factory):
    s = sim_factory("--duplex", "half")
    with libdf1.open(s.target, duplex="half", timeout_ms=100, nak_retries=1, enq_retries=1) as plc:
        assert plc.station_active(1)
        s.silence()
        with pytest.raises(libdf1.CommunicationError) as ei:
            plc.read("N7:0")
        assert ei.value.catalog_id == 2519 and ei.value.mnemonic == "NTC_NAK_LIMIT_EXCEEDED"
        assert not plc.station_active(1)
        with pytest.raises(libdf1.CommunicationError) as ei:
            plc.read("N7:0")
        assert ei.value.catalog_id == 2509 and ei.value.mnemonic == "ERR_INACTIVE_STATION"
        s.restore()
        assert plc.read("N7:2") == 2            # answers the one poll: active again
        assert plc.station_active(1)


def test_no_reply_in_time_is_2508_command_timeout(sim_factory):
    s = sim_factory("--delay", "3000")
    with libdf1.open(s.target, timeout_ms=200, cmd_timeout_ms=500) as plc:
        with pytest.raises(libdf1.CommunicationError) as ei:
            plc.read("N7:0")
    e = ei.value
    assert (e.catalog_id, e.mnemonic, e.name) == (2508, "ERR_COMMAND_TIMEOUT", "DF1_E_TIMEOUT")
    assert isinstance(e, TimeoutError)


def test_plc_error_status_no_such_file(sim):
    with libdf1.open(sim.target) as plc:
        with pytest.raises(libdf1.PlcError) as ei:
            plc.read("N99:0")
    e = ei.value
    # STS F0h: the code is in EXT STS; 06h: no such file (df1sim(1), M p.8-4)
    assert (e.sts, e.ext_sts, e.name, e.station, e.address) == (0xF0, 0x06, "DF1_E_REMOTE", 1, "N99:0")
    assert "EXT STS 0x06" in e.message
    assert e.ext_sts_text == libdf1.ffi.string(libdf1.lib.df1_ext_sts_text(6)).decode()


def test_element_beyond_the_file(sim):
    with libdf1.open(sim.target) as plc:
        with pytest.raises(libdf1.PlcError) as ei:
            plc.read("N7:300")
    assert ei.value.ext_sts == 0x07


@pytest.mark.parametrize("check,counter", [("crc", "CNT_CRC_ERRORS"), ("bcc", "CNT_BCC_ERRORS")])
def test_corrupt_replies_are_nakd_counted_and_sent_again(sim_factory, check, counter):
    # doc/REQUIREMENTS.md 001: a bad check is NAKed and the packet discarded; the sender retransmits
    s = sim_factory("--check", check, "--corrupt", "50", "--seed", "7")
    with libdf1.open(s.target, check=check, timeout_ms=500) as plc:
        for i in range(20):
            assert plc.read("N7:%d" % i) == i
        c = plc.counters()
        assert c[counter] >= 1 and c["CNT_NAKS_SENT"] == c[counter]


def test_address_errors(sim):
    with libdf1.open(sim.target) as plc:
        plc.counters_reset()
        with pytest.raises(libdf1.AddressError) as ei:
            plc.read("N7:x")
        assert (ei.value.catalog_id, ei.value.address) == (2503, "N7:x")
        assert isinstance(ei.value, ValueError)
        with pytest.raises(libdf1.AddressError) as ei:
            plc.read("N7:1000")
        assert ei.value.catalog_id == 2504 and ei.value.mnemonic == "ERR_ADDRESS_RANGE"
        assert plc.counters()["CNT_CMD_MSGS_SENT"] == 0


@pytest.mark.parametrize("address,value,name", [
    ("N7:0", 40000, "DF1_E_RANGE"), ("N7:0", -32769, "DF1_E_RANGE"), ("N7:0", "12", "DF1_E_TYPE"),
    ("N7:0", 1.5, "DF1_E_TYPE"), ("L10:0", 2 ** 31, "DF1_E_RANGE"), ("F8:0", "x", "DF1_E_TYPE"),
    ("B3:0/1", 2, "DF1_E_TYPE"), ("ST9:0", "x" * 83, "DF1_E_RANGE"), ("T4:0", 5, "DF1_E_TYPE"),
    ("T4:0", libdf1.Counter(), "DF1_E_TYPE"), ("N7:0", [1, 2, 99999], "DF1_E_RANGE"),
])
def test_values_that_do_not_fit_are_refused_before_sending(sim, address, value, name):
    with libdf1.open(sim.target) as plc:
        plc.counters_reset()
        with pytest.raises(libdf1.Df1ValueError) as ei:
            plc.write(address, value)
        assert ei.value.name == name and ei.value.address == address
        assert isinstance(ei.value, ValueError)
        assert plc.counters()["CNT_CMD_MSGS_SENT"] == 0
        # nothing of a list was written
        assert plc.read("N7:0") == 0


def test_network_file(tmp_path, sim):
    good = tmp_path / "net.csv"
    good.write_text("Station,Mode,PLC_Type,Error_Code,Com_Port,Baud,Timeout\n"
                    "0,Peer,SLC,CRC,%s,19200,500\n" % sim.target)
    with libdf1.open(net=str(good)) as plc:
        assert plc.target == sim.target
        assert plc.read("N7:4") == 4
    bad = tmp_path / "bad.csv"
    bad.write_text("Station,PLC_Type,NAK_Retries\n300,S7,42\n")
    with pytest.raises(libdf1.ConfigError) as ei:
        libdf1.open(sim.target, net=str(bad))
    ids = sorted(i.catalog_id for i in ei.value.issues)
    # CRT_BAD_STATION_ID, CRT_BAD_PLC_TYPE, CRT_BAD_NAK_RETRIES
    assert ids == [2552, 2555, 2557]
    assert ei.value.catalog_id in ids and isinstance(ei.value, ValueError)


def test_closed_plc(sim):
    plc = libdf1.open(sim.target)
    plc.close()
    plc.close()
    with pytest.raises(libdf1.PortError) as ei:
        plc.read("N7:0")
    assert ei.value.name == "DF1_E_NOT_OPEN"


@pytest.mark.parametrize("address,count,limit", [
    ("N7:0", 10 ** 9, 1000), ("N7:990", 11, 10), ("B3:0/5", 10 ** 12, 15995), ("T4:0/DN", 4, 3),
    ("L10:2/1", 31936, 31935),
])
def test_a_count_beyond_the_address_is_refused_before_allocating(sim, address, count, limit):
    # 10**9 values would be a MemoryError if the buffer came first; the limit is
    # the address range of df1_addr_parse(3): elements 0..999, bits of a T/C/R word
    with libdf1.open(sim.target) as plc:
        plc.counters_reset()
        with pytest.raises(libdf1.Df1ValueError) as ei:
            plc.read(address, count)
        assert "at most %d" % limit in str(ei.value) and ei.value.address == address
        with pytest.raises(libdf1.Df1ValueError):
            plc.read_many([(address, count)])
        assert plc.counters()["CNT_CMD_MSGS_SENT"] == 0
