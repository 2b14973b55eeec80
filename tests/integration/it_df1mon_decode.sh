#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# df1mon offline modes: --read (pcap, raw dump) and --decode (arguments, stdin).
# Run from the repository root; DF1_BIN is the directory of the built tools.
# Data: tests/data/serial-tap-*.pcap (copies of the shared captures) and
# tests/data/vectors.txt (doc/PROTOCOL.md 7).
. tests/support/lib.sh

MON="$BIN/df1mon"
DATA=tests/data
CAP="$DATA/serial-tap-slc-full-duplex.pcap"
ONE="$DATA/serial-tap-one-frame.pcap"
VEC="$DATA/vectors.txt"

# hex text -> bytes on stdout (POSIX awk and printf only)
hex2bin() {
	fmt=$(printf '%s\n' "$1" | awk '{
		s = toupper($0); gsub(/[^0-9A-F]/, "", s); out = ""
		for (i = 1; i < length(s); i += 2) {
			v = (index("0123456789ABCDEF", substr(s, i, 1)) - 1) * 16 + index("0123456789ABCDEF", substr(s, i + 1, 1)) - 1
			out = out sprintf("\\0%03o", v)
		}
		print out }')
	printf "%b" "$fmt"
}

[ -x "$MON" ] || { echo "no $MON"; exit 1; }
for f in "$CAP" "$ONE" "$VEC"; do [ -f "$f" ] || { echo "missing $f"; exit 1; }; done

# ---- the serial-tap capture: 134 frames, all good BCC, ENQ runs ----
expect 0 "read capture" -- "$MON" --read "$CAP"
cp "$T/out" "$T/cap.txt"
check "134 frames" '[ "$(grep -c " FRAME " "$T/cap.txt")" -eq 134 ]'
check "134 good BCC" '[ "$(grep " FRAME " "$T/cap.txt" | grep -c " BCC ok ")" -eq 134 ]'
check "no bad check" '! grep -q " bad " "$T/cap.txt"'
check "402 ENQ" '[ "$(grep -c " ENQ$" "$T/cap.txt")" -eq 402 ]'
check "summary" 'grep -q "^df1mon: frames 134 (good 134, bad 0), link symbols 402$" "$T/err"'
check "first line: write N7:5 = 13385" \
	'head -n 1 "$T/cap.txt" | grep -q "^ *1 *0\.000000  FRAME  BCC ok .* tns 3901  0F/AA .* N7:5 size 2  = 13385$"'
nw=$(grep -c " 0F/AA " "$T/cap.txt"); nr=$(grep -c " 0F/A2 " "$T/cap.txt")
check "writes and reads add up" '[ $((nw + nr)) -eq 134 ] && [ "$nw" -gt 0 ] && [ "$nr" -gt 0 ]'
check "every write is to N7:5 with a value" '[ "$(grep " 0F/AA " "$T/cap.txt" | grep -c " N7:5 size 2  = -\{0,1\}[0-9][0-9]*$")" -eq "$nw" ]'
check "every read is of N7:1" '[ "$(grep " 0F/A2 " "$T/cap.txt" | grep -c " N7:1 size 2$")" -eq "$nr" ]'
check "ENQ about 1 s after the first frame" 'sed -n 2p "$T/cap.txt" | grep -q "^ *2 *1\.00[0-9]*  ENQ$"'
check "last frame TNS 41D5" 'grep " FRAME " "$T/cap.txt" | tail -n 1 | grep -q "tns 41D5  0F/A2"'

