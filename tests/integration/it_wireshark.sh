#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_wireshark - the DF1 dissector (contrib/wireshark/df1.lua) under tshark.
#
# Independent expectations: df1mon --read of the same file (field by field, by
# tests/support/wireshark_helper.py compare), the spec's vectors (frames built by the
# helper from tests/data/vectors.txt and from the CRC/BCC rules of doc/PROTOCOL.md 1.4/1.5), and
# the facts of the captures (doc/PROTOCOL.md 7.2). Files:
#   - both serial-tap captures, copied into tests/data (the tree's own files:
#     a bare clone runs this script);
#   - the spec's vectors as RTAC-serial records (BCC, CRC, half duplex);
#   - a built capture: a frame split over three records (inside its DLE
#     stuffing), a corrupted CRC, a NAK, ENQ retries, a duplicate command, a
#     stale reply, an element above 254, T4:0.ACC, a PLC error reply;
#   - random frames of every command libdf1 knows, split at random (seeded);
#   - captures written by `df1mon --sniff -w` of df1read/df1write against
#     df1sim, through a tap (full duplex CRC, half duplex BCC, PLC-5, faults);
#   - raw DF1 over TCP (the port preference; off by default);
#   - the radio modem (the link mode preference): a built capture at a relay,
#     its relayed copies, duplicates and a retry, against the rules and df1mon;
# plus the preferences (RTAC off, Decode As), the personal plugin folder of
# the README's recipe, and make install-wireshark. tshark runs with -2: frames
# cut by a capture's end and links to later replies need the whole file read.
# Skips (exit 0, a SKIP line) without tshark or python3.
. tests/support/lib.sh

if ! command -v tshark >/dev/null 2>&1; then
	echo "SKIP: tshark is not installed (apt-get install tshark): the dissector is not tested"
	finish
fi
if ! command -v python3 >/dev/null 2>&1; then
	echo "SKIP: python3 is not installed: the dissector is not tested"
	finish
fi

LUA=contrib/wireshark/df1.lua
# Lua as root: Debian's init.lua sets run_user_scripts_when_superuser = true
# (CI runs as root); say so clearly if a tshark will not load the script
python3 tests/support/wireshark_helper.py pcap "$T/probe.pcap" "10 06"
if [ "$(env HOME="$T" tshark -X lua_script:$LUA -r "$T/probe.pcap" -T fields -e df1.symbol 2>/dev/null)" != ACK ]; then
	bad "tshark does not load $LUA (Lua disabled, or not run as superuser: see init.lua)"
	finish
fi
H=tests/support/wireshark_helper.py
CAP=tests/data
US=$(printf '\037')
# no personal preferences or plugins of whoever runs the tests
export WIRESHARK_CONFIG_DIR="$T/wsconf"
mkdir -p "$WIRESHARK_CONFIG_DIR"
# nor a df1.lua already in the personal plugin folder (it would load twice):
# tshark runs with HOME=$T/home
mkdir -p "$T/home"

# Debian's init.lua runs Lua scripts as root too (run_user_scripts_when_superuser
# = true): CI runs as root, so say so if that ever changes
tsh() { bounded env HOME="$T/home" tshark -2 -X lua_script:$LUA "$@" 2>> "$T/tshark.err"; }

FIELDS=""
for f in $(python3 $H fields); do FIELDS="$FIELDS -e $f"; done

# same_as_df1mon DESC FILE [TSHARK OPTIONS]: tshark's fields = df1mon -f json --read
# (and $MON_OPTS)
same_as_df1mon() {
	d=$1; file=$2; shift 2
	# shellcheck disable=SC2086
	"$BIN/df1mon" -f json --read "$file" ${MON_OPTS:-} > "$T/mon.json" 2> "$T/mon.err"
	tsh "$@" -r "$file" -T fields -E aggregator="$US" $FIELDS > "$T/ts.tsv"
	if python3 $H compare "$T/mon.json" "$T/ts.tsv" > "$T/cmp.out"; then ok; else
		bad "$d: tshark and df1mon differ"
		head -20 "$T/cmp.out" | sed 's/^/  /'
		tail -3 "$T/tshark.err" | sed 's/^/  tshark: /'
	fi
}

