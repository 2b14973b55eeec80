#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_radio - the DF1 Radio Modem (doc/PROTOCOL.md 2.6, libdf1(7) RADIO MODEM)
# on the radio channel fixture (tests/support/radio_channel.py: who hears
# whom, 9600 baud, a key-up delay per transmission, --log of every one):
# df1sim --duplex radio nodes as PLCs and relays, df1read / df1write /
# df1mon / df1gw --duplex radio as the master. The expectations are the
# channel's log (what went on the air, from whom to whom), df1sim's --log
# (what a PLC executed) and the rules of store and forward:
#  - point to point: a write and a read back;
#  - a chain of two relays (the AG-UM008 example: master 1, relays 2 and 3
#    with forward tables {1,3,4} and {1,2,4}, PLC 4; 1 hears only 2, 2 hears
#    1 and 3, 3 hears 2 and 4): the read gets through; on the air, the
#    command and the reply hop relay by relay, each relay sends each packet
#    once (the copy it hears back from the next relay is a duplicate, dropped)
#    and the relays execute nothing;
#  - two relays in parallel (the PLC hears both copies, duplicate detection
#    on): the write is executed once (the PLC's --log) and the master takes
#    one of the two replies;
#  - a silent station (df1sim muted by SIGUSR1) behind the relays: the
#    command is relayed, its copy heard back is not a reply, timeout 2508
#    after one transmission (--app-retries 0, the default);
#  - a broadcast (-a 255): executed by each PLC in range, by none out of
#    range, and no reply on the air;
#  - df1mon --who over the radio finds the stations in range;
#  - df1gw polling PLC 1 behind two relays in a chain, and behind two relays
#    in parallel (df1gw and the PLC with duplicate detection: each hears every
#    packet twice), a mosquitto broker on a loopback port: the values
#    published, the station's health ok (once ok, never failing or offline),
#    and the PLC's MSG writes (df1sim --msg, report by exception) reaching a
#    Receive row, each published once and in order.
# Run from the repository root; DF1_BIN = the built tools.
. tests/support/lib.sh
command -v python3 > /dev/null || { skip "python3 missing: no radio channel"; finish; }
for t in df1write df1read df1sim df1mon df1gw; do
	[ -x "$BIN/$t" ] || { bad "no $BIN/$t"; finish; }
done
unset DF1_DEVICE
W="$BIN/df1write"
R="$BIN/df1read"
# one hop at 9600 baud with a 50 ms key-up is about 80 ms: a chain's six
# transmissions fit well in 3 s, even on a loaded machine
RADIO="--duplex radio -o 3000 --cmd-timeout 3000"

# node NAME CHANNEL NODE DF1SIM OPTIONS...: df1sim --duplex radio on a
# channel's node, its --log $T/NAME.log; NODE_PID
node() {
	nname=$1; ndev=$T/$2.$3; shift 3
	"$BIN/df1sim" -d "$ndev" --duplex radio --log "$T/$nname.log" "$@" \
		> "$T/$nname.out" 2> "$T/$nname.err" &
	NODE_PID=$!
	echo "$NODE_PID" >> "$T/.sims"
	wait_for "df1sim $nname is up" 100 test -s "$T/$nname.out"
}
# air CHANNEL: the channel's log as "SENDER > RECEIVERS HEX..." lines, in order
air() { sort -n "$T/$1.log" | cut -d' ' -f3-; }
# pkt HEX...: the packet inside a logged transmission (DLE STX .. DLE ETX),
# its header DST SRC CMD STS TNS as "dst=.. src=.. cmd=.. tns=.."
pkt() {
	awk '{ i = 1; while (i < NF && !($i == "10" && $(i + 1) == "02")) i++
		if (i >= NF) { print "-"; exit }
		printf "dst=%d src=%d cmd=%s tns=%s%s\n", dec($(i + 2)), dec($(i + 3)), $(i + 4), $(i + 7), $(i + 6) }
	function dec(h) { return index("0123456789abcdef", substr(h, 1, 1)) * 16 + index("0123456789abcdef", substr(h, 2, 1)) - 17 }'
}
# hops CHANNEL: one line per transmission, "SENDER dst=D src=S cmd=C tns=T"
hops() {
	air "$1" | while read -r snd _ rcv rest; do
		printf '%s %s\n' "$snd" "$(printf '%s\n' "$rest" | pkt)"
	done
}
stop_all() { for p in "$@"; do sim_stop "$p"; done; }

