#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""radio_channel - one radio channel for the tests: N pseudo-terminals, one a
node, joined so that what a node transmits reaches the nodes in its range
(never the sender itself). Ranges make chains (1-2-3-4: 1 hears only 2) and
parallel relays, the layouts where DF1 radio modem nodes store and forward
each other's packets. Python 3 standard library only.

    radio_channel.py --prefix PREFIX --node NAME [--node NAME...]
                     [--link A-B[-C...]]... [--hears A:B[,C...]]...
                     [--baud N] [--keyup-ms MS] [--gap-chars N]
                     [--collide] [--log FILE]

  --node NAME     a node (letters, digits, _ and .; NAME,NAME... for several):
                  its pty's device is linked as PREFIX.NAME
  --link A-B-C    A and B hear each other, B and C hear each other (a chain)
  --hears A:B,C   A hears B and C (one way: B and C do not hear A by this)
                  without any --link or --hears every node hears every other
  --baud N        the channel's rate: a byte is on the air 10 bits, 10/N s
                  (default 9600; 0: no pacing, a transmission's bytes at once)
  --keyup-ms MS   a transmission goes on the air MS ms after its sender's
                  first byte (default 0)
  --gap-chars N   a transmission ends when the sender has nothing more on the
                  air for N character times (default 2); its next byte keys
                  up again
  --collide       transmissions overlapping at a receiver garble each other
                  there: each byte that reaches it while another transmission
                  in its range is on the air arrives XORed with 5Ah. Without
                  it (the default) a receiving radio buffers: a transmission
                  that begins while another is arriving follows it whole
  --log FILE      one line per transmission, written when it ends:
                    START END SENDER > RECEIVER[,RECEIVER...] HEX... [garbled:R,...]
                  START = the sender's first byte, END = its last byte off the
                  air, in seconds since the channel started (6 decimals);
                  receivers "-" when nobody is in range; HEX = the bytes,
                  two lowercase digits each, space-separated

On stdout, once every pty is there: one line "NAME DEVICE" per node, then
"ready". Runs until SIGTERM or SIGINT, then writes the transmissions on the
air (as ended there), removes its links and exits 0; on stderr, the bytes a
node's pty had no room for (nobody reading it), if any. Exit status 2: bad
arguments (the message names the option).
"""
import argparse
import fcntl
import os
import re
import select
import signal
import sys
import termios
import time
import tty

NAME_RE = re.compile(r"^[A-Za-z0-9_.]+$")
GARBLE = 0x5A


class Tx:
    """One transmission: its bytes and when each one is off the air."""

    def __init__(self, sender, start, air):
        self.sender = sender
        self.start = start  # the sender's first byte reached the radio
        self.air = air  # carrier on, after the key-up delay
        self.data = bytearray()
        self.due = []  # per byte: the time its last bit is on the air
        self.done = False
        self.garbled = set()

    def last_end(self):
        return self.due[-1] if self.due else self.air


class Node:
    def __init__(self, name, master, slave, link):
        self.name = name
        self.master = master
        self.slave = slave  # held open: a pty whose other side closes gives EIO
        self.link = link
        self.hears = set()
        self.tx = None  # the transmission on the air, if any
        self.streams = []  # [tx, bytes delivered] arriving here, oldest first
        self.dropped = 0  # bytes the pty had no room for (nobody reading)


def usage_error(msg):
    sys.stderr.write("radio_channel: %s\n" % msg)
    sys.exit(2)


def parse_args(argv):
    p = argparse.ArgumentParser(prog="radio_channel", add_help=True)
    p.add_argument("--prefix", required=True)
    p.add_argument("--node", action="append", default=[])
    p.add_argument("--link", action="append", default=[])
    p.add_argument("--hears", action="append", default=[])
    p.add_argument("--baud", type=int, default=9600)
    p.add_argument("--keyup-ms", type=float, default=0.0)
    p.add_argument("--gap-chars", type=float, default=2.0)
    p.add_argument("--collide", action="store_true")
    p.add_argument("--log")
    a = p.parse_args(argv)
    names = []
    for item in a.node:
        for n in item.split(","):
            if not NAME_RE.match(n):
                usage_error("--node: invalid name '%s' (letters, digits, _ and .)" % n)
            if n in names:
                usage_error("--node: '%s' given twice" % n)
            names.append(n)
    if not names:
        usage_error("--node: at least one node is needed")
    if a.baud < 0 or a.keyup_ms < 0 or a.gap_chars < 0:
        usage_error("--baud, --keyup-ms and --gap-chars are not negative")

    def known(opt, n):
        if n not in names:
            usage_error("%s: unknown node '%s' (not given with --node)" % (opt, n))
        return n

    hears = {n: set() for n in names}
    for chain in a.link:
        parts = [known("--link", n) for n in chain.split("-")]
        if len(parts) < 2:
            usage_error("--link: '%s' names no pair (A-B)" % chain)
        for x, y in zip(parts, parts[1:]):
            if x == y:
                usage_error("--link: '%s' links a node to itself" % chain)
            hears[x].add(y)
            hears[y].add(x)
    for spec in a.hears:
        who, sep, heard = spec.partition(":")
        if not sep or not heard:
            usage_error("--hears: '%s' is not NODE:NODE[,NODE...]" % spec)
        known("--hears", who)
        for n in heard.split(","):
            if known("--hears", n) == who:
                usage_error("--hears: '%s' hears itself" % spec)
            hears[who].add(n)
    if not a.link and not a.hears:
        for n in names:
            hears[n] = set(names) - {n}
    return a, names, hears


class Channel:
    def __init__(self, a, names, hears):
        self.char = 10.0 / a.baud if a.baud else 0.0
        self.keyup = a.keyup_ms / 1000.0
        self.gap = a.gap_chars * (self.char if self.char else 0.001)
        self.collide = a.collide
        self.t0 = time.monotonic()
        self.log = open(a.log, "a") if a.log else None
        self.nodes = []
        for name in names:
            m, s = os.openpty()
            tty.setraw(s)
            attrs = termios.tcgetattr(s)
            attrs[3] &= ~termios.ECHO
            termios.tcsetattr(s, termios.TCSANOW, attrs)
            fl = fcntl.fcntl(m, fcntl.F_GETFL)
            fcntl.fcntl(m, fcntl.F_SETFL, fl | os.O_NONBLOCK)
            link = "%s.%s" % (a.prefix, name)
            if os.path.lexists(link):
                os.unlink(link)
            os.symlink(os.ttyname(s), link)
            self.nodes.append(Node(name, m, s, link))
        by_name = {n.name: n for n in self.nodes}
        for n in self.nodes:
            n.hears = {by_name[h] for h in hears[n.name]}
        # who is in range of each sender, in the order the nodes were given
        self.range = {n: [r for r in self.nodes if n in r.hears] for n in self.nodes}

    # ---- the sender's side ----
    def transmit(self, node, data, now):
        tx = node.tx
        if tx is None or tx.done:
            tx = Tx(node, now, now + self.keyup)
            node.tx = tx
            for r in self.range[node]:
                r.streams.append([tx, 0])
        t = max(tx.last_end(), now)
        for b in data:
            t += self.char
            tx.data.append(b)
            tx.due.append(t)

    def end_transmissions(self, now):
        ended = False
        for n in self.nodes:
            tx = n.tx
            if tx is not None and not tx.done and now >= tx.last_end() + self.gap:
                self.finish(tx)
                ended = True
        return ended

    def finish(self, tx):
        tx.done = True
        # bytes still due reach their receivers on the next deliveries
        if self.log is None:
            return
        rx = ",".join(r.name for r in self.range[tx.sender]) or "-"
        line = "%.6f %.6f %s > %s %s" % (tx.start - self.t0, tx.last_end() - self.t0,
                                         tx.sender.name, rx, " ".join("%02x" % b for b in tx.data))
        if tx.garbled:
            line += " garbled:" + ",".join(r.name for r in self.range[tx.sender] if r in tx.garbled)
        self.log.write(line + "\n")
        self.log.flush()

    # ---- the receivers' side ----
    def on_air(self, other, t):
        """other's transmission is on the air around time t (one character)."""
        return other.air < t and other.last_end() > t - max(self.char, 1e-6)

    def deliver(self, now):
        for r in self.nodes:
            out = bytearray()
            keep = []
            blocked = False
            for st in r.streams:
                tx, i = st
                if blocked:
                    keep.append(st)
                    continue
                while i < len(tx.due) and tx.due[i] <= now:
                    b = tx.data[i]
                    if self.collide and any(o[0] is not tx and self.on_air(o[0], tx.due[i])
                                            for o in r.streams):
                        b ^= GARBLE
                        tx.garbled.add(r)
                    out.append(b)
                    i += 1
                st[1] = i
                if tx.done and i == len(tx.due):
                    continue  # all of it has arrived here
                keep.append(st)
                if not self.collide:
                    blocked = True  # the next transmission waits for this one
            r.streams = keep
            if out:
                self.put(r, bytes(out))

    def put(self, r, data):
        try:
            n = os.write(r.master, data)
        except BlockingIOError:
            n = 0
        except OSError:
            n = 0
        r.dropped += len(data) - n

    def deadline(self, now):
        """The next moment something is due (None: nothing until a node writes)."""
        times = []
        for n in self.nodes:
            if n.tx is not None and not n.tx.done:
                times.append(n.tx.last_end() + self.gap)
            for tx, i in n.streams:
                if i < len(tx.due):
                    times.append(tx.due[i])
                if not self.collide:
                    break
        if not times:
            return None
        return max(0.0, min(times) - now)

    def close(self):
        now = time.monotonic()
        self.deliver(now)
        for n in self.nodes:
            if n.tx is not None and not n.tx.done:
                self.finish(n.tx)
        for n in self.nodes:
            if n.dropped:
                sys.stderr.write("radio_channel: node %s: %d bytes lost, its pty was full "
                                 "(nobody reading)\n" % (n.name, n.dropped))
            if os.path.islink(n.link):
                os.unlink(n.link)
        if self.log:
            self.log.close()


def main():
    a, names, hears = parse_args(sys.argv[1:])
    ch = Channel(a, names, hears)
    rd, wr = os.pipe()
    for fd in (rd, wr):
        fcntl.fcntl(fd, fcntl.F_SETFL, fcntl.fcntl(fd, fcntl.F_GETFL) | os.O_NONBLOCK)
    signal.set_wakeup_fd(wr)
    stop = []
    for sig in (signal.SIGTERM, signal.SIGINT):
        signal.signal(sig, lambda *_: stop.append(1))
    for n in ch.nodes:
        print("%s %s" % (n.name, os.ttyname(n.slave)))
    print("ready", flush=True)
    by_fd = {n.master: n for n in ch.nodes}
    poller = select.poll()
    for fd in by_fd:
        poller.register(fd, select.POLLIN)
    poller.register(rd, select.POLLIN)
    while not stop:
        now = time.monotonic()
        wait = ch.deadline(now)
        timeout = None if wait is None else int(wait * 1000000 + 999) / 1000.0
        try:
            events = poller.poll(timeout)
        except InterruptedError:
            events = []
        now = time.monotonic()
        for fd, ev in events:
            if fd == rd:
                try:
                    os.read(rd, 64)
                except OSError:
                    pass
                continue
            node = by_fd[fd]
            try:
                data = os.read(fd, 4096)
            except (BlockingIOError, InterruptedError):
                continue
            except OSError:  # EIO: nobody has the slave side; not ours to fix
                data = b""
            if data:
                ch.transmit(node, data, now)
        ch.deliver(now)  # first: the log's garbled marks need every byte delivered
        if ch.end_transmissions(now):
            ch.deliver(now)  # what waited behind an ended transmission
    ch.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
