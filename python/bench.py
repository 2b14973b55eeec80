#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""Single-word reads per second from Python, next to the C figure for the same df1sim.

    python3 python/bench.py [--reads N] [--line-baud BAUD]

df1sim (DF1_BIN, default the tree's build/bin) on a pty; the library from
LIBDF1_PATH (default the tree's build/). The same df1sim serves both loops:
plc.read("N7:0") from Python, df1_read_int16() from C (python/bench_read.c,
compiled here against the same library). --line-baud paces df1sim's bytes as
a real line (19200: what a MicroLogix runs out of the box).
"""
import argparse
import os
import select
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
if not os.environ.get("LIBDF1_PATH") and os.path.exists(os.path.join(ROOT, "build", "libdf1.so.0")):
    os.environ["LIBDF1_PATH"] = os.path.join(ROOT, "build")


def start_sim(tmp, line_baud):
    bin_dir = os.environ.get("DF1_BIN") or os.path.join(ROOT, "build", "bin")
    cmd = [os.path.join(bin_dir, "df1sim"), "--pty", os.path.join(tmp, "plc")]
    if line_baud:
        cmd += ["--line-baud", str(line_baud)]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE)
    r, _, _ = select.select([p.stdout], [], [], 10)
    line = p.stdout.readline().decode().strip() if r else ""
    if not line:
        p.kill()
        raise SystemExit("bench: df1sim did not start")
    return p, line


def build_c(tmp):
    cc = os.environ.get("CC") or "cc"
    libdir = os.environ["LIBDF1_PATH"]
    libdir = libdir if os.path.isdir(libdir) else os.path.dirname(libdir)
    if shutil.which(cc.split()[0]) is None:
        return None
    exe = os.path.join(tmp, "bench_read")
    cmd = cc.split() + ["-O2", "-std=c11", "-I", os.path.join(ROOT, "include"), "-o", exe,
                        os.path.join(HERE, "bench_read.c"), os.path.join(libdir, "libdf1.so.0"),
                        "-Wl,-rpath," + libdir]
    return exe if subprocess.run(cmd).returncode == 0 else None


def c_round(exe, target, reads):
    out = subprocess.run([exe, target, str(reads)], stdout=subprocess.PIPE, universal_newlines=True).stdout
    return float(out.split(":")[1]) if out.startswith("C reads/s:") else None


def py_round(plc, reads):
    t0 = time.perf_counter()
    for _ in range(reads):
        plc.read("N7:0")
    return reads / (time.perf_counter() - t0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reads", type=int, default=2000)
    ap.add_argument("--line-baud", type=int, default=0)
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    import libdf1
    py, c = [], []
    with tempfile.TemporaryDirectory() as tmp:
        exe = build_c(tmp)
        sim, target = start_sim(tmp, args.line_baud)
        try:
            # rounds in turn, so that the load of a shared machine falls on both alike;
            # one opener at a time (the port is locked while open)
            for _ in range(args.rounds):
                with libdf1.open(target) as plc:
                    plc.read("N7:0")
                    py.append(py_round(plc, args.reads))
                if exe:
                    c.append(c_round(exe, target, args.reads))
        finally:
            sim.terminate()
            sim.wait()
    where = "pty at %d baud" % args.line_baud if args.line_baud else "pty, unpaced"
    print("python bench: single-word reads (N7:0) over a %s, %d rounds of %d, libdf1 %s, Python %s"
          % (where, args.rounds, args.reads, libdf1.library_version(), sys.version.split()[0]))
    print("Python reads/s: %.0f (median)" % statistics.median(py))
    if c and None not in c:
        print("C reads/s:      %.0f (median)" % statistics.median(c))
        print("Python / C:     %.2f" % (statistics.median(py) / statistics.median(c)))
    else:
        print("C reads/s:      not measured (no compiler, or bench_read failed)")

if __name__ == "__main__":
    main()
