"""The ``vessel-gym`` command. Exit codes: 0 success, 1 a manoeuvre could not complete, 2 bad input
(one line on stderr naming what was wrong)."""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Sequence


class UsageError(Exception):
    """Bad command-line input (exit code 2)."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2 (argparse prints usage lines by default)
        raise UsageError(f"{self.prog}: {message}")


def _finite(kind: str, lo: float | None = None, hi: float | None = None):
    def conv(text: str) -> float:
        try:
            x = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{kind} must be a number, got {text!r}") from None
        if not math.isfinite(x):
            raise argparse.ArgumentTypeError(f"{kind} must be finite, got {text!r}")
        if (lo is not None and x < lo) or (hi is not None and x > hi):
            raise argparse.ArgumentTypeError(f"{kind} {x:g} outside [{lo:g}, {hi:g}]")
        return x

    return conv


def _json_default(o):
    try:
        return float(o)
    except (TypeError, ValueError):
        return str(o)


def _emit(data: dict, as_json: bool, text: str) -> None:
    if as_json:
        from vessel_gym.outputs import rounded

        print(json.dumps(rounded(data), default=_json_default, allow_nan=False))
    else:
        print(text)


def _fmt(d: dict) -> str:
    rows = []
    for k, v in d.items():
        if isinstance(v, float):
            v = f"{v:.3f}"
        elif isinstance(v, list):
            v = ", ".join(f"{x:.2f}" if isinstance(x, float) else str(x) for x in v)
        rows.append(f"{k:<24}{v}")
    return "\n".join(rows)


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="vessel-gym", description="Ship manoeuvring: IMO checks, manoeuvres, environments.")
    sub = p.add_subparsers(dest="command", parser_class=_Parser)

    imo = sub.add_parser("imo", help="all IMO MSC.137(76) criteria for a ship (name or .toml path)")
    imo.add_argument("ship")
    imo.add_argument("--json", action="store_true", help="machine-readable output")
    imo.add_argument(
        "--plot",
        metavar="DIR|FILE.pdf",
        help="write every manoeuvre's plot (PNG) into DIR, or all of them into one multipage PDF",
    )
    imo.add_argument(
        "--report",
        metavar="DIR|FILE.html|FILE.pdf",
        help="write the report a student can hand in (particulars, source, criteria, plots): "
        "imo_<ship>.html in DIR, or the named HTML or PDF file",
    )
    imo.add_argument("--force", action="store_true", help="replace existing plot and report files")

    man = sub.add_parser("manoeuvre", help="one standard manoeuvre")
    msub = man.add_subparsers(dest="manoeuvre", parser_class=_Parser)
    common = dict(help="ship name or .toml path")
    tc = msub.add_parser("turning-circle")
    tc.add_argument("--ship", required=True, **common)
    tc.add_argument("--rudder", type=_finite("--rudder", -70, 70), default=35.0, help="deg, + = starboard")
    zz = msub.add_parser("zigzag")
    zz.add_argument("--ship", required=True, **common)
    zz.add_argument(
        "--rudder",
        type=_finite("--rudder", -70, 70),
        default=10.0,
        help="deg; positive = first execute to starboard",
    )
    zz.add_argument(
        "--heading", type=_finite("--heading", 0.1, 89.9), default=None, help="deg (default |rudder|)"
    )
    zz.add_argument("--overshoots", type=int, default=3)
    it = msub.add_parser("initial-turning")
    it.add_argument("--ship", required=True, **common)
    it.add_argument("--rudder", type=_finite("--rudder", -70, 70), default=10.0)
    stp = msub.add_parser("stopping")
    stp.add_argument("--ship", required=True, **common)
    po = msub.add_parser("pull-out")
    po.add_argument("--ship", required=True, **common)
    po.add_argument("--rudder", type=_finite("--rudder", 1, 70), default=20.0)
    for sp in (tc, zz, it, stp, po):
        sp.add_argument("--speed", type=_finite("--speed", 0.1, 60), default=None, help="approach speed, kn")
        sp.add_argument("--json", action="store_true")
        sp.add_argument(
            "--plot",
            metavar="FILE|DIR",
            help="write the manoeuvre's plot to FILE (.png, .svg or .pdf) or as <ship>_<manoeuvre>.png into DIR",
        )
        sp.add_argument("--force", action="store_true", help="replace an existing plot file")

    sub.add_parser("ships", help="list the built-in ships")
    sub.add_parser("scenarios", help="list the built-in scenarios")

    pl = sub.add_parser("play", help="drive a scenario's ship with the keyboard (pygame), debrief at the end")
    pl.add_argument("scenario", nargs="?", default="harbour", help="built-in scenario name or .toml path")
    pl.add_argument("--seed", type=int, default=None)
    pl.add_argument("--speedup", type=_finite("--speedup", 0.25, 16), default=1.0, help="initial time factor")
    pl.add_argument("--max-steps", type=int, default=None, help="stop after this many control steps")
    pl.add_argument("--out", default=".", help="directory for the debrief track plot")
    pl.add_argument("--force", action="store_true", help="replace an existing debrief plot")

    sv = sub.add_parser("serve", help="run a scenario in real time with the UDP link (NMEA, JSON state/helm)")
    sv.add_argument("scenario", nargs="?", default="harbour")
    sv.add_argument(
        "--nmea",
        metavar="HOST:PORT",
        action="append",
        default=None,
        help="NMEA 0183 destination (repeatable; default 127.0.0.1:10110; 'off' for none)",
    )
    sv.add_argument(
        "--json", metavar="HOST:PORT", default="127.0.0.1:10120", help="JSON channel bind address"
    )
    sv.add_argument(
        "--view",
        metavar="HOST:PORT",
        action="append",
        default=[],
        help="listen-only JSON destination (a viewer that never says hello; repeatable)",
    )
    sv.add_argument("--time-factor", type=_finite("--time-factor", 0.1, 100), default=1.0)
    sv.add_argument(
        "--agent", default="pid", help="helm when no human holds it: pid, scripted or an SB3 .zip"
    )
    sv.add_argument("--allow-remote", action="store_true", help="allow binding to a non-loopback address")
    sv.add_argument("--failsafe", choices=("hold", "midships_stop"), default="hold")
    sv.add_argument(
        "--duration",
        type=_finite("--duration", 0.1, 1e7),
        default=None,
        help="stop after this many wall-clock seconds",
    )
    sv.add_argument("--seed", type=int, default=None)

    hm = sub.add_parser("helm", help="pygame helm panel for a running 'vessel-gym serve'")
    hm.add_argument("--server", metavar="HOST:PORT", default="127.0.0.1:10120")
    hm.add_argument("--name", default="helm")
    vw = sub.add_parser("view", help="passive pygame viewer of a running 'vessel-gym serve'")
    vw.add_argument("--server", metavar="HOST:PORT", default="127.0.0.1:10120")
    vw.add_argument(
        "--listen",
        metavar="HOST:PORT",
        default=None,
        help="wait for state sent to this address instead of saying hello (static destination)",
    )
    for sp in (hm, vw):
        sp.add_argument("--duration", type=_finite("--duration", 0.1, 1e7), default=None)
    v3 = sub.add_parser(
        "view3d", help="3D view in the browser of a running 'vessel-gym serve' (extra 'view3d')"
    )
    v3.add_argument("--server", metavar="HOST:PORT", default="127.0.0.1:10120")
    v3.add_argument("--http", metavar="HOST:PORT", default="127.0.0.1:8080", help="where the page is served")
    v3.add_argument("--camera", default="chase", choices=("chase", "bridge", "top-down", "harbour", "free"))
    v3.add_argument("--rate", type=_finite("--rate", 1.0, 50.0), default=20.0, help="state rate, Hz (1-50)")
    v3.add_argument("--token", default=None, help="the link's shared secret, if it has one")
    v3.add_argument("--duration", type=_finite("--duration", 0.1, 1e7), default=None)
    return p


def host_port(text: str, what: str) -> tuple[str, int]:
    """'HOST:PORT' -> (host, port); raises UsageError naming the option."""
    host, sep, port = text.rpartition(":")
    if not sep or not host:
        raise UsageError(f"vessel-gym: {what}: expected HOST:PORT, got {text!r}")
    try:
        p = int(port)
    except ValueError:
        raise UsageError(f"vessel-gym: {what}: port must be an integer, got {port!r}") from None
    if not 0 <= p <= 65535:
        raise UsageError(f"vessel-gym: {what}: port {p} outside [0, 65535]")
    return host, p


def _cmd_imo(args) -> int:
    from vessel_gym.manoeuvres.imo import imo_report
    from vessel_gym.outputs import check_free, output_target
    from vessel_gym.physics.shipfile import load_ship

    ship = load_ship(args.ship)
    plot_out = report_file = None
    plot_is_dir = False
    # every output is checked before the trials run, so a refusal costs nothing
    if args.plot:
        from vessel_gym.manoeuvres.plots import REPORT_PLOTS

        plot_out, plot_is_dir = output_target(args.plot, (".pdf",), "--plot")
        files = [plot_out / f"{stem}.png" for stem in REPORT_PLOTS] if plot_is_dir else [plot_out]
        check_free(files, args.force, "--plot")
    if args.report:
        from vessel_gym.manoeuvres.report import report_name

        target, is_dir = output_target(args.report, (".html", ".pdf"), "--report")
        report_file = target / report_name(ship.name) if is_dir else target
        check_free([report_file], args.force, "--report")
        if plot_out is not None and not plot_is_dir and plot_out.resolve() == report_file.resolve():
            raise UsageError(f"vessel-gym imo: --plot and --report both name {str(report_file)!r}")
    report = imo_report(ship, with_pull_out=plot_out is not None or report_file is not None)
    written = []
    if plot_out is not None or report_file is not None:
        from vessel_gym.manoeuvres.plots import plot_report, report_pngs
        from vessel_gym.manoeuvres.report import write_report

        # rendered once, shared by the PNG files and the HTML report
        pngs = report_pngs(report) if plot_is_dir or str(report_file).lower().endswith(".html") else None
        if plot_out is not None:
            written += plot_report(report, plot_out, args.force, pdf=not plot_is_dir, pngs=pngs)
        if report_file is not None:
            written.append(write_report(report, report_file, args.force, pngs=pngs))
    if written and not args.json:
        print("wrote: " + ", ".join(str(f) for f in written), file=sys.stderr)
    _emit(report.to_dict(), args.json, report.table())
    return 0


def _cmd_manoeuvre(args) -> int:
    from vessel_gym.manoeuvres import trials
    from vessel_gym.physics.shipfile import load_ship

    kind = args.manoeuvre
    ship = load_ship(args.ship)
    plot_file = None
    if args.plot:
        from vessel_gym.outputs import check_free, output_target, safe_name

        target, is_dir = output_target(args.plot, (".png", ".svg", ".pdf"), "--plot")
        plot_file = target / f"{safe_name(ship.name)}_{kind}.png" if is_dir else target
        check_free([plot_file], args.force, "--plot")
    if kind == "turning-circle":
        res = trials.turning_circle(ship, args.rudder, args.speed)
    elif kind == "zigzag":
        res = trials.zigzag(ship, args.rudder, args.heading, args.speed, n_overshoots=args.overshoots)
    elif kind == "initial-turning":
        res = trials.initial_turning(ship, args.rudder, args.speed)
    elif kind == "stopping":
        res = trials.stopping(ship, args.speed)
    else:
        res = trials.pull_out(ship, args.rudder, args.speed)
    if plot_file is not None:
        from vessel_gym.manoeuvres.plots import plot_track

        path = plot_track(res, plot_file, f"{res.ship}: {kind}", force=args.force, ship=ship)
        if not args.json:
            print(f"wrote: {path}", file=sys.stderr)
    d = res.to_dict()
    _emit(d, args.json, _fmt(d))
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    from vessel_gym.manoeuvres.trials import ManoeuvreIncomplete
    from vessel_gym.physics.schema import SpecError
    from vessel_gym.physics.simulation import SimulationError

    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return 2
        if args.command == "imo":
            return _cmd_imo(args)
        if args.command == "manoeuvre":
            if args.manoeuvre is None:
                raise UsageError(
                    "vessel-gym manoeuvre: choose turning-circle, zigzag, initial-turning, "
                    "stopping or pull-out"
                )
            return _cmd_manoeuvre(args)
        if args.command == "ships":
            from vessel_gym.physics.shipfile import builtin_ships

            print("\n".join(builtin_ships()))
            return 0
        if args.command == "scenarios":
            from vessel_gym.scenarios import builtin_scenarios

            print("\n".join(builtin_scenarios()))
            return 0
        if args.command == "play":
            from vessel_gym.play import play
            from vessel_gym.scenarios import load_scenario

            load_scenario(args.scenario)  # bad names fail here, before a window opens
            debrief = play(
                args.scenario,
                seed=args.seed,
                max_steps=args.max_steps,
                speedup=args.speedup,
                out_dir=args.out,
                force=args.force,
            )
            print(debrief.summary())
            return 0
        if args.command == "serve":
            from vessel_gym.net.serve import serve

            nmea = (
                []
                if args.nmea == ["off"]
                else [host_port(t, "--nmea") for t in (args.nmea or ["127.0.0.1:10110"])]
            )
            return serve(
                args.scenario,
                nmea=nmea,
                json_bind=host_port(args.json, "--json"),
                listen_only=[host_port(t, "--view") for t in args.view],
                time_factor=args.time_factor,
                agent=args.agent,
                allow_remote=args.allow_remote,
                failsafe=args.failsafe,
                duration_s=args.duration,
                seed=args.seed,
            )
        if args.command in ("helm", "view"):
            from vessel_gym.net import clients

            server = host_port(args.server, "--server")
            if args.command == "helm":
                clients.run_helm(server, name=args.name, duration_s=args.duration)
            else:
                listen = host_port(args.listen, "--listen") if args.listen else None
                clients.run_viewer(server, listen=listen, duration_s=args.duration)
            return 0
        if args.command == "view3d":
            try:
                import viser  # noqa: F401

                from vessel_gym.net.view3d import view3d
            except ImportError:
                raise UsageError(
                    "vessel-gym view3d: needs the 'view3d' extra: pip install 'vessel-gym[view3d]'"
                ) from None
            return view3d(
                host_port(args.server, "--server"),
                host_port(args.http, "--http"),
                camera=args.camera,
                rate_hz=args.rate,
                token=args.token,
                duration_s=args.duration,
            )
        raise UsageError(f"vessel-gym: unknown command {args.command!r}")
    except UsageError as exc:
        print(str(exc), file=sys.stderr)
        return 2
    except (SpecError, ValueError) as exc:
        print(f"vessel-gym: {exc}", file=sys.stderr)
        return 2
    except (ManoeuvreIncomplete, SimulationError) as exc:
        print(f"vessel-gym: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
