#!/bin/sh
# SPDX-License-Identifier: MPL-2.0
# lint-spdx.sh - every source file of the tree carries the project's license
# line (doc/HACKING.md 4): C and headers, Python, Lua, shell, makefiles, man
# pages, the version script, fuzz dictionaries. Data files (CSV, pcap, the
# vectors) and plain-text documents go without; LICENSE covers the whole tree.
# Reads the tree itself, not git, so it also runs in a package build.
cd "$(dirname "$0")/../.." || exit 2
tag='SPDX-License-Identifier: MPL-2.0'
missing=$(find Makefile libdf1.pc.in .ci include lib tools tests bench examples python scripts contrib man doc \
	\( -name build -o -name __pycache__ -o -name '*.egg-info' -o -name .pytest_cache \) -prune -o \
	-type f \( -name '*.[ch]' -o -name '*.py' -o -name '*.lua' -o -name '*.sh' -o -name '*.mk' \
	-o -name '*.in' -o -name '*.[137]' -o -name '*.map' -o -name '*.toml' -o -name '*.dict' \
	-o -name '*.md' -o -name Makefile -o -name run \) -print 2>/dev/null |
	while read -r f; do grep -q "$tag" "$f" || echo "$f"; done)
if [ -n "$missing" ]; then
	echo "files without the line '$tag':"
	echo "$missing" | sed 's/^/  /'
	exit 1
fi
echo "license: every source file has its SPDX line"
