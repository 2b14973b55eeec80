# SPDX-License-Identifier: MPL-2.0
"""The handle: open, read, write, diagnostics (df1_new(3) ... df1_free(3)).

Thread rule (libdf1(7)): a handle is used by one thread at a time. A Plc keeps
that rule for you: every call on its handle holds the Plc's lock, so calls
from several threads take turns instead of overlapping. The poll engine's
Poller.write() is the one call that does not wait for the lock (df1_tag_write
is safe from any thread). Each Plc has its own lock, and cffi releases the GIL
in every call: two Plc objects on two lines, one thread each, work in parallel.
"""
import functools
import threading
from dataclasses import dataclass
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Tuple, Union

from ._ffi import ffi, lib, text
from .errors import ConfigError, ConfigIssue, Df1Error, Df1ValueError, from_handle, make_error
from .values import Addr, _Element, from_python, to_python

__all__ = ["Plc", "open", "DiagStatus", "Station", "option_names"]

_DUPLEX = {"full": lib.DF1_FULL_DUPLEX, "half": lib.DF1_HALF_DUPLEX_MASTER,
           "half-master": lib.DF1_HALF_DUPLEX_MASTER, "master": lib.DF1_HALF_DUPLEX_MASTER,
           "half-slave": lib.DF1_HALF_DUPLEX_SLAVE, "slave": lib.DF1_HALF_DUPLEX_SLAVE,
           "radio": lib.DF1_RADIO_MODEM}
_CHECK = {"crc": lib.DF1_CHECK_CRC, "bcc": lib.DF1_CHECK_BCC}
_PLC = {"slc": lib.DF1_PLC_SLC, "slc500": lib.DF1_PLC_SLC, "slc5/03": lib.DF1_PLC_SLC,
        "slc5/04": lib.DF1_PLC_SLC, "slc5/05": lib.DF1_PLC_SLC,
        "micrologix": lib.DF1_PLC_MICROLOGIX, "ml": lib.DF1_PLC_MICROLOGIX,
        "slc502": lib.DF1_PLC_SLC502, "slc5/01": lib.DF1_PLC_SLC502, "slc5/02": lib.DF1_PLC_SLC502,
        "plc5": lib.DF1_PLC_PLC5, "plc2": lib.DF1_PLC_PLC2, "plc3": lib.DF1_PLC_PLC3}
_PARITY = {"none": b"N", "n": b"N", "even": b"E", "e": b"E", "odd": b"O", "o": b"O"}


def _options() -> Dict[str, int]:
    """The df1_set_option keywords: DF1_OPT_RS485 -> rs485, from the enum in the cdefs."""
    names = ffi.typeof("enum df1_option").relements
    return {n[len("DF1_OPT_"):].lower(): v for n, v in names.items()}


_OPTIONS = _options()


def option_names() -> List[str]:
    """The keywords open() takes for df1_set_option(3), one per DF1_OPT_* of the library."""
    return sorted(_OPTIONS)


def _choice(kind: str, table: Dict[str, Any], value: Any) -> Any:
    key = str(value).strip().lower().replace(" ", "").replace("_", "").replace("-", "") \
        if kind == "plc" else str(value).strip().lower()
    if key in table:
        return table[key]
    raise Df1ValueError(lib.DF1_E_INVAL, "%s %r: one of %s" % (kind, value, ", ".join(sorted(table))))


@functools.lru_cache(maxsize=4096)
def _addr(address: str, plc: int = lib.DF1_PLC_SLC) -> Addr:
    return Addr(address, plc)


