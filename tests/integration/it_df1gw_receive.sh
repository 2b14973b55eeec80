#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_df1gw_receive - df1gw's Receive rows (df1gw(1), RECEIVE) against real
# parts: Debian's mosquitto on a free loopback port, mosquitto_sub as the
# plant's client, df1sim as the controller whose MSG instructions write to
# df1gw (df1sim --msg; its stderr reports DN or ER per message, the PLC's
# view), and df1read/df1write as the half-duplex master of a df1gw slave
# station, over two pseudo-terminals joined back to back
# (tests/support/pty_join.py).
#  - before any write a Receive row is published as no value, UNCERTAIN,
#    reason no_message_yet (also while only refused writes come), and a
#    PLC's MSG read (df1sim) or a master's df1read gets zeros; after a write
#    it is GOOD with what was written, the rest of the row zeros;
#  - full duplex, df1gw polling df1sim meanwhile (--outstanding 1 and 4, and
#    under df1sim's NAK, drop-ACK and corrupt-reply faults): every message
#    lands once and in order (df1sim numbers them in N7:0), is published
#    once with "from":1, and df1sim sees DN for each;
#  - a write outside the regions: df1sim sees ER STS F0h EXT STS 06h (no such
#    file) and 0Ah (running past the region), nothing published;
#  - /set to a Receive tag: never on the line (df1sim's log), and df1sim's
#    MSG read gets the new value;
#  - half-duplex slave: df1write/df1read --duplex half reach df1gw at its
#    station; what they write is published with "from":0 (their SRC), what
#    MQTT writes is what they read, and the diagnostic status names the
#    emulated processor (df1mon --who);
#  - df1mon --serve: each write a PLC's MSG makes printed once with its
#    sender (full duplex, and as a half-duplex slave for df1write/df1read),
#    and df1mon's decoder showing a PLC's command and its reply;
#  - Sparkplug: the Receive tags in the DBIRTH of df1gw's own station's
#    device (a row no PLC wrote: a null metric of its datatype, Quality
#    Uncertain, Reason no_message_yet), a PLC's write as DDATA (good, not
#    null) and a DCMD what the PLC's MSG reads,
#    decoded by an independent host (tests/support/spb_host.py, pysparkplug);
#  - a mapping with Read rows in slave mode, and a Receive row at another
#    station: refused with a clear message.
. tests/support/lib.sh

if [ ! -x "$MOSQ" ] || ! command -v mosquitto_sub >/dev/null 2>&1; then
	bad "no broker to test against (apt-get install mosquitto mosquitto-clients)"
	finish
fi
GW="$BIN/df1gw"
MQ_PORT=$(free_port)
broker_start broker "$MQ_PORT"
pub() { mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -q 1 -t "$1" -m "$2"; }
sub1() { mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t "$1" -C 1 -W 2 2>/dev/null; }

# listen NAME TOPIC: a subscriber writing TOPIC's messages to $T/NAME.sub
listen() {
	mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t "$2" -v > "$T/$1.sub" 2>&1 &
	echo $! >> "$T/.sims"
	LISTEN=$!
}
gw_run() {
	name=$1; shift
	"$GW" --mqtt "mqtt://127.0.0.1:$MQ_PORT" -v "$@" > "$T/$name.gwout" 2> "$T/$name.gwerr" &
	GW_PID=$!
	echo "$GW_PID" >> "$T/.sims"
}

cat > "$T/map.csv" <<'EOF'
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
Batch_Report,Receive,INT,0,SLC,N50:0,10,
Setpoint,Receive,INT,0,SLC,N52:0,5,
Speed,Read,INT,1,SLC,N7:0,1,100
EOF