expect 0 "read capture, json" -- "$MON" -f json --read "$CAP"
cp "$T/out" "$T/cap.json"
check "json lines parse" 'json_ok "$T/cap.json"'
check "json 134 frames" '[ "$(grep -c "\"kind\":\"FRAME\"" "$T/cap.json")" -eq 134 ]'
check "json all check_ok" '[ "$(grep -c "\"check\":\"BCC\",\"check_ok\":true" "$T/cap.json")" -eq 134 ]'
check "json first write" 'head -n 1 "$T/cap.json" | grep -q "\"t\":0.000000,.*\"cmd\":\"0F\",\"fnc\":\"AA\",.*\"tns\":\"3901\",\"address\":\"N7:5\",\"size\":2,\"values\":\[13385\]"'
check "json epoch" 'head -n 1 "$T/cap.json" | grep -q "\"epoch\":1539179624\.09[0-9]*"'
check "json ENQ" 'sed -n 2p "$T/cap.json" | grep -q "^{\"n\":2,\"t\":1\.[0-9]*,\"epoch\":[0-9.]*,\"kind\":\"ENQ\"}$"'

# its one record holds a frame without its DLE ETX BCC (the next record has them)
expect 1 "one-record capture" -- "$MON" -q --read "$ONE"
check "one-record: incomplete frame" '[ "$(wc -l < "$T/out")" -eq 1 ] && grep -q "ERROR .*\[2518\] NTC_NO_ETX_RCVD: .*bytes 00 00 0F 00 01 39 AA 02 07 89 05 00 49 34$" "$T/out"'
check "-q: nothing on stderr" '[ ! -s "$T/err" ]'

# the capture from stdin, and with the check forced
expect 0 "capture on stdin" -- sh -c "\"$MON\" -q --read - < \"$CAP\""
check "stdin same output" 'cmp -s "$T/out" "$T/cap.txt"'
expect 1 "capture read as CRC" -- "$MON" -q --check crc --read "$CAP"
check "CRC: bad frames" 'grep -q "CRC bad expected" "$T/out"'

# a truncated capture: what is there is decoded, exit 2
head -c 1000 "$CAP" > "$T/trunc.pcap"
expect 2 "truncated capture" -- "$MON" --read "$T/trunc.pcap"
check "truncated: message" 'grep -q "truncated" "$T/err"'
check "truncated: frames before the cut" 'grep -q " FRAME  BCC ok " "$T/out"'
printf '\012\015\015\012\000\000\000\000' > "$T/ng.pcapng"
expect 2 "pcapng refused" -- "$MON" --read "$T/ng.pcapng"
check "pcapng: says so" 'grep -q "pcapng" "$T/err"'

# ---- --read decodes as it reads (bounded memory, a live pipe) ----
# the offset of the first record header of a pcap at or after byte MIN
# (records: a 16-byte header whose bytes 8-11 are the included length, LE)
rec_at() {
	od -An -v -tu1 "$1" | tr -s ' ' '\n' | grep . | awk -v min="$2" '
		{ b[NR - 1] = $1 }
		END { p = 24
			while (p + 16 <= NR) {
				if (p >= min) { print p; exit }
				p += 16 + b[p + 8] + 256 * b[p + 9] + 65536 * b[p + 10] + 16777216 * b[p + 11]
			} }'
}
# half the capture into a FIFO, cut inside a record header: the frames of that
# half are on df1mon's stdout while the writer still holds the rest
cut=$(( $(rec_at "$CAP" 11000) + 7 ))
mkfifo "$T/live.fifo"
"$MON" --read "$T/live.fifo" > "$T/live.out" 2> "$T/live.err" &
live_pid=$!
echo "$live_pid" >> "$T/.sims"
exec 3> "$T/live.fifo"
head -c "$cut" "$CAP" >&3
wait_for "live pipe: frames shown before the end of the input" 100 grep -q " FRAME  BCC ok " "$T/live.out"
check "live pipe: df1mon still reading" '! grep -q "^df1mon: frames" "$T/live.err"'
tail -c +$((cut + 1)) "$CAP" >&3
exec 3>&-
if wait_for "live pipe: ends at EOF" 100 grep -q "^df1mon: frames" "$T/live.err"; then
	wait "$live_pid"; live_rc=$?
else
	lib_reap "$live_pid"; live_rc=none
