#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# make install into a staging directory (DESTDIR, PREFIX=/usr), from a private
# build directory so that PREFIX is really the one built into libdf1.pc; then the
# installed tools run (--version, a read and a write against the installed
# df1sim), the man pages and the .pc file are where they belong with no trace of
# DESTDIR, and examples/read_n7.c compiles with pkg-config against the staged
# tree, linked both with the shared library (LD_LIBRARY_PATH into the stage) and
# statically, and reads N7:0..9 from df1sim. Finally make uninstall removes it.
# Run from the repository root.
. tests/support/lib.sh
STAGE="$T/stage"
BUILD="$T/build"
MAKE=${MAKE:-make}
JOBS=$(nproc 2>/dev/null || echo 2)
CC=${CC:-cc}

[ -f Makefile ] && [ -f examples/read_n7.c ] || { echo "run from the repository root"; exit 1; }
# a make of our own, not a part of the make that may be running this test
unset MAKEFLAGS MFLAGS MAKELEVEL MAKEOVERRIDES SAN EXTRA TOOLS_LIB
# nor the install directories of an outer build (a package build runs make
# check with its own LIBDIR, SYSTEMDUNITDIR ...: they reach us as variables
# of the environment); this test chooses its own
unset PREFIX BINDIR LIBDIR INCLUDEDIR MANDIR PKGCONFIGDIR SYSTEMDUNITDIR WIRESHARK_PLUGINDIR \
	DESTDIR MULTIARCH
# (variables given on the outer make command line, like SAN=1 for the
# sanitizer pass, reach us through the environment: the installed tree is
# what a user builds, without sanitizers)

if ! $MAKE -j"$JOBS" B="$BUILD" DESTDIR="$STAGE" PREFIX=/usr install > "$T/make.log" 2>&1; then
	bad "make install failed"
	tail -n 20 "$T/make.log"
	finish
fi
ok
U="$STAGE/usr"

# ---- what was installed, where ----
for f in bin/df1read bin/df1write bin/df1mon bin/df1sim bin/df1gw include/df1.h include/df1_catalog.h include/df1_eip.h include/df1_probe.h include/df1_server.h lib/libdf1.a \
	lib/pkgconfig/libdf1.pc share/man/man1/df1read.1 share/man/man1/df1write.1 \
	share/man/man1/df1mon.1 share/man/man1/df1sim.1 share/man/man1/df1gw.1 share/man/man7/libdf1.7 \
	share/man/man3/df1_open.3 share/man/man3/df1_read_int16.3; do
	check "installed $f" '[ -f "$U/$f" ]'
done
check "shared library and links" '[ -f "$U/lib/libdf1.so.0" ] && [ -L "$U/lib/libdf1.so" ]'
check "tools are executable" '[ -x "$U/bin/df1read" ] && [ -x "$U/bin/df1write" ]'
check "no DESTDIR in installed text files" \
	'! grep -r -l -F "$STAGE" "$U/lib/pkgconfig" "$U/include" "$U/share" >/dev/null 2>&1'
check ".pc prefix is /usr" 'grep -q "^prefix=/usr\$" "$U/lib/pkgconfig/libdf1.pc"'
UNIT="$U/lib/systemd/system/df1gw@.service"
check "the gateway's systemd unit, with the install's BINDIR" \
	'[ -f "$UNIT" ] && grep -q "^ExecStart=/usr/bin/df1gw \$DF1GW_OPTS\$" "$UNIT" && ! grep -q "@BINDIR@" "$UNIT"'
# systemd's own reading of the unit (unknown keys, bad values), against a copy
# whose ExecStart exists on this machine
if command -v systemd-analyze >/dev/null 2>&1; then
	mkdir -p "$T/unit"
	sed "s|^ExecStart=/usr/bin/df1gw|ExecStart=$(command -v true)|" "$UNIT" > "$T/unit/df1gw@.service"
	(cd "$T/unit" && systemd-analyze verify --man=no ./df1gw@.service) > "$T/verify" 2>&1
	check "systemd-analyze verify: the unit is clean" '[ ! -s "$T/verify" ]'
	[ -s "$T/verify" ] && sed 's/^/  verify: /' "$T/verify" | head -5
fi

