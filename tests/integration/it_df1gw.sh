#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_df1gw.sh - df1gw against real parts: Debian's mosquitto broker on a free
# loopback port, df1sim on a pseudo-terminal, mosquitto_sub / mosquitto_pub as
# the plant's clients, df1sim's --log as the record of what reached the PLC.
# Expected values come from the df1sim --data file below and the issue's
# payload rules, never from df1gw's own output. Waits are bounded loops
# (mosquitto_sub -W, wait_for), never sleeps that hope.
. tests/support/lib.sh

if [ ! -x "$MOSQ" ] || ! command -v mosquitto_sub >/dev/null 2>&1; then
	echo "mosquitto or mosquitto-clients missing (apt-get install mosquitto mosquitto-clients)"
	bad "no broker to test against"
	finish
fi
GW="$BIN/df1gw"

MQ_PORT=$(free_port)
broker_start broker "$MQ_PORT"
BROKER1=$BROKER_PID

# sub1 TOPIC: the retained message of TOPIC (at most one, 2 s), payload only
sub1() { mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t "$1" -C 1 -W 2 2>/dev/null; }
pub() { mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -q 1 -t "$1" -m "$2"; }
# payload without its time (the rest is known in advance)
nots() { sed 's/,"ts":"[^"]*"//'; }
# has TOPIC TEXT: TOPIC's retained payload holds TEXT
has() { sub1 "$1" | grep -F -q -e "$2"; }
hasnt() { ! sub1 "$1" | grep -F -q -e "$2"; }

cat > "$T/plc.txt" <<'EOF'
N7:0=123
N7:1=-5
F8:1=1.5,2.25,-3
B3:0=0x0020
ST9:0="hello, PLC"
T4:0=PRE=500 ACC=7 EN=1
L10:0=100000
EOF
cat > "$T/map.csv" <<'EOF'
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
Speed,ReadWrite,INT,1,SLC,N7:0,1,100
Speed_Mirror,Read,INT,1,SLC,N7:0,1,100
Offset,ReadWrite,INT,1,SLC,N7:1,1,100
Level,Read,FLOAT,1,SLC,F8:1,3,100
Run,ReadWrite,BOOL,1,SLC,B3:0/5,1,100
Name,ReadWrite,STRING,1,SLC,ST9:0,1,100
Cycle,ReadWrite,TIMER,1,SLC,T4:0,1,100
Total,Read,LONG,1,MicroLogix,L10:0,1,100
EOF

sim_start plc --data "$T/plc.txt" --log "$T/sim.log" || finish

# ---- bad configuration: exit 2 with the catalog ID, nothing published ----
printf 'Tag,Command,Type,Station,PLC_Type,Address\nGood,Read,INT,1,SLC,N7:0\nBroken,Read,INT,1,SLC,N7:x\n' > "$T/bad.csv"
expect 2 "bad mapping row" -- "$GW" -d "$SIM_DEV" --map "$T/bad.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix bad
err_has "bad mapping row: catalog ID" "[2503] ERR_ADDRESS_SYNTAX"
err_has "bad mapping row: its line" "line 3"
printf 'Station,Baud\n300,19200\n' > "$T/badnet.csv"
expect 2 "bad network file" -- "$GW" -N "$T/badnet.csv" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix bad
err_has "bad network file: catalog ID" "[2552] CRT_BAD_STATION_ID"
expect 2 "broker URL that does not parse" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "http://127.0.0.1:$MQ_PORT" --prefix bad
err_has "broker URL: says what it expects" "mqtt://HOST[:PORT]"
expect 2 "broker URL with a password" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://u:secret@127.0.0.1:$MQ_PORT" --prefix bad
err_has "broker URL with a password: why" "--password-file"
expect 2 "--password refused" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --password=secret --prefix bad
err_has "--password refused: why" "visible to every user"
expect 2 "unknown option" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --bogus --prefix bad
expect 2 "a tag name that is no topic level" -- sh -c "printf 'Tag,Command,Type,Station,PLC_Type,Address\na/b,Read,INT,1,SLC,N7:0\n' > '$T/slash.csv'; exec '$GW' -d '$SIM_DEV' --map '$T/slash.csv' --mqtt 'mqtt://127.0.0.1:$MQ_PORT' --prefix bad"
err_has "tag name: why" "cannot hold '/'"
expect 2 "-a is not df1gw's (stations come from the map)" -- "$GW" -a 2 -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix bad
got=$(mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t 'bad/#' -v -W 1 2>/dev/null)
same "bad configuration: nothing published" "$got" ""
expect 0 "--help" -- "$GW" --help
check "--help: topics" 'grep -q "tag/NAME/set" "$T/out"'
expect 0 "--version" -- "$GW" --version

