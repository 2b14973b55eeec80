#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_df1gw_health.sh - df1gw's health side against real parts: df1sim on a
# pseudo-terminal (stations 1 and 3, station 3 silenced) whose --log is the
# record of what the line did; systemd's notification socket played by
# tests/support/notify_probe.py; /metrics read by prometheus_client's parser
# (tests/support/prom_probe.py); the status page in headless Chromium over
# the DevTools protocol (tests/support/page_probe.py: its tags, its charts,
# its layout at 1000 and 1400 px, a reason with markup; its screenshots kept
# in the build's log folder); a request flood with slow clients
# (tests/support/http_flood.py); `systemd-analyze verify` of the unit; and
# df1mon --counters -f prometheus. Waits are bounded loops, never sleeps
# that hope. Run from the repository root with DF1_BIN=<build/bin>.
. tests/support/lib.sh

GW="$BIN/df1gw"
PROM="python3 tests/support/prom_probe.py"
EPROBE="python3 tests/support/eipgw_probe.py"
ART=$(dirname "$BIN")/test-logs        # the screenshots: the build's log folder
mkdir -p "$ART"

have_prom=no
python3 -c 'import prometheus_client' 2>/dev/null && have_prom=yes

# gw_start NAME OPTIONS...: df1gw in the background; GW_PID; HTTP and EIP
# the addresses it says it listens on
gw_start() {
	gname=$1; shift
	"$GW" "$@" > "$T/$gname.out" 2> "$T/$gname.err" &
	GW_PID=$!
	echo "$GW_PID" >> "$T/.sims"
	wait_for "df1gw $gname says where HTTP listens" 100 gw_addr "$gname"
	EIP=$(sed -n 's|^df1gw: EtherNet/IP on \([0-9.]*:[0-9]*\).*|\1|p' "$T/$gname.err" | head -n 1)
}
gw_addr() {
	HTTP=$(sed -n 's|^df1gw: HTTP on \([^ ]*\) .*|\1|p' "$T/$1.err" 2>/dev/null | head -n 1)
	[ -n "$HTTP" ]
}
gw_stop() {
	kill -TERM "$1" 2>/dev/null
	lib_reap "$1"
}
# get PATH [METHOD]: the body of http://$HTTP/PATH in $T/body, headers in $T/head
get() {
	python3 - "$HTTP" "$1" "${2:-GET}" > "$T/body" 2> "$T/head" <<'PY'
import http.client, sys
c = http.client.HTTPConnection(sys.argv[1], timeout=20)
c.request(sys.argv[3], sys.argv[2])
r = c.getresponse()
sys.stderr.write("status %d\n" % r.status)
for k, v in r.getheaders():
	sys.stderr.write("%s: %s\n" % (k.lower(), v))
sys.stdout.write(r.read().decode())
PY
}
metric() { $PROM "http://$HTTP/metrics" "$1"; }
# scraped TEXT: /metrics holds the line TEXT (read as text: no parser needed)
scraped() {
	python3 -c 'import sys, urllib.request; sys.stdout.write(urllib.request.urlopen(sys.argv[1], timeout=10).read().decode())' \
		"http://$HTTP/metrics" 2>/dev/null | grep -qxF -e "$1"
}
# listeners PORT: the local addresses of TCP sockets listening on PORT (/proc/net/tcp, tcp6)
listeners() {
	hex=$(printf '%04X' "$1")
	cat /proc/net/tcp /proc/net/tcp6 2>/dev/null | awk -v p=":$hex" '$2 ~ p"$" && $4 == "0A" { print $2 }'
}
# logged PATTERN: lines of df1sim's log holding PATTERN
logged() { grep -c -e "$1" "$T/sim.log"; }

cat > "$T/plc.txt" <<'EOF2'
N7:0=123
N7:1=-5
F8:1=1.5
EOF2
# a tag name with markup in it: shown as text by the page
MARKUP='<img src=x onerror=alert(1)><b>x'
cat > "$T/map.csv" <<EOF2
Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms
Speed,ReadWrite,INT,1,SLC,N7:0,1,100
Level,Read,FLOAT,1,SLC,F8:1,1,100
$MARKUP,Read,INT,1,SLC,N7:1,1,100
Far,Read,INT,3,SLC,N7:0,1,100
EOF2

