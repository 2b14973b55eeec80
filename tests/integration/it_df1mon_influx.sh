#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_df1mon_influx - df1mon --map -f influx against df1sim on a pseudo-terminal:
# every readable tag one InfluxDB line per scan, read back with an independent
# line-protocol parser (tests/support/influx_parse.py) and compared with the
# values df1sim was given (--data): integer, float, bit, array, timer, string
# and long fields with their line-protocol types; names that need escaping or
# are reserved; a station that does not answer (quality only, no stale value);
# write-only tags left out; --counters; misuse refused (exit 2).
# Run from the repository root with DF1_BIN=<build/bin>; bounded waits only.
. tests/support/lib.sh

MON="$BIN/df1mon"
PARSE="python3 tests/support/influx_parse.py"
command -v python3 >/dev/null 2>&1 || { echo "SKIP: no python3"; exit 0; }
unset DF1_DEVICE

cat > "$T/data.txt" <<'DATA'
N7:0=-123,45
N7:2=1,2,3
F8:1=1.5
B3:0=32
T4:0.PRE=100
T4:0.ACC=7
ST9:0=say "hi" twice
L10:0=70000
DATA
cat > "$T/map.csv" <<'MAP'
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
Level,Read,INT,1,SLC,N7:0,,100
Temp,Read,FLOAT,1,SLC,F8:1,,100
Run,Read,BOOL,1,SLC,B3:0/5,,100
Stopped,Read,BOOL,1,SLC,B3:0/6,,100
Speeds,Read,INT,1,SLC,N7:2,3,100
Tmr,Read,TIMER,1,SLC,T4:0,,100
Text,Read,STRING,1,SLC,ST9:0,,100
"Line 2, east=x",Read,INT,1,SLC,N7:1,,100
time,Read,INT,1,SLC,N7:0,,100
Big,Read,DINT,1,SLC,L10:0,,100
Cmd,Write,INT,1,SLC,N7:9,,100
MAP

# field VALUE of TAG: the parsed lines (JSON) in $T/lines
field() {
	python3 -c 'import json,sys
for l in open(sys.argv[1]):
    o = json.loads(l)
    if o["tags"].get("tag") == sys.argv[2]:
        v = o["fields"].get(sys.argv[3])
        print("<absent>" if v is None else json.dumps(v)); break
else:
    print("<no line>")' "$T/lines" "$1" "$2"
}

sim_start hd --duplex half --station 1 --data "$T/data.txt" || finish
HD=$SIM_DEV

expect 0 "--map -1 -f influx" -- "$MON" -d "$HD" --duplex half --map "$T/map.csv" -1 -f influx
cp "$T/out" "$T/raw"
check "every line parses as line protocol" "$PARSE < '$T/raw' > '$T/lines'"
same "one line per readable tag, the write-only one left out" "$(wc -l < "$T/raw" | tr -d ' ')" 10
check "measurement df1, tags tag/station/address on every line" \
	'python3 -c "import json,sys
for l in open(sys.argv[1]):
    o = json.loads(l)
    assert o[\"measurement\"] == \"df1\" and o[\"tags\"][\"station\"] == \"1\" and o[\"tags\"][\"address\"], l
" "$T/lines"'
same "N7:0 as an integer" "$(field Level Level)" "-123"
same "F8:1 as a float" "$(field Temp Temp)" "1.5"
same "B3:0/5 as a boolean (32 = bit 5)" "$(field Run Run)" "true"
same "B3:0/6 as a boolean" "$(field Stopped Stopped)" "false"
same "Count 3: Speeds_0..2" "$(field Speeds Speeds_0) $(field Speeds Speeds_1) $(field Speeds Speeds_2)" "1 2 3"
same "a timer's PRE and ACC as integers" "$(field Tmr Tmr.PRE) $(field Tmr Tmr.ACC)" "100 7"
same "a timer's DN as a boolean" "$(field Tmr Tmr.DN)" "false"
same "ST9:0 as a string, quotes escaped" "$(field Text Text)" '"say \"hi\" twice"'
same "a name with a space, comma and equals sign, escaped" "$(field 'Line 2, east=x' 'Line 2, east=x')" "45"
same "a reserved field name gets tag_" "$(field time tag_time)" "-123"
same "L10:0 as an integer" "$(field Big Big)" "70000"
same "quality GOOD, reason none" "$(field Level quality) $(field Level reason)" '"GOOD" "none"'
check "integers carry the i suffix on the wire" 'grep -q " Level=-123i," "$T/raw" && grep -q "Tmr.PRE=100i" "$T/raw"'
check "one timestamp per scan, in ns since the epoch (after 2020)" \
	'[ "$(awk "{print \$NF}" "$T/raw" | sort -u | wc -l)" -eq 1 ] && [ "$(awk "{print \$NF; exit}" "$T/raw")" -gt 1577836800000000000 ]'

# a station that never answers: quality and reason only, no value field
printf 'Tag,Command,Type,Station,PLC_Type,Address\nGone,Read,INT,5,SLC,N7:0\nHere,Read,INT,1,SLC,N7:0\n' > "$T/gone.csv"
expect 1 "a station that does not answer: exit 1 for a BAD tag after -1" -- \
	"$MON" -d "$HD" --duplex half --map "$T/gone.csv" -1 -f influx -o 100
check "still parses" "$PARSE < '$T/out' > '$T/lines'"
same "no value field for the silent station" "$(field Gone Gone)" "<absent>"
same "its quality BAD, with the reason" "$(field Gone quality) $(field Gone reason)" '"BAD" "comm_failure"'
same "the other station's tag still has its value" "$(field Here Here)" "-123"

# several scans: each scan one block of lines with a later timestamp
expect 0 "--duration 1: scans every 100 ms" -- "$MON" -d "$HD" --duplex half --map "$T/map.csv" -f influx --duration 1
check "several scans, each a full set of lines" \
	'n=$(wc -l < "$T/out"); [ "$n" -ge 20 ] && [ $((n % 10)) -eq 0 ]'
check "timestamps never go back" 'awk "{print \$NF}" "$T/out" | sort -c -n'

# --counters: a df1_link line with the scan statistics and the seed counters
expect 0 "--counters -f influx" -- "$MON" -d "$HD" --duplex half --map "$T/map.csv" -1 -f influx --counters
check "the counters' line parses" "grep '^df1_link ' '$T/out' | $PARSE > '$T/lines'"
check "the counters' line has the scans and seed counters as integers" \
	'python3 -c "import json,sys
o = json.loads(open(sys.argv[1]).readline())
f = o[\"fields\"]
assert f[\"scans\"] >= 1 and f[\"CNT_MSG_PACKETS_SENT\"] >= 1 and \"CRD_CHAR_RECV\" in f, f
" "$T/lines"'

# misuse
expect 2 "-f influx without --map" -- "$MON" -d "$HD" --ping -f influx
err_has "-f influx without --map: says so" "-f influx needs --map"
expect 2 "an unknown format lists influx" -- "$MON" -d "$HD" --map "$T/map.csv" -f xml
err_has "the accepted formats" "plain, csv, json, influx or prometheus"

sim_stop
finish
