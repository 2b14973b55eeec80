#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_map_type.sh - the mapping file's Type column through df1mon --map and
# df1gw against df1sim (libdf1(7) "Mapping file"): a Type that fits converts
# as declared (REAL on N7:0 is a float field in InfluxDB line protocol, read
# back with tests/support/influx_parse.py; an empty Type keeps the address's
# own), a Type that does not fit or is no Type is a bad row named by its item
# (df1mon reports and skips it, df1gw exits 2), and a /set of a REAL tag on a
# word is converted back and range checked, df1sim's --log showing what
# reached the PLC. Expected values come from the --data file below.
# Run from the repository root with DF1_BIN=<build/bin>; bounded waits only.
. tests/support/lib.sh

MON="$BIN/df1mon"
GW="$BIN/df1gw"
PARSE="python3 tests/support/influx_parse.py"
unset DF1_DEVICE

cat > "$T/data.txt" <<'DATA'
N7:0=-123,40,7
F8:0=1.5
L10:0=70000
B3:0=32
T4:0.PRE=100
T4:0.ACC=7
DATA
cat > "$T/good.csv" <<'MAP'
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
Level,Read,REAL,1,SLC,N7:0,,100
Wide,ReadWrite,DINT,1,SLC,N7:1,,100
Set,ReadWrite,real,1,SLC,N7:2,,100
Temp,Read,FLOAT,1,SLC,F8:0,,100
Big,Read,LONG,1,SLC,L10:0,,100
Run,Read,BOOL,1,SLC,B3:0/5,,100
Tmr,Read,TIMER,1,SLC,T4:0,,100
Acc,Read,INT,1,SLC,T4:0.ACC,,100
Plain,Read,,1,SLC,N7:0,,100
MAP
{ cat "$T/good.csv"; cat <<'MAP'
F1,Read,INT,1,SLC,F8:0,,100
B1,Read,FLOAT,1,SLC,B3:0/5,,100
W,Read,WHATEVER,1,SLC,N7:0,,100
T1,Read,INT,1,SLC,T4:0,,100
MAP
} > "$T/bad.csv"

# field TAG FIELD: the value in the parsed lines (JSON) of $T/lines
field() {
	python3 -c 'import json,sys
for l in open(sys.argv[1]):
    o = json.loads(l)
    if o["tags"].get("tag") == sys.argv[2]:
        v = o["fields"].get(sys.argv[3])
        print("<absent>" if v is None else json.dumps(v)); break
else:
    print("<no line>")' "$T/lines" "$1" "$2"
}

sim_start sim --data "$T/data.txt" --log "$T/sim.log" || finish

# ---- df1mon --map ----
expect 0 "df1mon --map -1 -f influx, every Type that fits" -- "$MON" -d "$SIM_DEV" --map "$T/good.csv" -1 -f influx
check "every line parses as line protocol" "$PARSE < '$T/out' > '$T/lines'"
same "REAL on N7:0: a float field" "$(field Level Level)" "-123.0"
same "the same word without a Type: an integer" "$(field Plain Plain)" "-123"
same "DINT on N7:1: an integer" "$(field Wide Wide)" "40"
same "FLOAT on F8:0" "$(field Temp Temp)" "1.5"
same "LONG on L10:0" "$(field Big Big)" "70000"
same "BOOL on B3:0/5" "$(field Run Run)" "true"
same "TIMER on T4:0: its members" "$(field Tmr Tmr.PRE) $(field Tmr Tmr.ACC)" "100 7"
same "INT on T4:0.ACC" "$(field Acc Acc)" "7"
# ---- df1mon: bad rows refuse the file, as df1gw does; --skip-bad-rows polls the rest ----
expect 2 "df1mon --map with bad Types: refused" -- "$MON" -d "$SIM_DEV" --map "$T/bad.csv" -1 -f influx
err_has "item 10: INT on a float" "Item: 10, Type INT does not fit F8:0"
err_has "item 11: FLOAT on a bit" "Item: 11, Type FLOAT does not fit B3:0/5: a bit is BOOL"
err_has "item 12: no Type" "Item: 12, Invalid Type (WHATEVER)"
err_has "item 13: INT on a whole timer, refused" "Item: 13, Type INT does not fit T4:0: a whole timer is TIMER"
same "refused: nothing polled" "$(wc -l < "$T/out" | tr -d ' ')" 0
expect 0 "df1mon --map --skip-bad-rows: the good rows polled" -- "$MON" -d "$SIM_DEV" --map "$T/bad.csv" -1 -f influx --skip-bad-rows
err_has "--skip-bad-rows: item 12 still named" "Item: 12, Invalid Type (WHATEVER)"
same "the bad rows skipped, the nine good ones polled" "$(wc -l < "$T/out" | tr -d ' ')" 9

