# SPDX-License-Identifier: MPL-2.0
# tests/support/lib.sh - shared helpers for the integration tests (POSIX sh).
#
#   . tests/support/lib.sh          (from the repository root; DF1_BIN = the built tools)
#
# Gives:
#   $BIN $T                the tools' directory; a private temporary directory,
#                          removed at exit together with every df1sim started
#   expect STATUS DESC -- CMD...
#                          run CMD (bounded by $TEST_TIMEOUT seconds), stdout in
#                          $T/out, stderr in $T/err; count a failure unless it
#                          exits with STATUS
#   check DESC EXPR        count a failure unless `eval EXPR` succeeds
#   same DESC GOT WANT     count a failure unless GOT = WANT (both shown if not)
#   out_is DESC WANT       $T/out is exactly WANT (plus its final newline)
#   err_has DESC TEXT      $T/err holds TEXT (a fixed string)
#   sim_start NAME [DF1SIM OPTIONS...]
#                          start df1sim on a pseudo-terminal $T/NAME (or, with
#                          SIM_TRANSPORT=tcp, on tcp://127.0.0.1:0) and wait for
#                          the device line it prints when ready; sets SIM_DEV
#                          (the device to give -d) and SIM_PID; its stdout and
#                          stderr are $T/NAME.out and $T/NAME.err
#   sim_stop [PID]         stop a df1sim (default $SIM_PID) and wait for it
#   sim_run [DF1SIM ARGS...]
#                          start df1sim with exactly these arguments (nothing
#                          added); SIM_LINE = the first line it prints (read
#                          from a fifo: returns when written, or empty at EOF
#                          if it dies first, or after a 10 s watchdog kills a
#                          df1sim that neither prints nor exits); SIM_PID; its
#                          stderr is $T/sim.err
#   sim_end SIGNAL         send SIGNAL to $SIM_PID and wait; returns its exit
#                          status (the df1sim of sim_run)
#   lib_reap PID           wait (bounded, 5 s) for a process to end; KILL it if not
#   wait_for DESC TRIES CMD...
#                          run CMD every 0.1 s until it succeeds, at most TRIES
#                          times; count a failure (and return 1) if it never does
#   radio_start NAME RADIO_CHANNEL OPTIONS...
#                          start tests/support/radio_channel.py (--node,
#                          --link, --keyup-ms...: its header) with the ptys
#                          $T/NAME.<node> and the log $T/NAME.log, and wait
#                          until it is ready; RADIO_PID (sim_stop ends it)
#   json_ok FILE           every line of FILE is a JSON object (starts with {, ends
#                          with }, balanced braces and unescaped quotes)
#   skip DESC              print "SKIP: DESC": counted neither passed nor failed
#   finish                 print "N passed, N failed" and exit 0 only if none failed
#
# Waits are bounded loops on a condition, never a sleep that hopes; tests assert
# behaviour, never timing.

BIN=${DF1_BIN:-$(pwd)/build/bin}
TEST_TIMEOUT=${TEST_TIMEOUT:-60}
T=$(mktemp -d "${TMPDIR:-/tmp}/df1test.XXXXXX") || exit 1
# df1gw keeps Sparkplug's bdSeq in the state folder (df1gw(1) FILES): the
# test's own, never the user's home or a service's
XDG_STATE_HOME="$T/state"
export XDG_STATE_HOME
unset STATE_DIRECTORY
pass=0
fail=0
: > "$T/.sims"

lib_cleanup() {
	for p in $(cat "$T/.sims" 2>/dev/null); do
		kill -TERM "$p" 2>/dev/null
	done
	for p in $(cat "$T/.sims" 2>/dev/null); do
		lib_reap "$p"
	done
	rm -rf "$T"
}
trap lib_cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

# A short pause for polling loops (fractions of a second where sleep takes them).
tick() { sleep 0.1 2>/dev/null || sleep 1; }

