#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# df1opcua (python/libdf1/opcua, df1opcua(1)) against df1sim on a pty, through
# an OPC UA client that is not asyncua: tests/opcua/client.js on node-opcua
# (.ci/run installs it pinned under $DF1_NODE_OPCUA, default
# ~/.cache/libdf1/node-opcua). Expected values are df1sim's --data and its
# --log (one line per command it answered), never df1opcua's own output.
#   - usage and configuration errors: exit 2, nothing served
#   - the address space: folders, NodeIds, DataTypes, ValueRank and
#     ArrayDimensions, AccessLevel, station Variables, a TIMER's members
#   - values and StatusCodes, a subscription to a word df1sim ramps
#   - a write executed once (one typed write in df1sim's log) and Good; a
#     write to a Read row BadNotWritable and nothing sent
#   - the PLC silent: BadCommunicationError; answering again: Good
#   - loopback only by default; a named address says so and offers no None
#   - --users: anonymous refused, a wrong password refused; SignAndEncrypt
#     with an unknown certificate refused and kept in rejected/, admitted once
#     moved to trusted/ (no restart); Sign too
#   - a tag of a station that never answered: BadNoCommunication
#   - --write-timeout: df1sim slow to answer, a write on the line and two
#     waiting behind it: those two BadTimeout and never sent (df1sim --log),
#     the first and a later one Good, each written once
#   - -d eip:// through df1gw --eip (a second df1sim behind df1gw): values and
#     a write once, df1gw and df1opcua on one line at once
# SKIP (exit 0, nothing counted) when python3 has no asyncua, or node or
# node-opcua is missing. Run from the repository root.
B=${B:-build}
LIBDF1_PATH=$(cd "$B" && pwd)
DF1_BIN=${DF1_BIN:-$LIBDF1_PATH/bin}
export LIBDF1_PATH DF1_BIN
. tests/support/lib.sh
export PYTHONDONTWRITEBYTECODE=1
export PYTHONPATH="$(pwd)/python${PYTHONPATH:+:$PYTHONPATH}"
NODE_DIR=${DF1_NODE_OPCUA:-$HOME/.cache/libdf1/node-opcua}
if ! python3 -c 'import asyncua' >/dev/null 2>&1; then
	skip "it_df1opcua: python3 has no asyncua (pip install asyncua, or .ci/run)"
	finish
fi
if ! command -v node >/dev/null 2>&1 ||
	! NODE_PATH="$NODE_DIR/node_modules" node -e 'require("node-opcua-client")' >/dev/null 2>&1; then
	skip "it_df1opcua: no node or no node-opcua-client in $NODE_DIR (.ci/run installs it)"
	finish
fi
if readelf -d "$LIBDF1_PATH/libdf1.so.0" 2>/dev/null | grep -q 'NEEDED.*libasan'; then
	skip "it_df1opcua: a sanitizer build (python3 would need the runtime preloaded)"
	finish
fi
export NODE_PATH="$NODE_DIR/node_modules"
OPCUA="python3 -m libdf1.opcua"
CPKI=$T/client-pki
# the client's deadlines in seconds, scaled as wait_for's (DF1_TEST_SLACK, default 3): a loaded
# machine waits longer, a condition that holds returns at once. Every value is waited for before
# it is read: BadNoCommunication is the right answer until the server's first poll of the tag.
SLACK=${DF1_TEST_SLACK:-3}
W=$((10 * SLACK))
W2=$((20 * SLACK))

# client URL ARGS...: tests/opcua/client.js, its output in $T/cl (node-opcua's own log lines dropped)
# good NODE...: the steps that wait (at most $W s) until each NODE is Good
client() {
	url=$1; shift
	timeout $((100 * SLACK)) node tests/opcua/client.js "$url" pki="$CPKI" "$@" > "$T/cl.raw" 2>&1
	grep -E '^(child|attrs|read|write|wait|waitval|sub|subdone|kill|error) ' "$T/cl.raw" > "$T/cl"
}
has() { grep -qxF "$2" "$T/cl" && ok || { bad "$1: no line '$2'"; sed 's/^/  client: /' "$T/cl.raw" | tail -8; }; }
good() { for g; do printf 'wait:%s:Good:%s\n' "$g" "$W"; done; }
has_re() { grep -qE "$2" "$T/cl" && ok || { bad "$1: no line like '$2'"; sed 's/^/  client: /' "$T/cl.raw" | tail -8; }; }

