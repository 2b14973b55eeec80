#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# The link and PLC settings where the spec leaves a doubt (doc/PROTOCOL.md 8), end to end:
# df1read/df1write against df1sim over pseudo-terminals, each side set to either
# reading. Both readings work when the two sides agree; when they do not, the
# user sees what the man pages say: a BCC error (df1sim's [2507]) and no data for
# --hd-bcc; a tiny denormal (2.2421e-41 for 0.25) for --plc5-float; N7:10's value
# for N7:5, or a refused odd address, for --plc2-addr. PLC-5 typed-read timers,
# counters and controls in the 3- and 5-word forms (--plc5-timer-words): whole
# elements, members, named bits, writes. Expected values come from the --data
# file and the spec, packet counts from df1sim's --log. Bad values: exit 2 naming
# the option and what it takes. Run from the repository root.
. tests/support/lib.sh
R="$BIN/df1read"
W="$BIN/df1write"
M="$BIN/df1mon"
for t in df1read df1write df1mon df1sim; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE

cat > "$T/data" <<'EOF'
T4:1="EN=1 TT=1 DN=1 PRE=100 ACC=42"
C5:0="CU=1 OV=1 PRE=7 ACC=-3"
R6:2="DN=1 LEN=9 POS=4"
F8:3=0.25
N7:5=555
N7:10=1010
N9:5=95
N9:10=910
EOF
logged() { if [ -f "$1" ]; then wc -l < "$1" | tr -d ' '; else echo 0; fi; }
log_has() { [ "$(logged "$1")" -ge "$2" ]; }

# ---- PLC-5 typed-read T/C/R: the 3-word and the 5-word form ----
for words in 3 5; do
	rm -f "$T/t$words.log"
	sim_start "t$words" --plc plc5 --plc5-timer-words "$words" --data "$T/data" --log "$T/t$words.log" || continue
	D=$SIM_DEV
	expect 0 "$words words: T4:1" -- "$R" -d "$D" --plc plc5 T4:1
	out_is "$words words: T4:1 members" "EN=1 TT=1 DN=1 PRE=100 ACC=42"
	expect 0 "$words words: members and bits" -- "$R" -d "$D" --plc plc5 T4:1.ACC T4:1.PRE T4:1/DN T4:1/EN \
		T4:0.ACC,2 C5:0 C5:0/OV C5:0/CD C5:0.PRE R6:2 R6:2.POS R6:2/DN
	out_is "$words words: members and bits values" "42
100
1
1
0
42
CU=1 CD=0 DN=0 OV=1 UN=0 UA=0 PRE=7 ACC=-3
1
0
7
EN=0 EU=0 DN=1 EM=0 ER=0 UL=0 IN=0 FD=0 LEN=9 POS=4
4
1"
	# 40 timers: 38 (3 words) or 23 (5 words, 3 + 5 + 230 = 238) in the first reply
	before=$(logged "$T/t$words.log")
	expect 0 "$words words: 40 timers" -- "$R" -d "$D" --plc plc5 -f csv T4:0,40
	same "$words words: 40 timers, header and rows" "$(wc -l < "$T/out" | tr -d ' ')" 41
	same "$words words: T4:1 in the block" "$(grep '^T4:1,' "$T/out")" 'T4:1,"EN=1 TT=1 DN=1 PRE=100 ACC=42"'
	same "$words words: T4:39 in the block" "$(grep '^T4:39,' "$T/out")" 'T4:39,"EN=0 TT=0 DN=0 PRE=100 ACC=0"'
	wait_for "$words words: two reads logged" 50 log_has "$T/t$words.log" $((before + 2))
	first=$((38))
	[ "$words" = 5 ] && first=23
	check "$words words: the second packet asks for the rest" \
		"grep -q 'addr=T4:0 count=$((40 - first)) ' '$T/t$words.log'"
	# a whole timer written, and read back
	expect 0 "$words words: write a timer" -- "$W" -d "$D" --plc plc5 "T4:2=PRE=500 ACC=5 EN=1"
	expect 0 "$words words: read it back" -- "$R" -d "$D" --plc plc5 T4:2 T4:2.PRE
	out_is "$words words: the timer written" "EN=1 TT=0 DN=0 PRE=500 ACC=5
