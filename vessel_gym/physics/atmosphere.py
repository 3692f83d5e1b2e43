"""Environment & atmosphere: air density and wind loads on the above-water hull (Blendermann 1994).

Wind direction is meteorological ("from", clockwise from north). Wind loads act on the velocity of the air
relative to the ship over ground.
"""

from __future__ import annotations

import math

from numba import njit

from vessel_gym.physics import layout as lo
from vessel_gym.physics.units import P_ISA_PA, R_DRY_AIR_J_KGK, T_ISA_K


def air_density(pressure_pa: float = P_ISA_PA, temperature_k: float = T_ISA_K) -> float:
    """Dry-air density from the ideal-gas law, rho = p / (R T), kg/m^3 (1.225 at ISA sea level)."""
    if not (pressure_pa > 0.0 and temperature_k > 0.0):
        raise ValueError(
            f"air pressure and temperature must be positive, got {pressure_pa} Pa, {temperature_k} K"
        )
    return pressure_pa / (R_DRY_AIR_J_KGK * temperature_k)


@njit(cache=True)
def apparent_wind(u_g, v_g, psi, wind_speed, wind_from):
    """Apparent wind in the body frame: (speed m/s, angle from the bow rad, positive from starboard).

    (u_g, v_g) is the ship's velocity over ground in body axes.
    """
    # air velocity (earth, north/east): it blows *towards* wind_from + pi
    wn = -wind_speed * math.cos(wind_from)
    we = -wind_speed * math.sin(wind_from)
    c = math.cos(psi)
    s = math.sin(psi)
    wx = c * wn + s * we - u_g  # air relative to the ship, body axes
    wy = -s * wn + c * we - v_g
    V = math.sqrt(wx * wx + wy * wy)
    gamma = math.atan2(-wy, -wx) if V > 0.0 else 0.0
    return V, gamma


@njit(cache=True)
def blendermann_wind_forces(P, V_rw, gamma, rho_air):
    """Wind forces by Blendermann (1994), as presented in Fossen (2011) eq. 8.27-8.30.

    C_X = -CD_l (A_L/A_F) cos(g) / den,  C_Y = CD_t sin(g) / den,  den = 1 - delta/2 (1 - CD_l/CD_t) sin^2(2g)
    C_N = [s_L/L - 0.18 (g - pi/2)] C_Y, with CD_l = CD_l,AF(0) A_F/A_L for |g| <= pi/2, CD_l,AF(pi) A_F/A_L
    otherwise; X = q C_X A_F, Y = q C_Y A_L, N = q C_N A_L L, q = 1/2 rho_air V_rw^2.
    gamma is the angle the wind comes from relative to the bow (positive from starboard), so a head wind
    (gamma = 0) gives X < 0 and a wind from starboard pushes the ship to port (Y < 0).
    Returns (X, Y, N) in N, N, N m.
    """
    if P[lo.P_WIND_ON] == 0.0 or V_rw <= 0.0:
        return 0.0, 0.0, 0.0
    AF = P[lo.P_AFW]
    AL = P[lo.P_ALW]
    L = P[lo.P_L]
    CDt = P[lo.P_CDT]
    g = abs(gamma)
    CDl_AF = P[lo.P_CDL0] if g <= 0.5 * math.pi else P[lo.P_CDLPI]
    CDl = CDl_AF * AF / AL
    s2 = math.sin(2.0 * g)
    den = 1.0 - 0.5 * P[lo.P_BDELTA] * (1.0 - CDl / CDt) * s2 * s2
    CX = -CDl * (AL / AF) * math.cos(g) / den
    CY = CDt * math.sin(g) / den
    CN = (P[lo.P_SL] / L - 0.18 * (g - 0.5 * math.pi)) * CY
    q = 0.5 * rho_air * V_rw * V_rw
    sgn = -1.0 if gamma >= 0.0 else 1.0  # wind from starboard pushes to port
    return q * CX * AF, sgn * q * CY * AL, sgn * q * CN * AL * L
