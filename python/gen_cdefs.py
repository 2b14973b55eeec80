#!/usr/bin/env python3
# SPDX-License-Identifier: MPL-2.0
"""Generate libdf1/_cdefs.h, the cffi declarations, from include/df1.h.

    python3 python/gen_cdefs.py            rewrite python/libdf1/_cdefs.h
    python3 python/gen_cdefs.py --check    exit 1 if it differs from df1.h

The C preprocessor ($CC -E, default cc) expands df1.h as a compiler sees it:
the X-macro tables become plain enums, DF1_API and other attributes vanish,
and only the lines that come from df1.h and the headers beside it are kept
(system headers are cffi's own types). Object-like DF1_* macros whose value
is integer arithmetic become #define lines, which cffi takes as constants.
"""
import argparse
import ast
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_HEADER = os.path.join(HERE, "..", "include", "df1.h")
DEFAULT_OUT = os.path.join(HERE, "libdf1", "_cdefs.h")

BANNER = """\
/* SPDX-License-Identifier: MPL-2.0 */
/* Generated from include/df1.h by python/gen_cdefs.py: do not edit.
 * Regenerate after every change to df1.h (a test compares the two). */
"""


def preprocess(cc, header, extra=""):
    """Run the preprocessor on header (plus extra text after it); returns its output."""
    incdir = os.path.dirname(os.path.abspath(header))
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "cdefs_probe.c")
        with open(src, "w") as f:
            f.write('#include "%s"\n' % os.path.basename(header))
            f.write(extra)
        cmd = cc.split() + ["-E", "-std=c11", "-D__attribute__(x)=", "-I", incdir, src]
        res = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
        if res.returncode != 0:
            raise SystemExit("gen_cdefs: %s failed:\n%s" % (" ".join(cmd), res.stderr))
        return res.stdout


def library_lines(text, incdir):
    """The declarations that come from the headers in incdir, by the line markers."""
    keep = False
    out = []
    marker = re.compile(r'^#\s*(?:line\s+)?\d+\s+"([^"]*)"')
    incdir = os.path.realpath(incdir)
    for line in text.splitlines():
        m = marker.match(line)
        if m:
            path = m.group(1)
            keep = os.path.dirname(os.path.realpath(path)) == incdir if os.path.isabs(path) or os.path.exists(path) else False
            continue
        if line.startswith("#"):
            continue
        if keep and line.strip():
            out.append(line)
    return out


def declarations_only(text):
    """Drop what cffi's cdef cannot take: function bodies (static inline helpers)
    and _Static_assert declarations."""
    out, depth, start, i = [], 0, 0, 0
    while i < len(text):
        ch = text[i]
        if ch == "{":
            if depth == 0 and text[start:i].rstrip().endswith(")"):
                # a function definition: skip its body and its head
                level, j = 0, i
                while j < len(text):
                    if text[j] == "{":
                        level += 1
                    elif text[j] == "}":
                        level -= 1
                        if level == 0:
                            break
                    j += 1
                i = j + 1
                start = i
                continue
            depth += 1
        elif ch == "}":
            depth -= 1
        elif ch == ";" and depth == 0:
            decl = text[start:i + 1]
            if not re.match(r"\s*_Static_assert\b", decl):
                out.append(decl)
            start = i + 1
        i += 1
    return " ".join(out)


def layout(decls):
    """One declaration (or member, or enumerator) a line, indented by braces."""
    text = declarations_only(re.sub(r"\s+", " ", " ".join(decls)).strip())
    text = re.sub(r"\s+", " ", text).strip()
    out, depth, kinds, line = [], 0, [], ""
    last_stop = 0

    def flush():
        nonlocal line
        if line.strip():
            out.append("\t" * depth + line.strip())
        line = ""

    for i, ch in enumerate(text):
        if ch == "{":
            head = text[last_stop:i]
            kinds.append("enum" if re.search(r"\benum\b", head) else "other")
            line = line.rstrip() + " {"
            flush()
            depth += 1
            last_stop = i + 1
        elif ch == "}":
            flush()
            depth -= 1
            kinds.pop()
            line = "}"
            last_stop = i + 1
        elif ch == ";":
            line += ";"
            flush()
            last_stop = i + 1
        elif ch == "," and kinds and kinds[-1] == "enum":
            line += ","
            flush()
        else:
            line += ch
    flush()
    # "} name;" and "};" stay on the closing line
    return "\n".join(out)


