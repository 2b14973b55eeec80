#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_radio_channel - the radio channel fixture of the radio modem tests
# (tests/support/radio_channel.py), on its own and with the half-duplex link
# it already carries. Writers and readers are tests/support/radio_probe.py.
#  - a chain a-b-c-d (each node hears its neighbours only), 9600 baud, 50 ms
#    key-up: each node gets exactly the bytes of the nodes in its range, never
#    its own, in order; two transmissions that overlap at b reach it one after
#    the other, whole; two writes within the gap are one transmission; the
#    bytes take at least the key-up plus 10 bits each at 9600 baud to arrive
#    (lower bounds only: a loaded machine is slower, never faster); the log
#    has one line per transmission with its sender, receivers and bytes;
#  - parallel relays (a diamond): both relays reach the far node, whole, one
#    after the other;
#  - one-way ranges (--hears) and --collide: overlapping transmissions reach
#    a receiver garbled, and the log says so;
#  - every node in range of every other without --link/--hears; SIGTERM:
#    exit 0, links removed; idle, it uses no CPU to speak of (no busy loop);
#    bad arguments: exit 2 naming the option;
#  - df1read/df1write --duplex half against df1sim --duplex half across a
#    two-node channel with the 50 ms key-up (a point-to-point radio link).
# Run from the repository root with B=<build dir> and DF1_BIN=<build/bin>.
. tests/support/lib.sh
command -v python3 > /dev/null || { skip "python3 missing"; finish; }
RC=tests/support/radio_channel.py
PROBE=tests/support/radio_probe.py

# chan NAME OPTIONS...: the channel (lib.sh radio_start); CHAN_PID
chan() { radio_start "$@"; CHAN_PID=$RADIO_PID; }

# pat N FIRST: N bytes FIRST, FIRST+1, ... (mod 256) as hex without spaces
pat() { awk -v n="$1" -v s="$2" 'BEGIN { for (i = 0; i < n; i++) printf "%02x", (s + i) % 256; print "" }'; }
# spaced HEX: the same bytes as the log writes them ("10 02 ...")
spaced() { printf '%s\n' "$1" | sed 's/\(..\)/\1 /g; s/ $//'; }
# rx NODE: the hex a node received (probe output $T/probe)
rx() { awk -v n="$1" '$1 == "rx" && $2 == n { print $6 }' "$T/probe"; }
# field NODE K: field K of the node's rx line; txt NODE: when its first send left
field() { awk -v n="$1" -v k="$2" '$1 == "rx" && $2 == n { print $k }' "$T/probe"; }
txt() { awk -v n="$1" '$1 == "tx" && $2 == n { print $3; exit }' "$T/probe"; }
# ge A B: A >= B (decimals)
ge() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a + 0 >= b + 0) }'; }

# ---- a chain a-b-c-d ----
chan chain --node a,b,c,d --link a-b-c-d --baud 9600 --keyup-ms 50
for n in a b c d; do
	dev=$(awk -v n="$n" '$1 == n { print $2 }' "$T/chain.out")
	check "chain: node $n's device is printed and linked" "[ -n '$dev' ] && [ \"\$(readlink '$T/chain.$n')\" = '$dev' ] && [ -c '$dev' ]"
done
B96=$(pat 96 0); C40=$(pat 40 128); A20=$(pat 20 64); A20b=$(pat 20 96); A60=$(pat 60 16); C60=$(pat 60 160)
expect 0 "chain: the probe runs" -- python3 "$PROBE" "$T/chain" a,b,c,d \
	"send:b:$B96" pause:400 "send:c:$C40" pause:400 "send:a:$A20" "send:a:$A20b" pause:400 \
	"send:a:$A60" "send:c:$C60"
