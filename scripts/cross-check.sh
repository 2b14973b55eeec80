#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# scripts/cross-check.sh - the tree built for another CPU with Debian's cross
# compiler and the target's own libraries (multiarch), its tests run under
# qemu-user (make cross-check ARCH=...):
#   arm64  aarch64-linux-gnu    64-bit, little-endian, char unsigned
#   armhf  arm-linux-gnueabihf  32-bit long and pointers, char unsigned
#   s390x  s390x-linux-gnu      64-bit, big-endian (DF1 is little-endian on
#                               the wire: tests/data/vectors.txt fails here
#                               if an encoder used the host's byte order)
# It builds the library, the tools and the unit tests into B (default
# build/cross-ARCH) with CC, AR and PKG_CONFIG of the target, then runs with
# tests/run-tests.sh, each under qemu-ARCH: the unit tests (which
# include the vector tests of tests/unit/proto) and the integration scripts
# that need only pseudo-terminals, loopback TCP and the tools against each
# other (IT_LIST below). The tools' folder given to the tests as DF1_BIN holds
# shell wrappers that exec qemu on the real binaries, so df1sim started by a
# test (tests/support/simproc.c, tests/support/lib.sh) runs on the target CPU
# too. The last line is the runner's "N passed, N failed".
#
# df1gw and its unit tests need five more -dev packages of the target
# (libmosquitto, libssl, libprotobuf-c, libmicrohttpd, libsqlite3); where
# they cannot be installed (s390x on Debian bookworm: its security updates
# are not published for s390x, and the target's library must be the same
# version as the machine's own), df1gw is left out and the output says so.
#
# --quick (CI): only the static library, the tools the unit tests start
# (df1sim, df1write, df1mon; df1read with them) and the unit tests, without
# df1gw's; no integration script.
#
# Missing packages are installed as scripts/deps.sh does (root, or sudo
# without a password: dpkg --add-architecture ARCH, apt-get update, apt-get
# install), else the exact commands are printed and it fails with status 3
# (nothing was built or run; 1: the build or a test failed). A target's
# library must be the same version as the machine's own (Multi-Arch: same):
# while the machine has a security update that the target's archive lacks
# (bookworm's s390x), apt-get refuses it.
# Usage: sh scripts/cross-check.sh ARCH [--quick]     (B=... for another folder)
set -u
cd "$(dirname "$0")/.." || exit 2
ARCH=${1:-}
QUICK=0
[ "${2:-}" = --quick ] && QUICK=1
case $ARCH in
arm64) TRIPLET=aarch64-linux-gnu QEMU=qemu-aarch64 ;;
armhf) TRIPLET=arm-linux-gnueabihf QEMU=qemu-arm ;;
s390x) TRIPLET=s390x-linux-gnu QEMU=qemu-s390x ;;
*) echo "usage: $0 arm64|armhf|s390x [--quick]" >&2; exit 2 ;;
esac
B=${B:-build/cross-$ARCH}
start=$(date +%s)

# --- the packages -----------------------------------------------------------
# the target's C compiler and qemu on this machine; the target's libraries
# (multiarch: they and the target's C library, libc6:ARCH, go to
# /usr/lib/TRIPLET, and its dynamic loader to /lib, where qemu finds them;
# qemu's -L SYSROOT is not used: with it, qemu 7.2 hangs a forked child
# before its exec, and the tests fork df1sim)
need_base="crossbuild-essential-$ARCH qemu-user libc6:$ARCH pkg-config:$ARCH libcsv-dev:$ARCH libcmocka-dev:$ARCH"
need_gw="libmosquitto-dev:$ARCH libssl-dev:$ARCH libprotobuf-c-dev:$ARCH libmicrohttpd-dev:$ARCH libsqlite3-dev:$ARCH protobuf-c-compiler"
missing() { for p in "$@"; do dpkg -s "$p" > /dev/null 2>&1 || printf ' %s' "$p"; done; }
as=
if [ "$(id -u)" = 0 ]; then
	as=env
elif command -v sudo > /dev/null 2>&1 && sudo -n true 2> /dev/null; then
	as="sudo -n"
fi
updated=0
apt_ready() { # the target's architecture known to dpkg, the lists fetched once
	[ -n "$as" ] && command -v apt-get > /dev/null 2>&1 || return 1
	if ! dpkg --print-foreign-architectures | grep -qx "$ARCH"; then
		echo "cross-check: dpkg --add-architecture $ARCH" >&2
		$as dpkg --add-architecture "$ARCH" || return 1
		updated=0
	fi
	[ "$updated" = 1 ] || { $as apt-get update -q > /dev/null 2>&1 || true; updated=1; }
}
# shellcheck disable=SC2086
base_missing=$(missing $need_base)
if [ -n "$base_missing" ]; then
	echo "cross-check: installing:$base_missing" >&2
	# shellcheck disable=SC2086
	if ! { apt_ready && $as DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
		$base_missing > "${TMPDIR:-/tmp}/cross-check-apt.$$" 2>&1; }; then
		tail -n 5 "${TMPDIR:-/tmp}/cross-check-apt.$$" 2> /dev/null
		rm -f "${TMPDIR:-/tmp}/cross-check-apt.$$"
		sudo=
		[ "$(id -u)" = 0 ] || sudo="sudo "
		echo "cross-check: missing:$base_missing" >&2
		echo "cross-check: run: ${sudo}dpkg --add-architecture $ARCH && ${sudo}apt-get update &&" \
			"${sudo}apt-get install$base_missing" >&2
		exit 3
	fi
	rm -f "${TMPDIR:-/tmp}/cross-check-apt.$$"