# ---- full duplex: df1sim's MSG writes while df1gw polls it ----
# run NAME OUTSTANDING [DF1SIM OPTIONS...]
run() {
	name=$1; out=$2; shift 2
	P="rx/$name"
	sim_start "$name" --station 1 --msg write,N7:0,10,0,N50:0,100,seq "$@" || return 1
	listen "$name" "$P/tag/Batch_Report"
	gw_run "$name" -d "$SIM_DEV" --map "$T/map.csv" --prefix "$P" --outstanding "$out"
	# 4 s of messages, at least 20 of them seen by df1sim as done
	wait_for "$name: 20 MSGs done" 100 sh -c "[ \$(grep -c ': DN\$' '$T/$name.err') -ge 20 ]"
	kill -TERM "$GW_PID"; lib_reap "$GW_PID"
	sim_stop "$SIM_PID"
	kill -TERM "$LISTEN"; lib_reap "$LISTEN"
	# the numbers published with "from":1, in order; those df1sim saw DN for
	sed -n 's/^.*{"value":\[\([0-9]*\),.*"from":1}$/\1/p' "$T/$name.sub" > "$T/$name.got"
	sed -n 's/^df1sim: MSG write .*(first \([0-9]*\)): DN$/\1/p' "$T/$name.err" > "$T/$name.dn"
	got=$(wc -l < "$T/$name.got"); dn=$(wc -l < "$T/$name.dn")
	check "$name: at least 20 messages published ($got)" "[ $got -ge 20 ]"
	check "$name: each published once, in order (1..$got)" "seq 1 $got | cmp -s - '$T/$name.got'"
	check "$name: DN for each ($dn of $got)" "seq 1 $dn | cmp -s - '$T/$name.dn' && [ $got -le \$(($dn + 1)) ]"
	er=$(sed -n 's/^df1sim: MSG write .*(first \([0-9]*\)): ER.*/\1/p' "$T/$name.err" | awk -v d="$dn" '$1 <= d' | wc -l)
	check "$name: no MSG ended in error while df1gw ran" "[ $er -eq 0 ]"
	check "$name: the polled tag was published meanwhile" "grep -q '\"quality\":\"GOOD\"' '$T/$name.gwerr'"
	check "$name: the rest of the region as df1sim sent it (N7:1..9 = 1..9)" \
		"grep -q '^$P/tag/Batch_Report {\"value\":\[$got,1,2,3,4,5,6,7,8,9\],\"quality\":\"GOOD\"' '$T/$name.sub'"
}
run plain 1
run pipelined 4
run faults 1 --nak 10 --drop-ack 10 --corrupt 10 --seed 7
run faults-pipelined 4 --nak 10 --drop-ack 10 --corrupt 10 --seed 11

# the network file's Mode Peer: the same full-duplex station (Station 0 from the file)
printf 'Station,Mode,PLC_Type\n0,Peer,SLC\n' > "$T/peer_net.csv"
if sim_start peer --station 1 --msg write,N7:0,10,0,N50:0,100,seq; then
	gw_run peer -N "$T/peer_net.csv" -d "$SIM_DEV" --map "$T/map.csv" --prefix rx/peer
	wait_for "Mode Peer: 5 MSGs done" 100 sh -c "[ \$(grep -c ': DN\$' '$T/peer.err') -ge 5 ]"
	kill -TERM "$GW_PID"; lib_reap "$GW_PID"
	sim_stop "$SIM_PID"
	check "Mode Peer: published with from 1" "grep -q 'tag/Batch_Report {\"value\":\[5,1,2,3,4,5,6,7,8,9\],.*\"from\":1}' '$T/peer.gwerr'"
fi

