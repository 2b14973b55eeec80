#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_radio_mon - df1mon's decoding modes with --duplex radio (df1mon(1),
# RADIO MODEM; doc/PROTOCOL.md 2.6): full-duplex frames, no ACK expected,
# and a packet heard again unchanged (a store-and-forward relay's copy, the
# key DST SRC CMD STS TNS among the last 20 packets) marked "relay of #N",
# a further copy "(duplicate)", the tx side's own retry "repeat of #N";
# the radio tallies after the summary. The expectations follow from the
# rules and from the captures built here (frames from app bytes by
# tests/support/wireshark_helper.py, CRC-16 of doc/PROTOCOL.md 1.5):
#  - --decode: a command heard three times, a stray ACK, its reply three
#    times, a frame with a bad CRC; plain and JSON; a DLE ACK inside a frame
#    breaks it (no embedded responses on a radio modem);
#  - --read of an RTAC capture taken at a relay (rx and tx records): its own
#    relayed copies and retries counted as sent; the 20-packet window;
#  - --sniff as one more node of the radio fixture
#    (tests/support/radio_channel.py), hearing the whole AG-UM008 chain
#    master 1 - relay 2 - relay 3 - PLC 4 while df1read reads through it:
#    who sent what (DST/SRC), each relay's copy marked;
#  - --serve as a relay between the master and a PLC: its radio packets at
#    exit (df1_radio_stats): the command and the reply received and relayed.
# Run from the repository root; DF1_BIN = the built tools.
. tests/support/lib.sh
command -v python3 > /dev/null || { skip "python3 missing: no frames built, no radio channel"; finish; }
MON="$BIN/df1mon"
[ -x "$MON" ] || { bad "no $MON"; finish; }
H=tests/support/wireshark_helper.py
# hexf APP: the CRC frame around the app bytes APP, as hex
hexf() { python3 -c "import sys; sys.path.insert(0, 'tests/support'); import wireshark_helper as h; print(h.frame('crc', bytes.fromhex(sys.argv[1])).hex())" "$1"; }
# sym: $T/out without the symbol number and time columns
sym() { sed 's/^ *[0-9]*  *//; s/^[0-9]*\.[0-9]*  //' "$T/out"; }

# a typed read of N7:0, 2 elements, from 1 to 4, and its reply (1234, -5)
CA=04010f00c694a20207890000
RA=01044f00c694d204fbff
C=$(hexf $CA); R=$(hexf $RA)
BADC=$(printf '%s' "$C" | sed 's/..$/00/')   # its CRC's high byte spoiled

# ---- --decode ----
expect 1 "decode: three copies, an ACK, three copies of the reply, a bad frame" -- \
	"$MON" --decode --duplex radio "$C" "$C" "$C" 1006 "$R" "$R" "$R" "$BADC"
