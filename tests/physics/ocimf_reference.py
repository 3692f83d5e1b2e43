"""Published steady current loads on a loaded VLCC over 0-180 deg of flow angle: the reference data of the
oblique-towing validation (tests/physics/test_oblique_towing.py). A ship held in a uniform current of speed V
is a ship towed obliquely at V through still water, so these are captive oblique-towing forces.

Source. Oil Companies International Marine Forum (1994), "Prediction of Wind and Current Loads on VLCCs",
2nd edition, Witherby, London: force coefficients from model tests of VLCCs, reproduced in OCIMF (2008),
"Mooring Equipment Guidelines", 3rd edition (MEG3), Annex A:

    Figures A5-A9  C_Xc, longitudinal current force, loaded tanker, by water depth/draught and bow shape
    Figure  A10    C_Yc, lateral current force, loaded tanker, by water depth/draught
    Figure  A11    C_XYc, current yaw moment about midships, loaded tanker
    Figure  A12    C_Xc, ballasted tanker (40 % T): mean curve and the max/min envelope drawn around it

    F_Xc = 1/2 rho V^2 L_BP T C_Xc,  F_Yc = 1/2 rho V^2 L_BP T C_Yc,  M_XYc = 1/2 rho V^2 L_BP^2 T C_XYc

the prime system of the MMG hull (1/2 rho L d U^2, 1/2 rho L^2 d U^2), so the coefficients compare directly.

Convention (1994 edition onwards; the MEG2 note to its Fig. 2.8, MEG3 Annex A section A1 "Sign convention and
coordinate system", and the OPTIMOOR Users Guide App. C-1.2, which records that the 1994 edition moved the zero
from the bow to the stern and reversed the angle sense): theta is measured anticlockwise (seen from above) from
the stern, theta = 0 is a current flowing from stern to bow; x is forward, y to port, the moment positive
anticlockwise (bow to port). The data confirm it: C_Xc(0) = +0.036 pushes the ship forward in a current from
astern, and C_XYc/C_Yc puts the lateral centre of pressure at the leading end at small angles (the Munk
moment), aft for theta < 90 deg and forward for theta > 90 deg. In the ship's axes (x forward, y starboard,
N bow to starboard, midship origin) the ship moves through the water at u = -V cos(theta), v = +V sin(theta),
the flow angle from the bow is chi = 180 deg - theta, and X' = C_Xc, Y' = -C_Yc, N' = -C_XYc (:func:`ship_axes`).

Digitisation. The MEG3 figures as digitised in the public repository vamseeachanta/digitalmodel, file
docs/domains/charts/phase2/ocimf/ocimf_coefficient_explorer.html (commit 3303708d3b07fc3bf6ef7d841f3f60a478c5c788,
plot data of its "OCIMF Coef.xlsx" workbook). C_Yc and C_XYc are read on a pixel grid of 1/323 = 0.0031 and
1/2730 = 0.00037 (values are whole multiples of these, offset by the zero line), C_Xc at 5 deg steps to 1e-5;
rounded here to 4 decimals (below the grid). An independent reading of the same curves in MEG2 (a public
spreadsheet transcription, scribd.com document 663684625 "OCIMF Calculation", of MEG2 Figures 2.5, 2.6 and 2.8)
is kept for the check of the digitisation (:func:`digitising_fraction`). The two agree on the longitudinal
curves within 0.007 (3 % of the peak each); on the shallow-water lateral curves within 0.1 except with the stern
leading at 10-20 deg (C_Yc 1.13 against 0.74 at 20 deg), which the tolerance of Y' takes in.
Independently of OCIMF, the US Navy's mooring design method gives the deep-water lateral coefficient at
theta = 90 deg from the hull's proportions (:func:`ufc_deep_water_lateral`): 0.594 on L_pp T for the KVLCC2,
against 0.585 here.
"""

from __future__ import annotations

import numpy as np