# srv_start NAME ARGS...: df1opcua in the background until it says it serves; SRV_PID
# (srv_launch starts it, srv_wait NAME waits)
srv_launch() {
	sname=$1; shift
	: > "$T/$sname.err"
	$OPCUA "$@" > "$T/$sname.out" 2> "$T/$sname.err" &
	SRV_PID=$!
	echo "$SRV_PID" >> "$T/.sims"
}
srv_start() {
	srv_launch "$@"
	srv_wait "$1"
}
srv_wait() {
	sname=$1
	n=200
	while [ $n -gt 0 ] && ! grep -q ' tags of ' "$T/$sname.err"; do
		grep -q ' tags of \|Traceback\|: DF1_E' "$T/$sname.err" && break
		n=$((n - 1)); tick
	done
	grep -q ' tags of ' "$T/$sname.err" && ok || { bad "df1opcua $sname did not start"; sed 's/^/  df1opcua: /' "$T/$sname.err" | head; }
}
srv_stop() {
	p=${1:-$SRV_PID}
	kill -TERM "$p" 2>/dev/null
	wait "$p"
	same "df1opcua: SIGTERM ends it with status 0" "$?" 0
	grep -v "^$p\$" "$T/.sims" > "$T/.sims.new"; mv "$T/.sims.new" "$T/.sims"
}

cat > "$T/map.csv" <<'CSV'
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
Speed,ReadWrite,INT,1,SLC,N7:0,1,100
Counter,Read,INT,1,SLC,N7:1,1,100
Block,Read,INT,1,SLC,N7:10,4,200
Level,Read,FLOAT,1,SLC,F8:3,1,200
Running,ReadWrite,BOOL,1,SLC,B3:0/5,1,200
Total,Read,LONG,1,SLC,L10:0,1,200
Name,ReadWrite,STRING,1,SLC,ST9:0,1,500
Cycle,Read,TIMER,1,SLC,T4:0,1,200
CSV
printf 'N7:0=5\nN7:10=1,-2,3,30000\nF8:3=21.5\nL10:0=100000\nST9:0=hello\nT4:0.PRE=500\nT4:0.ACC=12\nB3:0=32\n' > "$T/plc.data"

# ---- usage and configuration errors: exit 2 ----
expect 2 "df1opcua: an unknown option" -- $OPCUA --bogus
err_has "df1opcua: the unknown option named" "--bogus"
expect 2 "df1opcua: no --map" -- $OPCUA -d /dev/null
err_has "df1opcua: --map asked for" "--map FILE.csv is required"
expect 2 "df1opcua: a --map that does not exist" -- $OPCUA -d /dev/null --map "$T/nope.csv"
err_has "df1opcua: the missing map named" "nope.csv: no such file"
expect 2 "df1opcua: a bad --listen" -- $OPCUA -d /dev/null --map "$T/map.csv" --listen 1.2.3.4:99999
printf 'Tag,Command,Type,Station,PLC_Type,Address\nX,Read,INT,1,SLC,N7:x\n' > "$T/bad.csv"
sim_start plc --data "$T/plc.data" --ramp N7:1@100 --log "$T/plc.log" --silent 9 -v
expect 2 "df1opcua: a mapping row with a bad address" -- $OPCUA -d "$SIM_DEV" --map "$T/bad.csv"
err_has "df1opcua: the bad row's catalog ID" "[2503]"
expect 2 "df1opcua: --add-user without --users" -- $OPCUA --add-user alice
expect 0 "df1opcua --help" -- $OPCUA --help
check "df1opcua --help: names --listen and its default" "grep -q '127.0.0.1:4840' '$T/out'"