500"
	# told the PLC sends 5 words, df1read asks for 23 at once
	if [ "$words" = 5 ]; then
		expect 0 "told 5 words: 40 timers" -- "$R" -d "$D" --plc plc5 --plc5-timer-words 5 T4:0,40
		wait_for "told 5 words: logged" 50 log_has "$T/t5.log" $((before + 6))
		check "told 5 words: 23 asked" "grep -q 'addr=T4:0 count=23 ' '$T/t5.log'"
	fi
	sim_stop
done
# df1sim's default for --plc plc5 is the manuals' 5-word timer (59 0A on the wire)
if sim_start tdef --plc plc5 --data "$T/data"; then
	expect 0 "default: T4:1" -- "$R" -vv -d "$SIM_DEV" --plc plc5 T4:1
	out_is "default: T4:1 members" "EN=1 TT=1 DN=1 PRE=100 ACC=42"
	err_has "default: a 5-word timer reply" "99 09 0C 59 0A 00 E0 64 00 2A 00 00 00 00 00"
	sim_stop
fi

# ---- the half-duplex master BCC: STN + data (doc/PROTOCOL.md 2.2's reading), or STX too ----
for bcc in stn stx; do
	sim_start "hd$bcc" --duplex half --check bcc --hd-bcc "$bcc" --data "$T/data" -v || continue
	expect 0 "--hd-bcc $bcc: read" -- "$R" -d "$SIM_DEV" --duplex half --check bcc --hd-bcc "$bcc" N7:5
	out_is "--hd-bcc $bcc: N7:5" "555"
	expect 0 "--hd-bcc $bcc: write" -- "$W" -d "$SIM_DEV" --duplex half --check bcc --hd-bcc "$bcc" N7:6=66
	expect 0 "--hd-bcc $bcc: read back" -- "$R" -d "$SIM_DEV" --duplex half --check bcc --hd-bcc "$bcc" N7:6
	out_is "--hd-bcc $bcc: N7:6" "66"
	# the other reading: the station does not take the frame; no data, exit 1
	other=stx
	[ "$bcc" = stx ] && other=stn
	expect 1 "--hd-bcc $other against $bcc" -- "$R" -d "$SIM_DEV" --duplex half --check bcc \
		--hd-bcc "$other" -o 200 --nak-retries 1 N7:5
	out_is "--hd-bcc $other against $bcc: no data" ""
	err_has "--hd-bcc $other against $bcc: not ACKed" "did not ACK the command"
	wait_for "--hd-bcc $other against $bcc: df1sim reports a bad BCC" 50 \
		grep -q '\[2507\] ERR_BAD_BCC' "$T/hd$bcc.err"
	sim_stop
done
# the doc/PROTOCOL.md 7.3 master message: A8 is STN + data, A6 would include STX
FR="10 01 01 10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03"
expect 0 "decode A8 as stn" -- "$M" --decode --check bcc "$FR A8"
check "decode A8 as stn: BCC ok" "grep -q 'BCC ok' '$T/out'"
expect 1 "decode A6 as stn" -- "$M" --decode --check bcc "$FR A6"
check "decode A6 as stn: BCC bad" "grep -q 'BCC bad expected 0xA8 actual 0xA6' '$T/out'"
expect 0 "decode A6 as stx" -- "$M" --decode --check bcc --hd-bcc stx "$FR A6"
check "decode A6 as stx: BCC ok" "grep -q 'BCC ok' '$T/out'"
# the other decoding options reach df1mon's decoder too
expect 0 "DLE 0F is NAK" -- "$M" --decode "10 0F"
check "DLE 0F is NAK: shown" "grep -q ' NAK' '$T/out'"
expect 1 "--nak-0f no" -- "$M" --decode --nak-0f no "10 0F"
check "--nak-0f no: 2514" "grep -q '2514' '$T/out'"

# ---- PLC-5 typed floats: plain (doc/PROTOCOL.md 5's recommendation) or word-swapped ----
if sim_start fsw --plc plc5 --plc5-float swapped --data "$T/data"; then
	expect 0 "swapped PLC, plain reader" -- "$R" -d "$SIM_DEV" --plc plc5 F8:3
	out_is "swapped PLC, plain reader: what the user sees" "2.2421e-41"
	expect 0 "swapped PLC, swapped reader" -- "$R" -d "$SIM_DEV" --plc plc5 --plc5-float swapped F8:3
	out_is "swapped PLC, swapped reader: 0.25" "0.25"
	expect 0 "swapped write" -- "$W" -d "$SIM_DEV" --plc plc5 --plc5-float swapped F8:4=1.5
	expect 0 "swapped read back" -- "$R" -d "$SIM_DEV" --plc plc5 --plc5-float swapped F8:4
	out_is "swapped read back: 1.5" "1.5"
	# written with the wrong setting, 1.5 is stored as a denormal
	expect 0 "plain write to a swapped PLC" -- "$W" -d "$SIM_DEV" --plc plc5 F8:5=1.5
	expect 0 "plain write: what is stored" -- "$R" -d "$SIM_DEV" --plc plc5 --plc5-float swapped F8:5
	out_is "plain write: 1.5 stored as 2.2869e-41" "2.2869e-41"
	sim_stop