#: OCIMF current angle theta, deg (anticlockwise from the stern; 0 = current from astern, 180 = from ahead)
THETA_DEG = np.arange(0.0, 181.0, 10.0)

#: MEG3 Fig. A10, loaded tanker, water depth/draught > 6 (deep water): lateral current force coefficient C_Yc
C_YC_DEEP = np.array(
    [0.0031, 0.0774, 0.1579, 0.2446, 0.3313, 0.4118, 0.4737, 0.5232, 0.5728, 0.5851,
     0.5789, 0.5356, 0.4799, 0.4056, 0.3251, 0.2322, 0.1579, 0.0650, 0.0031]
)  # fmt: skip

#: MEG3 Fig. A11, loaded tanker, water depth/draught > 6: current yaw moment coefficient C_XYc about midships
C_XYC_DEEP = np.array(
    [-0.0004, -0.0311, -0.0560, -0.0707, -0.0795, -0.0795, -0.0707, -0.0546, -0.0370, -0.0179,
     0.0055, 0.0245, 0.0421, 0.0524, 0.0538, 0.0451, 0.0348, 0.0172, -0.0004]
)  # fmt: skip

#: MEG3 Figs. A5-A9, loaded tanker, water depth/draught >= 4.4 (deep water), conventional bow: C_Xc
C_XC_DEEP_CONVENTIONAL = np.array(
    [0.0361, 0.0350, 0.0308, 0.0219, 0.0032, -0.0182, -0.0307, -0.0269, -0.0125, 0.0090,
     0.0285, 0.0408, 0.0399, 0.0184, -0.0061, -0.0222, -0.0299, -0.0321, -0.0337]
)  # fmt: skip

#: the same, cylindrical bow
C_XC_DEEP_CYLINDRICAL = np.array(
    [0.0478, 0.0451, 0.0417, 0.0323, 0.0169, 0.0008, -0.0060, -0.0049, 0.0028, 0.0174,
     0.0335, 0.0420, 0.0399, 0.0184, -0.0061, -0.0222, -0.0299, -0.0321, -0.0337]
)  # fmt: skip

#: MEG3 Figs. A5-A9, loaded tanker, water depth/draught 1.1, conventional bow (for the digitisation check)
C_XC_WDT11_CONVENTIONAL = np.array(
    [0.0375, -0.0023, -0.0108, 0.0368, 0.0779, 0.0933, 0.0893, 0.0694, 0.0384, -0.0009,
     -0.0465, -0.0872, -0.1112, -0.1077, -0.0529, 0.0503, 0.0670, -0.0027, -0.0358]
)  # fmt: skip

#: MEG3 Figs. A10 and A11, loaded tanker, water depth/draught 1.1: C_Yc and C_XYc (for the digitisation check)
C_YC_WDT11 = np.array(
    [0.0047, 0.3386, 0.7370, 1.1002, 1.4810, 1.8442, 2.1957, 2.5179, 2.8048, 2.8689,
     2.7922, 2.5689, 2.2812, 1.8760, 1.5765, 1.5409, 1.2941, 0.6661, 0.0029]
)  # fmt: skip
C_XYC_WDT11 = np.array(
    [-0.0004, -0.1440, -0.2978, -0.3432, -0.3095, -0.3007, -0.2875, -0.2509, -0.1747, -0.0927,
     0.0084, 0.1081, 0.1813, 0.2165, 0.2648, 0.3044, 0.2707, 0.1476, 0.0004]
)  # fmt: skip

