#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_df1gw_sparkplug.sh - df1gw --sparkplug against real parts: Debian's
# mosquitto on a free loopback port, df1sim on a pseudo-terminal serving two
# stations (its --log is the record of what reached the PLC), and an
# independent Sparkplug B host, tests/support/spb_host.py on pysparkplug,
# decoding every message on spBv1.0/#. Expected values come from the df1sim
# --data file below and the Sparkplug 3.0 specification's rules (NBIRTH seq 0,
# seq 0-255 continuous, bdSeq of the will, DDATA metrics born in DBIRTH),
# never from df1gw's own output. bdSeq goes on across restarts, also a kill -9
# without --sparkplug-state (the state folder: XDG_STATE_HOME, STATE_DIRECTORY),
# and the killed session's will carries the old one. Waits are bounded loops, never sleeps that hope.
. tests/support/lib.sh

HOST="python3 tests/support/spb_host.py"
if [ ! -x "$MOSQ" ]; then
	skip "mosquitto missing (apt-get install mosquitto)"
	finish
fi
if ! python3 -c 'import pysparkplug, paho.mqtt' 2>/dev/null; then
	skip "pysparkplug missing (pip install pysparkplug): no independent Sparkplug host"
	finish
fi
GW="$BIN/df1gw"

MQ_PORT=$(free_port)
broker_start broker "$MQ_PORT" || finish

cat > "$T/plc.txt" <<'PLC'
N7:0=123
N7:1=-5
F8:0=1.5,2.25,-3
B3:0=0x0020
ST9:0="hello, PLC"
T4:0=PRE=500 ACC=7 EN=1
L10:0=100000
PLC
cat > "$T/map.csv" <<'MAP'
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
Speed,ReadWrite,INT,1,SLC,N7:0,1,100
Offset,Read,INT,1,SLC,N7:1,1,100
Level,Read,FLOAT,1,SLC,F8:0,3,100
Run,ReadWrite,BOOL,2,SLC,B3:0/5,1,100
Name,ReadWrite,STRING,2,SLC,ST9:0,1,100
Cycle,ReadWrite,TIMER,2,SLC,T4:0,1,100
Total,Read,LONG,2,MicroLogix,L10:0,1,100
Missing,Read,INT,1,SLC,N50:0,1,100
MAP

# ---- bad options: exit 2, said ----
expect 2 "a group id with '/'" -- "$GW" -d /dev/null --map "$T/map.csv" --mqtt mqtt://127.0.0.1:1 --sparkplug a/b
err_has "group id refused" "one topic level"
expect 2 "--edge-node without --sparkplug" -- "$GW" -d /dev/null --map "$T/map.csv" --mqtt mqtt://127.0.0.1:1 --edge-node E
err_has "--edge-node alone refused" "go with --sparkplug"
expect 2 "--device-name without a station" -- "$GW" -d /dev/null --map "$T/map.csv" --mqtt mqtt://127.0.0.1:1 --sparkplug G --device-name x=A
err_has "--device-name refused" "N=NAME"

# df1sim's EtherNet/IP side changes its data while df1gw reads the pty (the seq wrap below)
EIP_PORT=$(free_port)
sim_start plc --station 1,2 --data "$T/plc.txt" --log "$T/sim.log" --eip "127.0.0.1:$EIP_PORT" || finish
SIM=$SIM_PID

REC="$T/rec.jsonl"
: > "$REC"
$HOST record "$MQ_PORT" "$REC" 2> "$T/host.err" &
echo $! >> "$T/.sims"
# the recorder is subscribed once its own test message comes back
wait_for "recorder subscribed" 100 sh -c "mosquitto_pub -h 127.0.0.1 -p $MQ_PORT -t spBv1.0/STATE/probe -m x 2>/dev/null; grep -q probe '$REC'"

mark() { wc -l < "$REC" | tr -d ' '; }
# has FROM EXPR: a condition over the records from line FROM on
has() { $HOST has "$REC" "$1" "$2"; }
# seen WHAT FROM EXPR: waited for (10 s at most)
seen() { wait_for "$1" 100 has "$2" "$3"; }
gw_start() {
	"$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --sparkplug Plant \
		--edge-node Line1 --json no --device-name 2=Mixer --sparkplug-state "$T/spb.state" \
		--watchdog 1500 --counters "$@" > "$T/gw.out" 2>> "$T/gw.err" &
	GW_PID=$!
	echo "$GW_PID" >> "$T/.sims"
}
NB='[r for r in R if r["type"] == "NBIRTH"]'
metric() { echo "[m['value'] for r in R if r['type'] in ('DBIRTH', 'DDATA') for m in r['metrics'] if m['name'] == '$1']"; }

