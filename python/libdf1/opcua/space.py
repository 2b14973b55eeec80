# SPDX-License-Identifier: MPL-2.0
"""df1opcua's address space and its link to the poll engine.

Objects/LINE/stationN/TAG, one Variable per mapping row (a TIMER, COUNTER or
CONTROL row an Object with its members), NodeIds "LINE.stationN.TAG" in the
server's namespace. The thread of Line owns the DF1 handle (libdf1(7), thread
rule): it runs the poll engine and hands every change to the event loop, which
writes it into the address space, where subscriptions take it from (no read
of the PLC per client). Writes from clients wait in Writes' FIFO, go to
Poller.write() one at a time and are answered when the engine reports the
PLC's acknowledgement (or BadTimeout when one never got its turn in time).
"""
import asyncio
import collections
import datetime
import logging
import threading
from dataclasses import dataclass, field
from typing import Any, Callable, Deque, Dict, List, Optional, Tuple

from asyncua import ua

import libdf1
from libdf1._ffi import ffi, lib, text
from libdf1.errors import make_error

log = logging.getLogger("df1opcua")

NAMESPACE = "urn:libdf1:df1opcua"
SC = ua.StatusCodes

# the kind of a tag's values (df1_tag_value_kind(3)) -> its OPC UA type
_VARIANT = {
    lib.DF1_VAL_INT16: ua.VariantType.Int16,
    lib.DF1_VAL_INT32: ua.VariantType.Int32,
    lib.DF1_VAL_FLOAT: ua.VariantType.Float,
    lib.DF1_VAL_BIT: ua.VariantType.Boolean,
    lib.DF1_VAL_STRING: ua.VariantType.String,
}
_ZERO = {ua.VariantType.Int16: 0, ua.VariantType.Int32: 0, ua.VariantType.Float: 0.0,
         ua.VariantType.Boolean: False, ua.VariantType.String: ""}
# members of a timer, counter or control: (BrowseName, attribute of libdf1.Timer/Counter/Control)
_MEMBERS = {
    lib.DF1_FT_T: ("Timer", ["EN", "TT", "DN", "PRE", "ACC"]),
    lib.DF1_FT_C: ("Counter", ["CU", "CD", "DN", "OV", "UN", "PRE", "ACC"]),
    lib.DF1_FT_R: ("Control", ["EN", "EU", "DN", "EM", "ER", "UL", "IN", "FD", "LEN", "POS"]),
}
_WORDS = ("PRE", "ACC", "LEN", "POS")
STATION_VARS = ("Online", "State", "ProcessorType")
# a station's last error that says the port itself is gone (a device server
# closed the connection, a pty or USB adapter vanished): the line is opened again
_PORT_GONE = {getattr(lib, n) for n in ("DF1_E_CLOSED", "DF1_E_SYS", "DF1_E_NOT_OPEN", "DF1_E_NODEV") if hasattr(lib, n)}


@dataclass
class TagNode:
    id: int
    name: str
    station: int
    access: int
    count: int
    kind: int
    file_type: int
    node: Any = None                                # the Variable, or the Object of a T/C/R row
    members: Dict[str, Any] = field(default_factory=dict)   # T/C/R: BrowseName -> Variable

    @property
    def writable(self) -> bool:
        return self.access in (lib.DF1_ACCESS_WRITE, lib.DF1_ACCESS_READWRITE)

    @property
    def readable(self) -> bool:
        return self.access in (lib.DF1_ACCESS_READ, lib.DF1_ACCESS_READWRITE)

    @property
    def vtype(self) -> ua.VariantType:
        return _VARIANT[self.kind]


def tag_rows(plc: "libdf1.Plc", poller: "libdf1.Poller") -> List[TagNode]:
    """The poll engine's tags, with what the address space needs of each (df1_tag_get(3))."""
    out = []
    st = ffi.new("struct df1_tag_state *")
    for name in poller.tags:
        tid = poller._info(name).id
        with plc._lock:
            plc._check(lib.df1_tag_get(plc.handle, tid, st))
            c = st.config
            out.append(TagNode(tid, text(c.name) or name, c.station, c.access, c.count,
                               lib.df1_tag_value_kind(c), c.addr.type))
    return out


