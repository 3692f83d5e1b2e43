"""Hull forces at any drift angle: the cross-flow model of Yoshimura, Nakao & Ishibashi (2009), for an MMG or an
Abkowitz hull (its linear terms converted from the set, :func:`_abkowitz_linear_terms`).

The MMG hull polynomial (hull.mmg_hull_forces; Yasukawa & Yoshimura 2015 eq. 8-10) is a Taylor fit to captive
tests at small drift (|beta| <~ 20 deg) and moderate yaw rate. Outside that range its even terms run away: the
KVLCC2's X'_vvvv v'^4 makes the surge force +39.9 MN at 4 m/s and 90 deg drift (against -1.2 MN straight ahead),
so a dead ship in a beam sea gathered headway. Yoshimura, Nakao & Ishibashi (2009), "Unified mathematical model
for ocean and harbour manoeuvring", MARSIM 2009, replace the nonlinear terms by cross-flow drag integrated along
the hull and keep the linear derivatives, written so that each term has the sign the flow direction gives it:

    X_H = 1/2 rho L d [ X'_0(chi) u U + X'_vr v r L ]
    Y_H = 1/2 rho L d [ Y'_v v |u| + Y'_r r L u - C_D int |v + C_rY r L x'| (v + C_rY r L x') dx' ]
    N_H = 1/2 rho L^2 d [ N'_v v u + N'_r r L |u| - C_D int |v + C_rN r L x'| (v + C_rN r L x') x' dx' ]

over x' = -1/2..1/2, with X'_0 = -R'_0 straight ahead and -R'_0,astern straight astern, interpolated linearly in
the flow angle chi = atan2(|v|, u) in [0, pi] (the angle between the flow past the hull and the bow direction).
At 90 deg drift u = 0, so the surge force is X'_vr v r L only: no surge gain from sway. The sway force at
90 deg is -1/2 rho L d C_D v|v| (C_D is the hull's lateral drag coefficient on L d). Yaw damping N'_r r L |u|
and the cross flow of a ship turning on the spot keep their sign in sternway, while the Munk moment N'_v v u and
the lift Y'_r r L u reverse with u. X'_vr, Y'_v, Y'_r, N'_v, N'_r are the ship's MMG derivatives (MMG axes:
the added-mass term (m + m_y) v r stays in the equations of motion, vessel.pack), or those converted from an
Abkowitz set.

Blend (our choice, documented in docs/physics.md): the published MMG set is used unchanged inside its fitted
range and the cross-flow model outside it, with weight w = w_beta(chi) * w_r(|r'|) on the MMG forces (times w_u(|u'|) for an
Abkowitz set in the surge perturbation u' = (u - U_ref)/U), each a C1 smoothstep from 1 to 0 between two limits of the ship file ([large_drift]). A pure rotation at rest
(|r'| -> infinity) and any sternway (chi -> 180 deg) are pure cross-flow model. Every term is continuous through
u = 0, v = 0 and chi = 90/180 deg, odd in (v, r) for Y and N and even for X (port/starboard mirror), and
vanishes at rest.

Shallow water (an MMG hull at draught-to-depth ratio H = T/h > 0, the ratio the MMG polynomial gets, clipped
where shallow_water.py clips it): the linear terms take the factors of the same MMG coefficients
(shallow_water.hull_factors) and C_D that of the lateral current force of UFC 4-159-03 eq. 11-13
(shallow_water.cross_flow_drag_factor), in Y and N alike; X'_0 is not corrected (:func:`yoshimura_forces_at_depth`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from vessel_gym.physics import layout as lo
from vessel_gym.physics.params import ABKOWITZ, BODY, HULL, LARGE_DRIFT, MMG, put, put_keys
from vessel_gym.physics.schema import SpecError
from vessel_gym.physics.sections import LargeDrift
from vessel_gym.physics.shallow_water import cross_flow_drag_factor, hull_factors


def check(ld: LargeDrift, hull_model: str, where: str, resistance_N: float = 0.0) -> None:
    """Cross-key rules of ``[large_drift]``; a SpecError names the file and key."""
    # a user's hull (an import path) replaces the built-in hull, and with it this table, which then has no
    # effect (a copied built-in file keeps working)
    if hull_model == "abkowitz" and resistance_N <= 0.0:
        # the cross-flow model's surge force is the straight-ahead resistance turned with the flow angle
        raise SpecError(
            f"{where} [large_drift]: an Abkowitz hull needs [hull] resistance_N > 0 (the straight-ahead "
            "resistance R'_0 of the cross-flow model)"
        )
    if ld.cross_flow_drift_min_deg <= ld.mmg_drift_max_deg:
        raise SpecError(
            f"{where} [large_drift] cross_flow_drift_min_deg: {ld.cross_flow_drift_min_deg:g} deg must exceed "
            f"mmg_drift_max_deg = {ld.mmg_drift_max_deg:g} deg"
        )
    if ld.cross_flow_r_prime_min <= ld.mmg_r_prime_max:
        raise SpecError(
            f"{where} [large_drift] cross_flow_r_prime_min: {ld.cross_flow_r_prime_min:g} must exceed "
            f"mmg_r_prime_max = {ld.mmg_r_prime_max:g}"
        )
    if ld.cross_flow_u_prime_min <= ld.polynomial_u_prime_max:
        raise SpecError(
            f"{where} [large_drift] cross_flow_u_prime_min: {ld.cross_flow_u_prime_min:g} must exceed "
            f"polynomial_u_prime_max = {ld.polynomial_u_prime_max:g}"
        )


def _abkowitz_monomial(P: np.ndarray, e: tuple[int, int, int, int]) -> np.ndarray:
    """(c_X, c_Y, c_N) of the Abkowitz monomial u'^e_u v'^e_v r'^e_r delta^e_d in a packed row (0 if absent)."""
    for k in range(int(P[ABKOWITZ.n_monomials])):
        j = ABKOWITZ.monomials + lo.ABK_STRIDE * k
        if tuple(int(x) for x in P[j : j + 4]) == e:
            return P[j + 4 : j + 7].copy()
    return np.zeros(3)


