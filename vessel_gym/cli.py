"""The ``vessel-gym`` command. Exit codes: 0 success, 1 a manoeuvre could not complete, 2 bad input
(one line on stderr naming what was wrong)."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence

from vessel_gym.cli_args import (
    SEED_MAX,
    OneLineParser,
    UsageError,
    error_line,
    int_in,
    number_in,
    require_extra,
)
from vessel_gym.cli_live import LIVE_COMMANDS, add_live_parsers, need_window, run_live


def _add_ship(sp: argparse.ArgumentParser) -> None:
    """A ship named either way: positional SHIP or --ship SHIP (main() checks that exactly one is given)."""
    sp.add_argument("ship", nargs="?", default=None, help="built-in ship name or ship file (.toml)")
    sp.add_argument("--ship", dest="ship_option", metavar="SHIP", default=None, help="the same, as an option")


#: the agents' command lines, run by ``vessel-gym train|evaluate ARGS`` (the ``agents`` package is installed with
#: vessel-gym; ``python agents/train.py`` and ``python agents/evaluate.py`` are the same commands)
AGENT_COMMANDS = {
    "train": "train an SB3 agent on an environment id (extra 'rl'); 'vessel-gym train --help'",
    "evaluate": "evaluate a baseline (pid, scripted) or a trained agent over seeded episodes; "
    "'vessel-gym evaluate --help'",
}


def _agent_command(name: str, argv: list[str]) -> int:
    """``vessel-gym train|evaluate ARGS``: the agents' own command line, its prog named as the user typed it."""
    import importlib

    try:
        return importlib.import_module(f"agents.{name}").main(argv, prog=f"vessel-gym {name}")
    except SystemExit as exc:  # a bad argument, already told in one line (--help exits 0)
        if exc.code != 2:
            raise
        return 2


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


#: deepest water on earth (Challenger Deep, ~10 935 m): a larger --depth is a typo, not a sea
MAX_DEPTH_M = 11000.0


def _add_depth(sp: argparse.ArgumentParser) -> None:
    sp.add_argument(
        "--depth",
        metavar="METRES",
        type=number_in("--depth", 0.01, MAX_DEPTH_M),
        default=None,
        help="water depth, m (default: deep water); shallow-water corrections for h/T >= 1.2, MMG ships",
    )


def _environment(args, ship) -> dict:
    """The trials' keyword arguments for ``--depth``: ``environment``, calm water of that depth (none
    without it: the trials' calm deep water). A depth the corrections do not cover (h/T below their range,
    a hull they are not for) is refused here, before any trial runs: one line, exit code 2."""
    from vessel_gym.physics.environment import Environment
    from vessel_gym.physics.shallow_water import check_hull

    if args.depth is None:
        return {}
    env = Environment(depth_m=args.depth)
    try:
        check_hull(ship, env.depth_m)
        env.row(ship.particulars.L_m, ship.particulars.T_m)
    except ValueError as exc:
        raise UsageError(f"vessel-gym {args.command}: --depth: {exc}") from None
    return {"environment": env}


