#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# A PLC-3 (doc/PROTOCOL.md 4.2a) through every tool: df1read, df1write, df1mon
# --map and df1gw against df1sim --plc plc3 on a pseudo-terminal. Values are
# checked against the data file df1sim was given and against what was written;
# the commands on the line (0F/01 word range read, 0F/00 word range write, 0F/02
# bit write) and their addresses in PLC-3 text are checked in df1sim's --log.
# The address forms are a PLC-3's own: octal bits and I/O words, T4.ACC.
# Run from the repository root; DF1_BIN = the built tools.
. tests/support/lib.sh
R="$BIN/df1read"
W="$BIN/df1write"
MON="$BIN/df1mon"
GW="$BIN/df1gw"
for t in df1read df1write df1mon df1sim; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE

cat > "$T/data" <<'EOF'
N3:173=42,-7
B5:173=0x0401
F2:10=1.5,-2.25
H8:99=123456789
D7:12=0x1234
I0:17=0x00FF
A1:126=0x4142
T4=PRE=500 ACC=7 EN=1
C2=PRE=10 ACC=3 CU=1
B3:0=3
EOF
LOG="$T/sim.log"
logged() { grep -c -F -e "$1" "$LOG" 2>/dev/null || true; }

# ---- usage: --plc plc3 and the PLC-3 grammar, refused before any device ----
expect 2 "an SLC address is not PLC-3 text" -- "$R" -d /nonexistent --plc plc3 T4:2.ACC
err_has "T4:2.ACC: range" "[2504] ERR_ADDRESS_RANGE"
expect 2 "octal bits: no 8" -- "$R" -d /nonexistent --plc plc3 B5:173/18
err_has "B5:173/18: syntax" "[2503] ERR_ADDRESS_SYNTAX"
expect 2 "no control section on a PLC-3" -- "$W" -d /nonexistent --plc plc3 R6:0=1
expect 2 "--plc plc4 is no family" -- "$R" -d /nonexistent --plc plc4 N7:0
err_has "--plc: the families" "plc3"

# ---- df1mon --decode: the hand-written frames of tests/data/plc3_vectors.txt ----
for chk in bcc crc; do
	grep -v '^#' tests/data/plc3_vectors.txt | awk -F' [|] ' -v c=$chk '$2 == c { print $3 }' > "$T/frames.$chk"
	expect 0 "df1mon --decode PLC-3 frames ($chk)" -- sh -c "exec \"$MON\" --check $chk --decode < \"$T/frames.$chk\""
	check "decode $chk: every frame good" 'grep -q "frames 14 (good 14, bad 0)" "$T/err"'
	check "decode $chk: a read named, PLC-3 text" 'grep -Eq "0F/01 +PLC-3 word range read +N3:173 size 2" "$T/out"'
	check "decode $chk: its reply's value" 'grep -Eq "reply to 0F/01 +N3:173 size 2 .*= 42" "$T/out"'
	check "decode $chk: an octal bit" 'grep -Eq "0F/02 +PLC-3 bit write +B5:173/15 += 1" "$T/out"'
	check "decode $chk: a float low word first" 'grep -Eq "reply to 0F/01 +F2:10 size 4 .*= 1.5" "$T/out"'
	check "decode $chk: a timer bit" 'grep -Eq "0F/02 +PLC-3 bit write +T4/EN += 0" "$T/out"'
	check "decode $chk: M p.13-6 address" 'grep -Eq "PLC-3 word range read +B260:0 size 2" "$T/out"'
done

sim_start p3 --plc plc3 --data "$T/data" --log "$LOG" || finish
D=$SIM_DEV

# ---- df1read: every section, values from the data file ----
expect 0 "df1read every section" -- "$R" -d "$D" --plc plc3 -f csv N3:173,2 B5:173/12 B5:173/10 \
	F2:10,2 H8:99 D7:12 I0:17 A1:126 T4 T4.ACC C2.PRE T4/EN C2/CU
out_is "df1read values" 'address,value
N3:173,42
N3:174,-7
B5:173/12,1
B5:173/10,0
F2:10,1.5
F2:11,-2.25
H8:99,123456789
D7:12,4660
I0:17,255
A1:126,16706
T4,"EN=1 TT=0 DN=0 PRE=500 ACC=7"
T4.ACC,7
C2.PRE,10
T4/EN,1
C2/CU,1'
check "log: word range reads, PLC-3 text" '[ "$(logged "cmd=0F/01 addr=N3:173 count=2")" -ge 1 ]'
check "log: an octal I/O word" '[ "$(logged "cmd=0F/01 addr=I0:17 count=1")" -ge 1 ]'
check "log: H is two words" '[ "$(logged "cmd=0F/01 addr=H8:99 count=2")" -ge 1 ]'
check "log: nothing but PLC-3 commands" '! grep -v "name=\"PLC-3 word range read (0F/01)\"" "$LOG"'

# a read larger than a packet: 244 bytes (122 words) a reply (1775-KA)
expect 0 "200 words" -- "$R" -d "$D" --plc plc3 N3:0,200
check "200 words: 122 then 78" '[ "$(logged "addr=N3:0 count=122")" = 1 ] && [ "$(logged "addr=N3:122 count=78")" = 1 ]'

# ---- df1write: words, floats, 32-bit, members, bits (0F/02, the other bits kept) ----
expect 0 "df1write" -- "$W" -d "$D" --plc plc3 N3:200=-5,6 F2:20=2.5 H8:100=-100000 T4.PRE=900 \
	D7:13=0x9999 O0:377=7 B5:173=0x0401
