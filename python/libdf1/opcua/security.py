# SPDX-License-Identifier: MPL-2.0
"""df1opcua's security: the PKI folder (own/ trusted/ rejected/), the client certificate check, users.

The layout is the one OPC UA stacks share: own/ holds the server's certificate
(own/cert.der) and key (own/private/key.pem, 0600), made at the first start;
a client certificate (DER or PEM, any file name, also under trusted/certs/)
in trusted/ is admitted; an unknown one is refused with
BadCertificateUntrusted and its DER saved in rejected/ so that an operator can
move it to trusted/. trusted/ is read again at every session: no restart.
"""
import datetime
import hashlib
import logging
import os
import socket
from pathlib import Path
from typing import Dict, Optional, Set

from asyncua import ua
from asyncua.crypto import cert_gen
from asyncua.common.utils import ServiceError
from asyncua.crypto.permission_rules import User, UserRole
from asyncua.server.user_managers import UserManager
from cryptography import x509
from cryptography.hazmat.primitives.serialization import Encoding
from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

from . import users as users_mod

log = logging.getLogger("df1opcua")


def default_pki() -> str:
    """$STATE_DIRECTORY (systemd's StateDirectory=, the first if several), else ~/.local/state/df1opcua."""
    sd = os.environ.get("STATE_DIRECTORY")
    if sd:
        return sd.split(":")[0]
    base = os.environ.get("XDG_STATE_HOME") or os.path.join(os.path.expanduser("~"), ".local", "state")
    return os.path.join(base, "df1opcua")


class Pki:
    def __init__(self, root: str) -> None:
        self.root = Path(root)
        self.own = self.root / "own"
        self.trusted = self.root / "trusted"
        self.rejected = self.root / "rejected"
        self.cert = self.own / "cert.der"
        self.key = self.own / "private" / "key.pem"

    def make_dirs(self) -> None:
        for d in (self.root, self.own, self.own / "private", self.trusted, self.rejected):
            d.mkdir(mode=0o700, parents=True, exist_ok=True)

    async def ensure_own(self, app_uri: str, name: str) -> bool:
        """Make the server's key and certificate if missing (or the certificate expired); True if made."""
        self.make_dirs()
        had = self.cert.is_file() and self.key.is_file()
        old = self.cert.stat().st_mtime if had else None
        umask = os.umask(0o077)
        try:
            await cert_gen.setup_self_signed_certificate(
                self.key, self.cert, app_uri, socket.gethostname(), [ExtendedKeyUsageOID.SERVER_AUTH],
                {"commonName": name, "organizationName": "libdf1"})
        finally:
            os.umask(umask)
        return not had or self.cert.stat().st_mtime != old

    def trusted_fingerprints(self) -> Set[bytes]:
        out: Set[bytes] = set()
        for dirpath, _, files in os.walk(self.trusted):
            for fn in files:
                der = _load_der(os.path.join(dirpath, fn))
                if der is not None:
                    out.add(hashlib.sha256(der).digest())
        return out

    def check(self, der: bytes) -> None:
        """Admit a trusted, current client certificate (DER); refuse others (ServiceError), keeping
        an unknown one in rejected/."""
        try:
            cert = x509.load_der_x509_certificate(der)
        except ValueError:
            log.warning("a client certificate that is not DER X.509 refused")
            raise ServiceError(ua.StatusCodes.BadCertificateInvalid) from None
        subject = _subject(cert)
        if hashlib.sha256(der).digest() not in self.trusted_fingerprints():
            path = self.rejected / ("%s [%s].der" % (_safe(subject), hashlib.sha1(der).hexdigest()))
            if not path.exists():
                path.write_bytes(der)
            log.warning("client certificate %r refused: not trusted (saved as %s; move it to %s/ to admit it)",
                        subject, path, self.trusted)
            raise ServiceError(ua.StatusCodes.BadCertificateUntrusted)
        now = datetime.datetime.now(datetime.timezone.utc)
        if not cert.not_valid_before_utc <= now <= cert.not_valid_after_utc:
            log.warning("client certificate %r refused: outside its validity", subject)
            raise ServiceError(ua.StatusCodes.BadCertificateTimeInvalid)
        log.info("client certificate %r admitted", subject)

    def guard(self, factories) -> None:
        """Check the client's certificate when a secure channel is opened with a policy that signs:
        every such factory of asyncua's server checks it before it makes the channel's policy."""
        for f in factories:
            if f.mode == ua.MessageSecurityMode.None_:
                continue
            make = f.create

            def create(peer_certificate, make=make):
                if not peer_certificate:
                    raise ServiceError(ua.StatusCodes.BadCertificateInvalid)
                try:
                    self.check(_first_der(peer_certificate))
                except ServiceError as e:
                    raise _refused(e.code) from None
                return make(peer_certificate)
            f.create = create


def _refused(code: int) -> Exception:
    """A client certificate refused while the secure channel opens. asyncua answers the one
    error it expects at that point (BadRequestTooLarge) with an ERR message carrying the
    exception's code, then closes the connection: with the code set to the true reason
    (BadCertificateUntrusted ...) the client reads it at once, rather than waiting for its
    own timeout."""
    e = ua.uaerrors.BadRequestTooLarge()
    e.code = code
    return e


def _first_der(data: bytes) -> bytes:
    """The first certificate of a chain of DER certificates (its length from the SEQUENCE header)."""
    if len(data) > 4 and data[0] == 0x30 and data[1] == 0x82:
        return data[:4 + (data[2] << 8 | data[3])]
    return data


def _load_der(path: str) -> Optional[bytes]:
    try:
        data = Path(path).read_bytes()
    except OSError:
        return None
    try:
        if b"-----BEGIN CERTIFICATE-----" in data:
            return x509.load_pem_x509_certificate(data).public_bytes(Encoding.DER)
        return x509.load_der_x509_certificate(data).public_bytes(Encoding.DER)
    except ValueError:
        return None


def _subject(cert: x509.Certificate) -> str:
    cn = cert.subject.get_attributes_for_oid(NameOID.COMMON_NAME)
    return str(cn[0].value) if cn else cert.subject.rfc4514_string()


def _safe(s: str) -> str:
    return "".join(c if c.isalnum() or c in "-_. " else "_" for c in s)[:64] or "client"


class Users(UserManager):
    """Sessions with a user name and password of the --users file; None (no --users): anyone.

    A wrong password or an unknown name: None, which asyncua answers BadUserAccessDenied."""

    def __init__(self, table: Optional[Dict[str, str]]) -> None:
        self.table = table

    def get_user(self, iserver, username=None, password=None, certificate=None):
        if self.table is None:
            return User(role=UserRole.User, name=username)
        if username is None:
            log.warning("anonymous session refused (--users)")
            return None
        if not users_mod.verify(self.table.get(username), password):
            log.warning("user %r refused: wrong user name or password", username)
            return None
        log.info("user %r admitted", username)
        return User(role=UserRole.User, name=username)
