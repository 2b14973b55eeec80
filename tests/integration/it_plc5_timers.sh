#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# The PLC-5 timer element size the client learns (libdf1(7) TIMEOUTS, df1read(1)):
# df1read --plc plc5 without --plc5-timer-words against df1sim serving 3-word
# and 5-word timers, with replies that are cut to what fits (df1sim's default)
# and with reads too large refused as STS F0 EXT STS 09 (--plc5-refuse-large, as
# another PLC-5 emulator answers). Expected counts follow from doc/PROTOCOL.md 6:
# T4:0 has a 3-byte address, so a reply holds 38 three-word timers
# (3 + 4 + 6n <= 240) or 23 five-word ones (3 + 5 + 10n <= 240); what was asked is
# read from df1sim's --log. Forcing 3 words against 5-word timers that refuse
# stays an error naming EXT STS 09. Run from the repository root.
. tests/support/lib.sh
R="$BIN/df1read"
for t in df1read df1sim; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE

printf 'T4:1="EN=1 TT=1 DN=1 PRE=100 ACC=42"\nT4:31="DN=1 PRE=7 ACC=3"\n' > "$T/data"
# the counts of the typed reads logged after line $2 of log $1
asked() { tail -n "+$(($2 + 1))" "$1" | sed -n 's/.*cmd=0F\/68 addr=T4:0 count=\([0-9]*\) .*/\1/p' | tr '\n' ' '; }
logged() { if [ -f "$1" ]; then wc -l < "$1" | tr -d ' '; else echo 0; fi; }
log_has() { [ "$(logged "$1")" -ge "$2" ]; }

# words, df1sim's extra option, the counts asked for T4:0,32, then for T4:0,40
for row in "3||32|38 2" "5||32 9|38 17" "3|--plc5-refuse-large|32|38 2" \
           "5|--plc5-refuse-large|32 23 9|38 23 17"; do
	words=${row%%|*}; rest=${row#*|}; extra=${rest%%|*}; rest=${rest#*|}
	w32=${rest%%|*}; w40=${rest#*|}
	label="$words words${extra:+ $extra}"
	rm -f "$T/log"
	sim_start "s$words$extra" --plc plc5 --plc5-timer-words "$words" $extra --data "$T/data" \
		--log "$T/log" || continue
	expect 0 "$label: T4:0,32" -- "$R" -d "$SIM_DEV" --plc plc5 -f csv T4:0,32
	same "$label: 32 rows" "$(wc -l < "$T/out" | tr -d ' ')" 33
	same "$label: T4:1" "$(grep '^T4:1,' "$T/out")" 'T4:1,"EN=1 TT=1 DN=1 PRE=100 ACC=42"'
	same "$label: T4:31" "$(grep '^T4:31,' "$T/out")" 'T4:31,"EN=0 TT=0 DN=1 PRE=7 ACC=3"'
	n=$(echo $w32 | wc -w)
	wait_for "$label: $n reads logged" 50 log_has "$T/log" "$n"
	same "$label: the counts asked for 32" "$(asked "$T/log" 0)" "$w32 "
	before=$(logged "$T/log")
	expect 0 "$label: T4:0,40" -- "$R" -d "$SIM_DEV" --plc plc5 -f csv T4:0,40
	same "$label: 40 rows" "$(wc -l < "$T/out" | tr -d ' ')" 41
	same "$label: T4:31 of 40" "$(grep '^T4:31,' "$T/out")" 'T4:31,"EN=0 TT=0 DN=1 PRE=7 ACC=3"'
	n=$(echo $w40 | wc -w)
	wait_for "$label: $n more reads logged" 50 log_has "$T/log" $((before + n))
	same "$label: the counts asked for 40" "$(asked "$T/log" "$before")" "$w40 "
	if [ "$words$extra" = "5--plc5-refuse-large" ]; then
		expect 1 "forced 3 words, refused" -- "$R" -d "$SIM_DEV" --plc plc5 --plc5-timer-words 3 T4:0,32
		err_has "forced 3 words: the PLC's answer" "EXT STS 0x09 (data or file is too large)"
		expect 0 "forced 5 words" -- "$R" -d "$SIM_DEV" --plc plc5 --plc5-timer-words 5 T4:31
		out_is "forced 5 words: T4:31" "EN=0 TT=0 DN=1 PRE=7 ACC=3"
	fi
	sim_stop
done
expect 2 "--plc5-refuse-large without --plc plc5" -- "$BIN/df1sim" --pty "$T/x" --plc slc --plc5-refuse-large
err_has "named" "--plc5-refuse-large goes with --plc plc5 only"
finish
