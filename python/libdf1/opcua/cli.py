# SPDX-License-Identifier: MPL-2.0
"""The df1opcua command (df1opcua(1)): options, start, run until SIGINT or SIGTERM.

Exit status as the other tools: 0 stopped by a signal, 1 a failure (the line
cannot be opened, the port cannot be bound, asyncua missing), 2 a usage or
configuration error (an option, the mapping, the users file).
"""
import argparse
import asyncio
import getpass
import ipaddress
import logging
import os
import re
import socket
import sys
from typing import List, Optional, Tuple

PROG = "df1opcua"
log = logging.getLogger(PROG)


class Usage(Exception):
    """A usage or configuration error: exit 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:
        raise Usage(message + " (see df1opcua --help)")


def number(lo: int, hi: int):
    """A decimal number (leading zeros decimal) or 0x hex, lo..hi, as the C tools take them."""
    def conv(s: str) -> int:
        try:
            v = int(s, 16) if s.lower().startswith("0x") else int(s, 10)
        except ValueError:
            raise argparse.ArgumentTypeError("%r is not a number" % s) from None
        if not lo <= v <= hi:
            raise argparse.ArgumentTypeError("%s: %d..%d" % (s, lo, hi))
        return v
    return conv


def parse_listen(s: str) -> Tuple[str, int]:
    """[ADDR:]PORT, ADDR an IPv4 address, [IPv6] or a host name; default 127.0.0.1."""
    m = re.fullmatch(r"(?:\[([0-9A-Fa-f:.]+)\]:|([^:\[\]]+):)?(\d{1,5})", s)
    if not m or not 1 <= int(m.group(3)) <= 65535:
        raise Usage("--listen %r: [ADDR:]PORT, PORT 1-65535 (e.g. 4840, 0.0.0.0:4840, [::1]:4840)" % s)
    return (m.group(1) or m.group(2) or "127.0.0.1"), int(m.group(3))


def is_loopback(host: str) -> bool:
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        try:
            return all(ipaddress.ip_address(a[4][0]).is_loopback for a in socket.getaddrinfo(host, None))
        except (socket.gaierror, ValueError):
            return False


def line_name(device: str) -> str:
    base = device.rstrip("/").rsplit("/", 1)[-1] if "://" not in device else device.split("://", 1)[1]
    return re.sub(r"[^A-Za-z0-9_-]", "_", base) or "line"


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog=PROG, add_help=False, usage="%(prog)s -d DEV --map FILE.csv [OPTIONS]",
                formatter_class=argparse.RawDescriptionHelpFormatter,
                description="Serve the tags of a DF1 line (PLC-5, SLC 500, MicroLogix) as an OPC UA server: "
                            "Objects/LINE/stationN/TAG,\nNodeIds ns=N;s=LINE.stationN.TAG. See df1opcua(1).",
                epilog="Exit status: 0 stopped by SIGINT/SIGTERM, 1 failure, 2 usage or configuration error.")
    g = p.add_argument_group("line (as df1read)")
    g.add_argument("-d", "--device", metavar="DEV",
                   help="serial device, tcp://HOST:PORT or eip://HOST[:PORT][/2] (df1gw --eip); "
                        "default the network file's port, else $DF1_DEVICE")
    g.add_argument("-N", "--net", metavar="FILE", help="a network configuration CSV (libdf1(7))")
    g.add_argument("-a", "--station", type=number(0, 254), default=1, metavar="N",
                   help="default station for diagnostics (the mapping's rows name their own); default 1")
    g.add_argument("--src", type=number(0, 254), metavar="N", help="our own station (default 0)")
    g.add_argument("-b", "--baud", type=number(1, 10000000), metavar="N", help="baud rate (default 19200)")
    g.add_argument("-P", "--parity", choices=("none", "even", "odd"))
    g.add_argument("--data-bits", type=number(7, 8), metavar="7|8")
    g.add_argument("--stop-bits", type=number(1, 2), metavar="1|2")
    g.add_argument("--handshake", nargs="?", const="yes", choices=("yes", "no"))
    g.add_argument("--duplex", choices=("full", "half"), help="full (default) or half (multidrop master)")
    g.add_argument("--check", choices=("crc", "bcc"), help="error check (default crc)")
    g.add_argument("--plc", choices=("slc", "micrologix", "slc502", "plc5", "plc2", "plc3"),
                   help="controller family for the default station (default slc)")
    g.add_argument("-o", "--timeout", type=number(0, 360000), metavar="MS", help="ACK and reply timeout")
    g.add_argument("--cmd-timeout", type=number(500, 5000), metavar="MS", help="transaction timeout")
    g.add_argument("--nak-retries", type=number(0, 10), metavar="N")
    g.add_argument("--enq-retries", type=number(0, 10), metavar="N")
    g.add_argument("--tx-delay", type=number(0, 65535), metavar="MS")
    g.add_argument("--rs485", action="store_true", help="the kernel's RS-485 mode")
    g = p.add_argument_group("tags")
    g.add_argument("--map", metavar="FILE.csv", help="the mapping file: one tag a row (required)")
    g.add_argument("--watchdog", type=number(100, 86400000), metavar="MS",
                   help="a station silent this long is offline, its tags Bad (df1_poll_set_watchdog(3))")
    g.add_argument("--max-pending-writes", type=number(1, 100000), default=1000, metavar="N",
                   help="writes waiting for the line at most; more: BadTooManyOperations (default 1000)")
    g.add_argument("--write-timeout", type=number(1, 3600000), default=30000, metavar="MS",
                   help="a write not started on the line within MS ms: BadTimeout, never written (default 30000)")
    g = p.add_argument_group("server")
    g.add_argument("--listen", default="127.0.0.1:4840", metavar="[ADDR:]PORT",
                   help="where to listen (default 127.0.0.1:4840, this machine only)")
    g.add_argument("--name", metavar="LINE", help="the line's folder (default the device's name)")
    g.add_argument("--pki", metavar="DIR",
                   help="certificates: own/ trusted/ rejected/ (default $STATE_DIRECTORY, else "
                        "~/.local/state/df1opcua)")
    g.add_argument("--allow-insecure", action="store_true",
                   help="offer SecurityPolicy None on a non-loopback address too")
    g.add_argument("--users", metavar="FILE", help="user names and password hashes; anonymous refused")
    g.add_argument("--add-user", metavar="NAME", help="add NAME to --users FILE, the password read on stdin, "
                                                     "and exit")
    g = p.add_argument_group("general")
    g.add_argument("-v", "--verbose", action="count", default=0,
                   help="say more on stderr (sessions, writes); twice: asyncua's own warnings too")
    g.add_argument("-q", "--quiet", action="store_true", help="only errors on stderr")
    g.add_argument("--version", action="store_true", help="print the version and exit")
    g.add_argument("-h", "--help", action="store_true", help="this help")
    return p


def add_user(args) -> int:
    from . import users
    if not args.users:
        raise Usage("--add-user needs --users FILE")
    users.check_name(args.add_user)
    if sys.stdin.isatty():
        pw = getpass.getpass("password for %s: " % args.add_user)
    else:
        pw = sys.stdin.readline().rstrip("\r\n")
    new = users.add_user(args.users, args.add_user, pw)
    if not args.quiet:
        print("%s: %s %s in %s" % (PROG, "added" if new else "changed the password of", args.add_user, args.users),
              file=sys.stderr)
    return 0


def open_line(args):
    """Open the line and load the mapping: (plc, poller). Raises libdf1's errors."""
    import libdf1
    kw = dict(net=args.net, station=args.station, src=args.src, baud=args.baud, parity=args.parity,
              data_bits=args.data_bits, stop_bits=args.stop_bits, duplex=args.duplex, check=args.check,
              plc=args.plc, timeout_ms=args.timeout, cmd_timeout_ms=args.cmd_timeout,
              nak_retries=args.nak_retries, enq_retries=args.enq_retries, tx_delay_ms=args.tx_delay)
    if args.handshake is not None:
        kw["handshake"] = args.handshake == "yes"
    if args.rs485:
        kw["rs485"] = True
    if getattr(args, "cancel", None):
        kw["cancel_fd"] = args.cancel[0]     # readable at stop: a wait on the line ends at once
    plc = libdf1.open(args.device, **kw)
    try:
        poller = plc.poller(map=args.map, strict=True, watchdog_ms=args.watchdog)
    except BaseException:
        plc.close()
        raise
    return plc, poller


