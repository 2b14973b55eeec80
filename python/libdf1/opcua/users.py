# SPDX-License-Identifier: MPL-2.0
"""The --users file of df1opcua: one user a line, "NAME:scrypt$N$r$p$SALT$HASH" (hex).

Only a salted scrypt hash is stored, never the password. Lines starting with
'#' and blank lines are skipped. Needs nothing beyond the standard library, so
that --add-user works where asyncua is missing too.
"""
import hashlib
import hmac
import os
import re
from typing import Dict, Optional

_N, _R, _P = 1 << 14, 8, 1
_NAME = re.compile(r"^[^\s:#][^\s:]{0,63}$")


class UsersError(ValueError):
    """A users file or a user name that cannot be used; the text says what and where."""


def _hash(password: str, salt: bytes, n: int, r: int, p: int) -> bytes:
    return hashlib.scrypt(password.encode("utf-8"), salt=salt, n=n, r=r, p=p, maxmem=64 * 1024 * 1024, dklen=32)


def make_entry(name: str, password: str) -> str:
    """The line stored for name: its scrypt parameters, a fresh 16-byte salt and the hash."""
    salt = os.urandom(16)
    return "%s:scrypt$%d$%d$%d$%s$%s" % (name, _N, _R, _P, salt.hex(), _hash(password, salt, _N, _R, _P).hex())


def check_name(name: str) -> None:
    if not _NAME.match(name):
        raise UsersError("user name %r: 1-64 characters, no blanks or ':', not starting with '#'" % name)


def load(path: str) -> Dict[str, str]:
    """The users of the file by name (their stored hash text); UsersError naming the line at fault."""
    users: Dict[str, str] = {}
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            name, sep, rest = line.partition(":")
            parts = rest.split("$")
            if not sep or len(parts) != 6 or parts[0] != "scrypt" or not _NAME.match(name):
                raise UsersError("%s:%d: not NAME:scrypt$N$r$p$SALT$HASH" % (path, n))
            try:
                int(parts[1]), int(parts[2]), int(parts[3]), bytes.fromhex(parts[4]), bytes.fromhex(parts[5])
            except ValueError:
                raise UsersError("%s:%d: a number or a hex field is malformed" % (path, n)) from None
            users[name] = rest
    return users


def verify(stored: Optional[str], password: Optional[str]) -> bool:
    """Whether password matches a stored hash text (False for a missing user or password)."""
    if stored is None or password is None:
        return False
    _, n, r, p, salt, want = stored.split("$")
    got = _hash(password, bytes.fromhex(salt), int(n), int(r), int(p))
    return hmac.compare_digest(got, bytes.fromhex(want))


def add_user(path: str, name: str, password: str) -> bool:
    """Store name with password's hash in path (created 0600 when missing; an existing entry of
    name replaced, every other line kept). Returns True if name was new."""
    check_name(name)
    if not password:
        raise UsersError("an empty password")
    lines = []
    if os.path.exists(path):
        load(path)          # refuse to rewrite a file we cannot read back
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    kept = [ln for ln in lines if ln.strip().partition(":")[0] != name or ln.strip().startswith("#")]
    new = len(kept) == len(lines)
    kept.append(make_entry(name, password))
    tmp = path + ".tmp"
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write("\n".join(kept) + "\n")
    os.replace(tmp, path)
    return new
