#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# df1read against df1sim, over pseudo-terminals and TCP: every output format,
# every value type, exit statuses 0/1/2, bad input, half and full duplex, BCC
# and CRC, several stations, elements above 254, reads split across packets and
# reads joined into blocks (counted with -v, which reports counter 2527, and
# with df1sim --log). Run from the repository root; DF1_BIN = the built tools.
. tests/support/lib.sh
R="$BIN/df1read"
for t in df1read df1sim; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE

# Initial data beyond df1sim's defaults (N7:n = n, F8:n = n + 0.5, T4/C5 PRE=100,
# 256 elements per file): strings, long integers, N7 grown to 301 elements.
cat > "$T/data" <<'EOF'
ST9:0="hello, world"
ST9:1=second
ST9:2="say \"hi\""
L10:0=70000,-5,0x7FFFFFFF
N7:300=42
F8:10=-0.1
T4:1="EN=1 DN=1 PRE=500 ACC=42"
C5:0="CU=1 PRE=10 ACC=3"
R6:0="LEN=8 POS=2"
B3:0=0x0029
EOF

# Commands df1sim answered so far (its --log has one line per command).
logged() { if [ -f "$1" ]; then wc -l < "$1" | tr -d ' '; else echo 0; fi; }
log_has() { [ "$(logged "$1")" -ge "$2" ]; }
# commands reported by -v ("N commands sent")
sent() { sed -n 's/.* \([0-9][0-9]*\) commands\{0,1\} sent$/\1/p' "$T/err" | tail -n 1; }

# ---- usage and address errors: exit 2, nothing sent (no device needed) ----
expect 2 "no operand" -- "$R" -d /nonexistent
err_has "no operand message" "no address given"
expect 2 "unknown option" -- "$R" --bogus N7:0
expect 2 "bad format" -- "$R" -d /nonexistent -f xml N7:0
expect 2 "bad station" -- "$R" -d /nonexistent -a 255 N7:0
expect 2 "bad syntax" -- "$R" -d /nonexistent N7:x
err_has "2503 text" "df1read: N7:x: [2503] ERR_ADDRESS_SYNTAX: Item: 1, Invalid Address Syntax (N7:x)"
check "2503: stdout empty" '[ ! -s "$T/out" ]'
expect 2 "bad syntax, second operand" -- "$R" -d /nonexistent N7:0 F8:0/1
err_has "2503 item 2" "Item: 2,"
expect 2 "element out of range" -- "$R" -d /nonexistent N7:1000
err_has "2504 text" "[2504] ERR_ADDRESS_RANGE: Item: 1, Address is out of range (N7:1000, len=1)"
expect 2 "count past element 999" -- "$R" -d /nonexistent N7:998,5
err_has "2504 count" "(N7:998, len=5)"
expect 2 "file out of range" -- "$R" -d /nonexistent N1000:0
err_has "2504 file" "[2504] ERR_ADDRESS_RANGE"
expect 2 "timer bits past the word" -- "$R" -d /nonexistent T4:0/DN,4
expect 2 "count 0" -- "$R" -d /nonexistent N7:0,0
expect 2 "count not a number" -- "$R" -d /nonexistent N7:0,x
expect 2 "no device" -- "$R" N7:0
err_has "no device message" "DF1_DEVICE"
expect 2 "bad network file" -- "$R" -N tests/data/net_invalid.csv N7:0
err_has "network file issue" "[255"
for id in 2552 2553 2555 2556 2557 2558 2559; do
	check "bad network file: [$id] reported" 'grep -q "^df1read: tests/data/net_invalid.csv: line 3: \[$id\] CRT_" "$T/err"'
