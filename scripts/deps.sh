#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# Checks the build dependencies; installs the missing Debian packages with
# apt-get when it can (root, or sudo without a password), else prints the
# exact command and fails.
missing=""
have_header() { printf '#include <%s>\n' "$1" | ${CC:-cc} -E -x c - >/dev/null 2>&1; }
command -v ${CC:-cc} >/dev/null 2>&1 || missing="$missing build-essential"
command -v pkg-config >/dev/null 2>&1 || missing="$missing pkg-config"
have_header csv.h || missing="$missing libcsv-dev"
have_header stdarg.h && printf '#include <stdarg.h>\n#include <stddef.h>\n#include <setjmp.h>\n#include <cmocka.h>\n' \
	| ${CC:-cc} -E -x c - >/dev/null 2>&1 || missing="$missing libcmocka-dev"
command -v mandoc >/dev/null 2>&1 || missing="$missing mandoc"
command -v python3 >/dev/null 2>&1 || missing="$missing python3"
have_header mosquitto.h || missing="$missing libmosquitto-dev"
# df1gw's certificate errors in detail (optional in the Makefile, wanted here)
have_header openssl/ssl.h || missing="$missing libssl-dev"
# df1gw --http
printf '#include <stdint.h>\n#include <sys/types.h>\n#include <sys/socket.h>\n#include <microhttpd.h>\n' \
	| ${CC:-cc} -E -x c - >/dev/null 2>&1 || missing="$missing libmicrohttpd-dev"
# the broker and its clients, for the gateway's tests and make demo
command -v mosquitto >/dev/null 2>&1 || [ -x /usr/sbin/mosquitto ] || missing="$missing mosquitto"
command -v mosquitto_sub >/dev/null 2>&1 || missing="$missing mosquitto-clients"
# Sparkplug B in df1gw: protobuf-c's library and its compiler protoc-c
have_header protobuf-c/protobuf-c.h || missing="$missing libprotobuf-c-dev"
command -v protoc-c >/dev/null 2>&1 || missing="$missing protobuf-c-compiler"
# store and forward in df1gw: SQLite
have_header sqlite3.h || missing="$missing libsqlite3-dev"
[ -z "$missing" ] && exit 0
cmd="apt-get install -y$missing"
as=
if [ "$(id -u)" = 0 ]; then
	as=" "
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
	as="sudo -n"
fi
if [ -n "$as" ] && command -v apt-get >/dev/null 2>&1; then
	echo "deps: installing:$missing" >&2
	# a fresh machine may have no package lists yet: update, then try again
	$as env DEBIAN_FRONTEND=noninteractive apt-get install -y -q $missing >&2 && exit 0
	$as apt-get update -q >&2 &&
		$as env DEBIAN_FRONTEND=noninteractive apt-get install -y -q $missing >&2 && exit 0
fi
sudo=
[ "$(id -u)" = 0 ] || sudo="sudo "
echo "deps: missing:$missing" >&2
echo "deps: run: ${sudo}apt-get update && ${sudo}$cmd" >&2
exit 1
