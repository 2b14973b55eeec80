#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# df1write against df1sim, over pseudo-terminals and TCP: write-then-read-back of
# every type, bit writes that leave the other bits alone, values checked before
# anything is sent (exit 2, nothing in df1sim's --log), the progress report of a
# failure part-way, half and full duplex, BCC and CRC, several stations, elements
# above 254, writes split across packets, SIGTERM part-way.
# Run from the repository root; DF1_BIN = the built tools.
. tests/support/lib.sh
W="$BIN/df1write"
R="$BIN/df1read"
for t in df1write df1read df1sim; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE

cat > "$T/data" <<'EOF'
ST9:0="hello"
L10:0=1
N7:300=0
A11:0=0
EOF

logged() { if [ -f "$1" ]; then wc -l < "$1" | tr -d ' '; else echo 0; fi; }
log_has() { [ "$(logged "$1")" -ge "$2" ]; }
sent() { sed -n 's/.* \([0-9][0-9]*\) commands\{0,1\} sent$/\1/p' "$T/err" | tail -n 1; }
# read back: rb DESC WANT DF1READ-ARGS...
rb() {
	rb_what=$1; rb_want=$2; shift 2
	expect 0 "$rb_what: read back" -- "$R" "$@"
	out_is "$rb_what: value read back" "$rb_want"
}

# ---- usage errors without a device ----
expect 2 "no operand" -- "$W" -d /nonexistent
expect 2 "no '='" -- "$W" -d /nonexistent N7:0
err_has "no '=' message" "expected ADDRESS=VALUE"
expect 2 "bad syntax" -- "$W" -d /nonexistent N7:x=1
err_has "2503" "df1write: N7:x: [2503] ERR_ADDRESS_SYNTAX: Item: 1, Invalid Address Syntax (N7:x)"
expect 2 "out of range" -- "$W" -d /nonexistent N7:0=1 N7:1000=1
err_has "2504" "df1write: N7:1000: [2504] ERR_ADDRESS_RANGE: Item: 2,"
expect 2 "values past element 999" -- "$W" -d /nonexistent N7:999=1,2
err_has "2504 len" "(N7:999, len=2)"
expect 2 "bits past a timer's word" -- "$W" -d /nonexistent T4:0/DN=1,1,1,1
# one 0x prefix, then hex digits (df1_value_parse(3)): refused before the device is opened
expect 2 "a second 0x prefix" -- "$W" -d /nonexistent N7:0=0x0x12
err_has "a second 0x prefix: the value named" "df1write: N7:0: '0x0x12': DF1_E_TYPE"
expect 2 "a negative second 0x prefix" -- "$W" -d /nonexistent N7:0=-0x0x1
expect 2 "no device" -- "$W" N7:0=1
expect 2 "-f csv" -- "$W" -d /nonexistent -f csv N7:0=1
expect 2 "invalid network file" -- "$W" -N tests/data/net_invalid.csv N7:0=1
err_has "invalid network file: 2552" "df1write: tests/data/net_invalid.csv: line 3: [2552] CRT_BAD_STATION_ID"
err_has "invalid network file: 2556" "[2556] CRT_BAD_ERROR_CODE"
expect 0 "--help" -- "$W" --help
check "--help: usage" 'grep -q "^Usage: df1write \[OPTIONS\] ADDRESS=VALUE\[,VALUE\.\.\.\]\.\.\." "$T/out"'
expect 0 "--version" -- "$W" --version
check "--version: the tool's and the library's" 'grep -q "^df1write (libdf1) [0-9]" "$T/out" && grep -q "^library: libdf1 [0-9]" "$T/out"'