fi
# the old spelling of df1sim's option is the same
if sim_start fsw2 --plc plc5 --plc5-float-swapped --data "$T/data"; then
	expect 0 "--plc5-float-swapped" -- "$R" -d "$SIM_DEV" --plc plc5 --plc5-float swapped F8:3
	out_is "--plc5-float-swapped: 0.25" "0.25"
	sim_stop
fi
if sim_start fpl --plc plc5 --data "$T/data"; then
	expect 0 "plain PLC, swapped reader" -- "$R" -d "$SIM_DEV" --plc plc5 --plc5-float swapped F8:3
	out_is "plain PLC, swapped reader" "2.2421e-41"
	expect 0 "plain PLC, plain reader" -- "$R" -d "$SIM_DEV" --plc plc5 --plc5-float plain F8:3
	out_is "plain PLC, plain reader: 0.25" "0.25"
	sim_stop
fi

# ---- PLC-2 addresses: bytes (2 x element) or words (the element) ----
# MicroLogix: the common interface file is N7 (doc/PROTOCOL.md 4.7)
for unit in bytes words; do
	sim_start "p2$unit" --plc micrologix --plc2-addr "$unit" --data "$T/data" --log "$T/p2$unit.log" || continue
	D=$SIM_DEV
	expect 0 "--plc2-addr $unit: N7:5" -- "$R" -d "$D" --plc plc2 --plc2-addr "$unit" N7:5 N7:10
	out_is "--plc2-addr $unit: N7:5 N7:10" "555
1010"
	expect 0 "--plc2-addr $unit: write N7:7" -- "$W" -d "$D" --plc plc2 --plc2-addr "$unit" N7:7=77,78
	expect 0 "--plc2-addr $unit: N7:7 read as MicroLogix" -- "$R" -d "$D" --plc micrologix N7:7,2
	out_is "--plc2-addr $unit: N7:7 N7:8 written" "77
78"
	if [ "$unit" = words ]; then
		# a reader sending bytes: N7:5 goes as address 10, which is word 10
		expect 0 "bytes against words" -- "$R" -d "$D" --plc plc2 N7:5
		out_is "bytes against words: N7:10's value" "1010"
		# and a write of N7:5 lands on N7:10
		expect 0 "bytes against words: write" -- "$W" -d "$D" --plc plc2 N7:5=4321
		expect 0 "bytes against words: what was written" -- "$R" -d "$D" --plc micrologix N7:5 N7:10
		out_is "bytes against words: N7:10 written, N7:5 not" "555
4321"
		# 05's blocks address bytes: refused before anything is sent
		expect 1 "words: no bit writes" -- "$W" -d "$D" --plc plc2 --plc2-addr words N7:5/1=1
		err_has "words: no bit writes, why" "PLC-2 bit writes (05) address bytes"
	else
		# a reader sending words: N7:5 goes as address 5, odd: refused (STS 10)
		expect 1 "words against bytes" -- "$R" -d "$D" --plc plc2 --plc2-addr words N7:5
		out_is "words against bytes: no data" ""
		err_has "words against bytes: the PLC's error" "STS 0x10"
		expect 0 "words against bytes, even word" -- "$R" -d "$D" --plc plc2 --plc2-addr words N7:10
		out_is "words against bytes: N7:10 gives N7:5's" "555"
	fi
	sim_stop
done
# SLC: the common interface file is N9; the file number of the address is ignored
if sim_start p2slc --plc slc --plc2-addr words --data "$T/data"; then
	expect 0 "SLC words: N7:5 is N9:5" -- "$R" -d "$SIM_DEV" --plc plc2 --plc2-addr words N7:5 N9:10
	out_is "SLC words: N9:5 N9:10" "95
910"
	sim_stop
fi

