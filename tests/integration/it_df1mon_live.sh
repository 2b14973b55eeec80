#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_df1mon_live - df1mon's live modes against df1sim on pseudo-terminals:
# --counters (alone, with -i/-c, after a transaction, csv/json, Ctrl-C),
# --ping (answered, silent station), --who (half duplex stations, full duplex
# peer), -v/-vv traces, --map wiring, --sniff through a FIFO (the pty side of
# --sniff is tests/unit/df1mon/test_df1mon_sniff.c) with -w and --read of the capture, and
# bad option combinations (exit 2).
# Run from the repository root with DF1_BIN=<build/bin>; bounded waits only,
# no timing assertions.
. tests/support/lib.sh

MON="$BIN/df1mon"
[ -x "$MON" ] || { echo "no $MON"; exit 1; }
unset DF1_DEVICE

# The counter IDs of the seed table, in order.
IDS="2525 2526 2527 2528 2529 2530 2531 2532 2533 2534 2535 2536 2537 2538 2539 2540 2541 2542 2543 2544 2545 2546 2547 2548 2549 2550 2551 2560 2561"
# counter VALUE of ID in file: counter FILE ID
counter() { awk -v id="$2" '$1 == id { v = $3 } END { print v + 0 }' "$1"; }
# the IDs of a plain table, one line
ids_of() { awk 'NF == 3 && $1 ~ /^[0-9]+$/ { printf "%s%s", sep, $1; sep = " " } END { print "" }' "$1"; }

# ---------------------------------------------------------------- full duplex
sim_start fd || finish
FD=$SIM_DEV

expect 0 "--counters alone" -- "$MON" -d "$FD" --counters
cp "$T/out" "$T/cnt"
same "--counters: every ID in order" "$(ids_of "$T/cnt")" "$IDS"
check "--counters: ID MNEMONIC VALUE lines only" \
	'[ "$(grep -c -v "^[0-9][0-9]* [A-Z][A-Z_]* [0-9][0-9]*$" "$T/cnt")" -eq 0 ]'
check "--counters: mnemonics of the seed" \
	'grep -q "^2525 CNT_MSG_PACKETS_SENT " "$T/cnt" && grep -q "^2546 CNT_BCC_ERRORS " "$T/cnt" && grep -q "^2551 CNT_COM_READ_ERRORS " "$T/cnt" && grep -q "^2560 CRD_CHAR_SENT " "$T/cnt" && grep -q "^2561 CRD_CHAR_RECV " "$T/cnt"'
# (the peer answers DLE ENQ with its last response: ACK, or NAK before any message)
check "--counters: the link test's DLE ENQ and its answer are counted" \
	'[ "$(counter "$T/cnt" 2560)" -eq 2 ] && [ "$(counter "$T/cnt" 2561)" -eq 2 ] && [ $(($(counter "$T/cnt" 2536) + $(counter "$T/cnt" 2534))) -eq 1 ]'
check "--counters: nothing failed" '[ "$(counter "$T/cnt" 2545)" -eq 0 ] && [ "$(counter "$T/cnt" 2547)" -eq 0 ]'

# counters after a transaction (the echo of one ping): plausible values
expect 0 "--ping -c 1 --counters" -- "$MON" -d "$FD" --ping -c 1 --counters
grep '^25[0-9][0-9] ' "$T/out" > "$T/cnt"
same "after a transaction: every ID" "$(ids_of "$T/cnt")" "$IDS"
check "after a transaction: one command sent, one reply received" \
	'[ "$(counter "$T/cnt" 2527)" -eq 1 ] && [ "$(counter "$T/cnt" 2530)" -eq 1 ] && [ "$(counter "$T/cnt" 2525)" -ge 1 ]'
check "after a transaction: ACKs both ways, characters both ways" \
	'[ "$(counter "$T/cnt" 2535)" -ge 1 ] && [ "$(counter "$T/cnt" 2536)" -ge 1 ] && [ $(($(counter "$T/cnt" 2536) + $(counter "$T/cnt" 2534))) -ge 2 ] && [ "$(counter "$T/cnt" 2560)" -gt 10 ] && [ "$(counter "$T/cnt" 2561)" -gt 10 ]'
check "after a transaction: no errors" \
	'[ "$(counter "$T/cnt" 2541)" -eq 0 ] && [ "$(counter "$T/cnt" 2545)" -eq 0 ] && [ "$(counter "$T/cnt" 2550)" -eq 0 ]'