@dataclass
class DiagStatus:
    """The diagnostic status of a station (df1_diag_status(3), 06/03)."""
    type_code: int          # processor type code (0x5B SLC 5/04, 0x9F ML1400, 0x15 PLC-5/40)
    name: str               # "SLC 5/04", "MicroLogix 1400", "PLC-5/40", or "unknown (0xNN)"
    series: str             # "A" ..
    revision: int           # FRN / revision
    mode: int               # mode code as the controller reports it
    mode_text: str          # "run", "program", "test", ...
    bulletin: str           # ASCII bulletin name when present
    raw: bytes              # the reply data

    @classmethod
    def _from_c(cls, d) -> "DiagStatus":
        return cls(type_code=d.type_code, name=text(d.name), series=d.series.decode("latin-1").strip("\0"),
                   revision=d.revision, mode=d.mode, mode_text=text(d.mode_text),
                   bulletin=text(d.bulletin), raw=bytes(ffi.buffer(d.raw, d.raw_len)))


@dataclass
class Station:
    """One station probed by discovery (struct df1_discover_result)."""
    station: int
    answered: bool               # it replied (a reply with an error STS counts)
    identified: bool             # status holds its diagnostic status
    error: Optional[Df1Error]    # why it was not identified, None when it was
    rtt_us: int                  # round trip of the probe it answered, 0 if none
    status: Optional[DiagStatus]


AddressItem = Union[str, Tuple[str, int]]