# fields FILE FIELD... [-- [-Y FILTER] TSHARK OPTIONS]: one line per record with
# a DF1 item (or matching FILTER)
fields() {
	file=$1; shift
	e=""
	while [ $# -gt 0 ] && [ "$1" != -- ]; do e="$e -e $1"; shift; done
	[ "$1" = -- ] && shift
	y=df1
	if [ "$1" = -Y ]; then y=$2; shift 2; fi
	tsh "$@" -r "$file" -Y "$y" -T fields -E aggregator=, $e
}

# ---------------------------------------------------------------- the serial-tap captures
C1="$CAP/serial-tap-slc-full-duplex.pcap"
C0="$CAP/serial-tap-one-frame.pcap"
if [ -f "$C1" ] && [ -f "$C0" ]; then
	same_as_df1mon "full-duplex capture" "$C1"
	check "the comparison covered 536 symbols" 'grep -q "^536 symbols compared, 0 differences" "$T/cmp.out"'
	fields "$C1" df1.symbol > "$T/sym"
	# the captures' README: 134 frames, all with a good BCC; ENQ runs after each
	same "134 frames" "$(grep -c '^FRAME$' "$T/sym")" 134
	same "402 ENQ" "$(grep -c '^ENQ$' "$T/sym")" 402
	fields "$C1" df1.check df1.check_ok -- -Y "df1.symbol == \"FRAME\"" > "$T/chk"
	same "every frame BCC, good" "$(sort -u "$T/chk")" "$(printf 'BCC\t1')"
	# doc/PROTOCOL.md 7.2 vectors 14 and 17: the first and the last frame of the file
	fields "$C1" df1.tns df1.cmd df1.fnc df1.addr df1.value -- -Y 'df1.symbol == "FRAME"' > "$T/fr"
	same "first frame: AA write N7:5 = 0x3449" "$(head -1 "$T/fr")" "$(printf '0x3901\t0x0f\t0xaa\tN7:5\t13385')"
	same "last frame: A2 read N7:1" "$(tail -1 "$T/fr")" "$(printf '0x41d5\t0x0f\t0xa2\tN7:1\t')"
	# its first frame is split over records 1 and 2 (README: concatenate them)
	fields "$C1" frame.number df1.reassembled_in df1.fragment -- -c 2 > "$T/split"
	same "frame split over two records" "$(cat "$T/split")" "$(printf '1\t2\t\n2\t\t1,2')"
	fields "$C1" df1.enq_retry df1.enq_for -- -Y 'df1.symbol == "ENQ"' -c 5 > "$T/enq"
	same "ENQ retries count and name the frame" "$(head -3 "$T/enq")" "$(printf '1\t2\n2\t2\n3\t2')"
	check "ENQ retries are expert notes" \
		'[ "$(tsh -r "$C1" -Y df1.expert.enq_retry | wc -l)" -eq 402 ]'
	same_as_df1mon "one-frame capture" "$C0"
	fields "$C0" df1.symbol df1.error_id > "$T/one"
	same "one frame, its end missing: 2518" "$(cat "$T/one")" "$(printf 'ERROR\t2518')"
	# no option: link type 250 is DF1 at once
	# every record of it holds DF1 bytes
	check "-Y df1 without options" \
		'[ "$(bounded env HOME="$T/home" tshark -X lua_script:$LUA -r "$C1" -Y df1 2>/dev/null | wc -l)" -eq "$(bounded env HOME="$T/home" tshark -r "$C1" 2>/dev/null | wc -l)" ]'
else
	bad "the serial-tap captures are missing from $CAP"
fi

# ---------------------------------------------------------------- the spec's vectors
V=tests/data/vectors.txt
grep -v '^#' "$V" | awk -F' [|] ' '$2 == "bcc" && $3 !~ /^10 0[15]/ { print "rx:" $3 }' \
	| python3 $H pcap "$T/vbcc.pcap" -
grep -v '^#' "$V" | awk -F' [|] ' '$2 == "crc" && $3 !~ /^10 01/ { print "tx:" $3 }' \
	| python3 $H pcap "$T/vcrc.pcap" -
grep -v '^#' "$V" | awk -F' [|] ' '($1 ~ /^derived-hd/ && $2 == "crc") || $1 ~ /^derived-hd-poll/ ||
	$1 ~ /^derived-(ack|nak|hd-eot)$/ { print "rx:" $3 }' | python3 $H pcap "$T/vhd.pcap" -
same_as_df1mon "BCC vectors" "$T/vbcc.pcap"
same_as_df1mon "CRC vectors" "$T/vcrc.pcap"
same_as_df1mon "half-duplex vectors" "$T/vhd.pcap"
fields "$T/vcrc.pcap" df1.tns df1.addr df1.size df1.value -- -Y 'df1.tns == 0x0004' > "$T/f8"
same "F8:0 read and its reply = 1.5 (doc/PROTOCOL.md 7.3)" "$(cat "$T/f8")" "$(printf '0x0004\tF8:0\t4\t\n0x0004\tF8:0\t4\t1.5')"
fields "$T/vcrc.pcap" df1.addr df1.value -- -Y 'df1.tns == 0x0006 && df1.reply == 1' > "$T/p5"
same "PLC-5 typed read reply 0..9" "$(cat "$T/p5")" "$(printf 'file 7:0\t0,1,2,3,4,5,6,7,8,9')"
fields "$T/vcrc.pcap" df1.addr -- -Y 'df1.tns == 0x0007' > "$T/asc"
same "logical ASCII address" "$(cat "$T/asc")" '$N7:0'
fields "$T/vcrc.pcap" df1.tns df1.addr df1.check_ok -- -Y 'df1.tns == 0x1010' > "$T/dle"
same "DLE stuffing removed: TNS 1010h, element 10h" "$(cat "$T/dle")" "$(printf '0x1010\tN7:16\t1')"
fields "$T/vcrc.pcap" df1.addr df1.value df1.mask df1.mask_data -- -Y 'df1.fnc == 0xab' > "$T/ab"
same "masked write: B3:0/5 := 1" "$(cat "$T/ab")" "$(printf 'B3:0/5\t1\t2000\t2000')"
fields "$T/vcrc.pcap" df1.sts df1.ext_sts df1.ext_sts_text -- -Y 'df1.sts == 0xf0' > "$T/ext"
same "STS F0, EXT STS 06 with its text" "$(cat "$T/ext")" \
	"$(printf "0xf0\t0x06\taddress doesn't point to something usable")"
# a PLC-3's frames (tests/data/plc3_vectors.txt, doc/PROTOCOL.md 4.2a): its own address text
grep -v '^#' tests/data/plc3_vectors.txt | awk -F' [|] ' '$2 == "crc" { print "tx:" $3 }' \
	| python3 $H pcap "$T/vplc3.pcap" -
same_as_df1mon "PLC-3 vectors" "$T/vplc3.pcap"
fields "$T/vplc3.pcap" df1.fnc df1.addr df1.value -- -Y 'df1.tns == 0x0303' > "$T/p3bit"
same "PLC-3 bit write: an octal bit" "$(head -1 "$T/p3bit")" "$(printf '0x02\tB5:173/15\t1')"
fields "$T/vplc3.pcap" df1.addr df1.value -- -Y 'df1.tns == 0x0305 && df1.reply == 1' > "$T/p3f"
same "PLC-3 float low word first" "$(cat "$T/p3f")" "$(printf 'F2:10\t1.5')"
fields "$T/vplc3.pcap" df1.addr -- -Y 'df1.tns == 0x0304 && df1.reply == 0' > "$T/p3t"
same "PLC-3 timer member" "$(cat "$T/p3t")" "T4.ACC"
fields "$T/vhd.pcap" df1.symbol df1.stn df1.master -- > "$T/hd"
check "polls with their station" 'grep -q "^POLL	1	\$" "$T/hd" && grep -q "^POLL	16	\$" "$T/hd" && grep -q "^POLL	255	\$" "$T/hd"'
check "master messages with STN" 'grep -q "^FRAME	1	1\$" "$T/hd" && grep -q "^FRAME	16	1\$" "$T/hd"'

# ---------------------------------------------------------------- a built capture
# Records (r: the PLC's side, t: the host's). The CRC frames come from the
# helper's own CRC (doc/PROTOCOL.md 1.5); the split one is doc/PROTOCOL.md 7.3's DLE-stuffing vector.
python3 $H pcap "$T/built.pcap" \
	"tx:10 02 01 00 0F 00 10" "tx:10 10 10 A2 02 07 89 10" "tx:10 00 10 03 A2 29" \
	"rx:10 06" \
	"rx:crc:00 01 4F 00 10 10 2A 00" \
	"tx:10 06" \
	"tx:crc:01 00 0F 00 04 00 A2 04 08 8A 00 00" "tx:10 05" "tx:10 05" \
	"rx:10 15" \
	"tx:crc:01 00 0F 00 04 00 A2 04 08 8A 00 00" \
	"rx:10 06" \
	"rx:10 02 00 01 4F 00 04 00 00 00 C0 3F 10 03 35 FC" \
	"tx:10 15" \
	"rx:crc:00 01 4F 00 04 00 00 00 C0 3F" \
	"tx:crc:01 00 0F 00 05 00 A2 02 07 89 FF 2C 01 00" \
	"rx:crc:00 01 4F 00 10 10 2A 00" \
	"rx:crc:00 01 4F 00 05 00 07 00" \
	"tx:crc:01 00 0F 00 06 00 A2 02 04 86 00 02" \
	"rx:crc:00 01 4F 00 06 00 64 00" \
	"tx:crc:01 00 0F 00 07 00 A2 02 07 89 00 00" \
	"rx:crc:00 01 4F 10 07 00"
same_as_df1mon "built capture" "$T/built.pcap"
fields "$T/built.pcap" frame.number df1.reassembled_in df1.fragment df1.tns -- -c 3 > "$T/sp"
same "a frame split over three records is one, on the third" "$(cat "$T/sp")" \
	"$(printf '1\t3\t\t\n2\t3\t\t\n3\t\t1,2,3\t0x1010')"
fields "$T/built.pcap" frame.number df1.check_ok df1.crc df1.check_expected -- -Y 'df1.check_ok == 0' > "$T/bad"
same "the corrupted CRC flagged" "$(cat "$T/bad")" "$(printf '13\t0\t0xfc35\t0xfb35')"
check "as a checksum error" '[ "$(tsh -r "$T/built.pcap" -Y df1.expert.bad_check -T fields -e frame.number)" = 13 ]'
check "NAKs are expert warnings" '[ "$(tsh -r "$T/built.pcap" -Y df1.expert.nak -T fields -e frame.number | tr "\n" " ")" = "10 14 " ]'
fields "$T/built.pcap" frame.number df1.duplicate_of -- -Y df1.expert.duplicate > "$T/dup"
same "the command sent again is a duplicate of the first" "$(cat "$T/dup")" "$(printf '11\t7')"
fields "$T/built.pcap" frame.number df1.request_in df1.value -- -Y 'df1.tns == 0x0004 && df1.reply == 1' > "$T/rq"
# the bad one is not a reply; the good one answers the command's last copy
same "the good reply links to its command" "$(cat "$T/rq")" "$(printf '13\t\t1.5\n15\t11\t1.5')"
check "and shows the response time (records 1.001 s apart)" \
	'[ "$(tsh -r "$T/built.pcap" -Y "frame.number == 15" -T fields -e df1.response_time)" = "4.004000000" ]'
check "the command links to its reply" \
	'[ "$(tsh -r "$T/built.pcap" -Y "frame.number == 11" -T fields -e df1.response_in)" = 15 ]'
fields "$T/built.pcap" frame.number df1.tns -- -Y df1.expert.stale > "$T/stale"
same "an old TNS answered again after newer commands: stale" "$(cat "$T/stale")" "$(printf '17\t0x1010')"
fields "$T/built.pcap" df1.addr df1.element -- -Y 'df1.tns == 0x0005 && df1.reply == 0' > "$T/e300"
same "element above 254 (FF escape)" "$(cat "$T/e300")" "$(printf 'N7:300\t300')"
fields "$T/built.pcap" df1.addr df1.value -- -Y 'df1.tns == 0x0006' > "$T/acc"
same "T4:0.ACC and its word" "$(cat "$T/acc")" "$(printf 'T4:0.ACC\t\nT4:0.ACC\t100')"
fields "$T/built.pcap" df1.sts df1.sts_text -- -Y 'df1.sts == 0x10' > "$T/sts"
same "STS 10 with its text" "$(cat "$T/sts")" "$(printf '0x10\tillegal command or format')"
check "a PLC error status is an expert warning" '[ "$(tsh -r "$T/built.pcap" -Y df1.expert.plc_error | wc -l)" -eq 1 ]'

# random frames of every CMD/FNC, split at random, some corrupted (seeded)
for seed in 1 2; do
	for c in crc bcc; do
		python3 $H random $seed 150 $c | python3 $H pcap "$T/rnd.pcap" -
		same_as_df1mon "random frames, seed $seed, $c" "$T/rnd.pcap"
	done
done

# ---------------------------------------------------------------- df1sim through a tap
# sniff NAME [DF1SIM OPTIONS] -- TOOL COMMANDS (";" separated; LINE is the tap's
# end): df1mon --sniff -w of both directions of the tools' traffic with df1sim
sniff() {
	name=$1; shift
	simopts=""
	while [ "$1" != -- ]; do simopts="$simopts $1"; shift; done
	shift
	sim_start "$name" $simopts || return 1
	rm -f "$T/tx" "$T/rx"
	mkfifo "$T/tx" "$T/rx"
	"$BIN/df1mon" --sniff -d "$T/tx" --sniff-b "$T/rx" -w "$T/$name.pcap" \
		> "$T/$name.sniff" 2> "$T/$name.sniff.err" &
	mon=$!
	# files of this tap only: an earlier one's "ready" must not be read as its own
	python3 $H tap "$T/line" "$SIM_DEV" "$T/tx" "$T/rx" > "$T/$name.tap" 2> "$T/$name.tap.err" &
	tap=$!
	wait_for "$name: the tap" 100 grep -q ready "$T/$name.tap" || { kill $tap $mon; return 1; }
	for c in "$@"; do
		eval "$c" > /dev/null 2>> "$T/$name.tools"
	done
	kill -TERM $tap
	lib_reap $tap
	lib_reap $mon          # the FIFOs' end ends the sniff
	sim_stop
	if grep -q "records written to" "$T/$name.sniff.err" && [ -s "$T/$name.sniff" ]; then ok; else
		bad "$name: no capture"
		cat "$T/$name.sniff.err" "$T/$name.tools" "$T/$name.tap.err" 2>/dev/null | head -10 | sed 's/^/  /'
	fi
}
# long timeouts: the tap and a sanitizer build are slow, and the values are checked
L='-d $T/line -o 3000'
sniff fd -- "\$BIN/df1read $L N7:0,12 F8:0,3 T4:0 C5:0 R6:0 ST9:0 L10:0,2 B3:0/5 T4:0.ACC C5:0/DN" \
	"\$BIN/df1write $L N7:1=-7 N7:16=4112 B3:0/3=1 F8:1=2.5 T4:1.PRE=250 L10:1=-70000" \
	"\$BIN/df1write $L ST9:1=hello" \
	"\$BIN/df1mon $L --ping -c 1 -i 0" "\$BIN/df1mon $L --who 1"
same_as_df1mon "df1sim full duplex CRC" "$T/fd.pcap"
fields "$T/fd.pcap" df1.value -- -Y 'df1.addr == "ST9:1"' > "$T/st"
if grep -q "^hello\$" "$T/st"; then ok; else
	bad "a string written, as written"
	sed 's/^/  /' "$T/st" "$T/fd.tools" | head -10
fi
# df1sim's default processor, as df1mon --who prints it (it_df1mon_live)
fields "$T/fd.pcap" df1.processor -- -Y df1.processor > "$T/proc"
same "diagnostic status: the processor" "$(cat "$T/proc")" "SLC 5/04 series C rev 5 (type 0x5B) mode run"
sniff hd --duplex half --check bcc --station 1,2 -- \
	"\$BIN/df1read $L --duplex half --check bcc N7:0,3 F8:0" \
	"\$BIN/df1read $L --duplex half --check bcc -a 2 N7:1" \
	"\$BIN/df1write $L --duplex half --check bcc N7:2=22"
same_as_df1mon "df1sim half duplex BCC" "$T/hd.pcap"
# a record may hold several symbols (as the tap's reads merge them): ask per station
for n in 1 2; do
	if [ -n "$(tsh -r "$T/hd.pcap" -Y "df1.symbol == \"POLL\" && df1.stn == $n" -T fields -e frame.number)" ]; then
		ok
	else
		bad "half duplex: a poll of station $n"
		sed 's/^/  /' "$T/hd.tools" 2>/dev/null | head -5
	fi
done
sniff p5 --plc plc5 -- "\$BIN/df1read $L --plc plc5 N7:0,4 F8:0 T4:0.ACC B3:0/2" \
	"\$BIN/df1write $L --plc plc5 N7:3=33 B3:0/4=1 F8:2=-1.25"
same_as_df1mon "df1sim PLC-5" "$T/p5.pcap"
check "PLC-5 typed reads and writes seen" '[ -n "$(tsh -r "$T/p5.pcap" -Y "df1.fnc == 0x68 || df1.fnc == 0x67" -T fields -e frame.number)" ]'
sniff flt --corrupt 25 --nak 15 --drop-ack 15 --stale 15 --seed 7 -- \
	"for i in 0 1 2 3 4 5 6 7 8 9; do \$BIN/df1read -d \$T/line -o 300 N7:\$i; \$BIN/df1write -d \$T/line -o 300 N7:\$i=\$i; done"
same_as_df1mon "df1sim with faults" "$T/flt.pcap"
check "faults: bad checks flagged" '[ -n "$(tsh -r "$T/flt.pcap" -Y df1.expert.bad_check -T fields -e frame.number)" ]'
check "faults: NAKs flagged" '[ -n "$(tsh -r "$T/flt.pcap" -Y df1.expert.nak -T fields -e frame.number)" ]'

# ---------------------------------------------------------------- raw DF1 over TCP
python3 $H tcp "$T/tcp.pcap" "c:10 02 01 00 0F 00 04 00 A2" "c:04 08 8A 00 00 10 03 09 C3" \
	"s:10 06" "s:crc:00 01 4F 00 04 00 00 00 C0 3F" "c:10 06"
check "TCP: not DF1 by default" '[ -z "$(tsh -r "$T/tcp.pcap" -Y df1)" ]'
fields "$T/tcp.pcap" frame.number df1.symbol df1.tns df1.value df1.dir df1.request_in -- -o df1.tcp_port:2101 > "$T/tcp"
same "TCP port preference: DF1, a frame split over two segments" "$(cat "$T/tcp")" \
	"$(printf '4\t\t\t\t\t\n5\tFRAME\t0x0004\t\ttx\t\n6\tACK\t\t\trx\t\n7\tFRAME\t0x0004\t1.5\trx\t5\n8\tACK\t\t\ttx\t')"
python3 $H tcp "$T/tcpr.pcap" "c:crc:01 00 0F 00 04 00 A2 04 08 8A 00 00" \
	"cr:crc:01 00 0F 00 04 00 A2 04 08 8A 00 00"
check "TCP: a retransmitted segment is not a second frame" \
	'[ "$(tsh -r "$T/tcpr.pcap" -o df1.tcp_port:2101 -Y "df1.symbol" | wc -l)" -eq 1 ]'
check "TCP: Decode As too" '[ "$(tsh -r "$T/tcp.pcap" -d tcp.port==2101,df1 -Y df1 | wc -l)" -eq 5 ]'

# ---------------------------------------------------------------- preferences
if [ -f "$C1" ]; then
	check "RTAC preference off: no DF1" '[ -z "$(tsh -o df1.rtac:FALSE -r "$C1" -Y df1)" ]'
	fields "$C1" df1.symbol -- -o df1.rtac:FALSE -d rtacser.data=df1 > "$T/da"
	check "then Decode As (RTAC serial data) still works" '[ "$(grep -c "^FRAME\$" "$T/da")" -eq 134 ]'
	fields "$C1" df1.check_ok -- -Y 'df1.symbol == "FRAME"' -o df1.check:CRC > "$T/crc"
	check "check preference CRC: the BCC frames are bad" '[ -n "$(cat "$T/crc")" ] && ! grep -q 1 "$T/crc"'
fi

# ---------------------------------------------------------------- radio modem
# The "Link mode" preference (doc/PROTOCOL.md 2.6): a capture at a relay of a
# radio channel, one frame per record: rx the master's command (1 > 4), tx the
# relay's own copy, rx the next relay's copy (a second copy: a duplicate), a
# stray ACK, rx the reply, tx its copy, tx a new command and tx it again (the
# tx side's retry), a stray ENQ. Expected by the rules, frame by frame; and
# df1mon --duplex radio marks the same frames as copies of the same ones.
RC=$(python3 -c "import sys; sys.path.insert(0, 'tests/support'); import wireshark_helper as h; print(h.frame('crc', bytes.fromhex('04010f00c694a20207890000')).hex())")
RR=$(python3 -c "import sys; sys.path.insert(0, 'tests/support'); import wireshark_helper as h; print(h.frame('crc', bytes.fromhex('01044f00c694d204fbff')).hex())")
RC2=$(python3 -c "import sys; sys.path.insert(0, 'tests/support'); import wireshark_helper as h; print(h.frame('crc', bytes.fromhex('04010f00c795a20207890000')).hex())")
python3 $H pcap "$T/radio.pcap" "rx:$RC" "tx:$RC" "rx:$RC" "rx:1006" "rx:$RR" "tx:$RR" "tx:$RC2" "tx:$RC2" "rx:1005"
RADIO_PREF="df1.link:Radio modem"
fields "$T/radio.pcap" frame.number df1.relay_of df1.radio_repeat df1.radio_duplicate df1.request_in df1.response_in \
	df1.duplicate_of df1.enq_retry -- -o "$RADIO_PREF" | tr '\t' ' ' > "$T/radio.f"
same "radio: relayed copies, duplicates, the retry; the reply answers the first copy; no ENQ retry" \
	"$(tr '\n' ';' < "$T/radio.f")" \
	"1     5  ;2 1  0    ;3 1  1    ;4       ;5    1   ;6 5  0    ;7       ;8  7 1    ;9       ;"
fields "$T/radio.pcap" _ws.expert.message -- -o "$RADIO_PREF" > "$T/radio.ex"
check "radio: the relays' notes, no duplicate command or ENQ retry warnings" \
	"grep -q '^Relayed copy of frame 1 (store and forward, unchanged)\$' '$T/radio.ex' && ! grep -Eq 'ACKs and discards|ENQ retry|NAK:' '$T/radio.ex'"
tsh -o "$RADIO_PREF" -r "$T/radio.pcap" > "$T/radio.info"
check "radio: the Info column names who sent what and the copies" \
	"sed -n 3p '$T/radio.info' | grep -q 'tns 0x94C6 1 > 4 \[relay of frame 1, duplicate\]\$' && sed -n 6p '$T/radio.info' | grep -q '= 1234 -5 tns 0x94C6 4 > 1 \[relay of frame 5\]\$'"
# the same copies as df1mon's (one symbol a record: its symbol number is the frame number)
"$BIN/df1mon" -f json --read "$T/radio.pcap" --duplex radio 2> /dev/null |
	sed -n 's/^{"n":\([0-9]*\),.*"copy_of":\([0-9]*\),.*$/\1 \2/p' > "$T/radio.mon"
same "radio: df1mon --duplex radio marks the same copies" \
	"$(fields "$T/radio.pcap" frame.number df1.relay_of df1.radio_repeat -- -o "$RADIO_PREF" |
		awk -F '\t' '$2 != "" || $3 != "" { print $1, ($2 != "" ? $2 : $3) }' | tr '\n' ';')" \
	"$(tr '\n' ';' < "$T/radio.mon")"
