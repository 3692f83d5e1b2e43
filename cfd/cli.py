"""``vessel-cfd``: command line of the CFD tool.

    vessel-cfd                      interactive set-up (the seed report's vesselScript flow)
    vessel-cfd run --hull H --lpp L --bwl B --tm T --grading G --tests all --out DIR [...]
    vessel-cfd run --study study.toml [--out DIR ...]
    vessel-cfd wigley --lpp L --bwl B --tm T --out hull.stl
    vessel-cfd clarke --lpp L --bwl B --tm T --cb CB
    vessel-cfd dtc-validation --out DIR [--hull DTC.stl] [--grading G] [--grid K] [--speeds ...] [--iterations N]
    vessel-cfd dtc-grid-study --grids DIR0,DIR1[,DIR2] --out DIR [--speeds ...]

Exit codes: 0 success, 1 a CFD step failed (one line on stderr naming the step and its log),
2 bad input (one line on stderr naming the argument or key and the allowed range), 3 the study finished
and wrote its ship file and report, but the verification gate failed (UNVERIFIED; see report/summary.md),
or the DTC validation or grid study ran but missed its target at some speed (see validation.md,
grid_study.md).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import signal
import sys
import threading
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NoReturn

from vessel_gym.cli_args import OneLineParser, error_line

from . import __version__
from .config import GRADINGS, SIMULATION_TYPES, Study, build_study, load_study_file, parse_list, parse_number
from .errors import CfdError, InputError
from .heel import RUN_OPTIONS as HEEL_OPTIONS
from .tank import GRIDS

EXIT_UNVERIFIED = 3  # the run finished but its verification gate failed


RUN_OPTIONS: tuple[tuple[str, str], ...] = (
    ("hull", "hull STL file (.stl or .stl.gz; bow to +x, z up, metres) or 'wigley'"),
    ("lpp", "length between perpendiculars (m)"),
    ("bwl", "waterline breadth (m)"),
    ("tm", "mean draught (m)"),
    ("grading", "mesh grading 1-5 (1 ULTRA COARSE ... 5 ULTRA FINE)"),
    ("tests", "tests to run: all, or a comma list of tow,drift,sway,yaw; add heel for roll (all,heel)"),
    ("out", "output directory (ship.toml, report/, cases/)"),
    ("procs", "processors for solving"),
    ("mesh-procs", "processors for meshing"),
    ("template", "ship file whose non-hull tables are copied (default: the built-in dtc ship)"),
    ("name", "ship name in the ship file"),
    ("x-ap", "x of the aft perpendicular in the STL (m; default: aft end of the underwater hull)"),
    ("z-keel", "z of the keel in the STL (m; default: lowest point)"),
    ("speeds", "tow speeds (m/s): 1.0 | 0.8,1.0,1.2 | MIN:MAX:COUNT (default: --pmm-speed, else Fn = 0.2)"),
    ("pmm-speed", "speed of the drift, sway and yaw tests (m/s; default: highest tow speed)"),
    ("drift-deg", "drift angles (deg), list or MIN:MAX:COUNT"),
    ("sway-period", "pure sway period (s; default pi L / U)"),
    ("sway-amplitude", "pure sway amplitudes (m), list or MIN:MAX:COUNT (default: 0.025 L)"),
    ("yaw-period", "pure yaw period (s; default pi L / U)"),
    ("yaw-deg", "pure yaw heading amplitudes (deg), list or MIN:MAX:COUNT"),
    ("sweep-omega-prime", "frequency sweep: extra sway and yaw runs at these omega' = omega L / U (0.2-5)"),
    ("cycles", "PMM periods simulated (first half period is a start ramp)"),
    ("fit-cycles", "last whole PMM periods used in the fits"),
    ("rho", "water density (kg/m3)"),
    ("nu", "kinematic viscosity (m2/s)"),
    ("layers", "prism layers on the hull, the first one sized for --yplus (true/false)"),
    ("yplus", "target y+ of the first cell centre"),
    ("wake", "refinement cylinder along the wake of each drift and PMM inflow angle (true/false)"),
    ("courant", "PMM time step as a Courant number U dt / h on the hull cells, 0.1-2.5"),
    ("time-scheme", "PMM time discretisation: backward (second order) or Euler (first order)"),
    ("sizing", "grading (default) or yplus (seed rule: background cell = wall cell x 2^levels)"),
    ("free-surface", "also write (not run) an interFoam free-surface tow case (true/false)"),
    ("max-iterations", "steady SIMPLE iterations (default by grading)"),
    ("normalisation", "rho_L2_U2 (seed eq. 5-6) or half_rho_L2_U2 (SNAME prime)"),
    ("scale-to", "template (scale particulars to the template's length) or cfd"),
    ("k-zz", "yaw radius of gyration (m; default from the template, else 0.25 Lpp)"),
    ("form-factor", "form factor k for ship-scale resistance (default: from the CFD)"),
    (
        "drift-form",
        "static-drift regression written to the ship file: abkowitz (Y_v v + Y_vvv v^3), mmg "
        "(Y_v v + Y_v|v| v|v|, written as its best cubic), linear (small angles), auto (lower residual)",
    ),
) + HEEL_OPTIONS


# Study defaults that mean "derived from other settings"; their help text says what they become instead.
_DERIVED = (None, "", (), 0, 0.0, -1.0)


def _run_help(opt: str, text: str) -> str:
    """The help of a run option with the Study's default appended (the default lives in one place: Study)."""
    field = {f.name: f for f in dataclasses.fields(Study)}.get(opt.replace("-", "_"))
    if field is None or field.default is dataclasses.MISSING or "default" in text:
        return text
    d = field.default
    if isinstance(d, bool):
        shown = str(d).lower()
    elif d in _DERIVED:
        return text
    elif isinstance(d, tuple):
        shown = ",".join(f"{x:g}" if isinstance(x, float) else str(x) for x in d)
    else:
        shown = f"{d:g}" if isinstance(d, float) else str(d)
    return f"{text} (default: {shown})"