def status_of(quality: str, reason: str, has_value: bool = True) -> int:
    """A tag's quality and reason (df1_quality_name(3), df1_reason_name(3)) as an OPC UA StatusCode;
    a tag never read whose station does not answer has no last known value: BadNoCommunication."""
    if quality == "GOOD":
        return SC.Good
    if quality == "UNCERTAIN":
        return SC.UncertainLastUsableValue
    if reason == "not_yet_read" or (not has_value and reason in ("comm_failure", "station_offline")):
        return SC.BadNoCommunication
    if reason == "plc_error":
        return SC.BadDeviceFailure
    if reason == "config":
        return SC.BadConfigurationError
    return SC.BadCommunicationError


def write_status(e: BaseException) -> int:
    """The StatusCode of a failed write (the Df1Error of its Future)."""
    if isinstance(e, libdf1.PlcError):
        return SC.BadDeviceFailure
    if isinstance(e, (libdf1.Df1ValueError, libdf1.AddressError)):
        return SC.BadOutOfRange
    return SC.BadCommunicationError


def _now() -> datetime.datetime:
    return datetime.datetime.now(datetime.timezone.utc)


class Space:
    """The address space of one line, built once at start from the mapping's rows."""

    def __init__(self, server, idx: int, line: str, tags: List[TagNode]) -> None:
        self.server = server
        self.idx = idx
        self.line = line
        self.tags = tags
        self.by_name: Dict[str, TagNode] = {t.name: t for t in tags}
        self.by_nodeid: Dict[ua.NodeId, TagNode] = {}
        self.stations: Dict[int, Dict[str, Any]] = {}

    def nodeid(self, *parts: str) -> ua.NodeId:
        return ua.NodeId(".".join((self.line,) + parts), self.idx)

    @staticmethod
    def check_names(tags: List[TagNode]) -> List[str]:
        """What makes the NodeIds ambiguous: a row's Tag used twice in a station, or a station Variable's name."""
        seen: Dict[Tuple[int, str], int] = {}
        problems = []
        for t in tags:
            if t.name in STATION_VARS:
                problems.append("tag %r of station %d: %s are the station folder's own Variables"
                                % (t.name, t.station, ", ".join(STATION_VARS)))
            if (t.station, t.name) in seen:
                problems.append("tag %r twice in station %d" % (t.name, t.station))
            seen[(t.station, t.name)] = 1
        return problems

    async def build(self) -> None:
        objects = self.server.nodes.objects
        line = await objects.add_folder(self.nodeid(), ua.QualifiedName(self.line, self.idx))
        folders = {}
        for t in self.tags:
            if t.station not in folders:
                sname = "station%d" % t.station
                folders[t.station] = await line.add_folder(self.nodeid(sname), ua.QualifiedName(sname, self.idx))
                self.stations[t.station] = await self._station_vars(folders[t.station], sname)
            await self._add_tag(folders[t.station], t)

    async def _station_vars(self, folder, sname: str) -> Dict[str, Any]:
        out = {}
        for name, vt, val in (("Online", ua.VariantType.Boolean, False), ("State", ua.VariantType.String, "unknown"),
                              ("ProcessorType", ua.VariantType.String, "")):
            out[name] = await folder.add_variable(self.nodeid(sname, name), ua.QualifiedName(name, self.idx),
                                                  ua.Variant(val, vt), vt)
        return out

    async def _variable(self, parent, nid: ua.NodeId, name: str, vt: ua.VariantType, count: int, access: int):
        init = [_ZERO[vt]] * count if count > 1 else _ZERO[vt]
        var = await parent.add_variable(nid, ua.QualifiedName(name, self.idx), ua.Variant(init, vt, is_array=count > 1),
                                        vt)
        if count > 1:
            await var.write_value_rank(ua.ValueRank.OneDimension)
            await var.write_array_dimensions([count])
        level = 0
        if access in (lib.DF1_ACCESS_READ, lib.DF1_ACCESS_READWRITE):
            level |= ua.AccessLevel.CurrentRead.mask
        if access in (lib.DF1_ACCESS_WRITE, lib.DF1_ACCESS_READWRITE):
            level |= ua.AccessLevel.CurrentWrite.mask
        for attr in (ua.AttributeIds.AccessLevel, ua.AttributeIds.UserAccessLevel):
            await var.write_attribute(attr, ua.DataValue(ua.Variant(level, ua.VariantType.Byte)))
        await self.server.write_attribute_value(var.nodeid, ua.DataValue(StatusCode=ua.StatusCode(SC.BadNoCommunication)))
        return var

    async def _add_tag(self, folder, t: TagNode) -> None:
        sname = "station%d" % t.station
        nid = self.nodeid(sname, t.name)
        if t.kind == lib.DF1_VAL_TCR:
            # members are read-only: writing one word of an element is its own mapping row (T4:0.PRE)
            t.node = await folder.add_object(nid, ua.QualifiedName(t.name, self.idx))
            for m in _MEMBERS[t.file_type][1]:
                vt = ua.VariantType.Int16 if m in _WORDS else ua.VariantType.Boolean
                t.members[m] = await self._variable(t.node, self.nodeid(sname, t.name, m), m, vt, t.count,
                                                    lib.DF1_ACCESS_READ)
        else:
            t.node = await self._variable(folder, nid, t.name, t.vtype, t.count, t.access)
            self.by_nodeid[nid] = t

    async def apply(self, change: "libdf1.Change") -> None:
        """One change of the poll engine into the address space (and so to every subscription)."""
        t = self.by_name.get(change.tag)
        if t is None:
            return
        code = status_of(str(change.quality), str(change.reason), change.timestamp is not None)
        bad = ua.StatusCode(code).is_bad()
        src = change.timestamp if not bad and change.timestamp else _now()
        if t.kind == lib.DF1_VAL_TCR:
            for m, var in t.members.items():
                vt = ua.VariantType.Int16 if m in _WORDS else ua.VariantType.Boolean
                attr = "in_" if m == "IN" else m.lower()
                v = change.value
                val = None if v is None else ([getattr(e, attr) for e in v] if t.count > 1 else getattr(v, attr))
                await self._set(var.nodeid, val, vt, t.count, code, src)
        else:
            await self._set(t.node.nodeid, change.value, t.vtype, t.count, code, src)

    async def _set(self, nid, value, vt, count, code, src) -> None:
        if value is None or ua.StatusCode(code).is_bad():
            dv = ua.DataValue(StatusCode=ua.StatusCode(code), SourceTimestamp=src, ServerTimestamp=_now())
        else:
            if vt == ua.VariantType.Float:
                value = [float(x) for x in value] if count > 1 else float(value)
            dv = ua.DataValue(ua.Variant(value, vt, is_array=count > 1), StatusCode=ua.StatusCode(code),
                              SourceTimestamp=src, ServerTimestamp=_now())
        await self.server.write_attribute_value(nid, dv)

    async def set_station(self, station: int, state: str, ptype: Optional[str]) -> None:
        vs = self.stations.get(station)
        if vs is None:
            return
        now = _now()
        await self.server.write_attribute_value(vs["Online"].nodeid, ua.DataValue(
            ua.Variant(state == "ok", ua.VariantType.Boolean), SourceTimestamp=now, ServerTimestamp=now))
        await self.server.write_attribute_value(vs["State"].nodeid, ua.DataValue(
            ua.Variant(state, ua.VariantType.String), SourceTimestamp=now, ServerTimestamp=now))
        if ptype is not None:
            await self.server.write_attribute_value(vs["ProcessorType"].nodeid, ua.DataValue(
                ua.Variant(ptype, ua.VariantType.String), SourceTimestamp=now, ServerTimestamp=now))

    async def all_bad(self, code: int) -> None:
        for t in self.tags:
            if t.readable:
                for nid in ([v.nodeid for v in t.members.values()] if t.members else [t.node.nodeid]):
                    await self.server.write_attribute_value(nid, ua.DataValue(
                        StatusCode=ua.StatusCode(code), SourceTimestamp=_now(), ServerTimestamp=_now()))


