"""The steady straight approach a simulation starts from (IMO trials start from one): the shaft speed of zero
surge acceleration, and the governor's fuel index that holds it."""

from __future__ import annotations

import numpy as np
from numba import njit

from vessel_gym.physics import layout as lo
from vessel_gym.physics.environment import CALM
from vessel_gym.physics.propulsion import engine_torque, engine_torque_to_hold, shaft_torque_to_hold
from vessel_gym.physics.shipfile import Ship
from vessel_gym.physics.units import KNOT_M_S
from vessel_gym.physics.vessel import NO_REFCOUNT, derivatives_of, force_terms

# surge balances solved again at most this many times while user component forces still change with the rpm
STEADY_MAX_ITERATIONS = 20


class SimulationError(RuntimeError):
    """A simulation cannot be set up or continued (e.g. a requested speed the engine cannot reach)."""


# The solvers below take the environment row twice: as ``env``, and as ``shallow_env``, which is ``env`` where the
# water may be shallow and None in deep water (:func:`_depth`). Given None, numba compiles them for the literal
# depth ratio 0, the deep-water kernel the batch drivers of a deep-water simulation run (integrate.drivers), so a
# simulation in deep water compiles the equations once; the results are the same either way.


def _depth(env: np.ndarray) -> np.ndarray | None:
    """``shallow_env`` for the solvers below: the row ``env``, or None in deep water (E_T_OVER_H exactly 0)."""
    return env if env[lo.E_T_OVER_H] != 0.0 else None


@njit(cache=True, **NO_REFCOUNT)
def _surge_acceleration(P, x, inp, env, F, shallow_env, xd):
    """du/dt (m/s^2) at state ``x`` (vessel.derivatives, with ``xd`` a scratch row of length NX)."""
    if shallow_env is None:
        H = 0
    else:
        H = shallow_env[lo.E_T_OVER_H]
    derivatives_of(P, x, inp, env, F, xd, H, True, True)
    return xd[lo.X_U]


@njit(cache=True, **NO_REFCOUNT)
def _propeller_torque(P, x, env, shallow_env):
    """The propeller's absorbed torque Q_P (N m) at state ``x`` (vessel.forces' "Q_prop")."""
    if shallow_env is None:
        H = 0
    else:
        H = shallow_env[lo.E_T_OVER_H]
    return force_terms(P, x, env, H)[14]


@njit(cache=True)
def _surge_balance_rev(P, x, inp, env, F, hi_n, shallow_env):
    """Shaft speed in [0, hi_n] of zero surge acceleration at state ``x`` (its X_REV and the order set to it).

    Bisection (thrust grows with rev), at most 80 halvings. Compiled: a vector environment
    resets a ship every few steps, and each reset solves this.
    """
    xd = np.zeros(lo.NX)

    def surge_accel(nrev):
        x[lo.X_REV] = nrev
        inp[lo.U_REV_C] = nrev
        return _surge_acceleration(P, x, inp, env, F, shallow_env, xd)

    lo_n = 0.0
    if surge_accel(0.0) > 0.0:
        hi_n = 0.0
    for _ in range(80):
        mid = 0.5 * (lo_n + hi_n)
        if surge_accel(mid) > 0.0:
            if hi_n == mid:
                break  # the bracket stopped shrinking: the remaining halvings would repeat this one
            hi_n = mid
        else:
            if lo_n == mid:
                break
            lo_n = mid
    nrev = 0.5 * (lo_n + hi_n)
    x[lo.X_REV] = nrev
    inp[lo.U_REV_C] = nrev
    return nrev


@njit(cache=True)
def _fuel_index_for(P, n_e, Q_need):
    """Governor fuel index in [0, 1] whose engine torque at ``n_e`` rev/s is ``Q_need`` N m (bisection)."""
    a, b = 0.0, 1.0
    for _ in range(60):
        mid = 0.5 * (a + b)
        if engine_torque(P, n_e, mid) < Q_need:
            if a == mid:
                break  # as in _surge_balance_rev
            a = mid
        else:
            if b == mid:
                break
            b = mid
    return 0.5 * (a + b)