class Plc:
    """One DF1 line (a serial port or a TCP connection) and its default station.

    Made by libdf1.open(); use it in a with-block or call close().
    """

    def __init__(self) -> None:
        self._lock = threading.RLock()
        out = ffi.new("df1_t **")
        rc = lib.df1_new(out)
        if rc < 0:
            raise make_error(rc)
        self._h = ffi.gc(out[0], lib.df1_free)
        self._keep: List[Any] = []      # callbacks the C side holds
        self.station = 1
        self.plc_type = lib.DF1_PLC_SLC
        self.target: Optional[str] = None
        self.last_reads = 0             # read calls of the last read_many()
        self._poller = None

    def __repr__(self) -> str:
        state = "open" if self._h is not None and lib.df1_is_open(self._h) else "closed"
        return "<libdf1.Plc %s %s station %d>" % (self.target, state, self.station)

    # ---- lifecycle ----
    def _check(self, rc: int, address: str = "", station: Optional[int] = None) -> int:
        if rc < 0:
            raise from_handle(self._h, rc, address=address, station=station)
        return rc

    def _open(self, target: str) -> None:
        with self._lock:
            self._check(lib.df1_open(self._h, target.encode()))
        self.target = target

    def close(self) -> None:
        """Close the line (df1_close(3)) and free the handle; the Plc cannot be used again."""
        with self._lock:
            if self._h is not None:
                h, self._h = self._h, None
                # df1_free ends queued writes through their callbacks: still alive here
                ffi.release(h)
                if self._poller is not None:
                    self._poller._detach()

    def __enter__(self) -> "Plc":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    @property
    def is_open(self) -> bool:
        """True while the line is open (df1_is_open(3))."""
        with self._lock:
            return self._h is not None and bool(lib.df1_is_open(self._h))

    @property
    def handle(self):
        """The df1_t * (a cffi pointer) for calls this module does not wrap; obey the thread rule."""
        if self._h is None:
            raise make_error(lib.DF1_E_NOT_OPEN, "the Plc is closed")
        return self._h

    def _st(self, station: Optional[int]) -> int:
        return self.station if station is None else station

    # ---- reading and writing ----
    def read(self, address: str, count: Optional[int] = None, *, station: Optional[int] = None) -> Any:
        """Read address ("N7:0", "F8:3", "B3:0/5", "T4:0", "T4:0.ACC", "ST9:0", "L10:0").

        Without count: one value (int, float, bool, str, or a Timer, Counter or
        Control); with count: a list of count values (consecutive elements, or
        consecutive bits for a bit address). Larger requests than one packet
        are split by the library (df1_read(3)). A count beyond what the address
        can hold (elements up to 999, the bits of a T/C/R word) is a
        Df1ValueError naming the limit, raised before anything is allocated.
        """
        a = _addr(address, self.plc_type)
        n = 1 if count is None else count
        if not isinstance(n, int) or n < 1:
            raise Df1ValueError(lib.DF1_E_INVAL, "count %r: 1 or more" % (count,), address=address)
        _check_count(a, n, address)
        st = self._st(station)
        buf = ffi.new("struct df1_value[]", n)
        with self._lock:
            rc = lib.df1_read_addr(self.handle, st, a.c, buf, n)
            if rc < 0:
                raise from_handle(self._h, rc, address=address, station=st)
        vals = [to_python(buf[i], a.type) for i in range(rc)]
        return vals[0] if count is None else vals

    def write(self, address: str, value: Any, *, station: Optional[int] = None) -> int:
        """Write value (or a list of values to consecutive elements) at address.

        A bit address writes that one bit (True/False) and leaves the others of
        its word alone; a T/C/R element takes a Timer, Counter or Control; ST
        a str of up to 82 characters. Every value is checked against the file
        type before anything is sent (Df1ValueError). Returns the values written.
        """
        a = _addr(address, self.plc_type)
        values = _as_list(a, value)
        if not values:
            raise Df1ValueError(lib.DF1_E_INVAL, "no values to write", address=address)
        buf = ffi.new("struct df1_value[]", len(values))
        for i, v in enumerate(values):
            from_python(a, v, buf[i])
        st = self._st(station)
        with self._lock:
            rc = lib.df1_write_addr(self.handle, st, a.c, buf, len(values))
            if rc < 0:
                raise from_handle(self._h, rc, address=address, station=st)
        return rc

    def read_many(self, addresses: Iterable[AddressItem], *, station: Optional[int] = None,
                  errors: str = "raise") -> Dict[AddressItem, Any]:
        """Read many addresses of one station in the fewest transactions (df1_read_multi(3)).

        Each item is an address ("N7:0": one value), "ADDRESS,COUNT" or
        (address, count) (a list of count values). Returns a dict from each item
        to its value(s). A block the PLC refuses is read again address by
        address, so one bad address does not hide the others: with
        errors="raise" (default) the first failure is raised (its .results holds
        what was read); with errors="return" a failed item maps to its Df1Error.
        """
        items = list(addresses)
        if not items:
            raise Df1ValueError(lib.DF1_E_INVAL, "no addresses to read")
        if errors not in ("raise", "return"):
            raise ValueError("errors: 'raise' or 'return'")
        n = len(items)
        reqs = ffi.new("struct df1_read_req[]", n)
        keep = []
        plan = []
        for i, item in enumerate(items):
            addr, count, many = _split_item(item)
            if isinstance(item, list):
                item = tuple(item)          # a dict key
            a = _addr(addr, self.plc_type)
            _check_count(a, count, addr)
            vals = ffi.new("struct df1_value[]", count)
            keep.append(vals)
            # by text, so that the library's error detail names the address as written
            t = ffi.new("char[]", addr.encode())
            keep.append(t)
            reqs[i].text = t
            reqs[i].count = count
            reqs[i].values = vals
            plan.append((item, addr, a, many, vals))
        st = self._st(station)
        reads = ffi.new("unsigned *")
        with self._lock:
            rc = lib.df1_read_multi(self.handle, st, reqs, n, 0, reads)
            first = from_handle(self._h, rc, station=st) if rc < 0 else None
            detail = lib.df1_last_error(self._h)
            detail_addr = text(detail.address) if rc < 0 else None
        self.last_reads = reads[0]
        out: Dict[AddressItem, Any] = {}
        failed: Dict[AddressItem, Df1Error] = {}
        for i, (item, addr, a, many, vals) in enumerate(plan):
            r = reqs[i].result
            if r > 0:
                got = [to_python(vals[j], a.type) for j in range(r)]
                out[item] = got if many else got[0]
            elif r < 0 and first is not None and first.code == r and detail_addr == addr:
                failed[item] = first        # the one failure the handle describes in full
            else:
                failed[item] = make_error(r if r < 0 else lib.DF1_E_INTR,
                                          None if r < 0 else "not read: the call ended first",
                                          address=addr, station=st)
        if first is not None and errors == "raise":
            first.results = out
            first.failed = failed
            raise first
        out.update(failed)
        return out

    def read_raw(self, address: str, nbytes: int, *, station: Optional[int] = None) -> bytes:
        """Element bytes as they are on the wire, little-endian words (df1_read_raw(3))."""
        buf = ffi.new("uint8_t[]", nbytes)
        st = self._st(station)
        with self._lock:
            rc = self._check(lib.df1_read_raw(self.handle, st, address.encode(), buf, nbytes), address, st)
        return bytes(ffi.buffer(buf, rc))

    def write_raw(self, address: str, data: bytes, *, station: Optional[int] = None) -> int:
        """Write raw element bytes (df1_write_raw(3)); returns the bytes written."""
        st = self._st(station)
        with self._lock:
            return self._check(lib.df1_write_raw(self.handle, st, address.encode(), data, len(data)), address, st)

    def command(self, cmd: int, body: bytes = b"", *, station: Optional[int] = None, reply_cap: int = 512) -> bytes:
        """Any PCCC command: FNC and data out, the reply's data back (df1_command(3))."""
        reply = ffi.new("uint8_t[]", reply_cap)
        st = self._st(station)
        with self._lock:
            rc = self._check(lib.df1_command(self.handle, st, cmd, body, len(body), reply, reply_cap), "", st)
        return bytes(ffi.buffer(reply, rc))

    # ---- diagnostics ----
    def diag_status(self, *, station: Optional[int] = None) -> DiagStatus:
        """The station's diagnostic status, 06/03: processor type, series, revision, mode."""
        d = ffi.new("struct df1_diag_status *")
        st = self._st(station)
        with self._lock:
            self._check(lib.df1_diag_status(self.handle, st, d), "", st)
        return DiagStatus._from_c(d)

    def echo(self, data: bytes = b"libdf1", *, station: Optional[int] = None) -> int:
        """06/00 echo: send data and check that it comes back; returns the length echoed."""
        st = self._st(station)
        with self._lock:
            return self._check(lib.df1_echo(self.handle, st, data, len(data)), "", st)

    def link_test(self, *, station: Optional[int] = None) -> None:
        """DLE ENQ (full duplex) or a poll (half duplex); raises unless the link answered."""
        st = self._st(station)
        with self._lock:
            self._check(lib.df1_link_test(self.handle, st), "", st)

    def change_mode(self, mode: int, *, station: Optional[int] = None) -> None:
        """0F/80 change mode (SLC 5/03+, MicroLogix): 1 program, 6 run."""
        st = self._st(station)
        with self._lock:
            self._check(lib.df1_change_mode(self.handle, st, mode), "", st)

    def counters(self) -> Dict[str, int]:
        """The link counters of doc/REQUIREMENTS.md 004 by mnemonic (2525-2551, 2560, 2561), df1_counter(3)."""
        out: Dict[str, int] = {}
        v = ffi.new("uint64_t *")
        with self._lock:
            h = self.handle
            i = 0
            while True:
                e = lib.df1_catalog_at(i)
                if e == ffi.NULL:
                    break
                i += 1
                if e.severity == lib.DF1_SEV_COUNTER and lib.df1_counter(h, e.id, v) >= 0:
                    out[text(e.mnemonic)] = int(v[0])
        return out

    def counters_reset(self) -> None:
        """Set every counter to 0 (df1_counters_reset(3))."""
        with self._lock:
            lib.df1_counters_reset(self.handle)

    def station_active(self, station: Optional[int] = None) -> bool:
        """Whether a station is on the active station list (df1_station_active(3))."""
        st = self._st(station)
        with self._lock:
            return bool(self._check(lib.df1_station_active(self.handle, st), "", st))

    def set_station_active(self, station: int, active: bool) -> None:
        """Put a station on the active station list or take it off."""
        with self._lock:
            self._check(lib.df1_station_set_active(self.handle, station, active), "", station)

    def discover(self, lo: int = 0, hi: int = 254,
                 progress: Optional[Callable[[Station], Optional[bool]]] = None) -> List[Station]:
        """Probe stations lo..hi in ascending order (df1_discover(3)); one Station per station probed.

        Half duplex: a poll, then the diagnostic status of those that answer;
        full duplex: one DLE ENQ for the line, then the diagnostic status
        addressed to each station. progress (optional) is called with each
        Station as it is probed; returning True stops the scan.
        """
        found: List[Station] = []
        failure: List[BaseException] = []

        def cb(user, r):
            try:
                s = Station(station=r.station, answered=bool(r.answered), identified=bool(r.identified),
                            error=None if r.error == 0 else from_handle(self._h, r.error, station=r.station),
                            rtt_us=int(r.rtt_us),
                            status=DiagStatus._from_c(r.status) if r.identified else None)
                found.append(s)
                if progress is not None and progress(s):
                    return 1
                return 0
            except BaseException as e:      # never let an exception cross the C frame
                failure.append(e)
                return 1

        fn = ffi.callback("df1_discover_fn", cb)
        with self._lock:
            rc = lib.df1_discover(self.handle, lo, hi, fn, ffi.NULL)
            if failure:
                raise failure[0]
            self._check(rc)
        return found

    def stations(self, lo: int = 0, hi: int = 254) -> List[Station]:
        """The stations of lo..hi that answer (discover() without the silent ones)."""
        return [s for s in self.discover(lo, hi) if s.answered]

    @property
    def last_error(self) -> Optional[Df1Error]:
        """The handle's last error (df1_last_error(3)) as an exception object, or None."""
        with self._lock:
            d = lib.df1_last_error(self.handle)
            return None if d.code == 0 else from_handle(self._h, d.code)

    # ---- the poll engine ----
    def poller(self, tags: Optional[Sequence[Any]] = None, map: Optional[str] = None, *, strict: bool = False,
               watchdog_ms: Optional[int] = None, absolute_retries: int = 0,
               station_range: Optional[Tuple[int, int]] = None):
        """The poll engine on this line (df1_poll(3)): tags given here and/or a mapping CSV.

        tags: addresses ("N7:0", "N7:0,10") or libdf1.Tag objects; map: a
        mapping CSV (df1_tag_load_map(3)), whose rows have their own station
        and PLC type. The handle has one engine: a second call adds tags to it.
        """
        from .poll import Poller
        with self._lock:
            if self._poller is None:
                self._poller = Poller(self)
            p = self._poller
            if watchdog_ms is not None:
                self._check(lib.df1_poll_set_watchdog(self.handle, watchdog_ms, absolute_retries))
            if station_range is not None:
                self._check(lib.df1_poll_set_station_range(self.handle, station_range[0], station_range[1]))
            for t in tags or ():
                p.add(t)
            if map is not None:
                p.load_map(map, strict=strict)
        return p


