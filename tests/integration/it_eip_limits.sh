#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_eip_limits.sh - the EtherNet/IP server's limits (df1-eip(7) "Limits")
# through df1gw --eip and df1sim --eip: 40 idle connections (20 with a session,
# 20 that never send a byte, tests/support/eip_flood.py) against a table of 32
# no longer lock a new client out: its RegisterSession is served at once (the
# table makes room) and a PCCC read through the bridge reaches df1sim; the
# idle ones are closed by --eip-register-timeout and --eip-idle-timeout (short
# here to keep it quick), each logged and counted (--counters). Waits are
# bounded; no timing is asserted beyond generous bounds.
# Run from the repository root with DF1_BIN=<build/bin>.
. tests/support/lib.sh

GW="$BIN/df1gw"
FLOOD="python3 tests/support/eip_flood.py"
PROBE="python3 tests/support/eipgw_probe.py"

gw_addr() {
	EIP=$(sed -n 's|^df1gw: EtherNet/IP on \([0-9.]*:[0-9]*\).*|\1|p' "$T/$1.err" 2>/dev/null | head -n 1)
	[ -n "$EIP" ]
}
eip_line() {
	EIP=$(sed -n 's|^eip://||p' "$T/$1.out" 2>/dev/null | head -n 1)
	[ -n "$EIP" ]
}
# counted FILE: "A B C" of the last "eip closed without session A, idle B, evicted C"
counted() {
	sed -n 's/^eip closed without session \([0-9]*\), idle \([0-9]*\), evicted \([0-9]*\)$/\1 \2 \3/p' "$1" |
		tail -n 1
}

cat > "$T/plc.txt" <<'EOF2'
N7:50=123
EOF2

# ---- options ----
for tool in "$GW" "$BIN/df1sim"; do
	name=$(basename "$tool")
	expect 2 "$name --eip-idle-timeout without --eip" -- "$tool" -d /dev/null --eip-idle-timeout 5
	err_has "$name: says what goes with --eip" "go with --eip"
	expect 2 "$name --eip-max-clients 0" -- "$tool" --eip 0 -d /dev/null --eip-max-clients 0
	expect 2 "$name --eip-register-timeout 3601" -- "$tool" --eip 0 -d /dev/null --eip-register-timeout 3601
	expect 0 "$name --help names the limits" -- "$tool" --help
	check "$name --help: the three limits" 'grep -q -- "--eip-max-clients" "$T/out" &&
		grep -q -- "--eip-register-timeout" "$T/out" && grep -q -- "--eip-idle-timeout" "$T/out"'
done

# ---------------------------------------------------------------------------
# df1gw --eip: 40 idle connections, the default table of 32
# ---------------------------------------------------------------------------
sim_start sim --data "$T/plc.txt" --log "$T/sim.log" || finish
"$GW" -d "$SIM_DEV" --eip 0 --eip-register-timeout 5 --eip-idle-timeout 6 --counters \
	> "$T/gw.out" 2> "$T/gw.err" &
GW_PID=$!
echo "$GW_PID" >> "$T/.sims"
wait_for "df1gw says where it listens" 100 gw_addr gw
$FLOOD "$EIP" 20 20 30 > "$T/flood.out" 2> "$T/flood.err" &
FL=$!
wait_for "a new client's RegisterSession is served with 40 idle connections held" 200 \
	grep -q '^served$' "$T/flood.out"
expect 0 "a PCCC read through the bridge meanwhile" -- $PROBE "$EIP" read - 50 123
wait $FL
same "the flood's end" "$(tail -n 1 "$T/flood.out")" "closed 40 of 40"
check "flood: no error" '[ ! -s "$T/flood.err" ] || { cat "$T/flood.err"; false; }'
same "a PCCC read reached df1sim once" "$(grep -c 'cmd=0F/A2 addr=N7:50 \|cmd=0F/01 ' "$T/sim.log")" 1
kill -TERM "$GW_PID" 2>/dev/null
lib_reap "$GW_PID"
read -r NOSESS IDLE EVICTED <<EOF2
$(counted "$T/gw.out")
EOF2
same "--counters: the 20 sessions closed for idleness" "$IDLE" 20
same "--counters: 20 without a session, closed or evicted" "$((NOSESS + EVICTED))" 20
check "--counters: at least one evicted for the new client" '[ "$EVICTED" -ge 1 ]'
same "each close logged" "$(grep -c '^df1gw: eip: closed 127\.0\.0\.1:[0-9]*: ' "$T/gw.err")" 40
same "idle closes say so" "$(grep -c 'session idle for 6 s' "$T/gw.err")" 20
sim_stop

# ---------------------------------------------------------------------------
# df1sim --eip: the same limits, a table of 4
# ---------------------------------------------------------------------------
"$BIN/df1sim" --eip 0 --eip-max-clients 4 --eip-register-timeout 1 --eip-idle-timeout 2 \
	> "$T/es.out" 2> "$T/es.err" &
ES=$!
echo "$ES" >> "$T/.sims"
wait_for "df1sim --eip prints its address" 100 eip_line es
expect 0 "df1sim: a new client served with 8 idle connections held" -- $FLOOD "$EIP" 2 6 30
same "df1sim: every held connection closed" "$(tail -n 1 "$T/out")" "closed 8 of 8"
same "df1sim: each close logged" "$(grep -c '^df1sim: eip: closed 127\.0\.0\.1:' "$T/es.err")" 8
same "df1sim: the idle sessions" "$(grep -c 'session idle past --eip-idle-timeout' "$T/es.err")" 2
sim_stop "$ES"

finish