def _abkowitz_linear_terms(P: np.ndarray) -> None:
    """The cross-flow model's linear terms from a packed Abkowitz hull (its polynomial and resistance curve
    already in ``P``), so that the two models have the same forces to first order in v and r at u = U_ref.

    The Yoshimura form is written for equations of motion that carry (m + m_y) v r + x_G m r^2 in surge and
    (m + m_x) u r, x_G m u r in sway and yaw (MMG axes). An Abkowitz set carries the rigid body's part of
    these in its equations (coriolis = 'separate') or in its derivatives (Mariner: X_rv = m'). The surge v r
    and sway u r terms have the form of X'_vr v r L and Y'_r r L u, so they are folded in: the converted
    X'_vr, Y'_r are the set's total derivatives. The yaw u r term is split off: N'_r r L |u| is damping (the
    hydrodynamic part), -x_G m u r is kinematics and reverses with u (LARGE_DRIFT.C_N_ur); likewise x_G m r^2 (LARGE_DRIFT.C_X_rr).
    """
    L, d = P[BODY.L_m], P[BODY.T_m]
    # an Abkowitz coefficient on FNORM L^2 U^2 (L^3 for N) -> on 1/2 rho L d U^2 (L for N); rho is in FNORM
    to_mmg = P[ABKOWITZ.force_norm] * L / (0.5 * P[BODY.rho_kg_m3] * d)
    _, Y_v, N_v = _abkowitz_monomial(P, (0, 1, 0, 0))
    _, Y_r, N_r = _abkowitz_monomial(P, (0, 0, 1, 0))
    X_vr = _abkowitz_monomial(P, (0, 1, 1, 0))[0]
    mxG = P[BODY.m] * P[BODY.x_G_m]
    q3 = 0.5 * P[BODY.rho_kg_m3] * L**3 * d  # turns a yaw coefficient in kg m into one on 1/2 rho L^2 d U^2, times L/U
    P[LARGE_DRIFT.R_0] = P[ABKOWITZ.R_res] / (0.5 * P[BODY.rho_kg_m3] * L * d)
    P[LARGE_DRIFT.X_vr] = X_vr * to_mmg
    P[LARGE_DRIFT.Y_v] = Y_v * to_mmg
    P[LARGE_DRIFT.Y_r] = Y_r * to_mmg
    P[LARGE_DRIFT.N_v] = N_v * to_mmg
    # the set's N_r r L U holds -(x_G m - c_N,ur) u r of kinematics; the rest is hydrodynamic damping
    P[LARGE_DRIFT.N_r] = N_r * to_mmg + (mxG - P[BODY.CN_ur]) / q3
    P[LARGE_DRIFT.C_N_ur] = -(mxG - P[BODY.CN_ur])
    P[LARGE_DRIFT.C_X_rr] = mxG - P[BODY.CX_rr]


