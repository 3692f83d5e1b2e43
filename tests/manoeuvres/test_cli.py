"""The command-line contract other tools rely on (JSON keys, exit codes, one-line errors)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from vessel_gym.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_turning_circle_json_keys(capsys):
    code, out, _ = run(
        capsys, "manoeuvre", "turning-circle", "--ship", "kvlcc2_l7", "--rudder", "35", "--json"
    )
    assert code == 0
    d = json.loads(out)
    for key in (
        "advance_L",
        "transfer_L",
        "tactical_diameter_L",
        "steady_diameter_L",
        "advance_m",
        "tactical_diameter_m",
        "time_to_90_s",
        "time_to_180_s",
        "final_speed_kn",
    ):
        assert isinstance(d[key], float), key
    assert 2.5 < d["advance_L"] < 3.5


def test_zigzag_json_keys_and_sign(capsys):
    code, out, _ = run(
        capsys, "manoeuvre", "zigzag", "--ship", "kvlcc2_l7", "--rudder", "-10", "--heading", "10", "--json"
    )
    assert code == 0
    d = json.loads(out)
    assert len(d["overshoot_deg"]) >= 2 and all(o > 0 for o in d["overshoot_deg"])
    assert d["period_s"] > 0


def test_initial_turning_and_stopping_keys(capsys):
    code, out, _ = run(capsys, "manoeuvre", "initial-turning", "--ship", "kvlcc2_l7", "--json")
    assert code == 0 and {"distance_L", "time_s"} <= set(json.loads(out))
    code, out, _ = run(capsys, "manoeuvre", "stopping", "--ship", "kvlcc2_l7", "--json")
    d = json.loads(out)
    assert code == 0 and {"track_reach_L", "head_reach_L", "lateral_deviation_L", "time_s"} <= set(d)
    assert d["track_reach_L"] > 0


def test_imo_json_contract(capsys, tmp_path):
    code, out, _ = run(capsys, "imo", "kvlcc2", "--json", "--plot", str(tmp_path))
    assert code == 0
    d = json.loads(out)
    assert {"ship", "L_m", "V_kn", "L_over_V_s", "criteria"} <= set(d)
    names = {c["name"] for c in d["criteria"]}
    assert names == {
        "advance",
        "tactical_diameter",
        "initial_turning",
        "zigzag_10_first_overshoot",
        "zigzag_10_second_overshoot",
        "zigzag_20_first_overshoot",
        "stopping_track_reach",
    }
    for c in d["criteria"]:
        assert {"name", "side", "value", "limit", "unit", "pass"} <= set(c)
        assert isinstance(c["pass"], bool)
    # L/V = 40 s -> 10/10 limits 20 and 40 deg (MSC.137(76) 5.3.3)
    lim = {(c["name"]): c["limit"] for c in d["criteria"]}
    assert lim["zigzag_10_first_overshoot"] == 20.0 and lim["zigzag_10_second_overshoot"] == 40.0
    pngs = sorted(p.name for p in tmp_path.glob("*.png"))
    assert pngs == [
        "initial_turning.png",
        "pull_out.png",
        "stopping.png",
        "turning_circle.png",
        "zigzag_10.png",
        "zigzag_20.png",
    ]
    assert all((tmp_path / p).stat().st_size > 10_000 for p in pngs)


@pytest.mark.parametrize(
    "argv",
    [
        ("manoeuvre", "turning-circle", "--ship", "nosuchship"),
        ("manoeuvre", "turning-circle", "--ship", "kvlcc2", "--rudder", "abc"),
        ("manoeuvre", "turning-circle", "--ship", "kvlcc2", "--rudder", "nan"),
        ("manoeuvre", "zigzag", "--ship", "kvlcc2", "--heading", "95"),
        ("manoeuvre", "turning-circle", "--ship", "kvlcc2", "--rudder", "50"),
        ("imo", "/nonexistent/ship.toml"),
        ("frobnicate",),
    ],
)
def test_bad_input_exit_2_one_line(capsys, argv):
    code, _out, err = run(capsys, *argv)
    assert code == 2
    assert err.strip() and len(err.strip().splitlines()) == 1


def test_incomplete_manoeuvre_says_so(capsys):
    # a 1 deg rudder at full scale cannot bring the ship round 180 deg within the time limit
    code, out, err = run(
        capsys, "manoeuvre", "turning-circle", "--ship", "kvlcc2", "--rudder", "0.5", "--json"
    )
    assert code == 1 and out == "" and "180" in err


def test_console_script_runs():
    res = subprocess.run(
        [sys.executable, "-m", "vessel_gym.cli", "ships"], capture_output=True, text=True, check=True
    )
    assert "kvlcc2" in res.stdout.split()


def _broken_ship(tmp_path):
    """Mariner with X_vv of the wrong sign and 100 x its size: any turn accelerates the ship without bound
    while every number stays finite (a runaway only the physical bounds catch)."""
    from pathlib import Path

    src = Path(__file__).resolve().parents[2] / "vessel_gym" / "physics" / "data" / "ships" / "mariner.toml"
    text = src.read_text()
    assert "X_vv = -8.990000e-03" in text
    p = tmp_path / "broken_mariner.toml"
    p.write_text(text.replace("X_vv = -8.990000e-03", "X_vv = 8.990000e-01"))
    return str(p)


def test_manoeuvre_that_runs_away_is_not_scored(capsys, tmp_path):
    ship = _broken_ship(tmp_path)
    code, out, _ = run(capsys, "manoeuvre", "turning-circle", "--ship", ship, "--json")
    assert code == 1
    d = json.loads(out)
    assert d["verdict"] == "diverged"
    assert "speed through the water" in d["reason"] and "exceeds" in d["reason"]
    assert "advance_L" not in d
    code, out, err = run(capsys, "manoeuvre", "turning-circle", "--ship", ship)
    assert code == 1 and out == ""
    assert err.count("\n") == 1 and "diverged" in err


@pytest.mark.slow
def test_imo_report_with_a_runaway_is_not_pass(capsys, tmp_path):
    code, out, _ = run(capsys, "imo", _broken_ship(tmp_path), "--json")
    assert code == 1
    d = json.loads(out)
    assert d["pass"] is False and d["verdict"] == "DIVERGED"
    turning = [c for c in d["criteria"] if c["name"] == "advance"]
    assert turning and all(c["verdict"] == "diverged" and c["value"] is None for c in turning)
    assert all("exceeds" in c["note"] for c in turning)
    code, out, _ = run(capsys, "imo", _broken_ship(tmp_path))
    assert code == 1 and "overall: DIVERGED" in out


def test_a_speed_far_below_the_test_speed_fails_at_once(capsys):
    """--speed 0.1 ran 55 s of a turn that never reached 180 deg, then exited 1: now refused before it runs."""
    import time

    t0 = time.monotonic()
    code, out, err = run(capsys, "manoeuvre", "turning-circle", "kvlcc2", "--speed", "0.1")
    assert code == 2 and out == ""
    assert time.monotonic() - t0 < 5.0
    assert err.count("\n") == 1 and "below 1.55 kn, a tenth of kvlcc2's test speed" in err


@pytest.mark.parametrize("argv", [["manoeuvre", "zigzag", "kvlcc2"], ["imo", "kvlcc2"]])
def test_an_unwritable_plot_target_is_refused_before_the_trials(argv, capsys):
    import time

    t0 = time.monotonic()
    code, out, err = run(capsys, *argv, "--plot", "/proc/x.pdf")
    assert code == 2 and out == ""
    assert time.monotonic() - t0 < 5.0  # the trials take longer: refused before them
    assert err.count("\n") == 1 and "--plot: cannot write in '/proc'" in err