# ---- outside the regions; /set then a MSG read ----
P=rx/edge
if sim_start edge --station 1 --log "$T/edge.log" --msg write,N7:0,10,0,N51:0,300 \
	--msg write,N7:0,10,0,N50:5,300 --msg read,N7:20,5,0,N52:0,200; then
	listen edge "$P/tag/#"
	gw_run edge -d "$SIM_DEV" --map "$T/map.csv" --prefix "$P"
	# before any write: no value, UNCERTAIN, no message yet (df1gw(1) RECEIVE);
	# df1sim's MSG read of the region gets zeros (not the table's N52:n = n)
	wait_for "edge: df1gw online" 50 grep -q "^$P/tag/Setpoint " "$T/edge.sub"
	wait_for "edge: df1sim's MSG read of N52 gets 0 before any write" 50 \
		grep -q "^df1sim: MSG read N7:20,5 from station 0 N52:0 (first 0): DN" "$T/edge.err"
	before=$(grep -c "addr=N52" "$T/edge.log")
	pub "$P/tag/Setpoint/set" '{"value":[4321,2,3,4,5],"id":"s1"}'
	wait_for "edge: /set result" 50 grep -q "^$P/tag/Setpoint/result {\"id\":\"s1\",\"ok\":true" "$T/edge.sub"
	wait_for "edge: df1sim's MSG read gets 4321" 50 \
		grep -q "^df1sim: MSG read N7:20,5 from station 0 N52:0 (first 4321): DN" "$T/edge.err"
	wait_for "edge: an ER for N51" 50 grep -q "MSG write N7:0,10 to station 0 N51:0 (first [0-9]*): ER STS F0h EXT STS 06h" "$T/edge.err"
	wait_for "edge: an ER for N50:5,10 (past the region)" 50 \
		grep -q "MSG write N7:0,10 to station 0 N50:5 (first [0-9]*): ER STS F0h EXT STS 0Ah" "$T/edge.err"
	kill -TERM "$GW_PID"; lib_reap "$GW_PID"
	sim_stop "$SIM_PID"
	kill -TERM "$LISTEN"; lib_reap "$LISTEN"
	check "edge: /set never reached the line (no command to df1sim names N52)" "[ \$(grep -c 'addr=N52' '$T/edge.log') -eq $before ]"
	check "edge: Setpoint's first publication: null, UNCERTAIN, no_message_yet" \
		"[ \"\$(grep -m1 '^$P/tag/Setpoint ' '$T/edge.sub')\" = '$P/tag/Setpoint {\"value\":null,\"quality\":\"UNCERTAIN\",\"reason\":\"no_message_yet\",\"ts\":null,\"address\":\"N52:0\",\"station\":0}' ]"
	check "edge: Batch_Report (only refused writes) stays null, UNCERTAIN" \
		"grep -q '^$P/tag/Batch_Report {\"value\":null,\"quality\":\"UNCERTAIN\",\"reason\":\"no_message_yet\",\"ts\":null,\"address\":\"N50:0\",\"station\":0}\$' '$T/edge.sub' && ! grep -q '^$P/tag/Batch_Report .*GOOD' '$T/edge.sub'"
	check "edge: Setpoint published with the MQTT value, without from" \
		"grep -q '^$P/tag/Setpoint {\"value\":\[4321,2,3,4,5\],\"quality\":\"GOOD\",.*\"station\":0}$' '$T/edge.sub'"
	check "edge: no refused write published" "! grep -q 'Batch_Report {.*\"from\"' '$T/edge.sub'"
	check "edge: no N50:5 DN" "! grep -q 'N50:5 (first [0-9]*): DN' '$T/edge.err'"
fi

# ---- half-duplex slave station: df1write / df1read as its master ----
P=rx/slave
python3 tests/support/pty_join.py "$T/la" "$T/lb" > "$T/join.out" 2> "$T/join.err" &
JOIN=$!
echo "$JOIN" >> "$T/.sims"
wait_for "pty_join ready" 50 grep -q ready "$T/join.out"
cat > "$T/slave.csv" <<'EOF'
Tag,Command,Type,Station,PLC_Type,Address,Count
Batch_Report,Receive,INT,3,SLC,N50:0,10
Flags,Receive,BOOL,3,SLC,B53:0/2,3
EOF
listen slave "$P/tag/#"
gw_run slave -d "$T/la" --duplex half-slave --src 3 --plc micrologix --map "$T/slave.csv" --prefix "$P"
wait_for "slave: online" 50 sh -c "mosquitto_sub -h 127.0.0.1 -p $MQ_PORT -t '$P/tag/Flags' -C 1 -W 2 | grep -q UNCERTAIN"
check "slave: Flags before any write: null, UNCERTAIN, no_message_yet" \
	"grep -q '^$P/tag/Flags {\"value\":null,\"quality\":\"UNCERTAIN\",\"reason\":\"no_message_yet\",\"ts\":null,\"address\":\"B53:0/2\",\"station\":3}\$' '$T/slave.sub'"