def pack(P: np.ndarray, ld: LargeDrift | None) -> None:
    """Fill the record params.LARGE_DRIFT of a parameter row (off when ``ld`` is None): the table's keys and
    the fields derived from them. Called after the hull fields are packed: the linear terms are the MMG set's,
    or converted from the Abkowitz set."""
    if ld is None:
        put(P, LARGE_DRIFT, on=0.0)
        return
    put_keys(P, LARGE_DRIFT, ld)
    drift_max = math.radians(ld.mmg_drift_max_deg)
    put(
        P,
        LARGE_DRIFT,
        on=1.0,
        mmg_drift_max=drift_max,
        tan_mmg_drift_max=math.tan(drift_max) * (1.0 - DRIFT_TEST_MARGIN),
        cross_flow_drift_min=math.radians(ld.cross_flow_drift_min_deg),
        mmg_r_prime_max_squared=(ld.mmg_r_prime_max * (1.0 - DRIFT_TEST_MARGIN)) ** 2,
        polynomial_u_prime_max_squared=(ld.polynomial_u_prime_max * (1.0 - DRIFT_TEST_MARGIN)) ** 2,
    )
    if int(P[HULL.kind]) == lo.HULL_ABKOWITZ:
        _abkowitz_linear_terms(P)
        return
    put(P, LARGE_DRIFT, **{name: P[getattr(MMG, name)] for name in ("R_0", "X_vr", "Y_v", "Y_r", "N_v", "N_r")})


#: strips of the cross-flow integral (midpoint rule): the integrand |s| s is C1, so the error is O(1/N^2),
#: 0.3 % of the pure-yaw moment at N = 20
CROSS_FLOW_STRIPS = 20


@njit(cache=True)
def cross_flow_integrals(v, rL, C_rY, C_rN):
    """int |v + C_rY rL x'|(v + C_rY rL x') dx' and int |v + C_rN rL x'|(v + C_rN rL x') x' dx' over
    x' = -1/2..1/2 (midpoint rule), in m^2/s^2; ``rL`` is r L in m/s."""
    h = 1.0 / CROSS_FLOW_STRIPS
    IY = 0.0
    IN = 0.0
    for i in range(CROSS_FLOW_STRIPS):
        x = -0.5 + (i + 0.5) * h
        sy = v + C_rY * rL * x
        sn = v + C_rN * rL * x
        IY += abs(sy) * sy
        IN += abs(sn) * sn * x
    return IY * h, IN * h


