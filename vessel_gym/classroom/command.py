"""``vessel-gym classroom SCENARIO``: its options and its run (docs/classroom.md)."""

from __future__ import annotations

import argparse
import asyncio
import ipaddress
import socket
import ssl
import time
from pathlib import Path

from vessel_gym.classroom import MAX_SHIPS
from vessel_gym.cli_args import UsageError, host_port, int_in, number_in

DEFAULT_BIND = "127.0.0.1:8090"


def add_parser(sub: argparse._SubParsersAction) -> None:
    cl = sub.add_parser(
        "classroom",
        help="a class in the browser: students steer ships of one harbour, the instructor watches and debriefs",
    )
    cl.add_argument("scenario", help="built-in scenario name or scenario file (vessel-gym scenarios)")
    cl.add_argument(
        "--ships",
        type=int_in("--ships", 1, MAX_SHIPS),
        default=4,
        help=f"own ships, 1-{MAX_SHIPS} (default 4)",
    )
    cl.add_argument(
        "--pilots",
        type=int_in("--pilots", 0, MAX_SHIPS),
        default=0,
        help="of the ships, how many the scripted harbour pilot steers (the last ones; default 0)",
    )
    cl.add_argument(
        "--agent",
        metavar="ZIP",
        default=None,
        help="a trained HarbourApproach agent (e.g. agents/trained/ppo_HarbourApproach-v3_seed0.zip) for --agents",
    )
    cl.add_argument(
        "--agents",
        type=int_in("--agents", 0, MAX_SHIPS),
        default=None,
        help="of the ships, how many the --agent steers (the last ones before the pilots; default 1 with --agent)",
    )
    cl.add_argument(
        "--bind",
        metavar="HOST:PORT",
        default=DEFAULT_BIND,
        help=f"where the page is served (default {DEFAULT_BIND}; a non-loopback address needs --allow-lan)",
    )
    cl.add_argument(
        "--allow-lan", action="store_true", help="allow a --bind address that other machines can reach"
    )
    cl.add_argument(
        "--host-name",
        action="append",
        default=[],
        metavar="NAME",
        help="a name the students' browsers reach this machine by (e.g. its DNS name; repeatable)",
    )
    cl.add_argument("--tls-cert", metavar="PEM", default=None, help="serve https/wss with this certificate")
    cl.add_argument("--tls-key", metavar="PEM", default=None, help="the certificate's private key")
    cl.add_argument(
        "--time-factor",
        type=number_in("--time-factor", 0.1, 10.0),
        default=1.0,
        help="simulation seconds per wall-clock second (default 1: real time)",
    )
    cl.add_argument(
        "--duration",
        type=number_in("--duration", 0.1, 1e7),
        default=None,
        help="end the class after this many wall-clock seconds (default: at Ctrl-C)",
    )
    cl.add_argument("--seed", type=int_in("--seed", 0), default=None, help="seed of the starts and weather")
    cl.add_argument("--out", default=".", help="folder of the class debrief (default: here)")


def _bind_socket(args: argparse.Namespace) -> socket.socket:
    host, port = host_port(args.bind, "--bind")
    try:
        ip = ipaddress.ip_address(host)
    except ValueError:
        raise UsageError(
            f"vessel-gym classroom: --bind: {host!r} is not an IP address (give the address)"
        ) from None
    if not ip.is_loopback and not args.allow_lan:
        raise UsageError(
            f"vessel-gym classroom: --bind {args.bind} is reachable from the network: add --allow-lan to mean it"
        )
    family = socket.AF_INET6 if ip.version == 6 else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((host, port))
    except OSError as exc:
        sock.close()
        raise UsageError(f"vessel-gym classroom: --bind {args.bind}: {exc.strerror or exc}") from None
    sock.listen(128)
    return sock


def _tls(args: argparse.Namespace) -> ssl.SSLContext | None:
    if (args.tls_cert is None) != (args.tls_key is None):
        raise UsageError("vessel-gym classroom: --tls-cert and --tls-key go together")
    if args.tls_cert is None:
        return None
    ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    ctx.minimum_version = ssl.TLSVersion.TLSv1_2
    try:
        ctx.load_cert_chain(args.tls_cert, args.tls_key)
    except (OSError, ssl.SSLError) as exc:
        raise UsageError(
            f"vessel-gym classroom: --tls-cert/--tls-key: {getattr(exc, 'strerror', None) or exc}"
        ) from None
    return ctx


def _lan_address() -> str:
    """This machine's address on the network its default route leads to (a UDP socket's connect sends
    nothing), for the address printed when bound to every interface."""
    try:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            s.connect(("192.0.2.1", 9))  # TEST-NET-1: never routed anywhere, only looked up in the table
            return s.getsockname()[0]
    except OSError:
        return socket.gethostname()


def run(args: argparse.Namespace) -> int:
    """Check every option, then serve the class until --duration or Ctrl-C; write the debrief at the end."""
    from vessel_gym.classroom.codes import ClassCodes
    from vessel_gym.classroom.harbour import ClassHarbour
    from vessel_gym.classroom.server import ClassroomServer
    from vessel_gym.outputs import check_free, safe_name
    from vessel_gym.scenarios import load_scenario

    sc = load_scenario(args.scenario)  # a bad name is one line here (ScenarioError is a ValueError)
    if args.pilots > args.ships:
        raise UsageError(f"vessel-gym classroom: --pilots {args.pilots} is more than --ships {args.ships}")
    agents = args.agents if args.agents is not None else int(args.agent is not None)
    if agents and args.agent is None:
        raise UsageError("vessel-gym classroom: --agents needs --agent (the trained agent's .zip)")
    if args.pilots + agents > args.ships:
        raise UsageError(
            f"vessel-gym classroom: --pilots {args.pilots} and --agents {agents} are more than --ships {args.ships}"
        )
    tls = _tls(args)
    stamp = time.strftime("%Y%m%d-%H%M%S", time.gmtime())
    debrief = Path(args.out) / f"classroom_{safe_name(sc.name)}_{stamp}.html"
    check_free([debrief], False, "--out")
    sock = _bind_socket(args)
    try:
        harbour = ClassHarbour(
            args.scenario, args.ships, seed=args.seed, pilots=args.pilots, agent=args.agent, agents=agents
        )
    except BaseException:
        sock.close()
        raise
    codes = ClassCodes(args.ships)
    host = sock.getsockname()[0]
    server = ClassroomServer(
        harbour,
        codes,
        (host, sock.getsockname()[1]),
        host_names=tuple(args.host_name),
        tls=tls,
        time_factor=args.time_factor,
        debrief_path=debrief,
    )
    scheme = "https" if tls else "http"
    shown = (
        host if host not in ("0.0.0.0", "::") else (args.host_name[0] if args.host_name else _lan_address())
    )
    print(
        f"classroom: {sc.name}, {args.ships} ships: open {scheme}://{shown}:{sock.getsockname()[1]}/",
        flush=True,
    )
    # the instructor's code is shown once, here, to whoever started the class; the others are on their page
    print(f"classroom: instructor code {codes.instructor}", flush=True)
    try:
        asyncio.run(server.serve(sock, duration_s=args.duration))
    except KeyboardInterrupt:
        pass
    finally:
        sock.close()
        _html, path = server.write_debrief()
        stats = " ".join(f"{k}={v}" for k, v in server.stats.items() if v)
        print(f"classroom: debrief {path}" + (f"; {stats}" if stats else ""), flush=True)
    return 0