# Run a command bounded in time when timeout(1) exists.
bounded() {
	if command -v timeout >/dev/null 2>&1; then
		timeout -k 5 "$TEST_TIMEOUT" "$@"
	else
		"$@"
	fi
}

expect() {
	want=$1; what=$2; shift 3
	bounded "$@" > "$T/out" 2> "$T/err"
	got=$?
	if [ "$got" -eq "$want" ]; then
		ok
	else
		bad "$what: exit $got, expected $want"
		sed 's/^/  out: /' "$T/out" | head -5
		sed 's/^/  err: /' "$T/err" | head -5
	fi
}

skip() { echo "SKIP: $*"; }

check() { if eval "$2"; then ok; else bad "$1"; fi; }

same() {
	if [ "$2" = "$3" ]; then ok; else
		bad "$1"
		printf '%s\n' "$2" | sed 's/^/  got:  /' | head -20
		printf '%s\n' "$3" | sed 's/^/  want: /' | head -20
	fi
}

out_is() { same "$1" "$(cat "$T/out")" "$2"; }

err_has() {
	if grep -F -q -e "$2" "$T/err"; then ok; else
		bad "$1: stderr lacks '$2'"
		sed 's/^/  err: /' "$T/err" | head -5
	fi
}

# TRIES is what the condition needs on a quiet machine (a try every 0.1 s);
# it is multiplied by DF1_TEST_SLACK (default 3), so that scripts run side by
# side (TEST_JOBS) on a loaded machine still make it: a condition that holds
# returns at once, only a failure waits the longer time.
wait_for() {
	what=$1; tries=$(($2 * ${DF1_TEST_SLACK:-3})); shift 2
	while [ "$tries" -gt 0 ]; do
		if "$@"; then ok; return 0; fi
		tries=$((tries - 1))
		tick
	done
	bad "$what: gave up waiting"
	return 1
}

# Wait (bounded) for a process to end, killing it if it will not.
lib_reap() {
	n=50
	while [ $n -gt 0 ] && kill -0 "$1" 2>/dev/null; do
		n=$((n - 1))
		tick
	done
	if kill -0 "$1" 2>/dev/null; then
		kill -KILL "$1" 2>/dev/null
	fi
	wait "$1" 2>/dev/null
	return 0
}

sim_start() {
	name=$1; shift
	SIM_DEV=
	SIM_PID=
	if [ "${SIM_TRANSPORT:-pty}" = tcp ]; then
		"$BIN/df1sim" --listen tcp://127.0.0.1:0 "$@" > "$T/$name.out" 2> "$T/$name.err" &
	else
		rm -f "$T/$name"
		"$BIN/df1sim" --pty "$T/$name" "$@" > "$T/$name.out" 2> "$T/$name.err" &
	fi
	SIM_PID=$!
	echo "$SIM_PID" >> "$T/.sims"
	n=100                   # 10 s at most
	while [ $n -gt 0 ]; do
		if [ -s "$T/$name.out" ] && SIM_DEV=$(head -n 1 "$T/$name.out") && [ -n "$SIM_DEV" ]; then
			return 0
		fi
		if ! kill -0 "$SIM_PID" 2>/dev/null; then
			break
		fi
		n=$((n - 1))
		tick
	done
	bad "df1sim $name did not start: $*"
	sed 's/^/  df1sim: /' "$T/$name.err" | head -5
	SIM_DEV=
	return 1
}

sim_stop() {
	p=${1:-$SIM_PID}
	[ -n "$p" ] || return 0
	kill -TERM "$p" 2>/dev/null
	lib_reap "$p"
	grep -v "^$p\$" "$T/.sims" > "$T/.sims.new" 2>/dev/null
	mv "$T/.sims.new" "$T/.sims"
	return 0
}