# Elements 0..999 in a file, I/O words 0..255 in a slot, bits 0..15 of a T/C/R
# word (df1_addr_parse(3)): the most a read from an address can return.
_ELEMENTS = 1000
_SUBS = 256
_PLC3_WORDS = 10000


def count_limit(a: Addr) -> int:
    """How many values a read from a (count elements, or bits for a bit address) can return."""
    c = a.c
    if a.plc == lib.DF1_PLC_PLC3:
        # words 0-9999 in a PLC-3 file (doc/PROTOCOL.md 4.2a): the library checks
        # the exact range; this bound only keeps the buffer from growing first
        return _PLC3_WORDS
    tcr = a.type in (lib.DF1_FT_T, lib.DF1_FT_C, lib.DF1_FT_R)
    if c.bit != lib.DF1_ADDR_NONE:
        if tcr:
            return 16 - c.bit
        wbits = 32 if a.type == lib.DF1_FT_L else 16
        words = _SUBS - c.sub if c.sub != lib.DF1_ADDR_NONE else _ELEMENTS - c.element
        return words * wbits - c.bit
    if c.sub != lib.DF1_ADDR_NONE and not tcr:
        return _SUBS - c.sub
    return _ELEMENTS - c.element


def _check_count(a: Addr, n: int, address: str) -> None:
    # before the buffer is allocated: a count of 10**9 is an error, not a MemoryError
    limit = count_limit(a)
    if n > limit:
        raise Df1ValueError(lib.DF1_E_INVAL, "count %d: at most %d %s from %s" %
                            (n, limit, "bits" if a.is_bit else "elements", address), address=address)