# ---- df1gw: bad rows are exit 2 ----
expect 2 "df1gw refuses a map with bad Types" -- "$GW" -d "$SIM_DEV" --map "$T/bad.csv" --mqtt mqtt://127.0.0.1:1 --once
err_has "df1gw names item 11" "Item: 11, Type FLOAT does not fit B3:0/5: a bit is BOOL"
err_has "df1gw names item 12" "Item: 12, Invalid Type (WHATEVER)"

# ---- df1gw: values and writes as the Type declares (a broker on loopback) ----
MOSQ=${MOSQUITTO:-/usr/sbin/mosquitto}
if [ ! -x "$MOSQ" ] || ! command -v mosquitto_sub >/dev/null 2>&1; then
	echo "mosquitto or mosquitto-clients missing (apt-get install mosquitto mosquitto-clients)"
	bad "no broker to test against"
	finish
fi
MQ_PORT=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
printf 'listener %s 127.0.0.1\npersistence false\nuser %s\nallow_anonymous true\n' "$MQ_PORT" "$(id -un)" > "$T/mq.conf"
"$MOSQ" -c "$T/mq.conf" > "$T/mq.log" 2>&1 &
echo $! >> "$T/.sims"
port_open() { python3 -c "import socket; socket.create_connection(('127.0.0.1', $MQ_PORT), 1).close()" 2>/dev/null; }
wait_for "broker listens" 100 port_open
P=df1/type
sub1() { mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t "$1" -C 1 -W 2 2>/dev/null; }
pub() { mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -q 1 -t "$1" -m "$2"; }
has() { sub1 "$1" | grep -F -q -e "$2"; }
"$GW" -d "$SIM_DEV" --map "$T/good.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix "$P" --timeout 300 \
	> "$T/gw.out" 2> "$T/gw.err" &
GW_PID=$!
echo "$GW_PID" >> "$T/.sims"
wait_for "Set GOOD" 100 has "$P/tag/Set" '"quality":"GOOD"'
check "Set: N7:2 published" 'has "$P/tag/Set" "{\"value\":7,"'
mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t "$P/tag/+/result" -v > "$T/results.txt" 2>&1 &
echo $! >> "$T/.sims"
sub_ready() { pub "$P/tag/Nope/set" 1 && grep -q "^$P/tag/Nope/result" "$T/results.txt"; }
wait_for "result subscriber ready" 50 sub_ready
writes() { grep -c "cmd=0F/AA addr=N7:2 " "$T/sim.log"; }
before=$(writes)
pub "$P/tag/Set/set" '{"value": 12.0, "id": "r1"}'
wait_for "12.0 to a REAL tag on N7:2: written" 50 grep -q "\"id\":\"r1\",\"ok\":true" "$T/results.txt"
same "r1 reached the PLC once" "$(writes)" "$((before + 1))"
wait_for "Set read back from the PLC: 12" 50 has "$P/tag/Set" '{"value":12,'
pub "$P/tag/Set/set" '{"value": 2.5, "id": "r2"}'
wait_for "2.5 to a REAL tag on a word: refused" 50 grep -q "\"id\":\"r2\",\"ok\":false,\"error\":\"DF1_E_RANGE" "$T/results.txt"
pub "$P/tag/Wide/set" '{"value": 40000, "id": "r3"}'
wait_for "40000 to a DINT tag on a word: refused" 50 grep -q "\"id\":\"r3\",\"ok\":false,\"error\":\"DF1_E_RANGE" "$T/results.txt"
same "r2, r3: nothing more on the line" "$(grep -c "cmd=0F/AA addr=N7:[12] " "$T/sim.log")" "$((before + 1))"
kill -TERM "$GW_PID" 2>/dev/null
lib_reap "$GW_PID"
sim_stop
finish
