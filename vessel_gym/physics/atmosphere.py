"""Environment & atmosphere: air density and wind loads on the above-water hull (Blendermann 1994).

Wind direction is meteorological ("from", clockwise from north). Wind loads act on the velocity of the air
relative to the ship over ground (:func:`vessel_gym.physics.kinematics.relative_wind`).
"""

from __future__ import annotations

import math

from numba import njit

from vessel_gym.physics.kinematics import relative_wind
from vessel_gym.physics.params import BODY, WINDAGE
from vessel_gym.physics.units import P_ISA_PA, R_DRY_AIR_J_KGK, T_ISA_K


def air_density(pressure_pa: float = P_ISA_PA, temperature_k: float = T_ISA_K) -> float:
    """Dry-air density from the ideal-gas law, rho = p / (R T), kg/m^3 (1.225 at ISA sea level)."""
    if not (pressure_pa > 0.0 and temperature_k > 0.0):
        raise ValueError(
            f"air pressure and temperature must be positive, got {pressure_pa} Pa, {temperature_k} K"
        )
    return pressure_pa / (R_DRY_AIR_J_KGK * temperature_k)


@njit(cache=True)
def air_velocity_earth(wind_speed, wind_from):
    """Air velocity (north, east) in m/s of a wind of ``wind_speed`` (m/s) from ``wind_from`` (rad): it blows
    *towards* wind_from + pi. Stored in the environment row (layout.E_WIND_N, E_WIND_E)."""
    return -wind_speed * math.cos(wind_from), -wind_speed * math.sin(wind_from)


@njit(cache=True)
def apparent_wind(u_g, v_g, psi, wind_speed, wind_from):
    """Apparent wind in the body frame: (speed m/s, angle from the bow rad, positive from starboard).

    (u_g, v_g) is the ship's velocity over ground in body axes;
    :func:`~vessel_gym.physics.kinematics.relative_wind` does the kinematics.
    """
    w_n, w_e = air_velocity_earth(wind_speed, wind_from)
    V, gamma, _, _ = relative_wind(u_g, v_g, math.cos(psi), math.sin(psi), w_n, w_e)
    return V, gamma


@njit(cache=True)
def blendermann_wind_forces(P, V_rw, gamma, rho_air):
    """Wind forces by Blendermann (1994) at apparent wind speed V_rw (m/s) from gamma (rad, relative to the
    bow, positive from starboard): see :func:`blendermann_wind_loads`. Returns (X, Y, N) in N, N, N m."""
    return blendermann_wind_loads(P, V_rw, gamma, math.cos(gamma), math.sin(gamma), rho_air)


@njit(cache=True)
def blendermann_wind_loads(P, V_rw, gamma, cos_gamma, sin_gamma, rho_air):
    """Wind forces by Blendermann (1994), as presented in Fossen (2011) eq. 8.27-8.30.

    C_X = -CD_l (A_L/A_F) cos(g) / den,  C_Y = CD_t sin(g) / den,  den = 1 - delta/2 (1 - CD_l/CD_t) sin^2(2g)
    C_N = [s_L/L - 0.18 (g - pi/2)] C_Y, with CD_l = CD_l,AF(0) A_F/A_L for |g| <= pi/2, CD_l,AF(pi) A_F/A_L
    otherwise; X = q C_X A_F, Y = q C_Y A_L, N = q C_N A_L L, q = 1/2 rho_air V_rw^2.
    gamma is the angle the wind comes from relative to the bow (positive from starboard), so a head wind
    (gamma = 0) gives X < 0 and a wind from starboard pushes the ship to port (Y < 0); cos_gamma and sin_gamma
    are its cosine and sine (from :func:`~vessel_gym.physics.kinematics.relative_wind`), so that g = |gamma|
    has cos g = cos_gamma, sin g = |sin_gamma| and sin 2g = 2 sin g cos g without further trigonometry.
    Returns (X, Y, N) in N, N, N m.
    """
    if P[WINDAGE.on] == 0.0 or V_rw <= 0.0:
        return 0.0, 0.0, 0.0
    AF = P[WINDAGE.A_F_m2]
    AL = P[WINDAGE.A_L_m2]
    L = P[BODY.L_m]
    CDt = P[WINDAGE.CD_t]
    g = abs(gamma)
    cos_g = cos_gamma
    sin_g = abs(sin_gamma)
    CDl_AF = P[WINDAGE.CD_l_AF_0] if g <= 0.5 * math.pi else P[WINDAGE.CD_l_AF_pi]
    CDl = CDl_AF * AF / AL
    s2 = 2.0 * sin_g * cos_g
    den = 1.0 - 0.5 * P[WINDAGE.delta] * (1.0 - CDl / CDt) * s2 * s2
    CX = -CDl * (AL / AF) * cos_g / den
    CY = CDt * sin_g / den
    CN = (P[WINDAGE.s_L_m] / L - 0.18 * (g - 0.5 * math.pi)) * CY
    q = 0.5 * rho_air * V_rw * V_rw
    sgn = -1.0 if gamma >= 0.0 else 1.0  # wind from starboard pushes to port
    return q * CX * AF, sgn * q * CY * AL, sgn * q * CN * AL * L