def main(argv: Optional[List[str]] = None) -> int:
    logging.basicConfig(format=PROG + ": %(message)s", level=logging.WARNING)
    try:
        args = build_parser().parse_args(argv)
        if args.help:
            build_parser().print_help()
            return 0
        if args.version:
            import libdf1
            print("%s %s (libdf1 %s)" % (PROG, libdf1.__version__, libdf1.library_version()))
            return 0
        log.setLevel(logging.INFO if args.verbose else logging.ERROR if args.quiet else logging.WARNING)
        if args.add_user:
            return add_user(args)
        return run(args)
    except Usage as e:
        print("%s: %s" % (PROG, e), file=sys.stderr)
        return 2
    except ValueError as e:     # a users file, a user name
        print("%s: %s" % (PROG, e), file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 0
    except OSError as e:        # a file of an option: the users file, the PKI folder
        print("%s: %s" % (PROG, e), file=sys.stderr)
        return 1


def run(args) -> int:
    if not args.map:
        raise Usage("--map FILE.csv is required")
    if not os.path.isfile(args.map):
        raise Usage("--map %s: no such file" % args.map)
    if not args.device and not args.net and not os.environ.get("DF1_DEVICE"):
        raise Usage("no line: -d DEV, -N FILE or $DF1_DEVICE")
    args.device = args.device or (None if args.net else os.environ.get("DF1_DEVICE"))
    host, port = parse_listen(args.listen)
    if args.name is not None and (not args.name or "." in args.name):
        raise Usage("--name %r: not empty, no '.' (it starts every NodeId)" % args.name)
    try:
        import asyncua  # noqa: F401
    except ImportError:
        print("%s: needs asyncua (Python 3.10 or later): pip install './python[opcua]' or pip install asyncua"
              % PROG, file=sys.stderr)
        return 1
    logging.getLogger("asyncua").setLevel(logging.WARNING if args.verbose > 1 else logging.CRITICAL)
    from . import users as users_mod
    table = None
    if args.users:
        try:
            table = users_mod.load(args.users)
        except OSError as e:
            raise Usage("--users %s: %s" % (args.users, e.strerror)) from None
        if not table:
            raise Usage("--users %s: no user in it (add one with --add-user NAME)" % args.users)
    loopback = is_loopback(host)
    args.cancel = os.pipe()
    import libdf1
    try:
        plc, poller = open_line(args)
    except libdf1.ConfigError as e:
        for i in e.issues:
            print("%s: %s:%d: [%d] %s" % (PROG, args.map, i.line, i.catalog_id, i.text), file=sys.stderr)
        print("%s: %s" % (PROG, e), file=sys.stderr)
        return 2
    except (libdf1.Df1ValueError, libdf1.AddressError) as e:
        print("%s: %s" % (PROG, e), file=sys.stderr)
        return 2
    except libdf1.Df1Error as e:
        print("%s: %s" % (PROG, e), file=sys.stderr)
        return 1
    from .serve import serve
    return asyncio.run(serve(args, plc, poller, lambda: open_line(args), host, port, loopback, table,
                             line_name(args.device or "line") if args.name is None else args.name))
