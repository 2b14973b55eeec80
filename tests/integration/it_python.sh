#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# The Python binding's tests (python/tests, pytest) against this build: the
# library of $B (LIBDF1_PATH) and the tools of $DF1_BIN (df1sim). Prints
# pytest's own output, then one check: pytest's exit status. Skips (exit 0, a
# SKIP line, nothing counted) only when python3, its cffi or pytest is missing. In the sanitizer build the library needs the
# sanitizer runtime loaded first: it is preloaded into python3, leak checking
# off (the interpreter keeps memory to the end on purpose).
# Run from the repository root.
B=${B:-build}
PY=${PYTHON:-python3}
LIBDF1_PATH=$(cd "$B" && pwd)
DF1_BIN=${DF1_BIN:-$LIBDF1_PATH/bin}
export LIBDF1_PATH DF1_BIN
. tests/support/lib.sh
if ! command -v "$PY" >/dev/null 2>&1; then
	skip "it_python: no $PY"
	exit 0
fi
for m in cffi pytest; do
	if ! "$PY" -c "import $m" >/dev/null 2>&1; then
		skip "it_python: $PY has no $m (apt-get install python3-cffi python3-pytest)"
		exit 0
	fi
done
if [ ! -f "$LIBDF1_PATH/libdf1.so.0" ]; then
	bad "it_python: $LIBDF1_PATH/libdf1.so.0 not built"
	finish
fi
preload=
if readelf -d "$LIBDF1_PATH/libdf1.so.0" 2>/dev/null | grep -q 'NEEDED.*libasan'; then
	preload=$(${CC:-cc} -print-file-name=libasan.so)
	export ASAN_OPTIONS="detect_leaks=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
fi
# no .pyc files or cache in the tree
export PYTHONDONTWRITEBYTECODE=1
LD_PRELOAD=$preload "$PY" -m pytest -p no:cacheprovider -q -r fEs --basetemp="$T/pytest" python/tests \
	> "$T/log" 2>&1
rc=$?
# pytest's own output; its summary is its last line ("85 passed in 5.61s")
cat "$T/log"
check "pytest python/tests: exit 0 (it said $rc)" '[ "$rc" -eq 0 ]'
finish
