#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# The eip:// client against df1sim --eip (a simulated MicroLogix 1400 over
# EtherNet/IP on loopback TCP): df1read and df1write on every file type, reads
# and writes split over packets, errors (an address out of range -> the PLC's
# STS, unknown host, refused port, a peer that closes, a bad route), connected
# messaging (--eip-connected), df1mon --ping/--who/--map and the poll engine
# over eip://. df1sim --log has one line per PCCC command it served: every
# write is executed exactly once. Run from the repository root.
. tests/support/lib.sh
R="$BIN/df1read"
W="$BIN/df1write"
MON="$BIN/df1mon"
for t in df1read df1write df1mon df1sim; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE

cat > "$T/data" <<'EOF'
ST9:0="hello, world"
L10:0=70000,-5
T4:1="EN=1 DN=1 PRE=500 ACC=42"
C5:0="CU=1 PRE=10 ACC=3"
R6:0="LEN=8 POS=2"
B3:0=0x0029
N7:255=-1
EOF

logged() { if [ -f "$1" ]; then wc -l < "$1" | tr -d ' '; else echo 0; fi; }
log_has() { [ "$(logged "$1")" -ge "$2" ]; }
# lines of the log after line $2 that match $3
log_new() { tail -n +"$(($2 + 1))" "$1" | grep -c -e "$3"; }

# df1sim serving EtherNet/IP only; EIP = its eip://ADDR:PORT line.
eip_start() {
	name=$1; shift
	"$BIN/df1sim" --eip tcp://127.0.0.1:0 "$@" > "$T/$name.out" 2> "$T/$name.err" &
	SIM_PID=$!
	echo "$SIM_PID" >> "$T/.sims"
	EIP=
	n=100
	while [ $n -gt 0 ]; do
		EIP=$(grep -m 1 '^eip://' "$T/$name.out" 2>/dev/null)
		[ -n "$EIP" ] && return 0
		kill -0 "$SIM_PID" 2>/dev/null || break
		n=$((n - 1))
		tick
	done
	bad "df1sim --eip $name did not start"
	sed 's/^/  df1sim: /' "$T/$name.err" | head -5
	return 1
}

eip_start sim --data "$T/data" --log "$T/sim.log" || finish
L="$T/sim.log"
MAIN_PID=$SIM_PID
MAIN_EIP=$EIP

# ---- every file type read, values from df1sim(1) DATA TABLE and $T/data ----
expect 0 "N7 read" -- "$R" -d "$EIP" N7:0,5
out_is "N7:0,5 = 0..4" "0
1
2
3
4"
expect 0 "N7:255" -- "$R" -d "$EIP" N7:255
out_is "N7:255" "-1"
expect 0 "F8 read" -- "$R" -d "$EIP" F8:2
out_is "F8:2 = 2.5" "2.5"
expect 0 "L read" -- "$R" -d "$EIP" L10:0,2 L10:3
out_is "L10" "70000
-5
196611"
expect 0 "ST read" -- "$R" -d "$EIP" ST9:0 ST9:4
out_is "ST9" "hello, world
STRING 4"
expect 0 "B read" -- "$R" -d "$EIP" B3:0 B3:0/0 B3:0/1 B3:0/3 B3:0/5
out_is "B3:0 = 0x29 and its bits" "41
1
0
1
1"
expect 0 "T read" -- "$R" -d "$EIP" T4:1 T4:1.ACC T4:1/DN T4:0.PRE
out_is "T4:1" "EN=1 TT=0 DN=1 PRE=500 ACC=42
42
1
100"
expect 0 "C read" -- "$R" -d "$EIP" C5:0.PRE C5:0.ACC C5:0/CU
out_is "C5:0" "10
3
1"
expect 0 "R read" -- "$R" -d "$EIP" R6:0.LEN R6:0.POS
out_is "R6:0" "8
2"
expect 0 "S, O and I read" -- "$R" -d "$EIP" S2:1 O0:0 I1:0
out_is "S2:1 O0:0 I1:0 start at 0" "0
0
0"
expect 0 "json" -- "$R" -d "$EIP" -f json N7:1
check "json" 'grep -q "\"N7:1\"" "$T/out" && grep -q "\"value\":1[,}]" "$T/out"'

# ---- writes: each once in the log, read back ----
before=$(logged "$L")
expect 0 "writes of every type" -- "$W" -d "$EIP" N7:10=1,2,3 N7:20=-5 F8:0=12.5 \
	'ST9:3=Pump 2' L10:5=-70000 B3:1/5=1 T4:2.PRE=250 C5:1.ACC=7 R6:1.LEN=4 O0:1=3