# ---- the gateway ----
P=df1/test
gw_start() {
	"$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix "$P" \
		--timeout 200 --enq-retries 1 --watchdog 4000 -v "$@" > "$T/gw.out" 2> "$T/gw.err" &
	GW_PID=$!
	echo "$GW_PID" >> "$T/.sims"
}
gw_start
wait_for "status online" 100 has "$P/status" online

# every tag retained, with df1sim's values and GOOD
wait_for "Speed GOOD" 50 has "$P/tag/Speed" '"quality":"GOOD"'
same "Speed" "$(sub1 "$P/tag/Speed" | nots)" \
	'{"value":123,"quality":"GOOD","reason":"none","address":"N7:0","station":1}'
same "Offset (signed)" "$(sub1 "$P/tag/Offset" | nots)" \
	'{"value":-5,"quality":"GOOD","reason":"none","address":"N7:1","station":1}'
same "Level (Count 3: an array of floats, shortest form)" "$(sub1 "$P/tag/Level" | nots)" \
	'{"value":[1.5,2.25,-3],"quality":"GOOD","reason":"none","address":"F8:1","station":1}'
same "Run (a bit: a boolean)" "$(sub1 "$P/tag/Run" | nots)" \
	'{"value":true,"quality":"GOOD","reason":"none","address":"B3:0/5","station":1}'
same "Name (a string)" "$(sub1 "$P/tag/Name" | nots)" \
	'{"value":"hello, PLC","quality":"GOOD","reason":"none","address":"ST9:0","station":1}'
same "Cycle (a timer: an object of its members)" "$(sub1 "$P/tag/Cycle" | nots)" \
	'{"value":{"EN":true,"TT":false,"DN":false,"PRE":500,"ACC":7},"quality":"GOOD","reason":"none","address":"T4:0","station":1}'
same "Total (L: a 32-bit integer)" "$(sub1 "$P/tag/Total" | nots)" \
	'{"value":100000,"quality":"GOOD","reason":"none","address":"L10:0","station":1}'
check "ts is RFC 3339 UTC" 'sub1 "$P/tag/Speed" | grep -Eq "\"ts\":\"[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}\.[0-9]{3}Z\""'
wait_for "station 1 ok" 50 has "$P/station/1" '"state":"ok"'
check "station 1: its counters" 'sub1 "$P/station/1" | grep -q "\"tags\":8,\"attempts\":[0-9]*,\"failures\":0"'

# ---- a write: exactly once on the line, its result once; a change published, only it ----
mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t "$P/tag/#" -v -R > "$T/live.txt" 2>&1 &
LIVE=$!
echo "$LIVE" >> "$T/.sims"
marker_seen() { pub "$P/tag/marker" m1 && grep -q "^$P/tag/marker m1" "$T/live.txt"; }
wait_for "live subscriber ready" 50 marker_seen
writes_n7_0() { grep -c "cmd=0F/AA addr=N7:0 " "$T/sim.log"; }
before=$(writes_n7_0)
pub "$P/tag/Speed/set" '{"value": 777, "id": "w-1"}'
wait_for "result of w-1" 50 grep -q "^$P/tag/Speed/result " "$T/live.txt"
same "result of w-1" "$(grep "^$P/tag/Speed/result " "$T/live.txt")" \
	"$P/tag/Speed/result {\"id\":\"w-1\",\"ok\":true,\"error\":null,\"unconfirmed\":false}"
