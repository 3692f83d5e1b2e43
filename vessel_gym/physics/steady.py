"""The steady straight approach a simulation starts from (IMO trials start from one): the shaft speed of zero
surge acceleration, and the governor's fuel index that holds it."""

from __future__ import annotations

import functools

import numba
import numpy as np
from numba import njit, prange

from vessel_gym.physics import layout as lo
from vessel_gym.physics.environment import CALM
from vessel_gym.physics.params import ENGINE, ROLL, TRANSMISSION
from vessel_gym.physics.propulsion import engine_torque, engine_torque_to_hold, shaft_torque_to_hold
from vessel_gym.physics.shipfile import Ship
from vessel_gym.physics.units import KNOT_M_S
from vessel_gym.physics.vessel import NO_REFCOUNT, abkowitz_family, derivatives_of, far_models, force_terms

# surge balances solved again at most this many times while user component forces still change with the rpm
STEADY_MAX_ITERATIONS = 20
# Many approaches (a vector env's first reset: each ship its own weather) are solved over the threads, each
# approach alone by the same compiled code (bitwise the serial rows). A solve is ~20 us; below this many the
# serial loop is kept, so a thread that waits for a busy core never holds up a small reset.
STEADY_THREADED_MIN = 4096  # approaches
# approaches handed to a thread at a time: a thread whose core is taken by another process holds up at most one
# chunk (~5 ms) while the free thread takes the rest, so the threaded solve is not slower than the serial one
STEADY_THREADED_CHUNK = 256  # approaches


class SimulationError(RuntimeError):
    """A simulation cannot be set up or continued (e.g. a requested speed the engine cannot reach)."""


# The solvers below are compiled for the kind of vessel they solve, as the batch drivers are (integrate.drivers):
# in deep water the draught-to-depth ratio is None (``shallow_env`` None: numba drops the branch on it), and
# without roll, a user's engine, a model of the Abkowitz family or one for far from the design point those parts
# of the equations are left out (``roll``, ``ext``, ``abk``, ``far`` from the closures of :func:`_solvers`). A deep-water 3-DOF simulation then compiles the right-hand side once, for
# its drivers and its steady approach alike; the results are the same for every kind.


def _kind(P: np.ndarray, env: np.ndarray, shallow: bool = False) -> tuple[bool, bool, bool, bool, bool]:
    """(shallow, roll, ext, abk, far) of one vessel with parameter row ``P`` in environment row ``env``
    (integrate.drivers); ``shallow`` True chooses the shallow-water kind in deep water too (Simulation's
    ``shallow_water``: the same results, one kind compiled)."""
    return (
        bool(shallow or env[lo.E_T_OVER_H] != 0.0),
        bool(P[ROLL.on] != 0.0),
        bool(P[ENGINE.by_component] != 0.0),
        abkowitz_family(P),
        far_models(P),
    )


@njit(cache=True, **NO_REFCOUNT)
def _surge_acceleration(P, x, inp, env, F, shallow_env, roll, ext, abk, far, xd):
    """du/dt (m/s^2) at state ``x`` (vessel.derivatives_of, with ``xd`` a scratch row of length NX)."""
    if shallow_env is None:
        H = None
    else:
        H = shallow_env[lo.E_T_OVER_H]
    derivatives_of(P, x, inp, env, F, xd, H, roll, ext, abk, far)
    return xd[lo.X_U]


@njit(cache=True, **NO_REFCOUNT)
def _propeller_torque(P, x, env, shallow_env, abk, far):
    """The propeller's absorbed torque Q_P (N m) at state ``x`` (vessel.forces' "Q_prop")."""
    if shallow_env is None:
        H = None
    else:
        H = shallow_env[lo.E_T_OVER_H]
    return force_terms(P, x, env, H, abk, far).Q_prop