# ---- the other options reach the handle ----
if sim_start other --data "$T/data" --log "$T/other.log"; then
	D=$SIM_DEV
	# --max-packet 20: 20 words in 2 reads of 10
	expect 0 "--max-packet 20" -- "$R" -d "$D" --max-packet 20 N7:0,20
	same "--max-packet 20: 20 values" "$(wc -l < "$T/out" | tr -d ' ')" 20
	wait_for "--max-packet 20: two reads" 50 log_has "$T/other.log" 2
	check "--max-packet 20: 10 words each" "[ \$(grep -c 'count=10 ' '$T/other.log') -eq 2 ]"
	# --slc-io-codes 82: O0:0 named by type code 82h (F2E), 8Bh by default
	expect 0 "--slc-io-codes 82" -- "$R" -vv -d "$D" --slc-io-codes 82 O0:0
	err_has "--slc-io-codes 82: 82 on the wire" "A2 02 00 82 00 00"
	expect 0 "--slc-io-codes 8b" -- "$R" -vv -d "$D" O0:0
	err_has "--slc-io-codes 8b: 8B on the wire" "A2 02 00 8B 00 00"
	for o in "--duplicate-detect no" "--embedded-responses no" "--nak-0f no" "--eot-bcc yes" "--echo-discard"; do
		# shellcheck disable=SC2086
		expect 0 "$o: a read" -- "$R" -d "$D" $o N7:5
		out_is "$o: N7:5" "555"
	done
	sim_stop
fi

# ---- bad values: exit 2, the option and what it takes, nothing opened ----
bad_value() {     # (expect uses $want itself)
	bv_tool=$1; bv_opt=$2; bv_val=$3; bv_takes=$4
	expect 2 "$bv_tool $bv_opt $bv_val" -- "$BIN/$bv_tool" -d /nonexistent "$bv_opt" "$bv_val" N7:0
	err_has "$bv_tool $bv_opt $bv_val: message" \
		"$bv_tool: $bv_opt: invalid value '$bv_val' (expected $bv_takes)"
}
for tool in df1read df1write; do
	bad_value $tool --hd-bcc both "stn or stx"
	bad_value $tool --plc5-float swap "plain or swapped"
	bad_value $tool --plc5-timer-words 4 "3 or 5"
	bad_value $tool --plc2-addr word "bytes or words"
	bad_value $tool --slc-io-codes 83 "8b or 82"
	bad_value $tool --max-packet 245 "0-244"
	bad_value $tool --duplicate-detect maybe "yes or no"
	bad_value $tool --embedded-responses 2 "yes or no"
	bad_value $tool --nak-0f x "yes or no"
	bad_value $tool --eot-bcc x "yes or no"
done
expect 2 "df1mon --hd-bcc x" -- "$M" --decode --hd-bcc x "10 06"
err_has "df1mon --hd-bcc x: message" "df1mon: --hd-bcc: invalid value 'x' (expected stn or stx)"
expect 2 "df1sim --plc5-timer-words 4" -- "$BIN/df1sim" --pty "$T/never" --plc plc5 --plc5-timer-words 4
err_has "df1sim --plc5-timer-words 4: message" "df1sim: --plc5-timer-words: invalid value '4' (expected 3 or 5)"
expect 2 "df1sim --plc5-timer-words without plc5" -- "$BIN/df1sim" --pty "$T/never" --plc5-timer-words 5
err_has "df1sim --plc5-timer-words without plc5: message" "--plc5-timer-words goes with --plc plc5 only"
expect 2 "df1sim --plc2-addr x" -- "$BIN/df1sim" --pty "$T/never" --plc2-addr x
err_has "df1sim --plc2-addr x: message" "df1sim: --plc2-addr: invalid value 'x' (expected bytes or words)"
check "df1sim made no link" "[ ! -e '$T/never' ]"
# and every option is in --help
for tool in df1read df1write df1mon; do
	expect 0 "$tool --help" -- "$BIN/$tool" --help
	for o in hd-bcc plc5-float plc5-timer-words plc2-addr slc-io-codes max-packet duplicate-detect \
		embedded-responses nak-0f eot-bcc echo-discard; do
		check "$tool --help: --$o" "grep -q -e '--$o' '$T/out'"
	done
done
expect 0 "df1sim --help" -- "$BIN/df1sim" --help
for o in hd-bcc plc5-float plc5-timer-words plc2-addr duplicate-detect embedded-responses nak-0f; do
	check "df1sim --help: --$o" "grep -q -e '--$o' '$T/out'"
done

finish