for tr in pty tcp; do
	SIM_TRANSPORT=$tr sim_start "w_$tr" --data "$T/data" --log "$T/w_$tr.log" || continue
	D=$SIM_DEV
	L="$T/w_$tr.log"

	# ---- bad values: exit 2, nothing sent, nothing changed ----
	before=$(logged "$L")
	expect 2 "$tr: float into N" -- "$W" -d "$D" N7:0=1 N7:1=1.5
	err_has "$tr: float into N: message" "df1write: N7:1: '1.5': DF1_E_TYPE"
	expect 2 "$tr: 70000 into N" -- "$W" -d "$D" N7:0=70000
	err_has "$tr: 70000: range" "DF1_E_RANGE"
	err_has "$tr: 70000: expected" "-32768..32767"
	expect 2 "$tr: second value bad" -- "$W" -d "$D" N7:0=1,x,3
	err_has "$tr: value 2 named" "value 2 'x'"
	expect 2 "$tr: empty item" -- "$W" -d "$D" N7:0=1,,3
	expect 2 "$tr: empty value" -- "$W" -d "$D" N7:0=
	expect 2 "$tr: 2^31 into L" -- "$W" -d "$D" L10:0=2147483648
	expect 2 "$tr: nan into F" -- "$W" -d "$D" F8:0=nan
	expect 2 "$tr: 1e39 into F" -- "$W" -d "$D" F8:0=1e39
	expect 2 "$tr: bit value 2" -- "$W" -d "$D" B3:0/1=2
	expect 2 "$tr: string of 83" -- "$W" -d "$D" \
		ST9:0=12345678901234567890123456789012345678901234567890123456789012345678901234567890123
	err_has "$tr: string too long" "(83 characters)"
	expect 2 "$tr: unknown timer member" -- "$W" -d "$D" T4:0=PRE=1,FOO=2
	expect 2 "$tr: counter bit on a timer" -- "$W" -d "$D" T4:0=CU=1
	check "$tr: nothing was sent" '[ "$(logged "$L")" -eq "$before" ]'
	rb "$tr: nothing written" "0
1" -d "$D" N7:0,2

	# ---- write, then read back, every type ----
	expect 0 "$tr: every type" -- "$W" -d "$D" N7:0=-5 N7:1=0x7FFF,0xFFFF,32767 L10:0=-70000,2147483647 \
		F8:0=0.1 F8:1=-2e-3 F8:2=3.4028235e+38 F8:3=-inf 'ST9:0=a,b="c" = d' ST9:1= \
		T4:0=PRE=500,ACC=7,EN=1 C5:0="CU=1 DN=1 PRE=10 ACC=3" R6:0=LEN=8,POS=2 \
		N7:300=123 A11:0=0x4142
	check "$tr: silent on success" '[ ! -s "$T/out" ] && [ ! -s "$T/err" ]'
	rb "$tr: N" "-5
32767
-1
32767" -d "$D" N7:0,4
	rb "$tr: L" "-70000
2147483647" -d "$D" L10:0,2
	rb "$tr: F" "0.1
-0.002
3.4028235e+38
-inf" -d "$D" F8:0,4
	expect 0 "$tr: ST csv" -- "$R" -d "$D" -f csv ST9:0,2
	out_is "$tr: ST csv rows" 'address,value
ST9:0,"a,b=""c"" = d"
ST9:1,""'
	rb "$tr: whole T, C, R" "EN=1 TT=0 DN=0 PRE=500 ACC=7
CU=1 CD=0 DN=1 OV=0 UN=0 UA=0 PRE=10 ACC=3
EN=0 EU=0 DN=0 EM=0 ER=0 UL=0 IN=0 FD=0 LEN=8 POS=2" -d "$D" T4:0 C5:0 R6:0
	rb "$tr: above 254" "123" -d "$D" N7:300
	rb "$tr: A" "16706" -d "$D" A11:0

	# a sub-element changes that word only
	expect 0 "$tr: T4:0.PRE" -- "$W" -d "$D" T4:0.PRE=900 C5:0.ACC=-1
	rb "$tr: T4:0.PRE kept the rest" "EN=1 TT=0 DN=0 PRE=900 ACC=7
CU=1 CD=0 DN=1 OV=0 UN=0 UA=0 PRE=10 ACC=-1" -d "$D" T4:0 C5:0

	# ---- a bit write leaves the other bits alone ----
	expect 0 "$tr: bit pattern" -- "$W" -d "$D" N7:10=0x5555 B3:0=0
	before=$(logged "$L")
	expect 0 "$tr: set and clear bits" -- "$W" -d "$D" N7:10/1=1 N7:10/0=0 B3:0/15=1,1,1 T4:0/DN=1
	rb "$tr: N7:10 bits" "21846" -d "$D" N7:10
	rb "$tr: bits across words" "-32768
