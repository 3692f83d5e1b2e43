"""Steering: steering gear (order -> actual rudder angle) and the MMG rudder force model."""

from __future__ import annotations

import math

from numba import njit

from vessel_gym.physics.hull import drift_angle
from vessel_gym.physics.params import BODY, HULL, PROPELLER, RUDDER, STEERING_GEAR
from vessel_gym.physics.shallow_water import flow_straightening_factor


@njit(cache=True)
def steering_gear_rate(P, delta, delta_c):
    """Rudder rate (rad/s) of a rate-limited first-order steering gear.

    The order is clipped to +-delta_max; the rudder follows (delta_c - delta)/T_delta, saturated at the
    maximum rate (MSS mariner.m uses the same form with T_delta = 1 s). IMO trials assume the gear moves the
    rudder at its rated speed (SOLAS II-1/29: 35 deg port to 30 deg starboard in 28 s).
    """
    dmax = P[STEERING_GEAR.delta_max]
    dc = min(max(delta_c, -dmax), dmax)
    rate = (dc - delta) / P[STEERING_GEAR.time_constant_s]
    rmax = P[STEERING_GEAR.delta_rate_max]
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
    dmax = P[STEERING_GEAR.delta_max]
    dc = min(max(delta_c, -dmax), dmax)
    tau = P[STEERING_GEAR.time_constant_s]
    rmax = P[STEERING_GEAR.delta_rate_max]
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
    """Rudder forces in deep water, Yasukawa & Yoshimura (2015) eq. 20-36 (X_R, Y_R, N_R at midship): see
    :func:`mmg_rudder_forces_beta`, which this calls with the ship's speed and drift angle."""
    U = math.sqrt(u * u + v * v)
    return mmg_rudder_forces_beta(P, u, U, drift_angle(u, v, U), r, delta, w_P, thrust, 0.0)


@njit(cache=True)
def mmg_rudder_forces_beta(P, u, U, beta, r, delta, w_P, thrust, H):
    """Rudder forces, Yasukawa & Yoshimura (2015) eq. 20-36 (X_R, Y_R, N_R at midship), at surge speed u,
    speed U = sqrt(u^2 + v^2) and flow drift angle beta (:func:`hull.drift_angle`, in [-pi/2, pi/2]), which
    the vessel computes once, and draught-to-depth ratio H = T/h (0: deep water). In shallow water the
    hull straightens the flow to the rudder more: gamma_R^+- times
    :func:`shallow_water.flow_straightening_factor` (Taimuri et al. 2020); the wake w_P comes in corrected.

    F_N = 1/2 rho A_R U_R^2 f_alpha sin(alpha_R), alpha_R = delta - atan2(v_R, u_R),
    v_R = U gamma_R beta_R, beta_R = beta - l'_R r'.
    The propeller-slipstream speed u_R (eq. 28) is written with the thrust itself:
    u_R = eps sqrt(eta (u_P + kappa (sqrt(u_P^2 + 8 T/(rho pi D^2)) - u_P))^2 + (1 - eta) u_P^2),
    which equals the published form for n > 0 and stays finite at J -> 0 (bollard pull, low-speed
    harbour work). Astern thrust gives no slipstream over the rudder (u_R = eps u_P).
    The normal force is evaluated as F_N = 1/2 rho A_R f_alpha U_R (u_R sin(delta) - v_R cos(delta)),
    U_R = sqrt(u_R^2 + v_R^2): the same equation (expand sin(delta - atan2(v_R, u_R))) without the atan2,
    physical when the inflow reverses (ship moving astern: the lift reverses with u_R) and 0 at U_R = 0.
    Below U_min, v_R is evaluated as gamma_R (U beta - l'_R r L) (= U gamma_R beta_R), with no division by U,
    so that a ship turning on the spot still sees the cross flow at its rudder.

    Sternway (u < 0; the ahead form at u >= 0 is unchanged). Flow straightening by the hull (gamma_R, l'_R),
    the rudder wake (1 - w_R = eps (1 - w_P)) and the hull-rudder interaction (t_R, a_H) are properties of
    ahead motion, where the rudder works in the hull's wake (Yasukawa & Yoshimura 2015 §2.4). Going astern
    the rudder is the leading appendage and sees the undisturbed flow: u_R = u, gamma_R = 1, the lateral
    inflow at its geometric position x_R, no interaction. This follows the four-quadrant rudder of Kose et al. (1982) and
    Yoshimura, Nakao & Ishibashi (2009), where flow straightening and interaction act only with the rudder
    downstream of the hull; the blending below is our choice (docs/physics.md). These ahead-only terms fade with the
    astern share of the motion, s_a = max(-u, 0) / U (0 at 90 deg drift, 1 straight astern), so the forces are
    continuous through u = 0 and +-90 deg drift. An ahead-turning propeller (T > 0) while moving astern adds
    its jet at bollard strength, eps sqrt(eta) kappa sqrt(8 T / (rho pi D^2)), continuous with the ahead
    form at u = 0; an astern-turning one adds nothing (its race goes forward, away from the rudder).
    """
    L = P[BODY.L_m]
    rho = P[BODY.rho_kg_m3]
    u_P = u * (1.0 - w_P)
    D = P[PROPELLER.D_m]
    eta = P[RUDDER.eta]
    eps = P[RUDDER.epsilon]
    s_a = 0.0
    jet = thrust > 0.0 and P[PROPELLER.on] > 0.0
    if u >= 0.0:
        if jet:
            slip = math.sqrt(u_P * u_P + 8.0 * thrust / (rho * math.pi * D * D))
            a = u_P + P[RUDDER.kappa] * (slip - u_P)
            u_R = eps * math.sqrt(eta * a * a + (1.0 - eta) * u_P * u_P)
        else:
            u_R = eps * u_P
    else:
        s_a = -u / U
        u_R = u
        if jet:
            u_R += eps * math.sqrt(eta) * P[RUDDER.kappa] * math.sqrt(8.0 * thrust / (rho * math.pi * D * D))
    l_R = P[RUDDER.l_R_prime] + s_a * (P[RUDDER.x_R_prime] - P[RUDDER.l_R_prime])
    if U >= P[HULL.U_min]:  # the published form, in the published order of operations
        beta_R = beta - l_R * (r * L / U)
    else:  # here beta_R stands for U beta_R (m/s), without the division: a ship turning on the spot
        beta_R = U * beta - l_R * r * L
    gamma = P[RUDDER.gamma_R_minus] if beta_R < 0.0 else P[RUDDER.gamma_R_plus]
    if H is not None:  # None: a deep-water kernel, where this is not compiled
        if H > 0.0:
            gamma *= flow_straightening_factor(P, H)
    gamma += s_a * (1.0 - gamma)
    v_R = U * gamma * beta_R if U >= P[HULL.U_min] else gamma * beta_R
    U_R = math.sqrt(u_R * u_R + v_R * v_R)
    sd = math.sin(delta)
    cd = math.cos(delta)
    F_N = 0.5 * rho * P[RUDDER.A_R_m2] * P[RUDDER.f_alpha] * U_R * (u_R * sd - v_R * cd)
    ahead = 1.0 - s_a
    a_H = ahead * P[RUDDER.a_H]
    X_R = -(1.0 - ahead * P[RUDDER.t_R]) * F_N * sd
    Y_R = -(1.0 + a_H) * F_N * cd
    N_R = -(P[RUDDER.x_R_prime] + a_H * P[RUDDER.x_H_prime]) * L * F_N * cd
    return X_R, Y_R, N_R
