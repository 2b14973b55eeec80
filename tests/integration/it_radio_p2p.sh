#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_radio_p2p - the DF1 Radio Modem (doc/PROTOCOL.md 2.6, libdf1(7) RADIO MODEM)
# point to point on a pseudo-terminal: df1sim --duplex radio as the PLC,
# df1read / df1write / df1mon --duplex radio as the master. What df1sim ran is
# checked in its --log (one line per command answered). No ACK, NAK or ENQ may
# cross the line either way (the -vv trace of the master); a write to station
# 255 is executed and not answered; a command for a station nobody serves
# times out (2508); df1sim --forward 3 sends a command for station 3 back on
# the line unchanged (the master sees its own frame come back) and does not
# run it. df1sim's MSG writes (report by exception) reach df1mon --serve.
# Bad --duplex / --forward / --dup-detect values exit 2.
# Run from the repository root; DF1_BIN = the built tools.
. tests/support/lib.sh
W="$BIN/df1write"
R="$BIN/df1read"
M="$BIN/df1mon"
for t in df1write df1read df1sim df1mon; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE
RADIO="--duplex radio -o 500 --cmd-timeout 500"

# 1. a radio PLC at station 1: write, read back, no link symbols on the line
sim_start plc --duplex radio --station 1 --log "$T/plc.log" || { finish; }
expect 0 "write N7:0" -- "$W" -d "$SIM_DEV" $RADIO -a 1 N7:0=1234
expect 0 "read N7:0" -- "$R" -d "$SIM_DEV" $RADIO -a 1 -vv N7:0
out_is "N7:0 read back" "1234"
check "no DLE ACK, NAK or ENQ either way" "! grep -Eq '  (ACK|NAK|ENQ|EOT)  ' '$T/err'"
err_has "the reply came as a frame" "rx  FRAME  CRC ok  dst   0  src   1"
logged_two() { [ "$(grep -c 'station=1 cmd=0F/A' "$T/plc.log")" -eq 2 ]; }
wait_for "df1sim logged the write and the read" 50 logged_two
check "the log: the write first" "head -n 1 '$T/plc.log' | grep -q 'cmd=0F/AA addr=N7:0 count=1'"

# a pty has no modem lines: keying asked for, the frames go out unkeyed, said once
expect 0 "two writes with --radio-rts and --dcd-wait on a pty" -- \
	"$W" -d "$SIM_DEV" $RADIO -a 1 --radio-rts yes --dcd-wait 100 -v N7:2=5 N7:8=6
same "no modem lines: said once" "$(grep -c 'has no modem lines' "$T/err")" 1
expect 0 "read them back" -- "$R" -d "$SIM_DEV" $RADIO -a 1 N7:2 N7:8
out_is "both written" "5
6"

# a network file's Link column (an extension, libdf1(7)): Radio is the radio
# modem; a Store_Forward without it is refused, naming the column
printf 'Station,Mode,Error_Code,Com_Port,Baud,Link,Cmd_Timeout\n0,Master,CRC,%s,19200,Radio,500\n' "$SIM_DEV" > "$T/net.csv"
expect 0 "df1read -N with Link Radio" -- "$R" -N "$T/net.csv" -a 1 -o 500 -vv N7:0
out_is "N7:0 through the network file" "1234"
check "Link Radio: no DLE ACK, NAK or ENQ either way" "! grep -Eq '  (ACK|NAK|ENQ|EOT)  ' '$T/err'"
printf 'Station,Link,Store_Forward\n0,Full,3\n' > "$T/badnet.csv"
expect 2 "Store_Forward without Link Radio" -- "$R" -N "$T/badnet.csv" -d "$SIM_DEV" -a 1 N7:0
err_has "names the column" "Store_Forward (3) needs Link Radio"

