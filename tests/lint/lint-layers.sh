#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# tests/lint/lint-layers.sh - the layers of doc/ARCHITECTURE.md 2, checked on
# files and on folders. Run after `make` (B=build by default); `make lint-code`
# runs it. Which source calls (or references) what another defines is read from
# the objects' symbol tables (nm); includes from the sources. Errors (exit 1):
#   - a cycle: files, layer folders, or lib/ or tools/ headers that call or
#     include each other in a loop (a call to a static inline function of X.h
#     counts as a call to X.c: nm cannot see it, the sources' text is read);
#   - an include that is not a path from its root: every #include "..." in
#     lib/ names a file relative to lib/, in tools/ one relative to tools/
#     (the public df1.h, df1_catalog.h, df1_eip.h, df1_probe.h, df1_server.h excepted); a bare name found
#     only beside the file is refused, and so is any lib/ header in tools/;
#   - an upward edge between lib/ wings: WINGS below lists them bottom first,
#     and a wing may call or include only wings below it. The top of lib/ (the
#     hub: handle.c, scheme.c, df1_int.h) is outside the order: it may call
#     any wing and any wing may call it, but never both ways for one wing (that
#     is a layer cycle). A new wing goes into WINGS, or the lint fails.
# Prints "A.c -> B.c" edges with -v, the order, the layer edges, then the
# problems found (none: "no cycles" and "layers: in order").
B=${B:-build}
VERBOSE=0
[ "${1:-}" = "-v" ] && VERBOSE=1
cd "$(dirname "$0")/../.." || exit 2
python3 - "$B" "$VERBOSE" <<'PY'
import subprocess, sys, glob, os
# lib/'s wings, bottom first (doc/ARCHITECTURE.md 2.1)
WINGS = ["proto", "base", "port", "link", "eip", "client", "table", "server", "config", "poll"]
PUBLIC = {"df1.h", "df1_catalog.h", "df1_eip.h", "df1_probe.h", "df1_server.h"}
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
# a static inline function of a header leaves no symbol for nm: a call to it is
# a call to the header's own .c (X.h -> X.c), read from the sources' text
import re
inl = {}
for h in glob.glob("lib/**/*.h", recursive=True) + glob.glob("tools/**/*.h", recursive=True):
    c = h[:-2] + ".c"
    if not os.path.isfile(c):
        continue
    with open(h) as f:
        for name in re.findall(r'^static\s+inline\b[^;{(]*?\b(\w+)\s*\(', f.read(), re.M):
            inl[name] = c
if inl:
    called = re.compile(r'\b(' + "|".join(sorted(inl)) + r')\s*\(')
    for s in list(edges):
        with open(s) as f:
            text = re.sub(r'/\*.*?\*/|//[^\n]*', ' ', f.read(), flags=re.S)
        more = {inl[n] for n in called.findall(text) if inl[n] != s and inl[n] in edges}
        edges[s] = sorted(set(edges[s]) | more)
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
problems = []
# every quoted include is a path from its root (lib/ or tools/), or public
incs = {}
for src in sorted(glob.glob("lib/**/*.[ch]", recursive=True) + glob.glob("tools/**/*.[ch]", recursive=True)):
    root = src.split("/")[0]
    incs[src] = []
    with open(src) as f:
        for m in re.findall(r'^\s*#\s*include\s+"([^"]+)"', f.read(), re.M):
            if m in PUBLIC:
                continue
            if not os.path.isfile(os.path.join(root, m)):
                why = "a lib/ header in tools/" if root == "tools" and os.path.isfile(os.path.join("lib", m)) \
                    else "not a path from %s/" % root
                problems.append('include: %s: "%s" is %s' % (src, m, why))
            else:
                incs[src].append(os.path.join(root, m))
# lib/'s wings: only downward edges (calls and includes); the top is the hub
def wing(path):
    parts = path.split("/")
    return parts[1] if parts[0] == "lib" and len(parts) > 2 else None
for w in sorted({wing(x) for x in list(edges) + list(incs)} - {None}):
    if w not in WINGS:
        problems.append("wing: lib/%s is not in WINGS (tests/lint/lint-layers.sh): put it in the order" % w)
rank = {w: i for i, w in enumerate(WINGS)}
def upward(kind, s, d):
    a, b = wing(s), wing(d)
    if a in rank and b in rank and rank[b] > rank[a]:
        problems.append("upward %s: %s -> %s (lib/%s is above lib/%s)" % (kind, s, d, b, a))
for s_, ds in sorted(edges.items()):
    for d in ds:
        upward("call", s_, d)
for s_, ds in sorted(incs.items()):
    for d in ds:
        upward("include", s_, d)
print("wings, bottom first: " + " < ".join(WINGS) + " (the top of lib/ is the hub)")
for k, v in sorted(lg.items()):
    print("layer %s -> %s" % (k, ", ".join(sorted(v))))
for c in fc:
    print("file cycle: " + " -> ".join(c))
for c in lc:
    print("layer cycle: " + " -> ".join(c))
for p in problems:
    print(p)
if not fc and not lc:
    print("no cycles")
if not problems:
    print("layers: in order; includes: paths from lib/ or tools/")
sys.exit(1 if fc or lc or problems else 0)
PY
