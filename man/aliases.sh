#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# Creates the alias pages of section 3. Every function named in the NAME
# section of a group page (man3/df1_read.3: "df1_read, df1_read_addr, ... \-")
# gets man3/<function>.3 as a symbolic link to its group page, so that
# `man df1_read_float` finds it and tests/lint/lint-man.sh finds a page for every
# DF1_API function of include/df1.h.
#
# To document new functions: add them to the NAME line and SYNOPSIS of a group
# page (or write a new group page), then run `sh man/aliases.sh`.
#
# Links, not ".so man3/<group>.3" stubs: mandoc -Tlint warns that .so is
# fragile and cannot resolve it from the top directory, so stubs would fail
# the lint. SO=1 writes .so stubs instead, for a packager who wants them.
set -eu
cd "$(dirname "$0")/man3"
for page in *.3; do
	[ -L "$page" ] && continue
	grep -q '^\.so ' "$page" && continue
	group=$page
	# the NAME section, joined: "f1, f2, ... \- description"
	names=$(sed -n '/^\.SH NAME/,/^\.SH/{/^\.SH/d;p;}' "$group" | tr '\n' ' ' |
		sed 's/\\-.*//' | tr ',' ' ')
	for fn in $names; do
		alias=$fn.3
		[ "$alias" = "$group" ] && continue
		if [ -f "$alias" ] && [ ! -L "$alias" ] && ! grep -q '^\.so ' "$alias"; then
			echo "aliases.sh: $alias is a page of its own, not linked to $group" >&2
			continue
		fi
		rm -f "$alias"
		if [ "${SO:-0}" = 1 ]; then
			printf '.so man3/%s\n' "$group" >"$alias"
		else
			ln -s "$group" "$alias"
		fi
	done
done