check "the ping line comes first" 'head -n 1 "$T/out" | grep -q "^station 1: seq=1 link=[0-9.]* ms echo=[0-9.]* ms (8 bytes)$"'

expect 0 "--counters -f csv" -- "$MON" -d "$FD" --counters -f csv
check "csv: header and 29 rows" \
	'[ "$(head -n 1 "$T/out")" = "t,id,mnemonic,value" ] && [ "$(grep -c "^[0-9.]*,[0-9]*,[A-Z_]*,[0-9]*$" "$T/out")" -eq 29 ]'
expect 0 "--counters -f json" -- "$MON" -d "$FD" --counters -f json
check "json: one object" '[ "$(wc -l < "$T/out")" -eq 1 ] && json_ok "$T/out"'
check "json: every ID" '[ "$(grep -o "\"id\":[0-9]*" "$T/out" | tr -d "\"id:" | tr "\n" " " | sed "s/ $//")" = "$IDS" ]'
check "json: final, with a value" 'grep -q "\"final\":true" "$T/out" && grep -q "{\"id\":2561,\"mnemonic\":\"CRD_CHAR_RECV\",\"value\":[1-9][0-9]*}" "$T/out"'

# -i/-c: a table per interval, separated by blank lines
expect 0 "--counters -i 0.05 -c 3" -- "$MON" -d "$FD" --counters -i 0.05 -c 3
check "three tables" '[ "$(grep -c "^2525 " "$T/out")" -eq 3 ] && [ "$(grep -c "^$" "$T/out")" -eq 2 ]'
check "the link tests add up" '[ "$(grep "^2536 " "$T/out" | tail -n 1 | cut -d" " -f3)" -ge 3 ]'

# Ctrl-C while looping: exit 0, the table printed at exit, port released
"$MON" -d "$FD" --counters -i 0.05 > "$T/loop.out" 2> "$T/loop.err" &
pid=$!
wait_for "--counters loop prints" 100 grep -q "^2561 " "$T/loop.out"
kill -INT "$pid"
lib_reap "$pid"
wait "$pid" 2>/dev/null
rc=$?
same "--counters loop: SIGINT exits 0" "$rc" 0
check "--counters loop: a final table" '[ "$(tail -n 1 "$T/loop.out" | cut -d" " -f1)" = 2561 ]'
check "--counters loop: says it was stopped" 'grep -q "stopped by SIGINT" "$T/loop.err"'
expect 0 "the port is free again after SIGINT" -- "$MON" -d "$FD" --ping -c 1 -q

# ping
expect 0 "--ping -c 3" -- "$MON" -d "$FD" --ping -c 3 -i 0.05
check "ping: three replies" '[ "$(grep -c "^station 1: seq=[123] link=[0-9.]* ms echo=[0-9.]* ms (8 bytes)$" "$T/out")" -eq 3 ]'
check "ping: summary" 'grep -q "^--- station 1: 3 probes sent, 3 answered, 0% loss$" "$T/out" && grep -q "^echo rtt min/avg/max = [0-9.]*/[0-9.]*/[0-9.]* ms$" "$T/out"'
expect 0 "--ping -f json" -- "$MON" -d "$FD" --ping -c 2 -i 0 -f json
check "ping json" 'json_ok "$T/out" && [ "$(grep -c "\"ok\":true" "$T/out")" -eq 2 ] && tail -n 1 "$T/out" | grep -q "\"summary\":true,\"station\":1,\"sent\":2,\"received\":2,\"loss_pct\":0.0"'
expect 0 "--ping -f csv" -- "$MON" -d "$FD" --ping -c 2 -i 0 -f csv
check "ping csv" '[ "$(head -n 1 "$T/out")" = "seq,station,status,link_ms,echo_ms,error" ] && [ "$(grep -c "^[12],1,ok,[0-9.]*,[0-9.]*,$" "$T/out")" -eq 2 ]'

# -v: link events; -vv: every frame, timestamped, on stderr only
expect 0 "--ping -v" -- "$MON" -d "$FD" --ping -c 1 -v
err_has "-v: the port" "$FD open: 19200 8N1, CRC, full duplex"
expect 0 "--ping -vv" -- "$MON" -d "$FD" --ping -c 1 -vv
check "-vv: bytes both ways with times" 'grep -q "^df1mon: [0-9]*\.[0-9]\{6\} tx 10 05$" "$T/err" && grep -q "^df1mon: [0-9]*\.[0-9]\{6\} rx 10 06$" "$T/err"'
check "-vv: decoded echo and its reply" 'grep -q "tx  FRAME  CRC ok .* 06/00  echo" "$T/err" && grep -q "rx  FRAME  CRC ok .* reply to 06/00" "$T/err"'
check "-vv: stdout unchanged" '[ "$(grep -c . "$T/out")" -eq 4 ] && ! grep -q FRAME "$T/out"'
expect 0 "--counters -vv" -- "$MON" -d "$FD" --counters -vv
check "--counters -vv: the link test traced" 'grep -q " tx  ENQ$" "$T/err" && grep -q " rx  ACK$" "$T/err"'

