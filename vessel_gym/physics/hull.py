"""Hull hydrodynamics: the nonlinear Abkowitz model and the MMG standard hull model.

Both are pure functions of the velocities *through the water* (current enters via relative velocity,
Fossen 2011 §10.3) and return hull forces (X, Y, N) at the body origin (midship), in N and N m.
Inertial (acceleration) derivatives live in the mass matrix, built once by :mod:`vessel_gym.physics.vessel`.

Low speed: both models are written in nondimensional velocities v' = v/U, r' = rL/U, which are undefined at
U = 0. Below ``U_min`` the nondimensionalising speed is held at ``U_min`` (forces then scale with U_min^2,
so they vanish smoothly as the ship stops) and |r'| is clipped at ``r_prime_max`` in the polynomial terms.
Published manoeuvring sets are fitted over |r'| <~ 1, so neither limit changes a manoeuvre at speed.
"""

from __future__ import annotations

import math

from numba import njit

from vessel_gym.physics import layout as lo
from vessel_gym.physics.crossflow import blend, blend_abkowitz, inside_polynomial_range, mmg_weight
from vessel_gym.physics.params import ABKOWITZ, BODY, HULL, LARGE_DRIFT, MMG
from vessel_gym.physics.shallow_water import hull_factors

# compiled callees are imported by name, not as attributes of their module: a recompilation of these functions for a
# loop over vessels (docs/performance.md, "Structure-of-arrays kernel") rebinds the names a function looks up,
# and reaches a callee only through such a name


@njit(cache=True, fastmath=False)
def _clip(x, lo_, hi):
    return lo_ if x < lo_ else (hi if x > hi else x)


@njit(cache=True)
def drift_angle(u, v, U):
    """Drift angle of the flow past the hull, beta = atan2(-v, |u|), rad, in the MMG sign convention
    (Yasukawa & Yoshimura 2015): the published beta = atan2(-v, u) ahead (u >= 0), and in sternway the angle
    between the flow and the ship's fore-aft line, so that beta stays in [-pi/2, pi/2] and the small-drift
    formulas of wake and rudder that read it (eq. 15-16, 26-27) are never evaluated at beta ~ +-180 deg,
    where atan2 jumps by 2 pi between v = -0 and v = +0. Continuous through u = 0, v = 0 and +-90 deg drift;
    0 at rest (U = sqrt(u^2 + v^2) <= 1e-9 m/s), where it is undefined. Wake and rudder share it."""
    return math.atan2(-v, abs(u)) if U > 1e-9 else 0.0


@njit(cache=True)
def abkowitz_forces(P, u, v, r, delta):
    """Abkowitz (1964) Taylor-series hull model with any set of named derivatives.

    Each term ``c * u'^a v'^b r'^c delta^d`` is one coefficient of the ship file (e.g. ``Y_vvr``). The
    normalisation is ``ABKOWITZ.force_norm * rho`` times L^2 U^2 (forces) or L^3 U^2 (moment): 1/2 for the SNAME
    prime system (Mariner, Chislett & Stroem-Tejsen 1965), 1 for the seed report's eq. 5-6.
    With ``U_ref > 0`` the surge variable is the perturbation u' = (u - U_ref)/U, as in MSS mariner.m.
    The seed's linear eq. 11 is the special case with only first-order terms.
    Returns (X, Y, N) in N, N, N m.
    """
    L = P[BODY.L_m]
    U = math.sqrt(u * u + v * v)
    Ue = max(U, P[HULL.U_min])
    # the surge perturbation u' = (u - U_ref)/U is a small quantity in the fitted range (PMM tests near the
    # approach speed); unbounded it grows as U_ref/U_min at rest, where it turned the bias terms Y_0uu, N_0uu
    # into a finite force and drove a stopped Mariner to 100 kn astern. |u'| <= 1 (the speed halved or doubled)
    # keeps every term O(U^2), so the hull forces vanish at rest; inside that range the model is as published.
    up = _clip((u - P[ABKOWITZ.U_ref_m_s]) / Ue, -1.0, 1.0)
    vp = v / Ue
    rp = _clip(r * L / Ue, -P[HULL.r_prime_max], P[HULL.r_prime_max])
    pu = (1.0, up, up * up, up * up * up, up * up * up * up)
    pv = (1.0, vp, vp * vp, vp * vp * vp, vp * vp * vp * vp)
    pr = (1.0, rp, rp * rp, rp * rp * rp, rp * rp * rp * rp)
    pd = (1.0, delta, delta * delta, delta * delta * delta, delta * delta * delta * delta)
    # one pass over the distinct monomials, each feeding the X, Y and N sums (vessel._pack_terms)
    Xs = 0.0
    Ys = 0.0
    Ns = 0.0
    for k in range(int(P[ABKOWITZ.n_monomials])):
        j = ABKOWITZ.monomials + lo.ABK_STRIDE * k
        m = pu[int(P[j])] * pv[int(P[j + 1])] * pr[int(P[j + 2])] * pd[int(P[j + 3])]
        Xs += P[j + 4] * m
        Ys += P[j + 5] * m
        Ns += P[j + 6] * m
    q = P[ABKOWITZ.force_norm] * L * L * Ue * Ue  # rho folded into FNORM
    X = q * Xs
    Y = q * Ys
    N = q * L * Ns
    # resistance curve of a propelled Abkowitz ship (R = R_res u|u|), see shipfile docs
    X -= P[ABKOWITZ.R_res] * u * abs(u)
    if P[ABKOWITZ.cross_flow_Cd] > 0.0:
        Yc, Nc = cross_flow_drag(P, v, r)
        Y += Yc
        N += Nc
    if P[LARGE_DRIFT.on] > 0.0 and not inside_polynomial_range(P, u, v, r):
        # outside the polynomial's fitted range: cross-flow model (crossflow.py)
        w = mmg_weight(P, u, v, r)
        if w < 1.0:
            Xd, Yd, Nd = _rudder_terms(P, delta)  # unpacked: numba does not inline a call with *args
            return blend_abkowitz(P, u, v, r, w, X, Y, N, Xd, Yd, Nd)
    return X, Y, N


