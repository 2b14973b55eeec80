#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""lint-ids: no bare message-catalog ID (2501-2561) in C code outside the
catalog table of include/df1.h. Comments and strings may cite IDs; code says
DF1_ID_<MNEMONIC>. With --fix, rewrites each bare ID to its name.

usage: lint-ids.py [--fix] FILE...   (exit 1 when a bare ID is found)
"""
import re
import sys

HEADER = "include/df1_catalog.h"


def catalog(header):
    text = open(header).read()
    rows = re.findall(r"X\((\w+), (25\d\d), (?:ERROR|NOTICE|COUNTER|CRITICAL),", text)
    return {int(i): "DF1_ID_" + m for m, i in rows}


def code_spans(src):
    """Yield (start, end) of the parts of src that are code: not comments,
    not string or character literals."""
    i, n, start = 0, len(src), 0
    while i < n:
        c = src[i]
        if src.startswith("/*", i):
            yield start, i
            j = src.find("*/", i + 2)
            i = n if j < 0 else j + 2
            start = i
        elif src.startswith("//", i):
            yield start, i
            j = src.find("\n", i)
            i = n if j < 0 else j
            start = i
        elif c in "\"'":
            yield start, i
            j = i + 1
            while j < n and src[j] != c:
                j += 2 if src[j] == "\\" else 1
            i = j + 1
            start = i
        else:
            i += 1
    yield start, n


def main(argv):
    fix = "--fix" in argv
    files = [a for a in argv if a != "--fix"]
    names = catalog(HEADER)
    bad = 0
    for path in files:
        src = open(path).read()
        out, last = [], 0
        for a, b in code_spans(src):
            for m in re.finditer(r"(?<![\w.])(25\d\d)(?![\w.])", src[a:b]):
                v = int(m.group(1))
                if v not in names:
                    continue
                pos = a + m.start()
                line = src.count("\n", 0, pos) + 1
                row = src[src.rfind("\n", 0, pos) + 1:pos + 4]
                if path == HEADER and re.fullmatch(r"\s*X\(\w+, 25\d\d", row):
                    continue  # the catalog table's own rows
                bad += 1
                print(f"{path}:{line}: bare catalog ID {v}: use {names[v]}")
                out.append(src[last:pos])
                out.append(names[v])
                last = pos + 4
        if fix and out:
            out.append(src[last:])
            open(path, "w").write("".join(out))
    if bad and not fix:
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