# 2. a broadcast write: executed, never answered (the master is done at once)
expect 0 "write to station 255" -- "$W" -d "$SIM_DEV" $RADIO -a 255 -vv N7:1=77
check "the broadcast drew no reply" "! grep -q 'rx  FRAME' '$T/err'"
expect 0 "read N7:1" -- "$R" -d "$SIM_DEV" $RADIO -a 1 N7:1
out_is "the broadcast ran" "77"
expect 2 "a read of station 255" -- "$R" -d "$SIM_DEV" $RADIO -a 255 N7:1
err_has "says nobody answers a broadcast read" "is a broadcast: nobody answers a read"
expect 2 "station 255 without --duplex radio" -- "$W" -d "$SIM_DEV" -a 255 N7:1=1
err_has "says broadcast needs radio" "needs --duplex radio"

# 3. nobody at station 2: the command goes out once and times out
expect 1 "read station 2" -- "$R" -d "$SIM_DEV" $RADIO -a 2 -vv N7:0
err_has "timeout 2508" "[2508] ERR_COMMAND_TIMEOUT"
same "the command went out once" "$(grep -c 'tx  FRAME' "$T/err")" 1
expect 1 "read station 2, two application retries" -- \
	"$R" -d "$SIM_DEV" $RADIO --app-retries 2 -a 2 -vv N7:0
same "the command went out three times" "$(grep -c 'tx  FRAME' "$T/err")" 3

# 4. df1mon: counters of a radio line (a link test is an echo; the radio rows)
expect 0 "df1mon --counters" -- "$M" -d "$SIM_DEV" $RADIO -a 1 --counters
check "radio rows printed" "grep -q '^0 RADIO_PACKETS_SENT 1$' '$T/out'"
check "a reply received" "grep -q '^0 RADIO_PACKETS_RCVD 1$' '$T/out'"
sim_stop

# 5. a relay: df1sim at station 1 forwards packets for station 3
sim_start relay --duplex radio --station 1 --forward 3 --log "$T/relay.log" || { finish; }
expect 1 "read station 3 through the relay (nobody answers)" -- \
	"$R" -d "$SIM_DEV" $RADIO -a 3 -vv N7:0
tx=$(grep 'tx  FRAME' "$T/err" | head -n 1 | sed 's/^[^ ]* *[0-9]* *[0-9.]* *tx//')
rx=$(grep 'rx  FRAME' "$T/err" | head -n 1 | sed 's/^[^ ]* *[0-9]* *[0-9.]* *rx//')
check "the relay sent a frame back" "[ -n \"$rx\" ]"
same "relayed unchanged" "$rx" "$tx"
expect 0 "the relay still answers for itself" -- "$R" -d "$SIM_DEV" $RADIO -a 1 N7:0
check "the relay ran no command for station 3" "! grep -q 'station=3' '$T/relay.log'"
sim_stop

# 6. report by exception: df1sim's MSG writes reach df1mon --serve, a radio node at station 0
sim_start msg --duplex radio --station 1 --msg write,N7:0,3,0,N50:0,200 || { finish; }
expect 0 "df1mon --serve takes df1sim's MSG writes" -- \
	"$M" -d "$SIM_DEV" --duplex radio --serve N50:0,10 --src 0 --duration 2
check "a write from station 1 landed" "grep -q 'from 1 to 0: N50:0 = 0 1 2' '$T/out'"
sim_stop

# 7. bad values
expect 2 "--duplex bogus" -- "$R" -d /dev/null --duplex bogus N7:0
err_has "names the values" "full, half or radio"
expect 2 "--forward 256" -- "$BIN/df1sim" --pty "$T/x" --duplex radio --forward 256
err_has "names the option" "--forward"
expect 2 "--forward without radio" -- "$BIN/df1sim" --pty "$T/x" --forward 3
expect 2 "--dup-detect maybe" -- "$BIN/df1sim" --pty "$T/x" --duplex radio --dup-detect maybe
err_has "names the values" "yes, no or auto"
expect 2 "df1mon --forward without --serve" -- "$M" -d /dev/null --duplex radio --forward 3 --counters

finish
