#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_route - messages that half-duplex slaves send on their own, through a
# routing master (lib/link/route.c, libdf1(7) UNSOLICITED MESSAGES): three
# df1sim slaves (stations 1-3, --msg) share one multidrop line
# (tests/support/multidrop.py) with examples/route_master, a half-duplex
# master at station 0 that serves N50 and keeps the slaves polled, by
# df1_serve(), by the poll engine between its scans, and by both in turn on
# the one handle.
#  - station 1 writes to the master (N50:0, a running number): each lands once,
#    in order, and station 1 sees DN for each;
#  - station 2 writes to station 3 (N7:40, routed): station 3's word changes to
#    a number station 2 saw DN for;
#  - station 2 writes to station 9, which nobody answers: it sees ER STS 02h
#    (the master's "remote node did not ACK");
#  - station 3 broadcasts (255) N7:30: station 1's word changes;
#  - with --route no (DF1_OPT_ROUTE 0), the routed write ends in the sender's
#    own timeout and station 3's word stays as it was.
# Run from the repository root with B=<build dir> and DF1_BIN=<build/bin>.
. tests/support/lib.sh
RM=${B:-build}/examples/route_master
[ -x "$RM" ] || { bad "$RM not built (make tests)"; finish; }
command -v python3 > /dev/null || { skip "python3 missing"; finish; }

# line NAME: four ptys joined, $T/NAME.0 for the master, .1-.3 for the slaves
line() {
	python3 tests/support/multidrop.py "$T/$1" 4 > "$T/$1.md" 2>&1 &
	echo $! >> "$T/.sims"
	wait_for "$1: the line is up" 50 grep -qs ready "$T/$1.md"
}

# slave NAME STATION OPTIONS...: a df1sim slave on the line NAME
slave() {
	L=$1; S=$2; shift 2
	"$BIN/df1sim" -d "$T/$L.$S" --duplex half --station "$S" --cmd-timeout 3000 "$@" \
		> "$T/$L.s$S.out" 2> "$T/$L.s$S.err" &
	echo $! >> "$T/.sims"
	wait_for "$L: df1sim $S is up" 50 test -s "$T/$L.s$S.out"
}

# the slaves first, the line last (a slave whose line goes reports DF1_E_CLOSED)
stop_all() {
	for p in $(tac "$T/.sims"); do sim_stop "$p"; done
}

# dn NAME STATION TARGET: the running numbers of station's MSGs to TARGET that ended DN
dn() { sed -n "s/^df1sim: MSG write .* to station $3 .*(first \\([0-9]*\\)): DN\$/\\1/p" "$T/$1.s$2.err"; }

