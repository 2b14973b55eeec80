# SPDX-License-Identifier: MPL-2.0
"""The binding's pure parts against the C library's own tables: error families,
names and catalog IDs, quality and reason names, T/C/R bits, open()'s options."""
import pytest

import libdf1
from libdf1 import ffi, lib
from libdf1.errors import make_error

CODES = ffi.typeof("enum df1_error").relements


def test_every_error_code_has_its_c_name_text_and_catalog_id():
    assert len(CODES) == lib.DF1_ERROR_COUNT
    for name, code in CODES.items():
        e = make_error(code)
        assert isinstance(e, libdf1.Df1Error)
        assert e.code == code and e.name == name
        assert e.message == ffi.string(lib.df1_strerror(code)).decode()
        assert e.catalog_id == lib.df1_error_catalog_id(code)
        if e.catalog_id:
            assert e.mnemonic == ffi.string(lib.df1_catalog_by_id(e.catalog_id).mnemonic).decode()
            assert str(e) == "[%d] %s: %s" % (e.catalog_id, e.mnemonic, e.message)
        else:
            assert e.mnemonic is None
            assert str(e) == "%s: %s" % (name, e.message)


@pytest.mark.parametrize("name,family,builtin", [
    ("DF1_E_TIMEOUT", libdf1.CommunicationError, TimeoutError),
    ("DF1_E_NAK_LIMIT", libdf1.CommunicationError, TimeoutError),
    ("DF1_E_ENQ_LIMIT", libdf1.CommunicationError, TimeoutError),
    ("DF1_E_CRC", libdf1.CommunicationError, TimeoutError),
    ("DF1_E_BCC", libdf1.CommunicationError, TimeoutError),
    ("DF1_E_INACTIVE", libdf1.CommunicationError, TimeoutError),
    ("DF1_E_REMOTE", libdf1.PlcError, libdf1.Df1Error),
    ("DF1_E_ADDR_SYNTAX", libdf1.AddressError, ValueError),
    ("DF1_E_ADDR_RANGE", libdf1.AddressError, ValueError),
    ("DF1_E_TYPE", libdf1.Df1ValueError, ValueError),
    ("DF1_E_RANGE", libdf1.Df1ValueError, ValueError),
    ("DF1_E_CONFIG", libdf1.ConfigError, ValueError),
    ("DF1_E_NODEV", libdf1.PortError, OSError),
    ("DF1_E_BUSY", libdf1.PortError, OSError),
])
def test_error_families(name, family, builtin):
    e = make_error(CODES[name])
    assert type(e) is family and isinstance(e, builtin)


def test_timeout_is_2508():
    e = make_error(lib.DF1_E_TIMEOUT, station=1, address="N7:0")
    assert (e.catalog_id, e.mnemonic, e.name) == (2508, "ERR_COMMAND_TIMEOUT", "DF1_E_TIMEOUT")
    assert str(e) == "N7:0: station 1: [2508] ERR_COMMAND_TIMEOUT: command timed out"


def test_errors_pickle():
    import pickle
    e = make_error(lib.DF1_E_REMOTE, "PLC error", station=2, sts=0xF0, ext_sts=6, address="N9:0")
    f = pickle.loads(pickle.dumps(e))
    assert type(f) is libdf1.PlcError and (f.sts, f.ext_sts, f.station, f.address) == (0xF0, 6, 2, "N9:0")


def test_quality_and_reason_are_the_c_names():
    q = ffi.typeof("enum df1_quality").relements
    assert {ffi.string(lib.df1_quality_name(v)).decode() for v in q.values()} == {m.value for m in libdf1.Quality}
    r = ffi.typeof("enum df1_quality_reason").relements
    assert {ffi.string(lib.df1_reason_name(v)).decode() for v in r.values()} == {m.value for m in libdf1.Reason}
    assert libdf1.Quality.GOOD == "GOOD"


@pytest.mark.parametrize("cls,ft,names", [
    (libdf1.Timer, lib.DF1_FT_T, ["EN", "TT", "DN"]),
    (libdf1.Counter, lib.DF1_FT_C, ["CU", "CD", "DN", "OV", "UN", "UA"]),
    (libdf1.Control, lib.DF1_FT_R, ["EN", "EU", "DN", "EM", "ER", "UL", "IN", "FD"]),
])
def test_tcr_bits_are_the_librarys(cls, ft, names):
    for name in names:
        bit = lib.df1_tcr_bit(ft, name.encode())
        assert bit >= 0
        attr = name.lower() + ("_" if name == "IN" else "")
        e = cls.from_words(1 << bit, 0, 0)
        assert getattr(e, attr) is True and e.other_bits == 0 and e.ctl == 1 << bit
    # a bit without a name is kept
    e = cls.from_words(0x0001, 7, -8)
    assert e.other_bits == 1 and e.ctl == 1 and e.words() == (1, 7, -8)


def test_the_manuals_timer_bits():
    # SLC 500 timer control word: EN bit 15, TT 14, DN 13 (1747-RM001)
    t = libdf1.Timer.from_words(0xA000, 500, 12)
    assert (t.en, t.tt, t.dn, t.pre, t.acc) == (True, False, True, 500, 12)


def test_open_takes_every_option_of_the_library():
    names = ffi.typeof("enum df1_option").relements
    assert sorted(n[len("DF1_OPT_"):].lower() for n in names) == libdf1.option_names()
    with pytest.raises(TypeError):
        libdf1.open("/dev/null", no_such_option=1)


def test_open_rejects_bad_choices():
    with pytest.raises(libdf1.Df1ValueError):
        libdf1.open("/dev/null", duplex="sideways")
    with pytest.raises(libdf1.Df1ValueError):
        libdf1.open("/dev/null", plc="s7")


def test_open_out_of_range_setting_is_the_librarys_error():
    # the seed's range for NAK_Retries is 0..10: critical error 2557
    with pytest.raises(libdf1.ConfigError) as ei:
        libdf1.open("/dev/null", nak_retries=11)
    assert (ei.value.catalog_id, ei.value.mnemonic) == (2557, "CRT_BAD_NAK_RETRIES")
    assert isinstance(ei.value, ValueError)


def test_open_missing_device_is_a_port_error(tmp_path):
    with pytest.raises(libdf1.PortError) as ei:
        libdf1.open(str(tmp_path / "no-such-tty"))
    assert ei.value.name == "DF1_E_NODEV"


def test_bad_address_is_2503_before_anything_is_sent():
    with pytest.raises(libdf1.AddressError) as ei:
        from libdf1.values import Addr
        Addr("N7:x")
    assert ei.value.catalog_id == 2503 and ei.value.mnemonic == "ERR_ADDRESS_SYNTAX"


def test_library_version():
    v = lib.df1_version()
    assert libdf1.library_version() == "%d.%d.%d" % (v.major, v.minor, v.micro)


def test_package_version_is_the_headers():
    """The binding is released with the library: its version is df1.h's."""
    import pathlib
    import re
    root = pathlib.Path(__file__).resolve().parents[2]
    header = (root / "include" / "df1.h").read_text()
    want = re.search(r'#define DF1_VERSION_STRING "([^"]+)"', header).group(1)
    pyproject = (root / "python" / "pyproject.toml").read_text()
    assert libdf1.__version__ == want
    assert re.search(r'^version = "([^"]+)"', pyproject, re.M).group(1) == want