done
check "bad network file: stdout empty" '[ ! -s "$T/out" ]'
# each invalid value alone: its critical ID, exit 2, the tool does not start
# (the device would be found: DF1_DEVICE is a file that exists)
: > "$T/notatty"
for row in "Station 255 2552" "Mode Boss 2553" "PLC_Type PLC4 2555" "Error_Code XOR 2556" \
	"NAK_Retries 11 2557" "ENQ_Retries x 2558" "Cmd_Timeout 499 2559" "Cmd_Timeout 5001 2559"; do
	set -- $row
	printf '%s\n%s\n' "$1" "$2" > "$T/bad_net.csv"
	expect 2 "network file $1=$2" -- env DF1_DEVICE="$T/notatty" "$R" -N "$T/bad_net.csv" N7:0
	err_has "network file $1=$2: ID" "df1read: $T/bad_net.csv: line 2: [$3] CRT_"
done
# a slave module's file does not describe a master tool, unless --duplex says how to run
printf 'Mode,Com_Port\nSlave,%s\n' "$T/notatty" > "$T/slave_net.csv"
expect 2 "network file Mode=Slave" -- "$R" -N "$T/slave_net.csv" N7:0
err_has "Mode=Slave: 2554" "df1read: $T/slave_net.csv: [2554] CRT_UNSUPPORTED_MODE: Unsupported Driver Mode (Slave)"
# a network file must hold a data row: a header alone is a configuration error
# (exit 2), and nothing is opened, neither the device given (which would fail
# loudly: it does not exist) nor the file's default port /dev/ttyS0
printf 'Station,Mode,Baud\n' > "$T/hdr_net.csv"
expect 2 "network file with only a header" -- "$R" -N "$T/hdr_net.csv" -d "$T/hdr-nodev" N7:0
err_has "header only: the file and the reason" "df1read: $T/hdr_net.csv: "
err_has "header only: no data row" "no data row"
check "header only: the device is not opened" '! grep -q "hdr-nodev" "$T/err"'
check "header only: stdout empty" '[ ! -s "$T/out" ]'
expect 2 "network file with only a header, DF1_DEVICE" -- env DF1_DEVICE="$T/hdr-nodev" "$R" -N "$T/hdr_net.csv" N7:0
check "header only, DF1_DEVICE: not opened" '! grep -q "hdr-nodev" "$T/err"'
expect 2 "network file with only a header, no device given" -- env -u DF1_DEVICE "$R" -N "$T/hdr_net.csv" N7:0
err_has "header only, no device: no data row" "no data row"
check "header only, no device: /dev/ttyS0 not opened" '! grep -q "ttyS0" "$T/err"'
expect 1 "device that does not exist" -- "$R" -d "$T/nodev" N7:0
expect 0 "--help" -- "$R" --help
check "--help: usage" 'grep -q "^Usage: df1read \[OPTIONS\] ADDRESS\[,COUNT\]\.\.\." "$T/out"'
check "--help: every format" 'grep -q "plain|csv|json" "$T/out"'
expect 0 "--version" -- "$R" --version
check "--version text" 'grep -q "^df1read (libdf1) [0-9]" "$T/out"'
check "--version: the library's version (df1_version) too" '[ "$(sed -n 2p "$T/out")" = "library: libdf1 $(sed -n "s/^df1read (libdf1) //p" "$T/out")" ]'

# ---- the same suite over a pseudo-terminal and over TCP ----
for tr in pty tcp; do
	SIM_TRANSPORT=$tr sim_start "full_$tr" --data "$T/data" --log "$T/full_$tr.log" || continue
	D=$SIM_DEV
	L="$T/full_$tr.log"

	expect 0 "$tr: one value" -- "$R" -d "$D" N7:5
	out_is "$tr: one value, nothing else" "5"
	v=$("$R" -d "$D" N7:7)
	same "$tr: v=\$(df1read ...)" "$v" "7"

	expect 0 "$tr: plain, every type" -- "$R" -d "$D" N7:0,3 F8:0 F8:10 L10:0,3 ST9:0 ST9:2 \
		T4:1 C5:0 R6:0 T4:1.PRE T4:1.ACC T4:1/DN T4:1/TT B3:0/0,4 B3/5 L10:0/4 N7:300
	out_is "$tr: plain values" "0