# ---- births: NBIRTH seq 0, a DBIRTH per station with df1sim's values ----
M=$(mark)
gw_start
seen "NBIRTH" "$M" "len($NB) == 1"
seen "DBIRTH of station1 and Mixer" "$M" \
	"{r['device'] for r in R if r['type'] == 'DBIRTH'} == {'station1', 'Mixer'}"
check "NBIRTH bdSeq 0 on the first start (no state file yet)" \
	"has $M '[m[\"value\"] for m in $NB[0][\"metrics\"] if m[\"name\"] == \"bdSeq\"] == [0]'"
check "node metrics in NBIRTH: counters" "has $M '{\"Sparkplug/Births\", \"Sparkplug/Rebirths\", \"Sparkplug/Commands\", \"Sparkplug/Rejected commands\", \"Sparkplug/Deaths\", \"Line/Scans\"} <= {m[\"name\"] for m in $NB[0][\"metrics\"]}'"
check "the line's settings as properties of Line/Device" \
	"has $M \"[r['props'].get('Line/Device') for r in R if r['type'] == 'NBIRTH'][0] == {'Baud': '19200', 'Framing': '8N1', 'Duplex': 'full', 'Check': 'CRC', 'PLC': 'SLC'}\""
check "station1 values (df1sim's data)" "has $M \"$(metric Speed)[:1] == [123] and $(metric Offset)[:1] == [-5] and $(metric Level)[:1] == [[1.5, 2.25, -3.0]]\""
check "Mixer values (df1sim's data)" "has $M \"$(metric Run)[:1] == [True] and $(metric Name)[:1] == ['hello, PLC'] and $(metric Total)[:1] == [100000]\""
check "timer members" "has $M \"$(metric Cycle/PRE)[:1] == [500] and $(metric Cycle/ACC)[:1] == [7] and $(metric Cycle/EN)[:1] == [True] and $(metric Cycle/DN)[:1] == [False]\""
check "datatypes from the file types" "has $M \"{m['name']: m['datatype'] for r in R if r['type'] == 'DBIRTH' for m in r['metrics']} == {'Speed': 'INT16', 'Offset': 'INT16', 'Level': 'FLOAT_ARRAY', 'Run': 'BOOLEAN', 'Name': 'STRING', 'Cycle/EN': 'BOOLEAN', 'Cycle/TT': 'BOOLEAN', 'Cycle/DN': 'BOOLEAN', 'Cycle/PRE': 'INT16', 'Cycle/ACC': 'INT16', 'Total': 'INT32', 'Missing': 'INT16'}\""
check "a BAD tag: Quality Bad (-2147483136) and its reason as properties (N50 is no file of df1sim's)" \
	"has $M \"[r['props'].get('Missing') for r in R if r['type'] == 'DBIRTH' and r['device'] == 'station1'][-1:] == [{'Quality': -2147483136, 'Reason': 'plc_error'}]\""
check "a GOOD tag: no quality property" "has $M \"[r for r in R if r['type'] == 'DBIRTH' and 'Speed' not in r['props']]\""
check "no DDATA repeating what DBIRTH said" "! has $M \"[r for r in R if r['type'] == 'DDATA']\""

# ---- DCMD: a write executed once, also when the broker delivers it again ----
M=$(mark)
TS=$(python3 -c 'import time; print(int(time.time() * 1000))')
$HOST dcmd "$MQ_PORT" Plant Line1 station1 Speed INT16 77 "$TS"
$HOST dcmd "$MQ_PORT" Plant Line1 station1 Speed INT16 77 "$TS"    # the same message again
seen "DDATA Speed 77 after the DCMD" "$M" "$(metric Speed) == [77]"
check "its metric's timestamp is the read's: after the command was sent, before it was received" \
	"has $M \"[m['timestamp'] for r in R if r['type'] == 'DDATA' for m in r['metrics'] if m['name'] == 'Speed' and $TS <= m['timestamp'] <= r['t'] * 1000 + 1000]\""