@njit(cache=True)
def _rudder_terms(P, delta):
    """Sums (X, Y, N) of an Abkowitz set's pure rudder monomials c delta^e_d (no u', v', r'), nondimensional."""
    Xd = 0.0
    Yd = 0.0
    Nd = 0.0
    for k in range(int(P[ABKOWITZ.n_monomials])):
        j = ABKOWITZ.monomials + lo.ABK_STRIDE * k
        if P[j] == 0.0 and P[j + 1] == 0.0 and P[j + 2] == 0.0 and P[j + 3] > 0.0:
            m = delta ** int(P[j + 3])
            Xd += P[j + 4] * m
            Yd += P[j + 5] * m
            Nd += P[j + 6] * m
    return Xd, Yd, Nd


CROSS_FLOW_STRIPS = 12


@njit(cache=True)
def cross_flow_drag(P, v, r):
    """Quadratic cross-flow drag of a hull of constant draught T (Faltinsen 1990 §6; Fossen 2011 eq. 6.75).

    Y = -1/2 rho T C_d int |v + x r|(v + x r) dx,  N = -1/2 rho T C_d int x |v + x r|(v + x r) dx
    over -L/2..L/2 (midpoint rule, 12 strips). It supplies the nonlinear sway-yaw damping of a hull whose
    published model is linear, and the damping of a ship turning on the spot. Returns (Y, N) in N, N m.
    """
    L = P[BODY.L_m]
    h = L / CROSS_FLOW_STRIPS
    c = 0.5 * P[BODY.rho_kg_m3] * P[BODY.T_m] * P[ABKOWITZ.cross_flow_Cd] * h
    Y = 0.0
    N = 0.0
    for i in range(CROSS_FLOW_STRIPS):
        x = -0.5 * L + (i + 0.5) * h
        w = v + x * r
        f = -c * abs(w) * w
        Y += f
        N += x * f
    return Y, N


