#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_df1gw_buffer.sh - df1gw's store and forward (df1gw(1), STORE AND FORWARD)
# against real parts: mosquitto on a loopback port (stopped and started again
# on the same port, its subscriber's session kept in its persistence file),
# df1sim --ramp N7:0,1@100 (10 changes a second), mosquitto_sub recording
# everything, the independent Sparkplug host of tests/support/spb_host.py
# (pysparkplug). What arrives is checked by tests/support/sfwd_check.py
# against the ramp's rule (a value never goes back) and the man page's
# (historical messages in seq order, a duplicate recognisable by its seq).
# Outages are waited out with short sleeps (the outage is the test); what
# follows them is waited for with bounded loops.
. tests/support/lib.sh

if [ ! -x "$MOSQ" ] || ! command -v mosquitto_sub >/dev/null 2>&1; then
	echo "mosquitto or mosquitto-clients missing (apt-get install mosquitto mosquitto-clients)"
	bad "no broker to test against"
	finish
fi
GW="$BIN/df1gw"
CHK="python3 tests/support/sfwd_check.py"
HOST="python3 tests/support/spb_host.py"

MQ_PORT=$(free_port)
# the recorder's session (and what is queued for it) survives the broker's restart
broker_start broker "$MQ_PORT" "allow_anonymous true" "persistence true" "persistence_location $T/" \
	"autosave_interval 1"
REC="$T/rec.txt"
: > "$REC"
mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -i df1test-recorder -c -q 1 -v -t 'p1/#' -t 'p2/#' -t 'p3/#' \
	-t 'p4/#' -t 'p5/#' -t 'p8/#' >> "$REC" 2> "$T/sub.err" &
echo $! >> "$T/.sims"
wait_for "recorder subscribed" 100 sh -c "mosquitto_pub -h 127.0.0.1 -p $MQ_PORT -t p1/probe -m '{}' 2>/dev/null; grep -q p1/probe '$REC'"

sim_start plc --ramp N7:0,1@100 || finish
cat > "$T/map.csv" <<'EOF'
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
Ramp,Read,INT,1,SLC,N7:0,1,20
EOF