$HOST dcmd "$MQ_PORT" Plant Line1 Mixer Run BOOLEAN 0
seen "DDATA Run false" "$M" "$(metric Run) == [False]"
M2=$(mark)
$HOST dcmd "$MQ_PORT" Plant Line1 Mixer Cycle/PRE INT16 600
seen "a timer member written: DDATA of that member only" "$M2" \
	"[[m['name'] for m in r['metrics']] for r in R if r['type'] == 'DDATA'] == [['Cycle/PRE']] and $(metric Cycle/PRE) == [600]"
same "the member written as the whole element, the rest as read (df1sim's log)" \
	"$(grep -c 'cmd=0F/AA addr=T4:0 ' "$T/sim.log")" 1
same "one write of N7:0 in df1sim's log" "$(grep -c 'cmd=0F/AA addr=N7:0 ' "$T/sim.log")" 1

# ---- DCMD at most once: the same PUBLISH again with MQTT's DUP flag (a
# publisher's resend, forwarded again by the broker), with a payload timestamp
# (the id ring) and without one (the same bytes within 10 s) ----
M=$(mark)
$HOST dcmd-dup "$MQ_PORT" Plant Line1 Mixer Name STRING "once" "$TS"
seen "DDATA Name 'once' after the resent DCMD with a timestamp" "$M" "$(metric Name) == ['once']"
M=$(mark)
$HOST dcmd-dup "$MQ_PORT" Plant Line1 Mixer Name STRING "twice" none
seen "DDATA Name 'twice' after the resent DCMD without a timestamp" "$M" "$(metric Name) == ['twice']"
# another command with the same timestamp to the same device is a command of
# its own (its bytes differ): executed; it also orders the log after the resends
$HOST dcmd "$MQ_PORT" Plant Line1 Mixer Run BOOLEAN 1 "$TS"
seen "DDATA Run true (a different DCMD with the same timestamp)" "$M" "$(metric Run) == [True]"
same "two writes of ST9:0 in df1sim's log for two commands each sent twice" \
	"$(grep -c 'cmd=0F/AA addr=ST9:0 ' "$T/sim.log")" 2
check "the timestamp-less resend logged as a redelivery" "grep -q 'taken as a redelivery' '$T/gw.err'"

# ---- DCMD to a read-only tag: refused, nothing sent, the true value again ----
M=$(mark)
$HOST dcmd "$MQ_PORT" Plant Line1 station1 Offset INT16 9
seen "DDATA Offset -5 (its true value) after the refused DCMD" "$M" "$(metric Offset) == [-5]"
same "no write of N7:1 in df1sim's log" "$(grep -c 'addr=N7:1 .*0F/AA\|0F/AA addr=N7:1' "$T/sim.log")" 0
check "the refusal logged" "grep -q 'write Offset' '$T/gw.err'"

# ---- NCMD rebirth: NBIRTH (same bdSeq) and DBIRTHs, no NDEATH ----
M=$(mark)
$HOST ncmd "$MQ_PORT" Plant Line1
seen "NBIRTH after the rebirth NCMD" "$M" "len($NB) == 1"
seen "both DBIRTHs again" "$M" "len([r for r in R if r['type'] == 'DBIRTH']) == 2"
check "no NDEATH on rebirth" "! has $M '[r for r in R if r[\"type\"] == \"NDEATH\"]'"
check "same bdSeq on rebirth" "has $M '[m[\"value\"] for m in $NB[0][\"metrics\"] if m[\"name\"] == \"bdSeq\"] == [0]'"

# ---- a silenced PLC: DDEATH within the watchdog; DBIRTH when it answers ----
M=$(mark)
K=$(python3 -c 'import time; print(time.time())')
kill -USR1 "$SIM"
wait_for "DDEATH of both devices" 200 has "$M" "{r['device'] for r in R if r['type'] == 'DDEATH'} == {'station1', 'Mixer'}"
# the poll engine judges a station when one of its attempts fails after the
# watchdog (1.5 s) has passed (df1_poll_set_watchdog(3)); the attempts queued
# when df1sim went silent fail one after the other, 1 s (--cmd-timeout) each,
# over the two stations' 7 blocks: about 8 s on an idle host, 14 s allowed
check "DDEATH within the watchdog and the failed attempts it waits for (14 s)" \
	"has $M \"max(r['t'] for r in R if r['type'] == 'DDEATH') - $K < 14\""
