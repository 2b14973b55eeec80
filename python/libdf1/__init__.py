# SPDX-License-Identifier: MPL-2.0
"""libdf1: the Allen-Bradley DF1 protocol (PLC-5, SLC 500, MicroLogix) from Python.

A thin binding (cffi, ABI mode) over the C library libdf1.so.0:

    import libdf1
    with libdf1.open("/dev/ttyUSB0", baud=19200, check="crc", duplex="full", plc="slc") as plc:
        n = plc.read("N7:0")                  # int
        plc.write("N7:5", 1234)
        print(plc.read_many(["N7:0", "F8:3", "T4:0.ACC"]))

Every call that waits on the line releases the GIL (cffi does so for every
ABI-mode call): lines in several threads progress together. A Plc is used by
one thread at a time (libdf1(7)); its methods take turns on a lock, and the
poll engine's Poller.write() may be called from any thread.
"""
from ._ffi import ffi, lib
from .errors import (AddressError, CommunicationError, ConfigError, ConfigIssue, Df1Error, Df1ValueError,
                     PlcError, PortError, errname, strerror)
from .plc import DiagStatus, Plc, Station, open, option_names
from .poll import Change, Poller, Quality, Reason, Tag, TagState
from .values import Control, Counter, Timer

__all__ = ["open", "Plc", "Poller", "Tag", "Change", "TagState", "Quality", "Reason", "Timer", "Counter",
           "Control", "DiagStatus", "Station", "Df1Error", "CommunicationError", "PlcError", "AddressError",
           "Df1ValueError", "ConfigError", "ConfigIssue", "PortError", "strerror", "errname", "option_names",
           "library_version", "__version__"]

__version__ = "0.5.0"


def library_version() -> str:
    """The version of the C library loaded (df1_version(3)), e.g. "0.5.0"."""
    return ffi.string(lib.df1_version().string).decode()