check "log: word range writes" '[ "$(logged "cmd=0F/00 addr=N3:200 count=2")" = 1 ] && [ "$(logged "cmd=0F/00 addr=T4.PRE count=1")" = 1 ]'
check "log: an octal output word" '[ "$(logged "cmd=0F/00 addr=O0:377 count=1")" = 1 ]'
expect 0 "a bit" -- "$W" -d "$D" --plc plc3 B5:173/17=1
check "log: a bit write" '[ "$(logged "cmd=0F/02 addr=B5:173 ")" = 1 ]'
expect 0 "read back" -- "$R" -d "$D" --plc plc3 N3:200,2 F2:20 H8:100 T4.PRE D7:13 O0:377 B5:173
out_is "read back values" '-5
6
2.5
-100000
900
-26215
7
-31743'
expect 0 "a timer's bit" -- "$W" -d "$D" --plc plc3 T4/EN=0
expect 0 "a timer's bit read back" -- "$R" -d "$D" --plc plc3 T4
out_is "T4: EN off, the rest kept" 'EN=0 TT=0 DN=0 PRE=900 ACC=7'
n=$(wc -l < "$LOG")
expect 2 "a value that does not fit" -- "$W" -d "$D" --plc plc3 N3:0=70000
same "nothing sent for a bad value" "$(wc -l < "$LOG")" "$n"
expect 1 "a file df1sim does not have" -- "$R" -d "$D" --plc plc3 N9:0
err_has "N9:0: the PLC's answer" "EXT STS 0x06"

# ---- the network file: PLC_Type PLC3 ----
printf 'PLC_Type,Error_Code,Mode\nPLC3,CRC,Peer\n' > "$T/net.csv"
expect 0 "-N with PLC_Type PLC3" -- "$R" -N "$T/net.csv" -d "$D" N3:173 T4.ACC
out_is "-N values" '42
7'

# ---- df1mon --map: PLC3 rows ----
cat > "$T/map.csv" <<'EOF'
Tag,Command,Type,Station,PLC_Type,Address,Count
level,Read,INT,1,PLC3,N3:173,2
run,Read,BOOL,1,PLC3,B5:173/12,1
flow,Read,FLOAT,1,PLC3,F2:10,1
acc,Read,INT,1,PLC3,T4.ACC,1
b3,Read,INT,1,PLC3,B3:0,1
n3,Read,INT,1,PLC3,N3:0,1
EOF
expect 0 "df1mon --map -1" -- "$MON" -d "$D" --map "$T/map.csv" -1
check "df1mon: level" 'grep -Eq "^level +1 N3:173,2 +42,-7 +GOOD" "$T/out"'
check "df1mon: run" 'grep -Eq "^run +1 B5:173/12 +1 +GOOD" "$T/out"'
check "df1mon: flow" 'grep -Eq "^flow +1 F2:10 +1.5 +GOOD" "$T/out"'
check "df1mon: acc" 'grep -Eq "^acc +1 T4.ACC +7 +GOOD" "$T/out"'
# file 3 of two sections: two files, two blocks (doc/PROTOCOL.md 4.2a)
check "df1mon: B3 is not N3" 'grep -Eq "^b3 +1 B3:0 +3 +GOOD" "$T/out" && grep -Eq "^n3 +1 N3:0 +0 +GOOD" "$T/out"'
printf 'Tag,Command,Type,Station,PLC_Type,Address\nbad,Read,INT,1,PLC3,N3:10000\n' > "$T/badmap.csv"
expect 2 "df1mon: a PLC3 row out of range" -- "$MON" -d "$D" --map "$T/badmap.csv" -1
err_has "df1mon: 2504" "[2504]"

# ---- df1gw: a PLC3 row published and written through MQTT ----
MOSQ=${MOSQUITTO:-/usr/sbin/mosquitto}
if [ -x "$GW" ] && [ -x "$MOSQ" ] && command -v mosquitto_sub >/dev/null 2>&1; then
	MQ_PORT=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
	printf 'listener %s 127.0.0.1\npersistence false\nuser %s\nallow_anonymous true\n' \
		"$MQ_PORT" "$(id -un)" > "$T/mq.conf"
	"$MOSQ" -c "$T/mq.conf" > "$T/mq.log" 2>&1 &
	echo $! >> "$T/.sims"
	port_open() { python3 -c "import socket; socket.create_connection(('127.0.0.1', $MQ_PORT), 1).close()" 2>/dev/null; }
	wait_for "broker listens" 100 port_open
	sub1() { mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t "$1" -C 1 -W 2 2>/dev/null; }
	has() { sub1 "$1" | grep -F -q -e "$2"; }
	cat > "$T/gwmap.csv" <<'EOF'
Tag,Command,Type,Station,PLC_Type,Address,Count
Level,ReadWrite,INT,1,PLC3,N3:173,1
Run,Read,BOOL,1,PLC3,B5:173/12,1
EOF
	"$GW" -d "$D" --map "$T/gwmap.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix p3 \
		> "$T/gw.out" 2> "$T/gw.err" &
	GW_PID=$!
	echo "$GW_PID" >> "$T/.sims"
	wait_for "df1gw: Level published" 100 has p3/tag/Level '"value":42'
	check "df1gw: Level's address in PLC-3 text" 'has p3/tag/Level "\"address\":\"N3:173\""'
	wait_for "df1gw: Run published" 50 has p3/tag/Run '"address":"B5:173/12"'
	mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -q 1 -t p3/tag/Level/set -m 77
	wait_for "df1gw: the write on the line" 100 sh -c "grep -q 'cmd=0F/00 addr=N3:173 count=1' '$LOG'"
	wait_for "df1gw: the new value published" 100 has p3/tag/Level '"value":77'
	kill -TERM "$GW_PID" 2>/dev/null
	lib_reap "$GW_PID"
else
	skip "df1gw part: df1gw, mosquitto or mosquitto-clients missing"
fi

sim_stop
finish