fi
same "live pipe: exit status" "$live_rc" 0
check "live pipe: the output of the whole file" 'cmp -s "$T/live.out" "$T/cap.txt"'
check "live pipe: the same summary" 'grep -q "^df1mon: frames 134 (good 134, bad 0), link symbols 402$" "$T/live.err"'
# an ENQ that ends a record, the next record (a second later) starting with
# DLE DLE: the ENQ has its own record's time (0), not the next one's (1 s)
{ head -c 24 "$CAP"
  printf '\001\000\000\000\000\000\000\000\016\000\000\000\016\000\000\000'
  printf '\000\000\000\000\000\000\000\000\002\000\000\000\020\005'
  printf '\002\000\000\000\000\000\000\000\035\000\000\000\035\000\000\000'
  printf '\000\000\000\000\000\000\000\000\002\000\000\000\020\020'
  hex2bin "10 02 00 01 4F 00 04 00 00 00 C0 3F 10 03 AD"; } > "$T/enq-split.pcap"
expect 0 "ENQ at a record's end, DLE DLE after" -- "$MON" --read "$T/enq-split.pcap"
check "ENQ: its record's time" '[ "$(sed -n 1p "$T/out")" = "    1     0.000000  ENQ" ]'
check "the frame: the second record's time" 'sed -n 2p "$T/out" | grep -q "^ *2 *1\.000000  FRAME  BCC ok "'
check "ENQ, DLE DLE, frame: 2 bytes of noise" 'grep -q "link symbols 1, 2 bytes of noise$" "$T/err"'

# the same through a pipe from stdin
expect 0 "capture through a pipe" -- sh -c "cat \"$CAP\" | \"$MON\" -q --read -"
check "pipe: same output" 'cmp -s "$T/out" "$T/cap.txt"'

# a noise byte, then a CRC frame cut after DLE ETX (its check missing): the
# end of the input reports the frame; the noise byte is still counted as noise
hex2bin "02 10 02 00 02 00 49 34 10 03" > "$T/cut-check.raw"
expect 1 "frame cut before its CRC" -- "$MON" --check crc --read "$T/cut-check.raw"
check "cut before its CRC: reported" 'grep -q "ERROR .*\[2518\].*input ended inside a symbol" "$T/out"'
check "cut before its CRC: 1 byte of noise" 'grep -q "errors 1, 1 bytes of noise$" "$T/err"'

# an endless input (a raw dump of zero bytes: all noise) in constant memory;
# watched until 256 MiB are read or it holds 64 MiB (a regression is stopped
# there, before it takes the machine's memory)
"$MON" -q --read /dev/zero > /dev/null 2>&1 &
zero_pid=$!
echo "$zero_pid" >> "$T/.sims"
zero_done() {
	zero_rss=$(awk '/^VmRSS:/ { print $2 }' "/proc/$zero_pid/status" 2>/dev/null)
	zero_read=$(awk '/^rchar:/ { print $2 }' "/proc/$zero_pid/io" 2>/dev/null)
	[ -n "$zero_rss" ] && [ -n "$zero_read" ] && { [ "$zero_read" -gt 268435456 ] || [ "$zero_rss" -gt 65536 ]; }
}
wait_for "/dev/zero: 256 MiB read or 64 MiB held" 600 zero_done
check "/dev/zero: resident size under 32 MiB after 256 MiB (${zero_rss:-?} kB, ${zero_read:-?} bytes read)" \
	'[ "${zero_read:-0}" -gt 268435456 ] && [ "${zero_rss:-99999999}" -lt 32768 ]'
kill -TERM "$zero_pid" 2>/dev/null
lib_reap "$zero_pid"

