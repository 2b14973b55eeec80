# SPDX-License-Identifier: MPL-2.0
"""The GIL is released while C waits on the line: two lines in two threads
progress at once. Line A's df1sim is silenced, so A's read waits in C (ENQ
after ENQ); thread B meanwhile reads line B, and only after B's reads, done
while A was still inside its call, is A's df1sim answering again. Were the GIL
held during A's call, B could not read until A's read had failed."""
import threading

import libdf1

READS_OF_B = 20


def test_two_lines_in_two_threads_progress_together(sim_factory):
    sim_a = sim_factory(name="a")
    sim_b = sim_factory(name="b")
    a = libdf1.open(sim_a.target, timeout_ms=500, enq_retries=10)
    b = libdf1.open(sim_b.target)
    sim_a.silence()
    a_in_call = threading.Event()
    a_done = threading.Event()
    result = {}

    def line_a():
        a_in_call.set()
        try:
            result["a"] = a.read("N7:3")
        except libdf1.Df1Error as e:
            result["a"] = e
        finally:
            a_done.set()

    def line_b():
        a_in_call.wait(10)
        during = 0
        values = []
        for i in range(READS_OF_B):
            values.append(b.read("N7:%d" % i))
            if not a_done.is_set():
                during += 1
        result["b"] = values
        result["b_during_a"] = during
        sim_a.restore()

    ta = threading.Thread(target=line_a)
    tb = threading.Thread(target=line_b)
    ta.start()
    tb.start()
    ta.join(60)
    tb.join(60)
    a.close()
    b.close()
    assert result["b"] == list(range(READS_OF_B))
    # every read of B completed while A's call was still waiting on its line ...
    assert result["b_during_a"] == READS_OF_B
    # ... and A's read then completed too, once its PLC answered
    assert result["a"] == 3
    assert len(sim_a.wait_log(1, "addr=N7:3")) == 1