@njit(cache=True)
def _steady_row(P, speed, heading, e, n_max, x, inp, F, xd, shallow_env, roll, ext, abk, far):
    """:class:`_SteadyApproach` (start, balance, finish; no user forces) of one approach at ``speed`` (m/s),
    ``heading`` (rad) in environment row ``e``, into the rows ``x``, ``inp``: the same calls in the same order.
    False where the propeller or the engine cannot hold it (the caller raises for it). ``shallow_env`` (``e`` or
    None), ``roll``, ``ext``, ``abk``, ``far``: the kind of vessel, as compile-time constants (:func:`_solvers`)."""
    x[:] = 0.0
    inp[:] = 0.0
    x[lo.X_U] = speed
    x[lo.X_PSI] = heading
    x[lo.X_REV] = inp[lo.U_REV_C] = n_max
    x[lo.X_CAM] = 1.0
    if _surge_acceleration(P, x, inp, e, F, shallow_env, roll, ext, abk, far, xd) < 0.0:
        return False
    nrev = _surge_balance_rev(P, x, inp, e, F, n_max, shallow_env, roll, ext, abk, far)
    Q_prop = _propeller_torque(P, x, e, shallow_env, abk, far)
    if P[ENGINE.by_component] > 0.0:
        x[lo.X_GOV] = x[lo.X_CAM] = 0.0
        return True
    Q_need = engine_torque_to_hold(P, nrev, Q_prop)
    n_e = P[TRANSMISSION.gear_ratio] * nrev
    if engine_torque(P, n_e, 1.0) < Q_need:
        return False
    x[lo.X_GOV] = fuel_index_for(P, n_e, Q_need)
    return True


@functools.cache
def _solvers(shallow: bool, roll: bool, ext: bool, abk: bool, far: bool):
    """(surge_acceleration(P, x, inp, env, F), surge_balance_rev(P, x, inp, env, F, hi_n), propeller_torque(P,
    x, env), steady_rows(...), steady_rows_threaded(...)) compiled for one kind of vessel (:func:`_kind`)."""
    SHALLOW, ROLL, EXT = shallow, (True if roll else None), ext  # as integrate.drivers
    ABK, FAR = (True if abk else None), (True if far else None)

    @njit(cache=True)
    def surge_acceleration(P, x, inp, env, F):
        return _surge_acceleration(P, x, inp, env, F, env if SHALLOW else None, ROLL, EXT, ABK, FAR, np.zeros(lo.NX))

    @njit(cache=True)
    def surge_balance_rev(P, x, inp, env, F, hi_n):
        return _surge_balance_rev(P, x, inp, env, F, hi_n, env if SHALLOW else None, ROLL, EXT, ABK, FAR)

    @njit(cache=True)
    def propeller_torque(P, x, env):
        return _propeller_torque(P, x, env, env if SHALLOW else None, ABK, FAR)

    @njit(cache=True)
    def steady_rows(P, speed, heading, env, n_max, out_x, out_u):
        # _steady_row of approach j for each row j of speed, heading (rad) and env, in one loop. Returns the
        # first j whose approach the propeller or the engine cannot hold (-1: none).
        F = np.zeros(3)
        xd = np.zeros(lo.NX)
        for j in range(speed.shape[0]):
            e = env[j]
            shallow_env = e if SHALLOW else None
            x, inp = out_x[j], out_u[j]
            if not _steady_row(P, speed[j], heading[j], e, n_max, x, inp, F, xd, shallow_env, ROLL, EXT, ABK, FAR):
                return j
        return -1

    @njit(cache=True, parallel=True)
    def steady_rows_threaded(P, speed, heading, env, n_max, out_x, out_u):
        # steady_rows over the threads: each approach is solved alone, by the same code, so the rows are those
        # of the serial loop to the bit; all approaches are solved, then the first failed one is returned
        m = speed.shape[0]
        ok = np.ones(m, dtype=np.bool_)
        F = np.zeros(3)  # read only
        for j in prange(m):
            e = env[j]
            shallow_env = e if SHALLOW else None
            x, inp, xd = out_x[j], out_u[j], np.zeros(lo.NX)
            ok[j] = _steady_row(P, speed[j], heading[j], e, n_max, x, inp, F, xd, shallow_env, ROLL, EXT, ABK, FAR)
        for j in range(m):
            if not ok[j]:
                return j
        return -1

    return surge_acceleration, surge_balance_rev, propeller_torque, steady_rows, steady_rows_threaded


