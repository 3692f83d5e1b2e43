"""Fuzz test of ship and scenario files through the command line: mutated built-in files (hostile values,
deleted and repeated lines, random bytes, truncation, device and directory paths) end in exit code 0 or 2
within a bounded time, never an uncaught exception, and every refusal is one line on stderr naming the file.

The command runs in-process (``vessel_gym.cli.main``) with the expensive part after loading replaced: the IMO
manoeuvres by loading and packing the ship, the pygame session by nothing, so a valid file costs
milliseconds. Hypothesis runs derandomized (a fixed sequence of cases), so CI is reproducible.
"""

from __future__ import annotations

import contextlib
import io
import json
import time
from pathlib import Path
from types import SimpleNamespace

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from vessel_gym.cli import main
from vessel_gym.physics.plausibility import check_ship
from vessel_gym.physics.shipfile import SHIP_DIR, builtin_ships, load_ship
from vessel_gym.physics.vessel import pack
from vessel_gym.scenarios.scenario import SCENARIO_DIR, builtin_scenarios

#: wall-clock bound per case, s: loading fails or succeeds in milliseconds; a hang or an unbounded read
#: (a device, a pipe) would take forever
CASE_S = 5.0

SHIPS = {name: (SHIP_DIR / f"{name}.toml").read_bytes() for name in builtin_ships()}
SCENARIOS = {name: (SCENARIO_DIR / f"{name}.toml").read_bytes() for name in builtin_scenarios()}

_HOSTILE = [
    "nan",
    "-nan",
    "inf",
    "-inf",
    "1e300",
    "-1e300",
    "1e-300",
    "0",
    "-0.0",
    "-1",
    "9" * 400,
    "-" + "9" * 400,
    "7" * 5000,
    '"text"',
    '""',
    "true",
    "[]",
    "[1, 2, 3]",
    "[[1.0, 2.0], [3.0]]",
    "{}",
    "{ a = 1 }",
    "[" * 100_000,
    "[" * 100_000 + "]" * 100_000,
    "[" * 300 + "1" + "]" * 300,
    '"/dev/zero"',
    '"/dev/stdin"',
    '"/dev/null"',
    '"."',
    '"/"',
    '"kvlcc2"',
    '"no_such_ship.toml"',
    '"' + "x/" * 3000 + '.toml"',
    '"a\\u0000b.toml"',
    "1979-05-27T07:32:00Z",
    "0x7fffffff",
]


def _float_token(x: float) -> str:
    return {"nan": "nan", "inf": "inf", "-inf": "-inf"}.get(repr(x), repr(x))


VALUES = st.one_of(
    st.sampled_from(_HOSTILE),
    st.floats(allow_nan=True, allow_infinity=True).map(_float_token),
    st.integers(min_value=-(10**30), max_value=10**30).map(str),
    st.text(max_size=20).map(lambda s: json.dumps(s)),
)


@st.composite
def mutated(draw, files: dict[str, bytes]) -> bytes:
    """A built-in file with one to three mutations."""
    text = files[draw(st.sampled_from(sorted(files)))]
    for _ in range(draw(st.integers(1, 3))):
        rows = text.split(b"\n")
        i = draw(st.integers(0, len(rows) - 1))
        kind = draw(st.sampled_from(["value"] * 6 + ["delete", "repeat", "bytes", "truncate"]))
        if kind == "value" and b"=" in rows[i]:
            key = rows[i].split(b"=", 1)[0]
            rows[i] = key + b"= " + draw(VALUES).encode()
        elif kind == "delete":
            del rows[i]
        elif kind == "repeat":
            rows.insert(i, rows[i])
        elif kind == "bytes":
            j = draw(st.integers(0, len(rows[i])))
            rows[i] = rows[i][:j] + draw(st.binary(min_size=1, max_size=8)) + rows[i][j:]
        elif kind == "truncate":
            rows = rows[:i]
        text = b"\n".join(rows)
    return text


def _fake_imo_report(ship, **_kw):
    """Stands in for the IMO manoeuvres: the loading and packing a real report starts with."""
    s = load_ship(ship)
    pack(s)
    check_ship(s)  # the hull-model checks every report runs first
    return SimpleNamespace(
        to_dict=lambda: {"ship": s.name}, table=lambda: s.name, diverged=False, implausible_reasons=[]
    )


def _fake_play(scenario, **_kw):
    return SimpleNamespace(summary=lambda: "")


def _run(argv: list[str], path: Path) -> None:
    err = io.StringIO()
    t0 = time.monotonic()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(argv)
    elapsed = time.monotonic() - t0
    assert elapsed < CASE_S, f"{elapsed:.1f} s"
    assert code in (0, 1, 2), code
    msg = err.getvalue()
    if code == 2:  # bad input: one line naming the file
        assert msg.endswith("\n") and msg.count("\n") == 1, msg
        assert "Traceback" not in msg and str(path) in msg, msg
    elif code == 1:  # a valid file whose ship cannot run (e.g. the propeller cannot make the test speed)
        assert msg.endswith("\n") and msg.count("\n") == 1 and "Traceback" not in msg, msg


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """One directory for the module (a function-scoped tmp_path would be shared by every example)."""
    import vessel_gym.manoeuvres.imo
    import vessel_gym.ui.play

    d = tmp_path_factory.mktemp("fuzz")
    # the checks' short runs compile each kind of ship's kernels once, before any case is timed
    for name in SHIPS:
        check_ship(name)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(vessel_gym.manoeuvres.imo, "imo_report", _fake_imo_report)
        mp.setattr(vessel_gym.ui.play, "play", _fake_play)
        yield d


def _settings(n: int):
    return settings(
        max_examples=n,
        derandomize=True,
        deadline=None,  # the bound is CASE_S, asserted per case
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )


def _ship_case(workdir: Path, text: bytes) -> None:
    path = workdir / "ship.toml"
    path.write_bytes(text)
    _run(["imo", str(path)], path)


def _scenario_case(workdir: Path, text: bytes) -> None:
    path = workdir / "scenario.toml"
    path.write_bytes(text)
    _run(["play", str(path)], path)


@_settings(300)
@given(text=mutated(SHIPS))
def test_fuzz_ship_files(workdir, text):
    _ship_case(workdir, text)


@_settings(150)
@given(text=mutated(SCENARIOS))
def test_fuzz_scenario_files(workdir, text):
    _scenario_case(workdir, text)


@pytest.mark.slow
@_settings(2000)
@given(text=mutated(SHIPS))
def test_fuzz_ship_files_many(workdir, text):
    _ship_case(workdir, text)


@pytest.mark.slow
@_settings(1000)
@given(text=mutated(SCENARIOS))
def test_fuzz_scenario_files_many(workdir, text):
    _scenario_case(workdir, text)


def test_the_fakes_load_valid_files(workdir):
    """The replaced steps still load: a built-in ship and scenario exit 0."""
    for name, text in SHIPS.items():
        _ship_case(workdir, text)
        assert load_ship(workdir / "ship.toml").particulars == load_ship(name).particulars
    for text in SCENARIOS.values():
        path = workdir / "scenario.toml"
        path.write_bytes(text)
        assert main(["play", str(path)]) == 0
