#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""notify_probe.py - plays systemd's side of the notification protocol for
df1gw (df1gw(1) SYSTEMD): binds the NOTIFY_SOCKET datagram socket (a path,
or an abstract name with --abstract), starts the command after "--" with
NOTIFY_SOCKET and WATCHDOG_USEC set, and checks what arrives against
sd_notify(3) and systemd.service(5), not against df1gw's own output:

  READY=1 only once df1sim's --log shows the line answered (the first scan),
  STATUS= lines, WATCHDOG=1 at least every WATCHDOG_USEC, none while the
  process is stopped (SIGSTOP) and again after SIGCONT, RELOADING=1 (with
  MONOTONIC_USEC) then READY=1 on SIGHUP, STOPPING=1 on SIGTERM and exit 0.

  notify_probe.py [--abstract] [--watchdog-usec N] --log SIM.LOG -- CMD...
  notify_probe.py --never-ready SECONDS -- CMD...   (no READY=1; STATUS says the line is down)
  notify_probe.py --broker-gate SHELL -- CMD...      (no READY=1 while the broker is missing;
                  then SHELL starts it, and READY=1 follows with STATUS "broker connected")

Prints one line per check ("ok ..." or "FAIL ..."); exits 1 if any failed.
"""
import argparse
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time

fails = 0


def check(cond, what):
    global fails
    print(("ok " if cond else "FAIL ") + what, flush=True)
    if not cond:
        fails += 1


class Listener:
    def __init__(self, abstract):
        self.s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        if abstract:
            name = "df1test-notify-%d-%d" % (os.getpid(), int(time.time() * 1000))
            self.s.bind("\0" + name)
            self.env = "@" + name
        else:
            self.dir = tempfile.mkdtemp()
            path = os.path.join(self.dir, "notify")
            self.s.bind(path)
            self.env = path
        self.msgs = []      # (monotonic seconds, {key: value})
        self.seen = 0       # msgs[:seen] were looked at by wait_for

    def read(self, until):
        """Messages until the monotonic time until."""
        got = []
        while True:
            left = until - time.monotonic()
            if left <= 0:
                return got
            self.s.settimeout(left)
            try:
                data = self.s.recv(4096)
            except socket.timeout:
                return got
            fields = {}
            for line in data.decode("utf-8", "replace").split("\n"):
                if "=" in line:
                    k, v = line.split("=", 1)
                    fields[k] = v
            m = (time.monotonic(), fields)
            self.msgs.append(m)
            got.append(m)

    def wait_for(self, key, value, seconds):
        """The first message with key=value within seconds, or None."""
        end = time.monotonic() + seconds
        while True:
            while self.seen < len(self.msgs):
                m = self.msgs[self.seen]
                self.seen += 1
                if m[1].get(key) == value:
                    return m
            if time.monotonic() >= end:
                return None
            self.read(min(end, time.monotonic() + 0.2))


def log_lines(path):
    try:
        with open(path) as f:
            return sum(1 for line in f if line.strip())
    except OSError:
        return 0


def pings(msgs):
    return [t for t, f in msgs if f.get("WATCHDOG") == "1"]


def scenario(a, lst, p):
    period = a.watchdog_usec / 1e6
    ready = lst.wait_for("READY", "1", 30)
    check(ready is not None, "READY=1 arrives")
    if ready is None:
        return
    check(log_lines(a.log) > 0, "READY=1 only after the line answered (df1sim logged a command)")
    statuses = [f["STATUS"] for t, f in lst.msgs if "STATUS" in f]
    check(any(s.startswith("line ok") for s in statuses), "STATUS= says the line is ok: %r" % statuses[-1:])
    # the watchdog: at least once per WATCHDOG_USEC over a few periods
    start = time.monotonic()
    got = lst.read(start + 4 * period)
    ts = [start] + pings(got)
    gaps = [b - a_ for a_, b in zip(ts, ts[1:])]
    check(len(ts) - 1 >= 3, "WATCHDOG=1 keeps coming (%d in %.1f s)" % (len(ts) - 1, 4 * period))
    check(gaps and max(gaps) < period, "WATCHDOG=1 within WATCHDOG_USEC (longest gap %.2f s of %.2f s)"
          % (max(gaps) if gaps else -1, period))
    # a stopped loop: no pings
    os.kill(p.pid, signal.SIGSTOP)
    lst.read(time.monotonic() + 0.3)        # what was on its way
    got = lst.read(time.monotonic() + 2 * period)
    lst.seen = len(lst.msgs)                # what follows comes after SIGCONT
    check(len(pings(got)) == 0, "no WATCHDOG=1 while the process is stopped (%d)" % len(pings(got)))
    os.kill(p.pid, signal.SIGCONT)
    check(lst.wait_for("WATCHDOG", "1", 2 * period) is not None, "WATCHDOG=1 again after SIGCONT")
    # a reload
    os.kill(p.pid, signal.SIGHUP)
    rl = lst.wait_for("RELOADING", "1", 10)
    check(rl is not None, "RELOADING=1 on SIGHUP")
    if rl:
        check(rl[1].get("MONOTONIC_USEC", "").isdigit(), "RELOADING=1 carries MONOTONIC_USEC")
        check(lst.wait_for("READY", "1", 30) is not None, "READY=1 after the reload")
    # the end
    os.kill(p.pid, signal.SIGTERM)
    check(lst.wait_for("STOPPING", "1", 10) is not None, "STOPPING=1 on SIGTERM")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--abstract", action="store_true")
    ap.add_argument("--watchdog-usec", type=int, default=2000000)
    ap.add_argument("--log")
    ap.add_argument("--never-ready", type=float)
    ap.add_argument("--broker-gate")
    ap.add_argument("cmd", nargs="+")
    a = ap.parse_args()
    lst = Listener(a.abstract)
    env = dict(os.environ, NOTIFY_SOCKET=lst.env, WATCHDOG_USEC=str(a.watchdog_usec))
    p = subprocess.Popen(a.cmd, env=env)
    try:
        if a.broker_gate:
            got = lst.read(time.monotonic() + 3)
            check(not any(f.get("READY") == "1" for t, f in got), "no READY=1 while the broker is missing")
            st = [f["STATUS"] for t, f in got if "STATUS" in f]
            check(any(s.startswith("line ok") and "broker connected" not in s for s in st),
                  "STATUS= says the line is ok and the broker is not: %r" % st[-1:])
            subprocess.run(a.broker_gate, shell=True, check=False)
            check(lst.wait_for("READY", "1", 30) is not None, "READY=1 once the broker is there")
            st = [f["STATUS"] for t, f in lst.msgs if "STATUS" in f]
            check(st and "broker connected" in st[-1], "STATUS= says the broker is connected: %r" % st[-1:])
            p.send_signal(signal.SIGTERM)
            check(lst.wait_for("STOPPING", "1", 10) is not None, "STOPPING=1 on SIGTERM")
        elif a.never_ready:
            got = lst.read(time.monotonic() + a.never_ready)
            check(not any(f.get("READY") == "1" for t, f in got), "no READY=1 while the line cannot open")
            st = [f["STATUS"] for t, f in got if "STATUS" in f]
            check(any(s.startswith("line down") for s in st), "STATUS= says the line is down: %r" % st[-1:])
            check(len(pings(got)) > 0, "WATCHDOG=1 still comes: the loop turns")
            p.send_signal(signal.SIGTERM)
        else:
            scenario(a, lst, p)
        rc = p.wait(timeout=20)
        check(rc == 0, "exit status 0 after SIGTERM (%s)" % rc)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    sys.exit(1 if fails else 0)


main()
