"""Shallow-water corrections of the MMG hull, propeller and rudder, after Taimuri et al. (2020).

Taimuri, Matusiak, Mikkola, Kujala & Hirdaris (2020), "A 6-DoF maneuvering model for the rapid estimation of
hydrodynamic actions in deep and shallow waters", Ocean Engineering 218:108103, collect one correction
factor per MMG coefficient as a function of the draught-to-depth ratio H = T/h and the hull's proportions
(block coefficient C_b, B/T, L/T, L/B):

* linear sway and yaw derivatives Y'_v, Y'_r, N'_r and the coupling terms N'_vvr, N'_vrr: Kijima, Nakiri,
  Tsutsui & Matsunaga (1990), "Prediction method of ship manoeuvrability in deep and shallow waters",
  MARSIM & ICSM 90, Tokyo -- f = 1/(1 - H)^n - H and cubic polynomials in H;
* the other hull derivatives (X'_vv, X'_vr, X'_rr, X'_vvvv, N'_v and the cubic terms): the slender-body
  factors K_0, K_1, K_2 of Ankudinov & Jakobsen (MARSIM 2000), functions of h/T - 1 and the hull's
  equivalent beam B_1 = C_b B (1 + B/L)^2;
* the propeller wake fraction w_P0, the thrust deduction t_P and the flow-straightening coefficient gamma_R:
  regressions in H and C_b L/T, C_b L/B, C_b B/L of Taimuri et al. (2020) eq. 40-42.

Every factor is 1 at H = 0 (deep water) and tends to 1 continuously as h/T grows; the one exception,
the thrust-deduction regression (1.002 at H = 0 for a VLCC), is applied relative to its deep-water value
so that deep water is recovered exactly. The flow-straightening regression switches between its two
published branches at H = 0.581 - 0.332 T/B (h/T ~ 2.2 for a VLCC) and is discontinuous there, as
published. R'_0, the added masses and l'_R are not corrected by the method (docs/physics.md).

The cross-flow hull that takes over from the polynomial at large drift (crossflow.py) reads the same H: its
linear terms take the factors above, its cross-flow drag coefficient C_D the lateral current force factor of
UFC 4-159-03 (2005), "Design: Moorings", eq. 11-13 (:func:`cross_flow_drag_factor`).

Validity: the regressions of Kijima et al. rest on captive tests down to h/T = 1.2, and Ankudinov's factors
grow without bound as h/T -> 1; the kernel evaluates no H beyond ``H_MAX`` (h/T = 1.2), and
:class:`~vessel_gym.physics.environment.Environment` refuses a depth below that. The corrections apply to
the MMG hull model only (their coefficients are MMG's); other hull models refuse a finite depth.
"""

from __future__ import annotations

import math

from numba import njit

from vessel_gym.physics import layout as lo
from vessel_gym.physics.params import BODY, PROPELLER

#: smallest depth-to-draught ratio the method covers (Kijima et al. 1990 captive tests), -
H_OVER_T_MIN = 1.2
#: largest draught-to-depth ratio T/h the kernel evaluates, -
H_MAX = 1.0 / H_OVER_T_MIN


@njit(cache=True)
def hull_proportions(P):
    """(C_b, B/T, L/T, L/B) of row ``P``: block coefficient from the mass, m / (rho L B T), and the ratios."""
    L = P[BODY.L_m]
    B = P[BODY.B_m]
    T = P[BODY.T_m]
    Cb = P[BODY.m] / (P[BODY.rho_kg_m3] * L * B * T)
    return Cb, B / T, L / T, L / B


@njit(cache=True)
def _kijima(H, n):
    """Kijima et al. (1990) factor of Y'_v and N'_r: 1/(1 - H)^n - H (1 at H = 0)."""
    return 1.0 / (1.0 - H) ** n - H