def _split_item(item: AddressItem) -> Tuple[str, int, bool]:
    if isinstance(item, (tuple, list)):
        addr, count = item
        return addr, int(count), True
    if isinstance(item, str) and "," in item:
        addr, _, count = item.rpartition(",")
        try:
            return addr.strip(), int(count), True
        except ValueError:
            raise Df1ValueError(lib.DF1_E_INVAL, "count %r is not a number" % count, address=item) from None
    return item, 1, False


def _as_list(a: Addr, value: Any) -> List[Any]:
    if isinstance(value, (str, bytes, bytearray, _Element)):
        return [value]
    if a.kind == lib.DF1_VAL_TCR and isinstance(value, tuple) and len(value) == 3 \
            and all(isinstance(x, int) for x in value):
        return [value]
    if isinstance(value, (list, tuple)):
        return list(value)
    return [value]


def open(target: Optional[str] = None, *, net: Optional[str] = None, station: int = 1,
         src: Optional[int] = None, baud: Optional[int] = None, data_bits: Optional[int] = None,
         parity: Optional[str] = None, stop_bits: Optional[int] = None, handshake: Optional[bool] = None,
         duplex: Optional[str] = None, check: Optional[str] = None, plc: Optional[str] = None,
         timeout_ms: Optional[int] = None, cmd_timeout_ms: Optional[int] = None,
         nak_retries: Optional[int] = None, enq_retries: Optional[int] = None,
         tx_delay_ms: Optional[int] = None, line_baud: Optional[int] = None,
         log: Optional[Callable[[int, int, str], None]] = None,
         trace: Optional[Callable[[str, bytes, int], None]] = None,
         cancel_fd: Optional[int] = None, options: Optional[Dict[str, int]] = None, **opts: Any) -> Plc:
    """Open a DF1 line: a serial device ("/dev/ttyUSB0") or "tcp://host:port" (any
    target df1_open(3) takes, so eip:// too once the library has it).

    Defaults are the library's (df1_new(3)): 19200 8N1, full duplex, CRC,
    SLC, own station 0. net="network.csv" takes the settings (and, without a
    target, the port) from a network file (df1_net_config_load(3)); the
    keywords given here override it. station is the destination every call
    uses unless it names another; src the station of our own commands
    (df1_set_station). Every df1_set_* setting is a keyword: baud, data_bits,
    parity ("none", "even", "odd"), stop_bits, handshake, duplex ("full",
    "half"; "half-slave"; "radio", the DF1 Radio Modem), check ("crc", "bcc"), plc ("slc", "micrologix",
    "slc502", "plc5", "plc2"), timeout_ms, cmd_timeout_ms, nak_retries,
    enq_retries, tx_delay_ms, line_baud, log (called with catalog ID,
    severity, text), trace (called with "rx"/"tx", bytes, microseconds),
    cancel_fd; and every df1_set_option(3) as its lower-case name
    (rs485=True, max_packet=82, plc5_typed_float_swapped=True, ...; see
    option_names()), or options={"rs485": 1}.
    """
    for k in opts:
        if k not in _OPTIONS:
            raise TypeError("open() got an unexpected keyword argument %r" % k)
    p = Plc()
    try:
        _configure(p, net, locals(), dict(options or {}, **opts))
        if target is None:
            target = p._net_port
        if not target:
            raise Df1ValueError(lib.DF1_E_INVAL, "no target: a device, tcp://host:port, or a network file")
        p.station = station
        p._open(target)
    except BaseException:
        p.close()
        raise
    return p


