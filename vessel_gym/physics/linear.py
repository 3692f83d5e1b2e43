"""Linearised dynamics of any ship model: sway-yaw Nomoto indices and the fastest mode of the full model.

The state derivative of the full model is differentiated numerically (central differences) about a straight
run at speed U with v = r = delta = 0, surge speed held: [v', r'] = A [v, r] + b delta. Its rudder-to-yaw-rate
transfer function is Nomoto's second-order model (Nomoto et al. 1957; Fossen 2011 eq. 7.49):

    r/delta (s) = K (1 + T3 s) / ((1 + T1 s)(1 + T2 s)),  first-order approximation T = T1 + T2 - T3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.integrate import EULER, RK4, STABILITY_LIMIT, derivatives_for
from vessel_gym.physics.shipfile import Ship, load_ship
from vessel_gym.physics.vessel import pack


@dataclass(frozen=True)
class Nomoto:
    K: float  # 1/s
    T1: float  # s
    T2: float  # s
    T3: float  # s

    @property
    def T(self) -> float:
        """First-order Nomoto time constant T1 + T2 - T3, s."""
        return self.T1 + self.T2 - self.T3


def sway_yaw_matrices(ship: str | Ship, speed_m_s: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(A, b) of the linearised sway-yaw model at ``speed_m_s`` (default: the ship's test speed)."""
    s = load_ship(ship)
    U = s.test_speed_m_s if speed_m_s is None else speed_m_s
    if s.components:  # a ship file's own components take part (composed as the simulation composes them)
        from vessel_gym.physics.simulation import Simulation

        sim = Simulation(s, dt=1.0)
        P = sim.Ps[0]

        def extra(x: np.ndarray) -> np.ndarray:
            return sim._component_forces(x[None, :])[0]
    else:
        P = pack(s)

        def extra(x: np.ndarray) -> np.ndarray:
            return np.zeros(3)

    env = np.zeros(lo.NE)
    rhs = derivatives_for(P, env)  # the drivers' kernel of this kind: nothing more to compile

    def f(v: float, r: float, d: float) -> np.ndarray:
        x = np.zeros(lo.NX)
        x[lo.X_U], x[lo.X_V], x[lo.X_R], x[lo.X_DELTA] = U, v, r, d
        xd = np.zeros(lo.NX)
        rhs(P, x, np.zeros(lo.NU), env, extra(x), xd)
        return np.array([xd[lo.X_V], xd[lo.X_R]])

    hv = 1e-6 * U
    hr = 1e-6 * U / s.particulars.L_m
    hd = 1e-6
    A = np.column_stack([(f(hv, 0, 0) - f(-hv, 0, 0)) / (2 * hv), (f(0, hr, 0) - f(0, -hr, 0)) / (2 * hr)])
    b = (f(0, 0, hd) - f(0, 0, -hd)) / (2 * hd)
    return A, b


def nomoto(ship: str | Ship, speed_m_s: float | None = None) -> Nomoto:
    """Nomoto indices K, T1, T2, T3 of the ship's linearised model (rudder positive to starboard)."""
    A, b = sway_yaw_matrices(ship, speed_m_s)
    det = float(np.linalg.det(A))
    num0 = A[1, 0] * b[0] - A[0, 0] * b[1]
    S = -float(np.trace(A)) / det  # T1 + T2
    P = 1.0 / det  # T1 T2
    disc = math.sqrt(max(S * S - 4.0 * P, 0.0))
    return Nomoto(K=num0 / det, T1=(S + disc) / 2.0, T2=(S - disc) / 2.0, T3=b[1] / num0)


def fastest_rate(ship: str | Ship, speed_m_s: float | None = None, shallow_water: bool = False) -> float:
    """Largest |eigenvalue| (1/s) of the full model's Jacobian at a steady straight run (default: test speed).

    The states the integrators step are perturbed (central differences), so the shaft and governor take part:
    on small models they, not the hull, are the fastest modes (kvlcc2_l7: 7.1 1/s). The rudder angle is left
    out: the integrators solve the steering gear's equation exactly (integrate.step_vessel), so its lag
    (0.1 s on kvlcc2_l7) does not bound their step. In deep water; ``shallow_water`` evaluates it with the
    shallow-water kind of the equations (Simulation's ``shallow_water``: the same numbers, the kind a
    simulation that will meet shallow water compiles anyway).
    """
    from vessel_gym.physics.simulation import Simulation  # the steady approach lives there

    sim = Simulation(load_ship(ship), dt=1.0, shallow_water=shallow_water)
    sim.reset(speed_m_s=speed_m_s)
    P, x0, inp, env = sim.Ps[0], sim.state[0].copy(), sim.inputs[0], sim.env[0]
    rhs = derivatives_for(P, env, shallow_water)

    def f(x: np.ndarray) -> np.ndarray:
        xd = np.zeros(lo.NX)
        F = sim._ext(x[None, :])[0] if sim.components else np.zeros(3)  # a ship file's own components
        rhs(P, x, inp, env, F, xd)
        return xd

    J = np.zeros((lo.NX, lo.NX))
    for j in range(lo.NX):
        h = 1e-6 * max(1.0, abs(x0[j]))
        xp, xm = x0.copy(), x0.copy()
        xp[j] += h
        xm[j] -= h
        J[:, j] = (f(xp) - f(xm)) / (2.0 * h)
    stepped = [i for i in range(lo.NX) if i != lo.X_DELTA]
    return float(np.max(np.abs(np.linalg.eigvals(J[np.ix_(stepped, stepped)]))))


def stable_step(
    ship: str | Ship, method: str = "rk4", speed_m_s: float | None = None, shallow_water: bool = False
) -> float:
    """The longest fixed step (s) at which ``method`` ("rk4" or "euler") integrates the fastest mode stably
    (in deep water; ``shallow_water`` as in :func:`fastest_rate`)."""
    limit = STABILITY_LIMIT[RK4 if method == "rk4" else EULER]
    return limit / max(fastest_rate(ship, speed_m_s, shallow_water), 1e-9)