3" -d "$D" B3:0,2
	rb "$tr: timer bit" "EN=1 TT=0 DN=1 PRE=900 ACC=7" -d "$D" T4:0
	wait_for "$tr: bit writes logged" 50 log_has "$L" $((before + 5))
	check "$tr: bit writes are masked writes (0F/AB)" \
		'[ "$(sed -n "$((before + 1)),\$p" "$L" | head -n 5 | grep -c "cmd=0F/AB")" -eq 5 ]'

	# ---- order: the same element twice, the last one stays ----
	expect 0 "$tr: in order" -- "$W" -d "$D" N7:20=1 N7:20=2
	rb "$tr: last write stays" "2" -d "$D" N7:20

	# ---- a long list, split across packets (234 bytes = 117 words a packet) ----
	vals=$(awk 'BEGIN { for (i = 0; i < 200; i++) printf "%s%d", i ? "," : "", 1000 + i }')
	expect 0 "$tr: 200 values" -- "$W" -d "$D" -v "N7:50=$vals"
	same "$tr: 200 values in 2 commands" "$(sent)" 2
	err_has "$tr: -v: written" "df1write: N7:50: written (200 values)"
	expect 0 "$tr: 200 values read back" -- "$R" -d "$D" N7:50,200
	same "$tr: 200 values" "$(tr '\n' ',' < "$T/out")" "$vals,"

	# ---- failure part-way: valid, valid, a file that does not exist, valid ----
	expect 0 "$tr: reset" -- "$W" -d "$D" N7:0=0,0 F8:1=1.5
	expect 1 "$tr: part-way" -- "$W" -d "$D" N7:0=7 N7:1=8 N20:0=1 F8:1=2
	err_has "$tr: part-way: PLC error" "df1write: N20:0: station 1: "
	err_has "$tr: part-way: EXT STS" "EXT STS 0x06"
	err_has "$tr: part-way: report" "df1write: written: N7:0 N7:1; not written: N20:0 F8:1"
	rb "$tr: part-way: first two written, last not" "7
8
1.5" -d "$D" N7:0,2 F8:1
	expect 1 "$tr: first fails" -- "$W" -d "$D" N20:0=1 N7:0=9
	err_has "$tr: first fails: report" "df1write: written: none; not written: N20:0 N7:0"
	expect 1 "$tr: PLC error, lower case" -- "$W" -d "$D" n20:0=1
	same "$tr: PLC error: the address once" "$(head -n 1 "$T/err" | grep -o -i "n20:0" | wc -l | tr -d ' ')" 1
	expect 1 "$tr: -q keeps errors" -- "$W" -d "$D" -q N20:0=1
	err_has "$tr: -q: report" "not written: N20:0"

	# ---- the device from DF1_DEVICE ----
	expect 0 "$tr: DF1_DEVICE" -- env DF1_DEVICE="$D" "$W" N7:2=-2
	rb "$tr: DF1_DEVICE" "-2" -d "$D" N7:2
	sim_stop
done

# ---- full duplex BCC ----
sim_start bcc --check bcc
expect 0 "BCC write" -- "$W" -d "$SIM_DEV" --check bcc N7:1=11 F8:0=2.25
rb "BCC" "11
2.25" -d "$SIM_DEV" --check bcc N7:1 F8:0
sim_stop

# ---- half duplex: several stations, each with its own data table ----
sim_start half --duplex half --check bcc --station 1,2,5 --data "$T/data"
H=$SIM_DEV
HD="--duplex half --check bcc"
expect 0 "half: write station 2" -- "$W" -d "$H" $HD -a 2 N7:0=222 ST9:0=two B3:0/4=1
expect 0 "half: write station 5" -- "$W" -d "$H" $HD -a 5 N7:0=555 N7:300=5
rb "half: station 2" "222
two
1" -d "$H" $HD -a 2 N7:0 ST9:0 B3:0/4
rb "half: station 5" "555
5" -d "$H" $HD -a 5 N7:0 N7:300
rb "half: station 1 untouched" "0
hello" -d "$H" $HD -a 1 N7:0 ST9:0
# a station nobody answers for: exit 1; the first operand was sent without an
# answer, the second never sent
expect 1 "half: unreachable station" -- "$W" -d "$H" $HD -a 9 -o 200 --nak-retries 1 \
	--enq-retries 1 N7:0=1 N7:1=2
