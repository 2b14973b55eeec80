#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_df1gw_eip.sh - df1gw --eip, the EtherNet/IP bridge, end to end with real
# processes: EtherNet/IP clients (tests/support/eipgw_probe.py and eip_probe.py,
# raw sockets, messages built from df1-eip(7); pycomm3's SLCDriver when it is
# installed) -> df1gw --eip on loopback TCP -> a pseudo-terminal -> df1sim,
# whose --log is the record of what reached the PLC. Full and half duplex,
# two stations (one through the route path), line faults, two clients at
# once, --eip-allow, --eip-read-only, a silent controller, and MQTT publishing
# (Debian's mosquitto) on the same line at once. Waits are bounded loops.
# Run from the repository root with DF1_BIN=<build/bin>.
. tests/support/lib.sh

GW="$BIN/df1gw"
PROBE="python3 tests/support/eipgw_probe.py"
EPROBE="python3 tests/support/eip_probe.py"
PYC="python3 tests/support/eip_pycomm3.py"
# ListIdentity names the bridge and the processor behind it (df1sim's diagnostic
# status: an SLC 5/04 by default)
NAME="libdf1 DF1 bridge SLC 5/04"

# gw_start NAME OPTIONS...: df1gw in the background; GW_PID, its stdout/stderr
# $T/NAME.out / $T/NAME.err
gw_start() {
	gname=$1; shift
	"$GW" "$@" > "$T/$gname.out" 2> "$T/$gname.err" &
	GW_PID=$!
	echo "$GW_PID" >> "$T/.sims"
	wait_for "df1gw $gname says where it listens" 100 gw_addr "$gname"
}
# The address df1gw prints: "df1gw: EtherNet/IP on ADDR:PORT..."
gw_addr() {
	EIP=$(sed -n 's|^df1gw: EtherNet/IP on \([0-9.]*:[0-9]*\).*|\1|p' "$T/$1.err" 2>/dev/null | head -n 1)
	[ -n "$EIP" ]
}
gw_stop() {
	kill -TERM "$1" 2>/dev/null
	lib_reap "$1"
}
# logged PATTERN: lines of df1sim's log holding PATTERN
logged() { grep -c -e "$1" "$T/sim.log"; }

cat > "$T/plc.txt" <<'EOF2'
N7:50=123
N7:51=-5
EOF2

# ---- options ----
expect 2 "--eip-allow without --eip" -- "$GW" -d /dev/null --eip-allow 127.0.0.1/32
err_has "--eip-allow without --eip: why" "go with --eip"
expect 2 "no --map, --mqtt or --eip" -- "$GW" -d /dev/null
err_has "neither tags nor a bridge: says --eip" "--eip PORT"
expect 2 "--once needs a broker" -- "$GW" -d /dev/null --eip 0 --once
expect 2 "--eip-station out of range" -- "$GW" -d /dev/null --eip 0 --eip-station 255
expect 0 "--help names --eip" -- "$GW" --help
check "--help: --eip-read-only" 'grep -q -- "--eip-read-only" "$T/out"'
check "--help: --map and --mqtt say when they are needed" 'grep -q -- "--map FILE.csv.*required without --eip" "$T/out" && grep -q -- "--mqtt URL.*required without --eip" "$T/out" && ! grep -q "(required)" "$T/out"'

# ---------------------------------------------------------------------------
# Full duplex, stations 1 and 3; a pure bridge (no --map, no broker)
# ---------------------------------------------------------------------------
sim_start sim --station 1,3 --data "$T/plc.txt" --log "$T/sim.log" || finish
gw_start gw -d "$SIM_DEV" --eip 0 --timeout 300 --counters
case $EIP in
127.0.0.1:[1-9]*) ok ;;
*) bad "--eip 0 listens on '$EIP', not loopback" ;;
esac
check "loopback: no network warning" '! grep -q "on a network" "$T/gw.err"'

