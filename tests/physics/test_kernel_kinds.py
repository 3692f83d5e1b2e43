"""The batch drivers compiled for one kind of batch (deep or shallow water, with or without roll, with or
without a user's engine: integrate.drivers) give the general kernel's results to the bit, and refuse a batch
they were not compiled for."""

from __future__ import annotations

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.integrate import RK4, derivatives_for, drivers, run_serial
from vessel_gym.physics.linear import stable_step
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.units import DEG
from vessel_gym.physics.vessel import derivatives

# wind, a beam sea and a current: every force the kernel has is non-zero (the wave drift at speed included)
WEATHER = dict(wind_speed_m_s=12.0, wind_from_deg=60.0, Hs_m=2.5, Tp_s=9.0, wave_from_deg=120.0)


def _sim(ships, n, depth_m=float("inf"), ship_index=None):
    sim = Simulation(
        ships, n=n, ship_index=ship_index, dt=0.2, environment=Environment(depth_m=depth_m, **WEATHER)
    )
    sim.reset()
    sim.set_helm(rudder_order_rad=np.linspace(-35.0, 35.0, n) * DEG)
    sim.inputs[0, lo.U_REV_C] *= -1.0  # one crash stop: the propeller astern, the hull in sternway
    sim.state[-1, lo.X_V] = 0.6 * sim.state[-1, lo.X_U]  # one at large drift: the cross-flow hull
    return sim


def _run(driver, sim, nsteps=300):
    X, alive = sim.state.copy(), sim.alive.copy()
    count = driver(sim.Ps, sim.ship_index, X, sim.inputs, sim.env, sim.F_ext, sim.dt, nsteps, RK4, alive)
    return X, alive, count


@pytest.mark.parametrize(
    "ships, depth_factor, kind",
    [
        ("kvlcc2", None, (False, False, False, False, True)),  # deep water, 3 DOF, MMG hull: no Abkowitz model
        ("kvlcc2_l7", None, (False, False, False, False, False)),  # no cross-flow hull, no four-quadrant propeller
        ("mariner", None, (False, False, False, True, True)),  # an Abkowitz hull
        ("container", None, (False, True, False, True, False)),  # roll (an Abkowitz hull)
        ("kvlcc2", 1.5, (True, False, False, False, True)),  # shallow water, h/T = 1.5
        (["kvlcc2", "container"], None, (False, True, False, True, True)),  # a 3-DOF MMG ship in a batch with roll
    ],
)
def test_kind_of_batch_matches_the_general_kernel_bit_for_bit(ships, depth_factor, kind):
    T = load_ship(ships if isinstance(ships, str) else ships[0]).particulars.T_m
    depth = float("inf") if depth_factor is None else depth_factor * T
    n = 4
    sim = _sim(ships, n, depth, ship_index=None if isinstance(ships, str) else np.arange(n) % 2)
    assert sim._kernels is drivers(*kind)  # the simulation chose the narrowest kind
    Xk, alive_k, count_k = _run(drivers(*kind)[0], sim)
    Xg, alive_g, count_g = _run(run_serial, sim)
    assert count_k == count_g == n and alive_k.all()
    assert np.array_equal(Xk, Xg)
    assert not np.array_equal(Xk, sim.state)  # it moved


def test_a_kernel_refuses_a_batch_not_of_its_kind_and_the_simulation_chooses_again():
    sim = _sim("container", 2)
    X, alive, count = _run(drivers(False, False, False, True, True)[0], sim)  # a 3-DOF kernel, a ship with roll
    assert count == -1 and np.array_equal(X, sim.state)  # refused, nothing integrated
    sim = _sim("mariner", 2)
    X, alive, count = _run(drivers(False, False, False, False, True)[0], sim)  # no Abkowitz model, an Abkowitz hull
    assert count == -1 and np.array_equal(X, sim.state)
    sim = _sim("kvlcc2", 2)
    X, alive, count = _run(drivers(False, False, False, False, False)[0], sim)  # no cross-flow hull, kvlcc2's
    assert count == -1 and np.array_equal(X, sim.state)
    # a shallow-water row written into the environment directly, past set_environment
    sim = _sim("kvlcc2", 2)
    before = sim.state.copy()
    sim.env[:, lo.E_T_OVER_H] = 1.0 / 1.5  # h/T = 1.5
    assert _run(sim._kernels[0], sim)[2] == -1
    ref, _, _ = _run(run_serial, sim, 50)
    sim.step(50)
    assert sim._kernels is drivers(True, False, False, False, True)
    assert np.array_equal(sim.state, ref) and not np.array_equal(sim.state, before)


@pytest.mark.parametrize(
    "ship, depth_factor",
    [("kvlcc2", None), ("kvlcc2", 1.5), ("kvlcc2_l7", None), ("container", None), ("mariner", None)],
)
def test_right_hand_side_of_the_narrowest_kind_is_the_general_one_to_the_bit(ship, depth_factor):
    # the linearisation (linear.py) evaluates the drivers' kind of right-hand side, not the general form
    T = load_ship(ship).particulars.T_m
    sim = _sim(ship, 4, float("inf") if depth_factor is None else depth_factor * T)
    for b in range(sim.n):
        P, x, u, e = sim.Ps[sim.ship_index[b]], sim.state[b], sim.inputs[b], sim.env[b]
        narrow, general = np.zeros(lo.NX), np.zeros(lo.NX)
        derivatives_for(P, e)(P, x, u, e, np.zeros(3), narrow)
        derivatives(P, x, u, e, np.zeros(3), general)
        assert np.array_equal(narrow, general) and np.any(narrow != 0.0)


def test_shallow_water_simulation_compiles_one_kind_and_gives_the_deep_water_bits():
    # a simulation told it will meet shallow water (HarbourApproach with the chart's depth) takes the shallow
    # kind from the start, in deep water too: its steady start, its steps and its linearisation are those of
    # the deep-water kind to the bit, and the first shallow row needs no other kernel
    told = Simulation("kvlcc2", n=4, dt=0.2, environment=Environment(**WEATHER), shallow_water=True)
    told.reset()
    assert told._kernels is drivers(True, False, False, False, True)
    fresh = Simulation("kvlcc2", n=4, dt=0.2, environment=Environment(**WEATHER))
    fresh.reset()
    assert fresh._kernels is drivers(False, False, False, False, True)
    assert np.array_equal(told.state, fresh.state) and np.array_equal(told.inputs, fresh.inputs)
    for s in (told, fresh):
        s.set_helm(rudder_order_rad=np.linspace(-35.0, 35.0, 4) * DEG)
        s.step(200)
    assert np.array_equal(told.state, fresh.state) and told._kernels is drivers(True, False, False, False, True)
    told.env[:, lo.E_T_OVER_H] = 1.0 / 1.5  # the chart's depth arrives: the same kernel goes on
    told.step(10)
    assert told._kernels is drivers(True, False, False, False, True)
    assert stable_step("kvlcc2_l7", shallow_water=True) == stable_step("kvlcc2_l7")
    P, e = told.Ps[0], np.zeros(lo.NE)
    assert derivatives_for(P, e, shallow=True) is not derivatives_for(P, e)
    a, b = np.zeros(lo.NX), np.zeros(lo.NX)
    derivatives_for(P, e, shallow=True)(P, fresh.state[1], fresh.inputs[1], e, np.zeros(3), a)
    derivatives_for(P, e)(P, fresh.state[1], fresh.inputs[1], e, np.zeros(3), b)
    assert np.array_equal(a, b) and np.any(a != 0.0)