H="--duplex half -d $T/lb --timeout 500"
expect 0 "slave: df1read N50:0,3 before any write" -- "$BIN/df1read" $H -a 3 N50:0,3
out_is "slave: the region starts at zero" "0
0
0"
expect 0 "slave: df1write N50:2=77,88" -- "$BIN/df1write" $H -a 3 N50:2=77,88
wait_for "slave: the write published with from 0, GOOD" 50 \
	grep -q "^$P/tag/Batch_Report {\"value\":\[0,0,77,88,0,0,0,0,0,0\],\"quality\":\"GOOD\",.*\"station\":3,\"from\":0}$" "$T/slave.sub"
same "slave: published once" "$(grep -c '"from":0' "$T/slave.sub")" 1
expect 0 "slave: df1write a bit" -- "$BIN/df1write" $H -a 3 B53:0/3=1
wait_for "slave: Flags published" 50 grep -q "^$P/tag/Flags {\"value\":\[false,true,false\],.*\"from\":0}$" "$T/slave.sub"
pub "$P/tag/Batch_Report/set" '[9,8,7,6,5,4,3,2,1,0]'
wait_for "slave: /set result" 50 grep -q "^$P/tag/Batch_Report/result {\"id\":null,\"ok\":true" "$T/slave.sub"
expect 0 "slave: df1read N50:0,3" -- "$BIN/df1read" $H -a 3 N50:0,3
out_is "slave: the master reads what MQTT wrote" "9
8
7"
expect 1 "slave: df1read outside the region" -- "$BIN/df1read" $H -a 3 N50:10
err_has "slave: EXT STS 07" "EXT STS 0x07"
expect 1 "slave: df1read of a file not declared" -- "$BIN/df1read" $H -a 3 N51:0
err_has "slave: EXT STS 06" "EXT STS 0x06"
expect 1 "slave: another station does not answer" -- "$BIN/df1read" $H -a 4 N50:0
expect 0 "slave: df1mon --who 3 names the emulated MicroLogix" -- "$BIN/df1mon" $H --who 3-3
check "slave: a MicroLogix in --who" "grep -qi 'micrologix' '$T/out'"
kill -TERM "$GW_PID"; lib_reap "$GW_PID"
kill -TERM "$LISTEN"; lib_reap "$LISTEN"

# the network file's Mode Slave (Station 3, an SLC 5/04 emulated) does the same
printf 'Station,Mode,PLC_Type,NAK_Retries\n3,Slave,SLC,3\n' > "$T/slave_net.csv"
gw_run netslave -N "$T/slave_net.csv" -d "$T/la" --map "$T/slave.csv" --prefix "$P"
wait_for "Mode Slave: serving" 50 grep -q "connected" "$T/netslave.gwerr"
expect 0 "Mode Slave: df1write N50:0=11" -- "$BIN/df1write" $H -a 3 N50:0=11
wait_for "Mode Slave: published with from 0" 50 \
	grep -q "tag/Batch_Report {\"value\":\[11,0,0,0,0,0,0,0,0,0\],.*\"from\":0}" "$T/netslave.gwerr"
expect 0 "Mode Slave: df1mon --who 3 names an SLC 5/04" -- "$BIN/df1mon" $H --who 3-3
check "Mode Slave: SLC 5/04 in --who" "grep -qi 'SLC 5/04' '$T/out'"
kill -TERM "$GW_PID"; lib_reap "$GW_PID"

# ---- df1mon --serve: what a PLC sends, without a gateway ----
if sim_start mon --station 1 --msg write,N7:0,3,0,N50:0,100,seq --msg write,N7:0,3,0,N51:0,300; then
	bounded "$BIN/df1mon" -d "$SIM_DEV" --serve N50:0,10 --duration 2 > "$T/mon.out" 2> "$T/mon.err"
	rc=$?
	sim_stop "$SIM_PID"
	check "mon: ran its 2 s (status $rc)" "[ $rc -eq 0 ]"
	sed -n 's/^[0-9:.]* from 1 to 0: N50:0 = \([0-9]*\) 1 2 (6 bytes)$/\1/p' "$T/mon.out" > "$T/mon.got"
	sed -n 's/^df1sim: MSG write N7:0,3 to station 0 N50:0 (first \([0-9]*\)): DN$/\1/p' "$T/mon.err" > "$T/mon.dn"
	got=$(wc -l < "$T/mon.got"); dn=$(wc -l < "$T/mon.dn")
	check "mon: each write printed once, in order ($got)" "[ $got -ge 8 ] && seq 1 $got | cmp -s - '$T/mon.got'"
	check "mon: DN for each ($dn)" "seq 1 $dn | cmp -s - '$T/mon.dn' && [ $got -le \$(($dn + 1)) ]"
	check "mon: N51 refused with EXT STS 06h" "grep -q 'N51:0 (first [0-9]*): ER STS F0h EXT STS 06h' '$T/mon.err'"
	check "mon: nothing else printed" "[ \$(wc -l < '$T/mon.out') -eq $got ]"
