#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""page_probe.py - df1gw's status page in a real browser: headless Chromium
driven over the DevTools protocol on a pipe (--remote-debugging-pipe: JSON
messages ended by NUL on descriptors 3 and 4), reading the DOM the page's
script built, as a technician's browser would show it.

  page_probe.py URL --shot FILE.png [--tag NAME=VALUE:QUALITY ...]
                [--markup NAME] [--then NAME=VALUE] [--ready FILE]
                [--reason TEXT] [--charts N [--chart ID:SERIES=CMP ...]]
                [--layout WIDTH=FILE.png ...]

Checks: every --tag row shows VALUE and QUALITY; the row of --markup NAME
shows NAME as text (no element made from it, no dialog); the filter input
narrows the rows; then writes "ready" to --ready FILE (the test changes a
value in the PLC) and waits, without reloading, until --then NAME shows
VALUE. --reason: a tag's reason holding TEXT (markup) is shown as text,
cut to one line with an ellipsis, the whole of it in its title. --charts:
the five charts are SVG elements with a title, a desc, labelled axes with
units, and each --chart's series (e.g. "failures:stn 3=>0", "broker:broker
=up") has N figures or more and its latest one as said (=, >, <), or
none at all ("reply:stn 3=none"). --layout:
at each WIDTH (CSS pixels) no header of any table takes more than one line
or overflows, no word in a header or cell is broken across lines, the tags
table fits its box and its Reason column takes at most 40 % of it; a
screenshot of the whole page at that width in FILE. A screenshot is kept in
--shot. One line per check; exit 1 if any failed.
"""
import argparse
import json
import os
import shutil
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


class Browser:
    def __init__(self):
        exe = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")
        if not exe:
            raise SystemExit("no chromium")
        self.dir = tempfile.mkdtemp()
        r_ours, w_theirs = os.pipe()    # chromium writes on its fd 4
        r_theirs, w_ours = os.pipe()    # and reads on its fd 3
        args = [exe, "--headless", "--disable-gpu", "--remote-debugging-pipe", "--no-first-run",
                "--user-data-dir=" + self.dir, "--window-size=1000,1400", "about:blank"]
        if os.geteuid() == 0:
            args.insert(2, "--no-sandbox")

        def fds():
            os.dup2(r_theirs, 3)
            os.dup2(w_theirs, 4)
        self.p = subprocess.Popen(args, pass_fds=(3, 4), preexec_fn=fds, stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL)
        os.close(r_theirs)
        os.close(w_theirs)
        self.r, self.w = r_ours, w_ours
        self.buf = b""
        self.n = 0
        self.events = []
        self.session = None

    def call(self, method, params=None, session=True):
        self.n += 1
        msg = {"id": self.n, "method": method, "params": params or {}}
        if session and self.session:
            msg["sessionId"] = self.session
        os.write(self.w, json.dumps(msg).encode() + b"\0")
        end = time.monotonic() + 30
        while time.monotonic() < end:
            while b"\0" not in self.buf:
                chunk = os.read(self.r, 65536)
                if not chunk:
                    raise SystemExit("chromium went away")
                self.buf += chunk
            raw, self.buf = self.buf.split(b"\0", 1)
            m = json.loads(raw)
            if m.get("id") == self.n:
                if "error" in m:
                    raise SystemExit("%s: %s" % (method, m["error"]))
                return m.get("result", {})
            self.events.append(m)
        raise SystemExit("%s: no answer" % method)

    def js(self, expr):
        r = self.call("Runtime.evaluate", {"expression": expr, "returnByValue": True})
        return r.get("result", {}).get("value")

    def close(self):
        try:
            self.call("Browser.close", session=False)
        except SystemExit:
            pass
        try:
            self.p.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.p.kill()
        shutil.rmtree(self.dir, ignore_errors=True)


ROWS = """Array.from(document.querySelectorAll('#tags tbody tr')).map(function (tr) {
  var c = tr.cells; return {name: c[0].textContent, value: c[1].textContent, quality: c[2].textContent,
  name_children: c[0].children.length}; })"""


def rows_until(b, pred, seconds):
    end = time.monotonic() + seconds
    rows = []
    while time.monotonic() < end:
        rows = b.js(ROWS) or []
        if pred(rows):
            return rows, True
        time.sleep(0.2)
    return rows, False


# Measured in the page: for each visible header its lines (the distinct tops
# of its text's boxes) and whether its text overflows; for each word of each
# visible header or cell, whether its boxes lie on more than one line (a
# word broken inside).
LAYOUT = """(function () {
  function tops(range) {
    var t = {};
    Array.prototype.forEach.call(range.getClientRects(), function (q) {
      if (q.width > 0 && q.height > 0) t[Math.round(q.top)] = true; });
    return Object.keys(t).length;
  }
  function visible(e) { return e.offsetParent !== null && e.getClientRects().length > 0; }
  var heads = [], broken = [], r = document.createRange();
  document.querySelectorAll('main th').forEach(function (th) {
    if (!visible(th)) return;
    r.selectNodeContents(th);
    var n = tops(r);
    if (n !== 1 || th.scrollWidth > th.clientWidth) heads.push(th.textContent + ' (' + n + ' lines, ' +
      th.scrollWidth + '/' + th.clientWidth + ' px)');
  });
  document.querySelectorAll('main th, main td').forEach(function (c) {
    if (!visible(c)) return;
    var w = document.createTreeWalker(c, NodeFilter.SHOW_TEXT), t, m, re;
    while ((t = w.nextNode())) {
      re = /\\S+/g;
      while ((m = re.exec(t.data))) {
        r.setStart(t, m.index); r.setEnd(t, m.index + m[0].length);
        if (tops(r) > 1) broken.push(m[0]);
      }
    }
  });
  var tags = document.getElementById('tags'), box = tags.parentNode, reason = tags.tHead.rows[0].cells[3];
  return { heads: heads, broken: broken, fits: box.scrollWidth <= box.clientWidth,
           table: tags.offsetWidth, reason: reason.offsetWidth, th: document.querySelectorAll('main th').length,
           height: document.documentElement.scrollHeight };
})()"""

CHARTS = """Array.prototype.map.call(document.querySelectorAll('#charts svg'), function (s) {
  var t = s.querySelector('title'), d = s.querySelector('desc'), ids = (s.getAttribute('aria-labelledby') || '').split(' ');
  return { id: s.getAttribute('data-chart'), points: Number(s.getAttribute('data-points')), role: s.getAttribute('role'),
    title: t ? t.textContent : '', desc: d ? d.textContent : '',
    labelled: ids.length === 2 && ids.every(function (i) { return document.getElementById(i) !== null; }),
    texts: Array.prototype.map.call(s.querySelectorAll('text'), function (x) { return x.textContent; }),
    series: Array.prototype.map.call(s.querySelectorAll('polyline.series'), function (p) {
      return { name: p.getAttribute('data-series'), n: p.points.numberOfItems }; }) };
})"""

UNITS = {"scans": "scans/s", "reply": "ms", "failures": "failures/min", "broker": "link", "backlog": "records"}


def latest(chart, series):
    """The latest figure of SERIES as the chart's desc says it ("NAME: now X, ...")."""
    import re
    m = re.search(r"(?:^|[.;] )%s: now ([^,;.]+(?:\.\d+)?)" % re.escape(series), chart["desc"])
    return m.group(1) if m else None