# full duplex --who: the peer, named; a range lists it per DST, with a note
expect 0 "--who (full duplex)" -- "$MON" -d "$FD" --who
out_is "--who: the peer" "station 1: SLC 5/04 series C rev 5 (type 0x5B) mode run"
expect 0 "--who 1-2 (full duplex)" -- "$MON" -d "$FD" --who 1-2
check "full duplex: a peer answers any DST, said so" '[ "$(grep -c "^station [12]: SLC 5/04" "$T/out")" -eq 2 ] && grep -q "point-to-point peer answers whatever the DST" "$T/err"'

# --map is wired to the poll engine's table (-1: one scan)
printf 'Tag,Command,Type,Station,PLC_Type,Address\nlevel,Read,INT,1,SLC,N7:0\n' > "$T/map.csv"
expect 0 "--map -1" -- "$MON" -d "$FD" --map "$T/map.csv" -1
check "--map: the tag" 'grep -q "level" "$T/out"'
sim_stop

# ---------------------------------------------------------------- half duplex
sim_start hd --duplex half --station 2,4 --processor ml1400 || finish
HD=$SIM_DEV
expect 0 "--who 1-5 (half duplex)" -- "$MON" -d "$HD" --duplex half --who 1-5
out_is "--who: exactly 2 and 4, named" "station 2: MicroLogix 1400 series C rev 5 (type 0x9F) mode run
station 4: MicroLogix 1400 series C rev 5 (type 0x9F) mode run"
err_has "--who: summary" "stations 1-5 (half duplex): 2 answered: 2 4"
expect 0 "--who=1-5 -f json" -- "$MON" -d "$HD" --duplex half --who=1-5 -f json
check "who json" 'json_ok "$T/out" && [ "$(grep -c "\"processor\":\"MicroLogix 1400\"" "$T/out")" -eq 2 ] && head -n 1 "$T/out" | grep -q "^{\"station\":2,\"type_code\":\"9F\","'
expect 0 "--who -f csv" -- "$MON" -d "$HD" --duplex half --who 3-4 -f csv
out_is "who csv" "station,type_code,processor,series,revision,mode,mode_text,bulletin,error
4,9F,MicroLogix 1400,C,5,6,run,1766,"
expect 1 "--who with nobody there" -- "$MON" -d "$HD" --duplex half --who 5-6 -o 100
check "nobody: no lines" '[ ! -s "$T/out" ]'
err_has "nobody: summary" "0 answered"
expect 0 "--who --counters" -- "$MON" -d "$HD" --duplex half --who 2 --counters
check "who + counters: polls counted" '[ "$(counter "$T/out" 2531)" -ge 2 ] && [ "$(counter "$T/out" 2538)" -ge 1 ]'
sim_stop

sim_start one --duplex half --station 1 || finish
expect 1 "--ping to a silent station" -- "$MON" -d "$SIM_DEV" --duplex half -a 7 --ping -c 2 -i 0 -o 100
check "silent: two failed probes" '[ "$(grep -c "^station 7: seq=[12] no answer (link): \[2508\] ERR_COMMAND_TIMEOUT" "$T/out")" -eq 2 ]'
check "silent: 100% loss" 'grep -q "^--- station 7: 2 probes sent, 0 answered, 100% loss$" "$T/out"'
expect 0 "--ping the station that is there" -- "$MON" -d "$SIM_DEV" --duplex half -a 1 --ping -c 2 -i 0
sim_stop

# ---------------------------------------------------------------- BCC, TCP
sim_start fbcc --check bcc || finish
expect 0 "--ping, full duplex BCC" -- "$MON" -d "$SIM_DEV" --check bcc --ping -c 1
check "BCC: answered" 'grep -q "^station 1: seq=1 link=" "$T/out"'
expect 1 "--ping, CRC against a BCC line" -- "$MON" -d "$SIM_DEV" --ping -c 1 -o 200 \
	--nak-retries 0 --enq-retries 0