# ---- the installed tools ----
expect 0 "installed df1read --version" -- "$U/bin/df1read" --version
check "df1read version text" 'grep -q "^df1read (libdf1) [0-9]" "$T/out"'
expect 0 "installed df1write --version" -- "$U/bin/df1write" --version
BIN="$U/bin"                   # sim_start uses the installed df1sim
sim_start inst || finish
expect 0 "installed df1write" -- "$U/bin/df1write" -d "$SIM_DEV" N7:9=-9
expect 0 "installed df1read" -- "$U/bin/df1read" -d "$SIM_DEV" N7:3 N7:9
out_is "installed df1read values" "3
-9"
expect 0 "installed df1mon --ping" -- "$U/bin/df1mon" -d "$SIM_DEV" --ping -c 1 --counters
check "installed df1mon: an answer and the counters" \
	'grep -q "^station 1: seq=1 link=" "$T/out" && grep -q "^2527 CNT_CMD_MSGS_SENT 1$" "$T/out"'

# ---- the example, built with pkg-config against the staged tree ----
if command -v pkg-config >/dev/null 2>&1; then
	flags=$(PKG_CONFIG_PATH="$U/lib/pkgconfig" PKG_CONFIG_LIBDIR="$U/lib/pkgconfig" \
		PKG_CONFIG_SYSROOT_DIR="$STAGE" pkg-config --cflags --libs libdf1)
	check "pkg-config found libdf1" '[ -n "$flags" ]'
	check "pkg-config flags point into the stage" 'echo "$flags" | grep -q -F -e "-I$U/include"'
	sflags=$(PKG_CONFIG_PATH="$U/lib/pkgconfig" PKG_CONFIG_LIBDIR="$U/lib/pkgconfig" \
		PKG_CONFIG_SYSROOT_DIR="$STAGE" pkg-config --cflags --static --libs libdf1)
else
	echo "note: no pkg-config; flags derived from the stage"
	flags="-I$U/include -L$U/lib -ldf1"
	sflags="$flags -lcsv -lm"
fi
# shellcheck disable=SC2086
expect 0 "example builds (shared)" -- $CC -std=c11 -Wall -Wextra -Werror -o "$T/read_n7" \
	examples/read_n7.c $flags
# the static build: the archive itself, then what Libs.private asks for
# shellcheck disable=SC2086
expect 0 "example builds (static libdf1)" -- $CC -std=c11 -Wall -Wextra -Werror \
	-I"$U/include" -o "$T/read_n7_static" examples/read_n7.c "$U/lib/libdf1.a" \
	$(echo "$sflags" | tr ' ' '\n' | grep -v -e '^-ldf1$' -e '^-I' -e '^-L' | tr '\n' ' ')
want_n7="N7:0 = 0
N7:1 = 1
N7:2 = 2
N7:3 = 3
N7:4 = 4
N7:5 = 5
N7:6 = 6
N7:7 = 7
N7:8 = 8
N7:9 = -9"
if [ -x "$T/read_n7" ]; then
	expect 0 "example runs (shared)" -- env LD_LIBRARY_PATH="$U/lib" "$T/read_n7" "$SIM_DEV" 1
	out_is "example output (shared)" "$want_n7"
	expect 1 "example: a device that does not exist" -- env LD_LIBRARY_PATH="$U/lib" \
		"$T/read_n7" "$T/nodev" 1
	check "example: error text" '[ -s "$T/err" ]'
	expect 2 "example: usage" -- env LD_LIBRARY_PATH="$U/lib" "$T/read_n7" "$SIM_DEV"
fi
if [ -x "$T/read_n7_static" ]; then
	expect 0 "example runs (static)" -- "$T/read_n7_static" "$SIM_DEV" 1
	out_is "example output (static)" "$want_n7"
fi
sim_stop

# an error reply through the example: station 9 on a half-duplex line nobody serves
sim_start half --duplex half --station 1 || finish
if [ -x "$T/read_n7_static" ]; then
	# the example keeps the defaults (full duplex): against a half-duplex slave the
	# read fails and the example reports it from df1_last_error
	expect 1 "example: no answer" -- "$T/read_n7_static" "$SIM_DEV" 9
	check "example: catalog tag, then the message naming the address and station" \
		'grep -q "read_n7[a-z_]*: \[25[0-9][0-9]\] [A-Z_]*: N7:0: .*station 9" "$T/err"'
	check "example: the address named once" '[ "$(grep -o "N7:0" "$T/err" | wc -l | tr -d " ")" -eq 1 ]'
fi
sim_stop

# ---- uninstall ----
if $MAKE B="$BUILD" DESTDIR="$STAGE" PREFIX=/usr uninstall > "$T/make.log" 2>&1; then
	ok
	left=$(find "$STAGE" -type f -o -type l)
	same "uninstall removed every file" "$left" ""
else
	bad "make uninstall failed"
	tail -n 10 "$T/make.log"
fi

finish
