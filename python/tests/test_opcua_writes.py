# SPDX-License-Identifier: MPL-2.0
"""df1opcua's write FIFO (libdf1.opcua.space.Writes, df1opcua(1) Writes) against a stand-in
line whose writes end when the test says: one write on the line at a time, in arrival order;
a write still waiting at --write-timeout answered BadTimeout and never handed to the line;
one handed over ends as the line says; BadTooManyOperations; BadShutdown at the stop.
The whole server is tested through node-opcua by tests/integration/it_df1opcua.sh."""
import asyncio
from concurrent.futures import Future
from types import SimpleNamespace

import pytest

pytest.importorskip("asyncua")
from asyncua import ua  # noqa: E402

import libdf1  # noqa: E402
from libdf1._ffi import lib  # noqa: E402
from libdf1.opcua.space import Space, TagNode, Writes  # noqa: E402

SC = ua.StatusCodes


class FakeLine:
    """Line.write(): records what was handed over; the test ends each write."""

    def __init__(self):
        self.handed = []        # (tag id, value, Future)

    def write(self, tid, value):
        f = Future()
        f.set_running_or_notify_cancel()
        self.handed.append((tid, value, f))
        return f


def make(max_pending=1000, timeout_ms=30000):
    service = SimpleNamespace(write=None)
    server = SimpleNamespace(iserver=SimpleNamespace(attribute_service=service))
    tag = TagNode(id=3, name="Speed", station=1, access=lib.DF1_ACCESS_READWRITE, count=1,
                  kind=lib.DF1_VAL_INT16, file_type=lib.DF1_FT_N)
    space = Space(server, 2, "L", [tag])
    nid = space.nodeid("station1", "Speed")
    space.by_nodeid[nid] = tag
    line = FakeLine()
    return Writes(space, line, max_pending, timeout_ms), line, nid


def request(nid, value):
    return ua.WriteValue(NodeId=nid, AttributeId=ua.AttributeIds.Value,
                         Value=ua.DataValue(ua.Variant(value, ua.VariantType.Int16)))


async def settle():
    for _ in range(5):
        await asyncio.sleep(0)


def codes(results):
    return [r.value for r in results]


def test_one_on_the_line_at_a_time_in_order():
    async def run():
        w, line, nid = make()
        task = asyncio.create_task(w.write(ua.WriteParameters(NodesToWrite=[request(nid, v) for v in (1, 2, 3)])))
        await settle()
        assert [h[1] for h in line.handed] == [1]           # the others wait for it
        line.handed[0][2].set_result(None)
        await settle()
        assert [h[1] for h in line.handed] == [1, 2]
        line.handed[1][2].set_exception(libdf1.CommunicationError(lib.DF1_E_TIMEOUT, "no reply"))
        await settle()
        assert [h[1] for h in line.handed] == [1, 2, 3]
        line.handed[2][2].set_exception(libdf1.PlcError(lib.DF1_E_REMOTE, "refused", sts=0x10))
        assert codes(await task) == [SC.Good, SC.BadCommunicationError, SC.BadDeviceFailure]
        assert w.counts["written"] == 1 and w.counts["failed"] == 2 and w.pending == 0
    asyncio.run(run())


def test_expired_write_is_never_handed_over():
    async def run():
        w, line, nid = make(timeout_ms=50)
        task = asyncio.create_task(w.write(ua.WriteParameters(NodesToWrite=[request(nid, v) for v in (1, 2, 3)])))
        await settle()
        assert len(line.handed) == 1
        # the first stays on the line past the others' deadline: they expire, it does not
        async def expired():
            while w.counts["expired"] < 2:
                await asyncio.sleep(0.01)
        await asyncio.wait_for(expired(), 10)
        assert not task.done() and len(line.handed) == 1
        line.handed[0][2].set_result(None)
        assert codes(await task) == [SC.Good, SC.BadTimeout, SC.BadTimeout]
        later = asyncio.create_task(w.write(ua.WriteParameters(NodesToWrite=[request(nid, 4)])))
        await settle()
        assert [h[1] for h in line.handed] == [1, 4]        # 2 and 3 never sent
        line.handed[1][2].set_result(None)
        assert codes(await later) == [SC.Good]
        assert w.counts["written"] == 2 and w.counts["expired"] == 2
    asyncio.run(run())


def test_too_many_waiting_and_the_stop():
    async def run():
        w, line, nid = make(max_pending=2)
        task = asyncio.create_task(w.write(ua.WriteParameters(NodesToWrite=[request(nid, v) for v in (1, 2, 3)])))
        await settle()
        w.close()                       # the stop: the waiting write answered, not sent
        await settle()
        line.handed[0][2].set_result(None)
        assert codes(await task) == [SC.Good, SC.BadShutdown, SC.BadTooManyOperations]
        assert [h[1] for h in line.handed] == [1]
        assert codes(await w.write(ua.WriteParameters(NodesToWrite=[request(nid, 5)]))) == [SC.BadShutdown]
        assert len(line.handed) == 1
    asyncio.run(run())


def test_line_not_open():
    async def run():
        w, line, nid = make()

        def closed(tid, value):
            raise libdf1.CommunicationError(lib.DF1_E_NOT_OPEN, "the line is not open")
        line.write = closed
        res = await w.write(ua.WriteParameters(NodesToWrite=[request(nid, 1), request(nid, 2)]))
        assert codes(res) == [SC.BadCommunicationError, SC.BadCommunicationError]
        assert w.pending == 0 and not w.busy
    asyncio.run(run())