# truncated captures on a pipe: what is there is decoded, a clear error, exit 2
expect 2 "truncated capture on a pipe" -- sh -c "head -c 1000 \"$CAP\" | \"$MON\" --read -"
check "pipe, cut in a record: names it" 'grep -q "^df1mon: -: record [0-9]* truncated ([0-9]* bytes, [0-9]* in the file)$" "$T/err"'
check "pipe, cut in a record: frames before the cut" 'grep -q " FRAME  BCC ok " "$T/out"'
hdr=$(rec_at "$CAP" 5000)
expect 2 "capture cut in a record header" -- sh -c "head -c $((hdr + 7)) \"$CAP\" | \"$MON\" --read -"
check "cut in a record header: its offset" 'grep -q "^df1mon: -: truncated record header at byte $hdr$" "$T/err"'
# a record that claims 4 GiB: read to the end of the input, never allocated
{ head -c 24 "$CAP"; printf '\001\000\000\000\000\000\000\000\377\377\377\377\377\377\377\377'
  head -c 112 /dev/zero; } > "$T/huge.pcap"
expect 2 "a record of 4 GiB" -- sh -c "cat \"$T/huge.pcap\" | \"$MON\" --read -"
check "a record of 4 GiB: truncated" 'grep -q "^df1mon: -: record 1 truncated (4294967295 bytes, 112 in the file)$" "$T/err"'

# ---- every vector, each with its own check and duplex ----
grep -v '^#' "$VEC" | grep '|' > "$T/vectors"
nvec=0
while IFS='|' read -r name chk hex desc; do
	name=$(echo $name); chk=$(echo $chk)
	case $chk in bcc|crc) ;; *) chk=auto ;; esac
	duplex=full
	case $name in *-hd-*) duplex=half ;; esac
	nvec=$((nvec + 1))
	expect 0 "vector $name ($chk, $duplex)" -- "$MON" -q --check "$chk" --duplex "$duplex" --decode "$hex"
	check "vector $name: one symbol" '[ "$(wc -l < "$T/out")" -eq 1 ]'
	case $chk in
	bcc) check "vector $name: BCC ok" 'grep -q " BCC ok " "$T/out"' ;;
	crc) check "vector $name: CRC ok" 'grep -q " CRC ok " "$T/out"' ;;
	esac
	if [ "$duplex" = full ]; then
		# auto detection finds the same verdict
		expect 0 "vector $name (auto)" -- "$MON" -q --decode "$hex"
		# the last byte changed: a bad check, exit 1
		case $chk in bcc|crc)
			last=$(printf '%s\n' "$hex" | awk '{print $NF}')
			flip=$(printf '%s\n' "$last" | tr '0123456789ABCDEFabcdef' '123456789ABCDEF0bcdef0')
			corrupt=$(printf '%s\n' "$hex" | awk -v f="$flip" '{ $NF = f; print }')
			expect 1 "vector $name corrupted" -- "$MON" -q --check "$chk" --decode "$corrupt"
			check "vector $name corrupted: bad" 'grep -q "$(echo "$chk" | tr a-z A-Z) bad expected 0x" "$T/out"'
			;;
		esac
		# the same bytes as a raw dump
		hex2bin "$hex" > "$T/raw.bin"
		expect 0 "vector $name raw dump" -- "$MON" -q --check "$chk" --read "$T/raw.bin"
	else
		# without --duplex the shape tells a poll or a master message (doc/PROTOCOL.md 2)
		expect 0 "vector $name (auto duplex)" -- "$MON" -q --check "$chk" --decode "$hex"
		check "vector $name (auto duplex): one symbol" '[ "$(wc -l < "$T/out")" -eq 1 ]'
		case $name in
		*-hd-poll-*) check "vector $name (auto duplex): a poll" 'grep -q "^ *1  POLL   BCC ok  stn " "$T/out"' ;;
		*-hd-master-*) check "vector $name (auto duplex): a master message" 'grep -q " FRAME .*(master message to stn [0-9]*)$" "$T/out"' ;;
		esac
	fi
done < "$T/vectors"
check "all vectors seen" '[ "$nvec" -ge 50 ]'