run_routed() {
	L=$1; mode=$2
	line "$L" || return 1
	slave "$L" 1 --msg write,N7:0,1,0,N50:0,300,seq
	slave "$L" 2 --msg write,N7:0,1,3,N7:40,300,seq --msg write,N7:0,1,9,N7:0,1000
	slave "$L" 3 --msg write,N7:0,1,255,N7:30,400,seq
	"$RM" "$T/$L.0" 5 1 "$mode" 1 2 3 -- 3 N7:40 1 N7:30 > "$T/$L.m" 2> "$T/$L.merr"
	rc=$?
	stop_all
	check "$L: the master ran (status $rc)" "[ $rc -eq 0 ] && [ ! -s '$T/$L.merr' ]"
	awk '$1 == "recv" && $3 == "N50:0" { print $4 }' "$T/$L.m" > "$T/$L.got"
	dn "$L" 1 0 > "$T/$L.dn1"
	got=$(wc -l < "$T/$L.got"); d1=$(wc -l < "$T/$L.dn1")
	check "$L: station 1's MSGs to the master landed ($got)" "[ $got -ge 5 ]"
	check "$L: each once, in order" "seq 1 $got | cmp -s - '$T/$L.got'"
	check "$L: station 1 saw DN for each ($d1 of $got)" "seq 1 $d1 | cmp -s - '$T/$L.dn1' && [ $got -le \$(($d1 + 1)) ]"
	check "$L: station 1 saw no ER but the one cut by the stop" \
		"[ \$(grep -c ': ER' '$T/$L.s1.err') -le 1 ] && ! grep ': ER' '$T/$L.s1.err' | grep -qv 'DF1_E_INTR\\|DF1_E_CLOSED'"
	dn "$L" 2 3 > "$T/$L.dn2"
	d2=$(wc -l < "$T/$L.dn2")
	v40=$(sed -n 's/^read 3 N7:40 //p' "$T/$L.m")
	check "$L: station 2's MSGs routed to station 3 saw DN ($d2)" "[ $d2 -ge 3 ]"
	check "$L: station 3's N7:40 is what station 2 sent (${v40:-none})" \
		"[ -n '$v40' ] && [ '$v40' -ge \$(tail -n 1 '$T/$L.dn2') ] && [ '$v40' -le \$((\$(tail -n 1 '$T/$L.dn2') + 1)) ]"
	check "$L: the MSG to the silent station 9 got ER STS 02h" \
		"grep -q 'to station 9 N7:0 (first [0-9]*): ER STS 02h' '$T/$L.s2.err'"
	check "$L: and never DN" "! grep -q 'to station 9 .*: DN' '$T/$L.s2.err'"
	d3=$(dn "$L" 3 255 | wc -l)
	v30=$(sed -n 's/^read 1 N7:30 //p' "$T/$L.m")
	check "$L: station 3's broadcasts were taken ($d3)" "[ $d3 -ge 3 ]"
	check "$L: station 1's N7:30 changed from 30 to a broadcast number (${v30:-none})" \
		"[ -n '$v30' ] && [ '$v30' -ge 1 ] && [ '$v30' -le $(($d3 + 1)) ]"
	set -- $(sed -n 's/^stats //p' "$T/$L.m")
	check "$L: counted: executed $1 routed $2 broadcasts $3 route replies $4 undeliverable $5" \
		"[ ${1:-0} -ge $got ] && [ ${2:-0} -ge $d2 ] && [ ${3:-0} -ge $d3 ] && [ ${4:-0} -ge $d2 ] && [ ${5:-0} -ge 1 ]"
}

# --route on the command line of a tool that can be a half-duplex master
"$BIN/df1read" -d /dev/null --duplex half --route maybe N7:0 > "$T/opt.out" 2> "$T/opt.err"
rc=$?
check "df1read --route maybe: usage error (status $rc)" "[ $rc -eq 2 ]"
check "df1read --route maybe: says what is wrong" \
	"grep -q -- \"--route: invalid value 'maybe' (expected yes or no)\" '$T/opt.err'"
check "df1read --help shows --route" "'$BIN/df1read' --help | grep -q -- '--route yes|no'"

run_routed serve serve
run_routed poll poll
run_routed both both

# --route no: the routed write is dropped and times out at the sender
L=noroute
if line "$L"; then
	slave "$L" 1 --msg write,N7:0,1,0,N50:0,300,seq
	slave "$L" 2 --msg write,N7:0,1,3,N7:40,300,seq
	slave "$L" 3
	"$RM" "$T/$L.0" 5 0 poll 1 2 3 -- 3 N7:40 > "$T/$L.m" 2> "$T/$L.merr"
	stop_all
	check "$L: the MSG to the master still lands" "grep -q '^recv 0 N50:0 1 1' '$T/$L.m'"
	check "$L: the routed MSG ends in the sender's timeout" \
		"grep -q 'to station 3 N7:40 (first 1): ER DF1_E_TIMEOUT' '$T/$L.s2.err'"
	check "$L: and never DN" "! grep -q 'to station 3 .*: DN' '$T/$L.s2.err'"
	check "$L: station 3's N7:40 is untouched" "grep -q '^read 3 N7:40 40$' '$T/$L.m'"
	set -- $(sed -n 's/^stats //p' "$T/$L.m")
	check "$L: nothing routed ($2), undeliverable counted ($5)" "[ ${2:-1} -eq 0 ] && [ ${5:-0} -ge 1 ]"
fi

finish