def _parser() -> OneLineParser:
    p = OneLineParser(
        prog="vessel-cfd", description="OpenFOAM PMM tests -> hydrodynamic derivatives -> ship file."
    )
    p.add_argument("--version", action="version", version=f"vessel-cfd {__version__}")
    sub = p.add_subparsers(dest="command", parser_class=OneLineParser)
    run = sub.add_parser("run", help="run a study non-interactively")
    run.add_argument("--study", help="study TOML file (keys as the options below, with underscores)")
    for opt, text in RUN_OPTIONS:
        run.add_argument(f"--{opt}", help=_run_help(opt, text))
    run.add_argument("--quiet", action="store_true", help="no progress lines")
    run.add_argument("--ray", metavar="ADDRESS", help="run the cases as tasks on a Ray cluster (or 'local')")
    grid = sub.add_parser(
        "study", help="grid study: the study at three (or two) gradings, Richardson extrapolation and GCI"
    )
    grid.add_argument(
        "--gradings", required=True, help="three gradings 1-5, e.g. 1,2,3 (or two, e.g. 1,2: two-grid GCI)"
    )
    grid.add_argument("--study", help="study TOML file (keys as the options of run, with underscores)")
    for opt, text in RUN_OPTIONS:
        if opt != "grading":
            grid.add_argument(f"--{opt}", help=_run_help(opt, text))
    grid.add_argument("--quiet", action="store_true", help="no progress lines")
    sl = sub.add_parser("slurm", help="SLURM job array for the written, unfinished cases of a study")
    sl.add_argument("--cases", required=True, help="the study's cases folder (OUT/cases)")
    sl.add_argument("--nodes", default="1", help="nodes per case")
    sl.add_argument("--tasks-per-node", default="32", help="MPI ranks per node")
    sl.add_argument("--time", default="04:00:00", help="time limit per case, [D-]HH:MM:SS")
    sl.add_argument("--partition", help="SLURM partition")
    sl.add_argument("--account", help="SLURM account")
    dv = sub.add_parser("dtc-validation", help="free-surface (interFoam) DTC tows against the towing tank")
    dv.add_argument("--hull", help="the DTC STL (default: Debian openfoam-examples' DTC-scaled.stl.gz)")
    dv.add_argument("--out", required=True, help="output folder (cases/, validation.md, validation.json)")
    dv.add_argument("--grading", default="1", help="mesh grading 1-5")
    dv.add_argument("--grid", default="0", help=f"grid K: cells / sqrt(2)^K ({GRIDS[0]}-{GRIDS[-1]})")
    dv.add_argument("--speeds", help="tank speeds to run (m/s), e.g. 1.668 (default: all six)")
    dv.add_argument("--iterations", default="4000", help="interFoam LTS iterations per speed")
    dv.add_argument("--procs", default="1", help="MPI processors per case")
    dv.add_argument(
        "--mode", default="run", help="run; write (mesh, write the cases, run none); collect (report)"
    )
    gs = sub.add_parser("dtc-grid-study", help="DTC free-surface tows on 2-3 grids: GCI and tank error")
    gs.add_argument("--grids", required=True, help="dtc-validation folders with reports, comma-separated")
    gs.add_argument("--out", required=True, help="output folder (grid_study.md, grid_study.json)")
    gs.add_argument("--speeds", help="tank speeds (m/s) (default: every speed reported on every grid)")
    sub.add_parser("interactive", help="interactive set-up (the default without a command)")
    w = sub.add_parser("wigley", help="write a parabolic Wigley hull STL (double body about the waterline)")
    for opt in ("lpp", "bwl", "tm", "out"):
        w.add_argument(f"--{opt}", required=True)
    c = sub.add_parser("clarke", help="print Clarke et al. (1983) linear derivatives")
    for opt in ("lpp", "bwl", "tm", "cb"):
        c.add_argument(f"--{opt}", required=True)
    c.add_argument("--normalisation", default="half_rho_L2_U2")
    return p


