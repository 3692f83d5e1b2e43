"""Flat-plate friction: the ITTC-1957 correlation line and the first-cell wall distance for a target y+.

Used to size the mesh's wall cells (:mod:`cfd.case.sizing`) and to split and extrapolate the towed
resistance (:mod:`cfd.analysis`, :mod:`cfd.report`).
"""

from __future__ import annotations

import math


def skin_friction_flat_plate(re: float) -> float:
    """Schlichting's turbulent flat-plate skin friction C_f = (2 log10 Re − 0.65)^−2.3 (local, at x = L)."""
    return (2.0 * math.log10(re) - 0.65) ** -2.3


def wall_distance(U_m_s: float, L_m: float, nu_m2_s: float, yplus: float) -> float:
    """Distance (m) of the first cell centre from the wall for a target y+ (flat plate of length L).

    u_τ = U √(C_f/2), y = y⁺ ν / u_τ — the seed report's method (boundary layer developing over Lpp).
    """
    cf = skin_friction_flat_plate(U_m_s * L_m / nu_m2_s)
    u_tau = U_m_s * math.sqrt(0.5 * cf)
    return yplus * nu_m2_s / u_tau


def ittc57(re: float) -> float:
    """ITTC-1957 model-ship correlation line C_F = 0.075 / (log10 Re − 2)²."""
    return 0.075 / (math.log10(re) - 2.0) ** 2
