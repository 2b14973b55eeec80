# SPDX-License-Identifier: MPL-2.0
"""Exceptions carrying the C library's error (df1_last_error(3), df1_strerror(3)).

Families a script catches:

    Df1Error              every error of the library
      CommunicationError  also a TimeoutError: no (good) answer on the line
      PlcError            the PLC answered with an error status (STS, EXT STS)
      AddressError        also a ValueError: malformed (2503) or out-of-range (2504) address
      Df1ValueError       also a ValueError: a value that does not fit the file type
      ConfigError         also a ValueError: a network or mapping file with problems
      PortError           also an OSError: the port cannot be opened or used
"""
from typing import List, Optional

from ._ffi import ffi, lib, text

__all__ = ["Df1Error", "CommunicationError", "PlcError", "AddressError", "Df1ValueError",
           "ConfigError", "PortError", "ConfigIssue", "errname", "strerror"]


def strerror(code: int) -> str:
    """The library's text for a DF1_E_* code (df1_strerror(3))."""
    return text(lib.df1_strerror(code))


def errname(code: int) -> str:
    """The DF1_E_* name of a code (df1_errname(3)), e.g. "DF1_E_TIMEOUT"."""
    return text(lib.df1_errname(code))


class Df1Error(Exception):
    """An error of libdf1, with the detail the handle kept (df1_last_error(3)).

    code        the negative DF1_E_* value
    name        its name, "DF1_E_TIMEOUT"
    catalog_id  the message catalog ID that reports it (2508), or 0
    mnemonic    the catalog mnemonic ("ERR_COMMAND_TIMEOUT"), or None
    station     the destination station, or None
    sts         the PLC's STS byte (PlcError), else 0
    ext_sts     the PLC's EXT STS byte when STS is F0h, else None
    address     the address the error concerns ("N7:0"), or ""
    message     the C library's text
    sys_errno   errno behind DF1_E_SYS, else 0

    str() is the tools' report: "N7:0: station 1: [2508] ERR_COMMAND_TIMEOUT: command timed out".
    """

    def __init__(self, code: int, message: Optional[str] = None, *, station: Optional[int] = None,
                 sts: int = 0, ext_sts: Optional[int] = None, address: str = "", catalog_id: int = 0,
                 sys_errno: int = 0):
        self.code = code
        self.name = errname(code)
        self.message = message or strerror(code)
        self.station = station
        self.sts = sts
        self.ext_sts = ext_sts
        self.address = address or ""
        self.catalog_id = catalog_id or lib.df1_error_catalog_id(code)
        entry = lib.df1_catalog_by_id(self.catalog_id) if self.catalog_id else ffi.NULL
        self.mnemonic = text(entry.mnemonic) if entry != ffi.NULL else None
        self.sys_errno = sys_errno
        super().__init__(self._report())

    def _report(self) -> str:
        parts = []
        if self.address:
            parts.append(self.address)
        if self.station is not None:
            parts.append("station %d" % self.station)
        tag = "[%d] %s" % (self.catalog_id, self.mnemonic) if self.mnemonic else self.name
        msg = self.message
        if self.sys_errno:
            sys_text = os_strerror(self.sys_errno)
            if sys_text not in msg:
                msg += ": " + sys_text
        parts.append("%s: %s" % (tag, msg))
        return ": ".join(parts)

    def __str__(self) -> str:
        return self._report()

    def __reduce__(self):
        return (_rebuild, (type(self), self.code, self.message, self.station, self.sts, self.ext_sts,
                           self.address, self.catalog_id, self.sys_errno))


def _rebuild(cls, code, message, station, sts, ext_sts, address, catalog_id, sys_errno):
    return cls(code, message, station=station, sts=sts, ext_sts=ext_sts, address=address,
               catalog_id=catalog_id, sys_errno=sys_errno)


def os_strerror(n: int) -> str:
    import os
    return os.strerror(n)


class CommunicationError(Df1Error, TimeoutError):
    """No usable answer: timeout, NAK/ENQ retry limits, bad BCC/CRC, wrong or
    malformed replies, an inactive station, a closed connection."""


