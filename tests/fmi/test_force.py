"""An FMU as a force component (vessel_gym.fmi.component:FmuForce): a speed-dependent damping force built
with pythonfmu in the test, against the same force written as a plain Python component."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pythonfmu")
pytest.importorskip("fmpy")

from vessel_gym.cli import main  # noqa: E402
from vessel_gym.physics import layout as lo  # noqa: E402
from vessel_gym.physics.components import State, allow_code  # noqa: E402
from vessel_gym.physics.shipfile import SHIP_DIR, load_ship  # noqa: E402
from vessel_gym.physics.simulation import Simulation  # noqa: E402

SHIP = "kvlcc2"
#: the force's coefficients: a fin's sway and yaw damping growing with speed, and its surge drag in a turn
C_X = 2.0e5  # N s^2/m^2: X = C_X v r L_REF
C_Y = 1.0e5  # N s^2/m^2: Y = -C_Y u v
C_N = 1.2e9  # N m s^2/m: N = -C_N u r
L_REF = 100.0  # m

SLAVE = f'''
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real
from pythonfmu.enums import Fmi2Initial


class DampingFin(Fmi2Slave):
    """X = C_X v r L, Y = -C_Y u v, N = -C_N u r; forces in kN, moment in kN.m (direct feedthrough)."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.u = self.v = self.r = 0.0
        for name in ("u", "v", "r"):
            self.register_variable(Real(name, causality=Fmi2Causality.input, variability=Fmi2Variability.continuous))
        for name, getter in (("Fx", self._x), ("Fy", self._y), ("Mz", self._n)):
            self.register_variable(Real(name, causality=Fmi2Causality.output, variability=Fmi2Variability.continuous,
                                        initial=Fmi2Initial.calculated, getter=getter))

    def _x(self):
        return {C_X!r} * self.v * self.r * {L_REF!r} / 1e3

    def _y(self):
        return -{C_Y!r} * self.u * self.v / 1e3

    def _n(self):
        return -{C_N!r} * self.u * self.r / 1e3

    def do_step(self, current_time, step_size):
        return True