_ARITH = re.compile(r"^[\s0-9()+\-*/%<>&|^~xXa-fA-FuUlL]*$")


def integer_value(expr):
    """The value of an integer constant expression such as (0 + 1 + 1), or None."""
    expr = expr.strip()
    if not expr or not _ARITH.match(expr):
        return None
    expr = re.sub(r"\b(0[xX][0-9a-fA-F]+|\d+)[uUlL]+\b", r"\1", expr)
    try:
        tree = ast.parse(expr.replace("/", "//"), mode="eval")
    except SyntaxError:
        return None
    allowed = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Constant, ast.Add, ast.Sub, ast.Mult,
               ast.FloorDiv, ast.Mod, ast.LShift, ast.RShift, ast.BitAnd, ast.BitOr, ast.BitXor,
               ast.USub, ast.UAdd, ast.Invert)
    if not all(isinstance(n, allowed) for n in ast.walk(tree)):
        return None
    value = eval(compile(tree, "<macro>", "eval"))
    return value if isinstance(value, int) else None


def integer_macros(cc, header, declared):
    """#define lines for the object-like DF1_* macros that are integer constants."""
    incdir = os.path.dirname(os.path.abspath(header))
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "macros.c")
        with open(src, "w") as f:
            f.write('#include "%s"\n' % os.path.basename(header))
        res = subprocess.run(cc.split() + ["-E", "-dM", "-std=c11", "-I", incdir, src],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
        if res.returncode != 0:
            raise SystemExit("gen_cdefs: %s -E -dM failed:\n%s" % (cc, res.stderr))
    names = sorted(set(re.findall(r"^#define (DF1_[A-Za-z0-9_]+)(?=\s|$)", res.stdout, re.M)))
    names = [n for n in names if n not in declared]
    probe = "".join("cdefs_probe_%s %s\n" % (n, n) for n in names)
    lines = preprocess(cc, header, probe).splitlines()
    defines = []
    for line in lines:
        m = re.match(r"^cdefs_probe_(DF1_[A-Za-z0-9_]+) (.*)$", line)
        if not m:
            continue
        value = integer_value(m.group(2))
        if value is not None:
            defines.append("#define %s %d" % (m.group(1), value))
    return defines


def generate(header, cc):
    incdir = os.path.dirname(os.path.abspath(header))
    decls = library_lines(preprocess(cc, header), incdir)
    body = layout(decls)
    declared = set(re.findall(r"\b(DF1_[A-Za-z0-9_]+)\b", body))
    defines = integer_macros(cc, header, declared)
    return BANNER + "\n".join(defines) + "\n\n" + body + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--header", default=DEFAULT_HEADER, help="df1.h to read (default: the tree's)")
    ap.add_argument("--out", default=DEFAULT_OUT, help="the cdefs file (default: the package's)")
    ap.add_argument("--check", action="store_true", help="compare instead of writing; exit 1 if stale")
    args = ap.parse_args(argv)
    cc = os.environ.get("CC") or "cc"
    text = generate(args.header, cc)
    if args.check:
        try:
            with open(args.out) as f:
                old = f.read()
        except OSError as e:
            print("gen_cdefs: %s: %s" % (args.out, e.strerror), file=sys.stderr)
            return 1
        if old != text:
            print("gen_cdefs: %s is stale: run python3 python/gen_cdefs.py after changing df1.h" % args.out,
                  file=sys.stderr)
            return 1
        return 0
    with open(args.out, "w") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