# gw NAME PREFIX [OPTIONS]: df1gw in the background, GW_PID; $T/NAME.err, $T/NAME.out
gw() {
	name=$1; prefix=$2; shift 2
	"$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix "$prefix" --counters \
		"$@" > "$T/$name.out" 2> "$T/$name.err" &
	GW_PID=$!
	echo "$GW_PID" >> "$T/.sims"
}
# live PREFIX N: N current messages of PREFIX's ramp recorded
live() { [ "$(grep -c "^$1/tag/Ramp {\"value\":[0-9]" "$REC")" -ge "$2" ]; }
# drained PREFIX: a current message after the historical ones
drained() { grep "^$1/tag/Ramp " "$REC" | awk '/"historical":true/ { h = 1; next } h { f = 1 } END { exit !f }'; }
broker_stop() { kill -TERM "$BROKER_PID"; lib_reap "$BROKER_PID"; }
outage() { n=$1; while [ "$n" -gt 0 ]; do sleep 1; n=$((n - 1)); done; }
now_ms() { python3 -c 'import time; print(int(time.time() * 1000))'; }
gw_stop() { kill -TERM "$GW_PID"; lib_reap "$GW_PID"; }

# ---- options ----
expect 2 "--buffer without --mqtt" -- "$GW" -d "$SIM_DEV" --eip 0 --buffer "$T/x.db"
err_has "--buffer needs a broker" "need --mqtt"
expect 2 "--buffer-max 12q refused" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt mqtt://127.0.0.1:1 --buffer-max 12q
err_has "--buffer-max says what" "--buffer-max 12q"
expect 2 "--replay-rate 0 refused" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt mqtt://127.0.0.1:1 --replay-rate 0
err_has "--replay-rate says what" "--replay-rate 0"

# ---- a 10 s outage: every change read meanwhile arrives, in order, then the newest retained ----
gw gw1 p1 --buffer "$T/b1.db"
wait_for "gw1 publishes" 100 live p1 5
broker_stop
outage 10
broker_run broker "$MQ_PORT"
wait_for "gw1's backlog replayed" 300 drained p1
if $CHK ramp "$REC" p1/tag/Ramp 10 > "$T/chk1"; then ok; else bad "gw1's replay"; sed 's/^/  /' "$T/chk1"; fi
h1=$(sed -n 's/^historical \([0-9]*\).*/\1/p' "$T/chk1")
check "gw1: the changes of 10 s replayed ($h1 historical)" '[ "${h1:-0}" -ge 30 ]'
gw_stop
check "gw1 said nothing was dropped" "! grep -q dropped '$T/gw1.err'"
newest=$($CHK last "$REC" p1/tag/Ramp)
ret=$(mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t p1/tag/Ramp -C 1 -W 3 2>/dev/null | sed 's/^{"value":\([0-9]*\).*/\1/')
same "gw1: the retained value is the newest" "$ret" "$newest"
line=$(grep '^buffer ' "$T/gw1.out")
seq1=$($CHK seqs "$REC" p1)
b1=$(echo "$line" | sed 's/^buffer \([0-9]*\) buffered.*/\1/')
same "gw1: every record buffered arrived (counters: $line)" "$seq1" "count $b1 min 1 max $b1 contiguous yes"
check "gw1: nothing left in the file" "echo '$line' | grep -q 'backlog 0 records'"

# ---- kill -9 during an outage, a restart on the same file: nothing lost ----
gw gw2 p2 --buffer "$T/b2.db"
wait_for "gw2 publishes" 100 live p2 5
broker_stop
outage 3
killed=$(now_ms)
kill -KILL "$GW_PID"
lib_reap "$GW_PID"
gw gw2b p2 --buffer "$T/b2.db"
outage 2
broker_run broker "$MQ_PORT"
wait_for "gw2's backlog replayed after its restart" 300 drained p2
gw_stop
if $CHK ramp "$REC" p2/tag/Ramp 40 > "$T/chk2"; then ok; else bad "gw2's replay"; sed 's/^/  /' "$T/chk2"; fi
pre=$($CHK before "$REC" p2/tag/Ramp "$killed")
check "gw2: the changes buffered before kill -9 arrived ($pre)" '[ "${pre:-0}" -ge 10 ]'

# ---- a bound that overflows: the newest kept, the drops counted exactly ----
gw gw3 p3 --buffer "$T/b3.db" --buffer-max 20r --http 0
wait_for "gw3 publishes" 100 live p3 5
HTTP=$(sed -n 's|^df1gw: HTTP on \([^ ]*\) .*|\1|p' "$T/gw3.err" | head -n 1)
broker_stop
outage 4
broker_run broker "$MQ_PORT"
wait_for "gw3's backlog replayed" 300 drained p3
wait_for "gw3's retained status after the replay" 100 sh -c "grep '^p3/status/buffer ' '$REC' | tail -n 1 | grep -q '\"replayed\":[1-9]'"
if python3 -c 'import prometheus_client' 2>/dev/null; then
	m3=$(python3 tests/support/prom_probe.py "http://$HTTP/metrics" --lint df1_buffer_dropped_size_total \
		df1_buffer_backlog_records df1_buffer_in_memory | tr '\n' ' ')
else
	m3=
	skip "prometheus_client missing: /metrics of the buffer not read"
fi
api3=$(python3 -c "import json, urllib.request; b = json.load(urllib.request.urlopen('http://$HTTP/api/status', timeout=20))['buffer']; print(b['dropped_size'], b['backlog_records'], b['storage'])")
gw_stop
seq3=$($CHK seqs "$REC" p3)
line=$(grep '^buffer ' "$T/gw3.out")
d3=$(echo "$line" | sed -n 's/.* \([0-9]*\) dropped (\([0-9]*\) size.*/\2/p')
min3=$(echo "$seq3" | sed -n 's/.* min \([0-9]*\) .*/\1/p')
check "gw3: the newest kept, contiguous ($seq3)" "echo '$seq3' | grep -q 'contiguous yes'"
same "gw3: the drops are the records before the first one replayed ($line)" "$d3" "$((min3 - 1))"
check "gw3: drops happened" '[ "${d3:-0}" -ge 10 ]'
s3=$(grep '^p3/status/buffer ' "$REC" | tail -n 1 | sed -n 's/.*"dropped_size":\([0-9]*\),.*/\1/p')
same "gw3: the retained PREFIX/status/buffer counts the same drops" "$s3" "$d3"
[ -z "$m3" ] || same "gw3: /metrics (prometheus_client): dropped, backlog, on file" "$m3" "$d3 0 0 "
same "gw3: /api/status buffer" "$api3" "$d3 0 file"
check "gw3 logged the drop count once" "[ \$(grep -c ' dropped during the outage' '$T/gw3.err') -eq 1 ] && grep -q '$d3 records dropped during the outage' '$T/gw3.err'"

# ---- the file cannot grow (a file size limit): said with path and errno, memory, live goes on ----
(trap '' XFSZ; ulimit -f 48; exec "$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" \
	--prefix p4 --buffer "$T/b4.db" > "$T/gw4.out" 2> "$T/gw4.err") &
GW_PID=$!
echo "$GW_PID" >> "$T/.sims"
wait_for "gw4 publishes" 100 live p4 5
broker_stop
outage 4
broker_run broker "$MQ_PORT"
wait_for "gw4's backlog replayed" 300 drained p4
n4=$(grep -c '^p4/tag/Ramp {"value":[0-9]' "$REC")
wait_for "gw4 publishes live after the full file" 100 live p4 $((n4 + 3))
gw_stop
check "gw4 said the file failed, with its path and errno" \
	"grep 'buffer ' '$T/gw4.err' | grep -q '$T/b4.db' && grep 'buffer ' '$T/gw4.err' | grep -q -i 'too large\|disk\|full\|I/O'"
grep -q 'buffer ' "$T/gw4.err" || sed 's/^/  gw4: /' "$T/gw4.err" | head -5
if $CHK ramp "$REC" p4/tag/Ramp 10 > "$T/chk4"; then ok; else bad "gw4's replay from memory"; sed 's/^/  /' "$T/chk4"; fi

# ---- messages handed over and never acknowledged (a broker that takes and says nothing, then
# closes): every one of them arrives from the buffer after the reconnection ----
broker_stop
NOACK="$T/noack.txt"
: > "$NOACK"
python3 tests/support/mqtt_noack.py "$MQ_PORT" df1test-noack 3 "$NOACK" > "$T/noack.out" 2>&1 &
NOACK_PID=$!
echo "$NOACK_PID" >> "$T/.sims"
wait_for "the broker without PUBACKs listens" 100 grep -q listening "$T/noack.out"
gw gw8 p8 --buffer "$T/b8.db" --client-id df1test-noack
noack_done() { ! kill -0 "$NOACK_PID" 2>/dev/null; }
wait_for "the broker without PUBACKs took messages and closed" 100 noack_done
broker_run broker "$MQ_PORT"
wait_for "gw8's backlog replayed" 300 drained p8
gw_stop
taken=$(grep -o '^p8/tag/Ramp {"value":[0-9]*' "$NOACK" | sed 's/.*://' | sort -n | tr '\n' ' ')
check "gw8 handed ramp values to the broker without PUBACKs ($taken)" '[ -n "$taken" ]'
lost=
for v in $taken; do
	grep -q "^p8/tag/Ramp {\"value\":$v,.*\"historical\":true" "$REC" || lost="$lost $v"
done
same "gw8: every value never acknowledged arrived as historical" "$lost" ""

# ---- a corrupt file: moved aside, a new one; a second df1gw on it: exit 2 ----
i=0; while [ $i -lt 200 ]; do echo "not a database, a text file that happens to be here"; i=$((i + 1)); done > "$T/b5.db"
gw gw5 p5 --buffer "$T/b5.db"
wait_for "gw5 publishes over a corrupt buffer file" 100 live p5 3
check "gw5 said the file was moved aside" "grep -q 'corrupt' '$T/gw5.err'"
check "the corrupt file is kept aside" "ls '$T'/b5.db.corrupt-* >/dev/null 2>&1"
check "gw5 runs on (it holds the file)" "kill -0 $GW_PID" || sed 's/^/  gw5: /' "$T/gw5.err"
expect 2 "a second df1gw on the same --buffer" -- "$GW" -d "$SIM_DEV" --map "$T/map.csv" \
	--mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix p6 --buffer "$T/b5.db"
err_has "the second says why" "another df1gw uses this file"
gw_stop

# ---- Receive rows: what a PLC writes while the broker is away arrives too, with its sender ----
# df1sim's MSG writes 1, 2, 3, ... (seq) to df1gw's N50:0 every 200 ms; a
# subscriber of its own (a kept session) records p9; a 4 s outage
PLC_DEV=$SIM_DEV
PLC_PID=$SIM_PID
printf 'Tag,Command,Type,Station,PLC_Type,Address,Count\nBatch,Receive,INT,0,SLC,N50:0,2\n' > "$T/rx.csv"
RXREC="$T/rx.txt"
: > "$RXREC"
mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -i df1test-rx -c -q 1 -v -t 'p9/tag/#' >> "$RXREC" 2> "$T/rxsub.err" &
echo $! >> "$T/.sims"
if sim_start rxplc --station 1 --msg write,N7:0,2,0,N50:0,200,seq; then
	"$GW" -d "$SIM_DEV" --map "$T/rx.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix p9 --buffer "$T/b9.db" \
		--counters > "$T/gw9.out" 2> "$T/gw9.err" &
	GW_PID=$!
	echo "$GW_PID" >> "$T/.sims"
	rx_live() { [ "$(grep -c '^p9/tag/Batch {"value"' "$RXREC")" -ge "$1" ]; }
	wait_for "gw9 publishes the PLC's writes" 100 rx_live 5
	broker_stop
	outage 4
	broker_run broker "$MQ_PORT"
	wait_for "gw9's backlog replayed" 300 sh -c "grep '^p9/tag/Batch ' '$RXREC' | awk '/\"historical\":true/ { h = 1; next } h { f = 1 } END { exit !f }'"
	gw_stop
	sim_stop "$SIM_PID"
	grep '^p9/tag/Batch ' "$RXREC" | sed -n 's/^p9\/tag\/Batch {"value":\[\([0-9]*\),.*/\1/p' | uniq > "$T/rx.vals"
	nh=$(grep -c '^p9/tag/Batch .*"historical":true' "$RXREC")
	first=$(head -n 1 "$T/rx.vals"); last=$(tail -n 1 "$T/rx.vals")
	check "gw9: the writes made during the outage replayed ($nh historical)" '[ "$nh" -ge 10 ]'
	check "gw9: every write from $first to $last arrived, in order" \
		"seq '$first' '$last' | cmp -s - '$T/rx.vals'"
	check "gw9: each historical message names its sender" \
		"! grep '^p9/tag/Batch .*\"historical\":true' '$RXREC' | grep -vq '\"from\":1}'"
	check "gw9: counted as buffered and replayed" "grep -q 'buffer' '$T/gw9.out'"
else
	bad "df1sim --msg for the Receive rows"
fi
SIM_DEV=$PLC_DEV
SIM_PID=$PLC_PID

# ---- Sparkplug: while the primary host is offline; historical DDATA after the births ----
SREC="$T/spb.jsonl"
: > "$SREC"
if $HOST record "$MQ_PORT" "$SREC" 2> "$T/host.err" & then echo $! >> "$T/.sims"; fi
wait_for "Sparkplug recorder subscribed" 100 sh -c "mosquitto_pub -h 127.0.0.1 -p $MQ_PORT -t spBv1.0/STATE/probe -m x 2>/dev/null; grep -q probe '$SREC'"
if ! grep -q probe "$SREC"; then
	skip "pysparkplug or paho-mqtt missing (pip install pysparkplug): no Sparkplug replay test"
	finish
fi
sh_has() { $HOST has "$SREC" 0 "$1"; }
$HOST state "$MQ_PORT" Scada online
gw gw7 p7 --buffer "$T/b7.db" --sparkplug Plant --edge-node Line1 --json no --primary-host Scada
DD="[r for r in R if r['type'] == 'DDATA' and not any(m['is_historical'] for m in r['metrics'])]"
wait_for "gw7 sends DDATA" 100 sh_has "len($DD) >= 5"
$HOST state "$MQ_PORT" Scada offline
wait_for "gw7's NDEATH" 100 sh_has "[r for r in R if r['type'] == 'NDEATH']"
outage 3
$HOST state "$MQ_PORT" Scada online
HD="[r for r in R if r['type'] == 'DDATA' and all(m['is_historical'] for m in r['metrics'])]"
wait_for "historical DDATA replayed" 200 sh_has "len($HD) >= 15"
gw_stop
$HOST state "$MQ_PORT" Scada offline
wait_for "gw7's last messages recorded" 50 sh_has "R[-1]['type'] == 'STATE'"
if $CHK spb "$SREC" 15 > "$T/chk7"; then ok; else bad "gw7's historical DDATA"; sed 's/^/  /' "$T/chk7"; fi
if $HOST check "$SREC" > "$T/spbcheck.out"; then ok; else bad "Sparkplug rules over the replay"; sed 's/^/  /' "$T/spbcheck.out"; fi

finish
