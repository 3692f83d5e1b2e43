"""The live link's commands of ``vessel-gym``: ``serve``, its clients ``helm`` and ``view`` (pygame) and
``view3d`` (the browser). Their options and their dispatch live here, beside each other; ``vessel_gym.cli``
registers them and catches their errors like every command's."""

from __future__ import annotations

import argparse
import time

from vessel_gym.cli_args import (
    SEED_MAX,
    UsageError,
    add_token_option,
    check_bindable,
    error_line,
    host_port,
    int_in,
    number_in,
    resolve_address,
    token_arg,
)

#: the commands this module serves
LIVE_COMMANDS = ("serve", "helm", "view", "view3d")

#: the link's JSON channel when none is given: where ``serve`` binds it and the clients look for it
JSON_CHANNEL = "127.0.0.1:10120"


def add_server(sp: argparse.ArgumentParser) -> None:
    """The ``--server`` option of the link's clients (helm, view, view3d)."""
    sp.add_argument("--server", metavar="HOST:PORT", default=JSON_CHANNEL, help="the link's JSON channel")


def need_window(command: str) -> None:
    """One line (exit 2) when no window can open, instead of running unseen."""
    from vessel_gym.ui.display import no_display_reason

    reason = no_display_reason()
    if reason is not None:
        raise UsageError(
            f"vessel-gym {command}: {reason}: it needs a window; run it on a desktop, or with "
            "SDL_VIDEODRIVER=dummy to run unseen"
        )


def add_live_parsers(sub) -> dict[str, argparse.ArgumentParser]:
    """Add the live commands to ``sub`` (the top parser's subparsers); their parsers by name."""
    sv = sub.add_parser("serve", help="run a scenario in real time with the UDP link (NMEA, JSON state/helm)")
    sv.add_argument("scenario", nargs="?", help="built-in scenario name or .toml path (default: harbour)")
    sv.add_argument(
        "--env",
        metavar="ID",
        help="a CollisionAvoidance or Berthing task instead (docs/protocol.md 6.1; default: none)",
    )
    sv.add_argument(
        "--nmea",
        metavar="HOST:PORT",
        action="append",
        default=None,
        help="NMEA 0183 destination (repeatable; default 127.0.0.1:10110; 'off' for none)",
    )
    sv.add_argument("--json", metavar="HOST:PORT", default=JSON_CHANNEL, help="JSON channel bind address")
    sv.add_argument(
        "--view",
        metavar="HOST:PORT",
        action="append",
        default=[],
        help="listen-only JSON destination (a viewer that never says hello; repeatable; default: none)",
    )
    sv.add_argument(
        "--time-factor",
        type=number_in("--time-factor", 0.1, 100),
        default=1.0,
        help="simulated seconds per wall-clock second",
    )
    sv.add_argument(
        "--agent",
        help="helm when no human holds it: pid, pid-nomoto, scripted or SB3 .zip (default pid; Berthing: scripted)",
    )
    sv.add_argument(
        "--target-agent",
        metavar="AGENT",
        default=None,
        help="CollisionAvoidance: the target ships steered by this agent (pid, scripted or SB3 .zip), each from "
        "its own observation, while the own ship is on the helm (default: none, scripted targets)",
    )
    sv.add_argument("--allow-remote", action="store_true", help="allow binding to a non-loopback address")
    sv.add_argument(
        "--failsafe",
        choices=("hold", "midships_stop"),
        default="hold",
        help="orders when a helm panel falls silent",
    )
    sv.add_argument(
        "--duration",
        type=number_in("--duration", 0.1, 1e7),
        default=None,
        help="stop after this many wall-clock seconds (default: run until Ctrl-C)",
    )
    sv.add_argument(
        "--seed",
        type=int_in("--seed", 0, SEED_MAX),
        default=None,
        help="seed of the first episode; later episodes continue its random stream (default: a fresh random draw)",
    )

    hm = sub.add_parser("helm", help="pygame helm panel for a running 'vessel-gym serve'")
    add_server(hm)
    hm.add_argument("--name", default="helm", help="name shown to the server and other clients")
    vw = sub.add_parser("view", help="passive pygame viewer of a running 'vessel-gym serve'")
    add_server(vw)
    vw.add_argument(
        "--listen",
        metavar="HOST:PORT",
        default=None,
        help="wait for state sent to this address instead of saying hello (static destination; default: none, "
        "say hello to --server)",
    )
    for sp in (hm, vw):
        sp.add_argument(
            "--duration",
            type=number_in("--duration", 0.1, 1e7),
            default=None,
            help="close after this many wall-clock seconds (default: when the window is closed)",
        )
    v3 = sub.add_parser(
        "view3d", help="3D view in the browser of a running 'vessel-gym serve' (extra 'view3d')"
    )
    add_server(v3)
    v3.add_argument(
        "--http",
        metavar="HOST:PORT",
        default="127.0.0.1:8080",
        help="where the page is served: a loopback address or name (resolved once, 5 s at most)",
    )
    v3.add_argument(
        "--lan",
        action="store_true",
        help="allow a --http address that is not loopback (the page is then reachable from the network)",
    )
    v3.add_argument(
        "--camera",
        default="chase",
        choices=("chase", "bridge", "top-down", "harbour", "free"),
        help="first camera (C cycles them in the page)",
    )
    v3.add_argument(
        "--rate",
        type=number_in("--rate", 1.0, 50.0),
        default=20.0,
        help="state rate asked of the link, Hz (1-50)",
    )
    v3.add_argument(
        "--duration",
        type=number_in("--duration", 0.1, 1e7),
        default=None,
        help="stop after this many wall-clock seconds (default: at Ctrl-C)",
    )
    for sp in (sv, hm, vw, v3):
        add_token_option(sp)
    return {"serve": sv, "helm": hm, "view": vw, "view3d": v3}