1
2
0.5
-0.1
70000
-5
2147483647
hello, world
say \"hi\"
EN=1 TT=0 DN=1 PRE=500 ACC=42
CU=1 CD=0 DN=0 OV=0 UN=0 UA=0 PRE=10 ACC=3
EN=0 EU=0 DN=0 EM=0 ER=0 UL=0 IN=0 FD=0 LEN=8 POS=2
500
42
1
0
1
0
0
1
1
1
42"
	check "$tr: nothing on stderr" '[ ! -s "$T/err" ]'

	expect 0 "$tr: csv" -- "$R" -d "$D" -f csv n7:0,2 F8:1 ST9:0,3 T4:1 B3/3,3 T4:1/EN L10:0/31,2 N7:299,2
	out_is "$tr: csv rows" 'address,value
N7:0,0
N7:1,1
F8:1,1.5
ST9:0,"hello, world"
ST9:1,"second"
ST9:2,"say ""hi"""
T4:1,"EN=1 TT=0 DN=1 PRE=500 ACC=42"
B3:0/3,1
B3:0/4,0
B3:0/5,1
T4:1/EN,1
L10:0/31,0
L10:1/0,1
N7:299,299
N7:300,42'

	expect 0 "$tr: json" -- "$R" -d "$D" -f json N7:0 F8:10 ST9:2 T4:1 C5:0.ACC B3:0/5 L10:1
	out_is "$tr: json array" '[
{"address":"N7:0","value":0},
{"address":"F8:10","value":-0.1},
{"address":"ST9:2","value":"say \"hi\""},
{"address":"T4:1","value":{"EN":1,"TT":0,"DN":1,"PRE":500,"ACC":42}},
{"address":"C5:0.ACC","value":3},
{"address":"B3:0/5","value":1},
{"address":"L10:1","value":-5}
]'
	if command -v python3 >/dev/null 2>&1; then
		check "$tr: json parses" 'python3 -c "import json,sys; json.load(sys.stdin)" < "$T/out"'
	fi

	# one read, split across packets: 200 words = 400 bytes > 236 -> 2 commands
	before=$(logged "$L")
	expect 0 "$tr: N7:0,200" -- "$R" -d "$D" -v N7:0,200
	check "$tr: 200 values" '[ "$(wc -l < "$T/out")" -eq 200 ]'
	check "$tr: value 199" '[ "$(sed -n 200p "$T/out")" = 199 ]'
	same "$tr: N7:0,200 took 2 commands (-v)" "$(sent)" 2
	wait_for "$tr: N7:0,200 in the sim log" 50 log_has "$L" $((before + 2))
	same "$tr: N7:0,200: 2 commands logged" "$(logged "$L")" $((before + 2))

	# operands joined: overlapping and touching ranges of N7, a bit of N7, one more
	# after a gap: one command; T4 whole, a word and a bit of it: one command
	before=$(logged "$L")
	expect 0 "$tr: joined reads" -- "$R" -d "$D" -v N7:0,5 N7:5,5 N7:2 N7:1/1 N7:20 T4:1 T4:1.ACC T4:1/DN
	out_is "$tr: joined values in operand order" "0
