#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# rfc2217:// targets: the client (lib/port/port_rfc2217.c) against Debian's
# ser2net (a telnet(rfc2217) accepter on a pty that df1sim serves), and
# against df1sim's own RFC 2217 listener. The baud the client asks for is the
# one df1sim reads in the pty's termios (its -v line); values whose bytes are
# 0xFF (doubled as Telnet IAC) go both ways; a dropped device-server
# connection is reported and reopened (df1gw, as a lost line). SKIP without
# ser2net.
. tests/support/lib.sh
for t in df1read df1write df1sim df1mon; do
	[ -x "$BIN/$t" ] || { echo "no $BIN/$t"; exit 1; }
done
unset DF1_DEVICE

# ---- df1sim's own listener (no ser2net needed) ----
rm -f "$T/own.out"
"$BIN/df1sim" --listen rfc2217://127.0.0.1:0 --line-settings 9600,8E1 -v > "$T/own.out" 2> "$T/own.err" &
OWN=$!
echo "$OWN" >> "$T/.sims"
wait_for "df1sim rfc2217 listener" 100 test -s "$T/own.out"
D=$(head -n 1 "$T/own.out")
check "the ready line names the scheme" "case '$D' in rfc2217://127.0.0.1:*) true;; *) false;; esac"
expect 0 "write 0xFFFF through df1sim's listener" -- "$BIN/df1write" -d "$D" -b 9600 -P even N7:1=-1
expect 0 "read it back" -- "$BIN/df1read" -d "$D" -b 9600 -P even N7:1
out_is "N7:1 through df1sim's listener" "-1"
expect 1 "the wrong parity gets no answer" -- "$BIN/df1read" -d "$D" -b 9600 -P odd -o 300 N7:1
check "df1sim saw the parity the client set" "grep -q 'the client set 9600 8O1' '$T/own.err'"
sim_stop "$OWN"

if ! command -v ser2net >/dev/null 2>&1; then
	skip "ser2net not installed: the ser2net half of it_rfc2217.sh"
	finish
fi

# ---- ser2net on the pty df1sim serves ----
sim_start line --line-settings 9600 -v || exit 1
PORT=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
cat > "$T/ser2net.yaml" <<EOF2
connection: &plc
  accepter: telnet(rfc2217),tcp,127.0.0.1,$PORT
  connector: serialdev,$SIM_DEV,19200n81,local
  options:
    kickolduser: true
EOF2
start_ser2net() {
	ser2net -n -d -c "$T/ser2net.yaml" > "$T/ser2net.log" 2>&1 &
	S2N=$!
	echo "$S2N" >> "$T/.sims"
	wait_for "ser2net listening" 100 python3 -c "
import socket, sys
s = socket.socket()
sys.exit(s.connect_ex(('127.0.0.1', $PORT)))"
}
start_ser2net
D="rfc2217://127.0.0.1:$PORT"
expect 0 "read through ser2net at 9600" -- "$BIN/df1read" -d "$D" -b 9600 N7:5
out_is "N7:5 through ser2net" "5"
check "df1sim's termios said 9600" "grep -q \"termios says 9600 baud\" '$T/line.err'"
expect 1 "at 19200 the line garbles" -- "$BIN/df1read" -d "$D" -b 19200 -o 300 N7:5
check "df1sim's termios said 19200" "grep -q \"termios says 19200 baud\" '$T/line.err'"

# 0xFF in the data both ways (Telnet IAC doubled and undoubled), and many
# transactions so CRC bytes of 0xFF pass too
expect 0 "write 0xFF bytes through ser2net" -- "$BIN/df1write" -d "$D" -b 9600 N7:10=-1,255,-256,-1
expect 0 "read 0xFF bytes through ser2net" -- "$BIN/df1read" -d "$D" -b 9600 N7:10,4
out_is "N7:10..13 through ser2net" "-1
255
-256
-1"
expect 0 "40 echoes through ser2net" -- "$BIN/df1mon" -d "$D" -b 9600 --ping -c 40 -i 0

