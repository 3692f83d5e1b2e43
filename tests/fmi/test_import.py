"""FMUs as components of a ship (vessel_gym.fmi.component): the ship's own engine and governor exported as
an FMU with pythonfmu and put back in place of the native engine; bad FMUs are one line naming the file and
the variable, exit 2 from the command line."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

pytest.importorskip("pythonfmu")
pytest.importorskip("fmpy")

from vessel_gym.cli import main  # noqa: E402
from vessel_gym.fmi.export import build_engine_fmu, build_steering_gear_fmu  # noqa: E402
from vessel_gym.physics import layout as lo  # noqa: E402
from vessel_gym.physics.components import allow_code  # noqa: E402
from vessel_gym.physics.params import TRANSMISSION
from vessel_gym.physics.shipfile import SHIP_DIR, load_ship  # noqa: E402
from vessel_gym.physics.vessel import pack  # noqa: E402

CHILD = Path(__file__).with_name("trials_child.py")
SHIP = "kvlcc2"  # direct-reversing two-stroke: the crash stop runs the whole reversing sequence
ROOT = Path(__file__).resolve().parents[2]


def engine_table(fmu: str, step: float, **changes) -> str:
    """The [[components]] entry of an FMU engine in place of the ship's own (its inertia the native one's)."""
    ship = load_ship(SHIP)
    inertia = float(pack(ship)[TRANSMISSION.I_shaft] - ship.transmission.shaft_inertia_kgm2)
    params = {
        "path": f'"{fmu}"',
        "step_s": repr(step),
        "shaft_inertia_kgm2": repr(inertia),
        "inputs": '{ shaft_speed = "shaft_speed", rev_order = { name = "rev_order", unit = "1/s" } }',
        "outputs": '{ shaft_torque = { name = "shaft_torque", unit = "N.m" } }',
        "hold_torque": '"hold_torque"',
    }
    params.update(changes)
    body = "\n".join(f"{k} = {v}" for k, v in params.items() if v is not None)
    return f'\n[[components]]\nslot = "engine"\nmodel = "vessel_gym.fmi.component:FmuEngine"\nreplace = true\n[components.params]\n{body}\n'


@pytest.fixture(scope="module")
def engine_dir(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("engine")
    build_engine_fmu(SHIP, d / "engine.fmu")
    text = (SHIP_DIR / f"{SHIP}.toml").read_text()
    for step in (0.1, 1.0):
        (d / f"fmu_{step}.toml").write_text(text + engine_table("engine.fmu", step))
    build_steering_gear_fmu(SHIP, d / "gear.fmu")
    (d / "gear.toml").write_text(text + GEAR_TABLE)
    return d


GEAR_TABLE = """
[[components]]
slot = "steering_gear"
model = "vessel_gym.fmi.component:FmuSteeringGear"
replace = true
[components.params]
path = "gear.fmu"
step_s = 0.1
inputs = { rudder_angle = "rudder_angle", rudder_order = { name = "rudder_order", unit = "rad" } }
outputs = { rudder_rate = "rudder_rate" }
"""


@pytest.fixture
def code_allowed():
    allow_code()
    yield
    allow_code(False)


def child_env() -> dict:
    return {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}


@pytest.mark.slow
def test_fmu_engine_and_gear_manoeuvre_the_ship_as_the_native_ones(engine_dir):
    ships = [
        SHIP,
        str(engine_dir / "fmu_0.1.toml"),
        str(engine_dir / "fmu_1.0.toml"),
        str(engine_dir / "gear.toml"),
    ]
    proc = subprocess.run(
        [sys.executable, str(CHILD), *ships], capture_output=True, text=True, timeout=900, env=child_env()
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    res = json.loads(proc.stdout)
    native, fmu01, fmu1, gear = (res[s] for s in ships)
    L = native["turning_circle"]["L_m"]
    U0 = native["turning_circle"]["speed_kn"] * 1852.0 / 3600.0  # m/s
    # turning circle: the engine holds the approach's speed order; the torque lag of the hold is invisible
    for fmu in (fmu01, fmu1):
        for key in ("advance_L", "transfer_L", "tactical_diameter_L", "steady_diameter_L"):
            assert fmu["turning_circle"][key] == pytest.approx(native["turning_circle"][key], abs=1e-4)
        assert fmu["turning_circle"]["time_to_90_s"] == pytest.approx(
            native["turning_circle"]["time_to_90_s"], abs=0.01
        )
    # crash stop (the reversing sequence: fuel off, gear shift, air braking, astern): the zero-order hold lags
    # the drive torque by H/2 on average, so the reach may move by at most the approach speed times H/2
    for fmu, H in ((fmu01, 0.1), (fmu1, 1.0)):
        d_reach = abs(fmu["stopping"]["track_reach_m"] - native["stopping"]["track_reach_m"])
        assert d_reach < U0 * H / 2.0
        assert abs(fmu["stopping"]["time_s"] - native["stopping"]["time_s"]) < H
    # the steering gear's FMU (rate held over 0.1 s, gear time constant 0.5 s): the rudder moves as the
    # native gear's exact solution to within the hold's lag
    for key in ("advance_L", "transfer_L", "tactical_diameter_L"):
        assert gear["turning_circle"][key] == pytest.approx(native["turning_circle"][key], abs=1e-4)
    assert gear["zigzag"]["overshoot_deg"] == pytest.approx(native["zigzag"]["overshoot_deg"], abs=0.01)
    assert fmu01["zigzag"]["overshoot_deg"] == pytest.approx(native["zigzag"]["overshoot_deg"], abs=0.01)
    # at the trials' own step the stop is the native one to a thousandth of a ship length
    assert fmu01["stopping"]["track_reach_m"] == pytest.approx(
        native["stopping"]["track_reach_m"], abs=1e-3 * L
    )


def _rewrite(src: Path, dst: Path, edit) -> None:
    """Copy the FMU ``src`` to ``dst`` with ``edit(name, data) -> data | None`` (None drops the member)."""
    buf = io.BytesIO()
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(buf, "w") as zout:
        for item in zin.infolist():
            data = edit(item.filename, zin.read(item.filename))
            if data is not None:
                zout.writestr(item, data)
    dst.write_bytes(buf.getvalue())


def _model_exchange(name: str, data: bytes) -> bytes:
    if name != "modelDescription.xml":
        return data
    text = data.decode()
    start = text.index("<CoSimulation")
    end = text.index("/>", start) + 2
    return (text[:start] + '<ModelExchange modelIdentifier="VesselGymEngine" />' + text[end:]).encode()


@pytest.mark.parametrize(
    "case, changes, words",
    [
        ("missing", {"outputs": '{ shaft_torque = "Q_brake" }'}, ["engine.fmu", "'Q_brake'", "no variable"]),
        (
            "causality",
            {"outputs": '{ shaft_torque = "rev_order" }'},
            ["engine.fmu", "'rev_order'", "causality input"],
        ),
        (
            "unit",
            {"inputs": '{ shaft_speed = { name = "shaft_speed", unit = "rpm" }, rev_order = "rev_order" }'},
            ["engine.fmu", "'shaft_speed'", "'rpm'"],
        ),
        ("hold", {"hold_torque": '"shaft_torque"'}, ["engine.fmu", "'shaft_torque'", "not parameter"]),
        ("step", {"step_s": "-1.0"}, ["engine.fmu", "step_s"]),
        ("me", {}, ["me.fmu", "model-exchange"]),
        ("platform", {}, ["platform.fmu", "no binary for this platform", "win64"]),
        ("nofile", {"path": '"nothere.fmu"'}, ["nothere.fmu", "no such FMU"]),
    ],
)
def test_bad_fmu_is_one_line_exit_2(engine_dir, tmp_path, code_allowed, capsys, case, changes, words):
    fmu = engine_dir / "engine.fmu"
    name = "engine.fmu"
    if case == "me":
        name = "me.fmu"
        _rewrite(fmu, tmp_path / name, _model_exchange)
    elif case == "platform":
        name = "platform.fmu"
        _rewrite(fmu, tmp_path / name, lambda n, d: None if n.startswith("binaries/linux64/") else d)
    else:
        (tmp_path / name).write_bytes(fmu.read_bytes())
    ship = tmp_path / "bad.toml"
    ship.write_text((SHIP_DIR / f"{SHIP}.toml").read_text() + engine_table(name, 0.1, **changes))
    assert main(["manoeuvre", "turning-circle", str(ship)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    for w in words:
        assert w in err, err


def test_fmu_engine_needs_consent(engine_dir, capsys):
    allow_code(False)
    assert main(["manoeuvre", "turning-circle", str(engine_dir / "fmu_0.1.toml")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--allow-code" in err and "vessel_gym.fmi.component" in err


@pytest.mark.slow
def test_failing_do_step_is_one_line_exit_2(engine_dir, tmp_path):
    """An FMU whose doStep fails (here: an internal step of 0 s) stops the trial with one line, exit 2."""
    (tmp_path / "engine.fmu").write_bytes((engine_dir / "engine.fmu").read_bytes())
    ship = tmp_path / "stepfail.toml"
    ship.write_text(
        (SHIP_DIR / f"{SHIP}.toml").read_text() + engine_table("engine.fmu", 0.1, start="{ max_step = 0.0 }")
    )
    proc = subprocess.run(
        [sys.executable, "-m", "vessel_gym.cli", "manoeuvre", "turning-circle", str(ship), "--allow-code"],
        capture_output=True,
        text=True,
        timeout=600,
        env=child_env(),
    )
    assert proc.returncode == 2, proc.stderr[-2000:]
    err = proc.stderr.strip()
    assert len(err.splitlines()) == 1 and "engine.fmu" in err and "doStep" in err, err
    assert "max_step 0 s" in err  # the FMU's own logged reason, passed on


BATCH_CHILD = """
import json, sys
import numpy as np, gymnasium as gym
import vessel_gym  # noqa: F401  (registers the environments)
from vessel_gym.physics.components import allow_code
from vessel_gym.physics.simulation import Simulation

