#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# libdf1 demo: run by `make demo` as `sh scripts/demo.sh BUILDDIR` after the build.
# Starts df1sim (a simulated SLC 5/04) on a pseudo-terminal in a temporary
# directory and shows the tools against it, each command printed before it
# runs, exactly as you would type it. The simulators are always stopped and
# the directory removed on exit. Exit status: 0 if every step worked, else 1.

B=${1:-build}
if ! B=$(cd "$B" 2>/dev/null && pwd); then
	echo "demo: build directory '${1:-build}' not found; run make first" >&2
	exit 1
fi
BIN="$B/bin"
for t in df1sim df1read df1write df1mon; do
	if [ ! -x "$BIN/$t" ]; then
		echo "demo: $BIN/$t is missing; run make first" >&2
		exit 1
	fi
done
PATH="$BIN:$PATH"
export PATH

T=$(mktemp -d "${TMPDIR:-/tmp}/df1demo.XXXXXX") || exit 1
SIM_PIDS=
stop_sims() {
	for p in $SIM_PIDS; do
		kill "$p" 2>/dev/null
	done
	st=0
	for p in $SIM_PIDS; do
		wait "$p" 2>/dev/null || st=1
	done
	SIM_PIDS=
	return $st
}
cleanup() {
	stop_sims
	rm -rf "$T"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

fail() {
	echo "demo: $*" >&2
	for f in "$T"/*.err; do
		[ -s "$f" ] || continue
		echo "demo: df1sim said ($f):" >&2
		sed 's/^/  /' "$f" >&2
	done
	exit 1
}

# The command line as you would type it (arguments with blanks quoted).
show() {
	out=
	for a in "$@"; do
		case $a in
		*[!A-Za-z0-9_./:,=%+@-]* | '') a="'$a'" ;;
		esac
		out="$out${out:+ }$a"
	done
	printf '%s' "$out"
}

# caption "COMMENT" COMMAND [ARG...]: the one-line caption of a command.
caption() {
	comment=$1
	shift
	echo
	printf '$ %s' "$(show "$@")"
	[ -n "$comment" ] && printf '      # %s' "$comment"
	echo
}

# step "COMMENT" COMMAND [ARG...]: show the command, run it (its messages on
# stderr go with its output, so they show in order); give up after 30 s
# where timeout(1) exists.
step() {
	caption "$@"
	shift
	if command -v timeout >/dev/null 2>&1; then
		timeout 30 "$@" 2>&1
	else
		"$@" 2>&1
	fi
	rc=$?
	[ "$rc" -eq 0 ] || fail "step failed (exit $rc): $(show "$@")"
}

# start_sim NAME "COMMENT" [DF1SIM OPTIONS...]: df1sim on the pty $T/NAME, in
# the background; waits (10 s at most) for the ready line it prints.
start_sim() {
	name=$1
	comment=$2
	shift 2
	echo
	printf '$ %s &      # %s\n' "$(show df1sim --pty "$T/$name" "$@")" "$comment"
	df1sim --pty "$T/$name" "$@" > "$T/$name.ready" 2> "$T/$name.err" &
	pid=$!
	SIM_PIDS="$SIM_PIDS $pid"
	i=0
	while [ ! -s "$T/$name.ready" ]; do
		kill -0 "$pid" 2>/dev/null || fail "df1sim exited before it was ready"
		i=$((i + 1))
		[ "$i" -le 100 ] || fail "df1sim did not get ready within 10 s"
		sleep 0.1 2>/dev/null || sleep 1
	done
	echo "[df1sim is ready on $(head -n 1 "$T/$name.ready")]"
}

# The simulator's documented initial data table (df1sim(1), DATA TABLE: N7:n = n,
# F8:n = n + 0.5, timers PRE 100 ...) plus a string file and one negative value.
cat > "$T/plc.data" <<'EOF'
ST9:0="Hello from df1sim"
N7:2=-1234
EOF

echo "libdf1 demo: the tools against df1sim, a simulated PLC on a pseudo-terminal."
echo "Each command is shown before its output."

start_sim plc "an SLC 5/04, full duplex, CRC" --data "$T/plc.data"
DF1_DEVICE="$T/plc"
export DF1_DEVICE
echo
echo "\$ export DF1_DEVICE=$DF1_DEVICE      # the tools' default device (or -d DEV)"

step "five integers, one per line" df1read N7:0,5
step "a float" df1read F8:0
step "a string" df1read ST9:0
step "a whole timer: status bits, PRE and ACC" df1read T4:0
step "CSV for spreadsheets (also -f json)" df1read -f csv N7:0,3 F8:0
step "write an integer" df1write N7:0=1234
step "set one bit; the rest of the word stays" df1write B3:0/5=1
step "read them back: N7:0, the bit, its word" df1read N7:0 B3:0/5 B3:0
step "every frame on the wire, decoded (on stderr)" df1read -vv N7:0,3

MON_HELP=$(df1mon --help 2>&1)
has() { printf '%s\n' "$MON_HELP" | grep -q -e "$1"; }

if has '--ping' && has '--counters'; then
	step "link test and echo, then the counter table (seed IDs)" \
		df1mon --ping -c 3 -i 0.2 --counters
	step "one probe again, every frame decoded with its time (on stderr)" \
		df1mon -vv --ping -c 1
elif has '--counters'; then
	step "the counter table (seed IDs)" df1mon --counters -c 1
else
	echo
	echo "# (df1mon --counters is not in this build: skipped)"
fi

if has '--who'; then
	start_sim line "a half-duplex line with stations 1 and 3" --duplex half --station 1,3
	step "which stations answer, and what they are" \
		df1mon -d "$T/line" --duplex half -o 200 --who 1-5
else
	echo
	echo "# (df1mon --who is not in this build: skipped)"
fi

# The gateway: a mosquitto broker of the demo's own on a free loopback port,
# one scan of df1gw into it, and what a subscriber then finds there (retained).
MOSQUITTO=$(command -v mosquitto || { [ -x /usr/sbin/mosquitto ] && echo /usr/sbin/mosquitto; })
if [ -x "$BIN/df1gw" ] && [ -n "$MOSQUITTO" ] && command -v mosquitto_sub >/dev/null 2>&1 &&
	command -v python3 >/dev/null 2>&1; then
	MQ_PORT=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
	printf 'listener %s 127.0.0.1\nallow_anonymous true\npersistence false\n' "$MQ_PORT" > "$T/mosquitto.conf"
	echo
	printf '$ mosquitto -c mosquitto.conf &      # a broker on 127.0.0.1:%s (the demo'"'"'s own)\n' "$MQ_PORT"
	"$MOSQUITTO" -c "$T/mosquitto.conf" > "$T/mosquitto.log" 2>&1 &
	SIM_PIDS="$SIM_PIDS $!"
	i=0
	until python3 -c "import socket; socket.create_connection(('127.0.0.1', $MQ_PORT), 1).close()" 2>/dev/null; do
		i=$((i + 1))
		[ "$i" -le 100 ] || fail "mosquitto did not listen within 10 s"
		sleep 0.1 2>/dev/null || sleep 1
	done
	printf 'Tag,Command,Type,Station,PLC_Type,Address,Count\nSpeed,ReadWrite,INT,1,SLC,N7:0,1\nLevels,Read,FLOAT,1,SLC,F8:0,2\nRun,Read,BOOL,1,SLC,B3:0/5,1\n' > "$T/tags.csv"
	echo
	echo "\$ cat tags.csv      # the tags the gateway keeps in the broker"
	cat "$T/tags.csv"
	step "one scan of the line into the broker (a daemon without --once)" \
		df1gw --once --map "$T/tags.csv" --mqtt "mqtt://127.0.0.1:$MQ_PORT" --prefix demo
	step "what any MQTT client finds there: a retained JSON message per tag" \
		mosquitto_sub -p "$MQ_PORT" -t 'demo/tag/#' -v -W 3 -C 3
else
	echo
	echo "# (df1gw or the mosquitto broker and clients are missing: the gateway step is skipped)"
fi

step "decode a frame given as hex (no device needed)" \
	df1mon --decode '10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03 60 46'

jobs_text=
n=0
for p in $SIM_PIDS; do
	n=$((n + 1))
	jobs_text="$jobs_text %$n"
done
echo
echo "\$ kill$jobs_text      # stop the simulators (and the broker)"
stop_sims || fail "a simulator did not stop cleanly"

cat <<'EOF'

Done. Next: `make check` builds and runs every test (unit tests, then the
tools and the library against df1sim over pseudo-terminals and TCP). The
manual pages are in man/: man -l man/man1/df1read.1 (also df1write.1,
df1mon.1, df1sim.1, df1gw.1) and man -l man/man7/libdf1.7 for the library.
README has the build, the API and examples.
EOF