# a DLE ACK inside a frame breaks it on a radio modem (2514, as df1mon reads it)
EMB=$(printf '%s' "$RC" | sed 's/^\(10020401\)/\11006/')
python3 $H pcap "$T/remb.pcap" "rx:$EMB"
same "radio: a DLE ACK inside a frame: an error, no embedded ACK" \
	"$(fields "$T/remb.pcap" df1.symbol df1.error_id -- -o "$RADIO_PREF" | tr '\t\n' ' ;')" "ERROR 2514;"
same "point to point: the embedded ACK and the frame" \
	"$(fields "$T/remb.pcap" df1.symbol | tr '\n' ';')" "ACK,FRAME;"
MON_OPTS="--duplex radio"
same_as_df1mon "radio: a DLE ACK inside a frame, as df1mon --duplex radio" "$T/remb.pcap" -o "$RADIO_PREF"
same_as_df1mon "radio: the relay's capture, as df1mon --duplex radio" "$T/radio.pcap" -o "$RADIO_PREF"
MON_OPTS=
# point to point (the default): the old reading, duplicates as the receiver ACKs them
fields "$T/radio.pcap" frame.number df1.relay_of df1.duplicate_of df1.enq_retry | tr '\t' ' ' > "$T/p2p.f"
same "point to point: no relays; duplicate commands and replies, an ENQ retry" \
	"$(tr '\n' ';' < "$T/p2p.f")" "1   ;2   ;3  1 ;4   ;5   ;6  5 ;7   ;8  7 ;9   1;"