def _configure(p: Plc, net: Optional[str], kw: Dict[str, Any], options: Dict[str, Any]) -> None:
    h = p._h
    serial = [19200, 8, b"N", 1]
    p._net_port = None
    if net is not None:
        c = ffi.new("struct df1_net_config *")
        lib.df1_net_config_defaults(c)
        issues: List[ConfigIssue] = []

        def on_issue(user, i):
            issues.append(ConfigIssue(i.catalog_id, i.item, i.line, text(i.text)))

        fn = ffi.callback("df1_config_issue_fn", on_issue)
        rc = lib.df1_net_config_load(net.encode(), c, fn, ffi.NULL)
        if rc < 0:
            if issues or rc == lib.DF1_E_CONFIG:
                raise ConfigError(rc, issues=issues, address=net)
            raise make_error(rc, "%s: cannot be read" % net, address=net)
        p._check(lib.df1_apply_net_config(h, c))
        serial = [c.baud, c.data_bits, c.parity, c.stop_bits]
        p.plc_type = c.plc
        if c.port_given:
            p._net_port = text(c.port)
    for i, name in enumerate(("baud", "data_bits", "parity", "stop_bits")):
        if kw[name] is not None:
            serial[i] = _choice("parity", _PARITY, kw[name]) if name == "parity" else kw[name]
    if net is None or any(kw[n] is not None for n in ("baud", "data_bits", "parity", "stop_bits")):
        p._check(lib.df1_set_serial(h, *serial))
    if kw["handshake"] is not None:
        p._check(lib.df1_set_handshake(h, bool(kw["handshake"])))
    if kw["duplex"] is not None:
        p._check(lib.df1_set_duplex(h, _choice("duplex", _DUPLEX, kw["duplex"])))
    if kw["check"] is not None:
        p._check(lib.df1_set_check(h, _choice("check", _CHECK, kw["check"])))
    if kw["src"] is not None:
        p._check(lib.df1_set_station(h, kw["src"]))
    if kw["plc"] is not None:
        p.plc_type = _choice("plc", _PLC, kw["plc"])
        p._check(lib.df1_set_plc(h, p.plc_type))
    for name, fn_ in (("timeout_ms", lib.df1_set_timeout_ms), ("cmd_timeout_ms", lib.df1_set_cmd_timeout_ms),
                      ("tx_delay_ms", lib.df1_set_tx_delay_ms), ("line_baud", lib.df1_set_line_baud)):
        if kw[name] is not None:
            p._check(fn_(h, kw[name]))
    if kw["nak_retries"] is not None or kw["enq_retries"] is not None:
        nak = 3 if kw["nak_retries"] is None else kw["nak_retries"]
        enq = 3 if kw["enq_retries"] is None else kw["enq_retries"]
        if net is not None:
            nak = c.nak_retries if kw["nak_retries"] is None else nak
            enq = c.enq_retries if kw["enq_retries"] is None else enq
        p._check(lib.df1_set_retries(h, nak, enq))
    for name, value in options.items():
        if name not in _OPTIONS:
            raise Df1ValueError(lib.DF1_E_INVAL, "unknown option %r: one of %s" % (name, ", ".join(option_names())))
        p._check(lib.df1_set_option(h, _OPTIONS[name], int(value)))
    if kw["log"] is not None:
        user_log = kw["log"]

        def on_log(user, cid, sev, msg):
            try:
                user_log(cid, sev, text(msg))
            except Exception:       # a callback's error must not cross the C frame
                pass

        cb = ffi.callback("df1_log_fn", on_log)
        p._keep.append(cb)
        lib.df1_set_log(h, cb, ffi.NULL)
    if kw["trace"] is not None:
        user_trace = kw["trace"]

        def on_trace(user, direction, data, n, t_us):
            try:
                user_trace("tx" if direction == lib.DF1_DIR_TX else "rx", bytes(ffi.buffer(data, n)), t_us)
            except Exception:
                pass

        cb = ffi.callback("df1_trace_fn", on_trace)
        p._keep.append(cb)
        lib.df1_set_trace(h, cb, ffi.NULL)
    if kw["cancel_fd"] is not None:
        p._check(lib.df1_set_cancel_fd(h, kw["cancel_fd"]))