def build_parser() -> argparse.ArgumentParser:
    from vessel_gym import __version__

    p = OneLineParser(
        prog="vessel-gym", description="Ship manoeuvring: IMO checks, manoeuvres, environments."
    )
    p.add_argument("--version", action="version", version=f"vessel-gym {__version__}")
    sub = p.add_subparsers(dest="command", parser_class=OneLineParser)

    imo = sub.add_parser("imo", help="all IMO MSC.137(76) criteria for a ship (name or .toml path)")
    _add_ship(imo)
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
    imo.add_argument(
        "--heel-limit",
        type=number_in("--heel-limit", 0.1, 89.9),
        default=None,
        metavar="DEG",
        help="also hold the largest heel of the 35 deg turning test to DEG (ships with roll only; the 2008 IS "
        "Code Part A 3.1.3 guidance for passenger ships is 10)",
    )
    _add_depth(imo)

    man = sub.add_parser("manoeuvre", help="one standard manoeuvre")
    msub = man.add_subparsers(dest="manoeuvre", parser_class=OneLineParser)
    tc = msub.add_parser("turning-circle")
    tc.add_argument("--rudder", type=number_in("--rudder", -70, 70), default=35.0, help="deg, + = starboard")
    zz = msub.add_parser("zigzag")
    zz.add_argument(
        "--rudder",
        type=number_in("--rudder", -70, 70),
        default=10.0,
        help="deg; positive = first execute to starboard",
    )
    zz.add_argument(
        "--heading", type=number_in("--heading", 0.1, 89.9), default=None, help="deg (default |rudder|)"
    )
    zz.add_argument(
        "--overshoots", type=int_in("--overshoots", 1, 10), default=3, help="overshoots to measure"
    )
    it = msub.add_parser("initial-turning")
    it.add_argument("--rudder", type=number_in("--rudder", -70, 70), default=10.0, help="deg, + = starboard")
    stp = msub.add_parser("stopping")
    po = msub.add_parser("pull-out")
    po.add_argument("--rudder", type=number_in("--rudder", 1, 70), default=20.0, help="deg, to starboard")
    for sp in (tc, zz, it, stp, po):
        _add_ship(sp)
        sp.add_argument(
            "--speed",
            type=number_in("--speed", 0.1, 60),
            default=None,
            help="approach speed, kn (default: the ship's test speed)",
        )
        sp.add_argument("--json", action="store_true", help="machine-readable output")
        sp.add_argument(
            "--plot",
            metavar="FILE|DIR",
            help="write the manoeuvre's plot to FILE (.png, .svg or .pdf) or as <ship>_<manoeuvre>.png into DIR",
        )
        sp.add_argument("--force", action="store_true", help="replace an existing plot file")
        _add_depth(sp)

    ships = sub.add_parser(
        "ships",
        help="list the built-in ships with their particulars and sources; 'ships check SHIP' checks a ship's "
        "hull model (derivative signs, energy, rudder) before any trial",
    )
    ships.add_argument("action", nargs="?", choices=("check",), help="check SHIP's hull model")
    ships.add_argument("ship", nargs="?", help="built-in ship name or ship file (.toml), with check")
    ships.add_argument("--json", action="store_true", help="machine-readable output")
    ships.add_argument(
        "--example",
        metavar="FILE",
        default=None,
        help="write a ship file to start your own from (a built-in ship with every key's unit, range and "
        "meaning as comments; docs/ship-file.md)",
    )
    ships.add_argument("--force", action="store_true", help="with --example: replace an existing FILE")
    sub.add_parser("scenarios", help="list the built-in scenarios, each with one line of description")
    for name, text in AGENT_COMMANDS.items():  # listed here, parsed by the agents' own command line
        sub.add_parser(name, help=text, add_help=False)

    pl = sub.add_parser("play", help="drive a scenario's ship with the keyboard (pygame), debrief at the end")
    pl.add_argument(
        "scenario",
        nargs="?",
        default=None,
        help="built-in scenario name or .toml path (default: harbour, or the --env preset's)",
    )
    pl.add_argument(
        "--env",
        metavar="ID",
        default=None,
        help="a berthing task to play (vessel_gym/Berthing-v0, vessel_gym/BerthingTanker-v0): thruster and "
        "tug keys, berthing debrief (docs/berthing.md); default: the harbour approach",
    )
    pl.add_argument(
        "--seed",
        type=int_in("--seed", 0, SEED_MAX),
        default=None,
        help="start pose and weather draw (default: a fresh random draw each run)",
    )
    pl.add_argument(
        "--speedup", type=number_in("--speedup", 0.25, 16), default=1.0, help="initial time factor"
    )
    pl.add_argument(
        "--max-steps",
        type=int_in("--max-steps", 1),
        default=None,
        help="stop after this many control steps (default: the 400 s time limit)",
    )
    pl.add_argument("--out", default=".", help="directory for the debrief track plot")
    pl.add_argument("--force", action="store_true", help="replace an existing debrief plot")

    live_parsers = add_live_parsers(sub)
    for sp in (imo, tc, zz, it, stp, po, ships, pl, live_parsers["serve"]):  # every command that loads a ship file
        sp.add_argument(
            "--allow-code",
            action="store_true",
            help="let ship files name components in any Python module (importing one runs its code); "
            "without it only vessel-gym's own components load (also: VESSEL_GYM_ALLOW_CODE=1)",
        )
    from vessel_gym.classroom.command import add_parser as add_classroom

    add_classroom(sub)
    from vessel_gym.cli_warm import add_parser as add_warm

    add_warm(sub)
    fm = sub.add_parser(
        "fmu",
        help="write an FMI 2.0 co-simulation FMU of the whole ship (docs/fmi.md; needs the 'fmi' extra)",
    )
    _add_ship(fm)
    fm.add_argument(
        "--out", metavar="FILE.fmu|DIR", required=True, help="the FMU, or a directory for <ship>.fmu"
    )
    fm.add_argument("--force", action="store_true", help="replace an existing FMU file")
    fm.add_argument(
        "--dt",
        type=number_in("--dt", 0.001, 5.0),
        default=0.1,
        metavar="S",
        help="internal physics step, s (the importer's communication step must be a whole multiple of it)",
    )
    fm.add_argument(
        "--allow-code",
        action="store_true",
        help="let the ship file name components in any Python module, here and in the FMU",
    )
    p.commands = tuple(sub.choices)
    return p