same "w-1 executed once in df1sim's log" "$(writes_n7_0)" "$((before + 1))"
# the mirror reads N7:0 from df1sim: the new value comes from the PLC, within a scan
wait_for "Speed_Mirror republished with df1sim's new value" 50 grep -q "^$P/tag/Speed_Mirror {\"value\":777," "$T/live.txt"
# the same id again (a redelivery): not executed, no second result
pub "$P/tag/Speed/set" '{"value": 777, "id": "w-1"}'
pub "$P/tag/Offset/set" '{"value": 6, "id": "w-2"}'
wait_for "result of w-2" 50 grep -q "^$P/tag/Offset/result {\"id\":\"w-2\",\"ok\":true" "$T/live.txt"
same "w-1 redelivered: not executed again" "$(writes_n7_0)" "$((before + 1))"
same "w-1 redelivered: no second result" "$(grep -c "^$P/tag/Speed/result " "$T/live.txt")" 1
# a bad value: an error result, nothing on the line
lines=$(wc -l < "$T/sim.log")
pub "$P/tag/Speed/set" '{"value": "fast", "id": "w-3"}'
wait_for "result of w-3" 50 grep -q "\"id\":\"w-3\"" "$T/live.txt"
check "w-3: an error result" 'grep "\"id\":\"w-3\"" "$T/live.txt" | grep -q "\"ok\":false,\"error\":\"DF1_E_TYPE: value does not fit the file type: expected a number, got a string\",\"unconfirmed\":false"'
pub "$P/tag/Speed/set" '40000'
wait_for "result of 40000" 50 grep -q "40000 does not fit a 16-bit integer" "$T/live.txt"
check "40000: no id" 'grep "40000 does not fit" "$T/live.txt" | grep -q "{\"id\":null,\"ok\":false,\"error\":\"DF1_E_RANGE"'
pub "$P/tag/Level/set" '[1,2,3]'
wait_for "a read-only tag refused" 50 grep -q "^$P/tag/Level/result .*read-only tag" "$T/live.txt"
pub "$P/tag/Speed/set" '{"value": 1,'
wait_for "not JSON refused" 50 grep -q "^$P/tag/Speed/result .*not JSON: at byte" "$T/live.txt"
pub "$P/tag/Nope/set" '1'
wait_for "an unknown tag refused" 50 grep -q "^$P/tag/Nope/result .*no tag" "$T/live.txt"
same "refused writes: nothing on the line" "$(sed -n "$((lines + 1)),\$p" "$T/sim.log" | grep -c "0F/A[AB]")" 0
# a bit, a timer member, a string: written as the PLC holds them
pub "$P/tag/Run/set" '{"value": false, "id": 17}'
wait_for "result of the bit write (a number id)" 50 grep -q "^$P/tag/Run/result {\"id\":17,\"ok\":true" "$T/live.txt"
wait_for "Run republished false" 50 grep -q "^$P/tag/Run {\"value\":false," "$T/live.txt"
pub "$P/tag/Cycle/set" '{"PRE": 900}'
wait_for "Cycle: PRE written, the rest kept" 50 grep -q "^$P/tag/Cycle {\"value\":{\"EN\":true,\"TT\":false,\"DN\":false,\"PRE\":900,\"ACC\":7}" "$T/live.txt"
pub "$P/tag/Name/set" '"caf\u00e9 ok"'
wait_for "Name: one byte per character" 50 grep -q "^$P/tag/Name {\"value\":\"caf\\\\u00e9 ok\"" "$T/live.txt"
pub "$P/tag/Name/set" '"\u20ac"'
wait_for "Name: a character above U+00FF refused" 50 grep -q "^$P/tag/Name/result .*U+00FF" "$T/live.txt"
# only what changed was republished: the tags written (and Speed_Mirror), nothing else
others=$(grep -v -e "^$P/tag/marker " -e "/set " -e "/result " -e "^$P/tag/Speed " -e "^$P/tag/Speed_Mirror " \
	-e "^$P/tag/Offset " -e "^$P/tag/Run " -e "^$P/tag/Cycle " -e "^$P/tag/Name " "$T/live.txt")
