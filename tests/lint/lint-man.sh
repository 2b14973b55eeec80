#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# Lints every man page (mandoc -Tlint, or groff -ww) and fails when a public
# function of include/df1.h has no section 3 page (a page or a .so alias).
status=0
for f in man/man*/*.[137]; do
	[ -f "$f" ] || continue
	if command -v mandoc >/dev/null 2>&1; then
		out=$(mandoc -Tlint -W warning "$f" 2>&1 | grep -v 'STYLE:' | grep -v 'referenced manual not found' )
	else
		out=$(groff -ww -man -z "$f" 2>&1)
	fi
	if [ -n "$out" ]; then echo "$out"; status=1; fi
done
for fn in $(sed -n 's/^DF1_API[^(]*[ *]\(df1_[a-z0-9_]*\)(.*/\1/p' include/*.h | sort -u); do
	if [ ! -f "man/man3/$fn.3" ]; then
		echo "lint-man: public function $fn has no man page (man/man3/$fn.3)"
		status=1
	fi
done
[ $status -eq 0 ] && echo "man pages: lint clean, every public function documented"
exit $status