# ---- 1. point to point ----
radio_start p2p --node m,p --link m-p --baud 9600 --keyup-ms 50 || finish
CH=$RADIO_PID
node p2p_plc p2p p --station 1; P=$NODE_PID
expect 0 "p2p: write N7:0" -- "$W" -d "$T/p2p.m" $RADIO -a 1 N7:0=4321
expect 0 "p2p: read N7:0" -- "$R" -d "$T/p2p.m" $RADIO -a 1 N7:0
out_is "p2p: read back" 4321
stop_all "$P" "$CH"
same "p2p: two commands and two replies on the air, nothing else" \
	"$(air p2p | awk '{ print $1, $2, $3 }' | tr '\n' ';')" "m > p;p > m;m > p;p > m;"

# ---- 2. a chain of two relays: 1 - 2 - 3 - 4 ----
radio_start chain --node m,r2,r3,p4 --link m-r2-r3-p4 --baud 9600 --keyup-ms 50 || finish
CH=$RADIO_PID
printf 'N7:0=1234,-5\n' > "$T/plc4.data"
node r2 chain r2 --station 2 --forward 1,3,4; R2=$NODE_PID
node r3 chain r3 --station 3 --forward 1,2,4; R3=$NODE_PID
node p4 chain p4 --station 4 --data "$T/plc4.data"; P4=$NODE_PID
expect 0 "chain: read station 4 through relays 2 and 3" -- "$R" -d "$T/chain.m" $RADIO --src 1 -a 4 N7:0,2
out_is "chain: the values" "1234
-5"
stop_all "$R2" "$R3" "$P4" "$CH"
hops chain > "$T/chain.hops"
cmdh=$(awk 'NR == 1 { print $2, $3, $4, $5 }' "$T/chain.hops")
reph=$(awk '$1 == "p4" { print $2, $3, $4, $5; exit }' "$T/chain.hops")
check "chain: the command is 1 > 4 ($cmdh)" "case '$cmdh' in 'dst=4 src=1 cmd=0f '*) true;; *) false;; esac"
check "chain: the reply is 4 > 1 ($reph)" "case '$reph' in 'dst=1 src=4 cmd=4f '*) true;; *) false;; esac"
# the order on the air: m, r2, r3 (the command), p4, r3, r2 (the reply)
same "chain: hop by hop, each relay once each way" \
	"$(awk '{ print $1, $2, $3 }' "$T/chain.hops" | tr '\n' ';')" \
	"m dst=4 src=1;r2 dst=4 src=1;r3 dst=4 src=1;p4 dst=1 src=4;r3 dst=1 src=4;r2 dst=1 src=4;"
same "chain: the relays' copies are the packets unchanged" \
	"$(air chain | awk '{ $1 = $2 = $3 = ""; print }' | sort | uniq -c | awk '{ print $1 }' | tr '\n' ' ')" "3 3 "
same "chain: no relay sent the same packet twice" \
	"$(air chain | awk '{ $2 = $3 = ""; print }' | sort | uniq -d | wc -l)" 0
same "chain: each relay sent twice (the command, the reply): the copies heard back were dropped" \
	"$(grep -c ' r2 >' "$T/chain.log") $(grep -c ' r3 >' "$T/chain.log")" "2 2"