check "CRC against BCC: no answer" 'grep -q "^--- station 1: 1 probe sent, 0 answered, 100% loss$" "$T/out"'
sim_stop
sim_start hbcc --duplex half --check bcc --station 6 || finish
expect 0 "--who, half duplex BCC" -- "$MON" -d "$SIM_DEV" --duplex half --check bcc --who 5-7
out_is "--who, half duplex BCC: station 6" "station 6: SLC 5/04 series C rev 5 (type 0x5B) mode run"
expect 0 "--counters -vv, half duplex BCC" -- "$MON" -d "$SIM_DEV" --duplex half --check bcc -a 6 --counters -vv
check "half duplex -vv: the poll traced" 'grep -q "^df1mon: [0-9]*\.[0-9]\{6\} tx 10 05 06 FA$" "$T/err"'
check "half duplex: a poll counted" '[ "$(counter "$T/out" 2531)" -ge 1 ]'
sim_stop
SIM_TRANSPORT=tcp sim_start tcp || finish
expect 0 "tcp: --ping --counters" -- "$MON" -d "$SIM_DEV" --ping -c 2 -i 0 --counters
check "tcp: two answers" '[ "$(grep -c "^station 1: seq=[12] link=" "$T/out")" -eq 2 ]'
check "tcp: commands counted" '[ "$(counter "$T/out" 2527)" -eq 2 ]'
expect 0 "tcp: --who" -- "$MON" -d "$SIM_DEV" --who
out_is "tcp: --who: the peer" "station 1: SLC 5/04 series C rev 5 (type 0x5B) mode run"
expect 0 "tcp: --ping -vv" -- "$MON" -d "$SIM_DEV" --ping -c 1 -vv
check "tcp: -vv: decoded frames" 'grep -q "tx  FRAME  CRC ok .* 06/00  echo" "$T/err"'
sim_stop

# ---------------------------------------------------------------- network file
expect 2 "-N invalid network file" -- "$MON" -N tests/data/net_invalid.csv --ping
err_has "-N invalid: station" "[2552] CRT_BAD_STATION_ID"
err_has "-N invalid: cmd timeout" "[2559] CRT_BAD_CMD_TIMEOUT"
check "-N invalid: stdout empty" '[ ! -s "$T/out" ]'
printf 'Mode,Com_Port\nSlave,/nonexistent/df1\n' > "$T/slave.csv"
expect 2 "-N Mode=Slave, a mode that transmits" -- "$MON" -N "$T/slave.csv" --ping
err_has "-N Mode=Slave: 2554" "[2554] CRT_UNSUPPORTED_MODE"

# ---------------------------------------------------------------- --sniff, FIFO
# A FIFO stands in for the tap here (the pty version is test_df1mon_sniff).
# Spec 7.3: SLC read F8:0 (split in two writes), ACK, the reply F8:0 = 1.5, ENQ.
mkfifo "$T/tap"
"$MON" --sniff -d "$T/tap" -w "$T/cap.pcap" > "$T/sniff.out" 2> "$T/sniff.err" &
pid=$!
{
	printf '\020\002\001\000\017\000\004\000\242\004'
	sleep 0.1 2>/dev/null || sleep 1
	printf '\010\212\000\000\020\003\264\020\006'
	printf '\020\002\000\001\117\000\004\000\000\000\300\077\020\003\255\020\005'
} > "$T/tap"
lib_reap "$pid"
wait "$pid"
rc=$?
same "sniff: the end of a FIFO ends it, exit 0" "$rc" 0
sed 's/^ *[0-9]* *[0-9.]*  //' "$T/sniff.out" > "$T/sniff.sym"
check "sniff: four symbols" '[ "$(wc -l < "$T/sniff.sym")" -eq 4 ]'
check "sniff: the command" 'sed -n 1p "$T/sniff.sym" | grep -q "^FRAME  BCC ok  dst   1  src   0  tns 0004  0F/A2 .* F8:0 size 4$"'
check "sniff: ACK, reply, ENQ" 'sed -n 2p "$T/sniff.sym" | grep -q "^ACK$" && sed -n 3p "$T/sniff.sym" | grep -q "reply to 0F/A2 .*= 1.5$" && sed -n 4p "$T/sniff.sym" | grep -q "^ENQ$"'
check "sniff: summary" 'grep -q "frames 2 (good 2, bad 0), link symbols 2" "$T/sniff.err" && grep -q "written to $T/cap.pcap" "$T/sniff.err"'
check "pcap: magic and link type 250" '[ "$(od -A n -t x1 -N 24 "$T/cap.pcap" | tr -d " \n")" = "d4c3b2a1020004000000000000000000ffff0000fa000000" ]'
if command -v tshark >/dev/null 2>&1; then
	expect 0 "tshark reads the capture" -- tshark -r "$T/cap.pcap"
	# one record per read of the tap: two or three here, as the chunks arrive
	check "tshark: the records are RTAC serial" '[ "$(grep -c "RTAC Serial" "$T/out")" -ge 2 ]'
