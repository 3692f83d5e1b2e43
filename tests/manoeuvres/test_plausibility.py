"""A ship that no hull could be is refused: the ship-file check (signs, energy, rudder) and the IMO report's
plausibility gate (speed or energy rising with no more power, a turn against the rudder)."""

from __future__ import annotations

import dataclasses
import json
import re
from pathlib import Path

import pytest

from vessel_gym.cli import main
from vessel_gym.manoeuvres.imo import SPEED_RISE_ALLOWANCE, imo_report
from vessel_gym.physics.plausibility import IMPOSSIBLE, OK, UNUSUAL, check_ship, impossible
from vessel_gym.physics.shipfile import builtin_ships

SHIPS = Path(__file__).resolve().parents[2] / "vessel_gym" / "physics" / "data" / "ships"


def _copy(tmp_path: Path, ship: str, edit) -> Path:
    path = tmp_path / f"{ship}_edited.toml"
    path.write_text(edit((SHIPS / f"{ship}.toml").read_text()))
    return path


def _set(text: str, **values: float) -> str:
    for key, value in values.items():
        text, n = re.subn(rf"(?m)^{key} = \S+", f"{key} = {value}", text)
        assert n == 1, key
    return text


def _reverse_rudder(text: str) -> str:
    """Every Abkowitz term odd in the rudder angle negated: the rudder pushes the other way."""

    def flip(m: re.Match) -> str:
        return f"{m.group(1)} = {-float(m.group(2))!r}"

    return re.sub(r"(?m)^([XYN]_[0uvr]*d(?:[uvr]*d[uvr]*d)*[uvr]*) = (\S+)", flip, text)


@pytest.fixture(scope="module")
def pushing_hull(tmp_path_factory) -> Path:
    """kvlcc2 with X_vv = X_vr = X_rr = +0.5, each inside its allowed range: drift and yaw push it along."""
    return _copy(tmp_path_factory.mktemp("ships"), "kvlcc2", lambda t: _set(t, X_vv=0.5, X_vr=0.5, X_rr=0.5))


@pytest.fixture(scope="module")
def reversed_rudder(tmp_path_factory) -> Path:
    return _copy(tmp_path_factory.mktemp("ships"), "mariner", _reverse_rudder)


@pytest.mark.parametrize("ship", builtin_ships())
def test_every_built_in_ship_is_possible(ship):
    findings = check_ship(ship)
    assert not impossible(findings), [f for f in findings if f.status == IMPOSSIBLE]
    energy = next(f for f in findings if f.quantity.startswith("hull power"))
    assert energy.status == OK and energy.value < 0.0
    rudder = next(f for f in findings if f.quantity.startswith("turn with"))
    assert rudder.value > 0.0


def test_the_supply_ships_positive_n_v_is_stated_not_refused():
    """Fossen's supply vessel has N_v > 0 (unlike Clarke's regression for merchant hulls): unusual only."""
    n_v = next(f for f in check_ship("supply") if f.quantity == "N_v")
    assert n_v.value > 0.0 and n_v.status == UNUSUAL


def test_a_hull_that_pushes_the_ship_is_impossible(pushing_hull):
    findings = check_ship(str(pushing_hull))
    bad = impossible(findings)
    assert [f.quantity for f in bad] == ["hull power P'(v', r')"]
    assert "Fossen 2011" in bad[0].source
    assert next(f for f in findings if f.quantity == "X_vv").status == UNUSUAL


def test_a_reversed_rudder_is_impossible(reversed_rudder):
    bad = impossible(check_ship(str(reversed_rudder)))
    assert [f.quantity for f in bad] == ["turn with starboard rudder, deg"]
    assert bad[0].value < 0.0


def test_imo_report_refuses_a_ship_that_gains_speed_in_a_turn(pushing_hull):
    r = imo_report(str(pushing_hull))
    assert r.verdict == "IMPLAUSIBLE" and not r.passed
    turning = r.trials["turning_starboard"]
    rise = max(turning.track.u) / turning.track.u[0]
    assert rise > 1.0 + SPEED_RISE_ALLOWANCE  # the attack: 1.66x the approach speed in the 35 deg turn
    for c in r.criteria_named("advance"):
        assert c.verdict == "implausible" and "speed rose" in c.implausible
    assert any("hull power" in why for why in r.implausible_reasons)
    assert "overall: IMPLAUSIBLE" in r.table()


