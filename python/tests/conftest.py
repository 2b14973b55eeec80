# SPDX-License-Identifier: MPL-2.0
"""Test fixtures: df1sim as a separate process, as tests/support/simproc.c and tests/support/lib.sh start it.

DF1_BIN names the directory of the tools (default: the tree's build/bin);
LIBDF1_PATH the library (default: the tree's build/ when it holds one).
Every wait is on a condition with a deadline (df1sim's ready line, a --log
line), never a sleep that hopes.
"""
import os
import select
import signal
import subprocess
import sys
import time

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.abspath(os.path.join(HERE, "..")))
if not os.environ.get("LIBDF1_PATH") and os.path.exists(os.path.join(ROOT, "build", "libdf1.so.0")):
    os.environ["LIBDF1_PATH"] = os.path.join(ROOT, "build")

BIN = os.environ.get("DF1_BIN") or os.path.join(ROOT, "build", "bin")
DF1SIM = os.path.join(BIN, "df1sim")


class Sim:
    """One df1sim: on a pty (default) or on tcp://127.0.0.1:0, with a --log frame log."""

    def __init__(self, tmpdir, name="plc", tcp=False, args=(), data=None):
        self.dir = str(tmpdir)
        self.log = os.path.join(self.dir, name + ".log")
        self.err = os.path.join(self.dir, name + ".err")
        cmd = [DF1SIM]
        if tcp:
            cmd += ["--listen", "tcp://127.0.0.1:0"]
        else:
            cmd += ["--pty", os.path.join(self.dir, name)]
        if data is not None:
            path = os.path.join(self.dir, name + ".data")
            with open(path, "w") as f:
                f.write(data)
            cmd += ["--data", path]
        # -v: df1sim says on stderr when a SIGUSR1/SIGUSR2 has been applied
        cmd += ["--log", self.log, "-v"] + list(args)
        self.errf = open(self.err, "w")
        self.proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=self.errf)
        self.target = self._ready_line(10.0)

    def _ready_line(self, timeout):
        deadline = time.monotonic() + timeout
        buf = b""
        fd = self.proc.stdout.fileno()
        while b"\n" not in buf:
            left = deadline - time.monotonic()
            if left <= 0 or self.proc.poll() is not None:
                break
            r, _, _ = select.select([fd], [], [], left)
            if r:
                chunk = os.read(fd, 512)
                if not chunk:
                    break
                buf += chunk
        if b"\n" not in buf:
            self.stop()
            with open(self.err) as f:
                raise RuntimeError("df1sim did not start: %s" % f.read())
        return buf.split(b"\n", 1)[0].decode()

    @property
    def pid(self):
        return self.proc.pid

    def _err_count(self, text):
        with open(self.err) as f:
            return f.read().count(text)

    def _signal(self, sig, said):
        # df1sim applies a signal when its wait ends: bytes already there may be
        # served first. Wait (bounded) until it says it has applied it.
        before = self._err_count(said)
        os.kill(self.proc.pid, sig)
        deadline = time.monotonic() + 10
        while self._err_count(said) <= before:
            if time.monotonic() > deadline:
                raise RuntimeError("df1sim did not apply signal %d" % sig)
            time.sleep(0.01)

    def silence(self):
        """SIGUSR1: every station stops answering (df1sim(1) SIGNALS)."""
        self._signal(signal.SIGUSR1, "SIGUSR1: every station silent")

    def restore(self):
        """SIGUSR2: answer again."""
        self._signal(signal.SIGUSR2, "SIGUSR2: stations answer again")

    def log_lines(self, *needles):
        """The --log lines holding every needle (one line per command answered)."""
        try:
            with open(self.log) as f:
                lines = f.read().splitlines()
        except FileNotFoundError:
            return []
        return [ln for ln in lines if all(n in ln for n in needles)]

    def wait_log(self, want, *needles, timeout=10.0):
        """df1sim logs a command after its reply went out: wait (bounded) for want lines."""
        deadline = time.monotonic() + timeout
        while True:
            got = self.log_lines(*needles)
            if len(got) >= want or time.monotonic() > deadline:
                return got
            time.sleep(0.01)

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.proc.stdout.close()
        self.errf.close()
        return self.proc.returncode


@pytest.fixture
def sim_factory(tmp_path):
    sims = []

    def start(*args, name=None, tcp=False, data=None):
        s = Sim(tmp_path, name or "plc%d" % len(sims), tcp=tcp, args=args, data=data)
        sims.append(s)
        return s

    yield start
    for s in sims:
        s.stop()


@pytest.fixture
def sim(sim_factory):
    return sim_factory()


def pytest_report_header(config):
    import libdf1
    return "libdf1 %s from %s; df1sim %s" % (libdf1.library_version(), os.environ.get("LIBDF1_PATH", "the system"),
                                          DF1SIM)
