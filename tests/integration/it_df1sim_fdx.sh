#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# df1sim as a full-duplex UART (df1sim(1) --line-baud): on a pty in full duplex
# each direction is paced on its own, so a master that sends while df1sim sends
# (tests/support/fdx_master.py, itself paced as a 4800-baud UART: long writes and
# long reads in turn, each message after the ACK of the one before) takes less
# than the two directions' wire times added up, and never less than the busier
# direction's own. The same master against df1sim --listen (the library's
# pacing, one thread for both directions) takes longer. Values are checked by the
# master (what each write put is what the next read returns). Bounds are
# generous: 0.95 of the sum, 0.95 of the one-direction time.
. tests/support/lib.sh
[ -x "$BIN/df1sim" ] || { echo "no $BIN/df1sim"; exit 1; }
command -v python3 >/dev/null 2>&1 || { skip "python3 missing"; finish; exit 1; }
M="python3 tests/support/fdx_master.py"
BAUD=4800

# "elapsed S tx N rx N" -> checks; sets E (the elapsed seconds)
judge() {
	label=$1; line=$2
	set -- $line
	E=$2
	awk -v lbl="$label" -v e="$2" -v tx="$4" -v rx="$6" -v b="$BAUD" 'BEGIN {
		sum = (tx + rx) * 10 / b; one = (tx > rx ? tx : rx) * 10 / b
		printf "  %s: %.3f s, sum %.3f s (%.2f), one direction %.3f s (%.2f)\n", lbl, e, sum, e / sum, one, e / one
	}'
}

sim_start fdx --line-baud $BAUD --max-queue 8 || { finish; exit 1; }
expect 0 "paced master against the full-duplex UART" -- $M "$SIM_DEV" $BAUD 3
LINE=$(cat "$T/out")
judge pty "$LINE"
E_PTY=$E
set -- $LINE
check "both directions overlap: under 0.95 of the sum" \
	"awk -v e=$2 -v tx=$4 -v rx=$6 -v b=$BAUD 'BEGIN { exit !(e < 0.95 * (tx + rx) * 10 / b) }'"
check "no faster than the busier direction's wire time" \
	"awk -v e=$2 -v tx=$4 -v rx=$6 -v b=$BAUD 'BEGIN { m = tx > rx ? tx : rx; exit !(e >= 0.95 * m * 10 / b) }'"
sim_stop

SIM_TRANSPORT=tcp sim_start fdxtcp --line-baud $BAUD --max-queue 8 || { finish; exit 1; }
PORT=${SIM_DEV##*:}
expect 0 "the same master against the library's one-thread pacing" -- $M "tcp:$PORT" $BAUD 3
judge tcp "$(cat "$T/out")"
check "the full-duplex UART is the faster" "awk -v a=$E_PTY -v b=$E 'BEGIN { exit !(a < b) }'"
sim_stop
finish