# ---- the duplex reading without --duplex (auto): a poll or a master message by
# its shape (doc/PROTOCOL.md 2.1: DLE ENQ STN BCC, BCC the two's complement of STN, the STN
# stuffed; 2.2: DLE SOH STN DLE STX), else the full-duplex DLE ENQ (doc/PROTOCOL.md 1.3) ----
expect 0 "auto: poll of station 16, STN stuffed" -- "$MON" --decode "10 05 10 10 F0"
out_is "auto: poll of station 16" "    1  POLL   BCC ok  stn  16"
check "auto: poll 16: no noise" 'grep -q "^df1mon: frames 0 (good 0, bad 0), link symbols 1$" "$T/err"'
expect 0 "auto: poll of station 1" -- "$MON" --decode "10 05 01 FF"
out_is "auto: poll of station 1" "    1  POLL   BCC ok  stn   1"
check "auto: poll 1: no noise" 'grep -q "^df1mon: frames 0 (good 0, bad 0), link symbols 1$" "$T/err"'
expect 0 "auto: poll of station 1, json" -- "$MON" -f json --decode "10 05 01 FF"
out_is "auto: poll json" '{"n":1,"kind":"POLL","check":"BCC","check_ok":true,"station":1}'
expect 0 "auto: two polls in one argument" -- "$MON" --decode "10 05 10 10 F0 10 05 02 FE"
check "auto: two polls" '[ "$(grep -c " POLL   BCC ok " "$T/out")" -eq 2 ] && sed -n 2p "$T/out" | grep -q "stn   2$"'
# forced readings
expect 0 "--duplex full: 10 05 01 FF is ENQ and noise" -- "$MON" --duplex full --decode "10 05 01 FF"
out_is "--duplex full: ENQ" "    1  ENQ"
check "--duplex full: 2 bytes of noise" 'grep -q "link symbols 1, 2 bytes of noise$" "$T/err"'
expect 1 "--duplex half: a poll with a bad BCC" -- "$MON" --duplex half --decode "10 05 01 FE"
check "--duplex half: 2507" 'grep -q "ERROR .*\[2507\]" "$T/out"'
# not a poll's shape: the full-duplex ENQ, then what follows read on its own
expect 0 "auto: poll shape with a bad BCC is ENQ and noise" -- "$MON" --decode "10 05 01 FE"
out_is "auto: bad BCC: ENQ" "    1  ENQ"
check "auto: bad BCC: 2 bytes of noise" 'grep -q "link symbols 1, 2 bytes of noise$" "$T/err"'
expect 0 "auto: ENQ alone" -- "$MON" --decode "10 05"
out_is "auto: ENQ alone" "    1  ENQ"
expect 0 "auto: ENQ then ACK" -- "$MON" --decode "10 05 10 06"
check "auto: ENQ then ACK" '[ "$(sed -n 1p "$T/out")" = "    1  ENQ" ] && [ "$(sed -n 2p "$T/out")" = "    2  ACK" ] && [ "$(wc -l < "$T/out")" -eq 2 ]'
expect 0 "auto: ENQ ENQ" -- "$MON" --decode "10 05 10 05"
check "auto: two ENQ" '[ "$(grep -c "^ *[12]  ENQ$" "$T/out")" -eq 2 ]'
reply="10 02 00 01 4F 00 04 00 00 00 C0 3F 10 03 AD"
expect 0 "auto: ENQ then a frame" -- "$MON" --decode "10 05 $reply"
check "auto: ENQ then a frame: ENQ" '[ "$(sed -n 1p "$T/out")" = "    1  ENQ" ]'
check "auto: ENQ then a frame: the frame" 'sed -n 2p "$T/out" | grep -q "^ *2  FRAME  BCC ok  dst   0  src   1  tns 0004  4F "'
check "auto: ENQ then a frame: no error, no noise" 'grep -q "^df1mon: frames 1 (good 1, bad 0), link symbols 1$" "$T/err"'
expect 0 "auto: ENQ, noise, then a frame" -- "$MON" --decode "10 05 33 $reply"
check "auto: ENQ noise frame" '[ "$(sed -n 1p "$T/out")" = "    1  ENQ" ] && sed -n 2p "$T/out" | grep -q " FRAME  BCC ok " && grep -q "link symbols 1, 1 bytes of noise$" "$T/err"'
expect 0 "auto: ENQ, DLE DLE noise, then a frame" -- "$MON" --decode "10 05 10 10 $reply"
check "auto: ENQ DLE DLE frame" '[ "$(sed -n 1p "$T/out")" = "    1  ENQ" ] && sed -n 2p "$T/out" | grep -q " FRAME  BCC ok " && grep -q "link symbols 1, 2 bytes of noise$" "$T/err"'
# the same as a raw dump, and one byte per stdin line (the decoder fed in pieces)
hex2bin "10 05 10 10 F0 10 05 $reply 10 05 01 FF" > "$T/mixed.bin"
expect 0 "auto: raw dump of polls, ENQ and a frame" -- "$MON" --read "$T/mixed.bin"
check "auto: raw dump symbols" '[ "$(grep -c " POLL " "$T/out")" -eq 2 ] && [ "$(grep -c " ENQ$" "$T/out")" -eq 1 ] && [ "$(grep -c " FRAME " "$T/out")" -eq 1 ] && [ "$(wc -l < "$T/out")" -eq 4 ]'
# a half-duplex master message, and a slave's reply after a poll
expect 0 "auto: master message" -- "$MON" --decode "10 01 01 10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03 A8"
check "auto: master message to stn 1" 'grep -q "^ *1  FRAME  BCC ok  dst   1  src   0  tns 0001  0F/A2 .*(master message to stn 1)$" "$T/out"'
expect 0 "auto: poll, then the slave's message" -- "$MON" --decode "10 05 01 FF $reply"
check "auto: poll then message" 'sed -n 1p "$T/out" | grep -q " POLL   BCC ok  stn   1$" && sed -n 2p "$T/out" | grep -q " FRAME  BCC ok  dst   0  src   1 "'
# the full-duplex capture reads the same whatever the duplex setting
expect 0 "capture, --duplex full" -- "$MON" --duplex full --read "$CAP"
check "capture: auto duplex same as full" 'cmp -s "$T/out" "$T/cap.txt"'

