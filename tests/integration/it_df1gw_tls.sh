#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_df1gw_tls.sh - df1gw against a TLS broker that is not there yet, dies
# (kill -9) and comes back, and one whose certificate the --cafile does not
# verify (df1gw(1), BROKER CONNECTION). Real parts: a CA and a server
# certificate made here with openssl, Debian's mosquitto with a TLS listener
# on a free loopback port, df1sim on a pseudo-terminal, mosquitto_sub over
# TLS as the observer. CPU time comes from /proc/PID/stat (utime + stime).
. tests/support/lib.sh

if [ ! -x "$MOSQ" ] || ! command -v mosquitto_sub >/dev/null 2>&1 || ! command -v openssl >/dev/null 2>&1; then
	echo "mosquitto, mosquitto-clients or openssl missing"
	bad "no TLS broker to test against"
	finish
fi
GW="$BIN/df1gw"

# ---- a CA, a server certificate it signs (for 127.0.0.1), another CA ----
(
	cd "$T" &&
	openssl req -x509 -newkey rsa:2048 -nodes -keyout ca.key -out ca.crt -days 2 -subj "/CN=df1 test CA" &&
	openssl req -newkey rsa:2048 -nodes -keyout srv.key -out srv.csr -subj "/CN=127.0.0.1" &&
	printf 'subjectAltName=IP:127.0.0.1,DNS:localhost\n' > srv.ext &&
	openssl x509 -req -in srv.csr -CA ca.crt -CAkey ca.key -CAcreateserial -out srv.crt -days 2 -extfile srv.ext &&
	openssl req -x509 -newkey rsa:2048 -nodes -keyout other.key -out other.crt -days 2 -subj "/CN=another CA" &&
	openssl req -newkey rsa:2048 -nodes -keyout host.key -out host.csr -subj "/CN=plc.example" &&
	printf 'subjectAltName=DNS:plc.example\n' > host.ext &&
	openssl x509 -req -in host.csr -CA ca.crt -CAkey ca.key -CAcreateserial -out host.crt -days 2 -extfile host.ext
) > "$T/openssl.log" 2>&1 || { bad "openssl could not make the certificates"; sed 's/^/  /' "$T/openssl.log" | tail -5; finish; }

PORT=$(free_port)
PORT2=$(free_port)
# a second listener whose certificate names another host (plc.example)
cat > "$T/broker.conf" <<EOF
per_listener_settings false
persistence false
user $(id -un)
allow_anonymous true
listener $PORT 127.0.0.1
cafile $T/ca.crt
certfile $T/srv.crt
keyfile $T/srv.key
listener $PORT2 127.0.0.1
cafile $T/ca.crt
certfile $T/host.crt
keyfile $T/host.key
EOF
sub1() { mosquitto_sub -h 127.0.0.1 -p "$PORT" --cafile "$T/ca.crt" -t "$1" -C 1 -W 2 2>/dev/null; }
has() { sub1 "$1" | grep -F -q -e "$2"; }
# cpu PID: clock ticks of user and system time so far
cpu() { awk '{ print $14 + $15 }' "/proc/$1/stat"; }
HZ=$(getconf CLK_TCK 2>/dev/null || echo 100)

printf 'N7:0=42\n' > "$T/plc.txt"
printf 'Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms\nSpeed,ReadWrite,INT,1,SLC,N7:0,1,500\n' > "$T/map.csv"
sim_start plc --data "$T/plc.txt" || finish

# ---- started before its broker: says so once, waits without burning CPU ----
P=df1/tls
"$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtts://127.0.0.1:$PORT" --cafile "$T/ca.crt" --prefix "$P" \
	> "$T/gw.out" 2> "$T/gw.err" &
GW_PID=$!
echo "$GW_PID" >> "$T/.sims"
gw_said() { grep -F -q -e "$1" "$T/gw.err"; }
wait_for "no broker: said without -v" 50 gw_said "cannot connect: Connection refused"
c0=$(cpu "$GW_PID")
# 5 s of waiting: at most a second of CPU (the spin took 93-100 % of a core)
n=50; while [ $n -gt 0 ]; do tick; n=$((n - 1)); done
c1=$(cpu "$GW_PID")
check "waiting for the broker: under 1 s of CPU in 5 s ($((c1 - c0)) ticks of 1/$HZ s)" '[ $((c1 - c0)) -lt "$HZ" ]'
same "the refusal said once, not at every try" "$(grep -c "cannot connect" "$T/gw.err")" 1

broker_run broker "$PORT"
wait_for "connected once the broker is up (backoff at most 30 s)" 400 has "$P/status" online
wait_for "Speed published over TLS" 50 has "$P/tag/Speed" '"value":42,"quality":"GOOD"'
wait_for "the recovery said" 50 gw_said "connected after"