@njit(cache=True)
def yoshimura_forces_at_depth(P, u, v, r, H):
    """Hull forces of the Yoshimura, Nakao & Ishibashi (2009) model (module docstring), midship origin, with the
    linear terms :func:`pack` put in the row (and, for an Abkowitz hull, the kinematic x_G m terms its
    equations of motion leave out), at draught-to-depth ratio H = T/h (0: deep water).

    In shallow water (H > 0, an MMG hull: shallow_water.check_hull refuses a depth for any other) the linear
    terms X'_vr, Y'_v, Y'_r, N'_v, N'_r take the factors the MMG polynomial gives the same coefficients
    (shallow_water.hull_factors: Kijima et al. 1990, Ankudinov), and C_D that of the lateral current force
    (shallow_water.cross_flow_drag_factor: UFC 4-159-03 eq. 11), in the sway force and the yaw moment alike.
    The surge resistance X'_0 is not corrected, as R'_0 is not in the polynomial. At H = 0 nothing is evaluated.
    Returns (X, Y, N) in N, N, N m."""
    L = P[BODY.L_m]
    U = math.sqrt(u * u + v * v)
    chi = math.atan2(abs(v), u) if U > 0.0 else 0.0
    R0 = P[LARGE_DRIFT.R_0]
    X0 = -(R0 + (P[LARGE_DRIFT.R_0_astern] - R0) * chi / math.pi)
    rL = r * L
    IY, IN = cross_flow_integrals(v, rL, P[LARGE_DRIFT.C_rY], P[LARGE_DRIFT.C_rN])
    CD = P[LARGE_DRIFT.C_D]
    X_vr, Y_v, Y_r, N_v, N_r = P[LARGE_DRIFT.X_vr], P[LARGE_DRIFT.Y_v], P[LARGE_DRIFT.Y_r], P[LARGE_DRIFT.N_v], P[LARGE_DRIFT.N_r]
    if H is not None:  # None: a deep-water kernel, where this is not compiled
        if H > 0.0:
            f = hull_factors(P, H)  # the order of hull_factors: X_vr 2, Y_v 5, Y_r 6, N_v 11, N_r 12
            X_vr, Y_v, Y_r, N_v, N_r = X_vr * f[2], Y_v * f[5], Y_r * f[6], N_v * f[11], N_r * f[12]
            CD = CD * cross_flow_drag_factor(P, H)
    q = 0.5 * P[BODY.rho_kg_m3] * L * P[BODY.T_m]
    X = q * (X0 * u * U + X_vr * v * rL) + P[LARGE_DRIFT.C_X_rr] * r * r
    Y = q * (Y_v * v * abs(u) + Y_r * rL * u - CD * IY)
    N = q * L * (N_v * v * u + N_r * rL * abs(u) - CD * IN) + P[LARGE_DRIFT.C_N_ur] * u * r
    return X, Y, N


#: relative margin of :func:`inside_polynomial_range` (its bounds shortened by it), -: a state that close to a bound
#: takes the full weight, so the forces are the same to the bit
DRIFT_TEST_MARGIN = 1e-9


@njit(cache=True)
def yoshimura_forces(P, u, v, r):
    """:func:`yoshimura_forces_at_depth` in deep water. Returns (X, Y, N) in N, N, N m.

    H is None, as in the deep-water drivers, so that one specialisation of the cross-flow functions serves both
    (hull.hull_forces says why)."""
    H = None
    return yoshimura_forces_at_depth(P, u, v, r, H)


@njit(cache=True)
def _fade(x, x1, x2):
    """1 for x <= x1, 0 for x >= x2, a C1 smoothstep between."""
    if x <= x1:
        return 1.0
    if x >= x2:
        return 0.0
    t = (x - x1) / (x2 - x1)
    return 1.0 - t * t * (3.0 - 2.0 * t)


@njit(cache=True)
def mmg_weight(P, u, v, r):
    """Weight of the hull polynomial (MMG or Abkowitz) in the blend (module docstring): 1 inside its fitted
    range."""
    U = math.sqrt(u * u + v * v)
    rL = abs(r) * P[BODY.L_m]
    if U <= 0.0:
        return 1.0 if rL == 0.0 else 0.0  # at rest both models give 0; turning on the spot: cross flow
    w_beta = _fade(math.atan2(abs(v), u), P[LARGE_DRIFT.mmg_drift_max], P[LARGE_DRIFT.cross_flow_drift_min])
    if w_beta == 0.0:
        return 0.0
    w = w_beta * _fade(rL / U, P[LARGE_DRIFT.mmg_r_prime_max], P[LARGE_DRIFT.cross_flow_r_prime_min])
    if P[ABKOWITZ.U_ref_m_s] > 0.0 and int(P[HULL.kind]) == lo.HULL_ABKOWITZ:
        # an Abkowitz set in the surge perturbation u' = (u - U_ref)/U is fitted near U_ref (hull.abkowitz_forces)
        Ue = max(U, P[HULL.U_min])
        w *= _fade(abs(u - P[ABKOWITZ.U_ref_m_s]) / Ue, P[LARGE_DRIFT.polynomial_u_prime_max], P[LARGE_DRIFT.cross_flow_u_prime_min])
    return w