sim_run() {
	rm -f "$T/sim.out"
	mkfifo "$T/sim.out" || exit 1
	"$BIN/df1sim" "$@" > "$T/sim.out" 2> "$T/sim.err" &
	SIM_PID=$!
	echo "$SIM_PID" >> "$T/.sims"
	# a df1sim that never says where it is gets killed after 10 s, so the
	# read below ends; one that did is marked, and the dog leaves it alone
	# even where SIGTERM is ignored (a package build can run so) and the
	# dog outlives its kill
	( sleep 10; [ -e "$T/sim.ready.$SIM_PID" ] || kill "$SIM_PID" 2>/dev/null ) &
	sim_dog=$!
	exec 3< "$T/sim.out"
	SIM_LINE=
	IFS= read -r SIM_LINE <&3 || SIM_LINE=
	: > "$T/sim.ready.$SIM_PID"
	kill -KILL "$sim_dog" 2>/dev/null
	wait "$sim_dog" 2>/dev/null
}

sim_end() {
	kill -s "$1" "$SIM_PID" 2>/dev/null
	wait "$SIM_PID"
	sim_rc=$?
	grep -v "^$SIM_PID\$" "$T/.sims" > "$T/.sims.new" 2>/dev/null
	mv "$T/.sims.new" "$T/.sims"
	SIM_PID=
	exec 3<&-
	return $sim_rc
}

radio_start() {
	rname=$1; shift
	python3 tests/support/radio_channel.py --prefix "$T/$rname" --log "$T/$rname.log" "$@" \
		> "$T/$rname.out" 2> "$T/$rname.err" &
	RADIO_PID=$!
	echo "$RADIO_PID" >> "$T/.sims"
	wait_for "radio channel $rname is up" 100 grep -qs '^ready$' "$T/$rname.out" && return 0
	sed 's/^/  radio_channel: /' "$T/$rname.err" | head -5
	return 1
}

# ---- an MQTT broker on a loopback port (the gateway's tests) ----
MOSQ=${MOSQUITTO:-/usr/sbin/mosquitto}

# free_port: a TCP port free on 127.0.0.1 now
free_port() {
	python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

# port_open PORT: something listens on 127.0.0.1:PORT
port_open() {
	python3 -c "import socket; socket.create_connection(('127.0.0.1', $1), 1).close()" 2>/dev/null
}

# broker_start NAME PORT [CONFIG LINES...]: $T/NAME.conf (a listener on
# 127.0.0.1:PORT, no persistence, the lines given or anonymous clients), then
# broker_run. As root mosquitto would become the user "mosquitto", who cannot
# read $T: it stays this user.
broker_start() {
	bname=$1; bport=$2; shift 2
	{
		echo "listener $bport 127.0.0.1"
		echo "persistence false"
		echo "user $(id -un)"
		if [ $# -gt 0 ]; then printf '%s\n' "$@"; else echo "allow_anonymous true"; fi
	} > "$T/$bname.conf"
	broker_run "$bname" "$bport"
}

# broker_run NAME PORT: mosquitto on $T/NAME.conf (again, after a kill: its
# log $T/NAME.log goes on), BROKER_PID, waited for until PORT listens.
broker_run() {
	"$MOSQ" -c "$T/$1.conf" >> "$T/$1.log" 2>&1 &
	BROKER_PID=$!
	echo "$BROKER_PID" >> "$T/.sims"
	wait_for "broker $1 listens" 100 port_open "$2"
}

json_ok() {
	awk '{
		if ($0 !~ /^\{".*\}$/) { bad = 1; print "not an object: " $0; next }
		s = $0; gsub(/\\\\/, "", s); gsub(/\\"/, "", s)
		n = gsub(/"/, "", s); if (n % 2) { bad = 1; print "odd quotes: " $0 }
		t = $0; o = gsub(/\{/, "", t); c = gsub(/\}/, "", t); if (o != c) { bad = 1; print "braces: " $0 }
	} END { exit bad }' "$1"
}

finish() {
	echo "$pass passed, $fail failed"
	[ "$fail" -eq 0 ]
	exit $?
}
