"""The fixed-step integrator over batched state arrays (RK4 default, explicit Euler for comparison).

One definition of the method: :func:`rk_stage` is one stage of one vessel's step (the right-hand side at the
stage state, then the next stage's state or the committed result). Two loops run it: the compiled drivers
(:func:`drivers`, serial or threaded over vessels) run the stages vessel by vessel (:func:`step_vessel`), and
:func:`run_with_components` runs them stage by stage over the whole batch, calling the user's Python components
between the stages. The same compiled calls in the same order, so a ship gives the same bits alone, in a
batch of 16384, serially or threaded, with or without a (zero) Python component. Parameters are indexed per
vessel through ``ship_index`` so that a batch of identical ships shares one parameter row.
A vessel whose state would become non-finite stops integrating, keeps its last finite state and is flagged
(divergence detection): a diverged vessel never shows a NaN.

Kernels per kind of batch (:func:`drivers`): the batch drivers are compiled for what a batch can hold -- deep
or shallow water, with or without roll, with or without a user's engine, the Abkowitz family's models, the
models for far from the design point -- from the one source of the
equations (:func:`~vessel_gym.physics.vessel.derivatives_of`), the choice reaching numba as compile-time
constants, so a deep-water 3-DOF ship runs no shallow-water or roll instructions. A simulation chooses the
narrowest kind that holds its vessels (:func:`drivers_for`); each kind compiles on its first use and gives the
general kernel's results to the bit.

Performance notes (figures in docs/performance.md): the drivers allocate their scratch rows once per call
(serial) or once per thread chunk (parallel), never per vessel; the per-vessel loop takes its row views
without reference counting (vessel.NO_REFCOUNT; ~70 ns per vessel otherwise); stage loops run over the
compile-time length ``layout.NX`` so that they unroll. The drivers do not use fastmath: the RK combination is a few
percent of a step (the right-hand side dominates), and fastmath's no-NaN/no-Inf assumptions would let the
compiler delete the divergence check.
"""


from __future__ import annotations

import math
import os

import numpy as np
from numba import njit, prange

from vessel_gym.physics import layout as lo
from vessel_gym.physics.params import ENGINE, HULL, LARGE_DRIFT, PROPELLER, ROLL, RUDDER, STEERING_GEAR
from vessel_gym.physics.steering import steering_gear_angle
from vessel_gym.physics.vessel import NO_REFCOUNT, abkowitz_family, derivatives_of, far_models, forces

# The threaded driver's worker threads sleep between calls rather than spin (GNU OpenMP spins for up to
# ~300000 polls after a parallel region by default). Spinning buys a few microseconds per call on an idle
# machine and costs whole time slices when other processes (a learner, another simulation) want the cores:
# the spinning threads take them. Read by the OpenMP runtime when numba starts its threads, at the first
# threaded call, so it is set here; a value set by the user wins. Measured in docs/performance.md.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

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
def _finite(x, nx):
    for i in range(nx):
        if not math.isfinite(x[i]):
            return False
    return True


@njit(cache=True)
def n_stages(method):
    """Right-hand-side evaluations per step: 4 for RK4, 1 for explicit Euler."""
    return 1 if method == EULER else 4


@njit(cache=True)
def stage_h(stage, dt):
    """How far into the step (s) RK4 stage ``stage`` (1, 2 or 3; 0 is the step's start) evaluates the right-hand
    side: dt/2, dt/2, dt (the c of the classical tableau, Hairer, Norsett & Wanner, Solving ODEs I, sec. II.1)."""
    return 0.5 * dt if stage < 3 else dt