# ---- a second line, owned by df1gw: df1opcua through its EtherNet/IP bridge ----
# (started now, so that it comes up while the first server's checks run)
PLC_PID=$SIM_PID; PLC_DEV=$SIM_DEV
sim_start gwplc --data "$T/plc.data" --log "$T/gwplc.log"
GWSIM_PID=$SIM_PID
"$BIN/df1gw" -d "$SIM_DEV" --eip 0 > "$T/gw.out" 2> "$T/gw.err" &
GW_PID=$!
echo "$GW_PID" >> "$T/.sims"
gw_addr() { EIP=$(sed -n 's|^df1gw: EtherNet/IP on \([0-9.]*:[0-9]*\).*|\1|p' "$T/gw.err" | head -n 1); [ -n "$EIP" ]; }
wait_for "df1gw --eip says where it listens" 100 gw_addr
P3=$(free_port)
srv_launch c -d "eip://$EIP" --name GW --map "$T/map.csv" --listen "$P3" --pki "$T/pki-c"
C_PID=$SRV_PID
SIM_PID=$PLC_PID; SIM_DEV=$PLC_DEV

# ---- one server on loopback, SecurityPolicy None ----
P1=$(free_port)
srv_start a -d "$SIM_DEV" --map "$T/map.csv" --listen "$P1" --name L1 --pki "$T/pki" --watchdog 3000 -o 200 --enq-retries 0 -v
check "df1opcua: on loopback it says nothing of other machines" "! grep -q 'other machines' '$T/a.err'"
check "df1opcua: the server's certificate made in own/" "[ -s '$T/pki/own/cert.der' ] && [ -s '$T/pki/own/private/key.pem' ]"
check "df1opcua: the key is 0600" "[ \"\$(stat -c %a '$T/pki/own/private/key.pem')\" = 600 ]"
U1=opc.tcp://127.0.0.1:$P1
client "$U1" browse:L1 browse:L1.station1 browse:L1.station1.Cycle \
	attrs:L1.station1.Speed attrs:L1.station1.Block attrs:L1.station1.Level attrs:L1.station1.Total \
	attrs:L1.station1.Running attrs:L1.station1.Name attrs:L1.station1.Cycle.PRE \
	waitval:L1.station1.Speed:5:$W \
	$(good L1.station1.Block L1.station1.Level L1.station1.Total L1.station1.Running L1.station1.Name \
		L1.station1.Cycle.PRE L1.station1.Cycle.ACC) \
	waitval:L1.station1.Online:true:$W "waitval:L1.station1.ProcessorType:\"SLC 5/04\":$W" \
	read:L1.station1.Block read:L1.station1.Level read:L1.station1.Total \
	read:L1.station1.Running read:L1.station1.Name read:L1.station1.Cycle.PRE read:L1.station1.Cycle.ACC \
	read:L1.station1.Online read:L1.station1.ProcessorType
has "browse: the line's folder holds station1" "child station1 Object ns=2;s=L1.station1"
for t in Speed Counter Block Level Running Total Name; do
	has "browse: $t a Variable" "child $t Variable ns=2;s=L1.station1.$t"