allow_code()
fmu_ship, native_ship = sys.argv[1], "kvlcc2"
out = {}
# one simulation of three ships: three FMU instances; vessel 1 is reset half-way and starts its FMU again
sims = {name: Simulation(name, n=3, dt=0.1) for name in (native_ship, fmu_ship)}
for name, sim in sims.items():
    sim.reset()
    sim.set_helm(rudder_order_rad=np.array([0.0, 0.3, -0.6]), rev_order=sim.rev_order * np.array([1.0, 0.5, -1.0]))
    sim.advance(20.0)
    sim.reset(k=np.array([1]))
    sim.set_helm(rudder_order_rad=np.array([0.0, 0.3, -0.6]), rev_order=sim.rev_order * np.array([1.0, 0.5, 1.0]))
    sim.advance(10.0)
    out[name] = sim.state.tolist()
out["instances"] = sum(1 for f in sims[fmu_ship].components[0]._instances if f is not None)
# the native vector environment (a batch of 3 in one simulation, physics step 0.25 s)
obs = {}
for name in (native_ship, fmu_ship.replace("fmu_0.1", "fmu_0.05")):
    env = gym.make_vec("vessel_gym/ZigZag-v1", num_envs=3, ship=name)
    env.reset(seed=3)
    rng = np.random.default_rng(0)
    rows = []
    for _ in range(60):
        o, *_ = env.step(rng.uniform(-1, 1, size=env.action_space.shape).astype(env.action_space.dtype))
        rows.append(o.tolist())
    obs[name] = rows
