#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
# sfwd_check.py - what a subscriber recorded (mosquitto_sub -v: "TOPIC PAYLOAD"
# a line) checked against df1gw's store and forward rules (df1gw(1), STORE AND
# FORWARD), for tests/integration/it_df1gw_buffer.sh. The expectations come
# from the ramp (df1sim --ramp N7:0,1: every read is the last value plus the
# steps due, never less) and the man page, not from df1gw's own output.
#   ramp FILE TOPIC MAXGAP        the messages of TOPIC: historical ones in seq
#                                 order with their read times, a duplicate the
#                                 same seq, value and read time; values never
#                                 going back (historical among themselves, and
#                                 the current ones after the replay); no step
#                                 over MAXGAP; prints "historical N first F last L"
#   seqs FILE PREFIX              the distinct seqs of historical messages under
#                                 PREFIX: "count N min A max B contiguous yes|no"
#   last FILE TOPIC               the value of TOPIC's last current (not
#                                 historical) message
#   before FILE TOPIC MS          how many historical messages of TOPIC were
#                                 read before MS (ms since the epoch)
#   spb FILE MIN                  a recording of tests/support/spb_host.py: every
#                                 historical DDATA in a session (after an NBIRTH,
#                                 no NDEATH since) after its device's DBIRTH, its
#                                 values in order with their read times, and at
#                                 least MIN of them after the last NBIRTH
import calendar
import json
import sys
import time


def records(path, prefix=None, topic=None):
    out = []
    for line in open(path, encoding="utf-8", errors="replace"):
        t, _, p = line.rstrip("\n").partition(" ")
        if topic and t != topic:
            continue
        if prefix and not t.startswith(prefix + "/"):
            continue
        try:
            j = json.loads(p)
        except ValueError:
            continue
        if isinstance(j, dict):
            out.append((t, j))
    return out


def ms_of(ts):
    """RFC 3339 with milliseconds, UTC ("2026-12-04T10:10:02.273Z") to ms."""
    base, frac = ts.rstrip("Z").split(".")
    return calendar.timegm(time.strptime(base, "%Y-%m-%dT%H:%M:%S")) * 1000 + int(frac)


def ramp(path, topic, maxgap):
    fails = []
    hist, seen, current = [], {}, []
    after_hist = False
    for _, j in records(path, topic=topic):
        if j.get("historical") is True:
            after_hist = True
            s = j.get("seq")
            if not isinstance(s, int) or "read" not in j or "ts" not in j:
                fails.append("historical without seq, read or ts: %r" % j)
                continue
            if s in seen:
                if seen[s] != (j["value"], j["read"]):
                    fails.append("duplicate seq %d differs: %r vs %r" % (s, seen[s], (j["value"], j["read"])))
                continue
            seen[s] = (j["value"], j["read"])
            hist.append((s, j["value"], ms_of(j["read"])))
        elif after_hist and isinstance(j.get("value"), int):
            current.append(j["value"])
    for a, b in zip(hist, hist[1:]):
        if b[0] <= a[0]:
            fails.append("seq %d after %d" % (b[0], a[0]))
        if b[1] < a[1]:
            fails.append("value %d (seq %d) after %d (seq %d)" % (b[1], b[0], a[1], a[0]))
        if b[2] < a[2]:
            fails.append("read time of seq %d before seq %d's" % (b[0], a[0]))
        if b[1] - a[1] > maxgap:
            fails.append("a step of %d between seq %d and %d" % (b[1] - a[1], a[0], b[0]))
    for a, b in zip(current, current[1:]):
        if b < a:
            fails.append("current value %d after %d" % (b, a))
    if hist and current and current[0] < hist[-1][1]:
        fails.append("the current value %d after the replay is older than the last historical %d"
                     % (current[0], hist[-1][1]))
    if hist and current and current[0] - hist[-1][1] > maxgap:
        fails.append("a step of %d from the replay to the current value" % (current[0] - hist[-1][1]))
    for f in fails[:10]:
        print("FAIL:", f)
    print("historical %d first %s last %s" % (len(hist), hist[0][1] if hist else "-", hist[-1][1] if hist else "-"))
    return 1 if fails else 0


def seqs(path, prefix):
    s = sorted({j["seq"] for _, j in records(path, prefix=prefix) if j.get("historical") is True})
    contiguous = "yes" if s and s[-1] - s[0] + 1 == len(s) else "no"
    print("count %d min %d max %d contiguous %s" % (len(s), s[0] if s else 0, s[-1] if s else 0, contiguous))
    return 0


def last(path, topic):
    cur = [j for _, j in records(path, topic=topic) if j.get("historical") is not True]
    print(cur[-1].get("value") if cur else "")
    return 0


def before(path, topic, ms):
    n = len({j["seq"] for _, j in records(path, topic=topic)
             if j.get("historical") is True and ms_of(j["read"]) < int(ms)})
    print(n)
    return 0


def spb(path, least):
    recs = [json.loads(x) for x in open(path, encoding="utf-8") if x.strip()]
    fails, born, dev, values, after_last = [], False, set(), [], 0
    for r in recs:
        t = r.get("type")
        if t == "NBIRTH":
            born, dev, after_last = True, set(), 0
        elif t == "NDEATH":
            born = False
        elif t == "DBIRTH":
            dev.add(r.get("device"))
        elif t == "DDATA":
            ms = r.get("metrics", [])
            hist = [m for m in ms if m.get("is_historical")]
            if not hist:
                continue
            if len(hist) != len(ms):
                fails.append("a DDATA with historical and current metrics")
            if not born or r.get("device") not in dev:
                fails.append("a historical DDATA outside a session or before its DBIRTH")
            for m in hist:
                if not m.get("timestamp"):
                    fails.append("a historical metric without its read time")
                values.append((m.get("timestamp"), m.get("value")))
            after_last += 1
    for a, b in zip(values, values[1:]):
        if b[1] < a[1] or b[0] < a[0]:
            fails.append("historical %r after %r" % (b, a))
    if after_last < least:
        fails.append("%d historical DDATA after the last NBIRTH, fewer than %d" % (after_last, least))
    for f in fails[:10]:
        print("FAIL:", f)
    print("historical DDATA %d, %d after the last NBIRTH" % (len(values), after_last))
    return 1 if fails else 0


def main(argv):
    if len(argv) >= 4 and argv[1] == "spb":
        return spb(argv[2], int(argv[3]))
    if len(argv) >= 5 and argv[1] == "ramp":
        return ramp(argv[2], argv[3], int(argv[4]))
    if len(argv) >= 4 and argv[1] == "seqs":
        return seqs(argv[2], argv[3])
    if len(argv) >= 4 and argv[1] == "last":
        return last(argv[2], argv[3])
    if len(argv) >= 5 and argv[1] == "before":
        return before(argv[2], argv[3], argv[4])
    print(__doc__ or "usage: see the file's opening comment", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