wait_for "writes logged" 50 log_has "$L" $((before + 10))
same "10 write commands, no more" "$(log_new "$L" "$before" .)" 10
same "no read among them" "$(log_new "$L" "$before" 'cmd=0F/A2')" 0
expect 0 "read back" -- "$R" -d "$EIP" N7:10,3 N7:20 F8:0 ST9:3 L10:5 B3:1/5 T4:2.PRE C5:1.ACC R6:1.LEN O0:1
out_is "written values" "1
2
3
-5
12.5
Pump 2
-70000
1
250
7
4
3"

# ---- splitting: 236 data bytes per read, 234 per write (MicroLogix / SLC 5/03+) ----
before=$(logged "$L")
expect 0 "200 integers" -- "$R" -d "$EIP" -f csv N7:0,200
same "200 values" "$(tail -n +2 "$T/out" | wc -l | tr -d ' ')" 200
check "values 0..199 (N7:10-12 and 20 as written)" \
	'tail -n +2 "$T/out" | cut -d, -f2 | sed -n "1p;10p;14p;200p" | tr "\n" " " | grep -q "^0 9 13 199 $"'
wait_for "split read logged" 50 log_has "$L" $((before + 2))
same "two commands: 118 + 82 words" "$(tail -n +"$((before + 1))" "$L" | sed -n 's/.*addr=\(N7:[0-9]*\) count=\([0-9]*\).*/\1,\2/p' | tr '\n' ' ')" "N7:0,118 N7:118,82 "
vals=$(seq 1000 1149 | tr '\n' ',' | sed 's/,$//')
before=$(logged "$L")
expect 0 "150 integers written" -- "$W" -d "$EIP" "N7:100=$vals"
wait_for "split write logged" 50 log_has "$L" $((before + 2))
same "two write commands: 117 + 33 words" "$(tail -n +"$((before + 1))" "$L" | sed -n 's/.*cmd=0F\/AA addr=\(N7:[0-9]*\) count=\([0-9]*\).*/\1,\2/p' | tr '\n' ' ')" "N7:100,117 N7:217,33 "
expect 0 "read back 150" -- "$R" -d "$EIP" N7:100,150
same "150 values back" "$(tr '\n' ',' < "$T/out" | sed 's/,$//')" "$vals"

# ---- connected messaging ----
before=$(logged "$L")
expect 0 "--eip-connected write" -- "$W" -d "$EIP" --eip-connected N7:30=77
wait_for "connected write logged" 50 log_has "$L" $((before + 1))
same "one write" "$(log_new "$L" "$before" 'addr=N7:30')" 1
expect 0 "--eip-connected read" -- "$R" -d "$EIP" --eip-connected N7:30 F8:2
out_is "connected read" "77
2.5"
expect 1 "--eip-connected with a route" -- "$R" -d "$EIP/2" --eip-connected N7:0
err_has "connected + route refused" "unconnected only"

# ---- errors ----
expect 1 "element past the file" -- "$R" -d "$EIP" N7:999
err_has "the PLC's STS" "DF1_E_REMOTE"
err_has "EXT STS named" "EXT STS 0x07"
expect 1 "no such file" -- "$R" -d "$EIP" N50:0
err_has "file missing: EXT STS 06" "EXT STS 0x06"
expect 1 "write past the file" -- "$W" -d "$EIP" N7:999=1
err_has "write refused by STS" "DF1_E_REMOTE"
expect 1 "route to a station the simulator does not have" -- "$R" -d "$EIP/2" -a 3 N7:0
err_has "CIP status named" "DF1_E_CIP"
expect 2 "bad route" -- "$R" -d "$EIP/3" N7:0
err_has "bad route named" "only /2"
expect 1 "unknown host" -- "$R" -d eip://no-such-host.invalid N7:0
err_has "unknown host named" "no-such-host.invalid"

