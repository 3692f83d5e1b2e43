"""Components that own states: a user's engine (with its governor) and a user's steering gear replace the
built-ins, their states integrated with the vessel's; replacement stays checked (docs/components.md)."""

from __future__ import annotations

import dataclasses
import math
import re
import sys
import types
from pathlib import Path

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import Engine, State, SteeringGear
from vessel_gym.physics.components.compose import builtin_slots
from vessel_gym.physics.params import ENGINE, STEERING_GEAR, TRANSMISSION
from vessel_gym.physics.propulsion import clutch_direction, engine_torque, governor
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.steady import fuel_index_for


class BuiltinEngineInPython(Engine):
    """The built-in clutch engine (torque map, PI governor with anti-windup) as a user's engine: its governor
    integrator is the component's own state. The equations are the compiled ones, called per vessel."""

    states = (State("governor", "-", 0.0, "PI integrator, fuel index"),)

    def __init__(self, ship, P):
        super().__init__(ship)
        self.P = P
        eng, tr = ship.engine, ship.transmission
        self.I_e = tr.gear_ratio**2 * eng.inertia_kgm2

    def shaft_inertia_kgm2(self):
        return self.I_e

    def _each(self, sim, x, s):
        for b in range(x.shape[0]):
            yield b, governor(self.P, x[b, lo.X_REV], s[b, 0], sim.rev_order[b])

    def rates(self, sim, x, s):
        return np.array([[di] for _, (_f, di, _s, _ne) in self._each(sim, x, s)])

    def shaft_torque(self, sim, x, s):
        P, Q = self.P, np.zeros(x.shape[0])
        for b, (fuel, _di, sgn, n_e) in self._each(sim, x, s):
            if sgn != 0.0:
                Q[b] = sgn * P[TRANSMISSION.efficiency] * P[TRANSMISSION.gear_ratio] * engine_torque(P, n_e, fuel)
                if sgn < 0.0:
                    Q[b] *= P[ENGINE.astern_torque_ratio]
        return Q

    def steady_states(self, sim, x, Q_hold):
        P = self.P  # the fuel index whose engine torque holds the shaft, as the built-in reset solves it
        Q_e = Q_hold / (P[TRANSMISSION.efficiency] * P[TRANSMISSION.gear_ratio])
        return np.array([[fuel_index_for(P, P[TRANSMISSION.gear_ratio] * x[b, lo.X_REV], Q_e[b])] for b in range(len(x))])


def test_user_engine_reimplementing_the_builtin_reproduces_its_crash_stop():
    """Plumbing check: the built-in engine's own equations, run as a user's engine (governor state owned by the
    component, drive torque into the shaft, inertia brought along), give the built-in's trajectory to
    round-off through an ahead run and a crash stop (order reversed: governor saturation, clutch astern)."""
    ship = load_ship("kvlcc2_l7")
    ref = Simulation(ship, dt=0.05)
    ref.reset()
    comp = BuiltinEngineInPython(ship, ref.Ps[0])
    sim = Simulation(ship, dt=0.05, components=[comp], replace=["engine"])
    assert sim.Ps[0, TRANSMISSION.I_shaft] == ref.Ps[0, TRANSMISSION.I_shaft] and sim.Ps[0, ENGINE.by_component] == 1.0
    assert "engine" not in builtin_slots(sim.Ps[0]) and "governor" not in builtin_slots(sim.Ps[0])
    sim.reset()
    assert sim.component_state("BuiltinEngineInPython.governor")[0] == ref.state[0, lo.X_GOV]
    for s in (ref, sim):
        s.set_helm(rudder_order_rad=0.1)
        s.advance(20.0)
        s.set_helm(rev_order=-s.rev_order[0])
        s.advance(40.0)
    assert sim.state[0, lo.X_GOV] == 0.0  # the built-in governor left with the engine
    np.testing.assert_allclose(sim.component_states[0, 0], ref.state[0, lo.X_GOV], rtol=1e-9, atol=1e-12)
    cols = [lo.X_U, lo.X_V, lo.X_R, lo.X_N, lo.X_E, lo.X_PSI, lo.X_DELTA, lo.X_REV]
    np.testing.assert_allclose(sim.state[0, cols], ref.state[0, cols], rtol=1e-9, atol=1e-9)
    assert ref.rev[0] < 0.0  # the crash stop got the shaft turning astern
    assert clutch_direction(ref.Ps[0], ref.rev_order[0]) == -1.0


