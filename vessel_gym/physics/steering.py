"""Steering: steering gear (order -> actual rudder angle) and the MMG rudder force model."""

from __future__ import annotations

import math

from numba import njit

from vessel_gym.physics import layout as lo
from vessel_gym.physics.hull import drift_angle


@njit(cache=True)
def steering_gear_rate(P, delta, delta_c):
    """Rudder rate (rad/s) of a rate-limited first-order steering gear.

    The order is clipped to +-delta_max; the rudder follows (delta_c - delta)/T_delta, saturated at the
    maximum rate (MSS mariner.m uses the same form with T_delta = 1 s). IMO trials assume the gear moves the
    rudder at its rated speed (SOLAS II-1/29: 35 deg port to 30 deg starboard in 28 s).
    """
    dmax = P[lo.P_DMAX]
    dc = min(max(delta_c, -dmax), dmax)
    rate = (dc - delta) / P[lo.P_DTAU]
    rmax = P[lo.P_DRATE]
    return min(max(rate, -rmax), rmax)


@njit(cache=True)
def steering_gear_angle(P, delta0, delta_c, t):
    """Rudder angle (rad) ``t`` seconds after ``delta0`` with the order ``delta_c`` held: the exact solution of
    :func:`steering_gear_rate`'s equation.

    With e = delta_c - delta (order clipped to +-delta_max), the gear first slews at the maximum rate R while
    |e| > R T_delta, then e decays as exp(-t / T_delta). The integrators use it at their stage times instead
    of integrating this equation themselves: the lag is the fastest mode of a small model's equations (0.1 s,
    10 1/s on kvlcc2_l7), and solved exactly it no longer bounds the step an explicit method may take.
    """
    dmax = P[lo.P_DMAX]
    dc = min(max(delta_c, -dmax), dmax)
    tau = P[lo.P_DTAU]
    rmax = P[lo.P_DRATE]
    e = dc - delta0
    e_lin = rmax * tau  # |e| below which the gear leaves its rate limit
    if abs(e) > e_lin:
        t_slew = (abs(e) - e_lin) / rmax
        if t <= t_slew:
            return delta0 + math.copysign(rmax * t, e)
        return dc - math.copysign(e_lin, e) * math.exp(-(t - t_slew) / tau)
    return dc - e * math.exp(-t / tau)


@njit(cache=True)
def mmg_rudder_forces(P, u, v, r, delta, w_P, thrust):
    """Rudder forces, Yasukawa & Yoshimura (2015) eq. 20-36 (X_R, Y_R, N_R at midship): see
    :func:`mmg_rudder_forces_beta`, which this calls with the ship's speed and drift angle."""
    U = math.sqrt(u * u + v * v)
    return mmg_rudder_forces_beta(P, u, U, drift_angle(u, v, U), r, delta, w_P, thrust)


@njit(cache=True)
def mmg_rudder_forces_beta(P, u, U, beta, r, delta, w_P, thrust):
    """Rudder forces, Yasukawa & Yoshimura (2015) eq. 20-36 (X_R, Y_R, N_R at midship), at surge speed u,
    speed U = sqrt(u^2 + v^2) and drift angle beta (:func:`hull.drift_angle`), which the vessel computes once.

    F_N = 1/2 rho A_R U_R^2 f_alpha sin(alpha_R), alpha_R = delta - atan2(v_R, u_R),
    v_R = U gamma_R beta_R, beta_R = beta - l'_R r'.
    The propeller-slipstream speed u_R (eq. 28) is written with the thrust itself:
    u_R = eps sqrt(eta (u_P + kappa (sqrt(u_P^2 + 8 T/(rho pi D^2)) - u_P))^2 + (1 - eta) u_P^2),
    which equals the published form for n > 0 and stays finite at J -> 0 (bollard pull, low-speed
    harbour work). Astern thrust gives no slipstream over the rudder (u_R = eps u_P).
    The normal force is evaluated as F_N = 1/2 rho A_R f_alpha U_R (u_R sin(delta) - v_R cos(delta)),
    U_R = sqrt(u_R^2 + v_R^2): the same equation (expand sin(delta - atan2(v_R, u_R))) without the atan2,
    physical when the inflow reverses (ship moving astern) and 0 at U_R = 0.
    """
    L = P[lo.P_L]
    rho = P[lo.P_RHO]
    Ue = max(U, P[lo.P_U_MIN])
    u_P = u * (1.0 - w_P)
    D = P[lo.P_DP]
    eta = P[lo.P_ETA]
    eps = P[lo.P_EPS]
    if thrust > 0.0 and u_P >= 0.0 and P[lo.P_PROP_ON] > 0.0:
        slip = math.sqrt(u_P * u_P + 8.0 * thrust / (rho * math.pi * D * D))
        a = u_P + P[lo.P_KAPPA] * (slip - u_P)
        u_R = eps * math.sqrt(eta * a * a + (1.0 - eta) * u_P * u_P)
    else:
        u_R = eps * u_P
    rp = r * L / Ue
    beta_R = beta - P[lo.P_LRP] * rp
    gamma = P[lo.P_GRM] if beta_R < 0.0 else P[lo.P_GRP]
    v_R = Ue * gamma * beta_R if U >= P[lo.P_U_MIN] else U * gamma * beta_R
    U_R = math.sqrt(u_R * u_R + v_R * v_R)
    sd = math.sin(delta)
    cd = math.cos(delta)
    F_N = 0.5 * rho * P[lo.P_AR] * P[lo.P_FALPHA] * U_R * (u_R * sd - v_R * cd)
    X_R = -(1.0 - P[lo.P_TR]) * F_N * sd
    Y_R = -(1.0 + P[lo.P_AH]) * F_N * cd
    N_R = -(P[lo.P_XRP] + P[lo.P_AH] * P[lo.P_XHP]) * L * F_N * cd
    return X_R, Y_R, N_R
