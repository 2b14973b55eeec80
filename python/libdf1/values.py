# SPDX-License-Identifier: MPL-2.0
"""Values: struct df1_value <-> Python, and the timer, counter and control elements.

Integer words (N, B, S, I, O, A and T/C/R words) are signed 16-bit ints, L files
signed 32-bit ints, F files floats (the float32 the PLC holds), bits bools, ST
strings str (Latin-1, up to 82 characters), a whole T, C or R element a Timer,
Counter or Control whose named bits are the library's (df1_tcr_bit(3)).
"""
from dataclasses import dataclass
from typing import Any, Dict, Tuple

from ._ffi import ffi, lib
from .errors import AddressError, Df1ValueError, from_handle, strerror

__all__ = ["Timer", "Counter", "Control"]

_INT16 = (-32768, 32767)
_INT32 = (-2147483648, 2147483647)


def _bit(ft: int, name: str) -> int:
    b = lib.df1_tcr_bit(ft, name.encode())
    if b < 0:
        raise RuntimeError("libdf1 has no bit %s for file type %d" % (name, ft))
    return b


class _Element:
    """Common part of Timer, Counter and Control: the control word from and to the named bits."""

    _FT = 0
    _BITS: Tuple[str, ...] = ()
    _WORDS: Tuple[str, str] = ("pre", "acc")

    @property
    def ctl(self) -> int:
        """Word 0 as the PLC holds it: the named bits plus other_bits."""
        w = self.other_bits
        for name in self._BITS:
            b = _bit(self._FT, name.rstrip("_").upper())
            w &= ~(1 << b)
            if getattr(self, name):
                w |= 1 << b
        return w & 0xFFFF

    @classmethod
    def from_words(cls, ctl: int, w1: int, w2: int) -> "_Element":
        kw: Dict[str, Any] = {cls._WORDS[0]: w1, cls._WORDS[1]: w2}
        other = ctl
        for name in cls._BITS:
            b = _bit(cls._FT, name.rstrip("_").upper())
            kw[name] = bool(ctl >> b & 1)
            other &= ~(1 << b)
        kw["other_bits"] = other & 0xFFFF
        return cls(**kw)

    def words(self) -> Tuple[int, int, int]:
        return self.ctl, getattr(self, self._WORDS[0]), getattr(self, self._WORDS[1])


@dataclass
class Timer(_Element):
    """A timer element (T file): PRE, ACC and the bits EN, TT, DN."""
    pre: int = 0
    acc: int = 0
    en: bool = False
    tt: bool = False
    dn: bool = False
    other_bits: int = 0     # bits of the control word that have no name

    _FT = lib.DF1_FT_T
    _BITS = ("en", "tt", "dn")


@dataclass
class Counter(_Element):
    """A counter element (C file): PRE, ACC and the bits CU, CD, DN, OV, UN, UA."""
    pre: int = 0
    acc: int = 0
    cu: bool = False
    cd: bool = False
    dn: bool = False
    ov: bool = False
    un: bool = False
    ua: bool = False
    other_bits: int = 0

    _FT = lib.DF1_FT_C
    _BITS = ("cu", "cd", "dn", "ov", "un", "ua")


@dataclass
class Control(_Element):
    """A control element (R file): LEN, POS and the bits EN, EU, DN, EM, ER, UL, IN, FD."""
    len: int = 0
    pos: int = 0
    en: bool = False
    eu: bool = False
    dn: bool = False
    em: bool = False
    er: bool = False
    ul: bool = False
    in_: bool = False       # IN (a Python keyword)
    fd: bool = False
    other_bits: int = 0

    _FT = lib.DF1_FT_R
    _BITS = ("en", "eu", "dn", "em", "er", "ul", "in_", "fd")
    _WORDS = ("len", "pos")


_TCR = {lib.DF1_FT_T: Timer, lib.DF1_FT_C: Counter, lib.DF1_FT_R: Control}


class Addr:
    """A parsed address (struct df1_addr) with the value kind it reads as."""

    __slots__ = ("text", "c", "kind", "type", "plc")

    def __init__(self, text_: str, plc: int = lib.DF1_PLC_SLC):
        if not isinstance(text_, str):
            raise AddressError(lib.DF1_E_ADDR_SYNTAX, "an address is a str, not %s" % type(text_).__name__)
        self.text = text_
        self.plc = plc
        self.c = ffi.new("struct df1_addr *")
        # the PLC type's address text: a PLC-3's own (N3:173, B5:173/15, T4.ACC), else the SLC's
        rc = lib.df1_addr_parse_plc(plc, text_.encode("utf-8", "replace"), self.c)
        if rc < 0:
            raise from_handle(None, rc, address=text_)
        self.kind = lib.df1_addr_value_kind(self.c)
        self.type = self.c.type

    @property
    def is_bit(self) -> bool:
        return self.kind == lib.DF1_VAL_BIT