@njit(cache=True)
def combined(x, k1, k2, k3, k4, dt, method):
    """One state one step on from its stage rates: RK4 x + dt/6 (k1 + 2 k2 + 2 k3 + k4), Euler x + dt k1 (the
    b of the tableau; k2..k4 unused by Euler)."""
    if method == EULER:
        return x + dt * k1
    return x + (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


@njit(cache=True, **NO_REFCOUNT)
def stage_state(x, k, h, delta, xt, nx):
    """Fill ``xt`` with the state at which an RK4 stage evaluates the right-hand side, x + h k (h from
    :func:`stage_h`, k the stage before's derivative), with the rudder angle ``delta`` (rad) at that stage's
    time; the first ``nx`` states (layout.NX, or NX_3DOF in a 3-DOF kernel).

    The rudder angle is not integrated by the method: with the order held over the step, the steering gear's
    equation has an exact solution (:func:`~vessel_gym.physics.steering.steering_gear_angle`), which every
    stage reads at its own time (t + dt/2 for the middle stages, t + dt at the end).
    """
    for i in range(nx):
        xt[i] = x[i] + h * k[i]
    xt[lo.X_DELTA] = delta


@njit(cache=True, **NO_REFCOUNT)
def finish_step(x, K, dt, method, delta_end, xt, nx):
    """Form in ``xt`` the state one step on from the stage derivatives ``K`` (4, NX) (:func:`combined`), with
    the rudder angle ``delta_end`` at t + dt, and commit it to ``x`` only if finite; the first ``nx`` states
    (as :func:`stage_state`). Returns False on divergence, with ``x`` left at the last finite state."""
    k1, k2, k3, k4 = K[0], K[1], K[2], K[3]
    for i in range(nx):
        xt[i] = combined(x[i], k1[i], k2[i], k3[i], k4[i], dt, method)
    xt[lo.X_DELTA] = delta_end
    if not _finite(xt, nx):
        return False
    for i in range(nx):
        x[i] = xt[i]
    return True


@njit(cache=True, **NO_REFCOUNT)
def rk_stage(P, x, inp, env, F, K, stage, xs, xt, dt, method, H, roll, ext, abk, far, nx):
    """Stage ``stage`` (0..3 for RK4, 0 for Euler) of one step of one vessel: the right-hand side at the stage
    state ``xs`` (``x`` itself at stage 0) into ``K[stage]``, then either the state the next stage evaluates at,
    formed in ``xt`` (:func:`stage_state`), or after the last stage the step's result committed to ``x``
    (:func:`finish_step`). Returns False only when the step diverged (``x`` then keeps its last finite state).

    The one definition of the method: the compiled driver (:func:`step_vessel`) runs the stages vessel by
    vessel, the driver with Python components (:func:`run_with_components`) stage by stage over the batch,
    calling the components in between; the same calls in the same order, so both give the same bits.

    ``H``, ``roll``, ``ext``, ``abk`` and ``far`` choose the kernel (:func:`~vessel_gym.physics.vessel.derivatives_of`). The rudder
    angle of each stage is the steering gear's exact solution at that stage's time, solved from the step's
    start; where a user's steering gear gives the rudder rate (``STEERING_GEAR.by_component``, with ``F`` carrying it as
    ``F_DELTA_RATE``) the angle is a state like any other, x + h k.
    """
    D = lo.X_DELTA
    k = K[stage]
    derivatives_of(P, xs, inp, env, F, k, H, roll, ext, abk, far)
    user_gear = ext and F.shape[0] > lo.F_DELTA_RATE and P[STEERING_GEAR.by_component] > 0.0
    if user_gear:
        k[D] = F[lo.F_DELTA_RATE]
    if method != EULER and stage < 3:
        h = stage_h(stage + 1, dt)
        if user_gear:
            d = x[D] + h * k[D]
        elif stage == 1:  # stage 2 is at t + dt/2 as stage 1, whose angle xt holds
            d = xt[D]
        else:
            d = steering_gear_angle(P, x[D], inp[lo.U_DELTA_C], h)
        stage_state(x, k, h, d, xt, nx)
        return True
    if user_gear:
        d_end = combined(x[D], K[0, D], K[1, D], K[2, D], K[3, D], dt, method)
    elif method == EULER:
        d_end = steering_gear_angle(P, x[D], inp[lo.U_DELTA_C], dt)
    else:  # stage 4's state, at t + dt
        d_end = xt[D]
    return finish_step(x, K, dt, method, d_end, xt, nx)


@njit(cache=True, **NO_REFCOUNT)
def step_vessel(P, x, inp, env, F_ext, dt, nsteps, method, K, xt, H, roll, ext, abk, far, nx):
    """Advance one vessel ``nsteps`` fixed steps of ``dt`` seconds in place, with the forces ``F_ext`` held: the
    stages of :func:`rk_stage` in turn. ``K`` (4, NX) and ``xt`` (NX) are scratch; ``nx`` is how many states
    the kernel integrates (layout.NX, or NX_3DOF without roll: the roll states of a 3-DOF vessel have zero
    rates and are left as they are). Returns False on divergence, with ``x`` left at the last finite state."""
    ns = n_stages(method)
    for _ in range(nsteps):
        for stage in range(ns):
            xs = x if stage == 0 else xt
            if not rk_stage(P, x, inp, env, F_ext, K, stage, xs, xt, dt, method, H, roll, ext, abk, far, nx):
                return False
    return True


@njit(cache=True, **NO_REFCOUNT)
def _run_range(
    Ps, ship_index, X, U, E, F, dt, nsteps, method, alive, first, stop, S, shallow_env, roll, ext, abk, far, nx
):
    """Integrate the alive vessels first..stop-1 with the scratch rows S (5, NX). Returns how many are alive.

    ``shallow_env`` is ``E`` in a kernel for shallow water (each vessel's draught-to-depth ratio read from its
    environment row) and None in a deep-water kernel: numba compiles the branch on ``shallow_env is None`` away,
    so H is None there and only the deep-water equations are compiled (vessel.force_terms)."""
    count = 0
    for b in range(first, stop):
        if alive[b]:
            if shallow_env is None:
                H = None
            else:
                H = shallow_env[b, lo.E_T_OVER_H]
            ok = step_vessel(
                Ps[ship_index[b]],
                X[b],
                U[b],
                E[b],
                F[b],
                dt,
                nsteps,
                method,
                S[:4],
                S[4],
                H,
                roll,
                ext,
                abk,
                far,
                nx,
            )
            alive[b] = ok
            count += ok
    return count


@njit(cache=True, **NO_REFCOUNT)
def kernel_fits(Ps, E, shallow_env, roll, ext, abk, far):
    """Whether the kernel chosen by ``shallow_env``, ``roll``, ``ext``, ``abk`` and ``far`` (:func:`drivers`)
    holds every vessel of the batch: deep water (E_T_OVER_H exactly 0) where ``shallow_env`` is None, no ship
    with roll where ``roll`` is None, no user engine or steering gear where ``ext`` is False, no model of the
    Abkowitz family (vessel.abkowitz_family) where ``abk`` is None, no cross-flow hull or four-quadrant
    propeller (vessel.far_models) where ``far`` is None."""
    if shallow_env is None:
        for b in range(E.shape[0]):
            if E[b, lo.E_T_OVER_H] != 0.0:
                return False
    for j in range(Ps.shape[0]):
        if roll is None and Ps[j, ROLL.on] != 0.0:
            return False
        if not ext and (Ps[j, ENGINE.by_component] != 0.0 or Ps[j, STEERING_GEAR.by_component] != 0.0):
            return False
        if abk is None and (
            Ps[j, HULL.kind] == lo.HULL_ABKOWITZ
            or Ps[j, RUDDER.kind] == lo.RUDDER_SON_NOMOTO
            or Ps[j, PROPELLER.wake_kind] == lo.WAKE_SON_NOMOTO
        ):
            return False
        if far is None and (Ps[j, LARGE_DRIFT.on] != 0.0 or Ps[j, PROPELLER.four_quadrant] != 0.0):
            return False
    return True


@njit(cache=True, parallel=True)
def _parallel(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive, shallow_env, roll, ext, abk, far, nx):
    if not kernel_fits(Ps, E, shallow_env, roll, ext, abk, far):
        return -1
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
            shallow_env,
            roll,
            ext,
            abk,
            far,
            nx,
        )
    return count