def run_live(args: argparse.Namespace) -> int:
    """Run one of :data:`LIVE_COMMANDS` with its parsed arguments."""
    if args.command == "serve":
        from vessel_gym.net.serve import serve

        nmea = (
            []
            if args.nmea == ["off"]
            else [host_port(t, "--nmea") for t in (args.nmea or ["127.0.0.1:10110"])]
        )
        return serve(
            args.scenario,
            env=args.env,
            nmea=nmea,
            json_bind=host_port(args.json, "--json"),
            listen_only=[host_port(t, "--view") for t in args.view],
            time_factor=args.time_factor,
            agent=args.agent,
            target_agent=args.target_agent,
            allow_remote=args.allow_remote,
            failsafe=args.failsafe,
            duration_s=args.duration,
            seed=args.seed,
            token=token_arg(args),
        )
    if args.command in ("helm", "view"):
        from vessel_gym.ui import panels

        server = resolve_address(host_port(args.server, "--server"), "--server")
        token = token_arg(args)
        listen = host_port(args.listen, "--listen") if getattr(args, "listen", None) else None
        if listen is not None:
            check_bindable(listen, "--listen")
        need_window(args.command)
        start = time.monotonic()
        if args.command == "helm":
            result = panels.run_helm(server, name=args.name, token=token, duration_s=args.duration)
        else:
            result = panels.run_viewer(server, listen=listen, token=token, duration_s=args.duration)
        if result.states_received == 0:  # the window said so; a log or a closed window needs the line
            where = f"at --listen {args.listen}" if listen else f"from {args.server}"
            error_line(
                f"vessel-gym {args.command}: no state {where} in {time.monotonic() - start:.0f} s: is "
                "'vessel-gym serve' running there (with the same --token)?"
            )
            return 1
        return 0
    if args.command == "view3d":
        try:
            import viser  # noqa: F401

            from vessel_gym.ui.view3d import view3d
        except ImportError:
            raise UsageError(
                "vessel-gym view3d: needs the 'view3d' extra: pip install 'vessel-gym[view3d]'"
            ) from None
        return view3d(
            resolve_address(host_port(args.server, "--server"), "--server"),
            host_port(args.http, "--http"),
            lan=args.lan,
            camera=args.camera,
            rate_hz=args.rate,
            token=token_arg(args),
            duration_s=args.duration,
        )
    raise UsageError(f"vessel-gym: unknown command {args.command!r}")
