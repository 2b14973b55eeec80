#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_poll - df1mon --map (the poll engine's live table, tools/df1mon/mon_map.c) against
# df1sim: one-shot scans in plain, csv and json; exit status 0 when every
# readable tag is GOOD, 1 when one is BAD (a missing file, a silent station),
# 2 for a missing or empty mapping file or one with a row that cannot be used
# (line and item named; --skip-bad-rows polls the rest); --counters adds the counter table; a live csv run has
# one record per tag per scan; on a terminal (script(1)) the table is redrawn
# every scan. Run from the repository root with DF1_BIN=<build/bin>. Skips
# (SKIP, exit 0) when this df1mon was built without --map.
set -u

. tests/support/lib.sh
SIM="$BIN/df1sim"
MON="$BIN/df1mon"

[ -x "$SIM" ] && [ -x "$MON" ] || { echo "FAIL tools not built in $BIN"; exit 1; }
if ! "$MON" --help 2>&1 | grep -q -- '--map'; then
	skip "df1mon has no --map"
	exit 0
fi

cat > "$T/good.csv" <<'EOF'
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
Speed,Read,INT,1,SLC,N7:5,1,500
Levels,Read,FLOAT,1,SLC,F8:0,3,500
Run,Read,BOOL,1,SLC,B3:0/0,1,500
Acc,Read,INT,1,SLC,T4:1.PRE,1,500
Setpoint,Write,INT,1,SLC,N7:100,1,500
EOF
{ cat "$T/good.csv"; echo "Missing,Read,INT,1,SLC,N77:0,1,500"; } > "$T/bad.csv"
{ cat "$T/good.csv"; echo "Far,Read,INT,2,SLC,N7:0,1,500"; } > "$T/silent.csv"
cat > "$T/rows.csv" <<'EOF'
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
Speed,Read,INT,1,SLC,N7:5,1,500
Broken,Read,INT,300,SLC,N7:0,1,500
Syntax,Read,INT,1,SLC,Q7:0,1,500
EOF
printf 'Tag,Command,Type,Station,PLC_Type,Address\nBad,Read,INT,999,SLC,N7:0\n' > "$T/none.csv"
printf 'Tag,Command,Type,Station,PLC_Type,Address\nSpeed,Read,INT,1,SLC,N7:5\nOdd,Read,WORD,1,SLC,N7:6\n' > "$T/type.csv"

sim_run --pty "$T/plc" --duplex half --station 1,2 --silent 2
[ "$SIM_LINE" = "$T/plc" ] || { echo "FAIL df1sim did not start: '$SIM_LINE'"; cat "$T/sim.err"; exit 1; }
D="-d $T/plc --duplex half -o 100"

# 1. plain, one scan, every tag GOOD: exit 0
"$MON" $D --map "$T/good.csv" -1 > "$T/o" 2> "$T/e"
rc=$?
if [ "$rc" -eq 0 ] && grep -q '^Speed .* 5 .*GOOD' "$T/o" && grep -q '^Levels .*0\.5,1\.5,2\.5' "$T/o" \
	&& grep -q '^Acc .*100 .*GOOD' "$T/o" && grep -q '^Setpoint .*write-only' "$T/o" \
	&& grep -q '^scan 1:' "$T/o" && ! grep -q "$(printf '\033')" "$T/o"; then
	ok "plain one-shot: values, qualities, exit 0, no ANSI on a pipe"
else
	bad "plain one-shot (rc=$rc)"; cat "$T/o" "$T/e"
fi

# 2. a tag on a missing file: BAD plc_error, exit 1
"$MON" $D --map "$T/bad.csv" -1 > "$T/o" 2> "$T/e"
rc=$?
if [ "$rc" -eq 1 ] && grep -q '^Missing .*BAD plc_error' "$T/o" && grep -q '^Speed .*GOOD' "$T/o"; then
	ok "bad tag: BAD plc_error, the others GOOD, exit 1"
else
	bad "bad tag (rc=$rc)"; cat "$T/o" "$T/e"
fi

# 3. a silent station: its tag BAD comm_failure after one scan, exit 1
"$MON" $D --map "$T/silent.csv" -1 > "$T/o" 2> "$T/e"
rc=$?
if [ "$rc" -eq 1 ] && grep -q '^Far .*BAD comm_failure' "$T/o" && grep -q '^Speed .*GOOD' "$T/o"; then
	ok "silent station: BAD comm_failure, exit 1"
else
	bad "silent station (rc=$rc)"; cat "$T/o" "$T/e"
fi

# 4. csv: the header, one row per tag
"$MON" $D --map "$T/good.csv" -1 -f csv > "$T/o" 2> "$T/e"
rc=$?
if [ "$rc" -eq 0 ] && [ "$(head -n 1 "$T/o")" = "t,scan,tag,station,address,value,quality,reason,age_ms" ] \
	&& [ "$(grep -c ',1,' "$T/o")" -ge 5 ] && grep -q ',Levels,1,F8:0,0\.5 1\.5 2\.5,GOOD,none,' "$T/o"; then
	ok "csv one-shot"
else
	bad "csv one-shot (rc=$rc)"; cat "$T/o" "$T/e"
fi

# 5. json: one object per tag
"$MON" $D --map "$T/good.csv" -1 -f json > "$T/o" 2> "$T/e"
rc=$?
if [ "$rc" -eq 0 ] && [ "$(wc -l < "$T/o")" -eq 5 ] \
	&& grep -q '"tag":"Levels","station":1,"address":"F8:0","value":\[0.5,1.5,2.5\],"quality":"GOOD"' "$T/o" \
	&& grep -q '"tag":"Setpoint".*"value":null' "$T/o"; then
	ok "json one-shot"
