#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# scripts/test-debian.sh - the Debian packages (debian/), built and tried:
#   1. debian/changelog's version is include/df1.h's DF1_VERSION_STRING;
#   2. debian/libdf1-0.symbols lists exactly the symbols libdf1.so exports
#      (nm -D), each a df1_* name of lib/libdf1.map's version node;
#   3. dpkg-buildpackage -us -uc -b in a scratch copy of the tree (nothing is
#      written beside the checkout), with the test suite at build time unless
#      DEB_BUILD_OPTIONS has nocheck;
#   4. lintian on the result: any E: line fails, W: lines are shown;
#   5. the packages unpacked into a scratch root (dpkg -x): the installed
#      df1read reads df1sim (both from df1-tools, on libdf1-0's library), and a
#      program compiled with `pkg-config --cflags --libs libdf1` from the
#      unpacked libdf1-dev reads it too;
#   6. with --install (as root, CI): `apt-get install ./*.deb` for real, the
#      same run against /usr, then the packages removed again.
# With --arch ARCH (arm64, armhf, ...: a cross build), step 3 is
# `dpkg-buildpackage -a ARCH -Pcross,nocheck -us -uc -b` (no tests at build
# time: make cross-check ARCH=... runs them under qemu), every .deb must say
# Architecture: ARCH (dpkg-deb -f) and its df1read be the target's machine
# code, and step 5 runs the unpacked tools and the pkg-config program (built
# with ARCH's cross compiler) under qemu-user; --install is for the build
# machine's own architecture only. Needs what make cross-check ARCH=...
# installs, and Build-Depends for ARCH (dpkg-checkbuilddeps -a ARCH -P cross,nocheck).
# Usage: sh scripts/test-debian.sh [--install] [--keep DIR] [--arch ARCH]
#        sh scripts/test-debian.sh --update-symbols   (rewrite the symbols file
#        from the built library, with the version of each symbol's "@since"
#        in include/df1*.h, 0.1.0 where none is given; run after adding API)
# Needs: dpkg-dev debhelper fakeroot lintian, and the Build-Depends.
set -u
cd "$(dirname "$0")/.." || exit 2
MODE=test
INSTALL=0
KEEP=
ARCH=
while [ $# -gt 0 ]; do
	case $1 in
	--update-symbols) MODE=symbols ;;
	--install) INSTALL=1 ;;
	--keep) KEEP=$2; shift ;;
	--arch) ARCH=${2:-}; shift ;;
	*) echo "usage: $0 [--install] [--keep DIR] [--arch ARCH] | --update-symbols" >&2; exit 2 ;;
	esac
	shift
done
BUILD_ARCH=$(dpkg-architecture -qDEB_BUILD_ARCH)
[ "$ARCH" = "$BUILD_ARCH" ] && ARCH=
RUN=            # what runs a program of the packages' architecture
XCC=${CC:-cc}   # what compiles one
if [ -n "$ARCH" ]; then
	TRIPLET=$(dpkg-architecture -a "$ARCH" -qDEB_HOST_GNU_TYPE 2> /dev/null) ||
		{ echo "test-debian: unknown architecture $ARCH" >&2; exit 2; }
	case $ARCH in
	arm64) RUN=qemu-aarch64 ;;
	armhf | armel) RUN=qemu-arm ;;
	*) RUN=qemu-$(dpkg-architecture -a "$ARCH" -qDEB_HOST_GNU_CPU) ;;
	esac
	XCC=$TRIPLET-gcc
	[ "$INSTALL" = 1 ] && { echo "test-debian: --install installs the build machine's packages only" >&2; exit 2; }
fi
fails=0
fail() { echo "test-debian: FAIL: $*"; fails=$((fails + 1)); }
pass() { echo "test-debian: ok: $*"; }

VERSION=$(sed -n 's/^#define DF1_VERSION_STRING "\(.*\)"/\1/p' include/df1.h)
MAJOR=${VERSION%%.*}
SYMBOLS=debian/libdf1-0.symbols

