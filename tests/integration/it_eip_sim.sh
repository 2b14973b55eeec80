#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_eip_sim - df1sim --eip: PCCC over EtherNet/IP from its data table, checked
# by two clients that are not libdf1's: tests/support/eip_probe.py (raw sockets,
# every message built from the layouts of df1-eip(7)) and pycomm3's SLCDriver
# from PyPI (tests/support/eip_pycomm3.py; SKIP, counted as passed, when it is
# not installed). What the EtherNet/IP side writes the DF1 side reads back
# with df1read, and the reverse; df1sim's --log shows each write once.
# Run from the repository root with DF1_BIN=<build/bin>.
. tests/support/lib.sh

PROBE="python3 tests/support/eip_probe.py"
PYC="python3 tests/support/eip_pycomm3.py"
NAME="libdf1 df1sim MicroLogix 1400"

# The EtherNet/IP address df1sim prints after its device line (eip://ADDR:PORT).
eip_line() {
	EIP=$(sed -n 's|^eip://||p' "$T/$1.out" 2>/dev/null | head -n 1)
	[ -n "$EIP" ]
}

# ---------------------------------------------------------------------------
# A simulator with a DF1 side (pty) and an EtherNet/IP side, stations 1 and 3
# ---------------------------------------------------------------------------
sim_start sim --station 1,3 --eip tcp://127.0.0.1:0 --log "$T/sim.log"
wait_for "df1sim prints its EtherNet/IP address" 100 eip_line sim
same "the device line comes first" "$(head -n 1 "$T/sim.out")" "$SIM_DEV"
case $EIP in
127.0.0.1:[1-9]*) ok ;;
*) bad "EtherNet/IP address '$EIP' is not loopback:PORT" ;;
esac

expect 0 "RegisterSession, a second one, version 2, UnRegisterSession" -- $PROBE "$EIP" register
expect 0 "ListIdentity over TCP and the Identity object" -- $PROBE "$EIP" identity-tcp "$NAME"
expect 0 "ListIdentity over UDP" -- $PROBE "$EIP" identity-udp "$NAME"
expect 0 "ListServices" -- $PROBE "$EIP" services
expect 0 "malformed encapsulation: statuses, the close after a bad length" -- $PROBE "$EIP" malformed
expect 0 "CIP errors: 08 service, 05 class/instance, 04 segment, 26 path size, 13 short" -- \
	$PROBE "$EIP" cip-errors
expect 0 "Execute PCCC reads and writes (SendRRData)" -- $PROBE "$EIP" read-write
expect 0 "Forward Open / SendUnitData / Forward Close" -- $PROBE "$EIP" connected
expect 0 "Large Forward Open / SendUnitData / Forward Close" -- $PROBE "$EIP" connected-large
expect 0 "Unconnected Send to station 3 (port 2, link 3), station 1 apart" -- $PROBE "$EIP" routed 3 333 1
expect 0 "a client stuck inside a header does not hold up another" -- $PROBE "$EIP" others-served

# what EtherNet/IP wrote, the DF1 side reads (and the reverse)
expect 0 "df1read N7:20 over DF1" -- "$BIN/df1read" -d "$SIM_DEV" N7:20
out_is "N7:20 as the EtherNet/IP client wrote it" "-1234"
expect 0 "df1read N7:9 of station 3 over DF1" -- "$BIN/df1read" -d "$SIM_DEV" -a 3 N7:9
out_is "station 3's N7:9 as the routed write left it" "333"
same "the EtherNet/IP write of N7:20 is logged once" \
	"$(grep -c 'cmd=0F/AA addr=N7:20 ' "$T/sim.log")" 1
same "the routed write is logged for station 3" \
	"$(grep -c 'station=3 cmd=0F/AA addr=N7:9 ' "$T/sim.log")" 1

# a station that does not answer (SIGUSR1): the CIP status of a timed-out request
kill -USR1 "$SIM_PID"
wait_for "SIGUSR1: EtherNet/IP requests fail with 01/0204" 50 \
	sh -c "$PROBE '$EIP' no-answer 2>/dev/null"
kill -USR2 "$SIM_PID"
wait_for "SIGUSR2: answered again" 50 sh -c "$PROBE '$EIP' read-write 2>/dev/null"

# ---------------------------------------------------------------------------
# pycomm3's SLCDriver
# ---------------------------------------------------------------------------
if $PYC available; then
	expect 0 "pycomm3 reads N, F, L, B bit, T/C words, ST" -- $PYC "$EIP" read \
		'N7:0{4}' F8:2 L10:3 B3:0/0 T4:1.PRE C5:2.PRE ST9:1
	out_is "pycomm3's values" "N7:0{4}=0,1,2,3
