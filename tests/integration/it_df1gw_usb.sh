#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_df1gw_usb.sh - df1gw shows the port's note (df1_port_note, libdf1(7) USB
# ADAPTERS) where its status is read: /api/status (line.port_note, read with
# Python's json), the summary that the page and systemd's STATUS= show, and
# --counters. As in it_usb_latency.sh a df1sim pseudo-terminal stands for
# the adapter and a fake sysfs tree (DF1_TEST_SYSFS_ROOT, the library's
# test-only root) lists it as usb-serial port ttyUSB9 with a latency timer of
# 16 ms that a pty cannot lower; with 1 ms there is no note. Waits are bounded
# loops. Run from the repository root with DF1_BIN=<build/bin>.
. tests/support/lib.sh

GW="$BIN/df1gw"
[ -x "$GW" ] || { echo "no $GW"; exit 1; }

gw_start() {
	gname=$1; shift
	"$GW" "$@" > "$T/$gname.out" 2> "$T/$gname.err" &
	GW_PID=$!
	echo "$GW_PID" >> "$T/.sims"
	wait_for "df1gw $gname says where HTTP listens" 100 gw_addr "$gname"
}
gw_addr() {
	HTTP=$(sed -n 's|^df1gw: HTTP on \([^ ]*\) .*|\1|p' "$T/$1.err" 2>/dev/null | head -n 1)
	[ -n "$HTTP" ]
}
# status KEY: line.KEY (or the summary, KEY "summary") of /api/status, "None" for null
status() {
	python3 - "$HTTP" "$1" <<'PY'
import json, sys, urllib.request
st = json.load(urllib.request.urlopen("http://%s/api/status" % sys.argv[1], timeout=10))
print(st["summary"] if sys.argv[2] == "summary" else st["line"].get(sys.argv[2], "absent"))
PY
}
line_up() { [ "$(status up 2>/dev/null)" = True ]; }

printf 'N7:0=1234\n' > "$T/data"
printf 'Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms\nSpeed,Read,INT,1,SLC,N7:0,1,100\n' > "$T/map.csv"
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

gw_start slow -d "$D" --map "$T/map.csv" --eip 0 --http 0 --counters
wait_for "the line is up" 100 line_up
status port_note > "$T/note"
check "/api/status line.port_note names the file" "grep -qF 'latency timer $TIMER' '$T/note'"
check "... and the udev rule" "grep -qF 'ATTR{latency_timer}=\"1\"' '$T/note'"
check "... and how long" "grep -qF 'up to 16 ms' '$T/note'"
status summary > "$T/summary"
check "the summary (page, STATUS=) says it after the line's state" \
	"grep -q '^line ok.*; .*USB adapter ttyUSB9 holds received bytes up to 16 ms' '$T/summary'"
kill -TERM "$GW_PID" 2>/dev/null
lib_reap "$GW_PID"
check "--counters prints the note" "grep -qF 'port note: ' '$T/slow.out' && grep -qF 'latency timer $TIMER' '$T/slow.out'"

echo 1 > "$TIMER"
gw_start fast -d "$D" --map "$T/map.csv" --eip 0 --http 0 --counters
wait_for "the line is up (1 ms)" 100 line_up
same "1 ms: line.port_note is null" "$(status port_note)" None
check "1 ms: the summary says nothing of it" "! status summary | grep -q 'USB adapter'"
kill -TERM "$GW_PID" 2>/dev/null
lib_reap "$GW_PID"
check "1 ms: --counters has no note" "! grep -q 'port note' '$T/fast.out'"

sim_stop
finish
