#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# Runs every cmocka test binary (those TEST_BINS names, as make test-run
# gives them; without it every $B/tests/test_*) and every
# tests/integration/*.sh script. Last line: "N passed, N failed"; exit status
# non-zero if anything failed. Each PASS or FAIL line ends with the seconds
# the test took, to see where a run's time goes.
B=${B:-build}
export B
export DF1_BIN="$(cd "$B" && pwd)/bin"
export DF1_SHARED="${DF1_SHARED:-$(cd "$(dirname "$0")/../../shared" 2>/dev/null && pwd)}"
passed=0
failed=0
failures=""
log_dir="$B/test-logs"
mkdir -p "$log_dir"
for t in ${TEST_BINS:-"$B"/tests/test_*}; do
	[ -x "$t" ] || continue
	name=$(basename "$t")
	start=$(date +%s)
	if "$t" > "$log_dir/$name.log" 2>&1; then
		passed=$((passed + 1)); echo "PASS $name ($(($(date +%s) - start)) s)"
	else
		failed=$((failed + 1)); failures="$failures $name"; echo "FAIL $name ($(($(date +%s) - start)) s)"
		tail -n 40 "$log_dir/$name.log"
	fi
done
for t in tests/integration/*.sh; do
	[ -f "$t" ] || continue
	name=$(basename "$t" .sh)
	start=$(date +%s)
	if timeout 600 sh "$t" > "$log_dir/$name.log" 2>&1; then
		passed=$((passed + 1)); echo "PASS $name ($(($(date +%s) - start)) s)"
	else
		failed=$((failed + 1)); failures="$failures $name"; echo "FAIL $name ($(($(date +%s) - start)) s)"
		tail -n 40 "$log_dir/$name.log"
	fi
done
[ -n "$failures" ] && echo "failed:$failures"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