1
2
3
4
5
6
7
8
9
2
0
20
EN=1 TT=0 DN=1 PRE=500 ACC=42
42
1"
	same "$tr: joined reads took 2 commands (-v)" "$(sent)" 2
	wait_for "$tr: joined reads in the sim log" 50 log_has "$L" $((before + 2))
	same "$tr: joined reads: 2 commands logged" "$(logged "$L")" $((before + 2))
	check "$tr: one N7 command, 21 elements" 'tail -n 2 "$L" | grep -q "addr=N7:0 count=21"'

	# a gap too wide to join: N7:0 and N7:250 are two small reads, not one of 251
	expect 0 "$tr: wide gap" -- "$R" -d "$D" -v N7:0 N7:250
	same "$tr: wide gap: 2 commands" "$(sent)" 2

	# 30 scattered words N7:0 N7:8 ... N7:232 span 233 words = 466 bytes: two
	# 236-byte packets (doc/PROTOCOL.md 6), where one read per address would be 30
	scat=$(i=0; while [ $i -lt 30 ]; do printf 'N7:%d ' $((i * 8)); i=$((i + 1)); done)
	before=$(logged "$L")
	expect 0 "$tr: 30 scattered" -- "$R" -d "$D" -v $scat
	check "$tr: 30 scattered: 30 values" '[ "$(wc -l < "$T/out")" -eq 30 ]'
	check "$tr: 30 scattered: value 29" '[ "$(sed -n 30p "$T/out")" = 232 ]'
	same "$tr: 30 scattered: 2 commands (-v)" "$(sent)" 2
	wait_for "$tr: 30 scattered in the sim log" 50 log_has "$L" $((before + 2))
	same "$tr: 30 scattered: 2 commands logged" "$(logged "$L")" $((before + 2))

	# PLC error reply: file 20 does not exist -> STS F0, EXT STS 06; exit 1
	expect 1 "$tr: non-existent file" -- "$R" -d "$D" N20:0
	err_has "$tr: PLC error text" "df1read: N20:0: station 1: "
	err_has "$tr: EXT STS shown" "EXT STS 0x06"
	check "$tr: PLC error: stdout empty" '[ ! -s "$T/out" ]'
	# all or nothing: a good read before the failing one prints nothing
	expect 1 "$tr: good then bad" -- "$R" -d "$D" N7:0 N20:0 N7:1
	check "$tr: all or nothing" '[ ! -s "$T/out" ]'
	err_has "$tr: names the bad operand" "df1read: N20:0:"
	# a joined block the PLC refuses: the operand at fault is named
	expect 1 "$tr: past the end of N7" -- "$R" -d "$D" N7:299,2 N7:301
	err_has "$tr: block fallback names N7:301" "df1read: N7:301: station 1:"
	check "$tr: past the end: stdout empty" '[ ! -s "$T/out" ]'
	# the operand is named once: not again inside the library's text, whatever its
	# spelling (lower case, a bit of a word read whole)
	expect 1 "$tr: PLC error, lower case" -- "$R" -d "$D" n20:0
	same "$tr: PLC error: the address once" "$(head -n 1 "$T/err" | grep -o -i "n20:0" | wc -l | tr -d ' ')" 1
	expect 1 "$tr: PLC error, a bit" -- "$R" -d "$D" N20:0/3
	err_has "$tr: PLC error, a bit: named" "df1read: N20:0/3: station 1: DF1_E_REMOTE: PLC error: STS 0xF0"

	# the device from DF1_DEVICE
	expect 0 "$tr: DF1_DEVICE" -- env DF1_DEVICE="$D" "$R" N7:9
	out_is "$tr: DF1_DEVICE value" "9"
	# a network file without Com_Port leaves the device to DF1_DEVICE; one that
	# names Com_Port wins over it
	printf 'Station,Mode,PLC_Type,Baud\n0,Peer,SLC,19200\n' > "$T/net_noport.csv"
	expect 0 "$tr: -N without Com_Port, DF1_DEVICE" -- env DF1_DEVICE="$D" "$R" -N "$T/net_noport.csv" N7:8
	out_is "$tr: -N without Com_Port value" "8"
	printf 'Station,Mode,PLC_Type,Baud,Com_Port\n0,Peer,SLC,19200,%s\n' "$D" > "$T/net_port.csv"
	expect 0 "$tr: -N Com_Port over DF1_DEVICE" -- env DF1_DEVICE="$T/nowhere" "$R" -N "$T/net_port.csv" N7:7
	out_is "$tr: -N Com_Port value" "7"
	sim_stop
done

