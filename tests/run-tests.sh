#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# Runs every cmocka test binary (those TEST_BINS names, as make test-run
# gives them; without it every $B/tests/test_*) and every
# tests/integration/*.sh script. Last line: "N passed, N failed"; exit status
# non-zero if anything failed. Each PASS or FAIL line ends with the seconds
# the test took, to see where a run's time goes.
#
# TEST_JOBS=N runs up to N integration scripts at once (default 1: one after
# the other; the unit test binaries always run one at a time). Each script has
# its own temporary folder, ports the kernel picks and its own processes, so
# they can share a machine; their waits are bounded in tries scaled by
# DF1_TEST_SLACK (tests/support/lib.sh), so a loaded machine is slower, not
# failing. TEST_SCRIPTS="tests/integration/it_a.sh ..." runs those scripts
# instead of all of them (the Debian package's smoke check, debian/rules).
#
# `sh tests/run-tests.sh --one SCRIPT` runs one integration script as the
# runner does (its log, its PASS or FAIL line, its result in the log folder).
#
# For a build of another CPU run under qemu-user (scripts/cross-check.sh):
# TEST_WRAP is put before each test binary ("qemu-aarch64"),
# TEST_TOOLS_DIR replaces $B/bin as DF1_BIN (a folder of wrappers that run
# the tools under qemu), and TEST_SCRIPTS names the integration scripts to
# run ("none": none).
B=${B:-build}
export B
export DF1_BIN="${TEST_TOOLS_DIR:-$(cd "$B" && pwd)/bin}"
log_dir="$B/test-logs"
mkdir -p "$log_dir"

# one test: its output in $log_dir/NAME.log, "0" or "1" in $log_dir/NAME.result
run_one() {
	name=$1; shift
	start=$(date +%s)
	if "$@" > "$log_dir/$name.log" 2>&1; then
		echo 0 > "$log_dir/$name.result"
		echo "PASS $name ($(($(date +%s) - start)) s)"
	else
		echo 1 > "$log_dir/$name.result"
		# one block per failure, also when several scripts end at once
		{ echo "FAIL $name ($(($(date +%s) - start)) s)"; tail -n 40 "$log_dir/$name.log"; } > "$log_dir/$name.fail"
		cat "$log_dir/$name.fail"
	fi
}

if [ "${1:-}" = --one ]; then
	run_one "$(basename "$2" .sh)" timeout 600 sh "$2"
	exit 0
fi

rm -f "$log_dir"/*.result "$log_dir"/*.fail
# the unit tests one at a time: some time a real df1sim on a pty (unit/api,
# unit/link/test_wire_timing), and a second test beside them is load they
# were not written for
for t in ${TEST_BINS:-"$B"/tests/test_*}; do
	[ -x "$t" ] || continue
	# shellcheck disable=SC2086
	run_one "$(basename "$t")" ${TEST_WRAP:-} "$t"
done
# the longest scripts first, so that the last one to start is a short one
# (tests/integration/.order lists the long ones; the rest follow by name)
if [ -n "${TEST_SCRIPTS:-}" ]; then
	scripts=$TEST_SCRIPTS
	[ "$scripts" = none ] && scripts=
else
	scripts=$( { grep -v '^#' tests/integration/.order 2>/dev/null | sed 's|^|tests/integration/|'
		ls tests/integration/*.sh; } | awk '!seen[$0]++' | while read -r s; do [ -f "$s" ] && echo "$s"; done)
fi
printf '%s\n' $scripts | xargs -r -n 1 -P "${TEST_JOBS:-1}" sh "$0" --one

passed=0
failed=0
failures=""
for r in "$log_dir"/*.result; do
	[ -f "$r" ] || continue
	if [ "$(cat "$r")" = 0 ]; then
		passed=$((passed + 1))
	else
		failed=$((failed + 1)); failures="$failures $(basename "$r" .result)"
	fi
done
[ -n "$failures" ] && echo "failed:$failures"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
