"""Fixed-step integrators over batched state arrays (RK4 default, explicit Euler for comparison).

One compiled source serves a single ship and a batch of 16384: the per-vessel step below is called by a
serial driver and by a parallel (``prange``) driver, so both give bitwise identical results. Parameters are
indexed per vessel through ``ship_index`` so that a batch of identical ships shares one cached parameter row.
A vessel whose state would become non-finite stops integrating, keeps its last finite state and is flagged
(divergence detection): a diverged vessel never shows a NaN.

Performance notes (figures in docs/performance.md): the drivers allocate their scratch rows once per call
(serial) or once per thread chunk (parallel), never per vessel; the per-vessel loop takes its row views
without reference counting (vessel.NO_REFCOUNT; ~70 ns per vessel otherwise); stage loops run over the
compile-time length ``layout.NX`` so that they unroll. The drivers do not use fastmath: the RK combination is a few
percent of a step (the right-hand side dominates), and fastmath's no-NaN/no-Inf assumptions would let the
compiler delete the divergence check.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from vessel_gym.physics import layout as lo
from vessel_gym.physics.steering import steering_gear_angle
from vessel_gym.physics.vessel import NO_REFCOUNT, derivatives, forces

RK4 = 0
EULER = 1

# Largest |lambda dt| on the negative real axis for which each method is stable (a decaying mode of the
# model decays in the integration too): explicit Euler 2, classical RK4 2.785 (Hairer & Wanner, Solving
# ODEs II, sec. IV.2, Fig. 2.1). Indexed by the method codes above.
STABILITY_LIMIT = (2.785, 2.0)

# parallel driver: the batch is split into at most this many contiguous chunks (each allocates its scratch once)
# and the chunks are shared out evenly over the threads; a constant, so the compiled driver can be cached
MAX_CHUNKS = 64


@njit(cache=True)
def _finite(x):
    for i in range(lo.NX):
        if not math.isfinite(x[i]):
            return False
    return True


@njit(cache=True, **NO_REFCOUNT)
def step_vessel(P, x, inp, env, F_ext, dt, nsteps, method, k1, k2, k3, k4, xt):
    """Advance one vessel ``nsteps`` fixed steps of ``dt`` seconds in place.

    ``k1``..``k4`` and ``xt`` are scratch rows of length NX; the new state is
    formed in ``xt`` and committed only if finite. Returns False on divergence, with ``x`` left at the last
    finite state.

    The rudder angle is not integrated by the method: with the order held over the step, the steering gear's
    equation has an exact solution (:func:`~vessel_gym.physics.steering.steering_gear_angle`), which every
    stage reads at its own time (t + dt/2 for RK4's middle stages, t + dt at the end).
    """
    half = 0.5 * dt
    sixth = dt / 6.0
    D = lo.X_DELTA
    for _ in range(nsteps):
        d_end = steering_gear_angle(P, x[D], inp[lo.U_DELTA_C], dt)
        derivatives(P, x, inp, env, F_ext, k1)
        if method == EULER:
            for i in range(lo.NX):
                xt[i] = x[i] + dt * k1[i]
        else:
            d_half = steering_gear_angle(P, x[D], inp[lo.U_DELTA_C], half)
            for i in range(lo.NX):
                xt[i] = x[i] + half * k1[i]
            xt[D] = d_half
            derivatives(P, xt, inp, env, F_ext, k2)
            for i in range(lo.NX):
                xt[i] = x[i] + half * k2[i]
            xt[D] = d_half
            derivatives(P, xt, inp, env, F_ext, k3)
            for i in range(lo.NX):
                xt[i] = x[i] + dt * k3[i]
            xt[D] = d_end
            derivatives(P, xt, inp, env, F_ext, k4)
            for i in range(lo.NX):
                xt[i] = x[i] + sixth * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        xt[D] = d_end
        if not _finite(xt):
            return False
        for i in range(lo.NX):
            x[i] = xt[i]
    return True


@njit(cache=True, **NO_REFCOUNT)
def _run_range(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive, first, stop, S):
    """Integrate the alive vessels first..stop-1 with the scratch rows S (5, NX). Returns how many are alive."""
    count = 0
    for b in range(first, stop):
        if alive[b]:
            ok = step_vessel(
                Ps[ship_index[b]], X[b], U[b], E[b], F[b], dt, nsteps, method, S[0], S[1], S[2], S[3], S[4]
            )
            alive[b] = ok
            count += ok
    return count


@njit(cache=True)
def run_serial(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive):
    """Integrate every alive vessel of the batch; marks diverged vessels dead. Returns the number alive."""
    return _run_range(
        Ps, ship_index, X, U, E, F, dt, nsteps, method, alive, 0, X.shape[0], np.empty((5, lo.NX))
    )


@njit(cache=True, parallel=True)
def run_parallel(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive):
    """Same as :func:`run_serial`, with contiguous chunks of vessels spread over threads (large batches)."""
    nb = X.shape[0]
    nchunks = min(nb, MAX_CHUNKS)
    count = 0
    for c in prange(nchunks):
        S = np.empty((5, lo.NX))
        count += _run_range(
            Ps,
            ship_index,
            X,
            U,
            E,
            F,
            dt,
            nsteps,
            method,
            alive,
            c * nb // nchunks,
            (c + 1) * nb // nchunks,
            S,
        )
    return count


@njit(cache=True)
def steering_gear_angles_batch(Ps, ship_index, X, U, t, out):
    """Rudder angles of a batch ``t`` seconds on with the orders held (the Python-component path's stages)."""
    for b in range(X.shape[0]):
        out[b] = steering_gear_angle(Ps[ship_index[b]], X[b, lo.X_DELTA], U[b, lo.U_DELTA_C], t)


@njit(cache=True)
def derivatives_batch(Ps, ship_index, X, U, E, F, Xdot):
    """State derivatives of a batch (used by the Python-component path and by tests)."""
    for b in range(X.shape[0]):
        derivatives(Ps[ship_index[b]], X[b], U[b], E[b], F[b], Xdot[b])


@njit(cache=True)
def forces_batch(Ps, ship_index, X, U, E, out):
    """Component forces of a batch, out shape (N, N_OUT) (see vessel.FORCE_NAMES)."""
    for b in range(X.shape[0]):
        forces(Ps[ship_index[b]], X[b], U[b], E[b], out[b])