'''


TUG_SLAVE = """
import math

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real
from pythonfmu.enums import Fmi2Initial


class EastTug(Fmi2Slave):
    \"\"\"A tug pushing the ship east with 300 kN from t = 20 s: body forces from the heading (in degrees).\"\"\"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.hdg = self.time = 0.0
        for name in ("hdg", "time"):
            self.register_variable(Real(name, causality=Fmi2Causality.input, variability=Fmi2Variability.continuous))
        for name, getter in (("Fx", self._x), ("Fy", self._y), ("Mz", lambda: 0.0)):
            self.register_variable(Real(name, causality=Fmi2Causality.output, variability=Fmi2Variability.continuous,
                                        initial=Fmi2Initial.calculated, getter=getter))

    def _push(self):
        return 300e3 if self.time >= 20.0 - 1e-9 else 0.0

    def _x(self):
        return self._push() * math.sin(math.radians(self.hdg))

    def _y(self):
        return self._push() * math.cos(math.radians(self.hdg))

    def do_step(self, current_time, step_size):
        return True
"""


class EastTug:
    """The same tug in plain Python, with a clock of its own (s since the reset) to know when to push."""

    slot = "extra"
    states = (State("clock", "s", 0.0, "time since the reset"),)

    def rates(self, sim, x, s):
        return np.ones((x.shape[0], 1))

    def forces(self, sim, x, s):
        F = np.where(s[:, 0] >= 20.0 - 1e-9, 300e3, 0.0)
        psi = x[:, lo.X_PSI]
        return np.column_stack([F * np.sin(psi), F * np.cos(psi), np.zeros_like(F)])


def test_fmu_tug_maps_heading_and_time(tmp_path, code_allowed):
    """Inputs ``heading`` (the FMU's in degrees) and ``t``: an earth-fixed push from t = 20 s, as in Python."""
    from pythonfmu.builder import FmuBuilder

    script = tmp_path / "script" / "east_tug.py"
    script.parent.mkdir()
    script.write_text(TUG_SLAVE)
    FmuBuilder.build_FMU(script, dest=tmp_path / "tug.fmu")
    (tmp_path / "tug.toml").write_text(
        (SHIP_DIR / f"{SHIP}.toml").read_text()
        + """
[[components]]
slot = "extra"
model = "vessel_gym.fmi.component:FmuForce"
[components.params]
path = "tug.fmu"
step_s = 0.1
inputs = { heading = { name = "hdg", unit = "deg" }, t = "time" }
outputs = { X = "Fx", Y = "Fy", N = { name = "Mz", unit = "N.m" } }
"""
    )
    L = load_ship(SHIP).particulars.L_m

    def run(sim):
        sim.reset()
        sim.advance(200.0)
        return sim.state[0].copy()

    fmu = run(Simulation(str(tmp_path / "tug.toml"), dt=0.1))
    py = run(Simulation(SHIP, dt=0.1, components=[EastTug()]))
    bare = run(Simulation(SHIP, dt=0.1))
    # the push moves the ship (its hull answers the sway with a yaw that takes it off the line: several metres)
    moved = np.hypot(py[lo.X_N] - bare[lo.X_N], py[lo.X_E] - bare[lo.X_E])
    assert moved > 1.0
    # the push starts at the same step (t = 20 s is a communication point); the heading is held over H
    d = np.hypot(fmu[lo.X_N] - py[lo.X_N], fmu[lo.X_E] - py[lo.X_E])
    assert d < 1e-3 * L and d < 0.01 * moved, (d, moved)


class DampingFin:
    """The same force in plain Python, evaluated at every RK4 stage."""

    slot = "extra"

    def __init__(self, ship=None, params=None):  # the ship-file contract: cls(ship, params)
        pass

    def forces(self, sim, x):
        u, v, r = x[:, lo.X_U], x[:, lo.X_V], x[:, lo.X_R]
        return np.column_stack([C_X * v * r * L_REF, -C_Y * u * v, -C_N * u * r])


def force_table(fmu: str, step: float, outputs: str | None = None) -> str:
    outputs = outputs or (
        '{ X = { name = "Fx", unit = "kN" }, Y = { name = "Fy", unit = "kN" }, N = { name = "Mz", unit = "kN.m" } }'
    )
    return f"""
[[components]]
slot = "extra"
model = "vessel_gym.fmi.component:FmuForce"
[components.params]
path = "{fmu}"
step_s = {step!r}
inputs = {{ u = "u", v = {{ name = "v", unit = "m/s" }}, r = "r" }}
outputs = {outputs}
"""


@pytest.fixture(scope="module")
def force_dir(tmp_path_factory) -> Path:
    from pythonfmu.builder import FmuBuilder

    d = tmp_path_factory.mktemp("force")
    script = d / "script" / "damping_fin.py"
    script.parent.mkdir()
    script.write_text(SLAVE)
    FmuBuilder.build_FMU(script, dest=d / "fin.fmu")
    text = (SHIP_DIR / f"{SHIP}.toml").read_text()
    for step in (0.1, 1.0):
        (d / f"fin_{step}.toml").write_text(text + force_table("fin.fmu", step))
    return d


@pytest.fixture
def code_allowed():
    allow_code()
    yield
    allow_code(False)


def _turn(sim: Simulation) -> np.ndarray:
    sim.reset()
    sim.set_helm(rudder_order_rad=np.deg2rad(35.0))
    sim.advance(300.0)
    return sim.state[0].copy()


def test_fmu_force_turns_the_ship_as_the_python_force(force_dir, code_allowed):
    L = load_ship(SHIP).particulars.L_m
    py = _turn(Simulation(SHIP, dt=0.1, components=[DampingFin()]))
    bare = _turn(Simulation(SHIP, dt=0.1))
    d_force = np.hypot(bare[lo.X_N] - py[lo.X_N], bare[lo.X_E] - py[lo.X_E])
    # the force matters: the fin moves the ship by more than a tenth of its length over the turn
    assert d_force > 0.1 * L
    d = {}
    for H in (0.1, 1.0):
        fmu = _turn(Simulation(str(force_dir / f"fin_{H}.toml"), dt=0.1))
        d[H] = np.hypot(fmu[lo.X_N] - py[lo.X_N], fmu[lo.X_E] - py[lo.X_E])
        # the held force lags the stage-evaluated one by H/2 on average: a heading error first order in H
        assert fmu[lo.X_PSI] == pytest.approx(py[lo.X_PSI], abs=1e-3 * H / 0.1)
    # a thousandth of the ship length at the trials' step, and first order in H: ten times the step, about
    # ten times the error (a zero-order hold's error; a wrong map or a stale force would not scale so)
    assert d[0.1] < 1e-3 * L, d
    assert 5.0 < d[1.0] / d[0.1] < 20.0, d


def test_bad_force_map_is_one_line_exit_2(force_dir, tmp_path, code_allowed, capsys):
    (tmp_path / "fin.fmu").write_bytes((force_dir / "fin.fmu").read_bytes())
    ship = tmp_path / "bad.toml"
    bad = '{ X = "Fx", Y = "Fy", N = "Yaw_moment" }'
    ship.write_text((SHIP_DIR / f"{SHIP}.toml").read_text() + force_table("fin.fmu", 0.1, bad))
    assert main(["manoeuvre", "turning-circle", str(ship)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert "fin.fmu" in err and "'Yaw_moment'" in err, err


def test_fmu_force_in_a_vector_env(force_dir, code_allowed):
    """make_vec with the FMU's ship: one instance per ship of the batch; the observations are those of the
    same force in plain Python named by a ship file (physics step 0.25 s: the FMU makes five 0.05 s steps per
    exchange, its force held over the physics step)."""
    import gymnasium as gym

    from vessel_gym.fmi.component import FmuForce

    text = (SHIP_DIR / f"{SHIP}.toml").read_text()
    (force_dir / "fin_0.05.toml").write_text(text + force_table("fin.fmu", 0.05))
    (force_dir / "py.toml").write_text(
        text + '\n[[components]]\nslot = "extra"\nmodel = "tests.fmi.test_force:DampingFin"\n'
    )
    obs, instances = {}, None
    for name in (SHIP, "py.toml", "fin_0.05.toml"):
        env = gym.make_vec(
            "vessel_gym/ZigZag-v1", num_envs=3, ship=name if name == SHIP else str(force_dir / name)
        )
        env.reset(seed=3)
        rng = np.random.default_rng(0)
        rows = []
        for _ in range(200):  # 50 s
            o, *_ = env.step(rng.uniform(-1, 1, size=env.action_space.shape).astype(env.action_space.dtype))
            rows.append(o)
        obs[name] = np.array(rows)
        fmus = [c for c in env.unwrapped.sim.components if isinstance(c, FmuForce)]
        if fmus:
            instances = sum(1 for f in fmus[0]._instances if f is not None)
        env.close()
    assert instances == 3
    bare, py, fmu = obs.values()
    # the fin changes what the agent sees; the FMU's fin is the Python one's to a hundredth of that change
    assert np.abs(py - bare).max() > 1e-4
    assert np.abs(fmu - py).max() < 0.01 * np.abs(py - bare).max()