# ---- full duplex, BCC; a check mismatch is a communication error ----
sim_start bcc --check bcc
expect 0 "full BCC" -- "$R" -d "$SIM_DEV" --check bcc N7:3 F8:2
out_is "full BCC values" "3
2.5"
expect 1 "CRC against a BCC line" -- "$R" -d "$SIM_DEV" -o 200 --nak-retries 0 --enq-retries 1 N7:3
check "mismatch: stdout empty" '[ ! -s "$T/out" ]'
sim_stop

# ---- half duplex, BCC and CRC, several stations ----
sim_start half --duplex half --check bcc --station 1,2,7 --data "$T/data"
H=$SIM_DEV
for st in 1 2 7; do
	expect 0 "half BCC station $st" -- "$R" -d "$H" --duplex half --check bcc -a $st N7:4 ST9:1
	out_is "half BCC station $st values" "4
second"
done
expect 0 "half BCC csv" -- "$R" -d "$H" --duplex half --check bcc -a 2 -f csv N7:300 L10:0
out_is "half BCC csv rows" "address,value
N7:300,42
L10:0,70000"
expect 0 "half BCC N7:0,200" -- "$R" -d "$H" --duplex half --check bcc -a 7 -v N7:0,200
check "half: 200 values" '[ "$(wc -l < "$T/out")" -eq 200 ]'
same "half: N7:0,200 took 2 commands" "$(sent)" 2
# a station nobody answers for: exit 1, the station named
expect 1 "half: unreachable station" -- "$R" -d "$H" --duplex half --check bcc -a 9 -o 200 \
	--nak-retries 1 --enq-retries 1 N7:0
err_has "half: station 9 named" "df1read: N7:0: station 9: ["
check "half: unreachable: stdout empty" '[ ! -s "$T/out" ]'
expect 1 "half: PLC error" -- "$R" -d "$H" --duplex half --check bcc -a 2 N20:0
err_has "half: EXT STS" "EXT STS 0x06"
# the network file: Master = half duplex, BCC, our station 0
printf 'Station,Mode,PLC_Type,Error_Code,Com_Port,Baud\n0,Master,SLC,BCC,%s,19200\n' "$H" > "$T/net.csv"
expect 0 "half: -N network file" -- "$R" -N "$T/net.csv" -a 2 N7:6
out_is "half: -N value" "6"
printf 'Mode,Error_Code,Com_Port\nSlave,BCC,%s\n' "$H" > "$T/slave.csv"
expect 0 "half: -N Mode=Slave with --duplex half" -- "$R" -N "$T/slave.csv" --duplex half -a 2 N7:6
out_is "half: -N Mode=Slave --duplex half value" "6"
sim_stop

sim_start halfcrc --duplex half --station 3
expect 0 "half CRC" -- "$R" -d "$SIM_DEV" --duplex half -a 3 -f json T4:0
out_is "half CRC json" '[
{"address":"T4:0","value":{"EN":0,"TT":0,"DN":0,"PRE":100,"ACC":0}}
]'
sim_stop

# ---- numbers are decimal: "-a 010" is station 10, never octal 8 ----
# Only station 10 answers this half-duplex slave, so a station number read as
# octal (010 = 8) is a read nobody answers, and "08" (no octal 8) is no longer
# refused as a usage error.
sim_start half10 --duplex half --station 10
expect 0 "decimal: -a 010 is station 10" -- "$R" -d "$SIM_DEV" --duplex half -a 010 N7:4
out_is "decimal: -a 010 value" "4"
expect 0 "decimal: hex only with 0x (-a 0x0A)" -- "$R" -d "$SIM_DEV" --duplex half -a 0x0A N7:4
expect 1 "decimal: -a 08 is station 8 (no answer)" -- "$R" -d "$SIM_DEV" --duplex half -a 08 \
	-o 200 --enq-retries 1 N7:4
expect 0 "decimal: df1write -a 010 writes station 10" -- "$BIN/df1write" -d "$SIM_DEV" --duplex half \
	-a 010 N7:3=42
