#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# tests/fuzz/run-target.sh TARGET - one target's part of `make fuzz`
# (tests/fuzz/fuzz.mk, tests/fuzz/README):
#   1. replay: every seed of build/fuzz/seeds/TARGET run once, whole, in name
#      order (the findings of earlier runs among them, tests/fuzz/found), so a
#      fixed finding that comes back fails every time, not by chance;
#   2. explore: FUZZ_SECONDS of libFuzzer on the working corpus and the seeds.
# Prints one line "fuzz TARGET: ok, ..." or the finding: what broke, the input
# in hex (so the log alone reproduces it: `xxd -r -p`), and the command that
# runs it again. Exit 0, or 1 on a finding.
# Environment (fuzz.mk sets them): FUZZ_B, FUZZ_SECONDS, FUZZ_TIMEOUT,
# FUZZ_MAX_LEN, FUZZ_FLAGS.
t=$1
B=${FUZZ_B:-build/fuzz}
bin=$B/bin/fuzz_$t
log=$B/logs/$t.log
seeds=$B/seeds/$t
mkdir -p "$B/corpus/$t" "$B/findings" "$B/logs"

# What broke, the input in hex and how to run it again; exit 1.
finding() {
	phase=$1
	echo "fuzz $t: FINDING in the $phase (see $log):"
	grep -E '^(==[0-9]+==ERROR|fuzz: |SUMMARY|.*runtime error|ERROR: libFuzzer)' "$log" | head -8 | sed 's/^/    /'
	art=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -1)
	if [ -z "$art" ] || [ ! -f "$art" ]; then
		# a replayed seed that broke without an artifact: the last one started
		art=$(sed -n 's/^Running: \(.*\)$/\1/p' "$log" | tail -1)
	fi
	if [ -n "$art" ] && [ -f "$art" ]; then
		echo "    input: $(wc -c <"$art") bytes, hex (xxd -r -p makes the file again):"
		if command -v xxd >/dev/null 2>&1; then
			xxd -p -c 40 "$art"
		else
			od -An -v -tx1 "$art" | tr -d ' \n' | fold -w 80
			echo
		fi | sed 's/^/    | /'
		echo "    reproduce: $bin $art"
		echo "    (from this output alone: sed -n 's/^    | //p' OUTPUT | xxd -r -p >in.bin; $bin in.bin)"
		echo "    once fixed, keep it as a seed: tests/fuzz/found/$t-WHAT.hex (tests/fuzz/README)"
	fi
	exit 1
}

: >"$log"
if [ -d "$seeds" ] && [ -n "$(ls "$seeds")" ]; then
	# shellcheck disable=SC2046
	if ! "$bin" -timeout="${FUZZ_TIMEOUT:-10}" -artifact_prefix="$B/findings/$t-" \
		$(find "$seeds" -type f | LC_ALL=C sort) >>"$log" 2>&1; then
		finding replay
	fi
fi
nseeds=$(find "$seeds" -type f 2>/dev/null | wc -l)
# shellcheck disable=SC2086
if ! "$bin" -max_total_time="${FUZZ_SECONDS:-60}" -timeout="${FUZZ_TIMEOUT:-10}" \
	-max_len="${FUZZ_MAX_LEN:-4096}" -dict="$B/dict/$t.dict" -artifact_prefix="$B/findings/$t-" \
	-print_final_stats=1 ${FUZZ_FLAGS:-} "$B/corpus/$t" "$seeds" >>"$log" 2>&1; then
	finding "random run"
fi
echo "fuzz $t: ok, $nseeds seeds replayed, $(sed -n 's/^stat::number_of_executed_units: *//p' "$log") runs" \
	"in ${FUZZ_SECONDS:-60} s, $(ls "$B/corpus/$t" | wc -l) inputs in its corpus"