@njit(cache=True)
def hull_factors(P, H):
    """Factors on the 17 MMG hull coefficients at draught-to-depth ratio H = T/h (-), in the order
    (R_0, X_vv, X_vr, X_rr, X_vvvv, Y_v, Y_r, Y_vvv, Y_vvr, Y_vrr, Y_rrr, N_v, N_r, N_vvv, N_vvr, N_vrr, N_rrr).

    Taimuri et al. (2020) §3.3: Kijima et al. (1990) for Y'_v, Y'_r, N'_r, N'_vvr, N'_vrr; Ankudinov's
    K_0, K_1, K_2 for the rest. R'_0 is not corrected (factor 1). H is clipped to [0, H_MAX].
    """
    if H is None:  # a deep-water kernel (integrate.drivers): nothing below is compiled
        return (1.0,) * 17
    H = min(max(H, 0.0), H_MAX)
    if H == 0.0:
        return (1.0,) * 17
    Cb, BT, LT, LB = hull_proportions(P)
    # Ankudinov: slender-body factors in HT = h/T - 1 and the equivalent beam B_1 = C_b B (1 + B/L)^2
    HT = 1.0 / H - 1.0
    K0 = 1.0 + 0.0775 / HT**2 - 0.011 / HT**3 + 0.000068 / HT**5
    K1 = -0.0643 / HT + 0.0724 / HT**2 - 0.0113 / HT**3 + 0.0000767 / HT**5
    K2 = 0.0342 / HT if BT <= 4.0 else 0.137 * BT / HT
    b1 = Cb * BT * (1.0 + 1.0 / LB) ** 2  # B_1 / T
    f_nr = K0 + 0.5 * K1 * b1 + (1.0 / 3.0) * K2 * b1 * b1
    f_yr = K0 + 0.4 * K1 * b1 + (24.0 / 105.0) * K2 * b1 * b1
    g_nr = K0 + (8.0 / 15.0) * K1 * b1 + (40.0 / 105.0) * K2 * b1 * b1
    f_nv = K0 + K1 * b1 + K2 * b1 * b1
    f_yv = 1.5 * f_nr - 0.5
    # Kijima et al. (1990): linear derivatives and the yaw coupling terms
    cbt = Cb * BT  # C_b B / T
    A1 = -5.5 * cbt * cbt + 26.0 * cbt - 31.5
    A2 = 37.0 * cbt * cbt - 185.0 * cbt + 230.0
    A3 = -38.0 * cbt * cbt + 197.0 * cbt - 250.0
    k_yv = _kijima(H, 0.4 * cbt)
    k_yr = 1.0 + A1 * H + A2 * H * H + A3 * H * H * H
    k_nr = _kijima(H, 1.5 - 14.28 / LT)
    ctb = Cb / BT  # C_b T / B
    n_vvr = 1.0 + (91.0 * ctb - 25.0) * H + (-515.0 * ctb + 144.0) * H * H + (508.0 * ctb - 143.0) * H**3
    n_vrr = 1.0 + (40.0 * cbt - 88.0) * H + (-295.0 * cbt + 645.0) * H * H + (312.0 * cbt - 678.0) * H**3
    return (
        1.0,  # R_0
        f_yv,  # X_vv
        f_yr,  # X_vr
        f_nr,  # X_rr
        f_yv,  # X_vvvv
        k_yv,  # Y_v
        k_yr,  # Y_r
        f_yv,  # Y_vvv
        f_yv,  # Y_vvr
        f_yv,  # Y_vrr
        g_nr,  # Y_rrr
        f_nv,  # N_v
        k_nr,  # N_r
        f_yv,  # N_vvv
        n_vvr,  # N_vvr
        n_vrr,  # N_vrr
        g_nr,  # N_rrr
    )


#: lateral current force coefficient of a ship at T/h = 1 (UFC 4-159-03 eq. 11, recommended for currents of
#: 1.5 m/s or less), on L T, -
C_YC_SHALLOW = 3.2
#: exponent of T/h in UFC 4-159-03 eq. 11: 2 fits "a wide range of ship and barge tests", -
K_YC_SHALLOW = 2.0


@njit(cache=True)
def cross_flow_drag_factor(P, H):
    """Factor (-) on the cross-flow drag coefficient C_D of the large-drift hull (crossflow.py) at H = T/h:
    the lateral current force coefficient of UFC 4-159-03 (2005), "Design: Moorings", section 4-5.1, eq. 11,
    C_yc = C_0 + (C_1 - C_0) (T/h)^k with C_1 = 3.2 and k = 2, divided by its deep-water value C_0 of eq. 12-13,
    C_0 = 0.22 sqrt(L_wL^2 A_m / (B V)); with L_wL = L and A_m = B T (neither is in a ship file) that is
    0.22 sqrt(L / (C_b B)). 1 at H = 0; H is clipped to [0, H_MAX] like every factor here."""
    if H is None:
        return 1.0
    H = min(max(H, 0.0), H_MAX)
    if H == 0.0:
        return 1.0
    Cb, _BT, _LT, LB = hull_proportions(P)
    C0 = 0.22 * math.sqrt(LB / Cb)
    return 1.0 + (C_YC_SHALLOW / C0 - 1.0) * H**K_YC_SHALLOW


@njit(cache=True)
def wake_fraction(P, H):
    """Straight-running wake fraction w_P0 (-) at H = T/h: Taimuri et al. (2020) eq. 40,
    w_P0(h) = w_P0 (1 + (-4.932 + 0.6425 C_b L/T - 0.0165 (C_b L/T)^2) H^1.655)."""
    w0 = P[PROPELLER.w_P0]
    if H is None:
        return w0
    H = min(max(H, 0.0), H_MAX)
    if H == 0.0:
        return w0
    Cb, _BT, LT, _LB = hull_proportions(P)
    c = Cb * LT
    return w0 * (1.0 + (-4.932 + 0.6425 * c - 0.0165 * c * c) * H**1.655)