expect 0 "ListIdentity: vendor 0, '$NAME'" -- $PROBE "$EIP" identity "$NAME"
expect 0 "RegisterSession / UnRegisterSession" -- $EPROBE "$EIP" register
expect 0 "malformed encapsulation answered, never a crash" -- $EPROBE "$EIP" malformed
expect 0 "N7:50 through the bridge" -- $PROBE "$EIP" read - 50 123
expect 0 "N7:51 (signed) through the bridge" -- $PROBE "$EIP" read - 51 -5
n0=$(logged 'cmd=0F/AA addr=N7:20 ')
expect 0 "write N7:20 = -1234" -- $PROBE "$EIP" write - 20 -1234
expect 0 "N7:20 read back" -- $PROBE "$EIP" read - 20 -1234
same "the write reached the PLC once" "$(logged 'station=1 cmd=0F/AA addr=N7:20 ')" $((n0 + 1))
expect 0 "diag status, error replies (STS F0 EXT STS) passed through" -- $EPROBE "$EIP" read-write
# station 3 through the route path (port 2, link address 3)
expect 0 "routed write to station 3 N7:9" -- $PROBE "$EIP" write 3 9 333
expect 0 "routed read of station 3 N7:9" -- $PROBE "$EIP" read 3 9 333
expect 0 "station 1 N7:9 untouched (direct)" -- $PROBE "$EIP" read - 9 9
expect 0 "a route to port 2 link 1: station 1" -- $PROBE "$EIP" read 1 9 9
same "the routed write went to station 3" "$(logged 'station=3 cmd=0F/AA addr=N7:9 ')" 1
same "and not to station 1" "$(logged 'station=1 cmd=0F/AA addr=N7:9 ')" 0

# two clients at once, each its own elements; every write once in the log
$PROBE "$EIP" writes - 100 20 1 > "$T/c1.out" 2> "$T/c1.err" &
C1=$!
$PROBE "$EIP" writes 3 200 20 2 > "$T/c2.out" 2> "$T/c2.err" &
C2=$!
wait $C1; r1=$?
wait $C2; r2=$?
same "client 1 ended well" "$r1" 0
same "client 2 ended well" "$r2" 0
same "client 1: 20 writes done" "$(grep -c ' ok$' "$T/c1.out")" 20
same "client 2: 20 writes done" "$(grep -c ' ok$' "$T/c2.out")" 20
dup=0
for e in $(seq 100 119); do
	[ "$(logged "station=1 cmd=0F/AA addr=N7:$e ")" = 1 ] || dup=$((dup + 1))
done
for e in $(seq 200 219); do
	[ "$(logged "station=3 cmd=0F/AA addr=N7:$e ")" = 1 ] || dup=$((dup + 1))
done
same "two clients: each write executed exactly once" "$dup" 0
expect 0 "client 1's last value" -- $PROBE "$EIP" read - 119 1019
expect 0 "client 2's last value (station 3)" -- $PROBE "$EIP" read 3 219 2019

# libdf1's own client: df1read / df1write -d eip:// (eip://HOST:PORT/2 routes
# to the station of -a)
if "$BIN/df1read" --help 2>&1 | grep -q 'eip://'; then
	expect 0 "df1read -d eip:// N7:50" -- "$BIN/df1read" -d "eip://$EIP" N7:50
	out_is "df1read's value through the bridge" "123"
	n0=$(logged 'station=1 cmd=0F/AA addr=N7:60 ')
	expect 0 "df1write -d eip:// N7:60=606" -- "$BIN/df1write" -d "eip://$EIP" N7:60=606
	same "df1write's write reached the PLC once" "$(logged 'station=1 cmd=0F/AA addr=N7:60 ')" $((n0 + 1))
	expect 0 "df1write -d eip://.../2 -a 3 N7:61=3061 (routed)" -- \
		"$BIN/df1write" -d "eip://$EIP/2" -a 3 N7:61=3061
	expect 0 "df1read -d eip://.../2 -a 3 N7:61 N7:60" -- "$BIN/df1read" -d "eip://$EIP/2" -a 3 N7:61 N7:60
	out_is "station 3's values" "3061
