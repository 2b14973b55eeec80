#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_unsolicited - a controller that speaks first, in full duplex: df1sim
# --msg (its MSG writes N7:0,10 with a running number in N7:0, every 100 ms)
# into the N50 file served by examples/msg_receiver.c through
# df1_set_responder(3), while the same handle polls df1sim with the poll
# engine (--outstanding 1 and 4, and under df1sim's NAK, drop-ACK and
# corrupt-reply faults, 10 % each). Every message lands exactly once and in order
# (the receiver's "recv" lines carry the numbers 1, 2, 3 ...), df1sim sees DN
# for each (its stderr, the MSG block's view: only the one the receiver may
# have taken as it quit can end otherwise), and the receiver's polls get
# through. A write to a file the receiver does not serve (N51) gets STS F0 /
# EXT STS 06 (no such file) and df1sim reports ER with that code.
# Run from the repository root with B=<build dir> and DF1_BIN=<build/bin>.
. tests/support/lib.sh
RX=${B:-build}/examples/msg_receiver
[ -x "$RX" ] || { bad "$RX not built (make tests)"; finish; }

# run NAME OUTSTANDING [DF1SIM FAULT OPTIONS...]
run() {
	name=$1; out=$2; shift 2
	sim_start "$name" --station 1 --msg write,N7:0,10,0,N50:0,100,seq "$@" || return 1
	"$RX" "$SIM_DEV" 1 10 4 "$out" > "$T/$name.rx" 2> "$T/$name.rxerr"
	rc=$?
	sim_stop "$SIM_PID"
	check "$name: the receiver ran (status $rc)" "[ $rc -eq 0 ]"
	# the numbers that landed, in arrival order, and those df1sim saw DN for
	awk '$1 == "recv" && $3 == "N50:0" { print $4 }' "$T/$name.rx" > "$T/$name.got"
	sed -n 's/^df1sim: MSG write .*(first \([0-9]*\)): DN$/\1/p' "$T/$name.err" > "$T/$name.dn"
	got=$(wc -l < "$T/$name.got"); dn=$(wc -l < "$T/$name.dn")
	check "$name: at least 20 messages landed ($got)" "[ $got -ge 20 ]"
	check "$name: each landed once, in order (1..$got)" "seq 1 $got | cmp -s - '$T/$name.got'"
	check "$name: DN for each ($dn of $got)" "seq 1 $dn | cmp -s - '$T/$name.dn' && [ $got -le \$(($dn + 1)) ]"
	# an ER may only be the last message, when the receiver had quit
	er=$(sed -n 's/^df1sim: MSG write .*(first \([0-9]*\)): ER.*/\1/p' "$T/$name.err" | awk -v d="$dn" '$1 <= d' | wc -l)
	check "$name: no MSG ended in error while the receiver ran" "[ $er -eq 0 ]"
	reads=$(sed -n 's/^reads //p' "$T/$name.rx")
	check "$name: the receiver's polls got through (${reads:-none})" "[ \"\${reads:-0}\" -ge 10 ]"
}

run plain 1
run pipelined 4
run faults 1 --nak 10 --drop-ack 10 --corrupt 10 --seed 7
run faults-pipelined 4 --nak 10 --drop-ack 10 --corrupt 10 --seed 11

# a write outside what the receiver serves: STS F0, EXT STS 06 (no such file)
if sim_start outside --station 1 --msg write,N7:0,10,0,N51:0,200; then
	"$RX" "$SIM_DEV" 1 10 2 > "$T/outside.rx" 2> "$T/outside.rxerr"
	sim_stop "$SIM_PID"
	check "outside: nothing landed" "! grep -q '^recv' '$T/outside.rx'"
	check "outside: df1sim sees ER STS F0h EXT STS 06h" \
		"grep -q 'MSG write N7:0,10 to station 0 N51:0 (first 0): ER STS F0h EXT STS 06h' '$T/outside.err'"
	check "outside: and no DN" "! grep -q ': DN$' '$T/outside.err'"
fi

finish