done
has "browse: a TIMER row an Object" "child Cycle Object ns=2;s=L1.station1.Cycle"
for m in EN TT DN PRE ACC; do has "browse: the timer's $m" "child $m Variable ns=2;s=L1.station1.Cycle.$m"; done
for m in Online State ProcessorType; do has "browse: the station's $m" "child $m Variable ns=2;s=L1.station1.$m"; done
# AccessLevel: CurrentRead 1, CurrentRead|CurrentWrite 3; ValueRank -1 scalar, 1 an array
has "attrs: INT ReadWrite" "attrs L1.station1.Speed Int16 -1 null 3 3"
has "attrs: INT Count 4 an array" "attrs L1.station1.Block Int16 1 [4] 1 1"
has "attrs: FLOAT" "attrs L1.station1.Level Float -1 null 1 1"
has "attrs: LONG" "attrs L1.station1.Total Int32 -1 null 1 1"
has "attrs: BOOL ReadWrite" "attrs L1.station1.Running Boolean -1 null 3 3"
has "attrs: STRING" "attrs L1.station1.Name String -1 null 3 3"
has "attrs: a timer's PRE" "attrs L1.station1.Cycle.PRE Int16 -1 null 1 1"
has "value: N7:0 from df1sim --data" "waitval L1.station1.Speed Good 5"
has_re "value: N7:10,4" "^read L1.station1.Block Good \[1,-2,3,30000\] [1-9]"
has_re "value: F8:3" "^read L1.station1.Level Good 21.5 [1-9]"
has_re "value: L10:0" "^read L1.station1.Total Good 100000 [1-9]"
has_re "value: B3:0/5 (B3:0=32)" "^read L1.station1.Running Good true [1-9]"
has_re "value: ST9:0" "^read L1.station1.Name Good \"hello\" [1-9]"
has_re "value: T4:0.PRE" "^read L1.station1.Cycle.PRE Good 500 [1-9]"
has_re "value: T4:0.ACC" "^read L1.station1.Cycle.ACC Good 12 [1-9]"
has_re "station: online" "^read L1.station1.Online Good true"
has_re "station: its processor from the diagnostic status" "^read L1.station1.ProcessorType Good \"SLC 5/04\""
# the SourceTimestamp is the read time: within the last minute of this machine's clock
ts=$(awk '$1 == "read" && $2 == "L1.station1.Level" { print $5 }' "$T/cl")
now=$(date +%s)
check "value: SourceTimestamp a recent read ($ts)" "[ -n '$ts' ] && [ \$(( $now - $ts / 1000 )) -lt 60 ] && [ \$(( $ts / 1000 - $now )) -le 1 ]"

# in one session: a subscription, writes, the PLC silent and back
# subscription: df1sim adds 1 to N7:1 every 100 ms; the first three notifications (however the
# server batches them), each larger
# writes: Good after the PLC acknowledged, exactly one typed write in df1sim's log
# the PLC goes silent (SIGUSR1): Uncertain (the last usable value), Bad once the watchdog says offline; Good when it answers again
client "$U1" sub:L1.station1.Counter:3:$W \
	write:L1.station1.Speed:Int16:42 write:L1.station1.Level:Float:1.5 \
	write:L1.station1.Block:Int16:[5,6,7,8] write:L1.station1.Name:String:'"line 2"' \
	write:L1.station1.Online:Boolean:false waitval:L1.station1.Speed:42:$W \
	kill:$SIM_PID:SIGUSR1 wait:L1.station1.Speed:UncertainLastUsableValue:$W2 \
	wait:L1.station1.Speed:BadCommunicationError:$W2 waitval:L1.station1.Online:false:$W \
	read:L1.station1.Online kill:$SIM_PID:SIGUSR2 wait:L1.station1.Speed:Good:$W2 read:L1.station1.Speed
has "subscription: three notifications" "subdone L1.station1.Counter 3"
check "subscription: the values rise" "awk '\$1 == \"sub\" { if (\$3 != \"Good\" || (n && \$4 <= last)) bad = 1; last = \$4; n++ } END { exit bad || n != 3 }' '$T/cl'"

has "write: a ReadWrite INT Good" "write L1.station1.Speed Good"
has "write: a Read FLOAT refused" "write L1.station1.Level BadNotWritable"
has "write: a Read array refused" "write L1.station1.Block BadNotWritable"
has "write: a ReadWrite STRING Good" "write L1.station1.Name Good"
has "write: a station Variable refused" "write L1.station1.Online BadNotWritable"
has "write: the value read back" "waitval L1.station1.Speed Good 42"
same "write: N7:0 written once (df1sim --log)" "$(grep -c 'cmd=0F/AA addr=N7:0 ' "$T/plc.log")" 1
same "write: ST9:0 written once" "$(grep -c 'cmd=0F/AA addr=ST9:0 ' "$T/plc.log")" 1
same "write: nothing sent for the Read rows" "$(grep -Ec 'cmd=0F/AA addr=(F8:3|N7:10) ' "$T/plc.log")" 0
has "silent PLC: first UncertainLastUsableValue" "wait L1.station1.Speed UncertainLastUsableValue"
has "silent PLC: BadCommunicationError" "wait L1.station1.Speed BadCommunicationError"
has_re "silent PLC: the station not online" "^read L1.station1.Online Good false"
has "PLC back: Good" "wait L1.station1.Speed Good"
has_re "PLC back: its value" "^read L1.station1.Speed Good 42 "

