"""Rudder and propeller inflow of Son & Nomoto (1982), as used by their high-speed container ship.

Son, K.H. and Nomoto, K. (1982). On the coupled motion of steering and rolling of a high-speed container
ship. Naval Architecture and Ocean Engineering 20, 73-83; as transcribed in Fossen's MSS ``container.m``.
The two differ from the MMG standard (Yasukawa & Yoshimura 2015) in form, not in idea:

* wake in a manoeuvre: 1 - w = 1 - w_P0 + tau ((v' + x'_P r')^2 + c_pv v' + c_pr r');
* flow across the rudder: v'_R = gamma_R v' + c_Rr r' + c_Rrrr r'^3 + c_Rrrv r'^2 v' (a polynomial fitted to
  captive tests, where MMG has gamma_R (v' + l'_R r'));
* flow along the rudder: u_R = epsilon u_a sqrt(1 + 8 kappa K_T / (pi J^2)), i.e. momentum theory with the
  propeller race contracted by kappa (MMG: eta, kappa, 1 + kappa (sqrt(...) - 1));
* rudder normal force F_N = -1/2 rho A_R f_alpha (u_R^2 + v_R^2) sin(alpha_R), alpha_R = delta + atan(v_R/u_R),
  with f_alpha = 6.13 Lambda/(Lambda + 2.25) (Fujii), and X_R = c_RX F_N sin(delta), Y_R = (1 + a_H) F_N
  cos(delta), N_R = (x'_R + a'_H x'_H) L F_N cos(delta).

Signs are vessel-gym's (and container.m's): delta > 0 turns the ship to starboard, F_N < 0 then.
"""

from __future__ import annotations

import math

from numba import njit

from vessel_gym.physics.params import BODY, HULL, PROPELLER, RUDDER


@njit(cache=True)
def son_nomoto_wake(P, u, v, r):
    """Wake fraction w_P (-) in a manoeuvre: w_P0 - tau ((v' + x'_P r')^2 + c_pv v' + c_pr r') at the
    velocities through the water u, v (m/s) and yaw rate r (rad/s); w_P0 at rest."""
    U = math.sqrt(u * u + v * v)
    if U < 1e-6:
        return P[PROPELLER.w_P0]
    vp = v / U
    rp = r * P[BODY.L_m] / U
    a = vp + P[PROPELLER.x_P_prime] * rp
    return P[PROPELLER.w_P0] - P[PROPELLER.tau_P] * (a * a + P[PROPELLER.c_pv] * vp + P[PROPELLER.c_pr] * rp)


@njit(cache=True)
def son_nomoto_rudder_forces(P, u, v, r, delta, u_a, thrust):
    """Rudder forces (X_R, Y_R, N_R) in N, N, N m at midship for the advance speed ``u_a`` (m/s) and the
    propeller thrust (N) of this instant.

    The race speed u_R^2 = epsilon^2 (u_a^2 + 8 kappa T / (pi rho D^2)) is container.m's
    (epsilon u_a)^2 (1 + 8 kappa K_T / (pi J^2)) written without the division by J (finite at n = 0 and
    u_a = 0); the bracket is held at >= 0 when the propeller pulls astern.
    """
    U = math.sqrt(u * u + v * v)
    Ue = max(U, P[HULL.U_min])
    L = P[BODY.L_m]
    vp = v / Ue
    rp = r * L / Ue
    vR = Ue * (
        P[RUDDER.gamma_R] * vp
        + P[RUDDER.c_Rr] * rp
        + P[RUDDER.c_Rrrr] * rp * rp * rp
        + P[RUDDER.c_Rrrv] * rp * rp * vp
    )
    D = P[PROPELLER.D_m]
    race = u_a * u_a + 8.0 * P[RUDDER.kappa] * thrust / (math.pi * P[BODY.rho_kg_m3] * D * D)
    uR = P[RUDDER.epsilon] * math.sqrt(max(race, 0.0))
    alphaR = delta + math.atan2(vR, uR) if uR > 0.0 else delta
    FN = -0.5 * P[BODY.rho_kg_m3] * P[RUDDER.A_R_m2] * P[RUDDER.f_alpha] * (uR * uR + vR * vR) * math.sin(alphaR)
    c = math.cos(delta)
    XR = P[RUDDER.c_RX] * FN * math.sin(delta)
    YR = (1.0 + P[RUDDER.a_H]) * FN * c
    NR = (P[RUDDER.x_R_prime] + P[RUDDER.a_H] * P[RUDDER.x_H_prime]) * L * FN * c
    return XR, YR, NR
