# SPDX-License-Identifier: MPL-2.0
"""The poll engine (df1_poll(3)): a scan list, block reads, quality, station health, queued writes.

Thread rule: the thread that iterates changes() (or calls poll()) owns the
handle while it does; Poller.write() may be called from any thread at any
time (df1_tag_write(3)), and its result arrives when the polling thread runs
the write in the next free slot between reads. A Future from write() is
completed by the polling thread: waiting on it in that same thread, without
polling, waits in vain.
"""
import collections
import threading
import time
from concurrent.futures import Future
from dataclasses import dataclass
from datetime import datetime, timezone
from enum import Enum
from typing import Any, Deque, Dict, Iterator, List, NamedTuple, Optional, Union

from ._ffi import ffi, lib, text
from .errors import ConfigError, ConfigIssue, Df1Error, Df1ValueError, from_handle, make_error
from .values import Addr, from_python, to_python

__all__ = ["Tag", "Quality", "Reason", "Change", "TagState", "Poller"]


class Quality(str, Enum):
    """A tag's quality (df1_quality_name(3)); compares equal to its name, "GOOD"."""
    BAD = "BAD"
    UNCERTAIN = "UNCERTAIN"
    GOOD = "GOOD"

    def __str__(self) -> str:
        return self.value

    __format__ = str.__format__


class Reason(str, Enum):
    """Why a tag is not GOOD (df1_reason_name(3)); "none" when it is."""
    NONE = "none"
    NOT_YET_READ = "not_yet_read"
    COMM_FAILURE = "comm_failure"
    STATION_OFFLINE = "station_offline"
    PLC_ERROR = "plc_error"
    CONFIG = "config"

    def __str__(self) -> str:
        return self.value

    __format__ = str.__format__


_ACCESS = {"read": lib.DF1_ACCESS_READ, "write": lib.DF1_ACCESS_WRITE, "readwrite": lib.DF1_ACCESS_READWRITE}


@dataclass
class Tag:
    """A tag of the scan list (struct df1_tag_config); name defaults to the address."""
    address: str
    name: Optional[str] = None
    count: int = 1
    scan_ms: int = 1000             # 0: every scan
    station: Optional[int] = None   # default: the Plc's station
    access: str = "read"            # "read", "write" or "readwrite"
    type: str = ""                  # the mapping file's Type: "" (the address's own), "INT", "DINT",
    #                                 "REAL", "BOOL", "STRING", "TIMER" ... (df1_tag_value_kind(3))


class Change(NamedTuple):
    """A change of a tag's value, quality or reason, as df1_poll(3) reports it."""
    tag: str
    value: Any                      # a value, a list for count > 1, None before the first read
    quality: Quality
    reason: Reason
    timestamp: Optional[datetime]   # the last good read (UTC), None if never


@dataclass
class TagState:
    """A snapshot of one tag (struct df1_tag_state)."""
    id: int
    tag: str
    value: Any
    quality: Quality
    reason: Reason
    timestamp: Optional[datetime]
    age_ms: int                     # since the last good read, -1 if never
    last_error: Optional[Df1Error]  # of the last failed read
    sts: int
    ext_sts: int
    reads: int


def _wall(ms: int) -> Optional[datetime]:
    return datetime.fromtimestamp(ms / 1000.0, tz=timezone.utc) if ms else None


class _TagInfo:
    __slots__ = ("id", "name", "addr", "count")

    def __init__(self, id_: int, name: str, addr: Addr, count: int):
        self.id = id_
        self.name = name
        self.addr = addr
        self.count = count