def to_python(v, ft: int) -> Any:
    """One struct df1_value as a Python value."""
    k = v.kind
    if k == lib.DF1_VAL_INT16:
        return int(v.v.i16)
    if k == lib.DF1_VAL_INT32:
        return int(v.v.i32)
    if k == lib.DF1_VAL_FLOAT:
        return float(v.v.f)
    if k == lib.DF1_VAL_BIT:
        return bool(v.v.bit)
    if k == lib.DF1_VAL_STRING:
        n = min(v.v.str.len, lib.DF1_STRING_MAX)
        return bytes(ffi.buffer(v.v.str.text, n)).split(b"\0", 1)[0].decode("latin-1")
    if k == lib.DF1_VAL_TCR:
        cls = _TCR.get(ft)
        t = v.v.tcr
        if cls is None:
            return (int(t.ctl), int(t.pre), int(t.acc))
        return cls.from_words(int(t.ctl), int(t.pre), int(t.acc))
    raise Df1ValueError(lib.DF1_E_TYPE, "value of unknown kind %d" % k)


def _range_error(a: Addr, value: Any, what: str) -> Df1ValueError:
    return Df1ValueError(lib.DF1_E_RANGE, "%s: %r does not fit %s" % (strerror(lib.DF1_E_RANGE), value, what),
                         address=a.text)


def _type_error(a: Addr, value: Any, what: str) -> Df1ValueError:
    return Df1ValueError(lib.DF1_E_TYPE, "%s: %r is not %s" % (strerror(lib.DF1_E_TYPE), value, what),
                         address=a.text)


def _int(a: Addr, value: Any, lo_hi: Tuple[int, int], what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        if isinstance(value, float) and value.is_integer():
            value = int(value)
        elif isinstance(value, bool):
            value = int(value)
        else:
            raise _type_error(a, value, "an integer")
    if not lo_hi[0] <= value <= lo_hi[1]:
        raise _range_error(a, value, "%s (%d..%d)" % (what, lo_hi[0], lo_hi[1]))
    return value


def from_python(a: Addr, value: Any, v) -> None:
    """Fill struct df1_value v for address a from a Python value; Df1ValueError if it does not fit."""
    k = a.kind
    v.kind = k
    if k == lib.DF1_VAL_INT16:
        v.v.i16 = _int(a, value, _INT16, "a 16-bit word")
    elif k == lib.DF1_VAL_INT32:
        v.v.i32 = _int(a, value, _INT32, "a 32-bit integer")
    elif k == lib.DF1_VAL_FLOAT:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise _type_error(a, value, "a number")
        f = float(value)
        if f == f and abs(f) > 3.4028234663852886e38 and f not in (float("inf"), float("-inf")):
            raise _range_error(a, value, "a 32-bit float")
        v.v.f = f
    elif k == lib.DF1_VAL_BIT:
        if isinstance(value, bool):
            v.v.bit = value
        elif isinstance(value, int) and value in (0, 1):
            v.v.bit = bool(value)
        else:
            raise _type_error(a, value, "a bit (True/False, 0/1)")
    elif k == lib.DF1_VAL_STRING:
        if isinstance(value, str):
            try:
                b = value.encode("latin-1")
            except UnicodeEncodeError:
                raise _type_error(a, value, "Latin-1 text") from None
        elif isinstance(value, (bytes, bytearray)):
            b = bytes(value)
        else:
            raise _type_error(a, value, "a string")
        if len(b) > lib.DF1_STRING_MAX:
            raise _range_error(a, value, "a string of at most %d characters" % lib.DF1_STRING_MAX)
        v.v.str.len = len(b)
        ffi.memmove(v.v.str.text, b, len(b))
        v.v.str.text[len(b)] = b"\0"
    elif k == lib.DF1_VAL_TCR:
        cls = _TCR.get(a.type)
        if isinstance(value, _Element):
            if cls is not None and not isinstance(value, cls):
                raise _type_error(a, value, "a %s" % cls.__name__)
            ctl, w1, w2 = value.words()
        elif isinstance(value, (tuple, list)) and len(value) == 3:
            ctl, w1, w2 = value
        else:
            raise _type_error(a, value, "a %s" % (cls.__name__ if cls else "(ctl, w1, w2) tuple"))
        v.v.tcr.ctl = _int(a, ctl, (0, 0xFFFF), "a control word")
        v.v.tcr.pre = _int(a, w1, _INT16, "a 16-bit word")
        v.v.tcr.acc = _int(a, w2, _INT16, "a 16-bit word")
    else:
        raise _type_error(a, value, "a value of a known kind")