fi
GW=0
if [ "$QUICK" = 0 ]; then
	# shellcheck disable=SC2086
	gw_missing=$(missing $need_gw)
	if [ -z "$gw_missing" ]; then
		GW=1
	elif apt_ready && $as apt-get install -s -q $gw_missing > /dev/null 2>&1; then
		echo "cross-check: installing (df1gw):$gw_missing" >&2
		# shellcheck disable=SC2086
		$as DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $gw_missing \
			> /dev/null 2>&1 && GW=1
	fi
	[ "$GW" = 1 ] || echo "cross-check: df1gw left out: its libraries for $ARCH do not install here" \
		"(apt-get install$gw_missing)"
fi

# --- the build --------------------------------------------------------------
VERSION=$(sed -n 's/^#define DF1_VERSION_STRING "\(.*\)"/\1/p' include/df1.h)
SO=$B/libdf1.so.$(echo "$VERSION" | cut -d. -f1-2)
tests=
for f in tests/unit/*/test_*.c; do
	case $f in tests/unit/df1gw/*) [ "$GW" = 1 ] || continue ;; esac
	n=${f##*/}
	tests="$tests $B/tests/${n%.c}"
done
# the unit tests start df1sim, df1write and df1mon (tests/support/simproc.c)
targets="$B/libdf1.a $B/bin/df1read $B/bin/df1write $B/bin/df1mon $B/bin/df1sim"
if [ "$QUICK" = 0 ]; then
	targets="$targets $SO"
	[ "$GW" = 1 ] && targets="$targets $B/bin/df1gw"
fi
echo "cross-check: $ARCH: building with $TRIPLET-gcc into $B"
mkdir -p "$B"   # its log sits beside it: a fresh clone has no build/ yet
# shellcheck disable=SC2086
make -j"${JOBS:-2}" B="$B" CC="$TRIPLET-gcc" AR="$TRIPLET-ar" PKG_CONFIG="$TRIPLET-pkg-config" \
	WERROR=-Werror $targets $tests > "$B.log" 2>&1 || {
	tail -n 40 "$B.log"
	echo "cross-check: $ARCH: the build failed (log: $B.log)"
	exit 1
}
built=$(date +%s)
echo "cross-check: $ARCH: built in $((built - start)) s (packages included): $(echo $targets | wc -w) targets," \
	"$(echo $tests | wc -w) unit tests"

# --- the run ----------------------------------------------------------------
# tools/ as the tests see them: each a wrapper running the target's binary
WRAP="$B/qemu-bin"
rm -rf "$WRAP"
mkdir -p "$WRAP"
for t in "$B"/bin/*; do
	[ -x "$t" ] || continue
	printf '#!/bin/sh\nexec %s %s "$@"\n' "$QEMU" "$(cd "$B/bin" && pwd)/${t##*/}" \
		> "$WRAP/${t##*/}"
	chmod 755 "$WRAP/${t##*/}"
done
# the integration scripts that need only ptys, loopback TCP and the tools
# (df1read, df1write, df1mon, df1sim) against each other
IT_LIST="it_df1read it_df1write it_df1sim it_df1sim_fdx it_df1sim_ramp it_df1mon_decode it_dup_tns
	it_poll it_pipeline it_plc5_timers it_settings it_autoconf"
its=none
if [ "$QUICK" = 0 ]; then
	its=
	for s in $IT_LIST; do its="$its tests/integration/$s.sh"; done
fi
gwnote=
[ "$GW" = 1 ] || gwnote=" (df1gw's left out)"
echo "cross-check: $ARCH: under $QEMU: $(echo $tests | wc -w) unit tests$gwnote"
if [ "$QUICK" = 1 ]; then
	echo "cross-check: $ARCH: integration scripts: none (--quick)"
else
	echo "cross-check: $ARCH: integration scripts:" $IT_LIST
fi
TEST_WRAP="$QEMU" TEST_TOOLS_DIR="$(cd "$WRAP" && pwd)" TEST_SCRIPTS="$its" \
	TEST_BINS="$tests" B="$B" sh tests/run-tests.sh
rc=$?
echo "cross-check: $ARCH: $(($(date +%s) - start)) s in all ($(($(date +%s) - built)) s of tests)"
exit $rc
