#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_df1gw_writes.sh - a burst of /set messages on a slow line (df1sim
# --line-baud 2400) with a short keepalive, against the write policy of
# df1gw(1), WRITE POLICY: the broker never drops the gateway, invalid and
# superseded writes are answered within seconds, exactly one result per id,
# the values left in the PLC are the last written, poll reads come between
# every --duty-cycle writes (df1sim's --log), an EtherNet/IP read through the
# bridge is answered meanwhile, behind at most one batch of a burst to 40
# tags (df1sim's --log; the burst from support/mqtt_burst.py),
# --max-pending-writes answers busy and
# "timeout_ms" expires a write that waited too long. Expected values come from
# the burst this script makes, never from df1gw's own output.
. tests/support/lib.sh

if [ ! -x "$MOSQ" ] || ! command -v mosquitto_sub >/dev/null 2>&1; then
	echo "mosquitto or mosquitto-clients missing"
	bad "no broker to test against"
	finish
fi
GW="$BIN/df1gw"
PORT=$(free_port)
# a broker's queue for a slow client is 1000 messages by default: the burst is more
broker_start broker "$PORT" "allow_anonymous true" "log_type all" "max_queued_messages 10000"

printf 'N7:0=0\nN7:1=0\nN7:2=0\nN7:3=0\nN7:9=99\nB3:0=0\n' > "$T/plc.txt"
cat > "$T/map.csv" <<'EOF'
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
S0,ReadWrite,INT,1,SLC,N7:0,1,100
S1,ReadWrite,INT,1,SLC,N7:1,1,100
S2,ReadWrite,INT,1,SLC,N7:2,1,100
S3,ReadWrite,INT,1,SLC,N7:3,1,100
Button,ReadWrite,BOOL,1,SLC,B3:0/1,1,100
EOF
sim_start plc --data "$T/plc.txt" --log "$T/sim.log" --line-baud 2400 || finish

P=df1/burst
DUTY=4
"$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$PORT" --prefix "$P" --keepalive 5 \
	--duty-cycle $DUTY --eip 127.0.0.1:0 --counters > "$T/gw.out" 2> "$T/gw.err" &
GW_PID=$!
echo "$GW_PID" >> "$T/.sims"
gw_addr() {
	EIP=$(sed -n 's|^df1gw: EtherNet/IP on \([0-9.]*:[0-9]*\).*|\1|p' "$T/gw.err" 2>/dev/null | head -n 1)
	[ -n "$EIP" ]
}
wait_for "df1gw says where EtherNet/IP listens" 100 gw_addr
sub1() { mosquitto_sub -h 127.0.0.1 -p "$PORT" -t "$1" -C 1 -W 2 2>/dev/null; }
has() { sub1 "$1" | grep -F -q -e "$2"; }
wait_for "status online" 100 has "$P/status" online
wait_for "S0 read" 100 has "$P/tag/S0" '"quality":"GOOD"'

mosquitto_sub -h 127.0.0.1 -p "$PORT" -q 1 -t "$P/tag/+/result" -v > "$T/results.txt" 2>&1 &
SUB=$!
echo "$SUB" >> "$T/.sims"
pub() { mosquitto_pub -h 127.0.0.1 -p "$PORT" -q 1 -t "$1" -m "$2"; }
marker() { pub "$P/tag/S0/set" '{"value":0,"id":"m0"}' && grep -q '"id":"m0"' "$T/results.txt"; }
wait_for "result subscriber ready" 100 marker

# ---- the burst: 4 tags x 600 messages, every fifth not JSON ----
# per tag: ids TAG-1..TAG-600; message i writes i unless i % 5 == 0 (not JSON)
for t in 0 1 2 3; do
	awk -v t=$t 'BEGIN { for (i = 1; i <= 600; i++)
		if (i % 5 == 0) printf "{\"value\": oops, \"id\": \"s%d-%d\"\n", t, i;
		else printf "{\"value\": %d, \"id\": \"s%d-%d\"}\n", i, t, i }' > "$T/burst$t.txt"
