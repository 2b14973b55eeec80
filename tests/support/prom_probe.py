#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""prom_probe.py - reads a Prometheus text exposition (an http:// URL, a
file, or - for stdin) with prometheus_client's own parser (from PyPI: an
independent reader of the format), checks the conventions df1gw(1) and
df1mon(1) promise, and answers queries.

  prom_probe.py SOURCE [--lint] [QUERY...]

--lint: every family df1_-prefixed and typed; counters' samples end in
_total; histogram buckets grow with le and +Inf equals _count. With a URL,
the Content-Type must be text/plain; version=0.0.4.

A QUERY is SAMPLE or SAMPLE{label=value,...}: its value is printed on a line
of its own ("none" when there is no such sample; "many" when the labels
given match more than one). Exit 1 on a parse error or a lint failure.
"""
import math
import re
import sys
import urllib.request

from prometheus_client.parser import text_string_to_metric_families


def load(src):
    if src.startswith("http://"):
        with urllib.request.urlopen(src, timeout=20) as r:
            ctype = r.headers.get("Content-Type", "")
            return r.read().decode("utf-8"), ctype
    if src == "-":
        return sys.stdin.read(), None
    with open(src, encoding="utf-8") as f:
        return f.read(), None


def lint(families, ctype):
    bad = []
    if ctype is not None and not re.match(r"text/plain;\s*version=0\.0\.4", ctype):
        bad.append("Content-Type %r" % ctype)
    for fam in families:
        if not fam.name.startswith("df1_"):
            bad.append("%s: not df1_-prefixed" % fam.name)
        if fam.type not in ("counter", "gauge", "histogram", "info"):
            bad.append("%s: type %s" % (fam.name, fam.type))
        for s in fam.samples:
            if fam.type == "counter" and not s.name.endswith(("_total", "_created")):
                bad.append("%s: counter sample %s without _total" % (fam.name, s.name))
        if fam.type == "histogram":
            buckets = [(float(s.labels["le"]), s.value) for s in fam.samples if s.name.endswith("_bucket")]
            count = [s.value for s in fam.samples if s.name.endswith("_count")]
            vals = [v for le, v in sorted(buckets)]
            if vals != sorted(vals):
                bad.append("%s: buckets do not grow" % fam.name)
            if not buckets or buckets[-1][0] != float("inf") or not count or buckets[-1][1] != count[0]:
                bad.append("%s: +Inf bucket is not _count" % fam.name)
    return bad


def query(families, q):
    m = re.match(r"^([a-zA-Z_:][a-zA-Z0-9_:]*)(?:\{(.*)\})?$", q)
    if not m:
        return "bad query"
    want = dict(kv.split("=", 1) for kv in m.group(2).split(",")) if m.group(2) else {}
    hits = [s.value for fam in families for s in fam.samples
            if s.name == m.group(1) and all(s.labels.get(k) == v for k, v in want.items())]
    if not hits:
        return "none"
    if len(hits) > 1:
        return "many"
    v = hits[0]
    if math.isnan(v) or math.isinf(v):
        return "NaN" if math.isnan(v) else ("+Inf" if v > 0 else "-Inf")
    return str(int(v)) if v == int(v) else repr(v)


def main():
    args = sys.argv[1:]
    if not args:
        sys.exit(__doc__)
    text, ctype = load(args[0])
    try:
        families = list(text_string_to_metric_families(text))
    except Exception as e:      # the parser's own verdict
        print("parse error: %s" % e, file=sys.stderr)
        sys.exit(1)
    rc = 0
    for q in args[1:]:
        if q == "--lint":
            for b in lint(families, ctype):
                print("lint: " + b, file=sys.stderr)
                rc = 1
            continue
        print(query(families, q))
    sys.exit(rc)


main()