# ---- options ----
expect 0 "--help names --http" -- "$GW" --help
check "--help: --http [ADDR:]PORT" 'grep -q -- "--http \[ADDR:\]PORT" "$T/out"'
expect 2 "--http with a port out of range" -- "$GW" -d /dev/null --map "$T/map.csv" --eip 0 --http 70000
err_has "--http: what is wrong" "--http 70000"
expect 2 "--http with no port" -- "$GW" -d /dev/null --map "$T/map.csv" --eip 0 --http 127.0.0.1:
expect 2 "--http on an address not this host's" -- "$GW" -d /dev/null --map "$T/map.csv" --eip 0 --http 192.0.2.1:0

# ---------------------------------------------------------------------------
# /metrics, /api/status, headers; station 3 silenced
# ---------------------------------------------------------------------------
sim_start sim --station 1,3 --silent 3 --data "$T/plc.txt" --log "$T/sim.log" || finish
gw_start gw -d "$SIM_DEV" --map "$T/map.csv" --eip 0 --http 0 --timeout 200 --watchdog 1000
case $HTTP in
127.0.0.1:[1-9]*) ok ;;
*) bad "--http 0 listens on '$HTTP', not loopback" ;;
esac
check "df1gw says it is loopback only" 'grep -qF "(loopback only, read-only)" "$T/gw.err"'
HPORT=${HTTP##*:}
same "the only listener on the HTTP port is 127.0.0.1" "$(listeners "$HPORT" | sort -u)" "$(printf '0100007F:%04X' "$HPORT")"

# headers, methods, paths
get /
check "page: 200" 'grep -q "^status 200" "$T/head"'
check "page: a content policy without inline script" \
	'grep -q "^content-security-policy: default-src .none.; script-src .self.;" "$T/head" && ! grep -qi "unsafe-inline" "$T/head"'
check "page: no framing (frame-ancestors)" 'grep -q "frame-ancestors .none." "$T/head"'
check "page: X-Frame-Options DENY" 'grep -q "^x-frame-options: DENY" "$T/head"'
check "page: nosniff" 'grep -q "^x-content-type-options: nosniff" "$T/head"'
check "page: no CDN, nothing from elsewhere" '! grep -Eq "(src|href)=\"(https?:)?//" "$T/body"'
get /metrics POST
check "POST: 405 (read-only)" 'grep -q "^status 405" "$T/head"'
get /api/status PUT
check "PUT: 405" 'grep -q "^status 405" "$T/head"'
get /nothing
check "unknown path: 404" 'grep -q "^status 404" "$T/head"'

# the line's state as it settles: station 3 offline, station 1 ok
wait_for "station 3 offline in /metrics" 150 scraped 'df1_station_state{station="3",state="offline"} 1'
get /metrics
cp "$T/body" "$T/gw.prom"
if [ "$have_prom" = yes ]; then
	expect 0 "/metrics parses with prometheus_client and keeps the conventions" -- \
		$PROM "http://$HTTP/metrics" --lint
	same "station 1 ok" "$(metric 'df1_station_state{station=1,state=ok}')" 1
	same "station 1: no failures" "$(metric 'df1_station_failures_total{station=1}')" 0
	# one scrape: an attempt in flight is counted before its failure
	$PROM "http://$HTTP/metrics" 'df1_station_attempts_total{station=3}' 'df1_station_failures_total{station=3}' \
		> "$T/s3"
	a3=$(sed -n 1p "$T/s3")
	f3=$(sed -n 2p "$T/s3")
	check "silenced station 3: attempts made ($a3)" '[ "$a3" -gt 0 ]'
	check "silenced station 3: every attempt failed ($f3 of $a3; one may be under way)" \
		'[ "$f3" -gt 0 ] && [ "$f3" -le "$a3" ] && [ "$f3" -ge $((a3 - 1)) ]'
	same "silenced station 3: nothing in df1sim's log" "$(logged 'station=3 ')" 0
	# station 1's transactions against df1sim's log (one line per command answered)
	m1=$(metric 'df1_station_attempts_total{station=1}')
	l1=$(logged 'station=1 ')
	m2=$(metric 'df1_station_attempts_total{station=1}')
	check "station 1's attempts match df1sim's log ($m1 <= $l1 <= $m2 + 1)" \
		'[ "$m1" -le "$l1" ] && [ "$l1" -le $((m2 + 1)) ]'
	same "station 3's reply time: none (it never answered)" "$(metric 'df1_station_last_reply_seconds{station=3}')" NaN
	same "tags GOOD: the three of station 1" "$(metric 'df1_tags{quality=GOOD}')" 3
	same "tags BAD: the one of station 3" "$(metric 'df1_tags{quality=BAD}')" 1
	same "build info: the version of df1gw --version" "$(metric 'df1_build_info')" 1
	v=$("$GW" --version 2>&1 | head -n 1 | awk '{ print $NF }')
	same "build info's version label is df1gw --version's ($v)" "$(metric "df1_build_info{version=$v}")" 1
	c=$(metric df1_scan_duration_seconds_count)
	check "scan histogram counts scans ($c)" '[ "$c" -gt 0 ]'
	same "the line up" "$(metric df1_line_up)" 1
	check "link counter by its catalog mnemonic (CNT_CMD_MSGS_SENT, 2527)" \
		'[ "$(metric "df1_link_cnt_cmd_msgs_sent_total{id=2527}")" -gt 0 ]'
	st=$(metric df1_process_start_time_seconds)
	check "start time is now-ish ($st)" '[ "${st%.*}" -gt $(($(date +%s) - 600)) ] && [ "${st%.*}" -le $(date +%s) ]'
	# EtherNet/IP: one write through the bridge, seen in its counters
	expect 0 "a write N7:0 = 777 through EtherNet/IP" -- $EPROBE "$EIP" write - 0 777
	same "the write reached the PLC once" "$(logged 'station=1 cmd=0F/AA addr=N7:0 ')" 1
	check "EtherNet/IP sessions counted" '[ "$(metric df1_eip_sessions_total)" -ge 1 ]'
	check "EtherNet/IP requests counted" '[ "$(metric df1_eip_requests_total)" -ge 1 ]'
	same "EtherNet/IP forwarded one request" "$(metric df1_eip_forwarded_total)" 1
	same "no MQTT figures without a broker" "$(metric df1_mqtt_connected)" none
else
	skip "prometheus_client missing (pip install prometheus_client): /metrics not parsed"
	expect 0 "a write N7:0 = 777 through EtherNet/IP" -- $EPROBE "$EIP" write - 0 777
fi

# /api/status: the same tags as df1sim's data
get /api/status
cat > "$T/status.py" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
tags = {t["name"]: t for t in d["tags"]}
want = {"Speed": (777, "GOOD"), "Level": (1.5, "GOOD"), sys.argv[2]: (-5, "GOOD"), "Far": (None, "BAD")}
bad = [n for n, (v, q) in want.items() if n not in tags or tags[n]["value"] != v or tags[n]["quality"] != q]
st = {s["station"]: s for s in d["stations"]}
ok = not bad and st[1]["state"] == "ok" and st[3]["state"] == "offline" and d["line"]["up"] is True
ok = ok and any(m["name"] == "df1_scans_total" for m in d["metrics"]) and d["summary"].startswith("line ok")
# the charts' figures: a clock since the start, the scans so far
ok = ok and 0 < d["uptime_s"] < 600 and isinstance(d["scans"], int) and d["scans"] > 0
print("bad: %s %s" % (bad, d["summary"]) if not ok else "ok")
sys.exit(0 if ok else 1)
PY
wait_for "/api/status: the tags as df1sim has them" 100 sh -c \
	"python3 - \"$HTTP\" > \"$T/st.json\" <<'PY'
import sys, urllib.request
sys.stdout.write(urllib.request.urlopen('http://' + sys.argv[1] + '/api/status', timeout=10).read().decode())
PY
python3 \"$T/status.py\" \"$T/st.json\" '$MARKUP' > /dev/null"
python3 "$T/status.py" "$T/st.json" "$MARKUP" > /dev/null || bad "/api/status: $(cat "$T/st.json" | head -c 400)"

# ---- the page in a real browser ----
if command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1; then
	rm -f "$T/ready"
	# the charts: station 3 (silenced) fails and has no reply time, station
	# 1 never fails; no broker here (its charts say so)
	python3 tests/support/page_probe.py "http://$HTTP/" --shot "$ART/df1gw-status-page.png" \
		--tag 'Speed=777:GOOD' --tag 'Level=1.5:GOOD' --tag "$MARKUP=-5:GOOD" --tag 'Far=-:BAD' \
		--markup "$MARKUP" --then 'Speed=4242' --ready "$T/ready" \
		--charts 3 --chart 'scans:scans=>0' --chart 'reply:stn 1=>-1' --chart 'reply:stn 3=none' \
		--chart 'failures:stn 1=0' --chart 'failures:stn 3=>0' \
		--layout "1000=$ART/df1gw-status-page-1000.png" --layout "1400=$ART/df1gw-status-page-1400.png" \
		> "$T/page.out" 2>&1 &
	PAGE=$!
	if wait_for "the page shows the tags" 600 test -f "$T/ready"; then
		expect 0 "a write N7:0 = 4242 (the value the page must show)" -- $EPROBE "$EIP" write - 0 4242
	fi
	wait $PAGE
	same "the page in headless Chromium: every check" "$?" 0
	sed 's/^/  page: /' "$T/page.out"
	check "screenshots kept in $ART" 'test -s "$ART/df1gw-status-page.png" && test -s "$ART/df1gw-status-page-1400.png"'
else
	skip "chromium missing (apt-get install chromium): the page not loaded in a browser"
fi

# ---- a flood of requests and slow clients does not slow the line ----
rate() {        # station 1's commands in df1sim's log per 10 s over $1 s
	n0=$(logged 'station=1 ')
	t0=$(date +%s.%N)
	"$@" > /dev/null 2>&1
	n1=$(logged 'station=1 ')
	t1=$(date +%s.%N)
	echo "$n0 $n1 $t0 $t1" | awk '{ printf "%d\n", ($2 - $1) * 10 / ($4 - $3) }'
}
base=$(rate sleep 4)
flood=$(rate python3 tests/support/http_flood.py "$HTTP" 1000 8 10 /api/status 4)
echo "  line: $base commands per 10 s before, $flood during 1000 requests and 10 slow clients"
check "the line's scan goes on under a flood ($flood vs $base per 10 s)" '[ "$flood" -ge $((base / 4)) ] && [ "$flood" -gt 0 ]'
expect 0 "1000 requests all answered (with slow clients about)" -- \
	python3 tests/support/http_flood.py "$HTTP" 1000 8 10 /metrics
gw_stop "$GW_PID"

# ---- the page with a long reason holding markup: a line that cannot open,
# named with HTML's special characters; every tag BAD, its reason
# "line_lost: <the device>: DF1_E_NODEV: ..." ----
if command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1; then
	LOST="$T/<i>&amp;\"no-tty"
	gw_start lost -d "$LOST" --map "$T/map.csv" --eip 0 --http 0
	expect 0 "the page: a reason with markup shown as text, cut with an ellipsis; the layout at 1000 and 1400 px" -- \
		python3 tests/support/page_probe.py "http://$HTTP/" --shot "$ART/df1gw-status-page-lost.png" \
		--tag 'Speed=-:BAD' --tag 'Far=-:BAD' --reason "line_lost: $LOST: DF1_E_NODEV" \
		--layout "1000=$ART/df1gw-status-page-lost-1000.png" --layout "1400=$ART/df1gw-status-page-lost-1400.png"
	sed 's/^/  page: /' "$T/out"
	gw_stop "$GW_PID"
fi

# ---- an address given: df1gw says it is reachable from a network ----
gw_start net -d "$SIM_DEV" --map "$T/map.csv" --eip 0 --http 0.0.0.0:0
check "an address given: df1gw says it is reachable from a network, read-only" \
	'grep -q "HTTP on 0.0.0.0:[0-9]*: listening on a network, reachable from other hosts (read-only" "$T/net.err"'
gw_stop "$GW_PID"
sim_stop

# ---- a station's reply time: df1sim delays its replies by 80 ms ----
sim_start dsim --delay 80 --data "$T/plc.txt" --log "$T/dsim.log" || finish
printf 'Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms\nSpeed,Read,INT,1,SLC,N7:0,1,100\n' > "$T/map1.csv"
gw_start delay -d "$SIM_DEV" --map "$T/map1.csv" --http 0 --eip 0
wait_for "station 1 answered (/metrics)" 100 scraped 'df1_station_state{station="1",state="ok"} 1'
if [ "$have_prom" = yes ]; then
	r1=$(metric 'df1_station_last_reply_seconds{station=1}')
	check "station 1's reply time: at least df1sim's 80 ms delay, less than 5 s ($r1 s)" \
		'python3 -c "import sys; sys.exit(not 0.08 <= float(sys.argv[1]) < 5)" "$r1"'
fi
if command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1; then
	expect 0 "the page's reply time chart: station 1 at least df1sim's 80 ms" -- \
		python3 tests/support/page_probe.py "http://$HTTP/" --shot "$ART/df1gw-status-page-delay.png" \
		--charts 2 --chart 'reply:stn 1=>79' --chart 'reply:stn 1=<5000'
	sed 's/^/  page: /' "$T/out"
fi
gw_stop "$GW_PID"
sim_stop

# ---------------------------------------------------------------------------
# systemd's notifications (a fresh df1sim: READY only after its first answer)
# ---------------------------------------------------------------------------
sim_start nsim --data "$T/plc.txt" --log "$T/nsim.log" || finish
expect 0 "NOTIFY_SOCKET (abstract): READY, STATUS, WATCHDOG, RELOADING, STOPPING" -- \
	python3 tests/support/notify_probe.py --abstract --log "$T/nsim.log" -- \
	"$GW" -q -d "$SIM_DEV" --map "$T/map1.csv" --eip 0
sed 's/^/  notify: /' "$T/out"
sim_stop
sim_start nsim2 --data "$T/plc.txt" --log "$T/nsim2.log" || finish
expect 0 "NOTIFY_SOCKET (a path), watchdog 1 s" -- \
	python3 tests/support/notify_probe.py --watchdog-usec 1000000 --log "$T/nsim2.log" -- \
	"$GW" -q -d "$SIM_DEV" --map "$T/map1.csv" --eip 0
sed 's/^/  notify: /' "$T/out"
sim_stop
expect 0 "a line that cannot open: no READY, STATUS says so, the watchdog still pinged" -- \
	python3 tests/support/notify_probe.py --never-ready 3 -- \
	"$GW" -q -d "$T/no-such-tty" --map "$T/map1.csv" --eip 0
sed 's/^/  notify: /' "$T/out"

# ---- with a broker: READY waits for it; its figures in /metrics ----
MOSQ=${MOSQUITTO:-/usr/sbin/mosquitto}
if [ -x "$MOSQ" ] && command -v mosquitto_sub >/dev/null 2>&1; then
	MQ_PORT=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
	{
		echo "listener $MQ_PORT 127.0.0.1"
		echo "persistence false"
		echo "user $(id -un)"
		echo "allow_anonymous true"
	} > "$T/broker.conf"
	sim_start bsim --data "$T/plc.txt" --log "$T/bsim.log" || finish
	expect 0 "READY=1 waits for the broker" -- \
		python3 tests/support/notify_probe.py \
		--broker-gate "'$MOSQ' -c '$T/broker.conf' > '$T/broker.log' 2>&1 & echo \$! >> '$T/.sims'" -- \
		"$GW" -q -d "$SIM_DEV" --map "$T/map1.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix health
	sed 's/^/  notify: /' "$T/out"
	gw_start mq -d "$SIM_DEV" --map "$T/map1.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix health --http 0
	wait_for "df1gw connected to the broker (/metrics)" 100 scraped 'df1_mqtt_connected 1'
	wait_for "the tag retained on the broker" 100 sh -c \
		"mosquitto_sub -h 127.0.0.1 -p $MQ_PORT -t health/tag/Speed -C 1 -W 2 | grep -q 123"
	n=$(mosquitto_sub -h 127.0.0.1 -p "$MQ_PORT" -t 'health/#' -W 2 2>/dev/null | grep -c .)
	if [ "$have_prom" = yes ]; then
		p=$(metric df1_mqtt_publications_total)
		check "publications counted: at least the $n retained messages on the broker ($p)" \
			'[ "$n" -ge 3 ] && [ "$p" -ge "$n" ]'
	fi
	# the write policy's figures (df1gw(1) WRITE POLICY): a /set that is not
	# JSON and one to a Read tag are both refused at once, nothing written
	mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -q 1 -t health/tag/Speed/set -m 'not json'
	mosquitto_pub -h 127.0.0.1 -p "$MQ_PORT" -q 1 -t health/tag/Speed/set -m '{"value":1,"id":"ro"}'
	wait_for "two refused writes in /metrics (not JSON, a Read tag)" 100 scraped 'df1_mqtt_writes_refused_total 2'
	check "the writes received 2, written 0, none waiting" \
		'scraped "df1_mqtt_writes_received_total 2" && scraped "df1_mqtt_writes_written_total 0" &&
		 scraped "df1_mqtt_writes_waiting 0"'
	get /api/status
	check "/api/status: the broker connected" 'grep -q "\"broker\":{[^}]*\"state\":\"connected\"" "$T/body"'
	if command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1; then
		expect 0 "the page's charts: the broker link up, the buffer's backlog empty" -- \
			python3 tests/support/page_probe.py "http://$HTTP/" --shot "$ART/df1gw-status-page-broker.png" --charts 2 \
			--chart 'broker:broker=up' --chart 'backlog:backlog=0'
		sed 's/^/  page: /' "$T/out"
	fi
	gw_stop "$GW_PID"
	# a payload format's own counters: Sparkplug's births (NBIRTH, then the
	# station's DBIRTH) as df1_sparkplug_births_total, bdSeq 0 the first session
	gw_start spb -d "$SIM_DEV" --map "$T/map1.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix health \
		--sparkplug Health --edge-node H1 --json no --http 0
	wait_for "Sparkplug's NBIRTH and DBIRTH counted in /metrics" 100 scraped 'df1_sparkplug_births_total 2'
	check "Sparkplug: no death, no command, bdSeq 0" \
		'scraped "df1_sparkplug_deaths_total 0" && scraped "df1_sparkplug_commands_total 0" &&
		 scraped "df1_sparkplug_bdseq 0"'
	gw_stop "$GW_PID"
	sim_stop
else
	skip "mosquitto missing: READY with a broker, MQTT figures"
fi

# ---- the unit ----
if command -v systemd-analyze >/dev/null 2>&1; then
	mkdir -p "$T/unit"
	sed "s|@BINDIR@|$BIN|" contrib/systemd/df1gw@.service.in > "$T/unit/df1gw@line1.service"
	expect 0 "systemd-analyze verify df1gw@line1.service" -- systemd-analyze verify --man=no "$T/unit/df1gw@line1.service"
	check "systemd-analyze: nothing said of the unit" '! grep -q "df1gw@" "$T/err"'
	check "the unit is Type=notify with a watchdog" \
		'grep -qx "Type=notify" "$T/unit/df1gw@line1.service" && grep -q "^WatchdogSec=" "$T/unit/df1gw@line1.service"'
else
	skip "systemd-analyze missing: the unit not verified"
fi

# ---------------------------------------------------------------------------
# df1mon --counters -f prometheus (node-exporter's textfile collector)
# ---------------------------------------------------------------------------
sim_start msim --log "$T/msim.log" || finish
expect 0 "df1mon --counters -f prometheus" -- "$BIN/df1mon" -d "$SIM_DEV" --counters -f prometheus
cp "$T/out" "$T/mon.prom"
if [ "$have_prom" = yes ]; then
	expect 0 "df1mon's text parses with prometheus_client and keeps the conventions" -- $PROM "$T/mon.prom" --lint
	# the link test is a DLE ENQ answered by the link layer (df1sim logs commands only)
	check "characters went out (the link test)" \
		'[ "$($PROM "$T/mon.prom" "df1_link_crd_char_sent_total{id=2560}")" -gt 0 ]'
	check "characters came back (its answer)" \
		'[ "$($PROM "$T/mon.prom" "df1_link_crd_char_recv_total{id=2561}")" -gt 0 ]'
	same "no command in df1sim's log, none counted" \
		"$($PROM "$T/mon.prom" 'df1_link_cnt_cmd_msgs_sent_total{id=2527}')" "$(grep -c . "$T/msim.log")"
else
	skip "prometheus_client missing: df1mon's text not parsed"
fi
grep '^# TYPE df1_link_' "$T/mon.prom" > "$T/mon.types"
grep '^# TYPE df1_link_' "$T/gw.prom" > "$T/gw.types"
same "df1mon: the 29 catalog counters" "$(grep -c . "$T/mon.types")" 29
check "df1mon: the same names and types as df1gw's /metrics" 'cmp -s "$T/mon.types" "$T/gw.types"'
expect 0 "df1mon --counters -f prometheus -c 3 -i 0.1" -- "$BIN/df1mon" -d "$SIM_DEV" --counters -f prometheus -c 3 -i 0.1
same "... one snapshot: each family once" "$(grep -c '^# TYPE df1_link_crd_char_sent_total counter' "$T/out")" 1
expect 2 "-f prometheus needs --counters alone" -- "$BIN/df1mon" -d "$SIM_DEV" --ping -f prometheus
sim_stop

finish