def chart_ok(charts, spec, want_n):
    cid, rest = spec.split(":", 1)
    for op in ("=>", "=<", "="):
        if op in rest:
            series, value = rest.split(op, 1)
            break
    c = [x for x in charts if x["id"] == cid]
    if not c:
        return False, "no chart " + cid
    n = sum(s["n"] for s in c[0]["series"] if s["name"] == series)
    v = latest(c[0], series)
    if value == "none":         # a series without a figure (a station that never answered)
        return n == 0 and v is None and (series + ": no figure yet") in c[0]["desc"], \
            "%s: %s without a figure (%d)" % (cid, series, n)
    if n < want_n or v is None:
        return False, "%s: %s has %d figures (latest %s)" % (cid, series, n, v)
    if op == "=":
        ok = v == value
    else:
        try:
            ok = float(v) > float(value) if op == "=>" else float(v) < float(value)
        except ValueError:
            ok = False
    return ok, "%s: %s latest %s (want %s%s), %d figures" % (cid, series, v, op[-1] if op != "=" else "", value, n)


def layout(b, width, shot):
    b.call("Emulation.setDeviceMetricsOverride", {"width": width, "height": 900, "deviceScaleFactor": 1,
                                                    "mobile": False})
    m = b.js(LAYOUT)
    check(m is not None and m["th"] > 0 and not m["heads"],
          "%d px: every header on one line, none overflowing %s" % (width, json.dumps(m and m["heads"])))
    check(m is not None and not m["broken"], "%d px: no word broken inside %s" % (width, json.dumps(m and m["broken"])))
    check(m is not None and m["fits"], "%d px: the tags table fits its box" % width)
    check(m is not None and 0 < m["reason"] <= 0.4 * m["table"],
          "%d px: the Reason column %s px of the table's %s px" % (width, m and m["reason"], m and m["table"]))
    height = min(max(int(m["height"]) if m else 900, 600), 8000)
    b.call("Emulation.setDeviceMetricsOverride", {"width": width, "height": height, "deviceScaleFactor": 1,
                                                    "mobile": False})
    shoot(b, shot)
    b.call("Emulation.clearDeviceMetricsOverride")