#: MEG3 Fig. A10, loaded tanker, water depth/draught 1.2, 1.5 and 3.0: C_Yc (the shallow-water validation of the
#: cross-flow hull, tests/physics/test_large_drift_shallow.py; same digitisation, same pixel grid)
C_YC_WDT12 = np.array(
    [0.0031, 0.4737, 1.0557, 1.1672, 1.3901, 1.5944, 1.8421, 2.0402, 2.2136, 2.3189,
     2.2941, 2.1455, 1.9536, 1.7802, 1.6068, 1.3034, 0.9876, 0.4118, 0.0031]
)  # fmt: skip
C_YC_WDT15 = np.array(
    [0.0031, 0.2632, 0.6594, 0.9690, 1.2291, 1.3963, 1.5201, 1.6006, 1.6563, 1.6687,
     1.6440, 1.5882, 1.4954, 1.3653, 1.1796, 0.9443, 0.6161, 0.2879, 0.0031]
)  # fmt: skip
C_YC_WDT30 = np.array(
    [0.0031, 0.1207, 0.3003, 0.4613, 0.6099, 0.7276, 0.8328, 0.9133, 0.9690, 0.9876,
     0.9690, 0.9009, 0.8019, 0.6718, 0.5418, 0.3994, 0.2570, 0.1269, 0.0031]
)  # fmt: skip
#: C_Yc of Fig. A10 by water depth/draught (the deep-water curve is for > 6)
C_YC_BY_DEPTH = {1.1: C_YC_WDT11, 1.2: C_YC_WDT12, 1.5: C_YC_WDT15, 3.0: C_YC_WDT30}

#: MEG3 Fig. A12, ballasted tanker: C_Xc mean curve and the max/min envelope the figure draws around it
C_XC_BALLAST_MEAN = np.array(
    [0.0562, 0.0597, 0.0623, 0.0623, 0.0537, 0.0398, 0.0220, 0.0140, 0.0096, 0.0072,
     0.0042, 0.0018, -0.0054, -0.0210, -0.0376, -0.0491, -0.0477, -0.0433, -0.0375]
)  # fmt: skip
C_XC_BALLAST_MAX = np.array(
    [0.0635, 0.0667, 0.0691, 0.0696, 0.0626, 0.0483, 0.0308, 0.0229, 0.0180, 0.0159,
     0.0130, 0.0107, 0.0042, -0.0104, -0.0273, -0.0384, -0.0384, -0.0337, -0.0282]
)  # fmt: skip
C_XC_BALLAST_MIN = np.array(
    [0.0462, 0.0485, 0.0511, 0.0517, 0.0448, 0.0312, 0.0120, 0.0046, 0.0001, -0.0026,
     -0.0053, -0.0077, -0.0148, -0.0290, -0.0467, -0.0592, -0.0574, -0.0531, -0.0475]
)  # fmt: skip

#: angles of the MEG2 spreadsheet reading, deg (same convention)
MEG2_THETA_DEG = np.array([0.0, 10.0, 20.0, 40.0, 60.0, 80.0, 100.0, 120.0, 140.0, 160.0, 170.0, 180.0])
#: MEG2 Fig. 2.6, loaded tanker, water depth/draught 1.1, conventional bow: C_Xc
MEG2_C_XC_WDT11_CONVENTIONAL = np.array(
    [0.036, 0.0, -0.01, 0.08, 0.09, 0.04, -0.05, -0.11, -0.06, 0.07, 0.0, -0.035]
)  # fmt: skip
#: MEG2 Fig. 2.5, loaded tanker, water depth/draught 1.1: lateral coefficients at the aft and forward
#: perpendiculars (the 1977 edition's form): C_Yc = C_YF + C_YA, C_XYc = (C_YF - C_YA)/2 about midships
MEG2_C_YA_WDT11 = np.array([0.0, 0.46, 0.9, 1.1, 1.41, 1.57, 1.35, 0.93, 0.5, 0.35, 0.175, 0.0])
MEG2_C_YF_WDT11 = np.array([0.0, 0.105, 0.23, 0.45, 0.88, 1.26, 1.415, 1.325, 1.05, 0.94, 0.43, 0.0])
#: MEG2 Fig. 2.8, ballasted tanker, mean curve: C_Xc
MEG2_C_XC_BALLAST = np.array(
    [0.055, 0.0575, 0.06, 0.053, 0.02, 0.0085, 0.005, -0.005, -0.04, -0.0475, -0.0425, -0.038]
)  # fmt: skip