F8:2=2.5
L10:3=196611
B3:0/0=false
T4:1.PRE=100
C5:2.PRE=100
ST9:1=\"STRING 1\""
	# (pycomm3 1.2 sends T/C .PRE/.ACC writes with sub-element 0 and ST writes
	# without their 82 characters: not SLC layouts, so not tried here)
	expect 0 "pycomm3 writes N, F, L, a B bit" -- $PYC "$EIP" write \
		N7:40=4242 F8:41=-2.75 L10:42=-100000 B3:1/5=true
	expect 0 "df1read the values pycomm3 wrote, over DF1" -- "$BIN/df1read" -d "$SIM_DEV" \
		N7:40 F8:41 L10:42 B3:1/5 B3:1
	out_is "what pycomm3 wrote, as DF1 reads it" "4242
-2.75
-100000
1
32"
	same "pycomm3's N7:40 write is logged once" "$(grep -c 'cmd=0F/AB addr=N7:40 ' "$T/sim.log")" 1
	expect 0 "df1write N7:43 over DF1" -- "$BIN/df1write" -d "$SIM_DEV" N7:43=-7
	expect 0 "pycomm3 reads what DF1 wrote" -- $PYC "$EIP" read N7:43
	out_is "N7:43 through pycomm3" "N7:43=-7"
	expect 0 "pycomm3: the diagnostic status' processor" -- $PYC "$EIP" processor
	out_is "a MicroLogix 1400 (1766)" "1766"
else
	echo "SKIP pycomm3 is not installed (python3 -m pip install pycomm3)"
	ok
fi
sim_stop

# ---------------------------------------------------------------------------
# --eip alone, --eip-read-only, --eip-allow, usage
# ---------------------------------------------------------------------------
"$BIN/df1sim" --eip 0 --eip-read-only --log "$T/ro.log" > "$T/ro.out" 2> "$T/ro.err" &
RO=$!
echo "$RO" >> "$T/.sims"
wait_for "--eip alone prints only its address" 100 eip_line ro
same "one line" "$(wc -l < "$T/ro.out" | tr -d ' ')" 1
expect 0 "--eip-read-only: writes and mode changes get STS 60, reads work" -- $PROBE "$EIP" read-only
same "nothing written in the log" "$(grep -c 'cmd=0F/A[AB9]\|cmd=0F/80' "$T/ro.log")" 0
sim_stop "$RO"

"$BIN/df1sim" --eip 127.0.0.1:0 --eip-allow 10.255.0.1/32,fd00::/8 > "$T/al.out" 2> "$T/al.err" &
AL=$!
echo "$AL" >> "$T/.sims"
wait_for "df1sim --eip-allow starts" 100 eip_line al
expect 0 "a client outside --eip-allow is closed" -- $PROBE "$EIP" refused
sim_stop "$AL"

"$BIN/df1sim" --eip 0 --eip-allow 127.0.0.0/8 > "$T/al2.out" 2> "$T/al2.err" &
AL=$!
echo "$AL" >> "$T/.sims"
wait_for "df1sim --eip-allow 127.0.0.0/8 starts" 100 eip_line al2
expect 0 "a client inside --eip-allow is served" -- $PROBE "$EIP" read-write
sim_stop "$AL"

expect 2 "--eip-allow without --eip" -- "$BIN/df1sim" --pty "$T/x" --eip-allow 10.0.0.0/8
err_has "says what goes with what" "--eip-allow, --eip-read-only, --eip-max-clients, --eip-register-timeout and --eip-idle-timeout go with --eip"
expect 2 "--eip-allow that is no network" -- "$BIN/df1sim" --eip 0 --eip-allow 10.0.0.0/33
err_has "names the bad network" "10.0.0.0/33"
expect 2 "--eip 0:PORT (every interface, not written out)" -- "$BIN/df1sim" --eip 0:0
err_has "says how to write it" "every interface only as 0.0.0.0 or ::"
"$BIN/df1sim" --eip 0.0.0.0:0 > "$T/any.out" 2> "$T/any.err" &
AL=$!
echo "$AL" >> "$T/.sims"
wait_for "df1sim --eip 0.0.0.0:0 starts" 100 eip_line any
check "says every interface is reachable" "grep -q 'every interface, reachable from other hosts' '$T/any.err'"
sim_stop "$AL"
expect 2 "--eip with a bad port" -- "$BIN/df1sim" --eip 127.0.0.1:99999
err_has "names the listen address" "127.0.0.1:99999"

finish