same "only changed tags republished" "$others" ""
check "Level and Total never republished" '! grep -q -e "^$P/tag/Level " -e "^$P/tag/Total " "$T/live.txt"'
kill "$LIVE" 2>/dev/null

# ---- df1sim silenced: UNCERTAIN, then BAD with the reason, station offline; back: GOOD ----
kill -USR1 "$SIM_PID"
wait_for "UNCERTAIN comm_failure" 100 has "$P/tag/Offset" '"quality":"UNCERTAIN","reason":"comm_failure","error":"[25'
check "UNCERTAIN keeps the last value" 'has "$P/tag/Offset" "{\"value\":6,"'
wait_for "BAD station_offline" 100 has "$P/tag/Offset" '"quality":"BAD","reason":"station_offline"'
wait_for "station 1 offline" 50 has "$P/station/1" '"state":"offline","error":"[25'
kill -USR2 "$SIM_PID"
wait_for "GOOD again" 100 has "$P/tag/Offset" '"quality":"GOOD","reason":"none"'
wait_for "station 1 ok again" 50 has "$P/station/1" '"state":"ok","error":null'

# ---- broker lost: the last will meanwhile; back: reconnected, republished ----
# through a TCP relay that can be cut: the broker sees the gateway vanish and
# publishes its will, which an observer on the broker sees
RELAY_PORT=$(free_port)
cat > "$T/relay.py" <<'EOF'
import socket, sys, threading
lst = socket.socket(); lst.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
lst.bind(("127.0.0.1", int(sys.argv[1]))); lst.listen(4)
def pump(a, b):
    try:
        while True:
            d = a.recv(65536)
            if not d: break
            b.sendall(d)
    except OSError: pass
    for s in (a, b):
        try: s.shutdown(socket.SHUT_RDWR)
        except OSError: pass
while True:
    c, _ = lst.accept()
    u = socket.create_connection(("127.0.0.1", int(sys.argv[2])))
    threading.Thread(target=pump, args=(c, u), daemon=True).start()
    threading.Thread(target=pump, args=(u, c), daemon=True).start()
EOF
relay_start() {
	python3 "$T/relay.py" "$RELAY_PORT" "$MQ_PORT" 2> "$T/relay.err" &
	RELAY_PID=$!
	echo "$RELAY_PID" >> "$T/.sims"
	wait_for "relay listens" 100 port_open "$RELAY_PORT"
}
sim_stop "$GW_PID"
relay_start
P=df1/relayed
# a retained .../set (stale, delivered at subscription) is no write
mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -q 1 -r -t "$P/tag/Offset/set" -m '{"value": 99, "id": "r-1"}'
mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t "$P/tag/Offset/result" -t "$P/probe" -v > "$T/retained.txt" 2>&1 &
RS=$!
echo "$RS" >> "$T/.sims"
# the result is not retained: df1gw starts once the subscriber is known to listen
sub_ready() {
	mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -t "$P/probe" -m ready 2>/dev/null
	grep -q "^$P/probe ready" "$T/retained.txt"
}
wait_for "relayed: the result subscriber listens" 100 sub_ready
"$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$RELAY_PORT" --prefix "$P" --keepalive 5 \
	> "$T/gw2.out" 2> "$T/gw2.err" &