Q='[p for r in R if r["type"] == "DDATA" for p in r["props"].values() if p.get("Quality") in (1073742081, -2147483126) and p.get("Reason")]'
if has "$M" "$Q"; then ok; else
	bad "not answering: DDATA with a quality (Uncertain_LastKnownValue 1073742081, Bad_NotConnected -2147483126) and its reason before the DDEATH"
	$HOST has "$REC" "$M" 'print([(r["type"], r.get("props")) for r in R][:8]) or True'
fi
M=$(mark)
kill -USR2 "$SIM"
seen "DBIRTH of both again" "$M" "{r['device'] for r in R if r['type'] == 'DBIRTH'} == {'station1', 'Mixer'}"

# ---- kill -9: the broker sends the will, NDEATH with this bdSeq ----
M=$(mark)
kill -9 "$GW_PID"
seen "NDEATH (the will) after kill -9" "$M" "[r['bdseq'] for r in R if r['type'] == 'NDEATH'] == [0]"
check "NDEATH not retained, QoS 1" "has $M '[(r[\"retain\"], r[\"qos\"]) for r in R if r[\"type\"] == \"NDEATH\"] == [(False, 1)]'"

# ---- a restart: bdSeq + 1 (the state file) ----
M=$(mark)
gw_start
seen "NBIRTH after the restart, bdSeq 1" "$M" "[m['value'] for r in R if r['type'] == 'NBIRTH' for m in r['metrics'] if m['name'] == 'bdSeq'] == [1]"
seen "DBIRTHs after the restart" "$M" "len([r for r in R if r['type'] == 'DBIRTH']) == 2"
M=$(mark)
kill -TERM "$GW_PID"
lib_reap "$GW_PID"
seen "NDEATH before a clean disconnect, bdSeq 1" "$M" "[r['bdseq'] for r in R if r['type'] == 'NDEATH'] == [1]"
check "counters: births, deaths, commands, rejected, rebirths" "grep -q 'sparkplug: .* births, .* deaths, .* commands (.* rejected), .* rebirths' '$T/gw.out'"

# ---- every message: decoded, seq continuous, DDATA born, bdSeq of its will ----
if $HOST check "$REC" > "$T/check.out"; then ok; else bad "Sparkplug rules"; sed 's/^/  /' "$T/check.out"; fi

# ---- primary host: no birth before its STATE is online; offline: NDEATH, reconnect ----
M=$(mark)
gw_start --primary-host Scada
tries=20; while [ $tries -gt 0 ]; do tick; tries=$((tries - 1)); done     # 2 s with no STATE
check "no NBIRTH while the primary host is not online" "! has $M '$NB'"
$HOST state "$MQ_PORT" Scada online
seen "NBIRTH once the primary host is online" "$M" "len($NB) == 1"
# a STATE older than the last one taken: a past session's will, delivered
# late; not a reason to leave (tck-id-operational-behavior-edge-node-termination-host-offline-timestamp)
M=$(mark)
OLD=$(python3 -c 'import time; print(int(time.time() * 1000) - 60000)')
$HOST state "$MQ_PORT" Scada offline "$OLD"
wait_for "the stale STATE logged" 100 grep -q "STATE of Scada older than the last one taken" "$T/gw.err"
tries=10; while [ $tries -gt 0 ]; do tick; tries=$((tries - 1)); done
check "no NDEATH for an offline STATE older than the online one" "! has $M '[r for r in R if r[\"type\"] == \"NDEATH\"]'"
check "no NBIRTH again either (the session goes on)" "! has $M '$NB'"
M=$(mark)
$HOST state "$MQ_PORT" Scada offline
seen "NDEATH when the primary host goes offline" "$M" "[r for r in R if r['type'] == 'NDEATH']"
tries=10; while [ $tries -gt 0 ]; do tick; tries=$((tries - 1)); done
check "no NBIRTH while it stays offline" "! has $M '$NB'"
# back in the Sparkplug 2.x form: STATE/Scada ONLINE (the 3.0 retained STATE cleared first)
mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -t spBv1.0/STATE/Scada -r -n 2>/dev/null
mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -q 1 -t STATE/Scada -m ONLINE
seen "NBIRTH again (a new session) when it is back (2.x STATE)" "$M" "len($NB) == 1"
check "the new session's bdSeq is the next one" "has $M '[m[\"value\"] for m in $NB[0][\"metrics\"] if m[\"name\"] == \"bdSeq\"] == [3]'"
kill -TERM "$GW_PID"
lib_reap "$GW_PID"
mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -t spBv1.0/STATE/Scada -r -n 2>/dev/null

