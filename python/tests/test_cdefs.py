# SPDX-License-Identifier: MPL-2.0
"""The cdefs are df1.h's: regenerated they equal the checked-in file, and cffi's
layout of every struct is the C compiler's."""
import os
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT

HEADER = os.path.join(ROOT, "include", "df1.h")
GEN = os.path.join(ROOT, "python", "gen_cdefs.py")
CC = os.environ.get("CC") or "cc"

needs_tree = pytest.mark.skipif(not os.path.exists(HEADER) or shutil.which(CC.split()[0]) is None,
                                reason="needs the source tree's include/df1.h and a C compiler")


@needs_tree
def test_cdefs_are_generated_from_the_current_df1_h():
    res = subprocess.run([sys.executable, GEN, "--check"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         universal_newlines=True)
    assert res.returncode == 0, res.stderr


@needs_tree
def test_check_fails_when_df1_h_changes(tmp_path):
    inc = tmp_path / "include"
    inc.mkdir()
    for name in os.listdir(os.path.dirname(HEADER)):
        shutil.copy(os.path.join(os.path.dirname(HEADER), name), str(inc))
    with open(str(inc / "df1.h")) as f:
        text = f.read()
    text = text.replace("DF1_API int df1_poll_fd(df1_t *h);",
                        "DF1_API int df1_poll_fd(df1_t *h);\nDF1_API int df1_new_call_for_the_test(int x);")
    assert "df1_new_call_for_the_test" in text
    with open(str(inc / "df1.h"), "w") as f:
        f.write(text)
    res = subprocess.run([sys.executable, GEN, "--check", "--header", str(inc / "df1.h")],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
    assert res.returncode == 1
    assert "stale" in res.stderr
    out = tmp_path / "cdefs.h"
    subprocess.check_call([sys.executable, GEN, "--header", str(inc / "df1.h"), "--out", str(out)])
    assert "int df1_new_call_for_the_test(int x);" in out.read_text()


@needs_tree
def test_struct_layouts_match_the_compiler(tmp_path):
    from libdf1 import ffi
    structs = [n for n in ffi.list_types()[1] if n.startswith("df1_")]
    assert "df1_value" in structs and "df1_tag_state" in structs
    lines = ['#include <stdio.h>', '#include <stddef.h>', '#include "df1.h"', "int main(void) {"]
    expect = []
    for s in sorted(structs):
        t = ffi.typeof("struct " + s)
        if t.fields is None:        # opaque: struct df1_decoder, struct df1_table
            continue
        lines.append('printf("%%s %%zu\\n", "%s", sizeof(struct %s));' % (s, s))
        expect.append("%s %d" % (s, ffi.sizeof(t)))
        for name, field in t.fields:
            if name is None or field.bitsize >= 0:
                continue
            lines.append('printf("%%s.%%s %%zu\\n", "%s", "%s", offsetof(struct %s, %s));' % (s, name, s, name))
            expect.append("%s.%s %d" % (s, name, field.offset))
    lines.append("return 0; }")
    src = tmp_path / "layout.c"
    src.write_text("\n".join(lines) + "\n")
    exe = tmp_path / "layout"
    subprocess.check_call(CC.split() + ["-std=c11", "-I", os.path.dirname(HEADER), "-o", str(exe), str(src)])
    got = subprocess.check_output([str(exe)], universal_newlines=True).split("\n")
    assert [g for g in got if g] == expect


def test_every_function_of_the_cdefs_is_in_the_library():
    from libdf1 import ffi, lib
    import re
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "libdf1", "_cdefs.h")
    with open(here) as f:
        names = re.findall(r"\b(df1_[a-z0-9_]+)\s*\(", f.read())
    missing = [n for n in sorted(set(names)) if not hasattr(lib, n)]
    assert not missing, "declared in the cdefs, absent from the library: %s" % missing


@needs_tree
def test_generator_takes_what_a_header_may_grow(tmp_path):
    # inline helpers, static assertions, system headers and new X-macro rows
    inc = tmp_path / "include"
    inc.mkdir()
    for name in os.listdir(os.path.dirname(HEADER)):
        shutil.copy(os.path.join(os.path.dirname(HEADER), name), str(inc))
    text = (inc / "df1.h").read_text()
    extra = ('#include <stdio.h>\n'
             'static inline int df1_twice(int x) { if (x) { return 2 * x; } return 0; }\n'
             '_Static_assert(sizeof(int) >= 4, "int");\n'
             'DF1_API int df1_dump(df1_t *h, FILE *f);\n'
             '#define DF1_NEW_LIMIT (DF1_STRING_MAX * 2 + 1)\n')
    text = text.replace("#ifdef __cplusplus\n}\n#endif", extra + "#ifdef __cplusplus\n}\n#endif")
    text = text.replace('"permission denied")', '"permission denied")                      \\\n'
                        '\tX(DF1_E_NEW_ONE,     -32, 0,                             "a new error")')
    assert "df1_dump" in text and "DF1_E_NEW_ONE" in text
    (inc / "df1.h").write_text(text)
    out = tmp_path / "cdefs.h"
    subprocess.check_call([sys.executable, GEN, "--header", str(inc / "df1.h"), "--out", str(out)])
    cdefs = out.read_text()
    assert "df1_twice" not in cdefs and "_Static_assert" not in cdefs
    assert "#define DF1_NEW_LIMIT 165" in cdefs and "DF1_E_NEW_ONE = -32," in cdefs
    import cffi
    f = cffi.FFI()
    f.cdef(cdefs)
    assert f.typeof("enum df1_error").relements["DF1_E_NEW_ONE"] == -32
