#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_df1sim_ramp - df1sim --ramp ADDR[,STEP][@MS] (df1sim(1)): df1read sees
# the values advance on their own, by whole steps from where they started
# (an N word wraps as a PLC's does, an F goes by its fractional step, a bit
# toggles), a value a master writes goes on from what was written, and bad
# ramps are refused with exit 2. No timing is asserted: the checks wait
# (bounded) for a change and check what the value is, not when it came.
# Run from the repository root with DF1_BIN=<build/bin>.
. tests/support/lib.sh
R="$BIN/df1read"
W="$BIN/df1write"
for t in df1read df1write df1sim; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE

cat > "$T/data" <<'DATA'
N7:0=3
N7:2=32760
F8:1=1.25
N7:3=0
DATA

sim_start ramp --data "$T/data" --ramp N7:0,5@100 --ramp N7:2,10@100 --ramp F8:1,0.5@100 \
	--ramp B3:0/4@100 --ramp N7:3,1@100 || finish

# rd ADDR: the value df1read reads now (empty on a failure)
rd() { bounded "$R" -d "$SIM_DEV" "$1" 2>> "$T/rd.err"; }

# N7:0 from 3 by 5: a later read is larger, and 3 more than a multiple of 5
first=$(rd N7:0)
check "N7:0 read ($first)" '[ -n "$first" ]'
advanced() { v=$(rd N7:0) && [ -n "$v" ] && [ "$v" -gt "$first" ]; }
wait_for "N7:0 advances past $first" 100 advanced
check "N7:0 by steps of 5 from 3 ($first, $v)" '[ $(( (v - 3) % 5 )) -eq 0 ] && [ $(( (first - 3) % 5 )) -eq 0 ]'

# N7:2 from 32760 by 10 wraps to -32766 and on, as a 16-bit word does
wrapped() { w=$(rd N7:2) && [ -n "$w" ] && [ "$w" -lt 0 ]; }
wait_for "N7:2 wraps" 100 wrapped
check "N7:2 after the wrap is 32760 + 10k - 65536 ($w)" '[ $(( (w - 32760 + 65536) % 10 )) -eq 0 ]'

# F8:1 from 1.25 by 0.5: 1.75, 2.25, ... (exact in a float)
f0=$(rd F8:1)
fmoved() { f=$(rd F8:1) && [ -n "$f" ] && [ "$f" != "$f0" ]; }
wait_for "F8:1 advances" 100 fmoved
check "F8:1 is 1.25 + 0.5k ($f0 then $f)" \
	"awk -v a='$f0' -v b='$f' 'BEGIN { x = (a - 1.25) / 0.5; y = (b - 1.25) / 0.5; exit !(x == int(x) && y == int(y) && b > a) }'"

# B3:0/4 toggles
b0=$(rd B3:0/4)
toggled() { b=$(rd B3:0/4) && [ -n "$b" ] && [ "$b" != "$b0" ]; }
wait_for "B3:0/4 toggles from $b0" 100 toggled

# a master's write: the ramp goes on from the value written
expect 0 "df1write N7:3=20000" -- "$W" -d "$SIM_DEV" N7:3=20000
n3=$(rd N7:3)
check "N7:3 goes on from 20000 ($n3)" '[ -n "$n3" ] && [ "$n3" -ge 20000 ] && [ "$n3" -lt 30000 ]'
sim_stop

# bad ramps: exit 2, saying what is wrong
expect 2 "--ramp N7:0,1.5" -- "$BIN/df1sim" --pty "$T/bad" --ramp N7:0,1.5
err_has "an integer step for a word" "an integer STEP"
expect 2 "--ramp ST9:0" -- "$BIN/df1sim" --pty "$T/bad" --ramp ST9:0
err_has "no ramp of a string" "a word, an L, an F or a bit only"
expect 2 "--ramp N7:0@0" -- "$BIN/df1sim" --pty "$T/bad" --ramp N7:0@0
err_has "a period of 1 ms at least" "ADDR[,STEP][@MS]"
expect 2 "--ramp N7:999" -- "$BIN/df1sim" --pty "$T/bad" --ramp N7:999
err_has "an address the table lacks" "--ramp N7:999"
finish
