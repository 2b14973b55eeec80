#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""http_flood.py - a request flood against df1gw --http: N GET requests of
PATH over THREADS connections at once, while SLOW clients trickle a request
one byte at a time and others never read their answer.

  http_flood.py HOST:PORT N THREADS SLOW [PATH [HOLD]]

The slow clients stay at least HOLD seconds (default 0) in all.

Prints "ok N" (answers with status 200) and "failed N"; exit 0 when every
request was answered with 200.
"""
import socket
import sys
import threading
import time
import http.client


def slow_client(addr, stop):
    """Sends its request a byte every 0.2 s (and never finishes it)."""
    try:
        s = socket.create_connection(addr, timeout=5)
        for ch in b"GET /metrics HTTP/1.1\r\nHost: x\r\nX-Slow: " + b"a" * 1000:
            if stop.is_set():
                break
            s.send(bytes([ch]))
            time.sleep(0.2)
        s.close()
    except OSError:
        pass


def no_reader(addr, stop):
    """Asks for the page again and again and never reads the answers."""
    try:
        s = socket.create_connection(addr, timeout=5)
        s.send(b"GET /api/status HTTP/1.1\r\nHost: x\r\n\r\n" * 20)
        stop.wait(30)
        s.close()
    except OSError:
        pass


def main():
    host, port = sys.argv[1].rsplit(":", 1)
    addr = (host, int(port))
    n, threads, slow = int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
    path = sys.argv[5] if len(sys.argv) > 5 else "/metrics"
    hold = float(sys.argv[6]) if len(sys.argv) > 6 else 0.0
    start = time.monotonic()
    stop = threading.Event()
    side = [threading.Thread(target=slow_client if i % 2 == 0 else no_reader, args=(addr, stop))
            for i in range(slow)]
    for t in side:
        t.start()
    lock = threading.Lock()
    count = {"ok": 0, "failed": 0, "next": 0}

    def worker():
        while True:
            with lock:
                if count["next"] >= n:
                    return
                count["next"] += 1
            try:
                c = http.client.HTTPConnection(host, int(port), timeout=20)
                c.request("GET", path)
                r = c.getresponse()
                r.read()
                good = r.status == 200
                c.close()
            except OSError:
                good = False
            with lock:
                count["ok" if good else "failed"] += 1

    ws = [threading.Thread(target=worker) for _ in range(threads)]
    for t in ws:
        t.start()
    for t in ws:
        t.join()
    if time.monotonic() - start < hold:
        stop.wait(hold - (time.monotonic() - start))
    stop.set()
    for t in side:
        t.join()
    print("ok %d" % count["ok"])
    print("failed %d" % count["failed"])
    sys.exit(0 if count["failed"] == 0 and count["ok"] == n else 1)


main()