def _grid(args: argparse.Namespace) -> int:
    from .gridstudy import run_grid_study  # noqa: PLC0415
    from .runner import Progress  # noqa: PLC0415

    values = parse_list("gradings", args.gradings, 0, 5)
    if len(values) not in (2, 3) or any(g != int(g) or g < 1 for g in values):  # values: sorted, unique
        raise InputError("gradings", f"two or three different whole gradings in [1, 5] (got {args.gradings})")
    gradings = [int(g) for g in values]
    args.grading = None
    study = _study(args)
    rep = run_grid_study(study, gradings, Progress(quiet=args.quiet))
    print(f"grid study: {study.out / 'grid_study.md'}")
    print(f"ship file:  {rep['ship_file']} (the finest grading's, with each derivative's grid uncertainty)")
    for k, q in rep["quantities"].items():
        gci = f", GCI {100 * q['gci_fine']:.2f} %" if "gci_fine" in q else ""
        unc = f", U {q['uncertainty']:.4g}" if "uncertainty" in q else ""
        print(f"  {k}: {q['condition']}{gci}{unc}")
    return 0


def _study(args: argparse.Namespace) -> Study:
    raw = {opt.replace("-", "_"): getattr(args, opt.replace("-", "_"), None) for opt, _ in RUN_OPTIONS}
    raw = {k: v for k, v in raw.items() if v is not None}
    if args.study:
        return load_study_file(args.study, raw)
    return build_study(raw)


def _run(args: argparse.Namespace) -> int:
    raw = {opt.replace("-", "_"): getattr(args, opt.replace("-", "_")) for opt, _ in RUN_OPTIONS}
    raw = {k: v for k, v in raw.items() if v is not None}
    study = load_study_file(args.study, raw) if args.study else build_study(raw)
    return _execute(study, quiet=args.quiet, ray=args.ray)


