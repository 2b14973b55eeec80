# SPDX-License-Identifier: MPL-2.0
"""The C library, loaded with cffi in ABI mode (no compiler needed).

libdf1.so.0 is found, in this order: the LIBDF1_PATH environment variable (a
.so file, or a build directory holding libdf1.so.0), the dynamic linker's
search (ld.so.cache, LD_LIBRARY_PATH), then /usr/local/lib and /usr/lib as
`make install` puts it there (before ldconfig has run).

cffi releases the GIL around every call into an ABI-mode library, so a call
that waits on the line lets other Python threads run.
"""
import os

import cffi

ffi = cffi.FFI()
_here = os.path.dirname(os.path.abspath(__file__))
with open(os.path.join(_here, "_cdefs.h")) as _f:
    ffi.cdef(_f.read())

SONAME = "libdf1.so.0"


def _candidates():
    env = os.environ.get("LIBDF1_PATH")
    if env:
        if os.path.isdir(env):
            return [os.path.join(env, SONAME)], env
        return [env], env
    return [SONAME, "/usr/local/lib/" + SONAME, "/usr/lib/" + SONAME], None


def _load():
    paths, env = _candidates()
    errors = []
    for p in paths:
        if os.path.sep in p and not os.path.exists(p):
            errors.append("%s: no such file" % p)
            continue
        try:
            return ffi.dlopen(p)
        except OSError as e:
            errors.append(str(e))
    if env:
        hint = "LIBDF1_PATH=%s does not name a loadable libdf1" % env
    else:
        hint = "install libdf1 (make install; ldconfig) or set LIBDF1_PATH to the .so or a build directory"
    raise ImportError("libdf1: cannot load %s (%s): %s" % (SONAME, hint, "; ".join(errors)))


lib = _load()

_ver = lib.df1_version()
if _ver.major != lib.DF1_VERSION_MAJOR:
    raise ImportError("libdf1: the library is version %s, the binding was made for major version %d"
                      % (ffi.string(_ver.string).decode(), lib.DF1_VERSION_MAJOR))


def text(p):
    """A C string (const char *) as str, or None for NULL."""
    if p == ffi.NULL:
        return None
    return ffi.string(p).decode("utf-8", "replace")
