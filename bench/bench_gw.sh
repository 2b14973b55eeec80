#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# bench/bench_gw.sh BUILDDIR - df1gw against mosquitto and df1sim on a pty
# (run by bench/run.sh, `make bench`; never by make check):
#  - latency: a change in df1sim (a write through .../set) to the MQTT message
#    of another tag that reads the same word in a block of its own (PLC_Type
#    MicroLogix: the engine reads a written block back at once, not this one),
#    Scan_Ms 100 (BENCH_GW_SCAN_MS); bench_gw.c;
#  - CPU: df1gw's user + system time per scan of 1000 tags (N10:0..999, one
#    Read tag each, Scan_Ms 0), from /proc/PID/stat, scans counted in df1sim's
#    --log; then the same with --refresh 1 (1000 publications a second);
#  - Sparkplug B: the same CPU figure with --sparkplug on; bench_spb.c: bytes
#    per update and updates encoded per second, JSON against Sparkplug;
#  - writes: BENCH_GW_SETS (default 2000) /set messages to 4 tags as fast as
#    mosquitto_pub sends them, with --write-optimize all and with the default
#    latest-non-bool (coalescing): /set answered a second, and writes that
#    reached df1sim (its --log) a second, on a full-speed pty;
#  - end to end, JSON against Sparkplug: the same 1000 tags changing at every
#    round (df1write over a second df1sim's --eip side writes N10:0..999 while
#    df1gw reads the pty), messages per second and bytes per update received
#    from the broker, df1gw CPU per round; bench_e2e.py (BENCH_E2E_ROUNDS, 20).
# BENCH_GW_WRITES (default 50) and BENCH_GW_SECONDS (default 10) set the size.
set -u
B=${1:-build}
CC=${CC:-cc}
MOSQ=${MOSQUITTO:-/usr/sbin/mosquitto}
WRITES=${BENCH_GW_WRITES:-50}
SECS=${BENCH_GW_SECONDS:-10}
if [ ! -x "$MOSQ" ]; then
	echo "bench_gw: no $MOSQ (apt-get install mosquitto mosquitto-clients): skipped"
	exit 0
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/df1bgw.XXXXXX") || exit 1
# --sparkplug keeps bdSeq in the state folder: the bench's own
XDG_STATE_HOME="$T/state"
export XDG_STATE_HOME
unset STATE_DIRECTORY
pids=
cleanup() {
	for p in $pids; do kill "$p" 2>/dev/null; done
	for p in $pids; do wait "$p" 2>/dev/null; done
	rm -rf "$T"
}
trap cleanup EXIT INT TERM

mkdir -p "$B/bench"
$CC -O2 -g -std=c11 -D_DEFAULT_SOURCE -Wall -Wextra -o "$B/bench/bench_gw" bench/bench_gw.c \
	$(pkg-config --libs libmosquitto 2>/dev/null || echo -lmosquitto) || exit 1

# wait_until TRIES CMD...: run CMD every 0.1 s until it succeeds
wait_until() {
	n=$1; shift
	while [ "$n" -gt 0 ]; do
		"$@" && return 0
		n=$((n - 1))
		sleep 0.1
	done
	echo "bench_gw: gave up waiting for: $*" >&2
	return 1
}
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
# set_tcp_nodelay: else the broker's Nagle and the clients' delayed ACKs add ~40 ms to a reply
# max_queued_messages: the write burst is more than a slow client's default 1000
printf 'listener %s 127.0.0.1\npersistence false\nallow_anonymous true\nuser %s\nset_tcp_nodelay true\nmax_queued_messages 100000\n' \
	"$port" "$(id -un)" > "$T/mq.conf"
"$MOSQ" -c "$T/mq.conf" > "$T/mq.log" 2>&1 &
pids="$pids $!"
wait_until 100 python3 -c "import socket; socket.create_connection(('127.0.0.1', $port), 1).close()" 2>/dev/null || exit 1
echo "N10:999=0" > "$T/plc.txt"
"$B/bin/df1sim" --pty "$T/plc" --data "$T/plc.txt" --log "$T/sim.log" > "$T/sim.out" 2> "$T/sim.err" &
pids="$pids $!"
wait_until 100 test -s "$T/sim.out" || exit 1
online() { mosquitto_sub -p "$port" -t "$1/status" -C 1 -W 2 2>/dev/null | grep -q online; }

