#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# it_table_example - examples/table_slave.c, the simulated slave of libdf1(7)
# and df1_table(3) built on the data table, as a process: it prints its pty,
# df1read reads the documented initial contents, df1write writes words and a
# bit that read back, df1mon --who names the processor, and a data file given
# to it is loaded (a bad one ends it with status 2 and the file:line message).
# The binary is built by `make tests` ($B/examples/table_slave).
# Run from the repository root with B=<build dir> and DF1_BIN=<build/bin>.
. tests/support/lib.sh
EX=${B:-build}/examples/table_slave
[ -x "$EX" ] || { bad "$EX not built (make tests)"; finish; }

# ex_start NAME [ARGS...]: start the example; EX_DEV is the pty it printed
ex_start() {
	name=$1; shift
	EX_DEV=
	"$EX" "$@" > "$T/$name.out" 2> "$T/$name.err" &
	EX_PID=$!
	echo "$EX_PID" >> "$T/.sims"
	n=100
	while [ $n -gt 0 ]; do
		if [ -s "$T/$name.out" ] && EX_DEV=$(head -n 1 "$T/$name.out") && [ -n "$EX_DEV" ]; then
			return 0
		fi
		kill -0 "$EX_PID" 2>/dev/null || break
		n=$((n - 1))
		tick
	done
	bad "table_slave $name did not start"
	sed 's/^/  table_slave: /' "$T/$name.err" | head -5
	return 1
}

if ex_start plain; then
	ok
	check "it prints a pty" 'case "$EX_DEV" in /dev/pts/*) true ;; *) false ;; esac'
	expect 0 "read the initial values" -- "$BIN/df1read" -d "$EX_DEV" N7:0,3 F8:2 L10:1 T4:0.PRE ST9:4
	out_is "initial values (df1sim(1) DATA TABLE)" "0
1
2
2.5
65537
100
STRING 4"
	expect 0 "write words and a bit" -- "$BIN/df1write" -d "$EX_DEV" N7:1=-300,7 B3:0/4=1
	expect 0 "read them back" -- "$BIN/df1read" -d "$EX_DEV" N7:0,4 B3:0 B3:0/4
	out_is "written values" "0
-300
7
3
16
1"
	expect 0 "diagnostic status" -- "$BIN/df1mon" -d "$EX_DEV" --who 1-1
	check "processor SLC 5/04 in run mode" 'grep -q "SLC 5/04.*type 0x5B.*mode run" "$T/out"'
	sim_stop "$EX_PID"
fi

printf '# values\nN7:0=11,12\nST9:0="hello, world"\n' > "$T/data.txt"
if ex_start data - "$T/data.txt"; then
	expect 0 "read values of the data file" -- "$BIN/df1read" -d "$EX_DEV" N7:0,3 ST9:0
	out_is "data file values" "11
12
2
hello, world"
	sim_stop "$EX_PID"
fi

printf 'N7:0=1\nN7:1=zz\n' > "$T/bad.txt"
expect 2 "a bad data file" -- "$EX" - "$T/bad.txt"
err_has "the message names file and line" "$T/bad.txt:2: N7:1: 'zz': value does not fit the file type"
finish