# ---- aliases: names and aliases in births, aliases only in DATA ----
M=$(mark)
gw_start --sparkplug-aliases --json yes --prefix plant/line1     # JSON beside Sparkplug
seen "DBIRTHs with aliases" "$M" "len([m for r in R if r['type'] == 'DBIRTH' for m in r['metrics'] if m['alias'] and m['name']]) >= 11"
$HOST dcmd "$MQ_PORT" Plant Line1 station1 Speed INT16 555
seen "DDATA by alias only (no name on the wire)" "$M" "[r for r in R if r['type'] == 'DDATA' and r['wire_names'] == [''] and r['metrics'][0]['name'] == 'Speed' and r['metrics'][0]['value'] == 555]"
check "JSON topics beside Sparkplug" \
	"mosquitto_sub -h 127.0.0.1 -p $MQ_PORT -t plant/line1/tag/Speed -C 1 -W 5 | grep -q '\"value\":555'"
A=$($HOST alias "$REC" Speed)
M2=$(mark)
$HOST dcmd "$MQ_PORT" Plant Line1 station1 "#$A" INT16 321
seen "a DCMD by alias only written (DDATA 321)" "$M2" "[r for r in R if r['type'] == 'DDATA' and r['metrics'][0]['name'] == 'Speed' and r['metrics'][0]['value'] == 321]"
same "the alias DCMD in df1sim's log" "$(grep -c 'cmd=0F/AA addr=N7:0 ' "$T/sim.log")" 3
# a reload (SIGHUP): every birth again, no NDEATH
M2=$(mark)
kill -HUP "$GW_PID"
seen "NBIRTH and DBIRTHs after a reload" "$M2" "len($NB) == 1 and len([r for r in R if r['type'] == 'DBIRTH']) == 2"
check "no NDEATH on a reload" "! has $M2 '[r for r in R if r[\"type\"] == \"NDEATH\"]'"
# seq past 255 in one session: values changed through df1sim's EtherNet/IP side
# (Offset, Level, Total) until a DDATA of seq 255 is followed by one of seq 0;
# the rules below check that every seq on the way was the next one
WRAP='[1 for a, b in zip(R, R[1:]) if a.get("seq") == 255 and b.get("seq") == 0]'
i=1; tries=600
while [ $tries -gt 0 ] && ! has "$M2" "$WRAP"; do
	"$BIN/df1write" -d "eip://127.0.0.1:$EIP_PORT" -q N7:1=$i F8:0=$i L10:0=$i 2>> "$T/eip.err" || break
	i=$((i + 1)); tries=$((tries - 1))
done
check "seq wrapped from 255 to 0 within the session (values from df1sim's EtherNet/IP side)" "has $M2 '$WRAP'"
check "Node Control/Rebirth never aliased" "has $M '[m for r in R if r[\"type\"] == \"NBIRTH\" for m in r[\"metrics\"] if m[\"name\"] == \"Node Control/Rebirth\" and not m[\"alias\"]]'"
kill -TERM "$GW_PID"
lib_reap "$GW_PID"