def _ship_name(args) -> str:
    """The ship named by the positional SHIP or --ship (one of them, or both the same)."""
    pos, opt = args.ship, args.ship_option
    prog = " ".join(["vessel-gym", args.command] + ([args.manoeuvre] if args.command == "manoeuvre" else []))
    if pos is not None and opt is not None and pos != opt:
        raise UsageError(f"{prog}: two ships named ({pos!r} and --ship {opt!r}); give one")
    if pos is None and opt is None:
        raise UsageError(f"{prog}: name a ship: SHIP or --ship SHIP (see 'vessel-gym ships')")
    return pos if pos is not None else opt


def _cmd_imo(args) -> int:
    from vessel_gym.manoeuvres.imo import imo_report
    from vessel_gym.outputs import check_free, output_target
    from vessel_gym.physics.shipfile import load_ship

    ship = load_ship(args.ship)
    env = _environment(args, ship)
    if args.heel_limit is not None and ship.roll is None:
        raise UsageError(
            f"vessel-gym imo: --heel-limit: ship {ship.name!r} has no roll (no [roll] table), so no heel"
        )
    plot_out = report_file = None
    plot_is_dir = False
    # every output is checked before the trials run, so a refusal costs nothing
    for opt in ("--plot", "--report"):
        if getattr(args, opt[2:]):
            require_extra(("matplotlib",), "plot", f"vessel-gym imo: {opt}")
    if args.plot:
        from vessel_gym.manoeuvres.plots import report_plot_names

        plot_out, plot_is_dir = output_target(args.plot, (".pdf",), "--plot")
        stems = report_plot_names(ship)
        files = [plot_out / f"{stem}.png" for stem in stems] if plot_is_dir else [plot_out]
        check_free(files, args.force, "--plot")
    if args.report:
        from vessel_gym.manoeuvres.report import report_name

        target, is_dir = output_target(args.report, (".html", ".pdf"), "--report")
        report_file = target / report_name(ship.name) if is_dir else target
        check_free([report_file], args.force, "--report")
        if plot_out is not None and not plot_is_dir and plot_out.resolve() == report_file.resolve():
            raise UsageError(f"vessel-gym imo: --plot and --report both name {str(report_file)!r}")
    report = imo_report(
        ship,
        with_pull_out=plot_out is not None or report_file is not None,
        heel_limit_deg=args.heel_limit,
        **env,
    )
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
    # a run that ran away, or a ship no hull could be, is a failure of the model, not a verdict on the ship
    return 1 if report.diverged or report.implausible_reasons else 0


def _cmd_manoeuvre(args) -> int:
    from vessel_gym.manoeuvres import trials
    from vessel_gym.physics.shipfile import load_ship

    kind = args.manoeuvre
    ship = load_ship(args.ship)
    env = _environment(args, ship)
    plot_file = None
    if args.plot:
        from vessel_gym.outputs import check_free, output_target, safe_name

        require_extra(("matplotlib",), "plot", f"vessel-gym manoeuvre {kind}: --plot")

        target, is_dir = output_target(args.plot, (".png", ".svg", ".pdf"), "--plot")
        plot_file = target / f"{safe_name(ship.name)}_{kind}.png" if is_dir else target
        check_free([plot_file], args.force, "--plot")
    try:
        if kind == "turning-circle":
            res = trials.turning_circle(ship, args.rudder, args.speed, **env)
        elif kind == "zigzag":
            res = trials.zigzag(
                ship, args.rudder, args.heading, args.speed, n_overshoots=args.overshoots, **env
            )
        elif kind == "initial-turning":
            res = trials.initial_turning(ship, args.rudder, args.speed, **env)
        elif kind == "stopping":
            res = trials.stopping(ship, args.speed, **env)
        else:
            res = trials.pull_out(ship, args.rudder, args.speed, **env)
    except trials.ManoeuvreDiverged as exc:
        if not args.json:
            raise  # one line on stderr, exit code 1
        d = {"ship": ship.name, "manoeuvre": kind, "verdict": "diverged", "reason": str(exc), "t_s": exc.t_s}
        _emit(d, True, "")
        return 1
    if plot_file is not None:
        from vessel_gym.manoeuvres.plots import plot_track

        path = plot_track(res, plot_file, f"{res.ship}: {kind}", force=args.force, ship=ship)
        if not args.json:
            print(f"wrote: {path}", file=sys.stderr)
    d = res.to_dict()
    if args.depth is not None:
        d["depth_m"] = args.depth
    _emit(d, args.json, _fmt(d))
    return 0


