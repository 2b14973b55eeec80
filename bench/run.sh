#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# bench/run.sh BUILDDIR - benchmarks (make bench; never run by make check).
# bench_poll: 200 tags over 5 stations on a simulated 19200-baud line (df1sim
# --line-baud 19200), four cases: half duplex, full duplex, full duplex
# pipelined (--outstanding 4 against df1sim --max-queue 8), half duplex
# against slaves with a 5 ms program scan (--scan-time 5): measured scan time
# against the wire-time bounds; half duplex also against a one-tag-per-read
# poller. BENCH_ROUNDS rounds (5) of BENCH_SCANS scans (6) per case, the cases
# in turn in each round, so that a busy moment of the machine spreads over
# them; each ratio's median, minimum and maximum over the rounds, and for the
# pipelined case also against the one-direction bound. bench/README.md says
# what the bounds are. The last line of make bench is, with the medians,
#   bench: half R1 full R2 full-pipelined R3 half-scan5 R4
# bench_load: df1_tag_load_map of 40 000 tags, df1_map_load of a 10 MB field.
# bench_buffer: df1gw's store and forward buffer, records/s and file bytes.
# python/bench.py (when python3 has cffi): single-word reads per second from
# Python next to the C figure, against one df1sim on a pty.
# bench_gw.sh: df1gw end to end. bench_radio.sh: reads a second across a
# simulated radio link (tests/support/radio_channel.py), half duplex against
# radio modem.
set -u
B=${1:-build}
CC=${CC:-cc}
T=$(mktemp -d "${TMPDIR:-/tmp}/df1bench.XXXXXX") || exit 1
pid=
cleanup() {
	[ -n "$pid" ] && kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null
	rm -rf "$T"
}
trap cleanup EXIT INT TERM

mkdir -p "$B/bench"
# bench_load: configuration files on big input (40 000 tags, a 10 MB field)
$CC -O2 -g -std=c11 -D_DEFAULT_SOURCE -Wall -Wextra -Iinclude -o "$B/bench/bench_load" \
	bench/bench_load.c "$B/libdf1.a" -lcsv -lm -lpthread || exit 1
"$B/bench/bench_load" "$T" "${BENCH_TAGS:-40000}" || exit 1
# bench_buffer: df1gw's store and forward buffer (records/s appended and
# replayed, bytes of file per record), on SQLite and in memory
$CC -O2 -g -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -Wall -Wextra -Iinclude -Itools -o "$B/bench/bench_buffer" \
	bench/bench_buffer.c tools/df1gw/gw_buffer.c tools/df1gw/gw_buffer_mem.c tools/df1gw/gw_buffer_sql.c \
	$(pkg-config --libs sqlite3 2>/dev/null || echo -lsqlite3) || exit 1
"$B/bench/bench_buffer" "$T" "${BENCH_BUFFER_RECORDS:-100000}" || exit 1
$CC -O2 -g -std=c11 -D_DEFAULT_SOURCE -Wall -Wextra -Iinclude -o "$B/bench/bench_poll" \
	bench/bench_poll.c "$B/libdf1.a" -lcsv -lm -lpthread || exit 1