else
	bad "json one-shot (rc=$rc)"; cat "$T/o" "$T/e"
fi

# 6. --counters: the seed counter table and the scan statistics
"$MON" $D --map "$T/good.csv" -1 --counters > "$T/o" 2> "$T/e"
rc=$?
if [ "$rc" -eq 0 ] && grep -q '^2525 CNT_MSG_PACKETS_SENT [1-9]' "$T/o" && grep -q 'transactions per scan' "$T/o"; then
	ok "--counters"
else
	bad "--counters (rc=$rc)"; cat "$T/o" "$T/e"
fi

# 7. a row that cannot be used refuses the file, as df1gw does: exit 2, each
# bad row named by its line and item, nothing polled; --skip-bad-rows polls
# the rest (the rows are still named)
"$MON" $D --map "$T/rows.csv" -1 > "$T/o" 2> "$T/e"
rc=$?
if [ "$rc" -eq 2 ] && grep -q 'rows.csv: line 3: \[2501\]' "$T/e" && grep -q 'rows.csv: line 4: \[2503\]' "$T/e" \
	&& [ ! -s "$T/o" ]; then
	ok "bad rows refuse the file: exit 2, lines and IDs named"
else
	bad "bad rows refuse the file (rc=$rc)"; cat "$T/o" "$T/e"
fi
"$MON" $D --map "$T/type.csv" -1 > "$T/o" 2> "$T/e"
rc=$?
if [ "$rc" -eq 2 ] && grep -q 'type.csv: line 3: .*Type' "$T/e" && [ ! -s "$T/o" ]; then
	ok "an invalid Type refuses the file: exit 2, line 3 and Type named"
else
	bad "invalid Type (rc=$rc)"; cat "$T/o" "$T/e"
fi
"$MON" $D --map "$T/rows.csv" -1 --skip-bad-rows > "$T/o" 2> "$T/e"
rc=$?
if [ "$rc" -eq 0 ] && grep -q '2501' "$T/e" && grep -q '2503' "$T/e" && grep -q '^Speed .*GOOD' "$T/o" \
	&& ! grep -q '^Broken' "$T/o"; then
	ok "--skip-bad-rows: bad rows reported on stderr and skipped, the rest polled"
else
	bad "--skip-bad-rows (rc=$rc)"; cat "$T/o" "$T/e"
fi
"$MON" $D --ping --skip-bad-rows > "$T/o" 2> "$T/e"
rc=$?
if [ "$rc" -eq 2 ] && grep -q -- '--skip-bad-rows needs --map' "$T/e"; then
	ok "--skip-bad-rows without --map: usage error"
else
	bad "--skip-bad-rows without --map (rc=$rc)"; cat "$T/e"
fi

# 8. configuration errors: exit 2
"$MON" $D --map "$T/nonexistent.csv" -1 > "$T/o" 2> "$T/e"
rc=$?
if [ "$rc" -eq 2 ] && [ -s "$T/e" ] && [ ! -s "$T/o" ]; then ok "missing file: exit 2"; else bad "missing file (rc=$rc)"; cat "$T/e"; fi
"$MON" $D --map "$T/none.csv" -1 --skip-bad-rows > "$T/o" 2> "$T/e"
rc=$?
if [ "$rc" -eq 2 ] && grep -q 'no valid tag' "$T/e"; then ok "no valid tag: exit 2"; else bad "no valid tag (rc=$rc)"; cat "$T/e"; fi

# 9. live csv: one record per tag per scan, every scan; SIGINT ends it with 0
sed 's/,500$/,100/' "$T/good.csv" > "$T/fast.csv"
"$MON" $D --map "$T/fast.csv" -f csv > "$T/o" 2> "$T/e" &
mpid=$!
sleep 1.5
kill -s INT "$mpid"
wait "$mpid"
rc=$?
scans=$(awk -F, 'NR > 1 { n[$2]++ } END { bad = 0; for (s in n) { k++; if (n[s] != 5) bad = 1 } print bad ? -1 : k }' "$T/o")
if [ "$rc" -eq 0 ] && [ "$scans" -ge 3 ]; then
	ok "live csv: $scans scans, 5 records each, exit 0 on SIGINT"
else
	bad "live csv (rc=$rc, scans=$scans)"; cat "$T/o" "$T/e"
fi

# 10. on a terminal (script(1) gives df1mon a pty): the table is redrawn every scan
if command -v script > /dev/null 2>&1 && command -v timeout > /dev/null 2>&1 \
	&& script -q -c true /dev/null > /dev/null 2>&1; then
	timeout -s INT 1.5 script -q -c "$MON $D --map $T/fast.csv --counters" /dev/null > "$T/o" 2>&1
	redraws=$(grep -c "$(printf '\033')\[H$(printf '\033')\[2JTAG" "$T/o")
	stats=$(grep -c '^scan [0-9]*: [0-9]* ms, [0-9]* transactions' "$T/o")
	if [ "$redraws" -ge 3 ] && [ "$stats" -eq "$redraws" ] && grep -q '^2525 CNT_MSG_PACKETS_SENT' "$T/o"; then
		ok "terminal: $redraws redraws, each with its scan statistics and counters"
	else
		bad "terminal (redraws=$redraws, stats=$stats)"; cat -v "$T/o" | tail -20
	fi
else
	skip "terminal redraw: no script(1)"
fi

sim_end TERM
finish