same "chain: PLC 4 ran the read once" "$(grep -c 'station=4 cmd=0F/A2' "$T/p4.log")" 1
check "chain: the relays executed nothing" "! grep -q 'cmd=' '$T/r2.log' && ! grep -q 'cmd=' '$T/r3.log'"

# ---- 3. a silent station behind the relays: a timeout, no retry ----
radio_start mute --node m,r2,r3,p4 --link m-r2-r3-p4 --baud 9600 --keyup-ms 50 || finish
CH=$RADIO_PID
node mr2 mute r2 --station 2 --forward 1,3,4; R2=$NODE_PID
node mr3 mute r3 --station 3 --forward 1,2,4; R3=$NODE_PID
node mp4 mute p4 --station 4; P4=$NODE_PID
kill -USR1 "$P4"
expect 1 "mute: read the silent station 4" -- "$R" -d "$T/mute.m" --duplex radio -o 1500 --src 1 -a 4 -vv N7:0
err_has "mute: timeout 2508" "[2508] ERR_COMMAND_TIMEOUT"
same "mute: the master sent the command once (--app-retries 0)" "$(grep -c 'tx  FRAME' "$T/err")" 1
check "mute: its copy came back relayed, not taken as a reply" "grep -q 'rx  FRAME' '$T/err'"
stop_all "$R2" "$R3" "$P4" "$CH"
same "mute: on the air, the command relayed twice and no reply" \
	"$(hops mute | awk '{ print $1, $2, $3 }' | tr '\n' ';')" "m dst=4 src=1;r2 dst=4 src=1;r3 dst=4 src=1;"
check "mute: station 4 executed nothing" "! grep -q 'cmd=' '$T/mp4.log'"

# ---- 4. two relays in parallel: the write executed once ----
radio_start dia --node m,ra,rb,p4 --link m-ra-p4 --link m-rb-p4 --baud 9600 --keyup-ms 50 || finish
CH=$RADIO_PID
node ra dia ra --station 2 --forward 1,4; RA=$NODE_PID
node rb dia rb --station 3 --forward 1,4; RB=$NODE_PID
node dp4 dia p4 --station 4 --dup-detect yes; P4=$NODE_PID
expect 0 "dia: write station 4 through both relays" -- "$W" -d "$T/dia.m" $RADIO --src 1 -a 4 -vv N7:3=777
same "dia: the master sent the write once" "$(grep -c 'tx  FRAME' "$T/err")" 1
expect 0 "dia: read it back" -- "$R" -d "$T/dia.m" $RADIO --src 1 -a 4 N7:3
out_is "dia: the value" 777
# df1mon as the master: its radio counters say what it heard
expect 0 "dia: df1mon --counters (a link test) through both relays" -- \
	"$BIN/df1mon" -d "$T/dia.m" $RADIO --src 1 -a 4 --counters
stop_all "$RA" "$RB" "$P4" "$CH"
same "dia: PLC 4 executed the write once" "$(grep -c 'station=4 cmd=0F/AA addr=N7:3' "$T/dp4.log")" 1
same "dia: PLC 4 replied once to each command" \
	"$(hops dia | awk '$1 == "p4"' | wc -l)" 3
same "dia: both relays relayed each command and each reply" \
	"$(hops dia | awk '$1 == "ra" || $1 == "rb" { print $1 }' | sort | uniq -c | awk '{ print $1 }' | tr '\n' ' ')" "6 6 "
check "dia: the master heard both copies of the link test's reply" \
	"grep -Eq '^0 RADIO_PACKETS_RCVD [2-9]' '$T/out'"