def _execute(study: Study, quiet: bool = False, ray: str | None = None) -> int:
    from .pipeline import Pipeline  # noqa: PLC0415 - keeps `vessel-cfd --help` light
    from .runner import Progress  # noqa: PLC0415

    try:  # the output directory is checked before any work starts
        study.out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError("out", f"cannot create directory {study.out} ({exc.strerror or exc})") from None

    result = Pipeline(study, Progress(quiet=quiet), ray=ray).run()
    d = result.derivatives
    print(f"ship file: {result.ship_file}")
    print(f"report:    {result.report_dir}")
    keys = [k for k in ("Y_v", "N_v", "Y_r", "N_r", "Y_vdot", "N_rdot") if k in d]
    print(f"derivatives ({result.normalisation}): " + ", ".join(f"{k} {d[k]:.5g}" for k in keys))
    print(f"borrowed:  {result.borrowed}")
    gate = result.verification
    if result.verified:
        print("verification: VERIFIED (every check passed; see report/summary.md)")
        return 0
    print(
        f"verification: UNVERIFIED, {len(gate['failures'])} checks failed ({'; '.join(gate['failures'][:3])}"
        + (", ..." if len(gate["failures"]) > 3 else "")
        + "); the ship file and report are written, see report/summary.md",
    )
    return EXIT_UNVERIFIED


# ---------------------------------------------------------------------------------- interactive
def _ask(
    prompt: str, check: Callable[[str], Any], default: str | None = None, read: Callable[[str], str] = input
) -> Any:
    """Ask until ``check`` accepts the answer; InputError messages are shown and the question repeated."""
    while True:
        shown = f"{prompt}{f' [{default}]' if default is not None else ''}: "
        try:
            answer = read(shown).strip()
        except EOFError:
            raise InputError("input", "ended before the set-up was complete") from None
        if not answer and default is not None:
            answer = default
        try:
            return check(answer)
        except InputError as exc:
            print(f"  invalid: {exc.message}. Please try again.", flush=True)


def _range_prompt(
    raw: dict[str, Any],
    key: str,
    what: str,
    unit: str,
    lo: float,
    hi: float,
    defaults: tuple[str, str, str],
    read,
) -> None:
    mn = _ask(
        f"Enter the minimum {what} ({unit})",
        lambda a: parse_number(key, a, lo, hi, lo_open=True),
        defaults[0],
        read,
    )

    def check_max(a: str) -> float:
        x = parse_number(key, a, lo, hi, lo_open=True)
        if x < mn:
            raise InputError(key, f"must be >= the minimum {mn:g}")
        return x

    mx = _ask(f"Enter the maximum {what} ({unit})", check_max, defaults[1], read)
    n = (
        1
        if mx == mn
        else _ask(
            "How many cases (the range is divided equally)",
            lambda a: parse_number(key + " count", a, 1, 20, integer=True),
            defaults[2],
            read,
        )
    )
    raw[key] = f"{mn}:{mx}:{n}"


def _yes_no(answer: str) -> bool:
    if answer.lower() in ("y", "yes"):
        return True
    if answer.lower() in ("n", "no"):
        return False
    raise InputError("answer", "type y or n")


def _list_check(key: str) -> Callable[[str], str]:
    def check(answer: str) -> str:
        parse_list(key, answer, 0, 20)
        return answer

    return check


