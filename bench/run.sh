#!/bin/sh
# bench/run.sh BUILDDIR - benchmarks (make bench; never run by make check).
# bench_poll: 200 tags over 5 stations on a simulated 19200-baud half-duplex
# line (df1sim --line-baud 19200, both ends paced): measured scan time against
# the wire-time bound, transactions per scan against a one-tag-per-read poller.
# bench_load: df1_tag_load_map of 40 000 tags, df1_map_load of a 10 MB field.
# python/bench.py (when python3 has cffi): single-word reads per second from
# Python next to the C figure, against one df1sim on a pty.
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
$CC -O2 -g -std=c11 -D_DEFAULT_SOURCE -Wall -Wextra -Iinclude -o "$B/bench/bench_poll" \
	bench/bench_poll.c "$B/libdf1.a" -lcsv -lm -lpthread || exit 1

mkfifo "$T/out" || exit 1
"$B/bin/df1sim" --pty "$T/plc" --duplex half --station 1-5 --line-baud 19200 > "$T/out" 2> "$T/err" &
pid=$!
( sleep 10; kill "$pid" 2>/dev/null ) &
dog=$!
line=
IFS= read -r line < "$T/out" || line=
kill "$dog" 2>/dev/null
if [ "$line" != "$T/plc" ]; then
	echo "bench: df1sim did not start" >&2
	cat "$T/err" >&2
	exit 1
fi
"$B/bench/bench_poll" "$T/plc" "${BENCH_SCANS:-10}" || exit 1
if python3 -c 'import cffi' >/dev/null 2>&1; then
	LIBDF1_PATH="$B" DF1_BIN="$B/bin" python3 python/bench.py || exit 1
else
	echo "python bench: skipped (python3 has no cffi: apt-get install python3-cffi)"
fi

# bench_gw: df1gw end to end (mosquitto, df1sim, df1gw): latency and CPU
sh bench/bench_gw.sh "$B"