class RateGear(SteeringGear):
    """A steering gear slewing at a constant rate towards the order (a hydraulic gear on its rate limit)."""

    def __init__(self, rate_rad_s):
        super().__init__()
        self.rate = rate_rad_s

    def rudder_rate(self, sim, x, s):
        e = sim.rudder_order - x[:, lo.X_DELTA]
        return np.clip(e / 0.05, -self.rate, self.rate)  # within 0.05 s of slewing from the order


def test_user_steering_gear_drives_the_rudder_angle():
    """SOLAS II-1/29.3.2: 35 deg to one side to 30 deg the other in 28 s is 65/28 = 2.32 deg/s. A gear slewing
    at that rate from 0 reaches 20 deg after 20 / 2.32 = 8.62 s; RK4 integrates a constant rate exactly."""
    rate = math.radians(65.0 / 28.0)
    sim = Simulation("kvlcc2", dt=0.1, components=[RateGear(rate)], replace=["steering_gear"])
    assert sim.Ps[0, STEERING_GEAR.by_component] == 1.0 and "steering_gear" not in builtin_slots(sim.Ps[0])
    sim.reset()
    sim.set_helm(rudder_order_rad=math.radians(20.0))
    sim.advance(5.0)
    assert sim.rudder[0] == pytest.approx(5.0 * rate, rel=1e-12)
    sim.advance(5.0)
    assert sim.rudder[0] == pytest.approx(math.radians(20.0), abs=1e-9)  # held at the order
    assert sim.r[0] > 0.0  # the ship answers its rudder


def test_user_steering_gear_first_order_matches_the_builtin_exact_solution():
    """The built-in gear (rate-limited first order, solved exactly over a step) as a user's gear integrated by
    RK4: the turn agrees to the integration error of RK4 at dt = 0.1 s on a 0.1 s lag (kvlcc2_l7)."""
    ship = load_ship("kvlcc2_l7")
    sg = ship.steering_gear

    class FirstOrderGear(SteeringGear):
        def rudder_rate(self, sim, x, s):
            dmax = math.radians(sg.max_angle_deg)
            rmax = math.radians(sg.max_rate_deg_s)
            dc = np.clip(sim.rudder_order, -dmax, dmax)
            return np.clip((dc - x[:, lo.X_DELTA]) / sg.time_constant_s, -rmax, rmax)

    runs = []
    for kw in ({}, {"components": [FirstOrderGear()], "replace": ["steering_gear"]}):
        sim = Simulation(ship, dt=0.02, **kw)
        sim.reset()
        sim.set_helm(rudder_order_rad=math.radians(35.0))
        sim.advance(30.0)
        runs.append(sim.state[0].copy())
    np.testing.assert_allclose(runs[1][lo.X_DELTA], runs[0][lo.X_DELTA], rtol=1e-6)
    np.testing.assert_allclose(runs[1][lo.X_PSI], runs[0][lo.X_PSI], rtol=1e-4)


class NoInertiaEngine(Engine):
    def shaft_torque(self, sim, x, s):
        return np.zeros(x.shape[0])

    shaft_inertia_kgm2 = None  # not callable


class Gear(SteeringGear):
    def rudder_rate(self, sim, x, s):
        return np.zeros(x.shape[0])