@njit(cache=True)
def _ctp(c, H):
    return 1.0 + (29.495 - 14.089 * c + 1.6486 * c * c) * (
        1.0 / 250.0 - 7.0 * H / 200.0 - 13.0 * H * H / 125.0
    )


@njit(cache=True)
def thrust_deduction(P, H):
    """Thrust deduction factor t_P (-) at H = T/h: Taimuri et al. (2020) eq. 41 on 1 - t_P, in the
    regressors C_b L/B and H, taken relative to its value at H = 0 so that deep water is exact."""
    tP = P[PROPELLER.t_P]
    if H is None:
        return tP
    H = min(max(H, 0.0), H_MAX)
    if H == 0.0:
        return tP
    Cb, _BT, _LT, LB = hull_proportions(P)
    c = Cb * LB
    return 1.0 - _ctp(c, H) / _ctp(c, 0.0) * (1.0 - tP)


@njit(cache=True)
def flow_straightening_factor(P, H):
    """Factor (-) on gamma_R^+ and gamma_R^- at H = T/h: Taimuri et al. (2020) eq. 42, two branches in the
    regressor C_b B/L, the deep branch (1 at H = 0) up to H = 0.581 - 0.332 T/B."""
    if H is None:
        return 1.0
    H = min(max(H, 0.0), H_MAX)
    if H == 0.0:
        return 1.0
    Cb, BT, _LT, LB = hull_proportions(P)
    c = Cb / LB  # C_b B / L
    if H <= 0.581 - 0.332 / BT:
        return 1.0 + (-135.25 + 2432.95 * c - 10137.7 * c * c) * H**4.81
    return 1.0 + (-10.258 + 178.207 * c - 686.25 * c * c) * (-3.854 + 13.665 * H - 10.468 * H * H)


def depth_ratio(depth_m: float, T_m: float) -> float:
    """Draught-to-depth ratio H = T/h (-) for the kernel's environment row: 0 in deep water (an infinite
    depth); ValueError (one line) below the method's range h/T >= H_OVER_T_MIN."""
    if math.isinf(depth_m):
        return 0.0
    if not depth_m > 0.0 or depth_m < H_OVER_T_MIN * T_m:
        raise ValueError(
            f"depth_m: {depth_m:g} m is h/T = {depth_m / T_m:.3g} for draught {T_m:g} m; the shallow-water "
            f"corrections (Kijima et al. 1990, Taimuri et al. 2020) hold for h/T >= {H_OVER_T_MIN:g} "
            f"(depth >= {H_OVER_T_MIN * T_m:.4g} m)"
        )
    return T_m / depth_m


@njit(cache=True, inline="always")
def set_charted_depth(env, k, depth_m, T_m):
    """Set the draught-to-depth ratio of vessel k's environment row ``env[k]`` (``Simulation.env``) for a depth
    read from a chart under a moving ship of draught ``T_m`` (m): H = T / max(depth_m, H_OVER_T_MIN T), 0 for an
    infinite depth. Unlike :func:`depth_ratio` (a depth the user sets, refused below the method's range) a
    charted depth between the draught and 1.2 T is taken as h/T = 1.2, the shallowest the method covers: the
    ship sails on into it and the chart's own rule (grounding below the draught) decides what happens there.
    The ship's hull must be one the corrections are for (:func:`check_hull`)."""
    env[k, lo.E_T_OVER_H] = 0.0 if math.isinf(depth_m) else T_m / max(depth_m, H_OVER_T_MIN * T_m)


def check_hull(ship, depth_m: float) -> None:
    """Refuse a finite depth for a ship whose hull is not the MMG model: the corrections are factors on the
    MMG coefficients and on the MMG propeller and rudder, with no counterpart for an Abkowitz polynomial or a
    user's hull (ValueError, one line naming the ship and its hull model)."""
    # the [hull] model key: "mmg" only for the MMG table (a user's hull is an import path "pkg.module:Class");
    # read by name so that this module, which the cross-flow hull imports, does not import the ship-file schema
    if math.isinf(depth_m) or ship.hull.model == "mmg":
        return
    raise ValueError(
        f"{ship.name}: depth_m = {depth_m:g} m, but the shallow-water corrections (Taimuri et al. 2020) are "
        f"defined for the MMG hull model and this ship's [hull] model is {ship.hull.model!r}; "
        "use depth_m = inf (deep water)"
    )