GW_PID=$!
echo "$GW_PID" >> "$T/.sims"
wait_for "relayed: online" 100 has "$P/status" online
wait_for "relayed: Speed GOOD" 50 has "$P/tag/Speed" '"quality":"GOOD"'
wait_for "a retained set refused" 50 grep -q "^$P/tag/Offset/result {\"id\":\"r-1\",\"ok\":false,\"error\":\"DF1_E_INVAL: invalid argument: a retained message is not a write" "$T/retained.txt"
check "Offset not written by the retained set" 'has "$P/tag/Offset" "{\"value\":6,"'
mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -r -t "$P/tag/Offset/set" -n
kill "$RS" 2>/dev/null
mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t "$P/status" -v > "$T/status.txt" 2>&1 &
OBS=$!
echo "$OBS" >> "$T/.sims"
wait_for "observer sees online" 50 grep -q "^$P/status online" "$T/status.txt"
kill -KILL "$RELAY_PID"
wait "$RELAY_PID" 2>/dev/null
wait_for "the last will: offline while the broker is out of reach" 100 grep -q "^$P/status offline" "$T/status.txt"
mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -r -t "$P/tag/Speed" -n     # forget it: a republish brings it back
relay_start
wait_for "reconnected: online again" 200 sh -c "grep -c '^$P/status online' '$T/status.txt' | grep -q 2"
wait_for "reconnected: every tag republished" 50 has "$P/tag/Speed" '"quality":"GOOD"'
check "the gateway said it lost the broker" 'grep -q "connection lost" "$T/gw2.err"'
check "gateway still running" 'kill -0 "$GW_PID"'
kill "$OBS" 2>/dev/null

# the broker itself killed and restarted (no persistence: it forgets everything)
sim_stop "$GW_PID"
P=df1/test
gw_start
wait_for "online (broker restart test)" 100 has "$P/status" online
kill -KILL "$BROKER1"
wait "$BROKER1" 2>/dev/null
broker_start broker "$MQ_PORT"
BROKER1=$BROKER_PID
wait_for "after the broker restart: online" 300 has "$P/status" online
wait_for "after the broker restart: tags republished" 50 has "$P/tag/Level" '"value":[1.5,2.25,-3],"quality":"GOOD"'
wait_for "after the broker restart: station republished" 50 has "$P/station/1" '"state":"ok"'
pub "$P/tag/Offset/set" '{"value": 8, "id": "after-restart"}'
wait_for "re-subscribed: a write after the restart" 50 has "$P/tag/Offset" '{"value":8,'

# ---- SIGHUP: the mapping file reloaded, the broker connection kept ----
mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t "$P/status" -v -R > "$T/status2.txt" 2>&1 &
OBS=$!
echo "$OBS" >> "$T/.sims"
sed -e '/^Name,/d' -e 's|^Run,ReadWrite,BOOL,1,SLC,B3:0/5|Run,ReadWrite,BOOL,1,SLC,B3:0/6|' "$T/map.csv" > "$T/map2.csv"
echo "Extra,Read,INT,1,SLC,N7:5,1,100" >> "$T/map2.csv"
cp "$T/map2.csv" "$T/map.csv"
hup_from=$(wc -l < "$T/gw.err")
kill -HUP "$GW_PID"
wait_for "reload: a tag added" 100 has "$P/tag/Extra" '{"value":5,"quality":"GOOD","reason":"none"'
wait_for "reload: a tag changed" 50 has "$P/tag/Run" '"address":"B3:0/6"'
wait_for "reload: a removed tag's retained topic cleared" 50 sh -c "! mosquitto_sub -h 127.0.0.1 -p $MQ_PORT -t '$P/tag/Name' -C 1 -W 1 | grep -q ."
check "reload: still running" 'kill -0 "$GW_PID"'
check "reload: the broker connection kept" '! sed -n "$((hup_from + 1)),\$p" "$T/gw.err" | grep -q -e "connection lost" -e "connected again"'
same "reload: status never offline" "$(cat "$T/status2.txt")" ""
kill "$OBS" 2>/dev/null
printf 'Tag,Command,Type,Station,PLC_Type,Address\nBroken,Read,INT,1,SLC,N7:x\n' > "$T/map.csv"
kill -HUP "$GW_PID"
wait_for "reload of a bad file: reported with its catalog ID" 50 grep -q "\[2503\] ERR_ADDRESS_SYNTAX" "$T/gw.err"
wait_for "reload of a bad file: the old tags kept" 50 grep -q "not reloaded" "$T/gw.err"
check "reload of a bad file: still running" 'kill -0 "$GW_PID"'
cp "$T/map2.csv" "$T/map.csv"