class Eng(Engine):
    def shaft_torque(self, sim, x, s):
        return np.zeros(x.shape[0])

    def shaft_inertia_kgm2(self):
        return 0.0


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"components": [Eng()]}, r"Eng fills slot 'engine', which the ship's engine fills; replace it"),
        ({"replace": ["engine"]}, r"replace=\['engine'\] needs an Engine component"),
        ({"replace": ["steering_gear"]}, r"replace=\['steering_gear'\] needs a SteeringGear component"),
        ({"components": [Gear()]}, r"fills slot 'steering_gear', which the ship's steering_gear fills"),
        ({"components": [Gear(), Gear()], "replace": ["steering_gear"]}, r"slot 'steering_gear' is filled twice"),
        ({"components": [NoInertiaEngine()], "replace": ["engine"]}, r"needs shaft_inertia_kgm2\(\)"),
        ({"replace": ["governor"]}, r"'governor' is not yet supported: the governor is part of the engine"),
    ],
)
def test_stateful_replacement_is_checked(kwargs, message):
    with pytest.raises(ValueError, match=message) as err:
        Simulation("kvlcc2", **kwargs)
    assert "\n" not in str(err.value)


def test_engine_on_a_ship_without_a_propeller_is_refused():
    glider = dataclasses.replace(load_ship("mariner"), propeller=None)  # its rudder is in the hull's terms
    with pytest.raises(ValueError, match="no propeller"):
        Simulation(glider, components=[Eng()], replace=["engine"])
    with pytest.raises(ValueError, match="no propeller shaft for an engine"):
        Simulation(glider, components=[Eng()])


def test_states_must_be_declared_as_state_entries():
    class Bad(Eng):
        states = ("governor",)

    with pytest.raises(ValueError, match="states must be State"):
        Simulation("kvlcc2", components=[Bad()], replace=["engine"])


def test_non_finite_component_state_stops_the_vessel_only():
    class Blows(Eng):
        states = (State("x", "-", 1.0),)

        def rates(self, sim, x, s):
            return np.where(np.arange(x.shape[0])[:, None] == 1, np.inf, 0.0) * np.ones_like(s)

    sim = Simulation("kvlcc2", n=3, components=[Blows()], replace=["engine"])
    sim.reset()
    assert sim.step(2) == 2
    assert not sim.alive[1] and sim.divergence(1) == "the state became non-finite"
    assert np.all(np.isfinite(sim.component_states))


def test_stateful_components_are_called_once_per_stage_for_the_whole_batch():
    """O(N): an engine's torque and states and a steering gear's rate, once per RK4 stage for all vessels."""
    calls = {"shaft_torque": 0, "rates": 0, "rudder_rate": 0}

    class CountedEngine(Eng):
        states = (State("lag", "-", 0.0),)

        def shaft_torque(self, sim, x, s):
            calls["shaft_torque"] += 1
            assert x.shape == (256, lo.NX) and s.shape == (256, 1)
            return np.zeros(x.shape[0])

        def rates(self, sim, x, s):
            calls["rates"] += 1
            return -s

    class CountedGear(Gear):
        def rudder_rate(self, sim, x, s):
            calls["rudder_rate"] += 1
            return np.zeros(x.shape[0])

    sim = Simulation(
        "kvlcc2", n=256, components=[CountedEngine(), CountedGear()], replace=["engine", "steering_gear"]
    )
    sim.reset()
    calls.update({k: 0 for k in calls})
    sim.step(3)
    assert calls == {"shaft_torque": 12, "rates": 12, "rudder_rate": 12}


def _docs_engine_source() -> str:
    """The source of the user's engine of docs/components.md ("Example: your own engine model")."""
    doc = (Path(__file__).resolve().parents[2] / "docs" / "components.md").read_text()
    return re.search(r"<!-- file: my_engine.py -->\n```python\n(.*?)\n```", doc, re.S).group(1) + "\n"


def _docs_engine():
    """The user's engine of docs/components.md, as a module."""
    src = _docs_engine_source()
    module = types.ModuleType("my_engine")
    sys.modules["my_engine"] = module  # dataclasses look their module up while decorating
    try:
        exec(compile(src, "docs/components.md my_engine.py", "exec"), module.__dict__)
    finally:
        del sys.modules["my_engine"]
    return module