sym > "$T/dec.sym"
same "decode: eight symbols" "$(wc -l < "$T/dec.sym")" 8
check "decode: 1 is the command, unmarked" "sed -n 1p '$T/dec.sym' | grep -q '^FRAME  CRC ok  dst   4  src   1  tns 94C6  0F/A2 .*N7:0 size 2\$'"
check "decode: 2 is a relay of #1" "sed -n 2p '$T/dec.sym' | grep -q 'N7:0 size 2  relay of #1\$'"
check "decode: 3 is one more: a duplicate" "sed -n 3p '$T/dec.sym' | grep -q 'N7:0 size 2  relay of #1 (duplicate)\$'"
check "decode: 4, the stray ACK, is shown and no error" "sed -n 4p '$T/dec.sym' | grep -q '^ACK\$'"
check "decode: 5 is the reply, its values" "sed -n 5p '$T/dec.sym' | grep -q 'dst   1  src   4  tns 94C6  4F .*= 1234 -5\$'"
check "decode: 6 and 7, relays of #5" "sed -n 6p '$T/dec.sym' | grep -q '= 1234 -5  relay of #5\$' && sed -n 7p '$T/dec.sym' | grep -q '= 1234 -5  relay of #5 (duplicate)\$'"
check "decode: 8, the bad CRC, no relay" "sed -n 8p '$T/dec.sym' | grep -q '^FRAME  CRC bad' && ! sed -n 8p '$T/dec.sym' | grep -q relay"
err_has "decode: the summary" "frames 7 (good 6, bad 1), link symbols 1"
err_has "decode: the radio tallies" "radio: packets sent 0, received 6, relayed 4, duplicates 2, bad 1"
check "decode: no complaint of a missing ACK" "! grep -Eqi 'missing|no ack|expected ack' '$T/err'"
# a DLE ACK inside a frame: embedded in full duplex, a broken frame on a radio
# modem, where nobody sends one (a node drops the frame)
EMB=$(printf '%s' "$C" | sed 's/^\(10020401\)/\11006/')
expect 1 "decode: a DLE ACK inside a frame" -- "$MON" --decode --duplex radio "$EMB"
check "decode: [2514], no frame, no embedded ACK" "grep -q 'ERROR .*\[2514\]' '$T/out' && ! grep -Eq 'FRAME|ACK' '$T/out'"
err_has "decode: counted a bad packet" "radio: packets sent 0, received 0, relayed 0, duplicates 0, bad 1"
expect 0 "decode: the same in full duplex" -- "$MON" --decode "$EMB"
check "full duplex: the embedded ACK and the frame" "grep -q 'ACK .*(embedded in a frame)' '$T/out' && grep -q 'FRAME  CRC ok' '$T/out'"
expect 0 "decode -f json" -- "$MON" --decode --duplex radio -f json "$C" "$C" "$C"
check "json: the first copy has no copy_of" "sed -n 1p '$T/out' | grep -vq copy_of"
check "json: the relay" "sed -n 2p '$T/out' | grep -q '\"copy_of\":1,\"relay\":true,\"duplicate\":false'"
check "json: the duplicate" "sed -n 3p '$T/out' | grep -q '\"copy_of\":1,\"relay\":true,\"duplicate\":true'"
expect 0 "decode: without --duplex radio nothing is marked" -- "$MON" --decode "$C" "$C"
check "full duplex: no relay marker, no radio line" "! grep -q relay '$T/out' && ! grep -q radio '$T/err'"

# ---- --read: a capture taken at relay 2 (rx: heard, tx: sent by it) ----
C2=$(hexf 04010f00c795a20207890000)
python3 "$H" pcap "$T/r2.pcap" "rx:$C" "tx:$C" "rx:$C" "rx:$R" "tx:$R" "tx:$C2" "tx:$C2"
expect 0 "read: the relay's capture" -- "$MON" --read "$T/r2.pcap" --duplex radio
sym > "$T/r2.sym"
check "read: rx 1, the command" "sed -n 1p '$T/r2.sym' | grep -q '^rx  FRAME .*src   1 .*size 2\$'"
check "read: tx 2, the relay's own copy" "sed -n 2p '$T/r2.sym' | grep -q '^tx  FRAME .*relay of #1\$'"
check "read: rx 3, relay 3's copy heard back: a duplicate" "sed -n 3p '$T/r2.sym' | grep -q '^rx  FRAME .*relay of #1 (duplicate)\$'"
check "read: tx 5, the reply relayed" "sed -n 5p '$T/r2.sym' | grep -q '^tx  FRAME .*relay of #4\$'"
check "read: tx 7, a command sent again by the tx side: a repeat" "sed -n 7p '$T/r2.sym' | grep -q '^tx  FRAME .*tns 95C7 .*repeat of #6 (duplicate)\$'"
err_has "read: the tallies" "radio: packets sent 4, received 3, relayed 3, duplicates 2, bad 0"
# the window: 21 packets (TNS 1..21), then TNS 1 (forgotten: new), TNS 21 (a copy)
: > "$T/win.rec"
for t in $(seq 1 21) 1 21; do
	printf 'rx:%s\n' "$(hexf "$(printf '04010600%02x0000aa' "$t")")" >> "$T/win.rec"
done
python3 "$H" pcap "$T/win.pcap" - < "$T/win.rec"
expect 0 "read: 23 echo packets" -- "$MON" --read "$T/win.pcap" --duplex radio
sym > "$T/win.sym"
check "read: the 22nd (TNS 1 again, 21 packets later) is new" "sed -n 22p '$T/win.sym' | grep -vq relay"
check "read: the 23rd (TNS 21 again) is a relay of #21" "sed -n 23p '$T/win.sym' | grep -q 'relay of #21\$'"

