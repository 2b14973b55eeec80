#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""df1opcua's bench line: 1 000 tags on a full-speed pty, how many tag reads a second reach the
PLC and how long a change takes from the read to an OPC UA subscriber.

    python3 python/bench_opcua.py [--seconds S] [--line-baud BAUD]

df1sim (DF1_BIN, default the tree's build/bin) on a pty ramps N7:0 every 100 ms; df1opcua
(this tree's python/, the library from LIBDF1_PATH) polls N7:0..N7:999, one INT tag each,
every scan. Reads a second come from df1sim's --log (the elements each logged read asked for),
not from df1opcua. The subscriber is asyncua's client (the point here is time, not
independence): the latency of each notification of N7:0 is its arrival minus its
SourceTimestamp (the read time), both on this machine's clock. Needs asyncua.
"""
import argparse
import asyncio
import os
import re
import select
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
if not os.environ.get("LIBDF1_PATH") and os.path.exists(os.path.join(ROOT, "build", "libdf1.so.0")):
    os.environ["LIBDF1_PATH"] = os.path.join(ROOT, "build")
TAGS = 1000


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_line(f, timeout: float, want: bytes) -> bytes:
    deadline = time.monotonic() + timeout
    buf = b""
    while want not in buf:
        left = deadline - time.monotonic()
        if left <= 0:
            break
        r, _, _ = select.select([f], [], [], left)
        if not r:
            break
        chunk = os.read(f.fileno(), 4096)
        if not chunk:
            break
        buf += chunk
    return buf


async def subscribe(url: str, seconds: float):
    import logging
    from asyncua import Client, ua
    logging.getLogger("asyncua").setLevel(logging.ERROR)
    lat = []

    class Handler:
        def datachange_notification(self, node, val, data):
            dv = data.monitored_item.Value
            src = dv.SourceTimestamp
            if src is not None and (dv.StatusCode is None or dv.StatusCode.is_good()):
                lat.append((datetime.now(timezone.utc) - src.replace(tzinfo=timezone.utc)).total_seconds())

    async with Client(url) as c:
        ns = await c.get_namespace_index("urn:libdf1:df1opcua")
        sub = await c.create_subscription(ua.CreateSubscriptionParameters(RequestedPublishingInterval=0,
                                                                          RequestedMaxKeepAliveCount=100), Handler())
        await sub.subscribe_data_change(c.get_node("ns=%d;s=bench.station1.T0" % ns), sampling_interval=0)
        await asyncio.sleep(seconds)
    return lat[1:]      # the first is the value as it was at subscription


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--line-baud", type=int, default=0)
    a = ap.parse_args()
    try:
        import asyncua  # noqa: F401
    except ImportError:
        print("bench_opcua: SKIP: no asyncua")
        return 0
    bin_dir = os.environ.get("DF1_BIN") or os.path.join(ROOT, "build", "bin")
    tmp = tempfile.mkdtemp(prefix="df1opcua-bench.")
    procs = []
    try:
        with open(os.path.join(tmp, "map.csv"), "w") as f:
            f.write("Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms\n")
            for i in range(TAGS):
                f.write("T%d,Read,INT,1,SLC,N7:%d,1,0\n" % (i, i))
        log = os.path.join(tmp, "plc.log")
        cmd = [os.path.join(bin_dir, "df1sim"), "--pty", os.path.join(tmp, "plc"), "--ramp", "N7:0@100", "--log", log]
        if a.line_baud:
            cmd += ["--line-baud", str(a.line_baud)]
        sim = subprocess.Popen(cmd, stdout=subprocess.PIPE)
        procs.append(sim)
        dev = wait_line(sim.stdout, 10, b"\n").decode().strip()
        if not dev:
            raise SystemExit("bench_opcua: df1sim did not start")
        port = free_port()
        env = dict(os.environ, PYTHONPATH=HERE + os.pathsep + os.environ.get("PYTHONPATH", ""))
        srv = subprocess.Popen([sys.executable, "-m", "libdf1.opcua", "-d", dev, "--map", os.path.join(tmp, "map.csv"),
                                "--name", "bench", "--listen", str(port), "--pki", os.path.join(tmp, "pki")],
                               stderr=subprocess.PIPE, env=env)
        procs.append(srv)
        if b" tags of " not in wait_line(srv.stderr, 60, b" tags of "):
            raise SystemExit("bench_opcua: df1opcua did not start")
        t0 = time.time()
        lat = asyncio.run(subscribe("opc.tcp://127.0.0.1:%d/" % port, a.seconds))
        t1 = time.time()
        # reads that df1sim answered in the window: the count of each logged read
        stamp = re.compile(r"^(\S+) .*cmd=0F/A2 .*count=(\d+)")
        n = 0
        with open(log) as f:
            for line in f:
                m = stamp.match(line)
                if m:
                    t = datetime.fromisoformat(m.group(1)).timestamp()
                    if t0 <= t <= t1:
                        n += int(m.group(2))
        print("bench_opcua: %d INT tags, every scan, %s pty" % (TAGS, "%d baud" % a.line_baud if a.line_baud
                                                                 else "full-speed"))
        print("  tag reads/s at the PLC (df1sim --log): %.0f" % (n / (t1 - t0)))
        if lat:
            lat.sort()
            print("  subscription latency, read to subscriber: median %.1f ms, 95th %.1f ms, max %.1f ms (%d changes)"
                  % (1000 * statistics.median(lat), 1000 * lat[int(0.95 * (len(lat) - 1))], 1000 * lat[-1], len(lat)))
        else:
            print("  subscription latency: no change arrived")
        return 0
    finally:
        for p in reversed(procs):
            if p.poll() is None:
                p.terminate()
                try:
                    p.wait(15)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait()
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