60"
	expect 0 "df1read --eip-connected (Forward Open) N7:60" -- "$BIN/df1read" -d "eip://$EIP" --eip-connected N7:60
	out_is "connected read" "606"
	expect 0 "df1mon --who over eip://" -- "$BIN/df1mon" -d "eip://$EIP" --who
	check "df1mon --who: the bridge's identity" 'grep -q "libdf1 DF1 bridge" "$T/out"'
else
	echo "SKIP: df1read without eip:// targets (branch eipcli not merged)"
	ok
fi

# pycomm3 (PyPI) as an independent client, when installed
if $PYC available; then
	expect 0 "pycomm3 writes N7:40 through the bridge" -- $PYC "$EIP" write N7:40=4242
	expect 0 "pycomm3 reads N7:40, N7:50" -- $PYC "$EIP" read N7:40 N7:50
	out_is "pycomm3's values" "N7:40=4242
N7:50=123"
	check "pycomm3's write reached the PLC once" '[ "$(logged "cmd=0F/AB addr=N7:40 \|cmd=0F/AA addr=N7:40 ")" = 1 ]'
else
	echo "SKIP: pycomm3 not installed (pip install pycomm3)"
	ok
fi

# a controller that does not answer: the PCCC STS a NET-ENI gives (30h)
kill -USR1 "$SIM_PID"
expect 0 "silent controller: STS 30h with the client's TNS" -- $PROBE "$EIP" no-answer
kill -USR2 "$SIM_PID"
wait_for "answered again" 50 sh -c "$PROBE '$EIP' read - 50 123 2>/dev/null"

gw_stop "$GW_PID"
check "--counters: EtherNet/IP sessions counted" 'grep -Eq "^eip sessions [1-9][0-9]*, " "$T/gw.out"'
check "--counters: requests forwarded" 'grep -Eq "forwarded [1-9][0-9]*, answered [1-9][0-9]*, no answer [1-9]" "$T/gw.out"'
check "--counters: the line's counters" 'grep -q "CNT_CMD_MSGS_SENT" "$T/gw.out"'

# ---- --eip-allow ----
gw_start gwa -d "$SIM_DEV" --eip 0 --eip-allow 10.99.0.0/16,192.0.2.7
expect 0 "a client outside --eip-allow is refused" -- $EPROBE "$EIP" refused
gw_stop "$GW_PID"
gw_start gwb -d "$SIM_DEV" --eip 127.0.0.1:0 --eip-allow 10.99.0.0/16,127.0.0.0/8
expect 0 "a client inside --eip-allow is served" -- $PROBE "$EIP" read - 50 123
gw_stop "$GW_PID"

# ---- --eip-read-only: STS 60h, nothing on the line ----
gw_start gwr -d "$SIM_DEV" --eip 0 --eip-read-only
n0=$(logged 'cmd=0F/AA addr=N7:30 ')
m0=$(logged 'cmd=0F/80')
expect 0 "--eip-read-only: a write and a mode change refused, a read passes" -- $PROBE "$EIP" read-only 30
same "nothing written on the line" "$(logged 'cmd=0F/AA addr=N7:30 ')" "$n0"
same "no mode change on the line" "$(logged 'cmd=0F/80')" "$m0"
gw_stop "$GW_PID"

# ---- an address given: listens on a network, and says so ----
gw_start gwn -d "$SIM_DEV" --eip 0.0.0.0:0
check "a network address: said on stderr" 'grep -q "listening on a network" "$T/gwn.err"'
gw_stop "$GW_PID"
sim_stop