def interactive(read: Callable[[str], str] = input, run: bool = True) -> Study | int:
    """The seed report's set-up dialogue; returns the Study (``run=False``) or runs it."""
    bar = "-" * 60
    print(
        f"{bar}\nWELCOME TO vessel-cfd {__version__} for OpenFOAM v1912!\n"
        f"TO START, PLEASE SELECT ONE OF THE FOLLOWING SIMULATION TYPES:\n{bar}"
    )
    for k, (name, _) in SIMULATION_TYPES.items():
        print(f"{k}. {name}")
    print(bar)
    kind = _ask(
        "Enter your simulation type [1-5]",
        lambda a: parse_number("simulation type", a, 1, 5, integer=True),
        None,
        read,
    )
    tests = SIMULATION_TYPES[kind][1]
    raw: dict[str, Any] = {"tests": ",".join(tests)}

    def hull_check(a: str) -> str:
        if a.lower() == "wigley":
            return "wigley"
        path = Path(a).expanduser()
        if not (path.name.lower().endswith(".stl") or path.name.lower().endswith(".stl.gz")):
            raise InputError("hull", "must be a .stl or .stl.gz file, or 'wigley'")
        if not path.is_file():
            raise InputError("hull", f"file {path} does not exist")
        return str(path.resolve())

    raw["hull"] = _ask(
        "Enter the file name for the hull geometry (NOTE: must be .stl, or 'wigley')", hull_check, None, read
    )
    raw["lpp"] = _ask(
        "Enter the Lpp value for the model (in metres)",
        lambda a: parse_number("lpp", a, 0, 500, lo_open=True),
        None,
        read,
    )
    raw["bwl"] = _ask(
        "Enter the Bwl value for the model (in metres)",
        lambda a: parse_number("bwl", a, 0, 0.5 * raw["lpp"], lo_open=True),
        None,
        read,
    )
    raw["tm"] = _ask(
        "Enter the Tm value for the model (in metres)",
        lambda a: parse_number("tm", a, 0, 0.5 * raw["lpp"], lo_open=True),
        None,
        read,
    )
    ncpu = os.cpu_count() or 1
    raw["mesh_procs"] = _ask(
        "Enter the number of local processors available for meshing",
        lambda a: parse_number("mesh_procs", a, 1, 4 * ncpu, integer=True),
        "1",
        read,
    )
    raw["procs"] = _ask(
        "Enter the number of local processors available for solving",
        lambda a: parse_number("procs", a, 1, 4 * ncpu, integer=True),
        str(ncpu),
        read,
    )
    print(f"{bar}\nMESH SETTINGS\n{bar}\nThese are the following options available for mesh grading.")
    for k, name in GRADINGS.items():
        print(f"{k}. {name}")
    print(bar)
    raw["grading"] = _ask(
        "Enter your choice of grading [1-5]",
        lambda a: parse_number("grading", a, 1, 5, integer=True),
        "1",
        read,
    )
    fn02 = round(0.2 * (9.81 * raw["lpp"]) ** 0.5, 4)
    if "tow" in tests:
        raw["speeds"] = _ask(
            "Enter the towing speeds (m/s): one value, a list a,b,c or MIN:MAX:COUNT",
            _list_check("speeds"),
            str(fn02),
            read,
        )
    if any(t in tests for t in ("drift", "sway", "yaw")):
        raw["pmm_speed"] = _ask(
            "Enter the forward speed for the drift/PMM tests (m/s)",
            lambda a: parse_number("pmm_speed", a, 0, 20, lo_open=True),
            str(fn02),
            read,
        )
    if "drift" in tests:
        _range_prompt(raw, "drift_deg", "drift angle", "deg", 0, 30, ("2", "10", "5"), read)
    U = raw.get("pmm_speed", fn02)
    period = f"{3.14159265 * raw['lpp'] / U:.4g}"
    if "sway" in tests:
        raw["sway_period"] = _ask(
            "Enter the time period for each complete sway motion (s)",
            lambda a: parse_number("sway_period", a, 0, 1e4, lo_open=True),
            period,
            read,
        )
        a0 = f"{0.02 * raw['lpp']:.4g}"
        _range_prompt(raw, "sway_amplitude", "sway amplitude", "m", 0, 0.5 * raw["lpp"], (a0, a0, "1"), read)
    if "yaw" in tests:
        raw["yaw_period"] = _ask(
            "Enter the time period for each complete yaw motion (s)",
            lambda a: parse_number("yaw_period", a, 0, 1e4, lo_open=True),
            period,
            read,
        )
        _range_prompt(raw, "yaw_deg", "yaw angle amplitude", "deg", 0, 30, ("4", "4", "1"), read)
    stem = "wigley" if raw["hull"] == "wigley" else Path(raw["hull"]).name.split(".")[0]
    raw["out"] = _ask("Enter the output directory", lambda a: a, f"vessel-cfd-{stem}", read)
    raw["template"] = (
        _ask(
            "Enter a template ship file for the non-hull tables (empty: built-in dtc)", lambda a: a, "", read
        )
        or None
    )
    if raw["template"] is None:
        del raw["template"]
    while True:
        try:
            study = build_study(raw)
            break
        except InputError as exc:
            print(f"  invalid: {exc}. Please enter it again.", flush=True)
            if exc.key not in raw:
                raise
            raw[exc.key] = _ask(f"Enter {exc.key}", lambda a: a, None, read)
    print(f"{bar}\nSet-up complete:")
    print(json.dumps(study.as_dict(), indent=1, default=str))
    if not run:
        return study
    saved = save_study(study)
    print(f"Study saved to {saved}; the same study runs again with: vessel-cfd run --study {saved}")
    if not _ask("Start the run? (y/n)", _yes_no, "y", read):
        print("Not started.")
        return 0
    return _execute(study)


