"""Physical constants and unit conversions used at the edges (files, CLI, UDP, docs).

Inside the physics everything is SI with angles in radians.
"""

from __future__ import annotations

import math

KNOT_M_S = 1852.0 / 3600.0  # m/s per knot (international nautical mile, exact)
G_M_S2 = 9.80665  # standard gravity, m/s^2 (CGPM 1901)
RHO_SEAWATER_KG_M3 = 1025.0  # ITTC standard sea water at 15 degC, kg/m^3
NU_SEAWATER_M2_S = 1.18831e-6  # ITTC 7.5-02-01-03 kinematic viscosity of sea water at 15 degC, m^2/s
R_DRY_AIR_J_KGK = 287.058  # specific gas constant of dry air, J/(kg K)
P_ISA_PA = 101325.0  # ISA sea-level pressure, Pa
T_ISA_K = 288.15  # ISA sea-level temperature, K
DEG = math.pi / 180.0  # rad per degree
RPM = 1.0 / 60.0  # rev/s per rpm


def kn_to_m_s(speed_kn: float) -> float:
    """Knots -> m/s."""
    return speed_kn * KNOT_M_S


def m_s_to_kn(speed_m_s: float) -> float:
    """m/s -> knots."""
    return speed_m_s / KNOT_M_S
