#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# df1mon --autoconf (df1_probe_line) against df1sim playing a line with fixed
# settings (--line-settings): a grid of cases (baud, parity, check, duplex,
# stations above 9 and 16 = DLE), over a pseudo-terminal and over RFC 2217
# (df1sim --listen rfc2217://). The expectation is the settings df1sim was
# started with; each answer is then used by df1read, which must read N7:0.
# Which path covers what: Linux's pty refuses PARENB (and forces 8 bits), so
# over the pty df1sim compares only the rate the master set in the pty's
# termios, and a line with parity is found as "-P none" (two settings answer:
# the one reported must work); parity mismatches are covered over rfc2217,
# where df1sim takes the settings the client sent and garbles by its UART model.
. tests/support/lib.sh
for t in df1mon df1sim df1read; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE

# case: transport line-settings duplex check hd-bcc station stations-range expected-parity
# (a station of - : full duplex)
run_case() {
	tr=$1 line=$2 dup=$3 chk=$4 hdb=$5 st=$6 range=$7 par=$8
	baud=${line%%,*}
	extra=
	[ "$hdb" = stx ] && extra="--hd-bcc stx"
	if [ "$st" = - ]; then
		simargs="--duplex $dup --check $chk"
		settings="-b $baud -P $par --check $chk --duplex $dup"
	else
		simargs="--duplex $dup --check $chk --station $st $extra"
		settings="-b $baud -P $par --check $chk --duplex $dup${extra:+ $extra} -a $st"
	fi
	ncase=$((ncase + 1))      # a name per case: sim_start could read an earlier case's ready line
	if [ "$tr" = pty ]; then
		sim_start "ac$ncase" --line-settings "$line" $simargs || return
	else
		"$BIN/df1sim" --listen rfc2217://127.0.0.1:0 --line-settings "$line" $simargs \
			> "$T/ac$ncase.out" 2> "$T/ac$ncase.err" &
		SIM_PID=$!
		echo "$SIM_PID" >> "$T/.sims"
		wait_for "df1sim rfc2217 ready" 100 test -s "$T/ac$ncase.out" || return
		SIM_DEV=$(head -n 1 "$T/ac$ncase.out")
	fi
	expect 0 "autoconf $tr $line $dup $chk $hdb $st" -- \
		"$BIN/df1mon" -d "$SIM_DEV" --autoconf --stations "$range" $PT
	same "autoconf $tr $line $dup $chk $hdb $st: the settings" "$(cat "$T/out")" "$settings"
	# the answer really works (with a timeout for a loaded host: the settings
	# found are what is checked, not how fast this host answers)
	# shellcheck disable=SC2046
	expect 0 "df1read with the settings found ($tr $line)" -- \
		"$BIN/df1read" -d "$SIM_DEV" $(cat "$T/out") -o 2000 N7:5
	out_is "df1read N7:5 ($tr $line)" "5"
	sim_stop
}

ncase=0
# answer windows of 150 ms instead of the automatic 30 ms + 6 characters: the
# host running the tests may be loaded (the search at the defaults: below)
PT="--poll-timeout 150"
# over a pty: the rate (and duplex, check, station) is found
run_case pty 19200,8N1 full crc - - 1-1 none
run_case pty 9600,8N1 full bcc - - 1-1 none
run_case pty 38400,8N1 half crc - 3 0-4 none
run_case pty 2400,8N1 half bcc - 16 14-17 none
run_case pty 4800,8N1 half bcc stx 17 15-18 none
run_case pty 57600,8N1 full crc - - 1-1 none
# two settings answer on a pty (9600 with or without parity): the first, which works
run_case pty 9600,8E1 full crc - - 1-1 none
# over rfc2217: parity too
run_case rfc 9600,8E1 full crc - - 1-1 even
run_case rfc 19200,8O1 full bcc - - 1-1 odd
run_case rfc 9600,8E1 half bcc - 10 9-11 even
run_case rfc 19200,8O1 half crc - 16 16-17 odd
run_case rfc 115200,8N1 half crc - 1 0-2 none
run_case rfc 2400,8E1 half bcc stx 12 11-12 even

# ---- the file -w writes is a network CSV the tools read ----
sim_start acw --line-settings 9600 --duplex half --check bcc --station 17 || exit 1
expect 0 "autoconf -w" -- "$BIN/df1mon" -d "$SIM_DEV" --autoconf --stations 16-18 $PT -w "$T/net.csv"
err_has "progress names what answered" "poll: answered"
check "the CSV row" "grep -q '^17,Master,SLC,BCC,$SIM_DEV,9600,8,1,None\$' '$T/net.csv'"
expect 0 "df1read -N net.csv" -- "$BIN/df1read" -N "$T/net.csv" -a 17 -o 2000 N7:3
out_is "df1read -N N7:3" "3"
sim_stop

# ---- nothing attached: exit 1, "nothing answered", within the time it announced ----
python3 -c '
import os, pty, sys, time
m, s = pty.openpty()
print(os.ttyname(s), flush=True)
time.sleep(120)
' > "$T/silent" &
SILENT=$!
echo "$SILENT" >> "$T/.sims"
wait_for "a silent pty" 50 test -s "$T/silent"
expect 1 "nothing attached" -- "$BIN/df1mon" -d "$(head -n 1 "$T/silent")" --autoconf --stations 0-1
err_has "nothing answered" "nothing answered"
err_has "the likely causes" "likely causes"
bound=$(sed -n 's/.*at most \([0-9]*\) s$/\1/p' "$T/err")
took=$(sed -n 's/.* in \([0-9]*\)\.[0-9] s: .*/\1/p' "$T/err")
check "it took ${took}s of the ${bound}s announced" "[ -n '$took' ] && [ -n '$bound' ] && [ '$took' -le '$bound' ]"
sim_stop "$SILENT"

finish