def _make_drivers(shallow: bool, roll: bool, ext: bool, abk: bool, far: bool):
    # the flags reach the compiled code as closure constants: numba types them as literals, passes them on as
    # such, and compiles (and caches) one kernel per combination, keyed by their values
    # roll, abk and far as True or None: numba compiles a part guarded by `flag is not None` only where it is True
    SHALLOW, ROLL, EXT = shallow, (True if roll else None), ext
    ABK, FAR = (True if abk else None), (True if far else None)
    NXK = lo.NX if roll else lo.NX_3DOF

    # the serial driver in one level: every call level counts references of its array arguments (~150 ns a call)
    @njit(cache=True)
    def run_serial(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive):
        shallow_env = E if SHALLOW else None
        if not kernel_fits(Ps, E, shallow_env, ROLL, EXT, ABK, FAR):
            return -1
        S = np.empty((5, lo.NX))
        n = X.shape[0]
        return _run_range(
            Ps, ship_index, X, U, E, F, dt, nsteps, method, alive, 0, n, S, shallow_env, ROLL, EXT, ABK, FAR, NXK
        )

    @njit(cache=True)
    def run_parallel(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive):
        return _parallel(
            Ps, ship_index, X, U, E, F, dt, nsteps, method, alive, E if SHALLOW else None, ROLL, EXT, ABK, FAR, NXK
        )

    return run_serial, run_parallel


_DRIVERS: dict[tuple[bool, bool, bool, bool, bool], tuple] = {}