# ---- kill -9 of the broker, 3 s down, back ----
kill -9 "$BROKER_PID"
wait "$BROKER_PID" 2>/dev/null
wait_for "the loss said" 50 gw_said "connection lost"
c0=$(cpu "$GW_PID")
n=30; while [ $n -gt 0 ]; do tick; n=$((n - 1)); done
c1=$(cpu "$GW_PID")
check "broker down 3 s: under 1 s of CPU ($((c1 - c0)) ticks of 1/$HZ s)" '[ $((c1 - c0)) -lt "$HZ" ]'
broker_run broker "$PORT"
wait_for "connected again after kill -9" 400 gw_said "connected again after"
wait_for "status online again" 50 has "$P/status" online
# a second outage: survived as the first
kill -9 "$BROKER_PID"
wait "$BROKER_PID" 2>/dev/null
broker_run broker "$PORT"
twice_again() { [ "$(grep -c "connected again after" "$T/gw.err")" -ge 2 ]; }
wait_for "connected again after a second kill -9" 400 twice_again
check "alive" 'kill -0 "$GW_PID"'
kill -TERM "$GW_PID"
lib_reap "$GW_PID"

# ---- a CA that does not verify the broker: a certificate error without -v;
# the CA file corrected: connected at the next try ----
cp "$T/other.crt" "$T/cafile.crt"
"$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtts://127.0.0.1:$PORT" --cafile "$T/cafile.crt" --prefix df1/bad \
	> "$T/gw2.out" 2> "$T/gw2.err" &
GW2=$!
echo "$GW2" >> "$T/.sims"
bad_ca_said() { grep -q "cannot connect: TLS handshake failed: certificate verify failed" "$T/gw2.err"; }
wait_for "wrong CA: certificate verify failed, without -v" 100 bad_ca_said
c0=$(cpu "$GW2")
n=30; while [ $n -gt 0 ]; do tick; n=$((n - 1)); done
c1=$(cpu "$GW2")
check "wrong CA: retrying under 1 s of CPU ($((c1 - c0)) ticks)" '[ $((c1 - c0)) -lt "$HZ" ]'
same "wrong CA: said once" "$(grep -c "cannot connect" "$T/gw2.err")" 1
[ "$(grep -c "cannot connect" "$T/gw2.err")" = 1 ] || sed "s/^/  gw: /" "$T/gw2.err"
check "wrong CA: nothing published" '[ -z "$(sub1 "df1/bad/#")" ]'
# the CA file put right: taken at the next try, without a restart
cp "$T/ca.crt" "$T/cafile.crt"
ca_fixed() { grep -q "connected after [0-9]* s" "$T/gw2.err"; }
wait_for "the CA file corrected: connected without a restart" 400 ca_fixed
wait_for "published once the CA is right" 50 has "df1/bad/status" online
kill -TERM "$GW2"
lib_reap "$GW2"

# ---- a certificate for another host name: said so without -v ----
"$GW" -d "$SIM_DEV" --map "$T/map.csv" --mqtt "mqtts://127.0.0.1:$PORT2" --cafile "$T/ca.crt" --prefix df1/host \
	> "$T/gw3.out" 2> "$T/gw3.err" &
GW3=$!
echo "$GW3" >> "$T/.sims"
host_said() { grep -q "cannot connect: TLS handshake failed: certificate verify failed (hostname mismatch" "$T/gw3.err"; }
wait_for "a certificate for another host: hostname mismatch, without -v" 100 host_said || sed 's/^/  gw: /' "$T/gw3.err"
kill -TERM "$GW3"
lib_reap "$GW3"

# ---- the serial line: a device not there yet is said once, its arrival too ----
"$GW" -d "$T/later" --map "$T/map.csv" --mqtt "mqtts://127.0.0.1:$PORT" --cafile "$T/ca.crt" --prefix df1/later \
	> "$T/gw4.out" 2> "$T/gw4.err" &
GW4=$!
echo "$GW4" >> "$T/.sims"
line_said() { grep -q "later.*; trying again" "$T/gw4.err"; }
wait_for "no device: said without -v" 50 line_said
n=30; while [ $n -gt 0 ]; do tick; n=$((n - 1)); done
same "no device: said once in 3 s of tries" "$(grep -c "trying again" "$T/gw4.err")" 1
sim_start later --data "$T/plc.txt" || finish
line_back() { grep -q "later: open after [0-9]* s" "$T/gw4.err"; }
wait_for "the device there: its recovery said" 400 line_back
wait_for "its tag published" 100 has "df1/later/tag/Speed" '"value":42,"quality":"GOOD"'
kill -TERM "$GW4"
lib_reap "$GW4"

finish