# loopback only: not reachable on this machine's other addresses
ip=$(hostname -I 2>/dev/null | tr ' ' '\n' | grep -E '^[0-9.]+$' | grep -v '^127\.' | head -n 1)
if [ -n "$ip" ]; then
	check "loopback only: nothing listens on $ip:$P1" \
		"! python3 -c \"import socket; socket.create_connection(('$ip', $P1), 2).close()\" 2>/dev/null"
else
	skip "loopback only: this machine has no other IPv4 address"
fi
srv_stop

# the line of df1gw, through its EtherNet/IP bridge: values, and a write once
srv_wait c
client "opc.tcp://127.0.0.1:$P3" waitval:GW.station1.Level:21.5:$W $(good GW.station1.Block) read:GW.station1.Block \
	write:GW.station1.Speed:Int16:9 waitval:GW.station1.Speed:9:$W write:GW.station1.Total:Int32:1
has "through df1gw --eip: F8:3" "waitval GW.station1.Level Good 21.5"
has_re "through df1gw --eip: N7:10,4" "^read GW.station1.Block Good \[1,-2,3,30000\] "
has "through df1gw --eip: a write Good" "write GW.station1.Speed Good"
has "through df1gw --eip: the value read back" "waitval GW.station1.Speed Good 9"
has "through df1gw --eip: a Read row refused" "write GW.station1.Total BadNotWritable"
same "through df1gw --eip: N7:0 written once (df1sim --log)" "$(grep -c 'cmd=0F/AA addr=N7:0 ' "$T/gwplc.log")" 1
same "through df1gw --eip: nothing written to L10:0" "$(grep -c 'cmd=0F/AA addr=L10:0 ' "$T/gwplc.log")" 0
srv_stop "$C_PID"
kill -TERM "$GW_PID"; lib_reap "$GW_PID"

# ---- users, a named address, Basic256Sha256 ----
# and a station that never answers (df1sim serves station 1 only): no last value, BadNoCommunication
{ cat "$T/map.csv"; echo "Ghost,Read,INT,9,SLC,N7:0,1,1000"; } > "$T/map2.csv"
printf 'secret one\n' | $OPCUA --users "$T/users" --add-user alice 2> "$T/add.err"
same "--add-user: exit 0" "$?" 0
check "--add-user: a salted hash, not the password" "grep -q '^alice:scrypt\\$' '$T/users' && ! grep -q 'secret' '$T/users'"
check "--add-user: the file 0600" "[ \"\$(stat -c %a '$T/users')\" = 600 ]"
P2=$(free_port)
if [ -n "$ip" ]; then
	L2=$ip; srv_start b -d "$SIM_DEV" --listen "$ip:$P2" --name L1 --pki "$T/pki" --users "$T/users" --map "$T/map2.csv" -o 200
	check "a named address: says other machines reach it" "grep -q 'reachable from other machines' '$T/b.err'"
else
	L2=127.0.0.1; srv_start b -d "$SIM_DEV" --listen "$P2" --name L1 --pki "$T/pki" --users "$T/users" --map "$T/map2.csv" -o 200
	skip "a named address: this machine has no other IPv4 address"
fi
U2=opc.tcp://$L2:$P2
if [ -n "$ip" ]; then
	client "$U2" read:L1.station1.Speed
	has_re "a named address: no SecurityPolicy None" "^error "