fi
"$BIN/df1mon" -d "$T/la" --serve N50:0,10 --duplex half-slave --src 3 --duration 4 > "$T/monh.out" 2> "$T/monh.err" &
MONH=$!
echo "$MONH" >> "$T/.sims"
wait_for "mon half-slave: serving" 50 grep -q "serving 1 region on" "$T/monh.err"
expect 0 "mon half-slave: df1write N50:1=5,6" -- "$BIN/df1write" $H -a 3 N50:1=5,6
expect 0 "mon half-slave: df1read N50:0,3" -- "$BIN/df1read" $H -a 3 N50:0,3
out_is "mon half-slave: the master reads what it wrote" "0
5
6"
lib_reap "$MONH"
check "mon half-slave: the write printed with its sender" "grep -q ' from 0 to 3: N50:1 = 5 6 (4 bytes)\$' '$T/monh.out'"
# the decoder shows a PLC's command to the computer and its reply like any other:
# DLE STX, DST 0 SRC 1 CMD 0F STS 0 TNS 0x360D, AA (typed write, 3 fields) 6 bytes
# to N50:0 (file 0x32, type 0x89, element 0, sub 0) = 1 1 2; CRC-16 over the
# application bytes and ETX (doc/PROTOCOL.md 1.4)
frame() { python3 -c '
import sys
app = bytes.fromhex(sys.argv[1])
crc = 0
for b in app + b"\x03":
    crc ^= b
    for _ in range(8):
        crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
body = app.replace(b"\x10", b"\x10\x10")
print((b"\x10\x02" + body + b"\x10\x03" + bytes([crc & 255, crc >> 8])).hex(" "))' "$1"; }
CMD=$(frame "00 01 0F 00 0D 36 AA 06 32 89 00 00 01 00 01 00 02 00")
REP=$(frame "01 00 4F 00 0D 36")
expect 0 "decode: a PLC's MSG and its reply" -- sh -c "printf '%s %s\n' '$CMD' '$REP' | '$BIN/df1mon' --decode --check crc"
check "decode: the command, from station 1 to 0" "grep -q 'dst   0  src   1  tns 360D  0F/AA .*N50:0 size 6  = 1 1 2' '$T/out'"
check "decode: its reply, matched to it" "grep -q 'dst   1  src   0  tns 360D  4F .*reply to 0F/AA .*N50:0 .*sts 00' '$T/out'"

# ---- Sparkplug: the Receive tags are metrics of the device of df1gw's own station ----
HOST="python3 tests/support/spb_host.py"
if ! python3 -c 'import pysparkplug, paho.mqtt' 2>/dev/null; then
	skip "pysparkplug missing (pip install pysparkplug): no independent Sparkplug host"
	bad "Sparkplug: no independent host to decode with"
elif sim_start spb --station 1 --msg write,N7:0,3,0,N50:0,300,seq --msg read,N7:20,1,0,N53:0,200; then
	REC="$T/rec.jsonl"
	: > "$REC"
	$HOST record "$MQ_PORT" "$REC" 2> "$T/host.err" &
	echo $! >> "$T/.sims"
	REC_PID=$!
	wait_for "recorder subscribed" 100 sh -c "mosquitto_pub -h 127.0.0.1 -p $MQ_PORT -t spBv1.0/STATE/probe -m x 2>/dev/null; grep -q probe '$REC'"
	printf 'Tag,Command,Type,Station,PLC_Type,Address,Count\nBatch,Receive,INT,0,SLC,N50:0,3\nRecipe,Receive,INT,0,SLC,N53:0,1\n' > "$T/spb.csv"
	gw_run spb -d "$SIM_DEV" --map "$T/spb.csv" --sparkplug Plant --edge-node Line1 --json no
	DB='[r for r in R if r["type"] == "DBIRTH" and r["device"] == "station0"]'
	DD='[r for r in R if r["type"] == "DDATA" and r["device"] == "station0"]'
	wait_for "Sparkplug: DBIRTH of station0 with Batch and Recipe" 100 $HOST has "$REC" 0 \
		"{(m['name'], m['datatype']) for m in $DB[0]['metrics']} == {('Batch', 'INT16_ARRAY'), ('Recipe', 'INT16')}"
	# Recipe: no PLC writes it (df1sim only reads it): null in the DBIRTH,
	# Quality Uncertain (0x40000000 | 256), Reason no_message_yet
	if $HOST has "$REC" 0 "[(m['is_null'], m['value']) for m in $DB[0]['metrics'] if m['name'] == 'Recipe'] == [(True, None)] and $DB[0]['props']['Recipe'] == {'Quality': 0x40000100, 'Reason': 'no_message_yet'}"; then
		ok
	else
		bad "Sparkplug: Recipe is_null in the DBIRTH, Uncertain, no_message_yet"
	fi
	wait_for "Sparkplug: df1sim's MSG read of Recipe gets 0 before the DCMD" 50 \
		grep -q "MSG read N7:20,1 from station 0 N53:0 (first 0): DN" "$T/spb.err"
	wait_for "Sparkplug: a PLC's write as DDATA [3, 1, 2]" 100 $HOST has "$REC" 0 \
		"any(m['name'] == 'Batch' and m['value'] == [3, 1, 2] for r in $DD for m in r['metrics'])"
	if $HOST has "$REC" 0 "all(not m['is_null'] and 'Batch' not in r['props'] for r in $DD for m in r['metrics'] if m['name'] == 'Batch')"; then
		ok
	else
		bad "Sparkplug: after the PLC's write Batch is good (no Quality property), not null"
	fi
	$HOST dcmd "$MQ_PORT" Plant Line1 station0 Recipe INT16 55
	wait_for "Sparkplug: DCMD Recipe=55 is what the PLC's MSG reads" 100 \
		grep -q "MSG read N7:20,1 from station 0 N53:0 (first 55): DN" "$T/spb.err"
	wait_for "Sparkplug: DDATA Recipe 55" 50 $HOST has "$REC" 0 \
		"any(m['name'] == 'Recipe' and m['value'] == 55 for r in $DD for m in r['metrics'])"
	kill -TERM "$GW_PID"; lib_reap "$GW_PID"
	sim_stop "$SIM_PID"
	kill -TERM "$REC_PID"; lib_reap "$REC_PID"
	check "Sparkplug: every message decoded, the rules kept" "$HOST check '$REC' > '$T/spbcheck.out' 2>&1"
fi

# ---- refused configurations ----
printf 'Tag,Command,Type,Station,PLC_Type,Address\nA,Receive,INT,3,SLC,N50:0\nB,Read,INT,1,SLC,N7:0\n' > "$T/mixed.csv"
expect 2 "slave with Read rows" -- "$GW" -d "$T/la" --duplex half-slave --src 3 --map "$T/mixed.csv" \
	--mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix bad
err_has "slave with Read rows: why" "polls nothing"
printf 'Tag,Command,Type,Station,PLC_Type,Address\nA,Receive,INT,5,SLC,N50:0\n' > "$T/other.csv"
expect 2 "Receive at another station" -- "$GW" -d "$T/la" --map "$T/other.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix bad
err_has "Receive at another station: why" "is not df1gw's own station 0"
expect 2 "slave with --eip" -- "$GW" -d "$T/la" --duplex half-slave --src 3 --map "$T/slave.csv" \
	--mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix bad --eip 127.0.0.1:0
err_has "slave with --eip: why" "a slave station"
expect 2 "--once with Receive rows alone" -- "$GW" -d "$T/la" --map "$T/slave.csv" --src 3 \
	--mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix bad --once
err_has "--once with Receive rows alone: why" "needs Read rows"
expect 2 "--duplex half-slave is df1gw's only" -- "$BIN/df1read" --duplex half-slave -d "$T/la" N7:0
kill -TERM "$JOIN"; lib_reap "$JOIN"

finish
