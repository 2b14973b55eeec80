# SPDX-License-Identifier: MPL-2.0
"""python/README.md's examples (read, write, poll, handle errors) run as written,
against df1sim standing in for the device they name."""
import contextlib
import io
import os
import re


README = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "README.md")


def example(section):
    with open(README) as f:
        text = f.read()
    body = re.split(r"\n%s\n-+\n" % re.escape(section), text)[1]
    body = re.split(r"\n[^\n]+\n-+\n", body)[0]
    m = re.search(r"((?:\n    [^\n]*|\n)+)", body)
    code = "\n".join(line[4:] for line in m.group(1).split("\n"))
    assert "import libdf1" in code
    return code


def run(code, **replace):
    for old, new in replace.items():
        assert old in code, old
        code = code.replace(old, new)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, README, "exec"), {})
    return out.getvalue()


def test_read(sim):
    out = run(example("Read"), **{'"/dev/ttyUSB0"': repr(sim.target)})
    assert out == "0 False 0 False\n"


def test_write(sim_factory):
    s = sim_factory("--duplex", "half", "--check", "bcc", "--station", "3", tcp=True)
    run(example("Write"), **{'"tcp://10.0.0.20:2101"': repr(s.target)})
    assert len(s.wait_log(1, "station=3", "addr=N7:5", "cmd=0F/AA")) == 1
    assert len(s.wait_log(1, "station=3", "addr=T4:0", "cmd=0F/AA")) == 1


def test_poll(sim_factory):
    s = sim_factory("--plc", "micrologix")
    out = run(example("Poll"), **{'"/dev/ttyUSB0"': repr(s.target), "timeout=60": "timeout=1"})
    lines = out.splitlines()
    assert any(ln.startswith("N7:0 0 GOOD none ") for ln in lines), out
    assert any(ln.startswith("F8:0,4 [0.5, 1.5, 2.5, 3.5] GOOD none ") for ln in lines), out
    assert any(ln.startswith("pump False GOOD none ") for ln in lines), out


def test_handle_errors(sim_factory):
    s = sim_factory()
    assert run(example("Handle errors"), **{'"/dev/ttyUSB0"': repr(s.target)}) == "0\n"
    s.silence()
    out = run(example("Handle errors"), **{'"/dev/ttyUSB0"': repr(s.target), "timeout_ms=500": "timeout_ms=100"})
    assert out == "no answer: 2520 NTC_ENQ_LIMIT_EXCEEDED 1\n"
