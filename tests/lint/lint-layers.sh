#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# tests/lint/lint-layers.sh - which lib/ or tools/ source calls (or references) what
# another source defines, read from the objects' symbol tables (nm), and
# whether any files or layer folders call each other in a loop, or any lib/ or
# tools/ headers include each other in a loop. Run after `make`; B=build by
# default. Prints "A.c -> B.c" edges with -v, the layer edges, then the cycles
# found (none: "no cycles"); exits 1 on a cycle. `make check` runs it.
B=${B:-build}
VERBOSE=0
[ "${1:-}" = "-v" ] && VERBOSE=1
cd "$(dirname "$0")/../.." || exit 2
python3 - "$B" "$VERBOSE" <<'PY'
import subprocess, sys, glob, os
b, verbose = sys.argv[1], sys.argv[2] == "1"
objs = sorted(o for o in glob.glob(b + "/lib/**/*.o", recursive=True) + glob.glob(b + "/tools/**/*.o", recursive=True)
              if os.path.exists(os.path.relpath(o, b)[:-2] + ".c"))  # not stale ones
if not objs:
    sys.exit("no objects under %s/lib: run make first" % b)
defs, uses = {}, {}
for o in objs:
    src = os.path.relpath(o, b)[:-2] + ".c"
    uses[src] = set()
    for line in subprocess.run(["nm", o], capture_output=True, text=True).stdout.splitlines():
        f = line.split()
        if len(f) == 2 and f[0] == "U":
            uses[src].add(f[1])
        elif len(f) == 3 and f[1] in "TDRB":
            defs[f[2]] = src
edges = {s: sorted({defs[u] for u in us if u in defs and defs[u] != s}) for s, us in uses.items()}
for s in sorted(edges):
    for d in edges[s] if verbose else ():
        print("%s -> %s" % (s, d))
def cycles(g):
    found, state = [], {}
    def dfs(n, path):
        state[n] = 1
        path.append(n)
        for m in g.get(n, ()):
            if state.get(m) == 1:
                found.append(path[path.index(m):] + [m])
            elif not state.get(m):
                dfs(m, path)
        path.pop()
        state[n] = 2
    for n in sorted(g):
        if not state.get(n):
            dfs(n, [])
    return found
def layer(s):
    d = os.path.dirname(s)
    return d if d != "lib" else "lib (top)"
lg = {}
for s, ds in edges.items():
    for d in ds:
        if layer(s) != layer(d):
            lg.setdefault(layer(s), set()).add(layer(d))
import re
hdrs = {os.path.relpath(h, h.split("/")[0]): h for h in glob.glob("lib/**/*.h", recursive=True) + glob.glob("tools/**/*.h", recursive=True)}
hg = {}
for n, h in hdrs.items():
    with open(h) as f:
        hg[h] = sorted(hdrs[m] for m in re.findall(r'^#include "([^"]+)"', f.read(), re.M) if m in hdrs)
fc, lc = cycles(edges), cycles({k: sorted(v) for k, v in lg.items()})
fc += [["(include)"] + c for c in cycles(hg)]
for k, v in sorted(lg.items()):
    print("layer %s -> %s" % (k, ", ".join(sorted(v))))
for c in fc:
    print("file cycle: " + " -> ".join(c))
for c in lc:
    print("layer cycle: " + " -> ".join(c))
if not fc and not lc:
    print("no cycles")
sys.exit(1 if fc or lc else 0)
PY