# ---- --autoconf through ser2net: every setting tried goes to the device server ----
said() { grep -c "termios says $1 baud" "$T/line.err"; }
before=$(said 19200)
# --poll-timeout 500: each attempt stays on the line long enough for df1sim
# to read its bytes and look at the termios they came with, on a loaded
# machine too (it looks when bytes arrive; at the default ~85 ms a slow
# df1sim saw the next rate already)
expect 0 "autoconf through ser2net" -- "$BIN/df1mon" -d "$D" --autoconf --stations 1-1 --poll-timeout 500
out_is "autoconf through ser2net: the settings" "-b 9600 -P none --check crc --duplex full"
check "df1sim's termios followed the search (19200 first, then 9600)" \
	"[ $(said 19200) -gt $before ] && tail -n 1 '$T/line.err' | grep -q 'termios says 9600 baud'"
# and a network file naming the target (Com_Port through the scheme table)
printf 'Station,Mode,Error_Code,Com_Port,Baud,Parity\n0,Peer,CRC,%s,9600,None\n' "$D" > "$T/net.csv"
expect 0 "df1read -N with Com_Port rfc2217://" -- "$BIN/df1read" -N "$T/net.csv" N7:6
out_is "N7:6 through the network file" "6"

# ---- a dropped device-server connection is reported ----
"$BIN/df1mon" -d "$D" -b 9600 --ping -c 0 -i 0.1 > "$T/ping.out" 2> "$T/ping.err" &
PING=$!
echo "$PING" >> "$T/.sims"
wait_for "pings going" 100 test -s "$T/ping.out"
sim_stop "$S2N"
wait_for "the loss is reported" 100 grep -q -i 'closed by peer' "$T/ping.err" "$T/ping.out"
sim_stop "$PING"
# and the target opens again once the device server is back
start_ser2net
expect 0 "read after the device server came back" -- "$BIN/df1read" -d "$D" -b 9600 N7:5

# ---- df1gw on an rfc2217:// line: the device server dropped is a lost line, reopened ----
MOSQ=${MOSQUITTO:-/usr/sbin/mosquitto}
if [ -x "$MOSQ" ] && command -v mosquitto_sub >/dev/null 2>&1 && [ -x "$BIN/df1gw" ]; then
	MQ_PORT=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
	printf 'listener %s 127.0.0.1\npersistence false\nuser %s\nallow_anonymous true\n' \
		"$MQ_PORT" "$(id -un)" > "$T/mosq.conf"
	"$MOSQ" -c "$T/mosq.conf" > "$T/mosq.log" 2>&1 &
	echo "$!" >> "$T/.sims"
	wait_for "broker listens" 100 python3 -c "
import socket, sys
sys.exit(socket.socket().connect_ex(('127.0.0.1', $MQ_PORT)))"
	printf 'Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms\nFive,Read,INT,1,SLC,N7:5,1,100\n' > "$T/map.csv"
	"$BIN/df1gw" -d "$D" -b 9600 --map "$T/map.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" \
		--prefix rfc > "$T/gw.out" 2> "$T/gw.err" &
	GW=$!
	echo "$GW" >> "$T/.sims"
	good() { mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t rfc/tag/Five -C 1 -W 2 2>/dev/null |
		grep -F -q '"value":5,"quality":"GOOD"'; }
	wait_for "df1gw reads through rfc2217" 100 good
	sim_stop "$S2N"
	wait_for "df1gw reports the device server gone" 100 grep -q "line lost; reopening" "$T/gw.err"
	start_ser2net
	wait_for "df1gw reads again once the device server is back" 200 good
	check "df1gw still running" "kill -0 $GW"
	sim_stop "$GW"
else
	skip "mosquitto or df1gw missing: df1gw's lost rfc2217 line not tried"
fi
sim_stop "$S2N"
sim_stop

finish
