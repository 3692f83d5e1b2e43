"""The geared plant with friction clutches as an FMU in the engine slot (docs/fmi.md, "The governor and the
gearbox"): the supply vessel's own ``ReversingGearbox`` exported with pythonfmu, given the propeller's load
torque through the optional ``load_torque`` input, against the native plant in the crash stop."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("pythonfmu")
pytest.importorskip("fmpy")

from vessel_gym.cli import main  # noqa: E402
from vessel_gym.fmi.export import build_gearbox_fmu  # noqa: E402
from vessel_gym.physics.components import allow_code  # noqa: E402
from vessel_gym.physics.shipfile import SHIP_DIR, load_ship  # noqa: E402

SHIP = "supply"  # non-reversible diesel, reversing gear with a friction clutch per direction
ROOT = Path(__file__).resolve().parents[2]
MAP = '{ shaft_speed = "shaft_speed", rev_order = "rev_order", load_torque = "load_torque" }'


def gearbox_ship(step: float, inputs: str = MAP) -> str:
    """supply.toml with the gearbox FMU in the engine slot in place of the native ReversingGearbox entry (the
    engine's inertia is behind the clutch, inside the FMU: none added to the shaft)."""
    text = (SHIP_DIR / f"{SHIP}.toml").read_text()
    start = text.index('[[components]]\nslot = "engine"')
    end = text.index("[[components]]", start + 1)
    return (
        text[:start]
        + text[end:]
        + f"""
[[components]]
slot = "engine"
model = "vessel_gym.fmi.component:FmuEngine"
replace = true
[components.params]
path = "gearbox.fmu"
step_s = {step!r}
shaft_inertia_kgm2 = 0.0
inputs = {inputs}
outputs = {{ shaft_torque = "shaft_torque" }}
hold_torque = "hold_torque"
start = {{ max_step = 0.05 }}
"""
    )


@pytest.fixture(scope="module")
def gearbox_dir(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("gearbox")
    build_gearbox_fmu(SHIP, d / "gearbox.fmu")
    for step in (0.01, 0.05, 0.5, 1.0):
        (d / f"fmu_{step}.toml").write_text(gearbox_ship(step))
    (d / "noload.toml").write_text(gearbox_ship(0.01, MAP.replace(', load_torque = "load_torque"', "")))
    return d


CHILD = """
import json, os, sys
import numpy as np
from vessel_gym.manoeuvres.trials import stopping
from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import allow_code
from vessel_gym.physics.simulation import Simulation

allow_code()
stops, series = json.loads(sys.argv[1]), json.loads(sys.argv[2])
out = {"stop": {}, "series": {}}
for ship, dt in stops:
    out["stop"][ship + "@" + repr(dt)] = stopping(ship, dt=dt).to_dict()
for ship in series:  # full astern from the approach, shaft speed every 0.05 s over 60 s
    sim = Simulation(ship, dt=0.05)
    sim.reset()
    sim.set_helm(rev_order=-sim.rev_order)
    n = []
    for _ in range(1200):
        sim.advance(0.05)
        n.append(float(sim.state[0, lo.X_REV]))
    out["series"][ship] = n
print(json.dumps(out))
sys.stdout.flush()
os._exit(0)  # pythonfmu 0.7's FMUs may abort the interpreter's own shutdown (docs/fmi.md)
"""


def run_child(stops: list, series: list) -> dict:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    proc = subprocess.run(
        [sys.executable, "-c", CHILD, json.dumps(stops), json.dumps(series)],
        capture_output=True,
        text=True,
        timeout=900,
        env=env,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout)


@pytest.mark.slow
def test_gearbox_fmu_crash_stop_matches_the_native_gearbox(gearbox_dir):
    import numpy as np

    f = {H: str(gearbox_dir / f"fmu_{H}.toml") for H in (0.01, 0.05, 0.5, 1.0)}
    noload = str(gearbox_dir / "noload.toml")
    dt = 0.01  # s: the native plant's own step error (events seen at step ends) below the hold's
    res = run_child([[SHIP, dt], [f[0.01], dt], [f[0.05], dt], [noload, dt]], [SHIP, f[0.5], f[1.0]])
    stop = {k.rsplit("@", 1)[0]: v for k, v in res["stop"].items()}
    native = stop[SHIP]
    U0 = native["speed_kn"] * 1852.0 / 3600.0  # m/s
    d = {H: abs(stop[f[H]]["track_reach_m"] - native["track_reach_m"]) for H in (0.01, 0.05)}
    for H in (0.01, 0.05):
        # the sequence (release, interlock on the shaft speed, fill, slip, lock, governor) sees the shaft speed
        # up to H late and its torque reaches the shaft held over H: the astern torque may come up to H late
        # (a stop moved by at most U0 H), and the native plant's own events up to one step dt late
        assert d[H] < U0 * (H + dt), (H, d)
        assert abs(stop[f[H]]["time_s"] - native["time_s"]) < H + dt
    assert d[0.01] < d[0.05]  # the hold's error shrinks with H
    # without the load torque the clutch's locked torque is wrong (only the slip feedback holds the lock):
    # the input is what makes the stop the native one
    d_noload = abs(stop[noload]["track_reach_m"] - native["track_reach_m"])
    assert d_noload > 3.0 * d[0.01], (d_noload, d)
    # stability of the held stick: the shaft takes its share (eta i^2 / I_s) / (1/I_E + eta i^2 / I_s) of the
    # slip correction with the torque held over H, so the hold is stable for H below about 2 T / share
    # (0.6 s on supply, T = lock_time_s = 0.2 s): at H = 0.5 s the shaft settles astern as the native one; at
    # H = 1 s the locked clutch oscillates (the shaft speed swings by more than 1 rev/s to the end)
    n_native = np.array(res["series"][SHIP])
    late = slice(800, None)  # the last 20 s, clutch locked astern
    swing = {H: np.ptp(np.array(res["series"][f[H]])[late]) for H in (0.5, 1.0)}
    assert swing[0.5] < 1.2 * np.ptp(n_native[late])
    assert abs(res["series"][f[0.5]][-1] - n_native[-1]) < 1e-3 * abs(n_native[-1])
    assert swing[1.0] > 0.5 * abs(n_native[-1])


@pytest.fixture
def code_allowed():
    allow_code()
    yield
    allow_code(False)


def test_load_torque_naming_a_missing_variable_is_one_line(gearbox_dir, tmp_path, code_allowed, capsys):
    (tmp_path / "gearbox.fmu").write_bytes((gearbox_dir / "gearbox.fmu").read_bytes())
    ship = tmp_path / "bad.toml"
    ship.write_text(gearbox_ship(0.05, MAP.replace('load_torque = "load_torque"', 'load_torque = "Q_load"')))
    assert main(["manoeuvre", "turning-circle", str(ship)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "gearbox.fmu" in err and "'Q_load'" in err, err


def test_gearbox_fmu_is_valid_with_units(gearbox_dir):
    from fmpy import read_model_description
    from fmpy.validation import validate_fmu

    fmu = str(gearbox_dir / "gearbox.fmu")
    assert validate_fmu(fmu) == []
    units = {v.name: (v.causality, v.unit) for v in read_model_description(fmu).modelVariables}
    assert units["load_torque"] == ("input", "N.m")
    assert units["shaft_speed"] == ("input", "1/s") and units["shaft_torque"] == ("output", "N.m")


def test_gearbox_fmu_needs_a_gearbox(tmp_path):
    with pytest.raises(ValueError, match="no ReversingGearbox"):
        build_gearbox_fmu("kvlcc2", tmp_path / "g.fmu")
    assert load_ship(SHIP).engine is not None