# ---------------------------------------------------------------- the README's recipe
P="$T/home/.local/lib/wireshark/plugins"
mkdir -p "$P"
cp "$LUA" "$P/"
check "personal plugin folder: DF1 with no option" \
	'[ "$(bounded env HOME="$T/home" tshark -r "$T/vbcc.pcap" -Y df1 2>/dev/null | wc -l)" -eq 30 ]'
rm -f "$P/df1.lua"

# ---------------------------------------------------------------- make install-wireshark
MAKE=${MAKE:-make}
unset MAKEFLAGS MFLAGS MAKELEVEL MAKEOVERRIDES
if $MAKE -s install-wireshark DESTDIR="$T/stage" PREFIX=/usr > "$T/inst.log" 2>&1; then
	inst=$(find "$T/stage" -name df1.lua)
	check "installed under lib/.../wireshark/plugins" 'case "$inst" in "$T/stage/usr/lib/"*wireshark/plugins/df1.lua) true;; *) false;; esac'
	check "the same file" 'cmp -s "$inst" "$LUA"'
	$MAKE -s uninstall-wireshark DESTDIR="$T/stage" PREFIX=/usr > "$T/inst.log" 2>&1
	check "uninstalled" '[ -z "$(find "$T/stage" -name df1.lua)" ]'
else
	bad "make install-wireshark failed"
	tail -5 "$T/inst.log"
fi

finish