# ---- 5. a broadcast: executed by each PLC in range, never answered ----
radio_start bc --node m,p1,p2,p3 --link m-p1 --link m-p2 --baud 9600 --keyup-ms 50 || finish
CH=$RADIO_PID
node bp1 bc p1 --station 1; B1=$NODE_PID
node bp2 bc p2 --station 2; B2=$NODE_PID
node bp3 bc p3 --station 3; B3=$NODE_PID
expect 0 "bc: write to station 255" -- "$W" -d "$T/bc.m" $RADIO -a 255 -vv N7:1=55
check "bc: no reply taken" "! grep -q 'rx  FRAME' '$T/err'"
for s in 1 2; do
	expect 0 "bc: read station $s" -- "$R" -d "$T/bc.m" $RADIO -a $s N7:1
	out_is "bc: station $s ran the broadcast" 55
done

# ---- 6. df1mon --who over the radio ----
expect 0 "bc: df1mon --who 1-3" -- "$BIN/df1mon" -d "$T/bc.m" --duplex radio -o 800 --who 1-3
check "who: station 1 found" "grep -q '^station 1: SLC' '$T/out'"
check "who: station 2 found" "grep -q '^station 2: SLC' '$T/out'"
check "who: station 3 (out of range) not found" "! grep -q '^station 3: SLC' '$T/out'"
cp "$T/out" "$T/who.out"
stop_all "$B1" "$B2" "$B3" "$CH"
check "bc: station 3, out of range, did not run it" "! grep -q 'cmd=0F/AA' '$T/bp3.log'"
same "bc: the broadcast went on the air once" "$(hops bc | awk '$2 == "dst=255"' | wc -l)" 1
# its TNS (the bytes after DST SRC CMD STS) in no reply (CMD 4F) on the air
btns=$(air bc | awk '$1 == "m" && $4 == "10" && $5 == "02" && $6 == "ff" { print $10, $11; exit }')
check "bc: nobody answered it (TNS $btns in no reply)" \
	"[ -n '$btns' ] && ! air bc | awk '\$1 != \"m\"' | grep -q ' 4f .. $btns'"

# ---- 7. df1gw polling PLC 1 behind relays; the PLC's MSGs published once ----
if [ ! -x "$MOSQ" ] || ! command -v mosquitto_sub > /dev/null 2>&1; then
	bad "gw: no broker to test against (apt-get install mosquitto mosquitto-clients)"
	finish
fi
MQ_PORT=$(free_port)
broker_start broker "$MQ_PORT" || finish
printf 'N7:20=4242\n' > "$T/gwplc.data"
cat > "$T/gw.csv" <<'EOF2'
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
Report,Receive,INT,0,SLC,N50:0,3,
Level,Read,INT,1,SLC,N7:20,1,500
EOF2