def shoot(b, path):
    import base64
    shot = b.call("Page.captureScreenshot", {"format": "png"})
    with open(path, "wb") as f:
        f.write(base64.b64decode(shot["data"]))
    check(os.path.getsize(path) > 1000, "screenshot kept: %s" % path)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("url")
    ap.add_argument("--shot", required=True)
    ap.add_argument("--tag", action="append", default=[])
    ap.add_argument("--markup")
    ap.add_argument("--then")
    ap.add_argument("--ready")
    ap.add_argument("--reason")
    ap.add_argument("--charts", type=int, default=0)
    ap.add_argument("--chart", action="append", default=[])
    ap.add_argument("--layout", action="append", default=[])
    a = ap.parse_args()
    b = Browser()
    try:
        t = b.call("Target.createTarget", {"url": "about:blank"}, session=False)
        s = b.call("Target.attachToTarget", {"targetId": t["targetId"], "flatten": True}, session=False)
        b.session = s["sessionId"]
        b.call("Page.enable")
        b.call("Runtime.enable")
        b.call("Page.navigate", {"url": a.url})
        want = {}
        for spec in a.tag:
            name, rest = spec.rsplit("=", 1)       # a name may hold '=', a value not
            value, quality = rest.rsplit(":", 1)
            want[name] = (value, quality)
        rows, ok = rows_until(b, lambda r: len(r) > 0 and all(
            any(x["name"] == n and x["value"] == v and x["quality"] == q for x in r)
            for n, (v, q) in want.items()), 20)
        check(ok, "tag rows with their values and qualities: %s" % json.dumps(rows))
        b.js("window.__df1probe = 'no reload'")
        if a.markup:
            hit = [x for x in rows if x["name"] == a.markup]
            check(len(hit) == 1 and hit[0]["name_children"] == 0, "a name with markup is shown as text")
            check(b.js("document.querySelectorAll('main img, main b, main script').length") == 0,
                  "no element made from a tag name")
            check(not any(e.get("method") == "Page.javascriptDialogOpening" for e in b.events),
                  "no script of a tag name ran")
        if want:
            first = sorted(want)[0]
            n = b.js("(function(){var f=document.getElementById('filter'); f.value=%s;"
                     "f.dispatchEvent(new Event('input')); return document.querySelectorAll("
                     "'#tags tbody tr').length;})()" % json.dumps(first))
            check(n is not None and 1 <= n < len(rows), "the filter narrows the rows (%s of %d)" % (n, len(rows)))
            b.js("(function(){var f=document.getElementById('filter'); f.value='';"
                 "f.dispatchEvent(new Event('input'));})()")
        if a.then:
            name, value = a.then.rsplit("=", 1)
            if a.ready:
                with open(a.ready, "w") as f:
                    f.write("ready\n")
            rows, ok = rows_until(b, lambda r: any(x["name"] == name and x["value"] == value for x in r), 30)
            check(ok, "%s shows %s without a reload" % (name, value))
            check(b.js("window.__df1probe") == "no reload", "the page was not reloaded")
        if a.reason:
            rr = b.js("""Array.prototype.map.call(document.querySelectorAll('#tags tbody td.reason'), function (td) {
              var sp = td.querySelector('span.clip');
              return { text: td.textContent, children: sp ? sp.children.length : -1, title: sp ? sp.title : '',
                       cut: sp ? sp.scrollWidth > sp.clientWidth : false,
                       oneline: sp ? sp.offsetHeight < 2 * parseFloat(getComputedStyle(sp).fontSize) : false }; })""") or []
            hit = [x for x in rr if a.reason in x["text"]]
            check(len(hit) > 0 and all(x["children"] == 0 for x in hit),
                  "a reason with markup shown as text: %s" % json.dumps(hit[:1]))
            check(b.js("document.querySelectorAll('main i, main img, main b, main script').length") == 0,
                  "no element made from a reason")
            check(len(hit) > 0 and all(x["title"] == x["text"] for x in hit), "the reason's whole text in its title")
            check(len(hit) > 0 and all(x["cut"] and x["oneline"] for x in hit),
                  "a long reason cut to one line (ellipsis)")
        if a.charts:
            end = time.monotonic() + 30 + 3 * a.charts
            while True:
                charts = b.js(CHARTS) or []
                res = [chart_ok(charts, spec, a.charts) for spec in a.chart]
                if all(ok for ok, _ in res) or time.monotonic() > end:
                    break
                time.sleep(0.5)
            ids = sorted(c["id"] for c in charts)
            check(ids == sorted(UNITS), "the charts as SVG: %s" % ids)
            for c in charts:
                check(c["role"] == "img" and c["labelled"] and c["title"] and c["desc"],
                      "chart %s: role img, a title and a desc (%s)" % (c["id"], c["desc"]))
                unit = UNITS.get(c["id"], "?")
                check(unit in c["texts"] and ("seconds ago" in c["texts"] or "minutes ago" in c["texts"]),
                      "chart %s: axes labelled (%s, time ago)" % (c["id"], unit))
            for ok, what in res:
                check(ok, "chart " + what)
        shoot(b, a.shot)
        for spec in a.layout:
            width, path = spec.split("=", 1)
            layout(b, int(width), path)
    finally:
        b.close()
    sys.exit(1 if fails else 0)


main()
