"""A component written in plain Python plugs into a simulation (docs/components.md)."""

from __future__ import annotations

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.shipfile import abkowitz_term, load_ship
from vessel_gym.physics.simulation import Simulation


class PolynomialHull:
    """An Abkowitz hull written in numpy by a user, reading the ship file's named derivatives
    (here the DTC: the seed's linear eq. 11 terms plus the file's nonlinear terms, rho L^2 U^2 normalisation)."""

    def __init__(self, ship):
        s = load_ship(ship)
        assert s.hull.normalisation == "rho_L2_U2" and s.hull.U_ref_m_s == 0.0
        self.L = s.particulars.L_m
        self.rho = s.particulars.rho_kg_m3
        self.terms = [(abkowitz_term(k), v) for k, v in s.hull.derivatives.items() if abkowitz_term(k)]
        self.R = s.hull.resistance_N / s.hull.resistance_speed_m_s**2

    def forces(self, sim, x):
        u, v, r, d = x[:, lo.X_U], x[:, lo.X_V], x[:, lo.X_R], x[:, lo.X_DELTA]
        U = np.maximum(np.hypot(u, v), 0.05)
        q = self.rho * self.L**2 * U**2  # seed eq. 5: rho U^2 L^2
        up, vp, rp = u / U, v / U, np.clip(r * self.L / U, -2, 2)
        F = {"X": 0.0, "Y": 0.0, "N": 0.0}
        for (eq, eu, ev, er, ed), c in self.terms:
            F[eq] = F[eq] + c * up**eu * vp**ev * rp**er * d**ed
        X = q * F["X"] - self.R * u * np.abs(u)
        return np.column_stack([X, q * F["Y"], q * self.L * F["N"]])


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
    user = _run(Simulation("dtc", dt=0.1, components=[PolynomialHull("dtc")], replace=["hull"]))
    # same equations in numpy vs compiled: agreement to floating-point round-off over 600 RK4 steps
    np.testing.assert_allclose(user, built_in, rtol=1e-9, atol=1e-6)


def test_extra_force_component_moves_ship():
    a = _run(Simulation("kvlcc2_l7", dt=0.05))
    b = _run(Simulation("kvlcc2_l7", dt=0.05, components=[ConstantPush(5.0)]))
    assert b[0, lo.X_E] < a[0, lo.X_E]  # pushed to port (west of the free track)


def test_unknown_replacement_rejected():
    with pytest.raises(ValueError, match="replace"):
        Simulation("dtc", replace=["engine"])