# all full-duplex frame vectors on stdin, one per line, with comments and blank lines
{
	echo "# full-duplex frames from vectors.txt"
	echo
	grep -v -e '-hd-' "$T/vectors" | awk -F'|' '{ print $3 "  # " $1 }'
} > "$T/lines"
nlines=$(grep -v -e '-hd-' "$T/vectors" | grep -c .)
expect 0 "stdin lines" -- sh -c "\"$MON\" --decode < \"$T/lines\""
check "stdin: one line per vector" '[ "$(wc -l < "$T/out")" -eq "$nlines" ]'
check "stdin: summary" 'grep -q "^df1mon: frames [0-9]* (good [0-9]*, bad 0), link symbols [0-9]*$" "$T/err"'

# a command and its reply: the reply is decoded with the command's file type
expect 0 "read F8:0 and its reply" -- "$MON" --decode \
	"10 02 01 00 0F 00 04 00 A2 04 08 8A 00 00 10 03 B4" "10 02 00 01 4F 00 04 00 00 00 C0 3F 10 03 AD"
check "reply value 1.5" 'sed -n 2p "$T/out" | grep -q "reply to 0F/A2 .* F8:0 size 4  sts 00 (success, no error)  = 1.5$"'
expect 0 "PLC-5 typed read and reply" -- "$MON" -f json --decode \
	"10 02 01 00 0F 00 06 00 68 00 00 0A 00 06 07 00 0A 00 10 03 61" \
	"10 02 00 01 4F 00 06 00 99 09 15 42 00 00 01 00 02 00 03 00 04 00 05 00 06 00 07 00 08 00 09 00 10 03 84"