expect 0 "decimal: the write reached station 10" -- "$R" -d "$SIM_DEV" --duplex half -a 10 N7:3
out_is "decimal: station 10 holds it" "42"
sim_stop

# ---- SLC 5/02: 82-byte packets; MicroLogix ----
sim_start slc502 --plc slc502
expect 0 "slc502: N7:0,100" -- "$R" -d "$SIM_DEV" --plc slc502 -v N7:0,100
check "slc502: 100 values" '[ "$(wc -l < "$T/out")" -eq 100 ]'
same "slc502: 100 words in 3 packets" "$(sent)" 3
sim_stop
sim_start ml --plc micrologix --data "$T/data"
expect 0 "micrologix: L" -- "$R" -d "$SIM_DEV" --plc micrologix L10:0,2
out_is "micrologix: L values" "70000
-5"
sim_stop

# ---- no reply in time: [2508] ERR_COMMAND_TIMEOUT, exit 1 ----
sim_start late --delay 2500
expect 1 "reply later than the timeout" -- "$R" -d "$SIM_DEV" -o 500 --cmd-timeout 500 N7:0
err_has "timeout text" "df1read: N7:0: station 1: [2508] ERR_COMMAND_TIMEOUT: "
expect 1 "reply later than the timeout, lower case" -- "$R" -d "$SIM_DEV" -o 500 --cmd-timeout 500 n7:0
out_is "timeout: nothing printed" ""
err_has "timeout, lower case: as typed" "df1read: n7:0: station 1: ["
same "timeout: the address once" "$(grep -o -i "n7:0" "$T/err" | wc -l | tr -d ' ')" 1
check "timeout: stdout empty" '[ ! -s "$T/out" ]'
sim_stop

# ---- Ctrl-C: the port is restored, nothing printed, ended by the signal ----
sim_start slow --delay 3000
before_tty=$(stty -g < "$SIM_DEV" 2>/dev/null)
"$R" -d "$SIM_DEV" -o 10000 N7:0 > "$T/int.out" 2> "$T/int.err" &
rp=$!
# wait until df1read has sent its command (the sim's stderr stays quiet; the
# port's settings change when df1read opens it)
opened() { [ "$(stty -g < "$SIM_DEV" 2>/dev/null)" != "$before_tty" ]; }
if [ -n "$before_tty" ]; then
	wait_for "df1read opened the port" 50 opened
fi
kill -INT "$rp"
{ wait "$rp"; } 2>/dev/null
st=$?
same "SIGINT: ended by the signal" "$st" 130
check "SIGINT: stdout empty" '[ ! -s "$T/int.out" ]'
check "SIGINT: message" 'grep -q "interrupted by SIGINT; nothing printed" "$T/int.err"'
if [ -n "$before_tty" ]; then
	same "SIGINT: port settings restored" "$(stty -g < "$SIM_DEV")" "$before_tty"
fi
sim_stop

# ---- PLC-2 commands (01 read, 08 write, 05 bit write): word offsets into the
# SLC's common interface file N9 (doc/PROTOCOL.md 4.7), which --data creates ----
printf 'N9:0=10,-20,30,0x0101\n' > "$T/n9.data"
sim_start plc2 --data "$T/n9.data"
expect 0 "plc2: read N9 words through 01" -- "$R" -d "$SIM_DEV" --plc plc2 N7:0,4
out_is "plc2: values" "10
-20
30
257"
expect 0 "plc2: write through 08" -- "$BIN/df1write" -d "$SIM_DEV" --plc plc2 N7:1=1234
expect 0 "plc2: bit write through 05" -- "$BIN/df1write" -d "$SIM_DEV" --plc plc2 B3:3/1=1
expect 0 "plc2: the SLC sees them in N9" -- "$R" -d "$SIM_DEV" N9:0,4
out_is "plc2: N9 after the writes" "10
1234
30
259"
sim_stop

finish