# start_sim NAME DF1SIM-OPTIONS...: a df1sim on the pty $T/NAME, paced as a
# 19200-baud line; sets pid (stopped by stop_sim)
start_sim() {
	name=$1
	shift
	rm -f "$T/out"
	mkfifo "$T/out" || exit 1
	"$B/bin/df1sim" --pty "$T/$name" --station 1-5 --line-baud 19200 "$@" > "$T/out" 2> "$T/err" &
	pid=$!
	( sleep 10; kill "$pid" 2>/dev/null ) &
	dog=$!
	line=
	IFS= read -r line < "$T/out" || line=
	kill "$dog" 2>/dev/null
	if [ "$line" != "$T/$name" ]; then
		echo "bench: df1sim $* did not start" >&2
		cat "$T/err" >&2
		exit 1
	fi
}
stop_sim() {
	kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null
	pid=
}
# run_case NAME DF1SIM-OPTIONS -- BENCH_POLL-ARGUMENTS...: one case, one
# round; its ratios (bench_poll's last line "case NAME ratio R [one-direction
# R1]") appended to $T/ratio.NAME and $T/onedir.NAME; bench_poll's report
# shown in the first round only
run_case() {
	name=$1
	shift
	sim_args=
	while [ "$1" != "--" ]; do
		sim_args="$sim_args $1"
		shift
	done
	shift
	# shellcheck disable=SC2086
	start_sim "$name" $sim_args
	"$B/bench/bench_poll" "$T/$name" "$@" --name "$name" > "$T/case.$name" || { cat "$T/case.$name"; exit 1; }
	stop_sim
	[ "$round" = 1 ] && sed '$d' "$T/case.$name"
	tail -n 1 "$T/case.$name" | sed -n 's/^case [^ ]* ratio \([^ ]*\).*/\1/p' >> "$T/ratio.$name"
	tail -n 1 "$T/case.$name" | sed -n 's/^case .* one-direction \([^ ]*\)$/\1/p' >> "$T/onedir.$name"
}
# stats FILE: "median min max" of the numbers in FILE, two decimals
stats() {
	sort -n "$1" | awk '{ v[NR] = $1 } END {
		m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
		printf "%.2f %.2f %.2f\n", m, v[1], v[NR] }'
}
S=${BENCH_SCANS:-6}
R=${BENCH_ROUNDS:-5}
round=1
while [ "$round" -le "$R" ]; do
	naive=--no-naive
	[ "$round" = 1 ] && naive=
	run_case half --duplex half -- half "$S" $naive
	run_case full --duplex full -- full "$S"
	# a controller that buffers commands (--max-queue), a master that pipelines
	run_case full-pipelined --duplex full --max-queue 8 -- full "$S" --outstanding 4
	# slaves that answer at the end of a 5 ms program scan, as an SLC does
	run_case half-scan5 --duplex half --scan-time 5 -- half "$S" --scan-time 5
	echo "poll bench round $round of $R: half $(tail -n 1 "$T/ratio.half") full $(tail -n 1 "$T/ratio.full")" \
	     "full-pipelined $(tail -n 1 "$T/ratio.full-pipelined") (one-direction $(tail -n 1 "$T/onedir.full-pipelined"))" \
	     "half-scan5 $(tail -n 1 "$T/ratio.half-scan5")"
	round=$((round + 1))
done
echo "poll bench, $R rounds of $S scans, ratio to the bound: median min max"
echo "  half                        $(stats "$T/ratio.half")   (x serial bound)"
echo "  full                        $(stats "$T/ratio.full")   (x serial bound)"
echo "  full-pipelined              $(stats "$T/ratio.full-pipelined")   (x serial bound)"
echo "  full-pipelined one-direction $(stats "$T/onedir.full-pipelined")  (x one-direction bound)"
echo "  half-scan5                  $(stats "$T/ratio.half-scan5")   (x (serial bound + scan waits))"
if python3 -c 'import cffi' >/dev/null 2>&1; then
	LIBDF1_PATH="$B" DF1_BIN="$B/bin" python3 python/bench.py || exit 1
else
	echo "python bench: skipped (python3 has no cffi: apt-get install python3-cffi)"
fi

# bench_gw: df1gw end to end (mosquitto, df1sim, df1gw): latency and CPU
sh bench/bench_gw.sh "$B"
# bench_radio: reads across a simulated radio link (50 ms key-up, 9600 baud),
# half duplex and, when the tools have it, radio modem
sh bench/bench_radio.sh "$B"
# python/bench_opcua.py: df1opcua with 1 000 tags on a full-speed pty, tag
# reads a second and the latency from a read to an OPC UA subscriber (asyncua)
if python3 -c 'import asyncua, cffi' >/dev/null 2>&1; then
	LIBDF1_PATH="$B" DF1_BIN="$B/bin" python3 python/bench_opcua.py || exit 1
else
	echo "opcua bench: skipped (no asyncua: pip install './python[opcua]')"
fi

# the summary line for scripts, last: the median over the rounds of measured
# scan / bound per case (bench_poll's comment: serial wire-time bound; for
# half-scan5 plus the scan-time waits the workload cannot avoid)
med() { stats "$1" | cut -d' ' -f1; }
echo "bench: half $(med "$T/ratio.half") full $(med "$T/ratio.full") full-pipelined $(med "$T/ratio.full-pipelined") half-scan5 $(med "$T/ratio.half-scan5")"