def drivers(shallow: bool = True, roll: bool = True, ext: bool = True, abk: bool = True, far: bool = True):
    """The batch drivers (serial, threaded) compiled for one kind of batch, each
    ``driver(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive)``:

    * ``shallow``: some vessel may be in shallow water (E_T_OVER_H > 0); False compiles the deep-water
      equations only (the draught-to-depth ratio is the constant 0);
    * ``roll``: some ship may have roll (ROLL.on); False compiles the 3-DOF equations only and integrates
      the first layout.NX_3DOF states;
    * ``ext``: a ship's engine or steering gear may be a user's component (ENGINE.by_component,
      STEERING_GEAR.by_component);
    * ``abk``: a ship may use a model of the Abkowitz family (vessel.abkowitz_family: an Abkowitz hull, the Son
      & Nomoto rudder or wake); False leaves those models out of the compilation: a batch of MMG ships compiles
      only the models it uses;
    * ``far``: a ship may use the cross-flow hull at large drift or the four-quadrant propeller curves
      (vessel.far_models); False leaves them out (about a fifth of a cold start of such a ship).

    All True is the general kernel (:data:`run_serial`, :data:`run_parallel`). Every combination gives the
    general kernel's results to the bit; a narrower one is only faster. A driver first checks that its kind
    holds every vessel of the batch (:func:`kernel_fits`) and returns -1 without integrating if not, so a
    wrong choice is never silent. Each combination compiles on its first use.
    """
    key = (bool(shallow), bool(roll), bool(ext), bool(abk), bool(far))
    if key not in _DRIVERS:
        _DRIVERS[key] = _make_drivers(*key)
    return _DRIVERS[key]


def drivers_for(Ps: np.ndarray, E: np.ndarray, shallow: bool = False):
    """:func:`drivers` of the narrowest kind that holds a batch with parameter rows ``Ps`` and environment rows
    ``E`` (numpy, O(N): call it when these change, not every step); ``shallow`` True takes the shallow-water
    kind in deep water too (a batch that will meet shallow water later: one kind compiled, the same bits)."""
    return drivers(
        shallow=bool(shallow or (E[:, lo.E_T_OVER_H] != 0.0).any()),
        roll=bool((Ps[:, ROLL.on] != 0.0).any()),
        ext=bool((Ps[:, ENGINE.by_component] != 0.0).any() or (Ps[:, STEERING_GEAR.by_component] != 0.0).any()),
        abk=abkowitz_family(Ps),
        far=far_models(Ps),
    )


def _make_rhs(shallow: bool, roll: bool, ext: bool, abk: bool, far: bool):
    # closure constants, as in _make_drivers
    SHALLOW, ROLL, EXT = shallow, (True if roll else None), ext
    ABK, FAR = (True if abk else None), (True if far else None)

    @njit(cache=True)
    def rhs(P, x, inp, env, F, xdot):
        shallow_env = env if SHALLOW else None
        if shallow_env is None:
            H = None
        else:
            H = shallow_env[lo.E_T_OVER_H]
        derivatives_of(P, x, inp, env, F, xdot, H, ROLL, EXT, ABK, FAR)

    return rhs


_RHS: dict[tuple[bool, bool, bool, bool, bool], object] = {}


def derivatives_for(P: np.ndarray, env: np.ndarray, shallow: bool = False):
    """The right-hand side ``rhs(P, x, inp, env, F, xdot)`` (vessel.derivatives) compiled for the narrowest kind
    that holds one vessel with parameter row ``P`` in environment row ``env``, as :func:`drivers_for` chooses
    the drivers: the same specialisation of the equations as the drivers, so that a caller outside them (the
    linearisation in linear.py) compiles nothing more, with the general form's results to the bit; ``shallow``
    as in :func:`drivers_for`."""
    key = (
        bool(shallow or env[lo.E_T_OVER_H] != 0.0),
        bool(P[ROLL.on] != 0.0),
        bool(P[ENGINE.by_component] != 0.0 or P[STEERING_GEAR.by_component] != 0.0),
        abkowitz_family(P),
        far_models(P),
    )
    if key not in _RHS:
        _RHS[key] = _make_rhs(*key)
    return _RHS[key]


#: the general batch drivers: integrate every alive vessel of the batch, serially or with contiguous chunks of
#: vessels spread over threads (large batches); mark diverged vessels dead; return the number alive
run_serial, run_parallel = drivers(True, True, True, True, True)


