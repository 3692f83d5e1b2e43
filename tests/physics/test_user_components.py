"""A component written in plain Python plugs into a simulation (docs/components.md)."""

from __future__ import annotations

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.shipchecks import abkowitz_term
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.steady import STEADY_MAX_ITERATIONS


class PolynomialHull:
    """An Abkowitz hull written in numpy by a user, reading the ship file's named derivatives
    (here the DTC: the seed's linear eq. 11 terms plus the file's nonlinear terms, rho L^2 U^2 normalisation)."""

    slot = "hull"

    def __init__(self, ship):
        s = load_ship(ship)
        assert s.hull.normalisation == "rho_L2_U2" and s.hull.U_ref_m_s == 0.0
        self.L = s.particulars.L_m
        self.rho = s.particulars.rho_kg_m3
        self.terms = [(abkowitz_term(k), v) for k, v in s.hull.derivatives.items() if abkowitz_term(k)]
        self.R = s.hull.resistance_N / s.hull.resistance_speed_m_s**2
        d = s.hull.derivatives
        L, f = self.L, self.rho  # seed eq. 5-6: rho L^3 (forces per acceleration), rho L^4, rho L^5
        self.M_A = -np.array(
            [
                [d.get("X_udot", 0.0) * f * L**3, 0.0, 0.0],
                [0.0, d.get("Y_vdot", 0.0) * f * L**3, d.get("Y_rdot", 0.0) * f * L**4],
                [0.0, d.get("N_vdot", 0.0) * f * L**4, d.get("N_rdot", 0.0) * f * L**5],
            ]
        )

    def added_mass(self):
        return self.M_A

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


class CountingShaftDrag:
    """A drag growing with the shaft speed (so that the steady approach iterates), counting its calls and the
    batch sizes it is given."""

    def __init__(self, coefficient_N_s2):
        self.c = coefficient_N_s2
        self.batches = []

    def forces(self, sim, x):
        self.batches.append(x.shape)
        F = np.zeros((x.shape[0], 3))
        F[:, 0] = -self.c * x[:, lo.X_REV] * np.abs(x[:, lo.X_REV])
        return F


class NoForce:
    def forces(self, sim, x):
        return np.zeros((x.shape[0], 3))


@pytest.mark.parametrize("method", ["rk4", "euler"])
def test_component_path_runs_the_compiled_stages(method):
    """The batch driver with Python components and the compiled driver share their stages: with a component
    that adds nothing the trajectories agree bit for bit, through rudder and engine orders that make the
    exact steering-gear stages matter (helm changed mid-run, different ships in one batch)."""
    runs = []
    for comps in ([], [NoForce()]):
        sim = Simulation(
            ["kvlcc2_l7", "mariner"], n=4, ship_index=[0, 1, 0, 1], dt=0.1, method=method, components=comps
        )
        sim.reset(heading_deg=[0.0, 45.0, 90.0, 135.0])
        sim.set_helm(rudder_order_rad=np.radians([35.0, -20.0, 5.0, 0.0]))
        sim.step(150)
        sim.set_helm(rudder_order_rad=np.radians([-35.0, 20.0, 0.0, 10.0]), rev_order=sim.rev * 0.5)
        sim.step(150)
        runs.append(sim.state.copy())
    assert np.array_equal(runs[0], runs[1])


@pytest.mark.parametrize("method, stages", [("rk4", 4), ("euler", 1)])
def test_component_is_evaluated_once_per_stage_for_the_whole_batch(method, stages):
    """O(N): a step calls a component once per stage with all N states, whatever N."""
    for n in (1, 64):
        drag = CountingShaftDrag(0.05)
        sim = Simulation("kvlcc2_l7", n=n, dt=0.1, method=method, components=[drag])
        sim.reset()
        drag.batches.clear()
        sim.step(10)
        assert drag.batches == [(n, lo.NX)] * (10 * stages)


def test_reset_with_component_calls_it_a_bounded_number_of_times():
    """A reset evaluates the components on the whole batch a few times, as many for 200 vessels as for 2 (it
    once evaluated them for every vessel separately: O(N^2)); the steady approach includes their force."""
    counts = []
    for n in (2, 200):
        drag = CountingShaftDrag(0.05)
        sim = Simulation("kvlcc2_l7", n=n, dt=0.1, components=[drag])
        drag.batches.clear()
        sim.reset(heading_deg=np.linspace(0.0, 360.0, n, endpoint=False))
        assert set(drag.batches) == {(n, lo.NX)}
        counts.append(len(drag.batches))
        drag.batches.clear()
        sim.reset(k=n // 2)  # one vessel: the same bounded number of whole-batch calls
        assert 1 < len(drag.batches) <= counts[-1]
    assert counts[0] == counts[1] <= STEADY_MAX_ITERATIONS
    free = Simulation("kvlcc2_l7", dt=0.1)
    free.reset()
    drag = CountingShaftDrag(0.05)
    held = Simulation("kvlcc2_l7", dt=0.1, components=[drag])
    held.reset()
    assert held.rev[0] > free.rev[0]  # the drag needs more rpm for the same speed
    u0 = held.u[0]
    held.advance(10.0)
    assert held.u[0] == pytest.approx(u0, rel=1e-4)  # a steady approach: the drag is in the surge balance
