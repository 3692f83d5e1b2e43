"""The lane drivers (physics.lanes): the same equations recompiled for vessels in structure-of-arrays form.

"exact" math gives the scalar drivers' results to the bit (it may replace them call by call); "vector" math
(branch-free exp, sin/cos, atan2) stays within 1e-12 relative of them per step. The kinds of batch are
compiled on first use (about a minute and a half of CPU each), so the comparisons of whole drivers are slow
tests; the recompilation, the transcendental functions and the choice are checked here without them.
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from vessel_gym.physics import hull, steering
from vessel_gym.physics import layout as lo
from vessel_gym.physics.drivers import _LaneChoice
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.integrate import RK4, drivers_for
from vessel_gym.physics.lanes import LANE_BLOCK, lane_drivers_for, recompile, vatan2, vexp, vsincos
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.units import DEG

WEATHER = dict(wind_speed_m_s=12.0, wind_from_deg=60.0, Hs_m=2.5, Tp_s=9.0, wave_from_deg=120.0)


def _ulps(got: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.abs(got - ref) / np.spacing(np.maximum(np.abs(ref), 1e-300))))


def test_branch_free_transcendentals_are_within_one_ulp_of_libm():
    # Cephes' double-precision approximations (Moshier 1989) claim < 1 ulp peak error over these ranges
    rng = np.random.default_rng(3)
    x = rng.uniform(-30.0, 5.0, 2000)
    assert _ulps(np.array([vexp(v) for v in x]), np.exp(x)) <= 1.0
    a = rng.uniform(-100.0, 100.0, 2000)  # headings of many turns, rudder and wind angles
    sc = np.array([vsincos(v) for v in a])
    assert np.max(np.abs(sc[:, 0] - np.sin(a))) <= 2.3e-16 and np.max(np.abs(sc[:, 1] - np.cos(a))) <= 2.3e-16
    y, xx = rng.normal(0.0, 3.0, 2000), rng.normal(0.0, 3.0, 2000)
    assert _ulps(np.array([vatan2(p, q) for p, q in zip(y, xx)]), np.arctan2(y, xx)) <= 1.0
    # the axes and signed zeros exactly as libm (a ship at rest, or moving straight astern, has v = +-0)
    for p in (0.0, -0.0, 1.0, -1.0):
        for q in (0.0, -0.0, 1.0, -1.0):
            got, ref = vatan2(p, q), math.atan2(p, q)
            assert got == ref and math.copysign(1.0, got) == math.copysign(1.0, ref), (p, q)
    for v in (0.0, -0.0):
        assert math.copysign(1.0, vsincos(v)[0]) == math.copysign(1.0, v) and vsincos(v) == (v, 1.0)


def test_exact_recompilation_gives_the_compiled_functions_results_to_the_bit():
    P = Simulation("kvlcc2").Ps[0]
    rng = np.random.default_rng(5)
    gear = recompile(steering.steering_gear_angle, "exact")
    mmg = recompile(hull.mmg_hull_forces, "exact")
    mmg_v = recompile(hull.mmg_hull_forces, "vector")
    for _ in range(200):
        d0, dc, t = rng.uniform(-0.6, 0.6), rng.uniform(-0.8, 0.8), rng.uniform(0.0, 30.0)
        assert gear(P, d0, dc, t) == steering.steering_gear_angle(P, d0, dc, t)
        u, v, r = rng.uniform(-2.0, 8.0), rng.uniform(-3.0, 3.0), rng.uniform(-0.02, 0.02)
        ref = hull.mmg_hull_forces(P, u, v, r, 0)
        assert mmg(P, u, v, r, 0) == ref
        assert np.allclose(mmg_v(P, u, v, r, 0), ref, rtol=1e-13, atol=0.0)
    with pytest.raises(ValueError, match="math flavour"):
        recompile(hull.mmg_hull_forces, "fast")


def test_the_lane_choice():
    assert _LaneChoice("vector").pick(False) == 1 and _LaneChoice("vector").pick(True) == 1
    assert _LaneChoice(None).pick(True) == -1
    exact = _LaneChoice("exact")
    assert exact.pick(False) == -1  # small calls keep the scalar fast path
    picks = []
    for _ in range(40):  # the lanes 2x faster: both are timed first, then the lanes are chosen
        lane = exact.pick(True)
        exact.record(lane, 1.0 if lane == 0 else 0.5, 1024)
        picks.append(lane)
    assert set(picks[:8]) == {0, 1} and picks[-8:].count(1) >= 7
    with pytest.raises(ValueError, match="math must be one of"):
        Simulation("kvlcc2", n=2, math="fast")


def test_lane_drivers_hold_only_batches_of_one_ship():
    sim = Simulation(["kvlcc2", "mariner"], n=4, ship_index=[0, 1, 0, 1])
    assert lane_drivers_for(sim.Ps, sim.ship_index, sim.env) is None
    one = Simulation(["kvlcc2", "mariner"], n=4, ship_index=[1, 1, 1, 1], math="exact")
    assert one._lanes is lane_drivers_for(one.Ps, one.ship_index, one.env, "exact") is not None
    assert pickle.loads(pickle.dumps(one))._lanes is one._lanes  # chosen again when unpickled


# --- whole drivers (slow: each kind of batch and flavour compiles once, then loads from the kernel cache)


# the 7 m model of kvlcc2 with windage: a breeze and a tidal stream at its scale (in a full-scale gale its engine
# cannot hold the approach speed)
MODEL_WEATHER = dict(wind_speed_m_s=4.0, wind_from_deg=60.0, current_speed_m_s=0.3, current_to_deg=200.0)


def _batch(ship: str, n: int, depth_factor: float | None = None, model: bool = False) -> Simulation:
    """n vessels of ``ship`` in wind and waves (``model``: MODEL_WEATHER), rudder orders -35..35 deg, one in a
    crash stop, one at large drift; vessel 7 given a surge speed that overflows (it diverges in the first
    step) and vessel 3 dead from the start."""
    T = load_ship(ship).particulars.T_m
    env = MODEL_WEATHER if model else WEATHER
    depth = float("inf") if depth_factor is None else depth_factor * T
    sim = Simulation(ship, n=n, dt=0.2, environment=Environment(depth_m=depth, **env))
    sim.reset(heading_deg=np.linspace(0.0, 360.0, n, endpoint=False))
    sim.set_helm(rudder_order_rad=np.linspace(-35.0, 35.0, n) * DEG)
    sim.inputs[0, lo.U_REV_C] *= -1.0
    sim.state[-1, lo.X_V] = 0.6 * sim.state[-1, lo.X_U]
    sim.state[7, lo.X_U] = 1e160
    sim.alive[3] = False
    return sim


def _run(driver, sim: Simulation, nsteps: int):
    X, alive = sim.state.copy(), sim.alive.copy()
    count = driver(sim.Ps, sim.ship_index, X, sim.inputs, sim.env, sim.F_ext, sim.dt, nsteps, RK4, alive)
    return X, alive, count


SHIPS = [
    ("kvlcc2", None, False),
    ("kvlcc2_l7_windage", None, True),  # windage in wind and a current
    ("kvlcc2_l7_harbour", 1.5, True),  # shallow water, h/T = 1.5
    ("mariner", None, False),  # Abkowitz hull, rudder in the hull derivatives
    ("container", None, False),  # roll
]


@pytest.mark.slow
@pytest.mark.parametrize("ship, depth_factor, model", SHIPS)
def test_exact_lane_drivers_equal_the_scalar_drivers_bit_for_bit(ship, depth_factor, model):
    n = LANE_BLOCK + 44  # a full block and a partial one
    sim = _batch(ship, n, depth_factor, model)
    scalar = drivers_for(sim.Ps, sim.env)
    lanes = lane_drivers_for(sim.Ps, sim.ship_index, sim.env, "exact")
    Xs, alive_s, count_s = _run(scalar[0], sim, 300)
    for lane_driver in lanes:  # serial and threaded
        Xl, alive_l, count_l = _run(lane_driver, sim, 300)
        assert count_l == count_s and np.array_equal(alive_l, alive_s)
        assert np.array_equal(Xl, Xs)
    assert not alive_s[7] and np.isfinite(Xs).all()  # diverged, kept its last finite state
    assert not alive_s[3] and np.array_equal(Xs[3], sim.state[3])  # dead vessels are not integrated
    assert alive_s.sum() >= n - 2 and not np.array_equal(Xs, sim.state)


@pytest.mark.slow
def test_a_simulation_with_exact_math_steps_as_the_scalar_one():
    a, b = _batch("kvlcc2", 200), _batch("kvlcc2", 200)
    b = Simulation("kvlcc2", n=200, dt=0.2, environment=a.environments[0], math="exact")
    b.state[:], b.inputs[:], b.alive[:] = a.state, a.inputs, a.alive
    for _ in range(12):  # the per-call choice tries the lane and the scalar drivers, serial and threaded
        a.step(10)
        b.step(10)
    assert np.array_equal(a.state, b.state) and np.array_equal(a.alive, b.alive)
    assert b._lane_choice.kind.warm == [True, True]  # both kinds of driver ran


def _relative(got: np.ndarray, ref: np.ndarray) -> float:
    """Largest difference per state column over the column's largest magnitude."""
    scale = np.maximum(np.abs(ref).max(axis=0), 1e-300)
    return float((np.abs(got - ref) / scale).max())


@pytest.mark.slow
def test_vector_lane_drivers_stay_within_1e12_of_the_scalar_drivers():
    sim = _batch("kvlcc2", 300)
    scalar = drivers_for(sim.Ps, sim.env)[0]
    vector = lane_drivers_for(sim.Ps, sim.ship_index, sim.env, "vector")[0]
    Xs, alive_s, _ = _run(scalar, sim, 1)
    Xv, alive_v, _ = _run(vector, sim, 1)
    assert np.array_equal(alive_v, alive_s)
    assert _relative(Xv, Xs) <= 1e-12  # one step: the branch-free functions' last bit through one RK4 step
    # a 60 s manoeuvre (300 steps): every vessel turning or stopping is a stable motion, so step differences
    # of ~1e-14..1e-13 add up rather than grow: 300 of them stay below 3e-11; 1e-9 leaves a margin of 30
    Xs, alive_s, _ = _run(scalar, sim, 300)
    Xv, alive_v, _ = _run(vector, sim, 300)
    assert np.array_equal(alive_v, alive_s)
    assert _relative(Xv[alive_s], Xs[alive_s]) <= 1e-9
