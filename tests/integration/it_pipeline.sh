#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_pipeline - full-duplex pipelining from the tools (--outstanding N, df1sim
# --max-queue N): df1mon --map with --outstanding 4 reads what it reads with 1;
# on a paced line (df1sim --line-baud) the next command goes out before the
# reply to the one before has come (the frame trace shows the order), every
# command is answered once (the frame log); against --max-queue 1 the commands
# beyond the one held are NAKed, retried, and every tag still ends GOOD; the
# one-shot tools take --outstanding too; half duplex reads the same with it;
# out-of-range values are usage errors.
# (The writes under faults: tests/unit/poll/test_pipeline_sim.c, unpaced and on a
# paced line with df1sim as a full-duplex UART and --max-queue 8.) Run from the repository
# root; DF1_BIN = the built tools.
. tests/support/lib.sh
MON="$BIN/df1mon"
R="$BIN/df1read"
for t in df1mon df1read df1sim; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE
if ! "$MON" --help 2>&1 | grep -q -- '--map'; then
	echo "skip: df1mon has no --map"
	exit 0
fi

# blocks of their own: elements far apart, two stations, two files
cat > "$T/map.csv" <<'EOF'
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
A,Read,INT,1,SLC,N7:0,4,0
B,Read,INT,1,SLC,N7:150,2,0
C,Read,FLOAT,1,SLC,F8:0,3,0
D,Read,FLOAT,1,SLC,F8:100,1,0
E,Read,INT,2,SLC,N7:5,1,0
F,Read,INT,2,SLC,N7:200,3,0
G,Read,BOOL,2,SLC,B3:0/1,1,0
EOF
# the table without the age column and the scan summary: values and qualities
table() { grep -v '^scan ' "$T/out" | awk '{ $NF = ""; print }'; }

sim_start plain --station 1,2 --log "$T/plain.log" || exit 1
expect 0 "--outstanding 1: one scan" -- "$MON" -d "$SIM_DEV" --map "$T/map.csv" -1
table > "$T/t1.txt"
expect 0 "--outstanding 4: one scan" -- "$MON" -d "$SIM_DEV" --outstanding 4 --map "$T/map.csv" -1
table > "$T/t4.txt"
same "the same values and qualities" "$(cat "$T/t4.txt")" "$(cat "$T/t1.txt")"
check "every tag GOOD" '[ "$(grep -c " GOOD" "$T/t4.txt")" -eq 7 ]'
check "values from the table" 'grep -q "^A 1 N7:0,4 0,1,2,3 GOOD" "$T/t4.txt" && grep -q "^F 2 N7:200,3 200,201,202 GOOD" "$T/t4.txt"'
# 7 blocks per scan, each answered once per scan: 14 commands in the log
wait_for "the log has both scans" 50 sh -c "[ \$(grep -c 'cmd=0F/A2' '$T/plain.log') -ge 14 ]"
same "each command answered once" "$(grep -c 'cmd=0F/A2' "$T/plain.log")" 14
expect 0 "df1read takes --outstanding" -- "$R" -d "$SIM_DEV" --outstanding 4 N7:3,2
out_is "df1read values" "3
4"
expect 2 "--outstanding 0: usage" -- "$R" -d "$SIM_DEV" --outstanding 0 N7:0
expect 2 "--outstanding 17: usage" -- "$R" -d "$SIM_DEV" --outstanding 17 N7:0
sim_stop

# a paced line: the next command goes while the reply before it is on its way
sim_start paced --station 1,2 --line-baud 9600 --log "$T/paced.log" || exit 1
expect 0 "paced, --outstanding 4" -- "$MON" -vv -d "$SIM_DEV" --outstanding 4 --map "$T/map.csv" -1
table > "$T/tp.txt"
same "paced: the same values" "$(cat "$T/tp.txt")" "$(cat "$T/t1.txt")"
# the decoded frames in order: tx (a command) and rx (a reply) of each TNS
grep -E '^df1mon: +[0-9]+ +[0-9.]+ +(tx|rx) +FRAME' "$T/err" | awk '{ print $4 }' > "$T/dirs"
check "a second command before the first reply" \
	'[ "$(sed -n 2p "$T/dirs")" = tx ] && [ "$(head -n 1 "$T/dirs")" = tx ]'
same "7 commands and 7 replies" "$(grep -c tx "$T/dirs") $(grep -c rx "$T/dirs")" "7 7"
sim_stop

# one command buffer: the extra ones are NAKed and sent again, all end well
sim_start one --station 1,2 --max-queue 1 --log "$T/one.log" || exit 1
expect 0 "--max-queue 1, --outstanding 4" -- "$MON" -d "$SIM_DEV" --outstanding 4 --map "$T/map.csv" -1
table > "$T/tq.txt"
same "--max-queue 1: the same values" "$(cat "$T/tq.txt")" "$(cat "$T/t1.txt")"
wait_for "the log has every block" 50 sh -c "[ \$(grep -c 'cmd=0F/A2' '$T/one.log') -ge 7 ]"
same "--max-queue 1: each command answered once" "$(grep -c 'cmd=0F/A2' "$T/one.log")" 7
expect 0 "--max-queue 1: the counters" -- "$MON" -d "$SIM_DEV" --outstanding 4 --map "$T/map.csv" \
	-1 --counters
check "NAKs received and retried" \
	'grep -q "^2534 CNT_NAKS_RCVD [1-9]" "$T/out" && grep -q "^2541 CNT_NAK_RETRIES [1-9]" "$T/out"'
check "no NAK limit reached" 'grep -q "^2542 CNT_NAK_LIMIT_EXCEEDED 0" "$T/out"'
check "every tag GOOD" '[ "$(grep -c " GOOD" "$T/out")" -eq 7 ]'
sim_stop

# half duplex: one message per poll, the option changes nothing
sim_start half --duplex half --station 1,2 --log "$T/half.log" || exit 1
expect 0 "half duplex, --outstanding 4" -- "$MON" -d "$SIM_DEV" --duplex half --outstanding 4 \
	--map "$T/map.csv" -1
table > "$T/th.txt"
same "half duplex: the same values" "$(cat "$T/th.txt")" "$(cat "$T/t1.txt")"
sim_stop

expect 2 "df1sim --max-queue 9: usage" -- "$BIN/df1sim" --pty "$T/x" --max-queue 9
finish