# gw NAME RADIO_CHANNEL OPTIONS -- DF1GW OPTIONS: df1gw (station 0) on node g
# of a channel whose relays are up; the PLC at node p1 starts once df1gw is
# online (no MSG before anyone listens), numbers its MSG writes in N7:0 (seq)
# and sends one every 400 ms to station 0; stopped after 8 done
gw() {
	gname=$1; shift
	copts=
	while [ "$1" != -- ]; do copts="$copts $1"; shift; done
	shift
	mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t "$gname/#" -v > "$T/$gname.sub" 2>&1 &
	SUB=$!
	echo "$SUB" >> "$T/.sims"
	# three hops each way: a reply is due within about 0.6 s; 3 s is ample.
	# The watchdog is shorter than the run, so a station judged silent shows
	# shellcheck disable=SC2086
	"$BIN/df1gw" --mqtt "mqtt://127.0.0.1:$MQ_PORT" -d "$T/$gname.g" $RADIO --src 0 --watchdog 4000 \
		--map "$T/gw.csv" --prefix "$gname" "$@" > "$T/$gname.gwout" 2> "$T/$gname.gwerr" &
	GW=$!
	echo "$GW" >> "$T/.sims"
	wait_for "$gname: df1gw is online" 100 grep -qs "^$gname/status online" "$T/$gname.sub"
	# shellcheck disable=SC2086
	node "${gname}p1" "$gname" p1 --station 1 --data "$T/gwplc.data" \
		--msg write,N7:0,3,0,N50:0,400,seq $copts; P1=$NODE_PID
	wait_for "$gname: 8 MSGs done at the PLC" 300 sh -c "[ \$(grep -c ': DN\$' '$T/${gname}p1.err') -ge 8 ]"
	kill -TERM "$GW"; lib_reap "$GW"
	sim_stop "$P1"
	kill -TERM "$SUB"; lib_reap "$SUB"
	sub=$T/$gname.sub; perr=$T/${gname}p1.err
	check "$gname: the polled value published" "grep -q '^$gname/tag/Level {\"value\":4242,' '$sub'"
	sed -n "s/^$gname\/tag\/Report {\"value\":\[\([0-9]*\),.*\"from\":1}\$/\1/p" "$sub" > "$T/$gname.got"
	sed -n 's/^df1sim: MSG write .*(first \([0-9]*\)): DN$/\1/p' "$perr" > "$T/$gname.dn"
	got=$(wc -l < "$T/$gname.got"); dn=$(wc -l < "$T/$gname.dn")
	check "$gname: at least 8 MSGs published ($got)" "[ $got -ge 8 ]"
	check "$gname: each published once, in order (1..$got)" "seq 1 $got | cmp -s - '$T/$gname.got'"
	check "$gname: DN at the PLC for each ($dn of $got)" "seq 1 $dn | cmp -s - '$T/$gname.dn' && [ $got -le \$(($dn + 1)) ]"
	check "$gname: no MSG failed at the PLC (but one the stop cut short)" "! grep ': ER' '$perr' | grep -vq 'ER DF1_E_INTR\$'"
	check "$gname: station 1's health said ok" "grep -q '^$gname/station/1 {\"station\":1,\"state\":\"ok\"' '$sub'"
	# before the PLC was up it may have been failing; once ok, never again
	check "$gname: station 1, once ok, never failing or offline" \
		"! sed -n '/^$gname\/station\/1 .*\"state\":\"ok\"/,\$p' '$sub' | grep -Eq '^$gname/station/1 .*\"state\":\"(failing|offline)\"'"
}

# a chain: g - r2 - r3 - p1 (1 hears only 3, df1gw only 2)
radio_start gwc --node g,r2,r3,p1 --link g-r2-r3-p1 --baud 9600 --keyup-ms 50 || finish
CH=$RADIO_PID
node gwcr2 gwc r2 --station 2 --forward 0,1; R2=$NODE_PID
node gwcr3 gwc r3 --station 3 --forward 0,1; R3=$NODE_PID
gw gwc --
stop_all "$R2" "$R3" "$CH"
check "gwc: the relays executed nothing" "! grep -q 'cmd=' '$T/gwcr2.log' && ! grep -q 'cmd=' '$T/gwcr3.log'"

# two relays in parallel: df1gw hears each MSG twice and takes it once
# (duplicate detection on), the PLC each poll twice
radio_start gwp --node g,ra,rb,p1 --link g-ra-p1 --link g-rb-p1 --baud 9600 --keyup-ms 50 || finish
CH=$RADIO_PID
node gwpra gwp ra --station 2 --forward 0,1; RA=$NODE_PID
node gwprb gwp rb --station 3 --forward 0,1; RB=$NODE_PID
gw gwp --dup-detect yes -- --dup-detect yes
stop_all "$RA" "$RB" "$CH"
# a relay's packets close together are one transmission on the air (the
# channel's gap rule): count the MSG frames (DST 0 SRC 1 CMD 0F) within them
relayed() { grep " $1 > g,p1 " "$T/gwp.log" | grep -o '10 02 00 01 0f' | wc -l; }
check "gwp: both relays relayed the MSGs ($(relayed ra), $(relayed rb))" \
	"[ $(relayed ra) -ge 8 ] && [ $(relayed rb) -ge 8 ]"

finish
