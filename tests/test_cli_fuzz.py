"""Fuzz of the command lines: random options and values for every subcommand of ``vessel-gym`` and ``vessel-cfd``
never raise a traceback, always end with exit code 0, 1 or 2, and return within a bounded time.

Every argument check runs for real (argparse types, ship and scenario loading, address parsing, name
resolution of IP literals and ``localhost``, binding of listen addresses, the CFD study validation). What
would then start a long run, a server or a window is replaced by an immediate exit once the checks have run:
the manoeuvre simulations (after the output files are checked), ``play``, ``serve``, the helm, viewer and 3D
viewer clients, the CFD pipeline and grid study. Host names that would need a DNS
server are left out (``tests/test_command_line.py`` checks one that does not resolve); so are ``/dev/zero``
and ``/dev/stdin`` as files (reading them is bounded by the ship- and scenario-file checks, tested with
those).
"""

from __future__ import annotations

import time
from types import SimpleNamespace

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cfd import cli as cfd_cli
from vessel_gym import cli

PER_CALL_S = 10.0  # s, bound on one command's wall time (the slowest real path is loading a ship file)

NUMBER = st.one_of(
    st.integers(-(10**6), 10**6).map(str),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["", "nan", "-inf", "1e400", "9" * 400, "0x10", "1_000", " 3 ", "abc", "-0", "1e-320"]),
)
TEXT = st.text(max_size=12)
HOST = st.sampled_from(["127.0.0.1", "0.0.0.0", "localhost", "8.8.8.8", "::1", "[::1]", "", "1.2.3", "a:b"])
ADDRESS = st.one_of(
    st.builds(lambda h, p: f"{h}:{p}", HOST, st.one_of(NUMBER, st.integers(0, 70000).map(str))),
    st.sampled_from(["off", "127.0.0.1", ":10110", "127.0.0.1:", "localhost:0"]),
    TEXT.filter(lambda t: ":" not in t),
)
PATHISH = st.sampled_from(
    ["/dev/null", "/proc/x", "/", ".", "..", "nosuch.toml", "/etc/passwd", "x.png", "sub/dir/", "\0"]
)
SHIP = st.one_of(
    st.sampled_from(["kvlcc2", "mariner", "dtc", "kvlcc2_l7", "KVLCC2", "nosuch"]), PATHISH, TEXT
)
SCENARIO = st.one_of(st.sampled_from(["harbour", "nosuch", "HARBOUR"]), PATHISH, TEXT)
VALUE = st.one_of(NUMBER, TEXT, PATHISH)

# option -> strategy of its value (None: a flag)
VESSEL_GYM = {
    "imo": {"--ship": SHIP, "--json": None, "--plot": PATHISH, "--report": PATHISH, "--force": None},
    "manoeuvre turning-circle": {"--ship": SHIP, "--rudder": NUMBER, "--speed": NUMBER, "--json": None},
    "manoeuvre zigzag": {
        "--ship": SHIP,
        "--rudder": NUMBER,
        "--heading": NUMBER,
        "--overshoots": NUMBER,
        "--speed": NUMBER,
        "--json": None,
    },
    "manoeuvre initial-turning": {"--ship": SHIP, "--rudder": NUMBER, "--speed": NUMBER},
    "manoeuvre stopping": {"--ship": SHIP, "--speed": NUMBER, "--json": None},
    "manoeuvre pull-out": {"--ship": SHIP, "--rudder": NUMBER, "--speed": NUMBER},
    "ships": {"--json": None},
    "scenarios": {},
    "play": {"--seed": NUMBER, "--speedup": NUMBER, "--max-steps": NUMBER, "--out": PATHISH, "--force": None},
    "serve": {
        "--nmea": ADDRESS,
        "--json": ADDRESS,
        "--view": ADDRESS,
        "--time-factor": NUMBER,
        "--agent": st.one_of(st.sampled_from(["pid", "scripted", "x.zip"]), TEXT),
        "--allow-remote": None,
        "--failsafe": st.sampled_from(["hold", "midships_stop", "x"]),
        "--duration": NUMBER,
        "--seed": NUMBER,
        "--token": TEXT,
    },
    "helm": {"--server": ADDRESS, "--name": TEXT, "--duration": NUMBER, "--token": TEXT},
    "view": {"--server": ADDRESS, "--listen": ADDRESS, "--duration": NUMBER, "--token": TEXT},
    "view3d": {
        "--server": ADDRESS,
        "--http": ADDRESS,
        "--camera": st.one_of(st.sampled_from(["chase", "top-down"]), TEXT),
        "--rate": NUMBER,
        "--duration": NUMBER,
        "--token": TEXT,
    },
}
for _manoeuvre in [k for k in VESSEL_GYM if k.startswith("manoeuvre ")]:  # every manoeuvre writes a plot
    VESSEL_GYM[_manoeuvre].update({"--plot": PATHISH, "--force": None})
POSITIONAL = {"imo": SHIP, "play": SCENARIO, "serve": SCENARIO, **{k: SHIP for k in VESSEL_GYM if " " in k}}