done
# the last valid value of each tag: 599
for t in 0 1 2 3; do
	mosquitto_pub -h 127.0.0.1 -p "$PORT" -q 1 -t "$P/tag/S$t/set" -l < "$T/burst$t.txt" &
	echo "$!" >> "$T/.sims"
	eval "PUB$t=$!"
done
# a push button meanwhile: 1 then 0, both written (latest-non-bool keeps bits)
pub "$P/tag/Button/set" '{"value":true,"id":"b1"}'
pub "$P/tag/Button/set" '{"value":false,"id":"b0"}'
# an EtherNet/IP read through the bridge while the writes are queued
if "$BIN/df1read" --help 2>&1 | grep -q 'eip://'; then
	expect 0 "an eip:// read answered during the burst" -- "$BIN/df1read" -d "eip://$EIP" --timeout 5000 N7:9
	out_is "the eip:// read's value" "99"
else
	skip "df1read without eip://"
fi
for t in 0 1 2 3; do eval "wait \$PUB$t"; done

# invalid (480) and superseded writes answered within seconds, not behind the line
invalid_all() { [ "$(grep -c '"id":null,"ok":false,"error":"DF1_E_INVAL: invalid argument: not JSON' "$T/results.txt")" -ge 480 ]; }
wait_for "the 480 payloads that are not JSON answered within seconds" 100 invalid_all
some_superseded() { grep -q '"error":"superseded by a later write (id \\"s' "$T/results.txt"; }
wait_for "superseded writes answered within seconds" 100 some_superseded
# every valid /set answered by its id: 4 x 480 + the button's 2 (the 480 not
# JSON have no id that could be read: counted above)
all_answered() { [ "$(grep -c '"id":"[sb]' "$T/results.txt")" -ge 1922 ]; }
wait_for "a result for every /set" 600 all_answered
sleep 1
ids=$(grep -o '"id":"[sb][^"]*"' "$T/results.txt" | sort)
same "exactly one result per id" "$(printf '%s\n' "$ids" | uniq -d | head -5)" ""
same "1922 ids answered" "$(printf '%s\n' "$ids" | uniq | wc -l | tr -d ' ')" 1922
same "480 results without an id: the payloads not JSON" "$(grep -c '"id":null' "$T/results.txt")" 480
check "results: ok, invalid or superseded only" '! grep "\"id\":\"s" "$T/results.txt" | grep -v -e "\"ok\":true" -e "not JSON" -e "superseded by a later write" | grep -q .'
check "the button's 1 and 0 both written" 'grep -q "\"id\":\"b1\",\"ok\":true" "$T/results.txt" && grep -q "\"id\":\"b0\",\"ok\":true" "$T/results.txt"'
# the PLC holds the last value written to each tag
for t in 0 1 2 3; do
	wait_for "S$t holds 599, the last written" 50 has "$P/tag/S$t" '{"value":599,'
done
check "the button's bit 0 again" 'has "$P/tag/Button" "{\"value\":false,"'
# no broker drop: the gateway never lost the broker, the broker never timed it out
check "df1gw never lost the broker" '! grep -q "connection lost" "$T/gw.err"'
check "the broker never dropped df1gw" '! grep -q -i "exceeded timeout" "$T/broker.log"'
# df1sim's log: never more than DUTY writes in a row without a read between
runs=$(awk '/cmd=0F\/AA/ { n++; if (n > m) m = n; next } /cmd=0F\/A2/ { n = 0 } END { print m + 0 }' "$T/sim.log")
check "at most $DUTY writes between two poll reads (longest run: $runs)" '[ "$runs" -le $DUTY ] && [ "$runs" -ge 1 ]'
kill "$SUB" 2>/dev/null

kill -TERM "$GW_PID"
lib_reap "$GW_PID"
check "--counters: the write line" 'grep -q "^writes [0-9]* received, [0-9]* written, .* superseded, .* refused busy, .* queue high-water [0-9]*" "$T/gw.out"'

# ---- the bridge behind a burst to 40 tags: its read waits behind at most one batch ----
# A burst of /set messages to 40 tags: 60 each (2 400) under the default
# latest-non-bool, which leaves some 40 writes, 4 batches of 10 (1.5 s each
# at 2400 baud); 3 each (120 writes) under --write-optimize all. Once the
# first write is on the line, an eip:// read (5 s client timeout) of N7:9,
# which no tag reads: in df1sim's log it is the only "addr=N7:9 count=1". It
# is executed behind at most one batch: the writes between the burst's first
# write and it are at most --duty-cycle, and the backlog goes on after it
# (df1gw(1), ETHERNET/IP). Before, its connect, session and request each
# waited for a batch and its poll read: 20 writes or more.
BDUTY=10
{
	echo 'Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms'
	for i in $(seq 0 39); do echo "T$i,ReadWrite,INT,1,SLC,N7:$((10 + i)),1,500"; done
} > "$T/map40.csv"
gwb_addr() {
	EIP=$(sed -n 's|^df1gw: EtherNet/IP on \([0-9.]*:[0-9]*\).*|\1|p' "$T/gwb.err" 2>/dev/null | head -n 1)
	[ -n "$EIP" ]
}
# bridge_burst OPTIMIZE PER_TAG
bridge_burst() {
	bopt=$1; per=$2
	# a prefix of its own: a tag seen GOOD is this df1gw's, so it has
	# subscribed (it does before it publishes tags), not a retained message
	# of the df1gw before
	bp=$P-$bopt
	: > "$T/gwb.err"
	"$GW" -d "$SIM_DEV" --map "$T/map40.csv" --mqtt "mqtt://127.0.0.1:$PORT" --prefix "$bp" --keepalive 5 \
		--write-optimize "$bopt" --duty-cycle $BDUTY --eip 127.0.0.1:0 > "$T/gwb.out" 2> "$T/gwb.err" &
	GW_PID=$!
	echo "$GW_PID" >> "$T/.sims"
	wait_for "df1gw says where EtherNet/IP listens ($bopt, 40 tags)" 100 gwb_addr
	wait_for "T39 read ($bopt)" 100 has "$bp/tag/T39" '"quality":"GOOD"'
	from=$(wc -l < "$T/sim.log")
	awk -v p="$bp" -v per="$per" 'BEGIN { for (k = 1; k <= per; k++) for (t = 0; t < 40; t++)
		printf "%s/tag/T%d/set {\"value\":%d,\"id\":\"b%d-%d\"}\n", p, t, k, t, k }' > "$T/burst40.txt"
	expect 0 "$bopt: a burst of $((per * 40)) /set messages to 40 tags" -- \
		python3 tests/support/mqtt_burst.py "$PORT" "$T/burst40.txt"
	# the read goes once the burst is on the line: its first write in the log
	burst_started() { sed -n "$((from + 1)),\$p" "$T/sim.log" | grep -q 'cmd=0F/AA'; }
	wait_for "$bopt: the burst's first write on the line" 100 burst_started
	expect 0 "$bopt: an eip:// read just after the burst, 5 s client timeout: answered" -- \
		"$BIN/df1read" -d "eip://$EIP" --timeout 5000 N7:9
	out_is "$bopt: the eip:// read's value" "99"
	# 40 writes at least: one per tag
	burst_written() { [ "$(sed -n "$((from + 1)),\$p" "$T/sim.log" | grep -c 'cmd=0F/AA')" -ge 40 ]; }
	wait_for "$bopt: 40 writes of the burst done" 300 burst_written
	sed -n "$((from + 1)),\$p" "$T/sim.log" > "$T/sim40.log"
	before=$(awk '/addr=N7:9 count=1 / { exit } /cmd=0F\/AA/ { n++ } END { print n + 0 }' "$T/sim40.log")
	after=$(awk 'f && /cmd=0F\/AA/ { n++ } /addr=N7:9 count=1 / { f = 1 } END { print n + 0 }' "$T/sim40.log")
	echo "  $bopt: the bridged read after $before writes of the burst, $after after it"
	check "$bopt: the bridged read executed (df1sim's log)" 'grep -q "cmd=0F/A2 addr=N7:9 count=1 " "$T/sim40.log"'
	check "$bopt: the bridged read behind at most one batch: $before writes of the burst before it (at most $BDUTY)" \
		'[ "$before" -le $BDUTY ]'
	check "$bopt: and ahead of the backlog: $after writes after it (20 at least)" '[ "$after" -ge 20 ]'
	kill -TERM "$GW_PID"
	lib_reap "$GW_PID"
}
if "$BIN/df1read" --help 2>&1 | grep -q 'eip://'; then
	bridge_burst latest-non-bool 60
	bridge_burst all 3
else
	skip "df1read without eip://"
fi

# ---- a real backlog (--write-optimize all): reads and the bridge keep their turns ----
: > "$T/gw.err"          # never the address of the first df1gw, read before this one writes
"$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$PORT" --prefix "$P" --keepalive 5 \
	--write-optimize all --duty-cycle $DUTY --eip 127.0.0.1:0 > "$T/gw.out" 2> "$T/gw.err" &
GW_PID=$!
echo "$GW_PID" >> "$T/.sims"
wait_for "df1gw says where EtherNet/IP listens (backlog)" 100 gw_addr
wait_for "status online (backlog)" 100 has "$P/status" online
mosquitto_sub -h 127.0.0.1 -p "$PORT" -q 1 -t "$P/tag/+/result" -v > "$T/results.txt" 2>&1 &
SUB=$!
echo "$SUB" >> "$T/.sims"
markerb() { pub "$P/tag/S0/set" '{"value":0,"id":"mb"}' && grep -q '"id":"mb"' "$T/results.txt"; }
wait_for "result subscriber ready (backlog)" 100 markerb
logged_before=$(wc -l < "$T/sim.log")
awk 'BEGIN { for (i = 1; i <= 120; i++) printf "{\"value\": %d, \"id\": \"a-%d\"}\n", i, i }' > "$T/burst_a.txt"
mosquitto_pub -h 127.0.0.1 -p "$PORT" -q 1 -t "$P/tag/S2/set" -l < "$T/burst_a.txt"
some_written() { [ "$(grep -c '"id":"a-[0-9]*","ok":true' "$T/results.txt")" -ge 8 ]; }
wait_for "the backlog is being written" 100 some_written
if "$BIN/df1read" --help 2>&1 | grep -q 'eip://'; then
	expect 0 "an eip:// read answered behind 100 queued writes" -- "$BIN/df1read" -d "eip://$EIP" --timeout 5000 N7:9
	out_is "the eip:// read's value (backlog)" "99"
	check "the backlog was still there when it was answered" '[ "$(grep -c "\"id\":\"a-" "$T/results.txt")" -lt 120 ]'
fi
a_all() { [ "$(grep -c '"id":"a-[0-9]*","ok":true' "$T/results.txt")" -ge 120 ]; }
wait_for "all 120 written, in order, one result each" 900 a_all
same "the 120 results in order" "$(grep -o '"id":"a-[0-9]*"' "$T/results.txt" | tr -dc '0-9\n' | tr '\n' ' ')" \
	"$(seq 1 120 | tr '\n' ' ')"
wait_for "S2 holds 120, the last written" 50 has "$P/tag/S2" '{"value":120,'
runs=$(sed -n "$((logged_before + 1)),\$p" "$T/sim.log" |
	awk '/cmd=0F\/AA/ { n++; if (n > m) m = n; next } /cmd=0F\/A2/ { n = 0 } END { print m + 0 }')
same "a backlog: runs of exactly $DUTY writes between two poll reads" "$runs" "$DUTY"
check "df1gw never lost the broker (backlog)" '! grep -q "connection lost" "$T/gw.err"'
kill "$SUB" 2>/dev/null
kill -TERM "$GW_PID"
lib_reap "$GW_PID"

# ---- the broker killed during a backlog: the results that fell meanwhile come after, once ----
"$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$PORT" --prefix "$P" --keepalive 5 \
	--write-optimize all --duty-cycle $DUTY > "$T/gw.out" 2> "$T/gw.err" &
GW_PID=$!
echo "$GW_PID" >> "$T/.sims"
wait_for "status online (broker kill)" 100 has "$P/status" online
mosquitto_sub -h 127.0.0.1 -p "$PORT" -q 1 -t "$P/tag/+/result" -v > "$T/res_a.txt" 2>&1 &
SUB=$!
echo "$SUB" >> "$T/.sims"
markerk() { pub "$P/tag/S0/set" '{"value":0,"id":"mk"}' && grep -q '"id":"mk"' "$T/res_a.txt"; }
wait_for "result subscriber ready (broker kill)" 100 markerk
awk 'BEGIN { for (i = 1; i <= 60; i++) printf "{\"value\": %d, \"id\": \"r-%d\"}\n", i, i }' > "$T/burst_r.txt"
mosquitto_pub -h 127.0.0.1 -p "$PORT" -q 1 -t "$P/tag/S3/set" -l < "$T/burst_r.txt"
r_some() { [ "$(grep -c '"id":"r-' "$T/res_a.txt")" -ge 4 ]; }
wait_for "the backlog is being written (broker kill)" 100 r_some
kill -9 "$BROKER_PID"
kill "$SUB" 2>/dev/null
wait "$BROKER_PID" 2>/dev/null
n=20; while [ $n -gt 0 ]; do tick; n=$((n - 1)); done
broker_run broker "$PORT"
mosquitto_sub -h 127.0.0.1 -p "$PORT" -q 1 -t "$P/tag/+/result" -v > "$T/res_b.txt" 2>&1 &
SUB=$!
echo "$SUB" >> "$T/.sims"
gw_back() { grep -q "connected again after" "$T/gw.err"; }
wait_for "df1gw back on the broker" 400 gw_back
r_done() { has "$P/tag/S3" '{"value":60,'; }
wait_for "S3 holds 60, the last written" 600 r_done
r_after() { grep -q '"id":"r-' "$T/res_b.txt"; }
wait_for "results that fell during the outage published after it" 100 r_after
sleep 1
same "no result twice across the outage" "$(cat "$T/res_a.txt" "$T/res_b.txt" | grep -o '"id":"r-[0-9]*"' | sort | uniq -d)" ""
got=$(cat "$T/res_a.txt" "$T/res_b.txt" | grep -o '"id":"r-[0-9]*"' | sort -u | wc -l)
check "nearly every result delivered across the outage ($got of 60; those on the wire at the kill may be lost)" '[ "$got" -ge 55 ]'
kill "$SUB" 2>/dev/null
kill -TERM "$GW_PID"
lib_reap "$GW_PID"

# ---- busy and expired ----
"$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$PORT" --prefix "$P" --keepalive 5 \
	--write-optimize all --max-pending-writes 5 --duty-cycle 1 > "$T/gw2.out" 2> "$T/gw2.err" &
GW_PID=$!
echo "$GW_PID" >> "$T/.sims"
wait_for "status online (2)" 100 has "$P/status" online
mosquitto_sub -h 127.0.0.1 -p "$PORT" -q 1 -t "$P/tag/+/result" -v > "$T/results2.txt" 2>&1 &
SUB=$!
echo "$SUB" >> "$T/.sims"
marker2() { pub "$P/tag/S0/set" '{"value":0,"id":"m2"}' && grep -q '"id":"m2"' "$T/results2.txt"; }
wait_for "result subscriber ready (2)" 100 marker2
awk 'BEGIN { for (i = 1; i <= 60; i++) printf "{\"value\": %d, \"id\": \"q-%d\", \"timeout_ms\": 300}\n", i, i }' \
	> "$T/burst_q.txt"
mosquitto_pub -h 127.0.0.1 -p "$PORT" -q 1 -t "$P/tag/S1/set" -l < "$T/burst_q.txt"
q_all() { [ "$(grep -c '"id":"q-' "$T/results2.txt")" -ge 60 ]; }
wait_for "a result for each of 60 writes" 300 q_all
check "busy: answered, not written" 'grep -q "\"id\":\"q-[0-9]*\",\"ok\":false,\"error\":\"busy, not written" "$T/results2.txt"'
check "timeout_ms 300: expired, not written" 'grep -q "\"id\":\"q-[0-9]*\",\"ok\":false,\"error\":\"expired, not written" "$T/results2.txt"'
same "busy/expired: one result per id" "$(grep -o '"id":"q-[0-9]*"' "$T/results2.txt" | sort | uniq -d | head -3)" ""
kill "$SUB" 2>/dev/null
kill -TERM "$GW_PID"
lib_reap "$GW_PID"

# ---- the line lost during a backlog: every write answered once, and none
# of those handed to the poll engine written late after the reopen
# (df1_poll_cancel_queued) ----
"$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$PORT" --prefix "$P" --keepalive 5 \
	--write-optimize all --duty-cycle 8 > "$T/gw3.out" 2> "$T/gw3.err" &
GW_PID=$!
echo "$GW_PID" >> "$T/.sims"
wait_for "status online (3)" 100 has "$P/status" online
mosquitto_sub -h 127.0.0.1 -p "$PORT" -q 1 -t "$P/tag/+/result" -v > "$T/results3.txt" 2>&1 &
SUB=$!
echo "$SUB" >> "$T/.sims"
marker3() { pub "$P/tag/S0/set" '{"value":0,"id":"m3"}' && grep -q '"id":"m3"' "$T/results3.txt"; }
wait_for "result subscriber ready (3)" 100 marker3
awk 'BEGIN { for (i = 1; i <= 60; i++) printf "{\"value\": %d, \"id\": \"l-%d\"}\n", i, i }' > "$T/burst_l.txt"
mosquitto_pub -h 127.0.0.1 -p "$PORT" -q 1 -t "$P/tag/S2/set" -l < "$T/burst_l.txt"
l_some() { [ "$(grep -c '"id":"l-' "$T/results3.txt")" -ge 2 ]; }
wait_for "the backlog is being written (line lost)" 100 l_some
sim_stop "$SIM_PID"
l_all() { [ "$(grep -c '"id":"l-' "$T/results3.txt")" -ge 60 ]; }
wait_for "a result for each of the 60 writes across the lost line" 300 l_all
same "one result per id (line lost)" "$(grep -o '"id":"l-[0-9]*"' "$T/results3.txt" | sort | uniq -d | head -3)" ""
check "writes not done answered not ok" 'grep -q "\"id\":\"l-[0-9]*\",\"ok\":false" "$T/results3.txt"'
sim_start plc --data "$T/plc.txt" --log "$T/sim3.log" --line-baud 2400 || finish
wait_for "the line back (3)" 400 has "$P/tag/S2" '"quality":"GOOD"'
n=20; while [ $n -gt 0 ]; do tick; n=$((n - 1)); done
check "no write of the backlog after the reopen" '! grep -q "cmd=0F/AA" "$T/sim3.log"'
kill "$SUB" 2>/dev/null
kill -TERM "$GW_PID"
lib_reap "$GW_PID"

finish