@njit(cache=True)
def inside_polynomial_range(P, u, v, r):
    """Whether (u, v, r) is clearly inside the hull polynomial's fitted range, where :func:`mmg_weight` is 1, tested
    without square root, atan2 or division (the hull calls it on every evaluation; the blend only where False):
    the flow angle by |v| < u tan(beta_1), |r'| by (r L)^2 < U^2 r'_1^2, an Abkowitz set's |u'| by
    (u - U_ref)^2 < max(U^2, U_min^2) u'_1^2, each bound shortened by DRIFT_TEST_MARGIN. The margin is far beyond
    the rounding of either form, so True implies that mmg_weight returns exactly 1; near a bound it is False and
    mmg_weight decides (a NaN gives False)."""
    if not abs(v) < u * P[LARGE_DRIFT.tan_mmg_drift_max]:
        return False
    rL = r * P[BODY.L_m]
    U2 = u * u + v * v
    if not rL * rL < U2 * P[LARGE_DRIFT.mmg_r_prime_max_squared]:
        return False
    if P[ABKOWITZ.U_ref_m_s] > 0.0 and int(P[HULL.kind]) == lo.HULL_ABKOWITZ:
        du = u - P[ABKOWITZ.U_ref_m_s]
        Umin = P[HULL.U_min]
        return du * du < max(U2, Umin * Umin) * P[LARGE_DRIFT.polynomial_u_prime_max_squared]
    return True


@njit(cache=True)
def blend(P, u, v, r, X_mmg, Y_mmg, N_mmg, H):
    """The MMG forces (X_mmg, Y_mmg, N_mmg, at draught-to-depth ratio H = T/h) inside their fitted range, the
    cross-flow model at the same H outside, blended. Returns (X, Y, N) in N, N, N m."""
    w = mmg_weight(P, u, v, r)
    if w == 1.0:
        return X_mmg, Y_mmg, N_mmg
    Xc, Yc, Nc = yoshimura_forces_at_depth(P, u, v, r, H)
    return w * X_mmg + (1.0 - w) * Xc, w * Y_mmg + (1.0 - w) * Yc, w * N_mmg + (1.0 - w) * Nc


@njit(cache=True)
def blend_abkowitz(P, u, v, r, w, X_p, Y_p, N_p, X_d, Y_d, N_d):
    """With the polynomial's weight w (:func:`mmg_weight`, < 1), an Abkowitz hull's polynomial forces (X_p, Y_p, N_p: hull, rudder terms, resistance curve and any
    Hoerner cross-flow drag) inside its fitted range, outside it the cross-flow model plus the rudder.

    The rudder of a set with delta terms ([rudder] model = 'derivatives') goes with the hull polynomial; in
    the cross-flow model it keeps the set's own rudder terms (X_d, Y_d, N_d: the sums of its pure delta
    monomials, nondimensional) at the dynamic pressure of the flow along the ship, u|u| instead of U^2: a
    rudder in reversed flow turns the ship the other way and one in pure cross flow gives no lift (our
    choice, as the MMG rudder does in reversed flow, docs/physics.md). Weights sum to one, so a Hoerner drag
    of the polynomial side and the model's C_D integral, the same cross-flow drag, are never added.
    Returns (X, Y, N) in N, N, N m."""
    Xc, Yc, Nc = yoshimura_forces(P, u, v, r)
    L = P[BODY.L_m]
    qd = P[ABKOWITZ.force_norm] * L * L * u * abs(u)
    Xc += qd * X_d
    Yc += qd * Y_d
    Nc += qd * L * N_d
    return w * X_p + (1.0 - w) * Xc, w * Y_p + (1.0 - w) * Yc, w * N_p + (1.0 - w) * Nc