@dataclass
class _Waiting:
    """A client's write in the FIFO of Writes, not yet handed to the line."""
    tag: TagNode
    value: Any
    done: "asyncio.Future[ua.StatusCode]"
    timer: Optional[asyncio.TimerHandle] = None


class Writes:
    """The Write service for the line's Variables; every other node goes to asyncua's own.

    The writes wait in a FIFO here and one at a time is handed to the poll
    engine (df1_tag_write(3)), the next once the engine has ended the one
    before: so a write handed over goes at the engine's next free slot, and
    one that waited longer than timeout_ms is answered BadTimeout and never
    sent (the engine's own queue has no way back). A write handed over ends as
    the line says, exactly once (the engine never resends it)."""

    def __init__(self, space: Space, line: "Line", max_pending: int, timeout_ms: int = 30000) -> None:
        self.space = space
        self.line = line
        self.max_pending = max_pending
        self.timeout_ms = timeout_ms
        self.pending = 0            # clients waiting for an answer: in the FIFO or on the line
        self.fifo: Deque[_Waiting] = collections.deque()
        self.busy = False           # a write handed to the engine and not ended
        self.closed = False
        self.counts = {"received": 0, "written": 0, "failed": 0, "refused": 0, "expired": 0}
        aservice = space.server.iserver.attribute_service
        self._orig = aservice.write
        aservice.write = self.write

    async def write(self, params: ua.WriteParameters, user=None) -> List[ua.StatusCode]:
        jobs = [self._one(wv, user) for wv in params.NodesToWrite]
        return list(await asyncio.gather(*jobs))

    async def _one(self, wv: ua.WriteValue, user) -> ua.StatusCode:
        if wv.NodeId.NamespaceIndex != self.space.idx:
            res = await self._orig(ua.WriteParameters(NodesToWrite=[wv]), user=user)
            return res[0]
        t = self.space.by_nodeid.get(wv.NodeId)
        self.counts["received"] += 1
        if t is None or wv.AttributeId != ua.AttributeIds.Value or not t.writable:
            self.counts["refused"] += 1
            log.info("write to %s refused: not writable", wv.NodeId.to_string())
            return ua.StatusCode(SC.BadNotWritable)
        if wv.IndexRange:
            self.counts["refused"] += 1
            return ua.StatusCode(SC.BadWriteNotSupported)
        var = wv.Value.Value if wv.Value is not None else None
        if var is None or var.Value is None or var.VariantType != t.vtype or \
                (t.count > 1) != isinstance(var.Value, list):
            self.counts["refused"] += 1
            return ua.StatusCode(SC.BadTypeMismatch)
        if self.closed:
            self.counts["refused"] += 1
            return ua.StatusCode(SC.BadShutdown)
        if self.pending >= self.max_pending:
            self.counts["refused"] += 1
            log.warning("write to %s refused: %d writes already wait", t.name, self.pending)
            return ua.StatusCode(SC.BadTooManyOperations)
        loop = asyncio.get_running_loop()
        w = _Waiting(t, var.Value, loop.create_future())
        w.timer = loop.call_later(self.timeout_ms / 1000.0, self._expire, w)
        self.fifo.append(w)
        self.pending += 1
        try:
            self._next()
            return await w.done
        finally:
            self.pending -= 1

    def _answer(self, w: _Waiting, code: int) -> None:
        if not w.done.done():       # a client gone meanwhile is not answered
            w.done.set_result(ua.StatusCode(code))

    def _expire(self, w: _Waiting) -> None:
        """w's deadline: if still in the FIFO, answered and dropped, never sent."""
        try:
            self.fifo.remove(w)     # the oldest (one timeout for all): at the front
        except ValueError:
            return                  # handed to the line already
        if w.done.done():
            return
        self.counts["expired"] += 1
        log.warning("write to %s expired, not written: not started within %d ms", w.tag.name, self.timeout_ms)
        self._answer(w, SC.BadTimeout)

    def _next(self) -> None:
        """Hand the oldest waiting write to the line when none is there."""
        while not self.busy and self.fifo:
            w = self.fifo.popleft()
            if w.timer is not None:
                w.timer.cancel()
            if w.done.done():
                continue            # its client went away: nothing sent
            try:
                fut = self.line.write(w.tag.id, w.value)
            except libdf1.Df1Error as e:
                self.counts["refused"] += 1
                log.info("write to %s refused: %s", w.tag.name, e)
                self._answer(w, write_status(e))
                continue
            self.busy = True
            asyncio.wrap_future(fut).add_done_callback(lambda f, w=w: self._ended(w, f))

    def _ended(self, w: _Waiting, f: "asyncio.Future[None]") -> None:
        self.busy = False
        e = None if f.cancelled() else f.exception()
        if f.cancelled() or e is not None:
            self.counts["failed"] += 1
            log.warning("write to %s failed: %s", w.tag.name, e or "cancelled")
            self._answer(w, write_status(e) if isinstance(e, libdf1.Df1Error) else SC.BadCommunicationError)
        else:
            self.counts["written"] += 1
            log.info("write to %s: written", w.tag.name)
            self._answer(w, SC.Good)
        self._next()

    def close(self) -> None:
        """At the stop: the writes still waiting are answered BadShutdown, nothing sent."""
        self.closed = True
        while self.fifo:
            w = self.fifo.popleft()
            if w.timer is not None:
                w.timer.cancel()
            self._answer(w, SC.BadShutdown)