# ---- latency ----
SCAN=${BENCH_GW_SCAN_MS:-100}
printf 'Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms\nSpeed,ReadWrite,INT,1,SLC,N7:0,1,%s\nMirror,Read,INT,1,MicroLogix,N7:0,1,%s\n' \
	"$SCAN" "$SCAN" > "$T/lat.csv"
"$B/bin/df1gw" -d "$T/plc" --map "$T/lat.csv" --mqtt "mqtt://127.0.0.1:$port" --prefix bench/lat -q &
gw=$!
pids="$pids $gw"
wait_until 100 online bench/lat || exit 1
echo "bench_gw: latency, 2 tags at Scan_Ms $SCAN on a pty (no line pacing), QoS 1, $WRITES writes:"
"$B/bench/bench_gw" "$port" bench/lat "$WRITES" "$SCAN"
kill "$gw"; wait "$gw" 2>/dev/null

# ---- CPU per 1000 tags per scan ----
{
	echo "Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms"
	i=0
	while [ $i -lt 1000 ]; do echo "T$i,Read,INT,1,SLC,N10:$i,1,0"; i=$((i + 1)); done
} > "$T/cpu.csv"
tck=$(getconf CLK_TCK)
cpu_of() { awk '{ print $14 + $15 }' "/proc/$1/stat"; }
scans() { grep -c "addr=N10:0 " "$T/sim.log"; }
measure() {
	label=$1; shift
	"$B/bin/df1gw" -d "$T/plc" --map "$T/cpu.csv" --mqtt "mqtt://127.0.0.1:$port" --prefix "bench/$label" -q "$@" &
	gw=$!
	pids="$pids $gw"
	wait_until 100 online "bench/$label" || return 1
	wait_until 100 sh -c "mosquitto_sub -p $port -t 'bench/$label/tag/T999' -C 1 -W 2 | grep -q GOOD" || return 1
	c0=$(cpu_of "$gw"); s0=$(scans); t0=$(date +%s.%N)
	sleep "$SECS"
	c1=$(cpu_of "$gw"); s1=$(scans); t1=$(date +%s.%N)
	kill "$gw"; wait "$gw" 2>/dev/null
	awk -v c="$((c1 - c0))" -v s="$((s1 - s0))" -v tck="$tck" -v t0="$t0" -v t1="$t1" -v l="$label" 'BEGIN {
		ms = c * 1000 / tck; el = t1 - t0
		printf "bench_gw: %-8s %d scans of 1000 tags in %.1f s (%.1f ms a scan): df1gw CPU %.0f ms, %.2f ms per 1000 tags per scan (%.0f%% of a core)\n",
		       l, s, el, s ? el * 1000 / s : 0, ms, s ? ms / s : 0, 100 * ms / (el * 1000) }'
}
echo "bench_gw: CPU, 1000 tags (N10:0..999, 9 block reads a scan), Scan_Ms 0, $SECS s each:"
measure steady
measure refresh --refresh 1