def steady_rows(
    ship: Ship,
    P: np.ndarray,
    speed: np.ndarray,
    heading_rad: np.ndarray,
    env: np.ndarray,
    shallow: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """(state rows, input rows) of many steady approaches of one ship (no user forces), each row that of
    :func:`steady_state` (speed m/s, heading rad and environment row j), solved in compiled loops (one per kind
    of environment: deep or shallow water; ``shallow`` True: the shallow kind for every row, :func:`_kind`).
    Raises SimulationError as :func:`steady_state` does for the first approach the ship cannot make."""
    m = len(speed)
    out_x, out_u = np.zeros((m, lo.NX)), np.zeros((m, lo.NU))
    if ship.propeller is None:  # nothing to solve: the approach as given
        out_x[:, lo.X_U], out_x[:, lo.X_PSI] = speed, heading_rad
        return out_x, out_u
    n_max = 3.0 * ship.engine.rated_rpm / 60.0 / ship.transmission.gear_ratio
    shallow_rows = (env[:, lo.E_T_OVER_H] != 0.0) | shallow
    for kind in (False, True):
        rows = np.flatnonzero(shallow_rows == kind)
        if not len(rows):
            continue
        solvers = _solvers(kind, *_kind(P, env[rows[0]])[1:])
        x, u = np.zeros((len(rows), lo.NX)), np.zeros((len(rows), lo.NU))
        solve_args = (P, speed[rows], heading_rad[rows], np.ascontiguousarray(env[rows]), n_max, x, u)
        if len(rows) >= STEADY_THREADED_MIN:
            with numba.parallel_chunksize(STEADY_THREADED_CHUNK):
                bad = solvers[4](*solve_args)
        else:
            bad = solvers[3](*solve_args)
        if bad >= 0:  # the scalar solver raises its error for it
            j = rows[bad]
            steady_state(ship, P, float(speed[j]), env=env[j], heading_rad=float(heading_rad[j]), shallow=shallow)
            raise SimulationError(f"{ship.name}: no steady approach at {speed[j] / KNOT_M_S:.2f} kn")
        out_x[rows], out_u[rows] = x, u
    return out_x, out_u


# FNV-1a's 64-bit prime: mixes the 8-byte words of a row into one hash (wrapping uint64 arithmetic)
_ROW_HASH_PRIME = np.uint64(0x100000001B3)


def distinct_rows(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first, inverse) of the distinct rows of the float array ``keys`` (m, k), compared byte for byte: row
    ``first[q]`` is the first of the q-th distinct row, and row j equals row ``first[inverse[j]]``.

    ``np.unique(keys, axis=0)`` sorts the rows as records, ~1 s for 262144 rows of 18 floats; here each row is
    hashed to one uint64 (numpy over the columns), the hashes are sorted, and every row is checked equal to the
    first of its hash; on a collision (two different rows, one hash) the rows are sorted as bytes instead."""
    words = np.ascontiguousarray(keys).view(np.uint64)
    h = np.zeros(len(words), dtype=np.uint64)
    for c in range(words.shape[1]):
        h ^= words[:, c]
        h *= _ROW_HASH_PRIME
    _, first, inverse = np.unique(h, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    if not np.array_equal(words[first][inverse], words):
        rows = words.view(np.dtype((np.void, words.itemsize * words.shape[1]))).reshape(-1)
        _, first, inverse = np.unique(rows, return_index=True, return_inverse=True)
        inverse = inverse.reshape(-1)
    return first, inverse


@njit(cache=True)
def _surge_balance_rev(P, x, inp, env, F, hi_n, shallow_env, roll, ext, abk, far):
    """Shaft speed in [0, hi_n] of zero surge acceleration at state ``x`` (its X_REV and the order set to it).

    Bisection (thrust grows with rev), at most 80 halvings. Compiled: a vector environment
    resets a ship every few steps, and each reset solves this.
    """
    xd = np.zeros(lo.NX)

    def surge_accel(nrev):
        x[lo.X_REV] = nrev
        inp[lo.U_REV_C] = nrev
        return _surge_acceleration(P, x, inp, env, F, shallow_env, roll, ext, abk, far, xd)

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
def fuel_index_for(P, n_e, Q_need):
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

    def __init__(
        self, ship: Ship, P: np.ndarray, speed_m_s: float, env: np.ndarray, heading_rad: float, shallow: bool = False
    ):
        self.ship, self.P, self.speed, self.env = ship, P, speed_m_s, env
        self._solve = _solvers(*_kind(P, env, shallow))
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
        if self._solve[0](self.P, self.x, self.inp, self.env, F) < 0.0:
            raise SimulationError(
                f"{self.ship.name}: the propeller cannot make {self.speed / KNOT_M_S:.2f} kn below "
                f"{self.n_max * 60:.0f} rpm"
            )
        self.balance(F)
        return True

    def balance(self, F: np.ndarray) -> None:
        """Solve the shaft speed of zero surge acceleration with the forces F (3,) (updates :attr:`x`)."""
        self.nrev = self._solve[1](self.P, self.x, self.inp, self.env, F, self.n_max)

    def finish(self) -> tuple[np.ndarray, np.ndarray]:
        """(state row, input row), the governor integrator at the fuel index whose torque holds the shaft
        speed; :attr:`Q_hold` the drive torque at the propeller shaft that holds it, N m."""
        x, P = self.x, self.P
        if self.ship.propeller is None:
            return x.copy(), self.inp.copy()
        Q_prop = self._solve[2](P, x, self.env)
        nrev = self.nrev
        self.Q_hold = shaft_torque_to_hold(P, nrev, Q_prop)
        if P[ENGINE.by_component] > 0.0:  # a user's engine: its own states hold the shaft (ComponentBatch)
            x[lo.X_GOV] = x[lo.X_CAM] = 0.0
            return x.copy(), self.inp.copy()
        Q_need = engine_torque_to_hold(P, nrev, Q_prop)
        n_e = P[TRANSMISSION.gear_ratio] * nrev
        if engine_torque(P, n_e, 1.0) < Q_need:
            raise SimulationError(
                f"{self.ship.name}: the engine cannot hold {nrev * 60:.1f} rpm for "
                f"{self.speed / KNOT_M_S:.2f} kn "
                f"(needs {Q_need / P[ENGINE.Q_e_rated]:.2f} x rated torque)"
            )
        x[lo.X_GOV] = fuel_index_for(P, n_e, Q_need)
        return x.copy(), self.inp.copy()


def steady_state(
    ship: Ship,
    P: np.ndarray,
    speed_m_s: float,
    extra=None,
    env: np.ndarray | None = None,
    heading_rad: float = 0.0,
    shallow: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """(state row, input row) of a steady straight run at ``speed_m_s`` through the water on ``heading_rad``
    at the origin, in the environment row ``env`` (default: calm water, still ISA air, whose drag on the
    ship's own speed is part of the balance). Only the surge balance is solved: in wind, current or waves
    the sway and yaw loads act from the first step.

    ``extra(x_row) -> (X, Y, N)`` adds user component forces to the balance; they are evaluated at the
    solved shaft speed and the balance is solved again until they no longer change (at once for forces
    that do not depend on the shaft speed). ``shallow`` True solves with the shallow-water kind of the
    equations in deep water too (:func:`_kind`; the same result)."""
    if env is None:
        env = CALM.row(ship.particulars.L_m, ship.particulars.T_m)
    s = _SteadyApproach(ship, P, speed_m_s, env, heading_rad, shallow)

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