cp "$T/out" "$T/probe"
same "chain: a hears b only" "$(rx a)" "$B96"
same "chain: b hears a and c, in order, overlapping transmissions whole one after the other" "$(rx b)" "$C40$A20$A20b$A60$C60"
same "chain: c hears b and d (d sent nothing)" "$(rx c)" "$B96"
same "chain: d hears c only" "$(rx d)" "$C40$C60"
# b's 96 bytes: the key-up, then 96 characters of 10 bits at 9600 baud
# (1.04 ms each): the first not before 50 ms, the last not before 150 ms
tb=$(txt b)
check "chain: a's first byte came after the key-up (sent $tb, got $(field a 4))" "ge \$(field a 4) \$(awk 'BEGIN { print $tb + 0.045 }')"
check "chain: a's last byte came after key-up + 96 characters (got $(field a 5))" "ge \$(field a 5) \$(awk 'BEGIN { print $tb + 0.9 * (0.050 + 96 * 10 / 9600) }')"
tc=$(txt c)
check "chain: d's first byte came after the key-up (sent $tc, got $(field d 4))" "ge \$(field d 4) \$(awk 'BEGIN { print $tc + 0.045 }')"
sim_stop "$CHAN_PID"
# the log: one line per transmission (a's two writes within the gap are one);
# the two overlapping ones end in either order
cut -d' ' -f3- "$T/chain.log" | sort > "$T/chain.air"
{
	echo "b > a,c $(spaced "$B96")"
	echo "c > b,d $(spaced "$C40")"
	echo "a > b $(spaced "$A20$A20b")"
	echo "a > b $(spaced "$A60")"
	echo "c > b,d $(spaced "$C60")"
} | sort > "$T/chain.want"
same "chain: the log holds each transmission, its sender, receivers and bytes" "$(cat "$T/chain.air")" "$(cat "$T/chain.want")"
# each transmission lasts at least its key-up and its characters
check "chain: every logged transmission takes its key-up and 10 bits a byte" \
	"awk '{ n = NF - 5; if (\$2 - \$1 < 0.99 * (0.050 + n * 10 / 9600)) bad = 1 } END { exit bad || NR != 5 }' '$T/chain.log'"

# ---- parallel relays: a diamond, a hears b and c, so does d ----
chan dia --node a,b,c,d --link a-b-d --link a-c-d --keyup-ms 20 --baud 19200
A30=$(pat 30 0); B30=$(pat 30 50); C30=$(pat 30 100)
expect 0 "dia: the probe runs" -- python3 "$PROBE" "$T/dia" a,b,c,d \
	"send:a:$A30" pause:300 "send:b:$B30" "send:c:$C30"
cp "$T/out" "$T/probe"
same "dia: b and c hear a" "$(rx b) $(rx c)" "$A30 $A30"
same "dia: d does not hear a; b and c both reach it, one after the other (buffered, not mixed)" "$(rx d)" "$B30$C30"
same "dia: a hears both relays" "$(rx a)" "$B30$C30"
sim_stop "$CHAN_PID"
same "dia: the log's receivers" "$(awk '{ print $3, $4, $5 }' "$T/dia.log" | sort | tr '\n' ';')" "a > b,c;b > a,d;c > a,d;"

# ---- one-way ranges and collisions ----
chan coll --node a,b,c,x,y --link a-b-c --hears y:x --collide --keyup-ms 0 --baud 9600
X10=$(pat 10 1); Y10=$(pat 10 11); A200=$(pat 200 0); C200=$(pat 200 100)
expect 0 "coll: the probe runs" -- python3 "$PROBE" "$T/coll" a,b,c,x,y \
	"send:x:$X10" "send:y:$Y10" pause:300 "send:a:$A200" "send:c:$C200"
cp "$T/out" "$T/probe"
same "coll: y hears x" "$(rx y)" "$X10"
same "coll: x does not hear y (--hears y:x is one way)" "$(rx x)" "-"
same "coll: b gets as many bytes as both sent" "$(field b 3)" 400
check "coll: b's bytes are garbled, not the two transmissions one after the other" \
	"[ '$(rx b)' != '$A200$C200' ] && [ '$(rx b)' != '$C200$A200' ]"
same "coll: a and c do not hear each other" "$(rx a)$(rx c)" "--"
sim_stop "$CHAN_PID"
same "coll: the log marks both transmissions garbled at b" \
	"$(grep -c ' garbled:b$' "$T/coll.log")" 2
same "coll: y's transmission reached nobody" "$(awk '$3 == "y" { print $5 }' "$T/coll.log")" "-"