def test_docs_engine_holds_its_steady_approach_and_its_governor_removes_the_speed_error():
    """Two properties of the model, not of its numbers: the reset's steady run stays steady (the states
    steady_states solves are an equilibrium of the shaft and the governor), and a PI governor's integral action
    leaves no steady speed error after an order change within the engine's torque."""
    m = _docs_engine()
    ship = load_ship("kvlcc2")
    p = m.LaggedDieselParams(rated_power_kW=105000.0, rated_rpm=115.0, inertia_kgm2=1.0e6, tau_s=3.0)
    sim = Simulation(ship, dt=0.2, components=[m.LaggedDiesel(ship, p)], replace=["engine"])
    sim.reset()
    start = sim.state.copy()
    sim.advance(100.0)
    np.testing.assert_allclose(sim.state[0, [lo.X_U, lo.X_REV]], start[0, [lo.X_U, lo.X_REV]], rtol=1e-9)
    assert sim.component_state("LaggedDiesel.torque")[0] < 1.0  # the order is within the engine's torque
    order = 1.03 * sim.rev_order[0]
    sim.set_helm(rev_order=order)
    sim.advance(600.0)
    assert sim.rev[0] == pytest.approx(order, rel=1e-4)
    assert sim.engine(0)["torque_Nm"] > 0.0 and math.isnan(sim.engine(0)["fuel_index"])


def test_cli_stopping_runs_a_ship_file_engine(ship_file, tmp_path, monkeypatch, capsys):
    """`vessel-gym manoeuvre stopping` with the docs' engine named in a ship file: the crash stop reverses the
    user's engine (the clutch by the order's sign), and the stop differs from the built-in engine's."""
    import json

    from vessel_gym.cli import main

    src = _docs_engine_source()
    (tmp_path / "my_engine.py").write_text(src)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("VESSEL_GYM_ALLOW_CODE", "1")  # these ship files name the test's own modules
    table = (
        '\n[[components]]\nslot = "engine"\nmodel = "my_engine:LaggedDiesel"\nreplace = true\n'
        "params = { rated_power_kW = 0.40, rated_rpm = 1200.0, inertia_kgm2 = 0.02, tau_s = 0.3 }\n"
    )
    results = []
    try:
        for path in (ship_file("kvlcc2_l7", filename="builtin.toml"), ship_file("kvlcc2_l7", lambda t: t + table)):
            assert main(["manoeuvre", "stopping", str(path), "--json"]) == 0
            results.append(json.loads(capsys.readouterr().out))
    finally:
        sys.modules.pop("my_engine", None)
    assert results[0] != results[1]
    assert all(math.isfinite(v) for v in results[1].values() if isinstance(v, float))


def test_added_component_with_a_state_of_its_own():
    """A bow thruster spinning up with a first-order lag, T(t) = T_max (1 - exp(-t / tau)) from rest: its own
    state is integrated by RK4 (its error on exp(-t/tau) is (dt/tau)^5/120 = 2.6e-9 per step at dt = tau/20, 1.1e-8
    after 50 steps: within 1e-7) and its force, read through named_forces, follows it."""
    tau, T_max = 4.0, 1.0e5  # s, N

    class SpinningThruster:
        slot = "extra"
        states = (State("spin", "-", 0.0, "thrust / full thrust"),)

        def forces(self, sim, x, s):
            Y = T_max * s[:, 0]
            return np.column_stack([np.zeros_like(Y), Y, 100.0 * Y])

        def rates(self, sim, x, s):
            return (1.0 - s) / tau

    sim = Simulation("kvlcc2", n=2, dt=0.2, components=[SpinningThruster()])
    sim.reset()
    assert sim.component_state_names == ("SpinningThruster.spin",)
    sim.advance(10.0)
    expected = 1.0 - math.exp(-10.0 / tau)
    np.testing.assert_allclose(sim.component_state("SpinningThruster.spin"), expected, rtol=1e-7)
    Y = sim.named_forces()["SpinningThruster"].Y
    np.testing.assert_array_equal(Y, T_max * sim.component_state("SpinningThruster.spin"))
    assert sim.r[0] > 0.0  # pushed the bow to starboard
