#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""page_probe.py - df1gw's status page in a real browser: headless Chromium
driven over the DevTools protocol on a pipe (--remote-debugging-pipe: JSON
messages ended by NUL on descriptors 3 and 4), reading the DOM the page's
script built, as a technician's browser would show it.

  page_probe.py URL --shot FILE.png [--tag NAME=VALUE:QUALITY ...]
                [--markup NAME] [--then NAME=VALUE] [--ready FILE]

Checks: every --tag row shows VALUE and QUALITY; the row of --markup NAME
shows NAME as text (no element made from it, no dialog); the filter input
narrows the rows; then writes "ready" to --ready FILE (the test changes a
value in the PLC) and waits, without reloading, until --then NAME shows
VALUE. A screenshot is kept in --shot. One line per check; exit 1 if any
failed.
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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("url")
    ap.add_argument("--shot", required=True)
    ap.add_argument("--tag", action="append", default=[])
    ap.add_argument("--markup")
    ap.add_argument("--then")
    ap.add_argument("--ready")
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
        shot = b.call("Page.captureScreenshot", {"format": "png"})
        import base64
        with open(a.shot, "wb") as f:
            f.write(base64.b64decode(shot["data"]))
        check(os.path.getsize(a.shot) > 1000, "screenshot kept: %s" % a.shot)
    finally:
        b.close()
    sys.exit(1 if fails else 0)


main()