class PlcError(Df1Error):
    """The PLC replied with an error status: .sts and .ext_sts say what (df1_sts_text(3))."""

    @property
    def sts_text(self) -> str:
        return text(lib.df1_sts_text(self.sts))

    @property
    def ext_sts_text(self) -> Optional[str]:
        return None if self.ext_sts is None else text(lib.df1_ext_sts_text(self.ext_sts))


class AddressError(Df1Error, ValueError):
    """An address that does not parse (2503 ERR_ADDRESS_SYNTAX) or is out of range (2504)."""


class Df1ValueError(Df1Error, ValueError):
    """A value that does not fit the file type (DF1_E_TYPE, DF1_E_RANGE) or an invalid argument."""


class PortError(Df1Error, OSError):
    """The port: busy, no such device, permission denied, a system call failed, not open.
    .errno is the system's errno behind it (as .sys_errno), or None."""

    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self.errno = self.sys_errno or None
        self.strerror = self.message


class ConfigIssue:
    """One problem of a configuration file (struct df1_config_issue)."""

    __slots__ = ("catalog_id", "item", "line", "text")

    def __init__(self, catalog_id: int, item: int, line: int, text_: str):
        self.catalog_id = catalog_id
        self.item = item
        self.line = line
        self.text = text_

    @property
    def mnemonic(self) -> Optional[str]:
        e = lib.df1_catalog_by_id(self.catalog_id)
        return text(e.mnemonic) if e != ffi.NULL else None

    def __repr__(self) -> str:
        return "ConfigIssue(%d %s, item %d, line %d: %s)" % (self.catalog_id, self.mnemonic, self.item,
                                                            self.line, self.text)


class ConfigError(Df1Error, ValueError):
    """A network or mapping file with problems; .issues lists each (catalog IDs 2552-2559, 2501-2504)."""

    def __init__(self, code: int, message: Optional[str] = None, *, issues: Optional[List[ConfigIssue]] = None,
                 **kw):
        self.issues = list(issues or [])
        if not kw.get("catalog_id") and self.issues:
            kw["catalog_id"] = self.issues[0].catalog_id
        if message is None and self.issues:
            message = "; ".join("line %d: %s" % (i.line, i.text) for i in self.issues)
        super().__init__(code, message, **kw)


_COMMUNICATION = ("TIMEOUT", "NAK_LIMIT", "ENQ_LIMIT", "BCC", "CRC", "TOO_LONG", "TOO_SHORT", "SYMBOL",
                  "BAD_FUNCTION", "INACTIVE", "WRONG_MSG", "CLOSED", "NAK", "BAD_REPLY", "NO_ETX")
_FAMILIES = {}
for _n in _COMMUNICATION:
    _FAMILIES["DF1_E_" + _n] = CommunicationError
_FAMILIES.update({
    "DF1_E_REMOTE": PlcError,
    "DF1_E_ADDR_SYNTAX": AddressError,
    "DF1_E_ADDR_RANGE": AddressError,
    "DF1_E_TYPE": Df1ValueError,
    "DF1_E_RANGE": Df1ValueError,
    "DF1_E_INVAL": Df1ValueError,
    "DF1_E_CONFIG": ConfigError,
    "DF1_E_SYS": PortError,
    "DF1_E_BUSY": PortError,
    "DF1_E_NODEV": PortError,
    "DF1_E_PERM": PortError,
    "DF1_E_NOT_OPEN": PortError,
})


def error_class(code: int) -> type:
    """The exception class of a DF1_E_* code (Df1Error for codes of no family)."""
    return _FAMILIES.get(errname(code), Df1Error)


def make_error(code: int, message: Optional[str] = None, **kw) -> Df1Error:
    """An exception of the right family for code."""
    return error_class(code)(code, message, **kw)


def from_handle(h, code: int, address: str = "", station: Optional[int] = None) -> Df1Error:
    """The exception for a failed call on handle h, with the handle's detail when it is about code."""
    d = lib.df1_last_error(h) if h is not None else ffi.NULL
    if d != ffi.NULL and d.code == code:
        return make_error(code, text(d.message) or None,
                          station=d.station if d.station >= 0 else station,
                          sts=d.sts, ext_sts=d.ext_sts if d.has_ext_sts else None,
                          address=text(d.address) or address, catalog_id=d.catalog_id,
                          sys_errno=d.sys_errno)
    return make_error(code, station=station, address=address)
