#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# The Python binding's tests (python/tests, pytest) against this build: the
# library of $B (LIBDF1_PATH) and the tools of $DF1_BIN (df1sim). Prints
# pytest's own summary line. Skips (exit 0, a SKIP line) only when python3,
# its cffi or pytest is missing. In the sanitizer build the library needs the
# sanitizer runtime loaded first: it is preloaded into python3, leak checking
# off (the interpreter keeps memory to the end on purpose).
# Run from the repository root.
B=${B:-build}
PY=${PYTHON:-python3}
if ! command -v "$PY" >/dev/null 2>&1; then
	echo "SKIP it_python: no $PY"
	exit 0
fi
for m in cffi pytest; do
	if ! "$PY" -c "import $m" >/dev/null 2>&1; then
		echo "SKIP it_python: $PY has no $m (apt-get install python3-cffi python3-pytest)"
		exit 0
	fi
done
LIBDF1_PATH=$(cd "$B" && pwd)
DF1_BIN=${DF1_BIN:-$LIBDF1_PATH/bin}
export LIBDF1_PATH DF1_BIN
if [ ! -f "$LIBDF1_PATH/libdf1.so.0" ]; then
	echo "it_python: $LIBDF1_PATH/libdf1.so.0 not built"
	exit 1
fi
preload=
if readelf -d "$LIBDF1_PATH/libdf1.so.0" 2>/dev/null | grep -q 'NEEDED.*libasan'; then
	preload=$(${CC:-cc} -print-file-name=libasan.so)
	export ASAN_OPTIONS="detect_leaks=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/df1py.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
# no .pyc files or cache in the tree
export PYTHONDONTWRITEBYTECODE=1
LD_PRELOAD=$preload "$PY" -m pytest -p no:cacheprovider -q -r fEs --basetemp="$T/pytest" python/tests \
	> "$T/log" 2>&1
rc=$?
# pytest's own output; its summary is the last line ("85 passed in 5.61s")
cat "$T/log"
exit $rc