# ---- Sparkplug B (df1gw --sparkplug) ----
# CPU of the same 1000 tags with Sparkplug on beside JSON; then bench_spb: the
# two formats' bytes per update and encode rate on one 1000-tag workload
echo "bench_gw: CPU with --sparkplug (JSON and Sparkplug B both on), as above:"
measure sparkplug --sparkplug Bench --edge-node B1
# df1gw's objects as an archive: the linker takes only those bench_spb needs
# (the formats, not the broker's or the loop's)
rm -f "$B/bench/libdf1gw-bench.a"
ar rcs "$B/bench/libdf1gw-bench.a" $(ls "$B"/tools/df1gw/*.o | grep -v '/df1gw\.o$') || exit 1
$CC -O2 -g -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -Wall -Wextra -Iinclude -Itools -o "$B/bench/bench_spb" \
	bench/bench_spb.c "$B/bench/libdf1gw-bench.a" \
	"$B/gen/df1gw/spb.pb-c.o" "$B/libdf1-tools.a" "$B/libdf1.a" \
	$(pkg-config --libs libprotobuf-c 2>/dev/null || echo -lprotobuf-c) -lsqlite3 -lcsv -lm -lpthread || exit 1
"$B/bench/bench_spb" "${BENCH_SPB_ROUNDS:-200}"

# ---- writes a second through /set, with and without coalescing ----
SETS=${BENCH_GW_SETS:-2000}
printf 'Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms\n' > "$T/w.csv"
for t in 0 1 2 3; do echo "W$t,ReadWrite,INT,1,SLC,N11:$t,1,100" >> "$T/w.csv"; done
now_s() { date +%s.%N; }
writes_logged() { grep -c "cmd=0F/AA addr=N11:" "$T/sim.log"; }
wbench() {
	label=$1; shift
	p=bench/w$label
	"$B/bin/df1gw" -d "$T/plc" --map "$T/w.csv" --mqtt "mqtt://127.0.0.1:$port" --prefix "$p" -q \
		--max-pending-writes 100000 --write-timeout 600000 "$@" &
	gw=$!
	pids="$pids $gw"
	wait_until 100 online "$p" || return 1
	mosquitto_sub -p "$port" -q 1 -t "$p/tag/+/result" > "$T/res.$label" 2>/dev/null &
	sub=$!
	pids="$pids $sub"
	wait_until 100 sh -c "mosquitto_pub -p $port -q 1 -t '$p/tag/W0/set' -m '{\"value\":0,\"id\":\"m\"}' &&
		grep -q '\"id\":\"m\"' '$T/res.$label'" || return 1
	per=$((SETS / 4))
	for t in 0 1 2 3; do
		awk -v t=$t -v n=$per 'BEGIN { for (i = 1; i <= n; i++) printf "{\"value\":%d,\"id\":\"%d-%d\"}\n", i, t, i }' \
			> "$T/sets$t"
	done
	w0=$(writes_logged); t0=$(now_s)
	for t in 0 1 2 3; do
		mosquitto_pub -p "$port" -q 1 -t "$p/tag/W$t/set" -l < "$T/sets$t" &
	done
	wait_until 3000 sh -c "[ \$(grep -c '\"id\":\"[0-3]-' '$T/res.$label') -ge $((per * 4)) ]" || return 1
	t1=$(now_s); w1=$(writes_logged)
	kill "$gw" "$sub"; wait "$gw" 2>/dev/null
	awk -v n="$((per * 4))" -v w="$((w1 - w0))" -v t0="$t0" -v t1="$t1" -v l="$label" 'BEGIN {
		el = t1 - t0
		printf "bench_gw: writes %-16s %d /set answered in %.2f s: %.0f /set a second; %d written on the line, %.0f writes a second\n",
		       l, n, el, n / el, w, w / el }'
}
echo "bench_gw: writes, $SETS /set to 4 tags (Scan_Ms 100) at once, full-speed pty, QoS 1:"
wbench all --write-optimize all
wbench latest-non-bool

# ---- end to end, JSON against Sparkplug B, through the broker ----
if ! python3 -c 'import paho.mqtt' 2>/dev/null; then
	echo "bench_gw: end to end: no paho-mqtt (pip install paho-mqtt): skipped"
	exit 0
fi
eport=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
"$B/bin/df1sim" --pty "$T/plc2" --eip "127.0.0.1:$eport" --data "$T/plc.txt" > "$T/sim2.out" 2> "$T/sim2.err" &
pids="$pids $!"
wait_until 100 test -s "$T/sim2.out" || exit 1
wait_until 100 python3 -c "import socket; socket.create_connection(('127.0.0.1', $eport), 1).close()" 2>/dev/null || exit 1
e2e() {
	label=$1 filt=$2 ready=$3; shift 3
	"$B/bin/df1gw" -d "$T/plc2" --map "$T/cpu.csv" --mqtt "mqtt://127.0.0.1:$port" -q "$@" &
	gw=$!
	pids="$pids $gw"
	python3 bench/bench_e2e.py "$label" "$port" "$filt" "$ready" "$gw" "$B/bin/df1write" "127.0.0.1:$eport" \
		"${BENCH_E2E_ROUNDS:-20}"
	kill "$gw"; wait "$gw" 2>/dev/null
}
echo "bench_gw: end to end, 1000 tags changing at every round, through mosquitto (QoS 0 subscriber):"
e2e json 'bench/e2e/tag/+' 'bench/e2e/tag/T999' --prefix bench/e2e
e2e sparkplug 'spBv1.0/Bench/DDATA/E2E/#' 'spBv1.0/Bench/DBIRTH/E2E/#' --sparkplug Bench --edge-node E2E --json no