# ---- the line lost (df1sim gone): BAD with the reason; back: GOOD, nothing exits ----
sim_stop "$SIM_PID"
wait_for "line lost: BAD line_lost" 100 has "$P/tag/Speed" '"quality":"BAD","reason":"line_lost"'
wait_for "line lost: station offline" 50 has "$P/station/1" '"state":"offline"'
check "line lost: gateway still running" 'kill -0 "$GW_PID"'
sim_start plc --data "$T/plc.txt" --log "$T/sim2.log" || finish
wait_for "line back: GOOD" 200 has "$P/tag/Speed" '"value":123,"quality":"GOOD"'
wait_for "line back: station ok" 50 has "$P/station/1" '"state":"ok"'

# ---- SIGTERM: offline published, exit 0 ----
kill -TERM "$GW_PID"
wait "$GW_PID"
same "SIGTERM: exit 0" "$?" 0
grep -v "^$GW_PID\$" "$T/.sims" > "$T/.sims.new"; mv "$T/.sims.new" "$T/.sims"
same "SIGTERM: status offline (retained)" "$(sub1 "$P/status")" offline

# ---- --once: one scan, published, exit ----
expect 0 "--once" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix df1/once --once
same "--once: Speed published" "$(sub1 df1/once/tag/Speed | nots)" \
	'{"value":123,"quality":"GOOD","reason":"none","address":"N7:0","station":1}'
same "--once: no status topic" "$(sub1 df1/once/status)" ""
kill -USR1 "$SIM_PID"
expect 1 "--once with the station silent: a tag BAD" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" \
	--mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix df1/once2 --once --timeout 100 --watchdog 0
kill -USR2 "$SIM_PID"
NOPORT=$(free_port)
expect 1 "--once without a broker" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$NOPORT" --once
err_has "--once without a broker: says so" "cannot connect"

# ---- credentials: refused is exit 1 with the broker's reason; a password file works ----
AUTH_PORT=$(free_port)
mosquitto_passwd -c -b "$T/passwd" plant s3cret >/dev/null 2>&1
chmod 600 "$T/passwd"
broker_start auth "$AUTH_PORT" "allow_anonymous false" "password_file $T/passwd"
expect 1 "wrong password" -- env DF1GW_PASSWORD=wrong "$GW" -d "$SIM_DEV" --map "$T/map.csv" \
	--mqtt "mqtt://127.0.0.1:$AUTH_PORT" --username plant
err_has "wrong password: the broker's reason" "refused the connection: Connection Refused: not authorised"
expect 1 "no credentials" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$AUTH_PORT"
printf 's3cret\n' > "$T/pw"
expect 0 "--password-file" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$AUTH_PORT" \
	--username plant --password-file "$T/pw" --once --prefix df1/auth
same "--password-file: published" "$(mosquitto_sub -h 127.0.0.1 -p "$AUTH_PORT" -u plant -P s3cret -t df1/auth/tag/Extra -C 1 -W 2 | nots)" \
	'{"value":5,"quality":"GOOD","reason":"none","address":"N7:5","station":1}'
expect 2 "a password without --username" -- env DF1GW_PASSWORD=x "$GW" -d "$SIM_DEV" --map "$T/map.csv" \
	--mqtt "mqtt://127.0.0.1:$AUTH_PORT"

# the default client id and prefix: df1gw-HOSTNAME-LINE
expect 0 "--once with the default prefix" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --once
check "default prefix df1/df1gw-HOSTNAME-plc" 'has "df1/df1gw-$(hostname)-plc/tag/Extra" "\"value\":5"'

finish
