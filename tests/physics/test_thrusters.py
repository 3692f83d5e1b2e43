"""Tunnel thrusters and tugs (vessel_gym.physics.components.thrusters, .tug) against their sources: bollard
thrust from power by momentum theory, the side force at speed on the Chislett & Bjorheden (1966) curve, the
first-order response; a tug's pull within its bollard pull along its line. docs/berthing.md."""

import math

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components.thrusters import SPEED_LOSS, bollard_thrust
from vessel_gym.physics.components.tug import G, Tug, TugParams
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.simulation import Simulation

SHIP = load_ship("supply")


def _thruster(name="bow_thruster"):
    sim = Simulation("supply", dt=0.1)
    return sim, next(c for c in sim.components if c.name == name)


def test_supply_has_a_bow_and_a_stern_thruster_with_momentum_theory_bollard_thrust():
    sim, bow = _thruster()
    stern = next(c for c in sim.components if c.name == "stern_thruster")
    assert bow.params.x_m > 0.0 > stern.params.x_m
    # T = (FM P sqrt(2 rho A))^(2/3): 880 kW, 2.0 m, FM 0.7 in sea water
    A = math.pi * 2.0**2 / 4.0
    want = (0.7 * 880e3 * math.sqrt(2.0 * 1025.0 * A)) ** (2.0 / 3.0)
    assert bow.T_max == pytest.approx(want, rel=1e-12)
    assert 130e3 < bow.T_max < 140e3  # 15.6 kgf/kW: within the 11-16 kgf/kW of tunnel thrusters at bollard
    assert bollard_thrust(590e3, 1.75, 0.7, 1025.0) == pytest.approx(stern.T_max)


@pytest.mark.parametrize("ratio", [0.0, 0.1, 0.2, 0.3, 0.4, 0.6, 1.0])
def test_side_force_at_speed_follows_the_published_curve(ratio):
    """At full thrust and surge speed U = ratio x V_j the side force is the curve's fraction of the bollard force
    (V_j = sqrt(T / (rho A)) the jet of the thrust's momentum flux); the moment is the force at the tunnel."""
    sim, bow = _thruster()
    V_j = math.sqrt(bow.T_max / (1025.0 * bow.area))
    x = np.zeros((1, lo.NX))
    x[0, lo.X_U] = ratio * V_j
    F = bow.forces(sim, x, np.ones((1, 1)))
    want = bow.T_max * np.interp(ratio, *SPEED_LOSS)
    assert F[0, 1] == pytest.approx(want, rel=1e-9)
    assert F[0, 2] == pytest.approx(bow.params.x_m * want, rel=1e-9)
    assert F[0, 0] == 0.0


def test_the_published_curve_has_its_documented_shape():
    """Chislett & Bjorheden (1966): about half the bollard side force near U / V_j = 0.3, a partial recovery
    above; V_j of the supply's bow thruster is 6.5 m/s, so half its force is gone at about 4 kn."""
    r, f = np.asarray(SPEED_LOSS[0]), np.asarray(SPEED_LOSS[1])
    assert f[0] == 1.0 and 0.45 <= f.min() <= 0.52 and 0.25 <= r[f.argmin()] <= 0.4
    assert f[-1] > f.min() + 0.15
    _sim, bow = _thruster()
    V_j = math.sqrt(bow.T_max / (1025.0 * bow.area))
    assert 6.0 < V_j < 7.0


def test_thrust_answers_the_order_as_n_squared_with_a_first_order_lag():
    sim, bow = _thruster()
    sim.reset(speed_m_s=0.5, heading_deg=0.0)
    sim.set_helm(rudder_order_rad=0.0, rev_order=0.0)
    bow.set_order(0.5)  # half rated rpm: a quarter of the bollard thrust
    tau = bow.params.time_constant_s
    sim.advance(tau)
    s = sim.component_state("bow_thruster.thrust")[0]
    assert s == pytest.approx(0.25 * (1.0 - math.exp(-1.0)), rel=2e-3)
    sim.advance(10.0 * tau)
    assert sim.component_state("bow_thruster.thrust")[0] == pytest.approx(0.25, rel=1e-3)
    bow.set_order(-3.0)  # clipped to full astern... to port
    assert bow.order[0] == -1.0


def test_a_thruster_turns_the_ship_the_way_its_order_says():
    sim, bow = _thruster()
    sim.reset(speed_m_s=0.0, heading_deg=0.0)
    sim.set_helm(rudder_order_rad=0.0, rev_order=0.0)
    bow.set_order(1.0)
    sim.advance(60.0)
    assert sim.state[0, lo.X_R] > 0.0 and sim.state[0, lo.X_V] > 0.0  # bow pushed to starboard


def test_a_tug_pulls_within_its_bollard_pull_along_its_line_after_its_lag():
    ship = load_ship("kvlcc2_full")
    p = TugParams(name="bow_tug", bollard_pull_t=60.0, x_m=120.0, line_angle_deg=30.0, time_constant_s=20.0)
    tug = Tug(ship, p)
    sim = Simulation(ship, dt=0.5, components=[tug])
    sim.reset(speed_m_s=0.5, heading_deg=0.0)
    tug.set_order(2.0)  # clipped: full bollard pull
    sim.advance(20.0)
    F = sim.named_forces()["bow_tug"]
    full = 60.0 * 1e3 * G
    assert math.hypot(F.X[0], F.Y[0]) == pytest.approx(full * (1.0 - math.exp(-1.0)), rel=5e-3)
    assert math.degrees(math.atan2(F.X[0], F.Y[0])) == pytest.approx(30.0, abs=1e-6)
    assert F.N[0] == pytest.approx(120.0 * F.Y[0])
    sim.advance(400.0)
    F = sim.named_forces()["bow_tug"]
    assert math.hypot(F.X[0], F.Y[0]) == pytest.approx(full, rel=1e-4)
    # what it delivers, on the order's scale: the force along its line / bollard pull, whatever the line angle
    s_now = np.array([[F.X[0], F.Y[0]]]) / full
    assert tug.delivered(s_now)[0] == pytest.approx(1.0, rel=1e-4)