def ship_axes(theta_deg):
    """The OCIMF curves in the ship's axes: (chi_deg, X', Y', N') with chi the flow angle from the bow
    (0: moving ahead, 180: moving astern) and the ship moving to starboard through the water (v > 0);
    the bow-shape-dependent X' is returned as the (conventional, cylindrical) pair."""
    i = np.searchsorted(THETA_DEG, theta_deg)
    if not np.all(THETA_DEG[i] == theta_deg):
        raise ValueError(f"theta_deg must be on the 10 deg grid of the digitisation, got {theta_deg}")
    X = np.stack([C_XC_DEEP_CONVENTIONAL[i], C_XC_DEEP_CYLINDRICAL[i]])
    return 180.0 - np.asarray(theta_deg, dtype=float), X, -C_YC_DEEP[i], -C_XYC_DEEP[i]


def scatter_band_fraction() -> float:
    """Half-width of the max/min envelope of MEG3 Fig. A12 over the peak of its mean curve: the scatter of the
    measurements about the curve OCIMF draws through them, the only scatter band OCIMF publishes, as a fraction
    of the curve's peak. A particular VLCC (not among the tested hulls) cannot be expected closer."""
    half = 0.5 * (C_XC_BALLAST_MAX - C_XC_BALLAST_MIN)
    return float(half.max() / np.abs(C_XC_BALLAST_MEAN).max())


def digitising_fraction(coefficient: str) -> float:
    """Largest difference between the two independent readings (MEG3 digitisation, MEG2 spreadsheet) of the
    published curves of one coefficient ("X", "Y" or "N"), over that curve's peak, halved: each reading's error
    as a fraction of the peak. For Y and N the MEG2 reading is of the perpendicular coefficients, combined."""
    idx = np.searchsorted(THETA_DEG, MEG2_THETA_DEG)
    pairs = {
        "X": (
            (C_XC_WDT11_CONVENTIONAL, MEG2_C_XC_WDT11_CONVENTIONAL),
            (C_XC_BALLAST_MEAN, MEG2_C_XC_BALLAST),
        ),
        "Y": ((C_YC_WDT11, MEG2_C_YF_WDT11 + MEG2_C_YA_WDT11),),
        "N": ((C_XYC_WDT11, 0.5 * (MEG2_C_YF_WDT11 - MEG2_C_YA_WDT11)),),
    }[coefficient]
    return 0.5 * max(float(np.abs(meg3[idx] - meg2).max() / np.abs(meg3).max()) for meg3, meg2 in pairs)


#: KVLCC2 waterline length and midship-section coefficient (SIMMAN 2008, KVLCC1/KVLCC2 geometry page), m and -
KVLCC2_L_WL_M = 325.5
KVLCC2_C_M = 0.998


def ufc_deep_water_lateral(L_pp_m, B_m, T_m, displacement_m3, L_wL_m, C_M):
    """Deep-water lateral current force coefficient at 90 deg on L_pp T, from UFC 4-159-03 (2005), "Design:
    Moorings", section 4-5.1, equations 11-13: C_0 = 0.22 sqrt(chi_s) on L_wL T with chi_s = L_wL^2 A_m / (B V)
    and A_m = C_M B T the midship section area (the square root, lost in some text copies of the document, is
    what its FFG-7 example, Table 4-6, needs); converted to L_pp T."""
    chi_s = L_wL_m**2 * C_M * B_m * T_m / (B_m * displacement_m3)
    return 0.22 * np.sqrt(chi_s) * L_wL_m / L_pp_m


#: tolerance of the comparison of each coefficient, as a fraction of its curve's peak over 0-180 deg: the
#: published scatter of the OCIMF data plus the error of the digitisation (each derived from the published
#: curves above, not from the model)
TOLERANCE_FRACTION = {k: scatter_band_fraction() + digitising_fraction(k) for k in ("X", "Y", "N")}