def save_study(study: Study) -> Path:
    """Write ``study`` as a study file in its output folder: ``study.toml``, or ``study-N.toml`` when a
    different study file is already there (a user's file is never overwritten). Keys equal to their
    default are left out, so the defaults that depend on the hull are derived again on loading."""
    from .shipfile import dumps_toml  # noqa: PLC0415

    defaults = {f.name: f.default for f in dataclasses.fields(Study)}
    keys = {}
    for k, v in study.as_dict().items():
        if v is None or v == defaults.get(k):
            continue
        keys[k] = ",".join(v) if k == "tests" else (list(v) if isinstance(v, tuple) else v)
    text = dumps_toml(keys, f"Study file written by the vessel-cfd {__version__} interactive set-up.")
    try:
        study.out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError("out", f"cannot create directory {study.out} ({exc.strerror or exc})") from None
    for n in range(1000):
        path = study.out / ("study.toml" if n == 0 else f"study-{n}.toml")
        if not path.exists():
            path.write_text(text)
            return path
        if path.read_text() == text:
            return path
    raise InputError("out", f"{study.out} already holds 1000 study files")


# ---------------------------------------------------------------------------------- small commands
def _slurm(args: argparse.Namespace) -> int:
    from .cluster import pending_cases, write_slurm  # noqa: PLC0415
    from .runner import parse_check_mesh  # noqa: PLC0415

    cases = Path(args.cases)
    log = cases / "mesh" / "log.checkMesh"
    if not log.is_file():
        raise InputError("cases", f"{cases} has no meshed study (missing {log})")
    cells = int(parse_check_mesh(log)["cells"])
    script = write_slurm(
        cases,
        cells=cells,
        nodes=int(parse_number("nodes", args.nodes, 1, 1000, integer=True)),
        tasks_per_node=int(parse_number("tasks_per_node", args.tasks_per_node, 1, 1024, integer=True)),
        time_limit=args.time,
        partition=args.partition,
        account=args.account,
    )
    print(f"{script}: {len(pending_cases(cases))} cases; submit with: sbatch {script}")
    return 0