# a peer that closes the connection: the client outside --eip-allow
eip_start closer --eip-allow 192.0.2.0/24 --log "$T/closer.log" || finish
CLOSER=$SIM_PID
expect 1 "peer closes" -- "$W" -d "$EIP" N7:0=5
check "closed reported" 'grep -q -e "DF1_E_CLOSED" -e "DF1_E_SYS" "$T/err"'
same "nothing executed there" "$(logged "$T/closer.log")" 0
# a refused port: that simulator's, once it is gone
PORT=${EIP##*:}
sim_stop "$CLOSER"
expect 1 "refused port" -- "$R" -d "eip://127.0.0.1:$PORT" N7:0
err_has "refused named" "cannot connect"

# ---- df1mon over eip:// ----
EIP=$MAIN_EIP
expect 0 "--ping" -- "$MON" -d "$EIP" --ping -c 2 -i 0.05
check "ping: both answered" 'cat "$T/out" "$T/err" | grep -q "2 probes sent, 2 answered"'
expect 0 "--who" -- "$MON" -d "$EIP" --who
check "--who: one device, a MicroLogix 1400 simulation" '[ "$(wc -l < "$T/out")" -eq 1 ] && grep -q "^127.0.0.1:${EIP##*:}: \".*MicroLogix 1400\" vendor [0-9]* device type [0-9]* product code [0-9]* revision [0-9]*\.[0-9]* serial [0-9A-F]\{8\} state [0-9]* status [0-9A-F]\{4\}$" "$T/out"'
err_has "--who summary" "1 device answered ListIdentity"
expect 0 "--who -f json" -- "$MON" -d "$EIP" --who -f json
check "--who json" 'json_ok "$T/out" && grep -q "\"product_name\":\"[^\"]*MicroLogix 1400\"" "$T/out"'
expect 0 "--who -f csv" -- "$MON" -d "$EIP" --who -f csv
check "--who csv header" 'head -n 1 "$T/out" | grep -q "^address,vendor_id,device_type,product_code,revision,serial,product_name,state,status$" && [ "$(wc -l < "$T/out")" -eq 2 ]'

printf 'Tag,Command,Type,Station,PLC_Type,Address\nlevel,Read,INT,1,MicroLogix,N7:30\ntemp,Read,FLOAT,1,MicroLogix,F8:2\nbig,Read,LONG,1,MicroLogix,L10:0\n' > "$T/map.csv"
expect 0 "--map -1" -- "$MON" -d "$EIP" --map "$T/map.csv" -1
check "--map: the tags and their values" 'grep "level" "$T/out" | grep -q " 77 " && grep "temp" "$T/out" | grep -q "2.5" && grep "big" "$T/out" | grep -q "70000"'
before=$(logged "$L")
expect 0 "--map live (poll engine)" -- "$MON" -d "$EIP" --map "$T/map.csv" -i 0.05 --duration 2
wait_for "live scans logged" 50 log_has "$L" $((before + 2))
check "the poll engine read N7:30 in more than one scan" '[ "$(log_new "$L" "$before" "addr=N7:30")" -ge 2 ]'
same "the poll engine wrote nothing" "$(log_new "$L" "$before" 'cmd=0F/AA')" 0

sim_stop "$MAIN_PID"

# ---- route path: two stations behind one address (eip://HOST/2, -a N) ----
eip_start two --station 1,4 --log "$T/two.log" || finish
TWO=$SIM_PID
expect 0 "routed write to station 4" -- "$W" -d "$EIP/2" -a 4 N7:3=44
expect 0 "routed reads of stations 4 and 1" -- sh -c "'$R' -d '$EIP/2' -a 4 N7:3 && '$R' -d '$EIP/2' -a 1 N7:3"
out_is "each station its own table" "44
3"
expect 0 "unrouted: the default station, whatever -a" -- "$R" -d "$EIP" -a 4 N7:3
out_is "default station's value" "3"
wait_for "routed commands logged" 50 log_has "$T/two.log" 4
same "stations served, in order" "$(sed -n 's/.* station=\([0-9]*\) cmd=\([0-9A-F/]*\) .*/\1 \2/p' "$T/two.log" | tr '\n' ',')" "4 0F/AA,4 0F/A2,1 0F/A2,1 0F/A2,"
printf 'Tag,Command,Type,Station,PLC_Type,Address\na,Read,INT,1,MicroLogix,N7:3\nb,Read,INT,4,MicroLogix,N7:3\n' > "$T/map2.csv"
expect 0 "--map over a route, two stations" -- "$MON" -d "$EIP/2" --map "$T/map2.csv" -1
check "--map: both stations' values" 'grep "^ *a " "$T/out" | grep -q " 3 " && grep "^ *b " "$T/out" | grep -q " 44 "'
sim_stop "$TWO"

# ---- the server goes away and comes back: the poll engine reconnects ----
PORT=${MAIN_EIP##*:}
"$BIN/df1sim" --eip "tcp://127.0.0.1:$PORT" --log "$T/r1.log" > "$T/r1.out" 2> "$T/r1.err" &
R1=$!
echo "$R1" >> "$T/.sims"
wait_for "restarted simulator up" 100 grep -q '^eip://' "$T/r1.out"
"$MON" -d "$MAIN_EIP" --map "$T/map.csv" -i 0.05 --duration 60 > "$T/live.out" 2> "$T/live.err" &
LIVE=$!
wait_for "scans on the first simulator" 100 log_has "$T/r1.log" 3
sim_stop "$R1"
"$BIN/df1sim" --eip "tcp://127.0.0.1:$PORT" --log "$T/r2.log" > "$T/r2.out" 2> "$T/r2.err" &
R2=$!
echo "$R2" >> "$T/.sims"
wait_for "second simulator up" 100 grep -q '^eip://' "$T/r2.out"
wait_for "scans again after the reconnect" 200 log_has "$T/r2.log" 3
kill -TERM "$LIVE" 2>/dev/null
lib_reap "$LIVE"
same "the poll engine only read" "$(grep -c 'cmd=0F/AA' "$T/r2.log")" 0
sim_stop "$R2"
finish