# ---- --sniff: one more node of the radio channel, hearing all ----
if [ -x "$BIN/df1read" ] && [ -x "$BIN/df1sim" ]; then
	radio_start ch --node m,r2,r3,p4,s --link m-r2-r3-p4 --hears s:m,r2,r3,p4 --baud 9600 --keyup-ms 50 || finish
	CH=$RADIO_PID
	printf 'N7:0=1234,-5\n' > "$T/p4.data"
	pids=
	for n in "r2 2 1,3,4" "r3 3 1,2,4" "p4 4 -"; do
		set -- $n
		fw=; [ "$3" != - ] && fw="--forward $3"
		# shellcheck disable=SC2086
		"$BIN/df1sim" -d "$T/ch.$1" --duplex radio --station "$2" $fw --data "$T/p4.data" \
			> "$T/$1.out" 2> "$T/$1.err" &
		echo $! >> "$T/.sims"; pids="$pids $!"
		wait_for "df1sim $1 is up" 100 test -s "$T/$1.out"
	done
	"$MON" --sniff -d "$T/ch.s" --duplex radio -c 6 -v > "$T/sniff.out" 2> "$T/sniff.err" &
	SN=$!
	echo "$SN" >> "$T/.sims"
	wait_for "sniff: listening" 100 grep -q 'sniffing' "$T/sniff.err"
	expect 0 "sniff: df1read through the chain meanwhile" -- \
		"$BIN/df1read" -d "$T/ch.m" --duplex radio -o 3000 --src 1 -a 4 N7:0,2
	out_is "sniff: the read's values" "1234
-5"
	wait_for "sniff: six frames heard, -c 6 ended it" 100 sh -c "! kill -0 $SN 2>/dev/null"
	lib_reap "$SN"
	grep -v '^ *bytes ' "$T/sniff.out" | sed 's/^ *[0-9]* *[0-9.]*  //' > "$T/sniff.sym"
	same "sniff: who sent what, each relay's copy marked" \
		"$(sed 's/^FRAME  CRC ok  dst *\([0-9]*\)  src *\([0-9]*\) .*  \(relay of #[0-9]*\( (duplicate)\)*\)$/\2>\1 \3/; s/^FRAME  CRC ok  dst *\([0-9]*\)  src *\([0-9]*\) .*$/\2>\1/' "$T/sniff.sym" | tr '\n' ';')" \
		"1>4;1>4 relay of #1;1>4 relay of #1 (duplicate);4>1;4>1 relay of #4;4>1 relay of #4 (duplicate);"
	check "sniff: the tallies" "grep -q 'radio: packets sent 0, received 6, relayed 4, duplicates 2, bad 0' '$T/sniff.err'"
	for p in $pids; do sim_stop "$p"; done
	sim_stop "$CH"
else
	bad "no df1read or df1sim in $BIN"
fi

# ---- --serve as a relay on the channel: its packets (df1_radio_stats) ----
# master 1 - df1mon (station 2, forward 1,3) - PLC 3: the command and the
# reply each heard once and relayed once by df1mon; then a write to it
if [ -x "$BIN/df1read" ] && [ -x "$BIN/df1sim" ]; then
	radio_start sv --node m,s2,p3 --link m-s2-p3 --baud 9600 --keyup-ms 50 || finish
	CH=$RADIO_PID
	"$BIN/df1sim" -d "$T/sv.p3" --duplex radio --station 3 --data "$T/p4.data" > "$T/sp3.out" 2> "$T/sp3.err" &
	P3=$!
	echo "$P3" >> "$T/.sims"
	wait_for "df1sim 3 is up" 100 test -s "$T/sp3.out"
	"$MON" -d "$T/sv.s2" --duplex radio --serve N50:0,10 --src 2 --forward 1,3 > "$T/sv.out" 2> "$T/sv.err" &
	SV=$!
	echo "$SV" >> "$T/.sims"
	wait_for "serve: up" 100 grep -q 'serving' "$T/sv.err"
	expect 0 "serve: read PLC 3 through df1mon's relay" -- \
		"$BIN/df1read" -d "$T/sv.m" --duplex radio -o 3000 --src 1 -a 3 N7:0
	out_is "serve: the value" 1234
	sim_stop "$SV"
	check "serve: df1mon relayed the command and the reply, both heard once" \
		"grep -q 'radio: packets sent 2, received 2, relayed 2, duplicates 0, bad 0, undelivered 0\$' '$T/sv.err'"
	sim_stop "$P3"
	sim_stop "$CH"
fi

finish
