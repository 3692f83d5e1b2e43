"""``vessel-gym serve`` on a scenario whose ship has an FMU engine: it runs at real time, sends states, and
the served simulation keeps one FMU instance for its one ship (the traffic ships get none)."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("pythonfmu")
pytest.importorskip("fmpy")

from vessel_gym.fmi.export import build_engine_fmu  # noqa: E402
from vessel_gym.physics.params import TRANSMISSION
from vessel_gym.physics.shipfile import SHIP_DIR, load_ship  # noqa: E402
from vessel_gym.physics.vessel import pack  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
CHILD = Path(__file__).with_name("serve_child.py")
SHIP = "kvlcc2_l7"  # the harbour scenario's ship
DURATION_S = 8.0


@pytest.mark.slow
def test_serve_runs_a_ship_with_an_fmu_engine_at_real_time(tmp_path):
    build_engine_fmu(SHIP, tmp_path / "engine.fmu")
    ship = load_ship(SHIP)
    inertia = float(pack(ship)[TRANSMISSION.I_shaft] - ship.transmission.shaft_inertia_kgm2)
    (tmp_path / "l7_fmu.toml").write_text(
        (SHIP_DIR / f"{SHIP}.toml").read_text()
        + f"""
[[components]]
slot = "engine"
model = "vessel_gym.fmi.component:FmuEngine"
replace = true
[components.params]
path = "engine.fmu"
step_s = 0.1
shaft_inertia_kgm2 = {inertia!r}
inputs = {{ shaft_speed = "shaft_speed", rev_order = "rev_order" }}
outputs = {{ shaft_torque = "shaft_torque" }}
hold_torque = "hold_torque"
"""
    )
    text = (ROOT / "vessel_gym" / "scenarios" / "harbour.toml").read_text()
    scenario = tmp_path / "harbour_fmu.toml"
    scenario.write_text(re.sub(r'(?m)^ship = "kvlcc2_l7"$', 'ship = "l7_fmu.toml"', text, count=1))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    proc = subprocess.run(
        [sys.executable, str(CHILD), str(scenario), str(DURATION_S)],
        capture_output=True,
        text=True,
        timeout=600,
        env=env,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    res = json.loads(proc.stdout.split("RESULT ")[-1])
    assert res["rc"] == 0
    # serve builds the ship's simulation more than once (the env, its linearisations for the physics step
    # and the pilot's gains): each that reset its ship made one instance, for vessel 0, the own ship only
    made = res["instances"]
    assert made and all(k == 0 for k, _ in made), made
    assert len({owner for _, owner in made}) == len(made), made
    states = res["states"]
    assert len(states) > 50, len(states)
    (t0, w0, _), (t1, w1, _) = states[0], states[-1]
    assert t1 - t0 > 0.5 * DURATION_S
    # paced to the wall clock at time factor 1 (on a loaded machine: within a quarter)
    assert 0.75 < (t1 - t0) / (w1 - w0) < 1.25, (t1 - t0, w1 - w0)
    # the FMU engine drives the shaft: finite, within the engine's range, and following the pilot's orders
    rpm = [s[2] for s in states]
    assert all(r is not None and abs(r) < 2.0 * ship.engine.rated_rpm for r in rpm), rpm[:5]
    assert max(rpm) - min(rpm) > 10.0, (min(rpm), max(rpm))