class Line:
    """The DF1 line: a thread that opens it, runs the poll engine and hands what changes to the loop.

    open_line() returns (plc, poller); when the line fails the thread closes
    it, turns every tag Bad and opens it again after a backoff (1 s, doubling
    to 30 s), until stop()."""

    def __init__(self, open_line: Callable[[], Tuple[Any, Any]], loop: asyncio.AbstractEventLoop,
                 queue: "asyncio.Queue", stations: List[int]) -> None:
        self._open_line = open_line
        self._loop = loop
        self._queue = queue
        self._stations = stations
        self._stop = threading.Event()
        self._poller = None
        self._lock = threading.Lock()
        self._thread = threading.Thread(target=self._run, name="df1-line", daemon=True)

    def start(self, plc, poller) -> None:
        self._first = (plc, poller)
        with self._lock:        # a write that comes before the thread first runs finds the line open
            self._poller = poller
        self._thread.start()

    def stop(self, cancel: Optional[Callable[[], None]] = None) -> None:
        """End the thread: cancel() (if given) wakes a wait on the line once the flag is set."""
        self._stop.set()
        if cancel is not None:
            cancel()
        self._thread.join(10)

    def write(self, tid: int, value: Any):
        with self._lock:
            p = self._poller
        if p is None:
            raise libdf1.CommunicationError(lib.DF1_E_NOT_OPEN, "the line is not open")
        return p.write(tid, value)

    def _put(self, item) -> None:
        self._loop.call_soon_threadsafe(self._queue.put_nowait, item)

    def _run(self) -> None:
        backoff = 1.0
        plc, poller = self._first
        while not self._stop.is_set():
            if plc is None:
                try:
                    plc, poller = self._open_line()
                    log.info("line open again")
                    backoff = 1.0
                except libdf1.Df1Error as e:
                    log.warning("line: %s; again in %.0f s", e, backoff)
                    self._stop.wait(backoff)
                    backoff = min(backoff * 2, 30.0)
                    continue
            with self._lock:
                self._poller = poller
            try:
                self._serve(plc, poller)
            except libdf1.Df1Error as e:
                if self._stop.is_set():     # cancelled by stop()
                    plc.close()
                    return
                log.error("line lost: %s", e)
                self._put(("lost", None))
            with self._lock:
                self._poller = None
            plc.close()
            plc = poller = None

    def _serve(self, plc, poller) -> None:
        known: Dict[int, str] = {}
        ptype: Dict[int, Optional[str]] = {}
        while not self._stop.is_set():
            changes = poller.poll(0.2)
            if changes:
                self._put(("changes", changes))
            gone = 0
            for s in self._stations:
                health = poller.station_health(s)
                state = health["state"]
                gone += state == "offline" and health["last_error"] in _PORT_GONE
                if state == known.get(s):
                    continue
                known[s] = state
                name = None
                if state == "ok" and not ptype.get(s):
                    try:
                        name = plc.diag_status(station=s).name
                    except libdf1.Df1Error as e:
                        log.info("station %d: no diagnostic status: %s", s, e)
                    ptype[s] = name
                self._put(("station", (s, state, name)))
            if gone == len(self._stations):
                raise make_error(lib.DF1_E_CLOSED, "every station offline, the port closed")
