# SPDX-License-Identifier: MPL-2.0
"""df1opcua's server: asyncua set up with the line's address space, its security, and the loop."""
import asyncio
import logging
import os
import signal
import socket
import sys

from asyncua import Server, ua

from .security import Pki, Users, default_pki
from .space import NAMESPACE, Line, Space, Writes, tag_rows

PROG = "df1opcua"
log = logging.getLogger(PROG)


def sd_notify(msg: str) -> None:
    """Tell systemd (Type=notify) when NOTIFY_SOCKET is set; nothing otherwise."""
    path = os.environ.get("NOTIFY_SOCKET")
    if not path:
        return
    if path.startswith("@"):
        path = "\0" + path[1:]
    try:
        with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM) as s:
            s.sendto(msg.encode(), path)
    except OSError as e:
        log.warning("NOTIFY_SOCKET: %s", e)


def _url(host: str, port: int) -> str:
    return "opc.tcp://%s:%d/" % ("[%s]" % host if ":" in host else host, port)


async def serve(args, plc, poller, reopen, host: str, port: int, loopback: bool, table, line: str) -> int:
    """Serve until SIGINT or SIGTERM; reopen() opens the line again after a loss. The exit status."""
    tags = tag_rows(plc, poller)
    problems = Space.check_names(tags)
    if problems:
        for p in problems:
            print("%s: %s: %s" % (PROG, args.map, p), file=sys.stderr)
        plc.close()
        return 2
    pki = Pki(args.pki or default_pki())
    app_uri = "urn:%s:libdf1:df1opcua" % socket.gethostname()
    try:
        if await pki.ensure_own(app_uri, "df1opcua@%s" % socket.gethostname()):
            log.warning("made the server's certificate %s (key in %s)", pki.cert, pki.key)
    except OSError as e:
        print("%s: --pki %s: %s" % (PROG, pki.root, e), file=sys.stderr)
        plc.close()
        return 2
    server = Server(user_manager=Users(table))
    await server.init()
    server.set_endpoint(_url(host, port))
    server.set_server_name("df1opcua %s" % line)
    await server.set_application_uri(app_uri)
    await server.load_certificate(str(pki.cert))
    await server.load_private_key(str(pki.key))
    policies = [ua.SecurityPolicyType.Basic256Sha256_SignAndEncrypt, ua.SecurityPolicyType.Basic256Sha256_Sign]
    insecure = loopback or args.allow_insecure
    if insecure:
        policies.insert(0, ua.SecurityPolicyType.NoSecurity)
    server.set_security_policy(policies)
    server.set_identity_tokens([ua.UserNameIdentityToken] if table is not None
                               else [ua.AnonymousIdentityToken, ua.UserNameIdentityToken])
    idx = await server.register_namespace(NAMESPACE)
    space = Space(server, idx, line, tags)
    await space.build()

    loop = asyncio.get_running_loop()
    queue: asyncio.Queue = asyncio.Queue()
    stations = sorted({t.station for t in tags})
    the_line = Line(reopen, loop, queue, stations)
    writes = Writes(space, the_line, args.max_pending_writes, args.write_timeout)
    setup = server._setup_server_nodes

    async def guarded_setup() -> None:     # the policies exist from here, before anything listens
        await setup()
        pki.guard(server._policies)
    server._setup_server_nodes = guarded_setup
    try:
        await server.start()
    except OSError as e:
        print("%s: cannot listen on %s:%d: %s" % (PROG, host, port, e.strerror or e), file=sys.stderr)
        plc.close()
        return 1
    stop = asyncio.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(sig, stop.set)
    the_line.start(plc, poller)
    if not loopback:
        log.warning("listening on %s:%d: reachable from other machines%s", host, port,
                    "; SecurityPolicy None offered (--allow-insecure)" if insecure else
                    "; Basic256Sha256 only")
    if not args.quiet:
        print("%s: %d tags of %s on %s (namespace %s, index %d)%s" %
              (PROG, len(tags), line, _url(host, port), NAMESPACE, idx,
               "; users of %s" % args.users if table is not None else ""), file=sys.stderr)
    sd_notify("READY=1\nSTATUS=serving %d tags on %s" % (len(tags), _url(host, port)))

    async def pump() -> None:
        while True:
            kind, item = await queue.get()
            try:
                if kind == "changes":
                    for c in item:
                        await space.apply(c)
                elif kind == "station":
                    await space.set_station(*item)
                elif kind == "lost":
                    await space.all_bad(ua.StatusCodes.BadCommunicationError)
                    for s in stations:
                        await space.set_station(s, "offline", None)
            except Exception:   # one bad change never stops the others
                log.exception("applying %s", kind)

    task = asyncio.create_task(pump())
    await stop.wait()
    sd_notify("STOPPING=1")
    writes.close()
    log.info("stopping: writes %s", writes.counts)
    cancel = getattr(args, "cancel", None)
    # the line's cancel_fd made readable: a transaction under way ends now
    await loop.run_in_executor(None, the_line.stop, (lambda: os.write(cancel[1], b"x")) if cancel else None)
    task.cancel()
    await server.stop()
    return 0
