#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# A run of df1write that starts on the TNS the previous run ended with, against
# one df1sim (duplicate detection on, its default), full and half duplex. Run 1's
# write is accepted (ACKed) but its reply is held back (--delay), and run 1 is
# stopped before the reply comes. Run 2's first command, another write, has the
# same SRC, CMD and TNS: df1sim ACKs and discards it as a duplicate (doc/PROTOCOL.md 1.7,
# KA p.117/118). The reply df1sim still holds is run 1's: sent to run 2, it made
# run 2 report a write that never ran (exit 0). Run 2 must time out (exit 1,
# unconfirmed), and the table must show run 1's write and not run 2's.
# DF1_TEST_FIRST_TNS (df1_new(3)) gives both runs the same first TNS.
# Run from the repository root; DF1_BIN = the built tools.
. tests/support/lib.sh
W="$BIN/df1write"
R="$BIN/df1read"
for t in df1write df1read df1sim; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE

for dx in full half; do
	# replies 2.5 s late; the tools wait 4 s
	sim_start "sim_$dx" --duplex "$dx" --delay 2500 --log "$T/$dx.log" || continue
	DF1_TEST_FIRST_TNS=0x4100 "$W" -vv -d "$SIM_DEV" --duplex "$dx" -o 4000 --cmd-timeout 4000 \
		N7:0=111 2> "$T/run1.err" &
	run1=$!
	wait_for "$dx: run 1's write ACKed" 100 grep -q "rx  ACK" "$T/run1.err"
	kill -INT "$run1" 2>/dev/null
	wait "$run1"
	expect 1 "$dx: run 2 on run 1's TNS: not confirmed" -- \
		env DF1_TEST_FIRST_TNS=0x4100 "$W" -d "$SIM_DEV" --duplex "$dx" -o 4000 --cmd-timeout 4000 N7:2=222
	err_has "$dx: run 2 reports its write unconfirmed" "unconfirmed: N7:2"
	expect 0 "$dx: read back" -- "$R" -d "$SIM_DEV" --duplex "$dx" -o 4000 --cmd-timeout 4000 N7:0,3
	out_is "$dx: run 1's write ran, run 2's was discarded" "111
1
2"
	sim_stop
done

# the same runs without a reply held back: run 2 is discarded too, and says so
sim_start sim_plain --log "$T/plain.log"
expect 0 "run 1 without a delay" -- env DF1_TEST_FIRST_TNS=0x4200 "$W" -d "$SIM_DEV" N7:5=555
expect 1 "run 2 on its TNS, reply already taken: not confirmed" -- \
	env DF1_TEST_FIRST_TNS=0x4200 "$W" -d "$SIM_DEV" N7:6=666
expect 0 "read back" -- "$R" -d "$SIM_DEV" N7:5,2
out_is "run 1's write ran, run 2's was discarded" "555
6"
sim_stop
finish