VESSEL_CFD = {
    "run": {
        **{f"--{opt}": VALUE for opt, _ in cfd_cli.RUN_OPTIONS},
        "--study": PATHISH,
        "--quiet": None,
        "--ray": VALUE,
    },
    "study": {
        **{f"--{opt}": VALUE for opt, _ in cfd_cli.RUN_OPTIONS if opt != "grading"},
        "--gradings": st.one_of(st.sampled_from(["1,2,3", "3,2,1", "1,2", "0,1,2", "1,1,2"]), TEXT),
        "--study": PATHISH,
    },
    "slurm": {
        "--cases": PATHISH,
        "--nodes": NUMBER,
        "--tasks-per-node": NUMBER,
        "--time": st.one_of(st.sampled_from(["04:00:00", "1-00:00:00", "25:61:00"]), TEXT),
        "--partition": TEXT,
        "--account": TEXT,
    },
    "wigley": {"--lpp": NUMBER, "--bwl": NUMBER, "--tm": NUMBER, "--out": PATHISH},
    "clarke": {
        "--lpp": NUMBER,
        "--bwl": NUMBER,
        "--tm": NUMBER,
        "--cb": NUMBER,
        "--normalisation": st.one_of(st.sampled_from(["rho_L2_U2", "half_rho_L2_U2"]), TEXT),
    },
}
WELL_FORMED_RUN = ["--hull", "wigley", "--lpp", "1", "--bwl", "0.1", "--tm", "0.0625", "--out", "study"]


@st.composite
def argv_for(draw, table: dict, positional: dict, base: list[str] | None = None) -> list[str]:
    command = draw(st.sampled_from(sorted(table)))
    options = table[command]
    argv = command.split()
    if command in positional and draw(st.booleans()):
        argv.append(draw(positional[command]))
    if base and command == "run" and draw(st.booleans()):
        argv += base  # often valid, so that the later checks are reached too
    for opt in draw(st.lists(st.sampled_from(sorted(options)), max_size=5)) if options else []:
        argv.append(opt)
        if options[opt] is not None:
            argv.append(draw(options[opt]))
    if draw(st.integers(0, 20)) == 0:
        argv.insert(
            draw(st.integers(0, len(argv))), draw(st.one_of(TEXT, st.sampled_from(["--help", "-x", "--"])))
        )
    return argv


class _Stopped:
    """What the replaced long runs return."""

    def summary(self) -> str:
        return "stopped"


@pytest.fixture
def immediate_exits(monkeypatch, tmp_path):
    """Replace the long runs by immediate exits that still do the input checks before them."""
    from cfd import gridstudy, pipeline
    from cfd.errors import CfdError
    from vessel_gym.manoeuvres import imo, trials
    from vessel_gym.net import serve
    from vessel_gym.scenarios import load_scenario
    from vessel_gym.ui import panels, play, view3d

    def no_trials(*args, **kwargs):  # reached only after every input and output check has passed
        raise cli.UsageError("fuzz: trials replaced")

    def serve_stub(scenario, **kwargs):
        load_scenario(scenario)
        return 0

    class PipelineStub:
        def __init__(self, study, progress, ray=None):
            pass

        def run(self):
            raise CfdError("fuzz", "pipeline replaced in the fuzz test")

    def no_grid_study(study, gradings, progress):
        raise CfdError("fuzz", "grid study replaced in the fuzz test")

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(imo, "imo_report", no_trials)
    for name in ("turning_circle", "zigzag", "initial_turning", "stopping", "pull_out"):
        monkeypatch.setattr(trials, name, no_trials)
    monkeypatch.setattr(view3d, "view3d", lambda *a, **kw: 0)
    monkeypatch.setattr(gridstudy, "run_grid_study", no_grid_study)
    monkeypatch.setattr(play, "play", lambda scenario, **kw: _Stopped())
    monkeypatch.setattr(serve, "serve", serve_stub)
    received = SimpleNamespace(states_received=1)  # a panel that saw the server
    monkeypatch.setattr(panels, "run_helm", lambda server, **kw: received)
    monkeypatch.setattr(panels, "run_viewer", lambda server, **kw: received)
    monkeypatch.setattr(pipeline, "Pipeline", PipelineStub)
    monkeypatch.setattr("builtins.input", lambda prompt="": (_ for _ in ()).throw(EOFError()))


def _check(entry, argv: list[str], capsys) -> None:
    t = time.perf_counter()
    try:
        code = entry(argv)
    except SystemExit as exc:  # --help, --version and vessel-cfd's argparse errors
        code = exc.code
    dt = time.perf_counter() - t
    out, err = capsys.readouterr()
    assert code in (0, 1, 2), (argv, code, err)
    assert "Traceback" not in err and "Traceback" not in out, (argv, err)
    if code != 0:
        assert err.strip(), (argv, "failed without a message")
        assert err.count("\n") == 1 or "usage:" in err, (argv, err)
    assert dt < PER_CALL_S, (argv, dt)


FUZZ = settings(
    max_examples=600,
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)


@FUZZ
@given(argv=argv_for(VESSEL_GYM, POSITIONAL))
def test_vessel_gym_arguments(immediate_exits, capsys, argv):
    _check(cli.main, argv, capsys)


@settings(FUZZ, max_examples=300)
@given(argv=argv_for(VESSEL_CFD, {}, WELL_FORMED_RUN))
def test_vessel_cfd_arguments(immediate_exits, capsys, argv):
    _check(cfd_cli.main, argv, capsys)