def test_a_single_trials_plot_does_not_pass_an_implausible_turn(pushing_hull):
    """`manoeuvre turning-circle SHIP --plot` draws the IMO verdicts of that one trial: a turn that gains speed
    is marked implausible there too (it was drawn as a green PASS box)."""
    from vessel_gym.manoeuvres.imo import criteria_for
    from vessel_gym.manoeuvres.plot_style import _verdict_lines
    from vessel_gym.manoeuvres.trials import turning_circle
    from vessel_gym.physics.shipfile import load_ship

    ship = load_ship(str(pushing_hull))
    crit = criteria_for(turning_circle(ship, 35.0, until_deg=360.0), ship)
    assert [c.name for c in crit] == ["advance", "tactical_diameter"]
    assert all(c.verdict == "implausible" and "speed rose" in c.implausible for c in crit)
    lines = _verdict_lines(crit)
    assert not any(ok for _, ok in lines) and not any("PASS" in text for text, _ in lines)
    assert "<= 4.50 L  IMPLAUSIBLE" in lines[0][0]  # the value is stated truly, the verdict withheld
    assert lines[-1][0].startswith("not scored: turning starboard: the speed rose to")
    good = load_ship("kvlcc2")
    crit = criteria_for(turning_circle(good, -35.0, until_deg=360.0), good)
    assert [text.endswith("PASS") for text, _ in _verdict_lines(crit)] == [True, True]


def test_imo_report_refuses_a_ship_that_turns_against_its_rudder(reversed_rudder):
    r = imo_report(str(reversed_rudder))
    assert r.verdict == "IMPLAUSIBLE"
    for c in r.criteria_named("advance") + r.criteria_named("initial_turning"):
        assert c.verdict == "implausible" and "turned to" in c.implausible, c


def test_a_crash_stop_that_gains_speed_or_energy_is_implausible():
    """The stopping test's rules, on kvlcc2's real crash stop with its recorded motion changed: the speed rising
    5 % above the approach, or the speed falling while a yaw spin-up adds kinetic energy (r L / U0 up to 0.8),
    is refused with its reason; the crash stop as run is not."""
    from types import SimpleNamespace

    import numpy as np

    from vessel_gym.manoeuvres.imo import implausibility
    from vessel_gym.manoeuvres.trials import stopping
    from vessel_gym.physics.shipfile import load_ship

    ship = load_ship("kvlcc2")
    st = stopping(ship)
    assert implausibility(st, ship, "stopping") == ""
    tr = st.track
    u, v, r, psi = (np.array(a, dtype=float) for a in (tr.u, tr.v, tr.r, tr.psi))
    ramp = np.linspace(0.0, 1.0, u.size)

    def judged(**arrays) -> str:
        motion = dict(u=u, v=v, r=r, psi=psi) | arrays
        return implausibility(dataclasses.replace(st, track=SimpleNamespace(**motion)), ship, "stopping")

    assert "the speed rose to 1.05x" in judged(u=u[0] * (1.0 + 0.05 * ramp))
    spin = judged(u=u[0] * (1.0 - 0.005 * ramp), r=0.8 * u[0] / ship.particulars.L_m * ramp)
    assert "the kinetic energy rose to" in spin and "engine astern" in spin


def test_imo_command_exits_1_on_an_implausible_ship(pushing_hull, capsys):
    code = main(["imo", str(pushing_hull), "--json"])
    d = json.loads(capsys.readouterr().out)
    assert code == 1
    assert d["verdict"] == "IMPLAUSIBLE" and d["pass"] is False and d["implausible"]
    assert not any(c["pass"] for c in d["criteria"] if c.get("implausible"))


def test_ships_check_command(pushing_hull, capsys):
    assert main(["ships", "check", "kvlcc2"]) == 0
    out = capsys.readouterr().out
    assert "overall: possible" in out and "Clarke, Gedling & Hine 1983" in out
    assert main(["ships", "check", str(pushing_hull), "--json"]) == 1
    d = json.loads(capsys.readouterr().out)
    assert d["possible"] is False
    assert {f["quantity"]: f["status"] for f in d["findings"]}["X_vv"] == UNUSUAL


@pytest.mark.parametrize("argv", [["ships", "check"], ["ships", "kvlcc2"], ["ships", "check", "nope.toml"]])
def test_ships_check_bad_input_is_one_line_exit_2(argv, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("vessel-gym") and "\n" not in err