check "typed read reply values" 'sed -n 2p "$T/out" | grep -q "\"values\":\[0,1,2,3,4,5,6,7,8,9\]"'
expect 0 "error reply" -- "$MON" -f json --decode "10 02 00 01 4F F0 05 00 06 10 03 B5"
check "error reply texts" 'grep -q "\"sts\":\"F0\",.*\"ext_sts\":\"06\",\"ext_sts_text\":\"address doesn.t point to something usable\"" "$T/out"'
check "error reply json" 'json_ok "$T/out"'

# PLC-5 word range floats are word-swapped (doc/PROTOCOL.md 5: 1.5 is C0 3F 00 00); typed
# write takes the type from its type/data parameter (94 08 = float, 4 bytes)
expect 0 "word range read \$F8:0 and reply" -- "$MON" --decode \
	"10 02 01 00 0F 00 09 00 01 00 00 02 00 00 24 46 38 3A 30 00 04 10 03 D4" \
	"10 02 00 01 4F 00 09 00 C0 3F 00 00 10 03 A8"
check "word range reply: 1.5" 'sed -n 2p "$T/out" | grep -q "reply to 0F/01 .* \$F8:0 size 4  sts 00 (success, no error)  = 1.5$"'
expect 0 "word range write \$F8:0 = 1.5 -2.5" -- "$MON" --decode \
	"10 02 01 00 0F 00 0A 00 00 00 00 04 00 00 24 46 38 3A 30 00 C0 3F 00 00 20 C0 00 00 10 03 F7"
check "word range write values" 'grep -q "0F/00  word range write .* \$F8:0 size 8  = 1.5 -2.5$" "$T/out"'
expect 0 "typed write of two floats" -- "$MON" -f json --decode \
	"10 02 01 00 0F 00 0C 00 67 00 00 02 00 06 08 00 99 09 0A 94 08 00 00 C0 3F 00 00 20 C0 10 03 46"
check "typed write float values" 'grep -q "\"address\":\"file 8:0\",\"size\":2,\"values\":\[1.5,-2.5\]" "$T/out"'

# a masked write of one bit shows the bit address and its value
expect 0 "AB B3:0/5 := 1" -- "$MON" --decode "10 02 01 00 0F 00 03 00 AB 02 03 85 00 00 20 00 20 00 10 03 78"
check "AB: B3:0/5 = 1" 'grep -q "0F/AB  SLC masked write  *B3:0/5 size 2  = 1  mask/data 20 00 / 20 00$" "$T/out"'
expect 0 "AB T4:3/DN := 0 and 26 bit 3 := 1" -- "$MON" -f json --decode \
	"10 02 01 00 0F 00 04 00 AB 02 04 86 03 00 00 20 00 00 10 03 92" \
	"10 02 01 00 0F 00 0A 00 26 06 07 00 FF FF 08 00 10 03 AD"
check "AB: T4:3/DN = 0" 'sed -n 1p "$T/out" | grep -q "\"address\":\"T4:3/DN\",\"size\":2,\"values\":\[0\]"'
check "26: file 7:0/3 = 1" 'sed -n 2p "$T/out" | grep -q "\"address\":\"file 7:0/3\",\"values\":\[1\]"'

# DH-485 EXT STS 1A/1B: the owner's node follows (doc/PROTOCOL.md 3.4)
expect 0 "EXT STS 1A with owner" -- "$MON" --decode "10 02 00 01 4B F0 05 00 1A 07 10 03 9E"
check "owner shown" 'grep -q "sts F0 ext 1A owner 7  error: .*EXT STS 1A: file open by another node (owner: node 7)$" "$T/out"'
expect 0 "EXT STS 1B with owner, json" -- "$MON" -f json --decode "10 02 00 01 4B F0 05 00 1B 03 10 03 A1"
check "owner in json" 'grep -q "\"ext_sts\":\"1B\",\"ext_sts_text\":\"program owned by another node\",\"owner\":3," "$T/out" && json_ok "$T/out"'
# a reply that lacks its EXT STS byte is malformed: exit 1
expect 1 "STS F0 without EXT STS" -- "$MON" --decode "10 02 00 01 4F F0 05 00 10 03 BB"
check "missing EXT STS named" 'grep -q "error: STS F0: .*; DF1_E_BAD_REPLY: invalid reply message$" "$T/out"'