class _SteadyApproach:
    """The steady straight run of one vessel, solved in steps so that user component forces (evaluated by the
    caller, for one vessel or a whole batch at once) can take part: :meth:`start` with the forces at the trial
    state :attr:`x`, :meth:`balance` with the forces at the last solution until they no longer change, then
    :meth:`finish`."""

    def __init__(self, ship: Ship, P: np.ndarray, speed_m_s: float, env: np.ndarray, heading_rad: float):
        self.ship, self.P, self.speed, self.env = ship, P, speed_m_s, env
        self.x = np.zeros(lo.NX)
        self.inp = np.zeros(lo.NU)
        self.x[lo.X_U] = speed_m_s
        self.x[lo.X_PSI] = heading_rad
        self.nrev = 0.0
        self.n_max = 0.0
        self.Q_hold = 0.0
        if ship.propeller is not None:
            self.n_max = 3.0 * ship.engine.rated_rpm / 60.0 / ship.transmission.gear_ratio
            self.x[lo.X_REV] = self.inp[lo.U_REV_C] = self.n_max
            self.x[lo.X_CAM] = 1.0  # a direct-reversing engine's gear set for ahead running

    def start(self, F: np.ndarray) -> bool:
        """Check at full trial rpm with the forces F (3,) that the propeller can make the speed (raises
        SimulationError if not). Returns whether a surge balance is to be solved (a ship with a propeller)."""
        if self.ship.propeller is None:
            return False
        if _surge_acceleration(self.P, self.x, self.inp, self.env, F, _depth(self.env), np.zeros(lo.NX)) < 0.0:
            raise SimulationError(
                f"{self.ship.name}: the propeller cannot make {self.speed / KNOT_M_S:.2f} kn below "
                f"{self.n_max * 60:.0f} rpm"
            )
        self.balance(F)
        return True

    def balance(self, F: np.ndarray) -> None:
        """Solve the shaft speed of zero surge acceleration with the forces F (3,) (updates :attr:`x`)."""
        self.nrev = _surge_balance_rev(self.P, self.x, self.inp, self.env, F, self.n_max, _depth(self.env))

    def finish(self) -> tuple[np.ndarray, np.ndarray]:
        """(state row, input row), the governor integrator at the fuel index whose torque holds the shaft
        speed; :attr:`Q_hold` the drive torque at the propeller shaft that holds it, N m."""
        x, P = self.x, self.P
        if self.ship.propeller is None:
            return x.copy(), self.inp.copy()
        Q_prop = _propeller_torque(P, x, self.env, _depth(self.env))
        nrev = self.nrev
        self.Q_hold = shaft_torque_to_hold(P, nrev, Q_prop)
        if P[lo.P_ENGINE_EXT] > 0.0:  # a user's engine: its own states hold the shaft (ComponentBatch)
            x[lo.X_GOV] = x[lo.X_CAM] = 0.0
            return x.copy(), self.inp.copy()
        Q_need = engine_torque_to_hold(P, nrev, Q_prop)
        n_e = P[lo.P_GEAR] * nrev
        if engine_torque(P, n_e, 1.0) < Q_need:
            raise SimulationError(
                f"{self.ship.name}: the engine cannot hold {nrev * 60:.1f} rpm for "
                f"{self.speed / KNOT_M_S:.2f} kn "
                f"(needs {Q_need / P[lo.P_ENG_QRATED]:.2f} x rated torque)"
            )
        x[lo.X_GOV] = _fuel_index_for(P, n_e, Q_need)
        return x.copy(), self.inp.copy()


def steady_state(
    ship: Ship,
    P: np.ndarray,
    speed_m_s: float,
    extra=None,
    env: np.ndarray | None = None,
    heading_rad: float = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """(state row, input row) of a steady straight run at ``speed_m_s`` through the water on ``heading_rad``
    at the origin, in the environment row ``env`` (default: calm water, still ISA air, whose drag on the
    ship's own speed is part of the balance). Only the surge balance is solved: in wind, current or waves
    the sway and yaw loads act from the first step.

    ``extra(x_row) -> (X, Y, N)`` adds user component forces to the balance; they are evaluated at the
    solved shaft speed and the balance is solved again until they no longer change (at once for forces
    that do not depend on the shaft speed)."""
    if env is None:
        env = CALM.row(ship.particulars.L_m, ship.particulars.T_m)
    s = _SteadyApproach(ship, P, speed_m_s, env, heading_rad)

    def extra_forces() -> np.ndarray:
        return np.zeros(3) if extra is None else np.asarray(extra(s.x.copy()), dtype=float)

    F = extra_forces()
    if s.start(F) and extra is not None:
        for _ in range(STEADY_MAX_ITERATIONS - 1):
            F_new = extra_forces()
            if np.array_equal(F_new, F):
                break
            F = F_new
            s.balance(F)
    return s.finish()