fi
rm -f "$T"/pki/rejected/*
client "$U2" mode=SignAndEncrypt user=alice "password=secret one" read:L1.station1.Speed
has_re "unknown client certificate: refused" "^error "
check "unknown client certificate: the client told BadCertificateUntrusted" "grep -q BadCertificateUntrusted '$T/cl.raw'"
check "unknown client certificate: kept in rejected/" "ls '$T'/pki/rejected/*.der >/dev/null 2>&1"
mv "$T"/pki/rejected/*.der "$T/pki/trusted/"
# the server just started: Speed waited for until its first poll, then read
client "$U2" mode=SignAndEncrypt user=alice "password=secret one" $(good L1.station1.Speed) read:L1.station1.Speed \
	write:L1.station1.Speed:Int16:7 \
	read:L1.station9.Ghost read:L1.station9.Online
has_re "moved to trusted/: admitted, SignAndEncrypt" "^read L1.station1.Speed Good "
has "SignAndEncrypt: a write Good" "write L1.station1.Speed Good"
has_re "a station that never answered: BadNoCommunication" "^read L1.station9.Ghost BadNoCommunication null "
has_re "a station that never answered: not online" "^read L1.station9.Online Good false "
same "SignAndEncrypt: N7:0=7 written once" "$(grep -c 'cmd=0F/AA addr=N7:0 ' "$T/plc.log")" 2
client "$U2" mode=Sign user=alice "password=secret one" read:L1.station1.Speed
has_re "Sign: admitted" "^read L1.station1.Speed Good "
client "$U2" mode=SignAndEncrypt user=alice password=wrong read:L1.station1.Speed
has_re "a wrong password: refused" "^error .*BadUserAccessDenied"
client "$U2" mode=SignAndEncrypt read:L1.station1.Speed
has_re "anonymous with --users: refused" "^error "
srv_stop

# ---- --write-timeout: writes that did not get the line in time ----
# df1sim answers every command 1 s late: of one Write request of three, the
# first goes to the line (>= 1 s), the two behind it wait and expire after
# 300 ms, answered BadTimeout and never sent; a write after that one Good.
sim_start slow --data "$T/plc.data" --log "$T/slow.log" --delay 1000
P4=$(free_port)
srv_start d -d "$SIM_DEV" --map "$T/map.csv" --listen "$P4" --name L4 --pki "$T/pki" -o 3000 --cmd-timeout 5000 \
	--write-timeout 300
client "opc.tcp://127.0.0.1:$P4" \
	'writes:L4.station1.Speed:Int16:11|L4.station1.Speed:Int16:12|L4.station1.Name:String:"late"' \
	write:L4.station1.Speed:Int16:13
same "--write-timeout: the first Good, the two behind it BadTimeout, a later one Good" \
	"$(grep '^write ' "$T/cl" | tr '\n' ' ')" \
	"write L4.station1.Speed Good write L4.station1.Speed BadTimeout write L4.station1.Name BadTimeout write L4.station1.Speed Good "
same "--write-timeout: N7:0 written twice, 11 and 13, not 12 (df1sim --log)" "$(grep -c 'cmd=0F/AA addr=N7:0 ' "$T/slow.log")" 2
same "--write-timeout: the expired ST9:0 never written" "$(grep -c 'cmd=0F/AA addr=ST9:0 ' "$T/slow.log")" 0
err_in() { grep -qF "$2" "$T/d.err" && ok || { bad "$1: no '$2' in df1opcua's stderr"; sed 's/^/  df1opcua: /' "$T/d.err" | tail -5; }; }
err_in "--write-timeout: says why N7:0 was not written" "write to Speed expired, not written: not started within 300 ms"
err_in "--write-timeout: says why ST9:0 was not written" "write to Name expired, not written: not started within 300 ms"
expect 2 "--write-timeout 0: a usage error" -- $OPCUA -d "$SIM_DEV" --map "$T/map.csv" --write-timeout 0
err_has "--write-timeout 0: names the option" "--write-timeout"
srv_stop
finish