# the symbols file as it should be, from a freshly built library
# (this version's file by name: an older version's may still lie beside it)
LIB=build/deb-symbols/libdf1.so."$MAJOR".$(echo "$VERSION" | cut -d. -f2)
make -s B=build/deb-symbols "$LIB" > /dev/null || { echo "test-debian: cannot build the library" >&2; exit 1; }
want_symbols() {
	nm -D --defined-only "$LIB" | awk '{print $3}' | python3 -c '
import re, sys
import glob
hdr = "\n".join(open(f).read() for f in sorted(glob.glob("include/df1*.h"))).split("\n")
since = {}
block = []
for line in hdr:
    s = line.strip()
    if s.startswith("/*") or s.startswith("*") or s.endswith("*/"):
        block.append(s)
        continue
    m = re.search(r"\b(df1_\w+)\s*\(", line) if "DF1_API" in line else None
    if m:
        # the comment right above the declaration (or a group of them) says
        v = re.findall(r"@since (\d+)\.(\d+)", " ".join(block) + line)
        if v:
            since[m.group(1)] = "%s.%s.0" % v[-1]
        block = []
    elif s == "":
        block = []      # a blank line ends a group: its notes are not for the next
soname = sys.argv[1]
print("%s libdf1-0 #MINVER#" % soname)
print("* Build-Depends-Package: libdf1-dev")
for sym in sorted(x.strip() for x in sys.stdin if x.strip()):
    name, _, node = sym.partition("@@")
    if not node:
        name, _, node = sym.partition("@")
    if not node:
        node = name    # the version node itself
    if name == node:
        print(" %s@%s 0.1.0" % (name, node))
    else:
        print(" %s@%s %s" % (name, node, since.get(name, "0.1.0")))
' "libdf1.so.$MAJOR"
}
if [ "$MODE" = symbols ]; then
	want_symbols > "$SYMBOLS" && echo "test-debian: wrote $SYMBOLS ($(grep -c '^ ' "$SYMBOLS") symbols)"
	exit $?
fi