# ---- every node in range without links; SIGTERM; no busy loop ----
chan mesh --node p,q,r
P5=$(pat 5 200)
expect 0 "mesh: the probe runs" -- python3 "$PROBE" "$T/mesh" p,q,r "send:p:$P5" --idle 0.5
cp "$T/out" "$T/probe"
same "mesh: q and r hear p, p not itself" "$(rx p) $(rx q) $(rx r)" "- $P5 $P5"
cpu() { awk '{ print $14 + $15 }' "/proc/$1/stat" 2>/dev/null; }
if [ -r "/proc/$CHAN_PID/stat" ]; then
	c0=$(cpu "$CHAN_PID")
	sleep 1          # idle on purpose: a busy loop would take most of this second
	c1=$(cpu "$CHAN_PID")
	check "mesh: idle for a second, the channel took under 0.3 s of CPU ($c0 -> $c1 ticks)" \
		"[ \$(( $c1 - $c0 )) -lt \$(( $(getconf CLK_TCK) * 3 / 10 )) ]"
else
	skip "mesh: no /proc to read the channel's CPU time from"
fi
kill -TERM "$CHAN_PID"
wait "$CHAN_PID"
same "mesh: SIGTERM ends the channel with status 0" "$?" 0
grep -v "^$CHAN_PID\$" "$T/.sims" > "$T/.sims.new"; mv "$T/.sims.new" "$T/.sims"
check "mesh: the links are removed" "[ ! -e '$T/mesh.p' ] && [ ! -L '$T/mesh.q' ]"
same "mesh: the log has p's transmission" "$(cut -d' ' -f3- "$T/mesh.log")" "p > q,r $(spaced "$P5")"

expect 2 "bad: a link to an unknown node" -- python3 "$RC" --prefix "$T/bad" --node a,b --link a-z
err_has "bad: the message names --link and the node" "--link: unknown node 'z'"
expect 2 "bad: --hears without a colon" -- python3 "$RC" --prefix "$T/bad" --node a,b --hears ab
err_has "bad: the message names --hears" "--hears: 'ab' is not"
check "bad: nothing was linked" "[ ! -e '$T/bad.a' ]"

# ---- half duplex across a point-to-point radio link ----
chan p2p --node m,s --link m-s --baud 9600 --keyup-ms 50
printf 'N7:0=1234,-5\n' > "$T/p2p.data"
"$BIN/df1sim" -d "$T/p2p.s" --duplex half --station 1 --data "$T/p2p.data" > "$T/p2p.sim" 2> "$T/p2p.simerr" &
SIMP=$!
echo "$SIMP" >> "$T/.sims"
wait_for "p2p: df1sim is up" 100 test -s "$T/p2p.sim"
# a poll's answer begins after the slave's key-up: 300 ms, not the default
HD="--duplex half --station 1 --poll-timeout 300 --timeout 2000"
# shellcheck disable=SC2086
expect 0 "p2p: df1read --duplex half across the radio" -- "$BIN/df1read" -d "$T/p2p.m" $HD N7:0,2
out_is "p2p: the values" "1234
-5"
# shellcheck disable=SC2086
expect 0 "p2p: df1write --duplex half across the radio" -- "$BIN/df1write" -d "$T/p2p.m" $HD N7:5=777
# shellcheck disable=SC2086
expect 0 "p2p: read back" -- "$BIN/df1read" -d "$T/p2p.m" $HD N7:5
out_is "p2p: the value written" 777
sim_stop "$SIMP"
sim_stop "$CHAN_PID"
# the air: the slave's ACK (DLE ACK) and its reply with 1234 and -5 (d2 04
# fb ff, low byte first) went to m; nothing went anywhere else
check "p2p: the slave ACKed over the air" "grep -q ' s > m 10 06' '$T/p2p.log'"
check "p2p: the reply with 1234 and -5 crossed the air" "grep -q ' s > m 10 02 .*d2 04 fb ff' '$T/p2p.log'"
check "p2p: every transmission went to the other node only" \
	"awk '!((\$3 == \"m\" && \$5 == \"s\") || (\$3 == \"s\" && \$5 == \"m\")) { bad = 1 } END { exit bad || NR < 4 }' '$T/p2p.log'"
finish
