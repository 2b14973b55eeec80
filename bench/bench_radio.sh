#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# bench/bench_radio.sh BUILDDIR - reads across a simulated radio link (run by
# bench/run.sh, `make bench`; never by make check). The link is
# tests/support/radio_channel.py with two nodes in range of each other, 9600
# baud (10 bits a byte) and a key-up delay of 50 ms before every transmission
# (BENCH_RADIO_BAUD, BENCH_RADIO_KEYUP_MS). Two cases, each on a channel of
# its own:
#  - half: df1read --duplex half (master) against df1sim --duplex half (slave):
#    a read is the command, the ACK, a poll, the reply, the ACK of the reply
#    (this one goes out with the next command);
#  - radio: df1read --duplex radio against df1sim --duplex radio: the command
#    and the reply, no ACK, poll or other link control. Run when
#    the tools accept --duplex radio; otherwise the bench says it skips it.
# Each case is BENCH_RADIO_READS (default 20) df1read processes one after the
# other, each reading N7:0 (1234, checked); transactions per second = reads /
# elapsed seconds (a process start, a few ms, is in each, in both cases), and
# transmissions per read from the channel's log. A benchmark reports numbers;
# it asserts nothing. Last line:
#   bench radio: half H/s radio R/s ratio X     (X = R / H)
# or, without radio modem in the tools,
#   bench radio: half H/s radio skipped (...)
set -u
B=${1:-build}
N=${BENCH_RADIO_READS:-20}
BAUD=${BENCH_RADIO_BAUD:-9600}
KEYUP=${BENCH_RADIO_KEYUP_MS:-50}
BIN=$B/bin
T=$(mktemp -d "${TMPDIR:-/tmp}/df1brad.XXXXXX") || exit 1
pids=
cleanup() {
	for p in $pids; do kill "$p" 2>/dev/null; done
	for p in $pids; do wait "$p" 2>/dev/null; done
	rm -rf "$T"
}
trap cleanup EXIT INT TERM
if ! command -v python3 > /dev/null; then
	echo "bench_radio: no python3 (the radio channel is a Python script): skipped"
	exit 0
fi
now() { python3 -c 'import time; print("%.6f" % time.monotonic())'; }

# wait_line FILE PATTERN PID: until FILE holds a line matching PATTERN (10 s
# at most, or until PID has ended)
wait_line() {
	n=100
	while [ $n -gt 0 ]; do
		grep -qs "$2" "$1" && return 0
		kill -0 "$3" 2>/dev/null || break
		n=$((n - 1))
		sleep 0.1
	done
	echo "bench_radio: $1: never saw '$2'" >&2
	cat "$1" "$1.err" 2>/dev/null | head -5 >&2
	exit 1
}

printf 'N7:0=1234\n' > "$T/data"
# run_case NAME DUPLEX DF1READ-OPTIONS...: a channel and a df1sim of its own,
# N reads; sets tps (reads a second) and per (transmissions a read)
run_case() {
	name=$1; duplex=$2; shift 2
	python3 tests/support/radio_channel.py --prefix "$T/$name" --node m,s --link m-s \
		--baud "$BAUD" --keyup-ms "$KEYUP" --log "$T/$name.log" > "$T/$name.ch" 2> "$T/$name.ch.err" &
	ch=$!
	pids="$pids $ch"
	wait_line "$T/$name.ch" '^ready$' "$ch"
	"$BIN/df1sim" -d "$T/$name.s" --duplex "$duplex" --station 1 --data "$T/data" \
		> "$T/$name.sim" 2> "$T/$name.sim.err" &
	sim=$!
	pids="$pids $sim"
	wait_line "$T/$name.sim" . "$sim"
	t0=$(now)
	i=0
	bad=0
	while [ $i -lt "$N" ]; do
		v=$("$BIN/df1read" -d "$T/$name.m" --duplex "$duplex" --station 1 "$@" N7:0 2>> "$T/$name.err")
		[ "$v" = 1234 ] || bad=$((bad + 1))
		i=$((i + 1))
	done
	t1=$(now)
	kill "$sim" 2>/dev/null; wait "$sim" 2>/dev/null
	kill "$ch" 2>/dev/null; wait "$ch" 2>/dev/null
	tps=$(awk -v n="$N" -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", n / (b - a) }')
	per=$(awk -v n="$N" 'END { printf "%.1f", NR / n }' "$T/$name.log")
	printf 'radio %-5s %d reads in %.2f s: %s transactions/s, %s transmissions a read' \
		"$name" "$N" "$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')" "$tps" "$per"
	if [ "$bad" -gt 0 ]; then
		printf ' (%d reads failed or read a wrong value: %s)' "$bad" "$(tail -n 1 "$T/$name.err")"
	fi
	echo
}

echo "radio bench: $N reads of N7:0 a case, a channel of $BAUD baud with $KEYUP ms key-up a transmission"
# the poll's answer begins after the slave's key-up: poll again after 300 ms, not the default
run_case half half --poll-timeout 300 --timeout 2000
half=$tps
if "$BIN/df1read" --duplex radio --help > /dev/null 2>&1 &&
   "$BIN/df1sim" --duplex radio --help > /dev/null 2>&1; then
	run_case radio radio --timeout 2000
	echo "bench radio: half $half/s radio $tps/s ratio $(awk -v r="$tps" -v h="$half" 'BEGIN { printf "%.2f", r / h }')"
else
	echo "radio bench: radio row skipped (df1read or df1sim refuses --duplex radio)"
	echo "bench radio: half $half/s radio skipped (no --duplex radio in the tools)"
fi