out["env"] = list(obs.values())
print(json.dumps(out))
"""


@pytest.mark.slow
def test_fmu_engine_in_a_batch_and_a_vector_env(engine_dir):
    """One FMU instance per vessel; a partial reset starts that vessel's instance again, steady; the vector
    environment (physics step 0.25 s, FMU step 0.05 s: five FMU steps per exchange) sees the native engine."""
    import numpy as np

    text = (SHIP_DIR / f"{SHIP}.toml").read_text()
    (engine_dir / "fmu_0.05.toml").write_text(text + engine_table("engine.fmu", 0.05))
    fmu_ship = str(engine_dir / "fmu_0.1.toml")
    proc = subprocess.run(
        [sys.executable, "-c", BATCH_CHILD, fmu_ship],
        capture_output=True,
        text=True,
        timeout=900,
        env=child_env(),
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    res = json.loads(proc.stdout)
    assert res["instances"] == 3
    native, fmu = np.array(res[SHIP]), np.array(res[fmu_ship])
    L = load_ship(SHIP).particulars.L_m
    assert np.max(np.abs(fmu[:, lo.X_N] - native[:, lo.X_N])) < 1e-4 * L  # ahead, half, astern
    assert np.max(np.abs(fmu[:, lo.X_REV] - native[:, lo.X_REV])) < 1e-3  # rev/s
    env_native, env_fmu = (np.array(o) for o in res["env"])
    assert np.max(np.abs(env_fmu - env_native)) < 1e-4
