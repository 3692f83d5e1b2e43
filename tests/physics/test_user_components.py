"""A component written in plain Python plugs into a simulation (docs/components.md)."""

from __future__ import annotations

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.simulation import Simulation


class LinearHull:
    """The seed's linear Abkowitz hull (eq. 11) written in numpy, reading the ship file's derivatives."""

    def __init__(self, ship):
        s = load_ship(ship)
        self.L = s.particulars.L_m
        self.rho = s.particulars.rho_kg_m3
        self.d = s.hull.derivatives
        self.R = s.hull.resistance_N / s.hull.resistance_speed_m_s**2
        self.Cd = s.hull.cross_flow_Cd
        self.T = s.particulars.T_m

    def forces(self, sim, x):
        u, v, r = x[:, lo.X_U], x[:, lo.X_V], x[:, lo.X_R]
        U = np.maximum(np.hypot(u, v), 0.05)
        q = self.rho * self.L**2 * U**2  # seed eq. 5: rho U^2 L^2
        vp, rp = v / U, np.clip(r * self.L / U, -2, 2)
        d = self.d
        X = q * d.get("X_vr", 0.0) * vp * rp - self.R * u * np.abs(u)
        Y = q * (d["Y_v"] * vp + d["Y_r"] * rp)
        N = q * self.L * (d["N_v"] * vp + d["N_r"] * rp)
        # cross-flow drag, 12 strips (as hull.cross_flow_drag)
        h = self.L / 12
        for i in range(12):
            xs = -0.5 * self.L + (i + 0.5) * h
            w = v + xs * r
            f = -0.5 * self.rho * self.T * self.Cd * h * np.abs(w) * w
            Y = Y + f
            N = N + xs * f
        return np.column_stack([X, Y, N])


class ConstantPush:
    """A tug pushing at midship with a fixed force to port (N)."""

    def __init__(self, force_N):
        self.force_N = force_N

    def forces(self, sim, x):
        return np.tile([0.0, -self.force_N, 0.0], (x.shape[0], 1))


def _run(sim):
    sim.reset()
    sim.set_helm(rudder_order_rad=np.radians(10.0))
    sim.advance(60.0)
    return sim.state.copy()


def test_python_hull_replaces_builtin_hull_and_matches():
    built_in = _run(Simulation("dtc", dt=0.1))
    user = _run(Simulation("dtc", dt=0.1, components=[LinearHull("dtc")], replace=["hull"]))
    # same equations in numpy vs compiled: agreement to floating-point round-off over 600 RK4 steps
    np.testing.assert_allclose(user, built_in, rtol=1e-9, atol=1e-6)


def test_extra_force_component_moves_ship():
    a = _run(Simulation("kvlcc2_l7", dt=0.05))
    b = _run(Simulation("kvlcc2_l7", dt=0.05, components=[ConstantPush(5.0)]))
    assert b[0, lo.X_E] < a[0, lo.X_E]  # pushed to port (west of the free track)


def test_unknown_replacement_rejected():
    with pytest.raises(ValueError, match="replace"):
        Simulation("dtc", replace=["engine"])