# ---------------------------------------------------------------------------
# Line faults (NAK, dropped ACK), full and half duplex: recovered, each write
# executed once when reported done, never twice
# ---------------------------------------------------------------------------
faults() {
	mode=$1
	rm -f "$T/sim.log"
	sim_start sim --duplex "$mode" --station 1,3 --log "$T/sim.log" --nak 10 --drop-ack 10 --seed 11 || return
	gw_start "gwf$mode" -d "$SIM_DEV" --duplex "$mode" --eip 0 --timeout 300
	wait_for "$mode duplex: the bridge reaches station 3" 100 sh -c "$PROBE '$EIP' read 3 9 9 2>/dev/null"
	$PROBE "$EIP" writes - 130 25 5 > "$T/f1.out" 2> "$T/f1.err" &
	F1=$!
	$PROBE "$EIP" writes 3 160 25 6 > "$T/f2.out" 2> "$T/f2.err" &
	F2=$!
	wait $F1; r1=$?
	wait $F2; r2=$?
	same "$mode duplex faults: client 1 answered every time" "$r1" 0
	same "$mode duplex faults: client 2 answered every time" "$r2" 0
	okn=$(cat "$T/f1.out" "$T/f2.out" | grep -c ' ok$')
	check "$mode duplex faults: most writes done ($okn of 50)" '[ "$okn" -ge 40 ]'
	bad_n=0
	for s in 1 3; do
		[ $s = 1 ] && f=$T/f1.out || f=$T/f2.out
		while read -r e res; do
			n=$(logged "station=$s cmd=0F/AA addr=N7:$e ")
			if [ "$res" = ok ] && [ "$n" != 1 ]; then bad_n=$((bad_n + 1)); fi
			if [ "$n" -gt 1 ]; then bad_n=$((bad_n + 1)); fi
		done < "$f"
	done
	same "$mode duplex faults: done once, nothing twice" "$bad_n" 0
	[ "$okn" -ge 40 ] || sed 's/^/  df1gw: /' "$T/gwf$mode.err" | head -5
	expect 0 "$mode duplex: station 3 read through the route" -- $PROBE "$EIP" read 3 184 6024
	gw_stop "$GW_PID"
	sim_stop
}
faults full
faults half

# ---------------------------------------------------------------------------
# MQTT publishing and EtherNet/IP on one line at once
# ---------------------------------------------------------------------------
MOSQ=${MOSQUITTO:-/usr/sbin/mosquitto}
if [ -x "$MOSQ" ] && command -v mosquitto_sub >/dev/null 2>&1; then
	MQ_PORT=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
	printf 'listener %s 127.0.0.1\npersistence false\nuser %s\nallow_anonymous true\n' "$MQ_PORT" "$(id -un)" > "$T/mq.conf"
	"$MOSQ" -c "$T/mq.conf" > "$T/mq.log" 2>&1 &
	echo $! >> "$T/.sims"
	wait_for "broker listens" 100 python3 -c "import socket; socket.create_connection(('127.0.0.1', $MQ_PORT), 1).close()"
	sub1() { mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t "$1" -C 1 -W 2 2>/dev/null; }
	has() { sub1 "$1" | grep -F -q -e "$2"; }
	printf 'Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms\nSpeed,ReadWrite,INT,1,SLC,N7:50,1,100\nFar,Read,INT,3,SLC,N7:5,1,100\n' > "$T/map.csv"
	sim_start sim --station 1,3 --data "$T/plc.txt" --log "$T/sim.log" || finish
	gw_start gwm -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix eipt \
		--eip 0 --timeout 300
	wait_for "MQTT: Speed published" 100 has eipt/tag/Speed '"value":123'
	expect 0 "EtherNet/IP writes N7:50 = 4321 while MQTT polls" -- $PROBE "$EIP" write - 50 4321
	wait_for "MQTT: Speed shows the EtherNet/IP write" 100 has eipt/tag/Speed '"value":4321'
	mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -q 1 -t eipt/tag/Speed/set -m 77
	wait_for "EtherNet/IP reads the MQTT write" 100 sh -c "$PROBE '$EIP' read - 50 77 2>/dev/null"
	expect 0 "EtherNet/IP writes station 3 N7:5 = 55 (route)" -- $PROBE "$EIP" write 3 5 55
	wait_for "MQTT: Far (station 3) shows it" 100 has eipt/tag/Far '"value":55'
	gw_stop "$GW_PID"
	sim_stop
else
	echo "SKIP: mosquitto or mosquitto-clients missing"
	ok
fi

finish
