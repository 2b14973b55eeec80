#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# USB serial adapters (libdf1(7) USB ADAPTERS) as a user of the tools sees
# them: a df1sim pseudo-terminal stands for the adapter and a fake sysfs tree
# (DF1_TEST_SYSFS_ROOT, the library's test-only root) lists it as usb-serial
# port ttyUSB9 with a latency_timer of 16 ms. A pty has no TIOCSSERIAL, so the
# timer stays: df1read -v and df1mon -v say so once, naming the file and the
# udev rule, and read the value all the same; --low-latency no, a timer of
# 1 ms and no -v say nothing; a bad --low-latency value is a usage error.
# Run from the repository root.
. tests/support/lib.sh
R="$BIN/df1read"
M="$BIN/df1mon"
for t in df1read df1mon df1sim; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE

printf 'N7:0=1234\n' > "$T/data"
sim_start usb --data "$T/data" || { finish; exit 1; }
D=$SIM_DEV

# the fake tree: dev/char/MAJ:MIN/uevent names ttyUSB9, bus/usb-serial lists it
set -- $(stat -L -c '%t %T' "$D")
MM="$(printf '%d:%d' "0x$1" "0x$2")"
S="$T/sys"
mkdir -p "$S/dev/char/$MM" "$S/bus/usb-serial/devices/ttyUSB9"
printf 'MAJOR=%s\nMINOR=%s\nDEVNAME=ttyUSB9\n' "${MM%:*}" "${MM#*:}" > "$S/dev/char/$MM/uevent"
TIMER="$S/bus/usb-serial/devices/ttyUSB9/latency_timer"
echo 16 > "$TIMER"
export DF1_TEST_SYSFS_ROOT="$S"

expect 0 "df1read -v, 16 ms timer" -- "$R" -v -d "$D" N7:0
out_is "df1read -v reads all the same" "1234"
err_has "df1read -v names the file" "latency timer $TIMER"
err_has "df1read -v names the rule" 'ATTR{latency_timer}="1"'
err_has "df1read -v says how long" "up to 16 ms"
same "said once" "$(grep -c 'latency timer' "$T/err")" 1

expect 0 "df1mon -v --ping, 16 ms timer" -- "$M" -v -d "$D" --ping --count 1
err_has "df1mon -v names the file" "latency timer $TIMER"
err_has "df1mon -v names the device" "df1mon: $D: USB adapter ttyUSB9"

expect 0 "df1read without -v" -- "$R" -d "$D" N7:0
same "quiet without -v" "$(cat "$T/err")" ""

expect 0 "df1read --low-latency no" -- "$R" -v --low-latency no -d "$D" N7:0
check "--low-latency no says nothing" "! grep -q 'latency timer' '$T/err'"

echo 1 > "$TIMER"
expect 0 "df1read -v, 1 ms timer" -- "$R" -v -d "$D" N7:0
check "1 ms says nothing" "! grep -q 'latency timer' '$T/err'"

expect 2 "--low-latency maybe" -- "$R" --low-latency maybe -d "$D" N7:0
err_has "bad value named" "--low-latency"
check "--help lists it" "'$R' --help | grep -q -- '--low-latency yes|no'"

sim_stop
finish