class Poller:
    """The poll engine of one Plc: made by Plc.poller()."""

    def __init__(self, plc) -> None:
        self._plc = plc
        self._pending: Deque[Change] = collections.deque()
        self._by_name: Dict[str, _TagInfo] = {}
        self._by_id: Dict[int, _TagInfo] = {}
        self._writes: Dict[Any, Future] = {}
        self._writes_lock = threading.Lock()
        self.issues: List[ConfigIssue] = []
        self._on_tag = ffi.callback("df1_tag_fn", self._tag_changed)
        self._on_done = ffi.callback("df1_write_done_fn", self._write_done)
        plc._check(lib.df1_set_tag_callback(plc.handle, self._on_tag, ffi.NULL))

    def _detach(self) -> None:
        with self._writes_lock:
            pending = list(self._writes.values())
            self._writes.clear()
        for _, f in pending:
            if not f.done():
                f.set_exception(make_error(lib.DF1_E_NOT_OPEN, "the Plc was closed"))

    # ---- the scan list ----
    def add(self, tag: Union[str, Tag]) -> int:
        """Add a tag (an address, "N7:0,10", or a Tag); returns its id (df1_tag_add(3))."""
        if isinstance(tag, str):
            addr, _, count = tag.partition(",")
            tag = Tag(address=addr.strip(), name=tag, count=int(count) if count else 1)
        name = tag.name or tag.address
        a = Addr(tag.address, self._plc.plc_type)
        c = ffi.new("struct df1_tag_config *")
        nb = name.encode()
        if len(nb) >= ffi.sizeof(c.name):
            raise Df1ValueError(lib.DF1_E_INVAL, "tag name longer than %d bytes" % (ffi.sizeof(c.name) - 1),
                                address=name)
        c.name = nb
        if tag.access not in _ACCESS:
            raise Df1ValueError(lib.DF1_E_INVAL, "access %r: read, write or readwrite" % tag.access)
        c.access = _ACCESS[tag.access]
        c.station = self._plc.station if tag.station is None else tag.station
        c.plc = self._plc.plc_type
        ffi.memmove(ffi.addressof(c[0], "addr"), a.c, ffi.sizeof("struct df1_addr"))
        c.count = tag.count
        c.scan_ms = tag.scan_ms
        tb = tag.type.encode()
        if len(tb) >= ffi.sizeof(c.type):
            raise Df1ValueError(lib.DF1_E_INVAL, "Type %r: not a Type" % tag.type, address=tag.address)
        c.type = tb
        with self._plc._lock:
            tid = self._plc._check(lib.df1_tag_add(self._plc.handle, c), tag.address)
        k = lib.df1_tag_value_kind(c)
        if k >= 0:
            a.kind = k          # writes take values of the Type (REAL on N7:0: a float)
        self._remember(tid, name, a, tag.count)
        return tid

    def load_map(self, path: str, strict: bool = False) -> int:
        """Add every row of a mapping CSV (df1_tag_load_map(3)); returns the tags added.

        Rows with problems are skipped and listed in .issues (catalog IDs
        2501-2504); strict: any problem adds nothing and raises ConfigError.
        """
        issues: List[ConfigIssue] = []

        def on_issue(user, i):
            issues.append(ConfigIssue(i.catalog_id, i.item, i.line, text(i.text)))

        fn = ffi.callback("df1_config_issue_fn", on_issue)
        with self._plc._lock:
            h = self._plc.handle
            before = lib.df1_tag_count(h)
            rc = lib.df1_tag_load_map(h, path.encode(), strict, fn, ffi.NULL)
            self.issues.extend(issues)
            if rc < 0:
                if rc == lib.DF1_E_CONFIG:
                    raise ConfigError(rc, issues=issues, address=path)
                raise from_handle(h, rc, address=path)
            st = ffi.new("struct df1_tag_state *")
            buf = ffi.new("char[]", 64)
            for tid in range(before, lib.df1_tag_count(h)):
                if lib.df1_tag_get(h, tid, st) < 0:
                    continue
                lib.df1_addr_format_plc(st.config.plc, ffi.addressof(st.config, "addr"), buf, 64)
                name = text(st.config.name) or text(buf)
                a = Addr(text(buf), st.config.plc)
                k = lib.df1_tag_value_kind(st.config)
                if k >= 0:
                    a.kind = k
                self._remember(tid, name, a, st.config.count)
        return rc

    def _remember(self, tid: int, name: str, a: Addr, count: int) -> None:
        info = _TagInfo(tid, name, a, count)
        self._by_id[tid] = info
        self._by_name.setdefault(name, info)

    @property
    def tags(self) -> List[str]:
        """The names of the tags, in id order."""
        return [self._by_id[i].name for i in sorted(self._by_id)]

    def _info(self, tag: Union[str, int]) -> _TagInfo:
        info = self._by_id.get(tag) if isinstance(tag, int) else self._by_name.get(tag)
        if info is None:
            raise Df1ValueError(lib.DF1_E_INVAL, "no such tag", address=str(tag))
        return info

    # ---- polling ----
    def _values(self, info: Optional[_TagInfo], st) -> Any:
        if not st.has_value:
            return None
        ft = st.config.addr.type
        vals = [to_python(st.values[i], ft) for i in range(st.count)]
        return vals[0] if st.count == 1 else vals

    def _tag_changed(self, user, tid, st) -> None:
        try:
            info = self._by_id.get(tid)
            name = info.name if info else text(st.config.name)
            self._pending.append(Change(name, self._values(info, st), Quality(text(lib.df1_quality_name(st.quality))),
                                        Reason(text(lib.df1_reason_name(st.reason))), _wall(st.last_good_wall_ms)))
        except Exception:       # never across the C frame
            pass

    def poll(self, timeout: Optional[float] = 0) -> List[Change]:
        """One df1_poll(3): run the work that is due (waiting up to timeout seconds for
        some if none is; None: until the next due item) and return the changes it made."""
        ms = -1 if timeout is None else max(0, int(timeout * 1000))
        with self._plc._lock:
            rc = lib.df1_poll(self._plc.handle, ms)
            if rc < 0:
                raise from_handle(self._plc._h, rc)
        out = list(self._pending)
        self._pending.clear()
        return out

    def changes(self, timeout: Optional[float] = None) -> Iterator[Change]:
        """Poll and yield every change (tag, value, quality, reason, timestamp) for timeout
        seconds in all (None: for ever). The first scan reports every tag once."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            while self._pending:
                yield self._pending.popleft()
            if deadline is None:
                wait = 1.0
            else:
                wait = deadline - time.monotonic()
                if wait <= 0:
                    return
                wait = min(wait, 1.0)   # back to Python now and then (KeyboardInterrupt)
            with self._plc._lock:
                rc = lib.df1_poll(self._plc.handle, max(1, int(wait * 1000)))
                if rc < 0:
                    raise from_handle(self._plc._h, rc)

    def state(self, tag: Union[str, int]) -> TagState:
        """The current state of a tag (df1_tag_get(3))."""
        info = self._info(tag)
        st = ffi.new("struct df1_tag_state *")
        with self._plc._lock:
            self._plc._check(lib.df1_tag_get(self._plc.handle, info.id, st))
            return TagState(id=info.id, tag=info.name, value=self._values(info, st),
                            quality=Quality(text(lib.df1_quality_name(st.quality))),
                            reason=Reason(text(lib.df1_reason_name(st.reason))),
                            timestamp=_wall(st.last_good_wall_ms), age_ms=st.age_ms,
                            last_error=make_error(st.last_error, address=info.name) if st.last_error else None,
                            sts=st.sts, ext_sts=st.ext_sts, reads=st.reads)

    def stats(self) -> Dict[str, int]:
        """The engine's statistics (df1_poll_stats(3)) by field name."""
        s = ffi.new("struct df1_poll_stats *")
        with self._plc._lock:
            self._plc._check(lib.df1_poll_stats(self._plc.handle, s))
        return {name: int(getattr(s, name)) for name, _ in ffi.typeof("struct df1_poll_stats").fields}

    def station_health(self, station: Optional[int] = None) -> Dict[str, Any]:
        """One station's health (df1_station_health(3)); state as its name ("ok", "offline" ...)."""
        st = self._plc.station if station is None else station
        s = ffi.new("struct df1_station_health *")
        with self._plc._lock:
            self._plc._check(lib.df1_station_health(self._plc.handle, st, s), "", st)
        out = {name: int(getattr(s, name)) for name, _ in ffi.typeof("struct df1_station_health").fields}
        out["state"] = text(lib.df1_station_state_name(s.state))
        return out

    # ---- writes (any thread) ----
    def write(self, tag: Union[str, int], value: Any) -> "Future[None]":
        """Queue a write of a tag (df1_tag_write(3)); safe from any thread.

        The value(s) are checked now (Df1ValueError); the write is sent by the
        polling thread in the next free slot and ends exactly once: the returned
        concurrent.futures.Future gets None (written) or the Df1Error of the
        failure. A failed write is never resent (a timeout: the PLC may or may
        not have executed it).
        """
        info = self._info(tag)
        values = value if isinstance(value, (list, tuple)) and not isinstance(value, str) and \
            not (info.addr.kind == lib.DF1_VAL_TCR and len(value) == 3 and all(isinstance(x, int) for x in value)) \
            else [value]
        if not 1 <= len(values) <= info.count:
            raise Df1ValueError(lib.DF1_E_INVAL, "%d values for a tag of %d" % (len(values), info.count),
                                address=info.name)
        buf = ffi.new("struct df1_value[]", len(values))
        for i, v in enumerate(values):
            from_python(info.addr, v, buf[i])
        fut: Future = Future()
        fut.set_running_or_notify_cancel()
        key = ffi.new_handle(fut)
        kid = int(ffi.cast("uintptr_t", key))
        with self._writes_lock:
            self._writes[kid] = (key, fut)
        rc = lib.df1_tag_write(self._plc.handle, info.id, buf, len(values), self._on_done, key)
        if rc < 0:
            with self._writes_lock:
                self._writes.pop(kid, None)
            raise make_error(rc, address=info.name)
        fut.write_id = rc
        return fut

    def _write_done(self, user, tid, write_id, result) -> None:
        try:
            with self._writes_lock:
                entry = self._writes.pop(int(ffi.cast("uintptr_t", user)), None)
            if entry is None or entry[1].done():
                return
            fut = entry[1]
            if result == 0:
                fut.set_result(None)
            else:
                info = self._by_id.get(tid)
                # called from df1_poll: the handle's detail may describe this failure
                h = self._plc._h
                fut.set_exception(from_handle(h, result, address=info.name if info else "")
                                  if h is not None else make_error(result))
        except Exception:       # never across the C frame
            pass