fi
expect 0 "--read the capture" -- "$MON" --read "$T/cap.pcap"
sed 's/^ *[0-9]* *[0-9.]*  //' "$T/out" > "$T/read.sym"
check "--read gives the same symbols" 'cmp -s "$T/sniff.sym" "$T/read.sym"'
expect 0 "-f json --read the capture" -- "$MON" -f json --read "$T/cap.pcap"
check "the capture's records carry times" 'json_ok "$T/out" && grep -q "\"epoch\":[0-9]*\.[0-9]*,\"kind\":\"FRAME\"" "$T/out"'

# -c: stop after N frames
"$MON" --sniff -d "$T/tap" -c 1 -q > "$T/sniff.out" 2> "$T/sniff.err" &
pid=$!
printf '\020\002\000\001\117\000\004\000\000\000\300\077\020\003\255\020\002\000\001\117\000\004\000\000\000\300\077\020\003\255' > "$T/tap"
lib_reap "$pid"
wait "$pid"
rc=$?
same "sniff -c 1: exit 0" "$rc" 0
check "sniff -c 1: one frame" '[ "$(grep -c " FRAME " "$T/sniff.out")" -eq 1 ]'

# --duration ends a sniff with its writer still there; -w - puts the pcap on stdout
"$MON" --sniff -d "$T/tap" --duration 0.3 -w - -q > "$T/dur.pcap" 2> "$T/dur.err" &
pid=$!
{ printf '\020\006'; sleep 3; } > "$T/tap" &
writer=$!
lib_reap "$pid"
wait "$pid"
rc=$?
kill "$writer" 2>/dev/null
wait "$writer" 2>/dev/null
same "sniff --duration: exit 0" "$rc" 0
expect 0 "-w - wrote a capture" -- "$MON" --read "$T/dur.pcap"
check "-w -: the ACK" 'grep -q " ACK$" "$T/out"'

# a bad frame seen: exit 1, as --read
"$MON" --sniff -d "$T/tap" -q > "$T/sniff.out" 2> "$T/sniff.err" &
pid=$!
printf '\020\002\000\001\117\000\004\000\000\000\300\077\020\003\256' > "$T/tap"
lib_reap "$pid"
wait "$pid"
rc=$?
same "sniff: a bad BCC exits 1" "$rc" 1
check "sniff: the bad frame shown" 'grep -q "BCC bad expected 0xAD actual 0xAE" "$T/sniff.out"'

# ---------------------------------------------------------------- usage: exit 2
X=/nonexistent/df1
for args in "--ping --who -d $X" \
	"--sniff --counters -d $X" \
	"--ping -w $T/x.pcap -d $X" \
	"--ping --sniff-b $X -d $X" \
	"--sniff -d $X --sniff-b $X" \
	"--who -c 3 -d $X" \
	"--who -i 1 -d $X" \
	"--who 5-2 -d $X" \
	"--who 0-255 -d $X" \
	"--ping -i abc -d $X" \
	"--ping -c -1 -d $X" \
	"--duration 0 --ping -d $X" \
	"--sniff -f csv -d $X" \
	"--read $T/cap.pcap --duration 1" \
	"--decode -c 1 10 06" \
	"--ping --check auto -d $X" \
	"-1 --ping -d $X" \
	"--ping extra -d $X" \
	"--counters" \
	"--sniff" \
	"--map"; do
	# shellcheck disable=SC2086
	expect 2 "usage: $args" -- "$MON" $args
	check "usage: $args: message, no output" '[ -s "$T/err" ] && [ ! -s "$T/out" ]'
done
expect 0 "--help names every mode" -- "$MON" --help
help_has_all() {
	for o in --decode --read --sniff --sniff-b --ping --who --map --counters --interval --count \
		--duration --once --write; do
		grep -q -- "$o" "$T/out" || { echo "  --help lacks $o"; return 1; }
	done
}
check "--help: modes" help_has_all
expect 1 "a device that is not there" -- "$MON" --ping -d "$X"
expect 1 "a tap that is not there" -- "$MON" --sniff -d "$X"

finish