# ---- without --sparkplug-state: bdSeq kept in the state folder, per group and edge node ----
# XDG_STATE_HOME is the test's own (tests/support/lib.sh); XS overrides it
# gw_plain EDGE: df1gw as an operator starts it, no --sparkplug-state
gw_plain() {
	env XDG_STATE_HOME="${XS:-$XDG_STATE_HOME}" "$GW" -d "$SIM_DEV" --map "$T/map.csv" \
		--mqtt "mqtt://127.0.0.1:$MQ_PORT" --sparkplug Plant --edge-node "$1" --json no --watchdog 1500 \
		> "$T/gw_$1.out" 2>> "$T/gw_$1.err" &
	GW_PID=$!
	echo "$GW_PID" >> "$T/.sims"
}
# bd EDGE: the bdSeq of EDGE's NBIRTHs; will EDGE: the bdSeq of its NDEATHs
bd() { echo "[m['value'] for r in R if r['type'] == 'NBIRTH' and r['topic'].endswith('/$1') for m in r['metrics'] if m['name'] == 'bdSeq']"; }
will() { echo "[r['bdseq'] for r in R if r['type'] == 'NDEATH' and r['topic'].endswith('/$1')]"; }
M=$(mark)
gw_plain Line9
seen "state folder: NBIRTH bdSeq 0 at the first start (an empty folder)" "$M" "$(bd Line9) == [0]"
same "state folder: the file \$XDG_STATE_HOME/df1gw/Plant@Line9.bdseq" \
	"$(cat "$XDG_STATE_HOME/df1gw/Plant@Line9.bdseq" 2>&1)" "bdSeq 0"
for k in 1 2; do    # (lib_reap uses n)
	M=$(mark)
	kill -9 "$GW_PID"
	lib_reap "$GW_PID"
	seen "state folder: the killed session's will carries its bdSeq $((k - 1))" "$M" "$(will Line9) == [$((k - 1))]"
	M=$(mark)
	gw_plain Line9
	seen "state folder: kill -9, a restart without --sparkplug-state births with bdSeq $k" "$M" "$(bd Line9) == [$k]"
	if has "$M" "$(will Line9)"; then bad "state folder: an NDEATH of the old session after the new NBIRTH ($k)"; else ok; fi
done
M=$(mark)
kill -TERM "$GW_PID"
lib_reap "$GW_PID"
seen "state folder: NDEATH before a clean stop, bdSeq 2" "$M" "$(will Line9) == [2]"
check "state folder: nothing said about it" "! grep -qi 'state folder\|bdSeq' '$T/gw_Line9.err'"
# another edge node of the same group: a file of its own, from 0
M=$(mark)
gw_plain Line7
seen "state folder: another edge node starts at 0" "$M" "$(bd Line7) == [0]"
kill -TERM "$GW_PID"
lib_reap "$GW_PID"
check "state folder: a file per edge node" \
	"[ -f '$XDG_STATE_HOME/df1gw/Plant@Line7.bdseq' ] && [ \"\$(cat '$XDG_STATE_HOME/df1gw/Plant@Line9.bdseq')\" = 'bdSeq 2' ]"
# systemd's StateDirectory= ($STATE_DIRECTORY) comes first
mkdir -p "$T/sd"
M=$(mark)
STATE_DIRECTORY="$T/sd:$T/other"
export STATE_DIRECTORY
gw_plain Line6
unset STATE_DIRECTORY
seen "STATE_DIRECTORY: NBIRTH bdSeq 0" "$M" "$(bd Line6) == [0]"
kill -TERM "$GW_PID"
lib_reap "$GW_PID"
check "STATE_DIRECTORY: the file there, not in XDG_STATE_HOME" \
	"[ -f '$T/sd/Plant@Line6.bdseq' ] && [ ! -e '$XDG_STATE_HOME/df1gw/Plant@Line6.bdseq' ]"
# a folder that cannot be made: said once (the path, the reason), bdSeq from 0 as before
: > "$T/notadir"
M=$(mark)
XS="$T/notadir" gw_plain Line5
seen "unusable state folder: NBIRTH bdSeq 0 all the same" "$M" "$(bd Line5) == [0]"
M=$(mark)
kill -9 "$GW_PID"
lib_reap "$GW_PID"
seen "unusable state folder: the will" "$M" "$(will Line5) == [0]"
same "unusable state folder: said once, with the path and the reason" \
	"$(grep -c "state folder $T/notadir/df1gw: Not a directory" "$T/gw_Line5.err")" 1
check "unusable state folder: nothing else said of it" "[ \$(grep -ci 'bdSeq' '$T/gw_Line5.err') -eq 1 ]"
if $HOST check "$REC" > "$T/check.out"; then ok; else bad "Sparkplug rules (all sessions)"; sed 's/^/  /' "$T/check.out"; fi
finish