T=$(mktemp -d "${TMPDIR:-/tmp}/df1deb.XXXXXX") || exit 1
sim=
cleanup() {
	[ -n "$sim" ] && kill "$sim" 2>/dev/null && wait "$sim" 2>/dev/null
	[ -n "$KEEP" ] && { mkdir -p "$KEEP" && cp "$T"/*.deb "$KEEP"/ 2>/dev/null; }
	rm -rf "$T"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# 1. versions in step
CHV=$(dpkg-parsechangelog -l debian/changelog -S Version)
if [ "$CHV" = "$VERSION" ]; then
	pass "debian/changelog version $CHV = df1.h"
else
	fail "debian/changelog says $CHV, include/df1.h $VERSION: add a changelog entry (dch -v $VERSION)"
fi

# 2. symbols: the file, the library, the map
want_symbols > "$T/symbols.want"
if diff -u "$SYMBOLS" "$T/symbols.want" > "$T/symbols.diff"; then
	pass "$SYMBOLS lists the $(grep -c '^ ' "$SYMBOLS") exported symbols"
else
	fail "$SYMBOLS differs from what libdf1.so exports (+ to add, - to remove):"
	sed -n 's/^\([+-] .*\)/    \1/p' "$T/symbols.diff"
	echo "    regenerate it with: sh scripts/test-debian.sh --update-symbols"
fi
node=$(sed -n 's/^\([A-Z0-9_]*\) {.*/\1/p' lib/libdf1.map | head -n 1)
bad=$(grep '^ ' "$SYMBOLS" | awk '{print $1}' | grep -v "^df1_[a-z0-9_]*@$node\$" | grep -v "^$node@$node\$")
[ -z "$bad" ] && pass "every symbol is a df1_* of version node $node (lib/libdf1.map)" \
	|| fail "symbols outside lib/libdf1.map's df1_* in $node: $bad"

# 3. build in a scratch copy of the tracked tree (plus what is changed in it)
SRC="$T/libdf1-$VERSION"
mkdir -p "$SRC"
git ls-files -z --cached --others --exclude-standard | (cd "$SRC" && xargs -0 -I{} sh -c 'mkdir -p "$(dirname "{}")"' ) 2>/dev/null
git ls-files -z --cached --others --exclude-standard | xargs -0 sh -c 'for f; do [ -e "$f" ] || [ -L "$f" ] && cp -P "$f" "'"$SRC"'/$f"; done' sh
DPKG_BP="dpkg-buildpackage -us -uc -b"
[ -n "$ARCH" ] && DPKG_BP="dpkg-buildpackage -a $ARCH -Pcross,nocheck -us -uc -b"
echo "test-debian: $DPKG_BP (DEB_BUILD_OPTIONS=${DEB_BUILD_OPTIONS:-})"
start=$(date +%s)
# shellcheck disable=SC2086
if (cd "$SRC" && $DPKG_BP) > "$T/build.log" 2>&1; then
	pass "dpkg-buildpackage in $(( $(date +%s) - start )) s"
else
	fail "dpkg-buildpackage (last lines of its log:)"
	tail -n 40 "$T/build.log"
	exit 1
fi
grep -E "^[0-9]+ passed, [0-9]+ failed$" "$T/build.log" | sed 's/^/test-debian: build-time tests: /'
ls "$T"/*.deb | sed 's|.*/|test-debian: built |'
if [ -n "$ARCH" ]; then
	for d in "$T"/*.deb; do
		a=$(dpkg-deb -f "$d" Architecture)
		[ "$a" = "$ARCH" ] || fail "${d##*/} says Architecture: $a, not $ARCH"
	done
	pass "every .deb says Architecture: $ARCH (dpkg-deb -f)"
fi

# 4. lintian
lintian --tag-display-limit 0 "$T"/libdf1_"$VERSION"_*.changes > "$T/lintian.txt" 2>&1
if grep -q '^E:' "$T/lintian.txt"; then
	fail "lintian errors:"
	grep '^E:' "$T/lintian.txt"
else
	pass "lintian: no errors"
fi
grep -E '^[WI]:' "$T/lintian.txt" | sed 's/^/test-debian: lintian: /'

# 5. unpacked into a scratch root
ROOT="$T/root"
for d in "$T"/*.deb; do dpkg -x "$d" "$ROOT"; done
MA=$(dpkg-architecture ${ARCH:+-a "$ARCH"} -qDEB_HOST_MULTIARCH 2> /dev/null)
if [ -n "$ARCH" ]; then
	m=$(file -b "$ROOT/usr/bin/df1read" 2> /dev/null | cut -d, -f1-2)
	[ -n "$m" ] && echo "test-debian: /usr/bin/df1read: $m"
	command -v "$RUN" > /dev/null 2>&1 || { fail "$RUN (qemu-user) is missing: apt-get install qemu-user"; RUN=false; }
fi
for f in usr/lib/"$MA"/libdf1.so.0 usr/include/df1.h usr/lib/"$MA"/pkgconfig/libdf1.pc \
	usr/bin/df1read usr/bin/df1gw usr/share/man/man1/df1read.1.gz usr/share/man/man3/df1_open.3.gz \
	lib/systemd/system/df1gw@.service usr/lib/"$MA"/wireshark/plugins/df1.lua; do
	[ -e "$ROOT/$f" ] || fail "not in the packages: /$f"
done
try_installed() { # PREFIXROOT LIBPATH: df1read and a pkg-config program against df1sim
	r=$1
	rm -f "$T/sim.out"
	mkfifo "$T/sim.out"
	# shellcheck disable=SC2086
	LD_LIBRARY_PATH=$2 $RUN "$r/usr/bin/df1sim" --pty "$T/plc" --data "$T/data" > "$T/sim.out" 2> "$T/sim.err" &
	sim=$!
	line=
	IFS= read -r line < "$T/sim.out" || line=
	if [ "$line" != "$T/plc" ]; then
		fail "installed df1sim did not start: $(cat "$T/sim.err")"
		return
	fi
	# shellcheck disable=SC2086
	got=$(LD_LIBRARY_PATH=$2 $RUN "$r/usr/bin/df1read" -d "$T/plc" N7:0 N7:1)
	[ "$got" = "$(printf '1234\n-5')" ] && pass "$3: df1read reads df1sim" \
		|| fail "$3: df1read printed '$got'"
	if [ -n "$RUN" ]; then  # ldd is the build machine's: the guest's loader lists the libraries
		$RUN -E LD_TRACE_LOADED_OBJECTS=1 -E LD_LIBRARY_PATH="$2" "$r/usr/bin/df1read" 2>&1 | grep -q "libdf1.so.0 => $2" \
			&& pass "$3: df1read uses libdf1-0's library" || fail "$3: df1read does not load $2/libdf1.so.0"
	else
		LD_LIBRARY_PATH=$2 ldd "$r/usr/bin/df1read" | grep -q "libdf1.so.0 => $2" \
			&& pass "$3: df1read uses libdf1-0's library" || fail "$3: df1read does not load $2/libdf1.so.0"
	fi
	if [ "$r" = / ]; then pc="pkg-config"; else
		pc="env PKG_CONFIG_SYSROOT_DIR=$r PKG_CONFIG_LIBDIR=$r/usr/lib/$MA/pkgconfig pkg-config"; fi
	# shellcheck disable=SC2046
	if $XCC -std=c11 -o "$T/read_n7" examples/read_n7.c $($pc --cflags --libs libdf1) 2> "$T/cc.err"; then
		# shellcheck disable=SC2086
		out=$(LD_LIBRARY_PATH=$2 $RUN "$T/read_n7" "$T/plc" 1 2>&1)
		echo "$out" | grep -q "1234" && pass "$3: a program built with pkg-config libdf1 reads df1sim" \
			|| fail "$3: read_n7 printed: $out"
	else
		fail "$3: compiling with pkg-config libdf1: $(cat "$T/cc.err")"
	fi
	kill "$sim" 2>/dev/null && wait "$sim" 2>/dev/null
	sim=
}
printf 'N7:0=1234,-5\n' > "$T/data"
try_installed "$ROOT" "$ROOT/usr/lib/$MA" "dpkg -x"

# 6. a real installation
if [ "$INSTALL" = 1 ]; then
	if [ "$(id -u)" -ne 0 ]; then
		fail "--install needs root"
	elif (cd "$T" && DEBIAN_FRONTEND=noninteractive apt-get install -y -q ./df1-tools_*.deb \
		./libdf1-0_*.deb ./libdf1-dev_*.deb) > "$T/apt.log" 2>&1; then
		pass "apt-get install ./df1-tools_*.deb ./libdf1-0_*.deb ./libdf1-dev_*.deb"
		try_installed / "/usr/lib/$MA" "installed"
		command -v systemd-analyze >/dev/null 2>&1 && {
			systemd-analyze verify /lib/systemd/system/df1gw@.service > "$T/sa.log" 2>&1 \
				&& pass "systemd-analyze verify df1gw@.service" \
				|| { grep -q "df1gw" "$T/sa.log" && fail "systemd-analyze: $(cat "$T/sa.log")" \
				     || pass "systemd-analyze verify (no remarks on df1gw)"; }
		}
		DEBIAN_FRONTEND=noninteractive apt-get purge -y -q df1-tools libdf1-dev libdf1-0 > /dev/null 2>&1 \
			&& pass "packages removed again" || fail "apt-get purge"
	else
		fail "apt-get install of the packages:"
		tail -n 20 "$T/apt.log"
	fi
fi
[ "$fails" -eq 0 ] && echo "test-debian: all passed" || echo "test-debian: $fails failed"
[ "$fails" -eq 0 ]