def _cmd_fmu(args) -> int:
    """``vessel-gym fmu SHIP --out FILE.fmu``: the whole ship as an FMI 2.0 co-simulation FMU (vessel_gym.fmi)."""
    from vessel_gym.fmi.export import build_ship_fmu

    path = build_ship_fmu(
        _ship_name(args), args.out, force=args.force, dt=args.dt, allow_code=args.allow_code
    )
    print(f"wrote {path}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``vessel-gym`` command; returns the exit code."""
    try:
        code = _main(argv)
        sys.stdout.flush()
        return code
    except BrokenPipeError:
        # The reader went away (``vessel-gym imo kvlcc2 --json | head``): stop quietly, as other tools in a
        # pipe do, and keep Python from reporting the failed flush of stdout at exit.
        import os

        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1


def _main(argv: Sequence[str] | None) -> int:
    from vessel_gym.manoeuvres.trials import ManoeuvreIncomplete
    from vessel_gym.physics.schema import SpecError
    from vessel_gym.physics.steady import SimulationError

    parser = build_parser()
    try:
        words = list(sys.argv[1:] if argv is None else argv)
        if "--version" in words and len(words) > 1:
            # argparse's version action prints and exits 0 at once, whatever follows it
            others = " ".join(w for w in words if w != "--version")
            raise UsageError(f"vessel-gym: --version takes no other arguments (got {others!r})")
        if words and words[0] in AGENT_COMMANDS:
            return _agent_command(words[0], words[1:])
        try:
            args = parser.parse_args(words)
        except SystemExit as exc:  # a bad argument, already told in one line: its exit code (--help exits)
            if exc.code != 2:
                raise
            return 2
        if args.command is None:
            commands = ", ".join(sorted(parser.commands))
            raise UsageError(f"vessel-gym: no command given; choose one of {commands} (vessel-gym --help)")
        if getattr(args, "allow_code", False):
            from vessel_gym.physics.components import allow_code

            allow_code()
        if args.command in ("imo", "manoeuvre") and getattr(args, "manoeuvre", "") is not None:
            args.ship = _ship_name(args)
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
            from vessel_gym.cli_ships import cmd_ships

            return cmd_ships(args, _emit)
        if args.command == "fmu":
            return _cmd_fmu(args)
        if args.command == "scenarios":
            from vessel_gym.scenarios import builtin_scenarios, load_scenario

            names = builtin_scenarios()
            w = max(len(n) for n in names) + 2
            for name in names:  # each with the first sentence of its description
                first = " ".join(load_scenario(name).description.split()).split(". ")[0].rstrip(".")
                print(f"{name:<{w}}{first}.")
            return 0
        if args.command == "play":
            from vessel_gym.scenarios import load_scenario
            from vessel_gym.ui.play import play

            if args.env is not None:
                from vessel_gym.ui.play_berthing import berthing_ids

                if args.env not in berthing_ids():
                    raise ValueError(
                        f"play --env: {args.env!r} is not a berthing task (one of {', '.join(berthing_ids())})"
                    )
            if args.scenario is not None or args.env is None:
                load_scenario(args.scenario or "harbour")  # bad names fail here, before a window opens
            need_window(args.command)
            debrief = play(
                args.scenario,
                env_id=args.env,
                seed=args.seed,
                max_steps=args.max_steps,
                speedup=args.speedup,
                out_dir=args.out,
                force=args.force,
            )
            print(debrief.summary())
            return 0
        if args.command in LIVE_COMMANDS:
            return run_live(args)
        if args.command == "classroom":
            from vessel_gym.classroom.command import run as run_classroom

            return run_classroom(args)
        if args.command == "warm":
            from vessel_gym.cli_warm import run as run_warm

            return run_warm(args)
        raise UsageError(f"vessel-gym: unknown command {args.command!r}")
    except UsageError as exc:
        error_line(str(exc))
        return 2
    except (SpecError, ValueError) as exc:
        error_line(f"vessel-gym: {exc}")
        return 2
    except (ManoeuvreIncomplete, SimulationError) as exc:
        error_line(f"vessel-gym: {exc}")
        return 1
    except BrokenPipeError:
        raise
    except OSError as exc:  # a path or address given on the command line that the system refuses
        where = f"{exc.filename}: " if exc.filename else ""
        error_line(f"vessel-gym: {where}{exc.strerror or exc}")
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
