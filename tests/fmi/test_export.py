"""The whole ship as an FMI 2.0 co-simulation FMU (vessel_gym.fmi.export, ``vessel-gym fmu``): checked with
fmpy's validation, and simulated with fmpy against the native simulation of the same turning circle."""

from __future__ import annotations

import json
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

from vessel_gym.cli import main
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.simulation import Simulation

pytest.importorskip("pythonfmu")
pytest.importorskip("fmpy")

CHILD = Path(__file__).with_name("fmu_child.py")
SHIP = "kvlcc2_l7_windage"  # with a windage table, so the wind inputs act
DT = 0.1  # s, the FMU's internal step and the communication step
DURATION = 300.0  # s: the 35 deg turn of the 7 m model past 540 deg of heading change
OUTPUTS = ["x", "y", "heading", "u", "v", "r", "rudder_angle", "shaft_speed"]
WEATHER = {
    "wind_speed": 12.0,
    "wind_from": np.radians(60.0),
    "current_speed": 0.3,
    "current_to": np.radians(200.0),
}


def run_fmus(runs: list[dict], tmp: Path) -> dict:
    spec, out = tmp / "runs.json", tmp / "out.npz"
    spec.write_text(json.dumps(runs))
    proc = subprocess.run(
        [sys.executable, str(CHILD), str(spec), str(out)], capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    return dict(np.load(out))


def native(weather: dict | None) -> dict:
    sim = Simulation(SHIP, dt=DT)
    if weather:
        sim.set_environment(
            Environment(
                wind_speed_m_s=weather["wind_speed"],
                wind_from_deg=np.degrees(weather["wind_from"]),
                current_speed_m_s=weather["current_speed"],
                current_to_deg=np.degrees(weather["current_to"]) - 360.0,
            )
        )
    sim.reset()
    sim.set_helm(rudder_order_rad=np.radians(35.0))
    rows = [[sim.north[0], sim.east[0], sim.heading[0]]]
    for _ in range(round(DURATION / DT)):
        sim.step(1)
        rows.append([sim.north[0], sim.east[0], sim.heading[0]])
    return np.array(rows)


@pytest.fixture(scope="module")
def ship_fmu(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("fmu") / "ship.fmu"
    assert main(["fmu", SHIP, "--out", str(out)]) == 0
    return out


@pytest.mark.slow
def test_fmu_passes_fmpy_validation(ship_fmu):
    from fmpy import read_model_description
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(ship_fmu)) == []
    md = read_model_description(str(ship_fmu))
    assert md.fmiVersion == "2.0" and md.coSimulation is not None and md.modelExchange is None
    causality = {v.name: (v.causality, v.unit) for v in md.modelVariables}
    for name in ("rudder_order", "rev_order", "wind_speed", "wind_from", "current_speed", "current_to"):
        assert causality[name][0] == "input"
    for name in OUTPUTS:
        assert causality[name][0] == "output"
    assert (
        causality["x"][1] == "m" and causality["heading"][1] == "rad" and causality["shaft_speed"][1] == "1/s"
    )
    # the ship file travels in the FMU: its parameters are the ship's
    with zipfile.ZipFile(ship_fmu) as z:
        embedded = z.read("resources/ship.toml").decode()
    assert load_ship(SHIP).path and embedded == Path(load_ship(SHIP).path).read_text()


@pytest.mark.slow
def test_fmu_turning_circle_is_the_native_one(ship_fmu, tmp_path):
    L = load_ship(SHIP).particulars.L_m
    rudder = {"rudder_order": float(np.radians(35.0))}
    runs = [
        {
            "fmu": str(ship_fmu),
            "stop_time": DURATION,
            "step_size": DT,
            "start_values": rudder,
            "output": OUTPUTS,
        },
        {
            "fmu": str(ship_fmu),
            "stop_time": DURATION,
            "step_size": DT,
            "start_values": {**rudder, **{k: float(v) for k, v in WEATHER.items()}},
            "output": OUTPUTS,
        },
    ]
    res = run_fmus(runs, tmp_path)
    for i, weather in enumerate((None, WEATHER)):
        ref = native(weather)
        got = np.column_stack([res[f"run{i}_x"], res[f"run{i}_y"], res[f"run{i}_heading"]])
        assert got.shape == ref.shape
        assert abs(ref[-1, 2]) > np.radians(540.0)  # a whole turning circle and more
        assert np.max(np.hypot(got[:, 0] - ref[:, 0], got[:, 1] - ref[:, 1])) < 1e-6 * L
        assert np.max(np.abs(got[:, 2] - ref[:, 2])) < 1e-9
    # the weather moved the circle: the inputs reached the physics
    assert np.hypot(res["run1_x"][-1] - res["run0_x"][-1], res["run1_y"][-1] - res["run0_y"][-1]) > 0.5 * L


@pytest.mark.slow
def test_fmu_start_parameters_order_and_longer_steps(ship_fmu, tmp_path):
    """Start position and heading, a shaft-speed order set by the importer, and a communication step of five
    internal steps: the native simulation's at every communication point."""
    start = {"x0": 100.0, "y0": -50.0, "heading0": 1.0, "rudder_order": -0.2}
    sim = Simulation(SHIP, dt=DT)
    sim.reset(heading_deg=np.degrees(1.0), x_m=100.0, y_m=-50.0)
    rev = 0.6 * float(sim.rev_order[0])
    sim.set_helm(rudder_order_rad=-0.2, rev_order=rev)
    H, T = 5 * DT, 60.0
    run = {"fmu": str(ship_fmu), "stop_time": T, "step_size": H, "output": OUTPUTS}
    res = run_fmus([{**run, "start_values": {**start, "rev_order": rev}}], tmp_path)
    ref = [[sim.north[0], sim.east[0], sim.heading[0], sim.rev[0]]]
    for _ in range(round(T / H)):
        sim.step(5)
        ref.append([sim.north[0], sim.east[0], sim.heading[0], sim.rev[0]])
    ref = np.array(ref)
    got = np.column_stack([res["run0_x"], res["run0_y"], res["run0_heading"], res["run0_shaft_speed"]])
    assert got.shape == ref.shape and np.max(np.abs(got - ref)) < 1e-9
    assert ref[-1, 3] < 0.7 * ref[0, 3]  # the order reached the shaft


def test_fmu_command_refuses_to_replace_a_file(tmp_path, capsys):
    out = tmp_path / "ship.fmu"
    out.write_bytes(b"mine")
    assert main(["fmu", "kvlcc2", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "exists" in err and "--force" in err
    assert out.read_bytes() == b"mine"


@pytest.mark.parametrize(
    "argv, words",
    [
        (["fmu", "no_such_ship", "--out", "x.fmu"], "no_such_ship"),
        (["fmu", "kvlcc2"], "--out"),
        (["fmu", "kvlcc2", "--out", "ship.png"], ".png"),
        (["fmu", "kvlcc2", "--out", "s.fmu", "--dt", "0"], "--dt"),
    ],
)
def test_fmu_command_bad_input_is_one_line(argv, words, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and words in err
    assert not list(tmp_path.iterdir())
