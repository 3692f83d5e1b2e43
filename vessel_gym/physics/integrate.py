"""Fixed-step integrators over batched state arrays (RK4 default, explicit Euler for comparison).

One compiled source serves a single ship and a batch of 16384: the per-vessel step below is called by a
serial driver and by a parallel (``prange``) driver. Parameters are indexed per vessel through
``ship_index`` so that a batch of identical ships shares one cached parameter row.
A vessel whose state becomes non-finite stops integrating and is flagged (divergence detection).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from vessel_gym.physics import layout as lo
from vessel_gym.physics.vessel import N_OUT, derivatives, forces

RK4 = 0
EULER = 1


@njit(cache=True)
def _finite(x):
    for i in range(x.shape[0]):
        if not math.isfinite(x[i]):
            return False
    return True


@njit(cache=True)
def step_vessel(P, x, inp, env, F_ext, dt, nsteps, method, k1, k2, k3, k4, xt, work):
    """Advance one vessel ``nsteps`` fixed steps of ``dt`` seconds in place. Returns False on divergence."""
    n = x.shape[0]
    for _ in range(nsteps):
        derivatives(P, x, inp, env, F_ext, k1, work)
        if method == EULER:
            for i in range(n):
                x[i] += dt * k1[i]
        else:
            for i in range(n):
                xt[i] = x[i] + 0.5 * dt * k1[i]
            derivatives(P, xt, inp, env, F_ext, k2, work)
            for i in range(n):
                xt[i] = x[i] + 0.5 * dt * k2[i]
            derivatives(P, xt, inp, env, F_ext, k3, work)
            for i in range(n):
                xt[i] = x[i] + dt * k3[i]
            derivatives(P, xt, inp, env, F_ext, k4, work)
            for i in range(n):
                x[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        if not _finite(x):
            return False
    return True


@njit(cache=True)
def run_serial(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive):
    """Integrate every alive vessel of the batch; marks diverged vessels dead. Returns the number alive."""
    k1 = np.empty(lo.NX)
    k2 = np.empty(lo.NX)
    k3 = np.empty(lo.NX)
    k4 = np.empty(lo.NX)
    xt = np.empty(lo.NX)
    work = np.empty(N_OUT)
    count = 0
    for b in range(X.shape[0]):
        if alive[b]:
            ok = step_vessel(
                Ps[ship_index[b]], X[b], U[b], E[b], F[b], dt, nsteps, method, k1, k2, k3, k4, xt, work
            )
            alive[b] = ok
            count += ok
    return count


@njit(cache=True, parallel=True)
def run_parallel(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive):
    """Same as :func:`run_serial`, vessels spread over threads (large batches)."""
    nb = X.shape[0]
    for b in prange(nb):
        if alive[b]:
            k1 = np.empty(lo.NX)
            k2 = np.empty(lo.NX)
            k3 = np.empty(lo.NX)
            k4 = np.empty(lo.NX)
            xt = np.empty(lo.NX)
            work = np.empty(N_OUT)
            alive[b] = step_vessel(
                Ps[ship_index[b]], X[b], U[b], E[b], F[b], dt, nsteps, method, k1, k2, k3, k4, xt, work
            )
    return int(alive.sum())


@njit(cache=True)
def derivatives_batch(Ps, ship_index, X, U, E, F, Xdot):
    """State derivatives of a batch (used by the Python-component path and by tests)."""
    work = np.empty(N_OUT)
    for b in range(X.shape[0]):
        derivatives(Ps[ship_index[b]], X[b], U[b], E[b], F[b], Xdot[b], work)


@njit(cache=True)
def forces_batch(Ps, ship_index, X, U, E, out):
    """Component forces of a batch, out shape (N, N_OUT) (see vessel.FORCE_NAMES)."""
    for b in range(X.shape[0]):
        forces(Ps[ship_index[b]], X[b], U[b], E[b], out[b])