@njit(cache=True)
def stage_batch(Ps, ship_index, X, U, E, F, K, stage, dt, method, alive, Xt):
    """:func:`rk_stage` ``stage`` of every vessel of a batch, with what the Python components gave at the stage
    states, ``F`` (N, NF), and the stage derivatives ``K`` (N, 4, NX): every vessel's right-hand side is
    evaluated (the components see the whole batch), only alive vessels finish a step. Returns the number
    alive after the last stage, else -1."""
    last = method == EULER or stage == 3
    count = 0
    for b in range(X.shape[0]):
        if last and not alive[b]:
            continue
        xs = X[b] if stage == 0 else Xt[b]
        H = E[b, lo.E_T_OVER_H]
        P = Ps[ship_index[b]]
        ok = rk_stage(P, X[b], U[b], E[b], F[b], K[b], stage, xs, Xt[b], dt, method, H, True, True, True, True, lo.NX)
        if last:
            alive[b] = ok
            count += ok
    return count if last else -1


@njit(cache=True)
def own_states_stage(Z, KZ, stage, dt, Zt):
    """The components' own states ``Zt`` (N, NZ) at which stage ``stage`` (1..3) evaluates, Z + h k from the
    stage before's rates ``KZ`` (N, 4, NZ), as :func:`rk_stage` forms the vessel's."""
    h = stage_h(stage, dt)
    for b in range(Z.shape[0]):
        for i in range(Z.shape[1]):
            Zt[b, i] = Z[b, i] + h * KZ[b, stage - 1, i]


@njit(cache=True)
def own_states_end(Z, KZ, dt, method, alive, Zend):
    """The components' own states one step on (:func:`combined`) into ``Zend``; a vessel whose own states would
    become non-finite is marked dead (it is then not advanced, as on any divergence)."""
    for b in range(Z.shape[0]):
        for i in range(Z.shape[1]):
            Zend[b, i] = combined(Z[b, i], KZ[b, 0, i], KZ[b, 1, i], KZ[b, 2, i], KZ[b, 3, i], dt, method)
            if not math.isfinite(Zend[b, i]):
                alive[b] = False


def run_with_components(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive, components, Z=None):
    """Integrate a batch whose right-hand side includes Python components: the stages of :func:`rk_stage`
    (the compiled drivers' own), run stage by stage over the whole batch (:func:`stage_batch`).

    ``components(Xs, Zs)`` returns, for the batch of stage states ``Xs`` (N, NX) and the components' own
    states ``Zs`` (N, NZ), what the components give the kernel, (N, NF) (forces X N, Y N, N N m, a user
    engine's shaft torque N m, a user steering gear's rudder rate rad/s: layout F_*), and the rates of their
    own states (N, NZ). It is called once per stage for the whole batch, so a vectorised component costs
    O(N) per evaluation. ``F`` (N, 3) is added to the forces. ``Z`` (N, NZ; None: no own states) is
    integrated in place with the same method and stages as the vessel's state. Every vessel's right-hand
    side is evaluated (the components see the whole batch); only alive vessels are advanced, and a vessel
    whose own states would become non-finite is stopped as on any divergence. Returns the number alive.
    """
    n = X.shape[0]
    Z = np.zeros((n, 0)) if Z is None else Z
    nz = Z.shape[1]
    K = np.zeros((n, 4, lo.NX))
    KZ = np.zeros((n, 4, nz))
    Xt = np.empty((n, lo.NX))
    Zt = np.empty((n, nz))
    Zend = np.empty((n, nz))
    Fs = np.empty((n, lo.NF))
    count = int(alive.sum())
    ns = n_stages(method)
    for _ in range(nsteps):
        for stage in range(ns):
            if stage > 0 and nz:
                own_states_stage(Z, KZ, stage, dt, Zt)
            Fc, Zdot = components(X, Z) if stage == 0 else components(Xt, Zt)
            Fs[:] = np.asarray(Fc, dtype=float).reshape(n, lo.NF)
            np.add(Fs[:, : lo.F_N + 1], F, out=Fs[:, : lo.F_N + 1])
            KZ[:, stage] = np.asarray(Zdot, dtype=float).reshape(n, nz)
            if stage == ns - 1 and nz:
                own_states_end(Z, KZ, dt, method, alive, Zend)
            done = stage_batch(Ps, ship_index, X, U, E, Fs, K, stage, dt, method, alive, Xt)
        count = done
        if nz:
            Z[alive] = Zend[alive]
    return count


@njit(cache=True)
def forces_batch(Ps, ship_index, X, U, E, out):
    """Component forces of a batch, out shape (N, N_OUT) (see vessel.FORCE_NAMES)."""
    for b in range(X.shape[0]):
        forces(Ps[ship_index[b]], X[b], U[b], E[b], out[b])