# malformed input: exit 1 with an ERROR line
expect 1 "incomplete frame" -- "$MON" --decode "10 02 01 00 0F 00"
check "incomplete: 2518" 'grep -q "ERROR .*\[2518\] NTC_NO_ETX_RCVD" "$T/out"'
# the input ends on the DLE of a DLE ETX that never came: still the frame's 2518,
# its data as far as it went, and the DLE no noise (it belonged to the frame)
expect 1 "incomplete frame ending on a DLE" -- "$MON" --decode "10 02 01 00 0F 00 01 00 10"
check "ending on a DLE: 2518 with the data" 'grep -q "ERROR .*\[2518\] NTC_NO_ETX_RCVD: .*bytes 01 00 0F 00 01 00$" "$T/out"'
check "ending on a DLE: no noise" 'grep -q "errors 1$" "$T/err"'
# a DLE DLE (a data byte 10) last is no pending DLE: the 10 is in the frame's data
expect 1 "incomplete frame ending on DLE DLE" -- "$MON" --decode "10 02 01 00 10 10"
check "ending on DLE DLE: data 10" 'grep -q "ERROR .*\[2518\] .*bytes 01 00 10$" "$T/out"'
# a lone DLE outside any frame stays noise
expect 0 "a lone DLE" -- "$MON" --decode "10"
check "lone DLE: noise" 'grep -q "1 bytes of noise$" "$T/err"'
expect 1 "invalid symbol" -- "$MON" -f json --decode "10 02 01 00 0F 00 01 00 10 07 10 03 00"
check "invalid symbol: 2514" 'grep -q "\"kind\":\"ERROR\".*\"error_id\":2514" "$T/out" && json_ok "$T/out"'

# usage and input errors: exit 2
expect 2 "bad hex" -- "$MON" --decode "10 02 0G"
check "bad hex: message" 'grep -q "^df1mon: argument 1: bad hex" "$T/err"'
check "bad hex: nothing decoded" '[ ! -s "$T/out" ]'
expect 2 "odd digit count" -- "$MON" --decode "10 0"
expect 2 "bad hex on stdin" -- sh -c "printf '10 06\nzz\n' | \"$MON\" --decode"
check "bad stdin line named" 'grep -q "stdin: line 2: bad hex" "$T/err"'
expect 2 "missing file" -- "$MON" --read "$T/no-such-file.pcap"
check "missing file: message" 'grep -q "^df1mon: .*no-such-file.pcap: No such file or directory$" "$T/err"'
expect 2 "no mode" -- "$MON"
expect 2 "two modes" -- "$MON" --decode --read "$CAP"
expect 2 "bad --check" -- "$MON" --check xyz --decode "10 06"
check "bad --check: names the option" 'grep -q "^df1mon: --check: invalid value .xyz." "$T/err"'
expect 2 "bad --format" -- "$MON" -f xml --decode "10 06"
expect 2 "unknown option" -- "$MON" --bogus
expect 0 "--help" -- "$MON" --help
check "--help on stdout" 'grep -q "^Usage: df1mon" "$T/out" && [ ! -s "$T/err" ]'
expect 0 "--version" -- "$MON" --version
check "--version" 'grep -q "^df1mon (libdf1) [0-9]" "$T/out"'
check "--version: two lines, the second the library's" '[ "$(wc -l < "$T/out")" -eq 2 ] && sed -n 2p "$T/out" | grep -q "^library: libdf1 [0-9][0-9]*\.[0-9][0-9]*\.[0-9][0-9]*$"'

finish
