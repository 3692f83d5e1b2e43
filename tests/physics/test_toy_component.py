"""A force component written in this file alone acts on the ship: a constant thrust, its parameters a named
record (the ``Params`` dataclass: fields with units) built from its ship-file table, its forces named by the
component in ``Simulation.named_forces()``. No other file of the package is edited to add it.

The expected numbers come from the ship file's published coefficients through the model's documented
equations (docs/physics.md), solved here independently of the compiled kernel:

* the straight-running surge balance of the MMG model (Yasukawa & Yoshimura 2015, eq. 8 and 19-21) at a
  shaft speed the governor holds: hull resistance R'_0 1/2 rho L d u^2 (with the low-speed fade
  u/sqrt(u^2 + U_min^2) of hull.mmg_hull_forces), propeller thrust (1 - t_P) rho n^2 D^4 K_T(J),
  J = u (1 - w_P0) / (n D); a constant surge force F moves the steady speed to the root of
  (1 - t_P) T(u) + F - R(u) = 0;
* a sway force Y at x forward of midship is a yaw moment x Y about midship.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import Component
from vessel_gym.physics.params import BODY
from vessel_gym.physics.schema import param
from vessel_gym.physics.shipfile import SHIP_DIR, load_ship
from vessel_gym.physics.simulation import Simulation


@dataclass(frozen=True, kw_only=True)
class ConstantThrustParams:
    surge_N: float = param(0.0, unit="N", lo=-1e7, hi=1e7, doc="force along the body x axis (forward)")
    sway_N: float = param(0.0, unit="N", lo=-1e7, hi=1e7, doc="force along the body y axis (starboard)")
    x_m: float = param(0.0, unit="m", lo=-500.0, hi=500.0, doc="point of action forward of midship")


class ConstantThrust(Component):
    """A constant force (a tug on a towline held at a fixed bearing, a thruster at a fixed order)."""

    slot = "extra"
    Params = ConstantThrustParams

    def forces(self, sim, x):
        p = self.params
        ones = np.ones(x.shape[0])
        return np.column_stack([p.surge_N * ones, p.sway_N * ones, p.x_m * p.sway_N * ones])


SHIP = "kvlcc2_l7"  # MMG hull and propeller, no windage or wave drift: straight ahead only hull and propeller act


@pytest.fixture
def with_thrust(tmp_path, monkeypatch):
    """A ship file: kvlcc2_l7 with a [[components]] table naming ConstantThrust of this module."""
    monkeypatch.setenv("VESSEL_GYM_ALLOW_CODE", "1")  # the ship file names this test module's code

    def make(**params) -> str:
        table = ", ".join(f"{k} = {float(v)!r}" for k, v in params.items())
        text = (SHIP_DIR / f"{SHIP}.toml").read_text()
        text += f'\n[[components]]\nmodel = "{ConstantThrust.__module__}:ConstantThrust"\nparams = {{ {table} }}\n'
        path = tmp_path / f"{SHIP}_thrust.toml"
        path.write_text(text)
        return str(path)

    return make


def _surge_balance(ship, u: float, n: float, F: float) -> float:
    """Net surge force, N, in straight running at speed u (m/s) and shaft speed n (rev/s) with a force F added
    (the model's equations written out from the ship file's coefficients)."""
    pt, h, pr = ship.particulars, ship.hull, ship.propeller
    R = h.R_0 * 0.5 * pt.rho_kg_m3 * pt.L_m * pt.T_m * u * u * u / math.sqrt(u * u + h.U_min_m_s**2)
    J = u * (1.0 - pr.w_P0) / (n * pr.D_m)
    T = pt.rho_kg_m3 * n * n * pr.D_m**4 * (pr.k_0 + pr.k_1 * J + pr.k_2 * J * J)
    return (1.0 - pr.t_P) * T + F - R


def _steady_speed(ship, n: float, F: float, lo_: float, hi: float) -> float:
    """Root of the surge balance in u between lo_ and hi (bisection to round-off)."""
    for _ in range(200):
        mid = 0.5 * (lo_ + hi)
        if _surge_balance(ship, mid, n, F) > 0.0:
            lo_ = mid
        else:
            hi = mid
    return 0.5 * (lo_ + hi)


def test_params_are_built_from_the_ship_file_table(with_thrust):
    ship = load_ship(with_thrust(surge_N=12.5, sway_N=-3.0, x_m=2.0))
    sim = Simulation(ship)
    (c,) = sim.components
    assert isinstance(c, ConstantThrust)
    assert (c.params.surge_N, c.params.sway_N, c.params.x_m) == (12.5, -3.0, 2.0)


def test_bad_param_is_a_one_line_error(with_thrust):
    with pytest.raises(ValueError, match=r"x_m") as err:
        load_ship(with_thrust(x_m=1e4))  # out of its declared range
    assert "\n" not in str(err.value)


def test_constant_surge_thrust_raises_the_steady_speed_as_the_resistance_curve_predicts(with_thrust):
    ship = load_ship(SHIP)
    base = Simulation(SHIP, dt=0.1)
    base.reset()
    u0, n0 = base.state[0, lo.X_U], base.state[0, lo.X_REV]
    R0 = ship.hull.R_0 * 0.5 * ship.particulars.rho_kg_m3 * ship.particulars.L_m * ship.particulars.T_m * u0**2
    # the independent balance holds at the model's own steady approach: the test's equations are the model's
    assert abs(_surge_balance(ship, u0, n0, 0.0)) < 1e-9 * R0
    F = 0.25 * R0  # N: a quarter of the resistance at the approach speed
    u_expected = _steady_speed(ship, n0, F, u0, 2.0 * u0)
    assert u_expected > 1.05 * u0  # the force is large enough to matter

    sim = Simulation(with_thrust(surge_N=F), dt=0.1)
    sim.reset()
    sim.state[:] = base.state  # the approach without the force, then the force acts at the same shaft order
    sim.set_helm(rudder_order_rad=0.0, rev_order=base.inputs[0, lo.U_REV_C])
    sim.advance(1500.0)  # some 30 surge time constants
    assert sim.state[0, lo.X_REV] == pytest.approx(n0, rel=1e-6)  # the governor holds the shaft speed
    assert sim.state[0, lo.X_U] == pytest.approx(u_expected, rel=1e-6)
    assert sim.named_forces()["ConstantThrust"].X.tolist() == [F]


def test_sway_force_at_a_lever_arm_is_a_yaw_moment_by_name(with_thrust):
    Y, x = 4.0, 3.0  # N at 3 m forward of midship
    sim = Simulation(with_thrust(sway_N=Y, x_m=x), dt=0.1)
    sim.reset()
    named = sim.named_forces()
    assert set(named) >= {"ConstantThrust", "mmg_hull", "propeller"}
    f = named["ConstantThrust"]
    assert (f.X.tolist(), f.Y.tolist(), f.N.tolist()) == ([0.0], [Y], [x * Y])
    # it acts: from a straight approach with the rudder amidships the bow is pushed to starboard
    base = Simulation(SHIP, dt=0.1)
    base.reset()
    sim.state[:] = base.state
    sim.set_helm(rudder_order_rad=0.0, rev_order=base.inputs[0, lo.U_REV_C])
    sim.advance(5.0)
    assert sim.state[0, lo.X_R] > 0.0 and sim.state[0, lo.X_PSI] > 0.0
    # in the first instant, before the hull reacts, the yaw acceleration is the inverse mass matrix times (Y, xY)
    sim.state[:] = base.state
    P = sim.Ps[0]
    rdot_expected = P[BODY.Minv32] * Y + P[BODY.Minv33] * x * Y
    sim.step(1)
    assert sim.state[0, lo.X_R] == pytest.approx(rdot_expected * sim.dt, rel=0.05)
