"""Clarke, Gedling & Hine (1983) regressions for linear manoeuvring derivatives (pure numpy).

Reference: D. Clarke, P. Gedling and G. Hine (1983), "The application of manoeuvring criteria in
hull design using linear theory", Trans. RINA 125, 45–68; as printed in T. I. Fossen, *Handbook of
Marine Craft Hydrodynamics and Motion Control* (2nd ed. 2021, §6.4.1) and MSS / PythonVehicleSimulator
``clarke83``. The linear velocity derivatives come from rotating-arm tests, the acceleration
derivatives from PMM tests, both regressed on L, B, T and C_B of single-screw merchant hulls.

Clarke's values are in the SNAME prime system: force/(½ρU²L²), moment/(½ρU²L³), v' = v/U,
r' = rL/U, v̇' = v̇L/U², ṙ' = ṙL²/U² (``normalisation = "half_rho_L2_U2"``). Without the ½
(``"rho_L2_U2"``, the seed report's eq. 5–6) every value halves.

Axes: standard body axes (x forward, y starboard, z down); Y_v < 0, N_r < 0 for a normal hull.
Hydrodynamic derivatives only (no rigid-body mass terms).
"""

from __future__ import annotations

import math

NORMALISATIONS = ("rho_L2_U2", "half_rho_L2_U2")


def clarke83(L_m: float, B_m: float, T_m: float, C_B: float, normalisation: str = "half_rho_L2_U2") -> dict:
    """Linear sway/yaw derivatives of a hull from Clarke et al. (1983).

    Parameters are the length between perpendiculars, breadth, draught (m) and block coefficient.
    Returns ``{"Y_v", "Y_r", "N_v", "N_r", "Y_vdot", "Y_rdot", "N_vdot", "N_rdot"}`` as
    non-dimensional values in ``normalisation`` (``"half_rho_L2_U2"`` as published, or
    ``"rho_L2_U2"``).
    """
    if normalisation not in NORMALISATIONS:
        raise ValueError(f"normalisation must be one of {NORMALISATIONS} (got {normalisation!r})")
    if min(L_m, B_m, T_m) <= 0 or not 0 < C_B <= 1:
        raise ValueError(f"need L, B, T > 0 and 0 < C_B <= 1 (got {L_m}, {B_m}, {T_m}, {C_B})")
    BL, BT, TL = B_m / L_m, B_m / T_m, T_m / L_m
    s = math.pi * TL**2
    d = {
        "Y_v": -s * (1.0 + 0.40 * C_B * BT),
        "Y_r": -s * (-0.5 + 2.2 * BL - 0.080 * BT),
        "N_v": -s * (0.5 + 2.4 * TL),
        "N_r": -s * (0.25 + 0.039 * BT - 0.56 * BL),
        "Y_vdot": -s * (1.0 + 0.16 * C_B * BT - 5.1 * BL**2),
        "Y_rdot": -s * (0.67 * BL - 0.0033 * BT**2),
        "N_vdot": -s * (1.1 * BL - 0.041 * BT),
        "N_rdot": -s * (1.0 / 12.0 + 0.017 * C_B * BT - 0.33 * BL),
    }
    if normalisation == "rho_L2_U2":
        d = {k: 0.5 * v for k, v in d.items()}
    return d


def soding_surge_added_mass(volume_m3: float, L_m: float, rho_kg_m3: float) -> float:
    """Surge added mass A11 = −X_u̇ = 2.7 ρ ∇^(5/3) / L² (kg), Söding (1982), as in Fossen's MSS
    ``addedMassSurge``. Used only where no CFD value exists."""
    if min(volume_m3, L_m, rho_kg_m3) <= 0:
        raise ValueError("volume, L and rho must be > 0")
    return 2.7 * rho_kg_m3 * volume_m3 ** (5.0 / 3.0) / L_m**2