err_has "half: station 9 named" "df1write: N7:0: station 9: ["
err_has "half: unreachable: report" "df1write: written: none; unconfirmed: N7:0; not written: N7:1"
expect 1 "half: PLC error" -- "$W" -d "$H" $HD -a 2 N7:1=5 N20:0=1
err_has "half: PLC error report" "written: N7:1; not written: N20:0"
printf 'Station,Mode,PLC_Type,Error_Code,Com_Port\n0,Master,SLC,BCC,%s\n' "$H" > "$T/net.csv"
expect 0 "half: -N network file" -- "$W" -N "$T/net.csv" -a 5 N7:7=77
rb "half: -N" "77" -d "$H" $HD -a 5 N7:7
sim_stop

sim_start halfcrc --duplex half --station 4 --data "$T/data"
expect 0 "half CRC" -- "$W" -d "$SIM_DEV" --duplex half -a 4 T4:2="EN=1 PRE=3 ACC=1" L10:0=5
rb "half CRC" "EN=1 TT=0 DN=0 PRE=3 ACC=1
5" -d "$SIM_DEV" --duplex half -a 4 T4:2 L10:0
sim_stop

# ---- every try NAKed in full duplex: the station never took it, but the
# library cannot tell that from a half-duplex try without an ACK (taken, the
# ACK lost), so it stays unconfirmed (df1_error_unexecuted(3)); nothing served ----
sim_start naks --nak 100 --log "$T/naks.log"
expect 1 "NAK on every try" -- "$W" -d "$SIM_DEV" --nak-retries 2 N7:0=1 N7:1=2
err_has "NAK: named" "NAK"
err_has "NAK: report" "df1write: written: none; unconfirmed: N7:0; not written: N7:1"
check "NAK: nothing served" '[ ! -s "$T/naks.log" ]'
sim_stop

# ---- SIGTERM part-way: the item under way is unconfirmed, the rest not written ----
sim_start slow --delay 3000
before_tty=$(stty -g < "$SIM_DEV" 2>/dev/null)
"$W" -d "$SIM_DEV" -v -o 10000 N7:0=1 N7:1=2 N7:2=3 > "$T/int.out" 2> "$T/int.err" &
wp=$!
first_done() { grep -q "N7:0: written" "$T/int.err"; }
wait_for "first operand written" 100 first_done
kill -TERM "$wp"
{ wait "$wp"; } 2>/dev/null   # no "Terminated" from the shell
st=$?
same "SIGTERM: ended by the signal" "$st" 143
check "SIGTERM: message" 'grep -q "df1write: N7:1: interrupted by SIGTERM" "$T/int.err"'
check "SIGTERM: report" \
	'grep -q "df1write: written: N7:0; unconfirmed: N7:1; not written: N7:2" "$T/int.err"'
if [ -n "$before_tty" ]; then
	same "SIGTERM: port settings restored" "$(stty -g < "$SIM_DEV")" "$before_tty"
fi
# every other signal that would end it ends it the same way: report, port
# restored, 128 + N (SIGQUIT exits 131 rather than dumping core)
for sg in HUP:129 USR1:138 ALRM:142 QUIT:131; do
	name=${sg%%:*}
	want=${sg#*:}
	: > "$T/int.err"
	"$W" -d "$SIM_DEV" -v -o 10000 N7:0=1 N7:1=2 N7:2=3 > "$T/int.out" 2> "$T/int.err" &
	wp=$!
	wait_for "SIG$name: first operand written" 100 first_done
	kill -s "$name" "$wp"
	{ wait "$wp"; } 2>/dev/null
	st=$?
	same "SIG$name: ended with 128 + N" "$st" "$want"
	check "SIG$name: message" "grep -q 'df1write: N7:1: interrupted by SIG$name' \"\$T/int.err\""
	check "SIG$name: report" \
		'grep -q "df1write: written: N7:0; unconfirmed: N7:1; not written: N7:2" "$T/int.err"'
	if [ -n "$before_tty" ]; then
		same "SIG$name: port settings restored" "$(stty -g < "$SIM_DEV")" "$before_tty"
	fi
done
sim_stop

finish