def _dtc_validation(args: argparse.Namespace) -> int:
    from .runner import Progress  # noqa: PLC0415
    from .tank import DTC_STL, console_lines, validate_dtc  # noqa: PLC0415

    hull = Path(args.hull) if args.hull else DTC_STL
    if not hull.is_file():
        raise InputError("hull", f"{hull} does not exist (apt-get install openfoam-examples, or give --hull)")
    doc = validate_dtc(
        hull,
        Path(args.out),
        grading=int(parse_number("grading", args.grading, 1, 5, integer=True)),
        speeds=parse_list("speeds", args.speeds, 0.0, 20.0) if args.speeds else None,
        iterations=int(parse_number("iterations", args.iterations, 1, 100000, integer=True)),
        procs=int(parse_number("procs", args.procs, 1, 4 * (os.cpu_count() or 1), integer=True)),
        progress=Progress(),
        mode=args.mode,
        grid=int(parse_number("grid", args.grid, GRIDS[0], GRIDS[-1], integer=True)),
    )
    print("\n".join(console_lines(doc, Path(args.out))))
    return 0 if doc.get("passed", True) else EXIT_UNVERIFIED


def _dtc_grid_study(args: argparse.Namespace) -> int:
    from .tank_grid import console_lines, dtc_grid_study  # noqa: PLC0415

    speeds = parse_list("speeds", args.speeds, 0.0, 20.0) if args.speeds else None
    doc = dtc_grid_study([Path(f) for f in args.grids.split(",") if f.strip()], Path(args.out), speeds)
    print("\n".join(console_lines(doc, Path(args.out))))
    return 0 if doc["passed"] else EXIT_UNVERIFIED


def _wigley(args: argparse.Namespace) -> int:
    from .geometry import hydrostatics, wigley_hull, write_stl  # noqa: PLC0415

    L = parse_number("lpp", args.lpp, 0, 500, lo_open=True)
    B = parse_number("bwl", args.bwl, 0, 0.5 * L, lo_open=True)
    T = parse_number("tm", args.tm, 0, 0.5 * L, lo_open=True)
    tris = wigley_hull(L, B, T)
    path = write_stl(Path(args.out), tris)
    h = hydrostatics(tris)
    print(
        f"{path}: {len(tris)} triangles, V = {h.volume_m3:.6g} m3, S = {h.wetted_area_m2:.6g} m2 below z = 0"
    )
    return 0


def _clarke(args: argparse.Namespace) -> int:
    from .clarke import clarke83  # noqa: PLC0415

    L = parse_number("lpp", args.lpp, 0, 1e4, lo_open=True)
    B = parse_number("bwl", args.bwl, 0, L, lo_open=True)
    T = parse_number("tm", args.tm, 0, L, lo_open=True)
    cb = parse_number("cb", args.cb, 0, 1, lo_open=True)
    try:
        d = clarke83(L, B, T, cb, args.normalisation)
    except ValueError as exc:
        raise InputError("normalisation", str(exc)) from None
    print(json.dumps(d, indent=1))
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``vessel-cfd`` console script."""
    args = _parser().parse_args(argv)
    # SIGTERM (a batch system's stop, kill) ends the run like Ctrl-C: solvers stopped, finished cases kept
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, _sigterm)
    try:
        if args.command == "run":
            return _run(args)
        if args.command == "study":
            return _grid(args)
        if args.command == "slurm":
            return _slurm(args)
        if args.command == "dtc-validation":
            return _dtc_validation(args)
        if args.command == "dtc-grid-study":
            return _dtc_grid_study(args)
        if args.command == "wigley":
            return _wigley(args)
        if args.command == "clarke":
            return _clarke(args)
        result = interactive()
        return result if isinstance(result, int) else 0
    except InputError as exc:
        error_line(f"vessel-cfd: error: {exc}")
        return 2
    except CfdError as exc:
        error_line(f"vessel-cfd: {exc}")
        return 1
    except OSError as exc:  # a file or directory given on the command line that the system refuses
        where = f"{exc.filename}: " if exc.filename else ""
        error_line(f"vessel-cfd: error: {where}{exc.strerror or exc}")
        return 2
    except KeyboardInterrupt:
        error_line("vessel-cfd: interrupted; running solvers stopped, finished cases kept (a rerun resumes)")
        return 130
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


def _sigterm(signum: int, frame: Any) -> NoReturn:
    raise KeyboardInterrupt


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
