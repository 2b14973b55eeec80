#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""Parse InfluxDB line protocol (as the InfluxDB reference describes it) into
JSON, one object per line: {"measurement", "tags": {}, "fields": {}, "ts"}.
Field values keep their type: 12i -> int, 1.5 -> float, true -> bool,
"text" -> str. Exits 1 naming the line on any syntax error. Used by the tests
to read df1mon -f influx output without trusting the writer's code."""
import json
import sys


def split_unescaped(s, sep, quotes=False):
    """Split s on sep where sep is not backslash-escaped (nor inside a quoted
    string when quotes is set)."""
    out, cur, i, inq = [], "", 0, False
    while i < len(s):
        c = s[i]
        if c == "\\" and i + 1 < len(s):
            cur += c + s[i + 1]
            i += 2
            continue
        if quotes and c == '"':
            inq = not inq
        if c == sep and not inq:
            out.append(cur)
            cur = ""
        else:
            cur += c
        i += 1
    if inq:
        raise ValueError("unterminated string")
    out.append(cur)
    return out


def unescape(s):
    out, i = "", 0
    while i < len(s):
        if s[i] == "\\" and i + 1 < len(s) and s[i + 1] in ",= \\\"":
            out += s[i + 1]
            i += 2
        else:
            out += s[i]
            i += 1
    return out


def field_value(v):
    if v.startswith('"'):
        if not v.endswith('"') or len(v) < 2:
            raise ValueError("bad string " + v)
        return unescape(v[1:-1])
    if v in ("true", "t", "T", "True", "TRUE"):
        return True
    if v in ("false", "f", "F", "False", "FALSE"):
        return False
    if v.endswith("i"):
        return int(v[:-1])
    return float(v)


def parse(line):
    parts = split_unescaped(line, " ", quotes=True)
    if len(parts) not in (2, 3):
        raise ValueError("expected 2 or 3 space-separated sections, got %d" % len(parts))
    head = split_unescaped(parts[0], ",")
    tags = {}
    for t in head[1:]:
        kv = split_unescaped(t, "=")
        if len(kv) != 2 or not kv[0] or not kv[1]:
            raise ValueError("bad tag " + t)
        tags[unescape(kv[0])] = unescape(kv[1])
    fields = {}
    for fv in split_unescaped(parts[1], ",", quotes=True):
        kv = split_unescaped(fv, "=", quotes=True)
        if len(kv) != 2 or not kv[0]:
            raise ValueError("bad field " + fv)
        fields[unescape(kv[0])] = field_value(kv[1])
    if not fields:
        raise ValueError("no field")
    ts = int(parts[2]) if len(parts) == 3 else None
    return {"measurement": unescape(head[0]), "tags": tags, "fields": fields, "ts": ts}


def main():
    n = 0
    for line in sys.stdin:
        n += 1
        line = line.rstrip("\n")
        if not line or line.startswith("#"):
            continue
        try:
            print(json.dumps(parse(line), sort_keys=True))
        except ValueError as e:
            print("line %d: %s: %s" % (n, e, line), file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