@njit(cache=True)
def mmg_hull_forces(P, u, v, r, H):
    """MMG standard hull forces, Yasukawa & Yoshimura (2015) eq. 8-10 (midship origin), at draught-to-depth
    ratio H = T/h (0: deep water).

    X_H = 1/2 rho L d U^2 X'_H(v', r'), Y_H likewise, N_H = 1/2 rho L^2 d U^2 N'_H(v', r').
    The resistance term -R'_0 changes sign with u (smoothly over |u| < U_min) so that the hull resists
    motion astern too; at speed ahead it is exactly the published -R'_0. In shallow water each coefficient
    is multiplied by its factor of :func:`~vessel_gym.physics.shallow_water.hull_factors` (all 1 at H = 0,
    where the result is bitwise the deep-water one).
    Returns (X, Y, N) in N, N, N m.
    """
    L = P[BODY.L_m]
    d = P[BODY.T_m]
    U = math.sqrt(u * u + v * v)
    Umin = P[HULL.U_min]
    Ue = max(U, Umin)
    vp = v / Ue
    rp = _clip(r * L / Ue, -P[HULL.r_prime_max], P[HULL.r_prime_max])
    su = u / math.sqrt(u * u + Umin * Umin)
    f = hull_factors(P, H)
    Xp = (
        -P[MMG.R_0] * f[0] * su
        + P[MMG.X_vv] * f[1] * vp * vp
        + P[MMG.X_vr] * f[2] * vp * rp
        + P[MMG.X_rr] * f[3] * rp * rp
        + P[MMG.X_vvvv] * f[4] * vp * vp * vp * vp
    )
    Yp = (
        P[MMG.Y_v] * f[5] * vp
        + P[MMG.Y_r] * f[6] * rp
        + P[MMG.Y_vvv] * f[7] * vp * vp * vp
        + P[MMG.Y_vvr] * f[8] * vp * vp * rp
        + P[MMG.Y_vrr] * f[9] * vp * rp * rp
        + P[MMG.Y_rrr] * f[10] * rp * rp * rp
    )
    Np = (
        P[MMG.N_v] * f[11] * vp
        + P[MMG.N_r] * f[12] * rp
        + P[MMG.N_vvv] * f[13] * vp * vp * vp
        + P[MMG.N_vvr] * f[14] * vp * vp * rp
        + P[MMG.N_vrr] * f[15] * vp * rp * rp
        + P[MMG.N_rrr] * f[16] * rp * rp * rp
    )
    q = 0.5 * P[BODY.rho_kg_m3] * L * d * Ue * Ue
    return q * Xp, q * Yp, q * L * Np


@njit(cache=True)
def hull_forces_at_depth(P, u, v, r, delta, H, abk, far):
    """Dispatch on the ship's hull model, at draught-to-depth ratio H = T/h (0: deep water; only the MMG
    hull has shallow-water corrections, see :mod:`~vessel_gym.physics.shallow_water`).

    ``abk``: True where the hull may be an Abkowitz polynomial, None where it is not. The kernels pass None for
    batches without one (integrate.drivers): numba prunes the branch on ``abk is not None`` before typing, so
    the Abkowitz model and its cross-flow blend are not compiled (a quarter of the hull chain's compile time).
    ``far`` likewise: True where the MMG hull may have the cross-flow model at large drift (``[large_drift]``),
    None where no ship of the kernel has it (vessel.far_models); the blend is then not compiled.
    Returns (X, Y, N) in N, N, N m."""
    kind = int(P[HULL.kind])
    if abk is not None:
        if kind == lo.HULL_ABKOWITZ:
            return abkowitz_forces(P, u, v, r, delta)
    if kind == lo.HULL_MMG:
        X, Y, N = mmg_hull_forces(P, u, v, r, H)
        if far is not None:
            if P[LARGE_DRIFT.on] > 0.0 and not inside_polynomial_range(P, u, v, r):
                # outside the polynomial's fitted range: cross-flow model (crossflow.py)
                return blend(P, u, v, r, X, Y, N, H)
        return X, Y, N
    return 0.0, 0.0, 0.0


@njit(cache=True)
def hull_forces(P, u, v, r, delta):
    """Hull forces in deep water (:func:`hull_forces_at_depth` at H = 0). Returns (X, Y, N) in N, N, N m.

    H is None, as in the deep-water drivers (integrate._run_range): the same specialisation of the hull
    functions serves both, where a float 0.0 would compile the hull chain a second time (~20 % of a cold start)
    for the same results (every shallow-water function returns its deep-water value for H None, as at H = 0,
    and compiles nothing else)."""
    H = None
    return hull_forces_at_depth(P, u, v, r, delta, H, True, True)


@njit(cache=True)
def hull_forces_not_abkowitz(P, u, v, r, delta):
    """:func:`hull_forces` of a ship whose hull is not an Abkowitz polynomial (MMG or a user's), compiled
    without the Abkowitz model: the specialisation the drivers of such a ship use (same results)."""
    H = None
    return hull_forces_at_depth(P, u, v, r, delta, H, None, True)


@njit(cache=True)
def hull_forces_near(P, u, v, r, delta):
    """:func:`hull_forces` of a ship with neither an Abkowitz hull nor the cross-flow model at large drift
    (vessel.far_models), compiled without either: the specialisation such a ship's drivers use."""
    H = None
    return hull_forces_at_depth(P, u, v, r, delta, H, None, None)
