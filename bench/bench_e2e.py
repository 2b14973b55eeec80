#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
# bench_e2e.py - df1gw's publications end to end, through a real broker (run
# by bench/bench_gw.sh, `make bench`): rounds in which every one of 1000 tags
# changes in df1sim (df1write over df1sim's EtherNet/IP side writes N10:0..999
# while df1gw reads them over the pty), each round waited for until the 1000
# messages it makes arrived at this subscriber. Reported: messages per second
# received, bytes per update (topic + payload, as the broker carries them) and
# df1gw's CPU per round (/proc/PID/stat). A benchmark reports; it asserts nothing.
#
# usage: bench_e2e.py LABEL MQTT_PORT TOPIC_FILTER READY_TOPIC GW_PID DF1WRITE EIP_ADDR ROUNDS
#   READY_TOPIC: a message on it (a DBIRTH, the last tag's first value) says df1gw is ready
import os
import subprocess
import sys
import threading
import time

import paho.mqtt.client as mqtt

NTAGS = 1000


def cpu_ms(pid):
    with open("/proc/%s/stat" % pid) as f:
        v = f.read().rsplit(")", 1)[1].split()
    return (int(v[11]) + int(v[12])) * 1000 / os.sysconf("SC_CLK_TCK")


def main():
    label, port, filt, ready, pid, df1write, eip, rounds = sys.argv[1:9]
    rounds = int(rounds)
    lock = threading.Condition()
    st = {"n": 0, "bytes": 0, "ready": False}

    def on_message(c, u, msg):
        with lock:
            if mqtt.topic_matches_sub(ready, msg.topic):
                st["ready"] = True
            if mqtt.topic_matches_sub(filt, msg.topic):
                st["n"] += 1
                st["bytes"] += len(msg.topic) + len(msg.payload)
            lock.notify_all()

    c = mqtt.Client(client_id="", clean_session=True)
    c.on_message = on_message
    c.connect("127.0.0.1", int(port), 30)
    c.subscribe([(filt, 0), (ready, 0)])
    c.loop_start()

    def wait(cond, secs):
        end = time.monotonic() + secs
        with lock:
            while not cond():
                left = end - time.monotonic()
                if left <= 0:
                    return False
                lock.wait(left)
        return True

    if not wait(lambda: st["ready"], 20):
        print("bench_e2e: %s: df1gw not ready, skipped" % label)
        return
    # quiet: the first publication of every tag (JSON) is over
    last = -1
    while last != st["n"]:
        last = st["n"]
        time.sleep(0.5)
    with lock:
        base_n, base_b = st["n"], st["bytes"]
    c0, t0 = cpu_ms(pid), time.monotonic()
    done = 0
    for r in range(1, rounds + 1):
        vals = ",".join(str((r * 7 + i) % 30000) for i in range(NTAGS))
        subprocess.run([df1write, "-d", "eip://" + eip, "-q", "N10:0=" + vals], check=True)
        if not wait(lambda: st["n"] - base_n >= r * NTAGS, 20):
            print("bench_e2e: %s: round %d incomplete (%d of %d messages)" % (label, r, st["n"] - base_n,
                                                                              r * NTAGS))
            break
        done = r
    el, c1 = time.monotonic() - t0, cpu_ms(pid)
    with lock:
        n, b = st["n"] - base_n, st["bytes"] - base_b
    c.loop_stop()
    if not done:
        return
    print("bench_e2e: %-9s %d rounds of 1000 changes in %.2f s: %.0f messages/s received, "
          "%.1f bytes per update (topic + payload), df1gw CPU %.1f ms per round of 1000 updates"
          % (label, done, el, n / el, b / n if n else 0, (c1 - c0) / done))


if __name__ == "__main__":
    main()
