"""Four-quadrant open-water characteristics of Wageningen B-series propellers.

Over all four quadrants a propeller's thrust and torque are written in the hydrodynamic advance angle
beta = atan2(V_A, 0.7 pi n D) (0 bollard ahead, 90 deg locked propeller with the ship moving ahead, +-180 deg
bollard astern, -90 deg locked propeller with the ship moving astern) as

    T = C_T*(beta) 1/2 rho (V_A^2 + (0.7 pi n D)^2) (pi/4) D^2,
    Q = C_Q*(beta) 1/2 rho (V_A^2 + (0.7 pi n D)^2) (pi/4) D^3,
    C_T*(beta) = sum_k A_T(k) cos(k beta) + B_T(k) sin(k beta)   (k = 0..30; C_Q* likewise),

which stays finite through n = 0 and V_A = 0. The coefficients are those published by Roddy, Hess & Faller
(2006), "Neural network predictions of the 4-quadrant Wageningen propeller series", NSWCCD-50-TR-2006/004
(DTIC ADA455497), from the open-water tests of van Lammeren, van Manen & Oosterveld (1969): the report lists
100 C_T* and -1000 C_Q* for each propeller, and the tables below keep that form so that they can be read
against it. Sign convention here: T > 0 ahead, Q with the sign of n for a propeller absorbing power.

How a ship's own first-quadrant polynomial is joined to these curves is :func:`blended_coefficients`
(docs/physics.md, "Propeller in four quadrants").
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: names a ship file may give in ``[propeller] four_quadrant``; table i + 1 is packed as the code (0: none)
TABLE_NAMES = ("B4-70 P/D=0.8", "B4-70 P/D=1.0")
#: Fourier order of the published series (k = 0..30)
N_TERMS = 31
#: (0.7 pi)^2 pi / 8: T = C_T* rho n^2 D^4 x this at V_A = 0, i.e. K_T(J = 0) / C_T*(0), -
BOLLARD_FACTOR = 0.49 * math.pi**3 / 8.0

# Roddy, Hess & Faller (2006), Fourier coefficients of the B4-70 propellers (4 blades, A_E/A_0 = 0.70):
# rows k = 0..30 of (A_T, B_T) for 100 C_T* and (A_Q, B_Q) for -1000 C_Q*.
_B4_70_PD08 = (
    (2.8757, 0.0, -2.5783, 0.0),
    (13.007, -77.762, -15.727, 93.08),
    (0.62869, -1.3032, -0.6896, -0.20482),
    (2.8104, 10.58, -5.4402, -13.786),
    (-1.6832, -1.0413, 2.4674, 1.5588),
    (-4.4894, 4.5769, 5.0717, -6.8953),
    (0.37703, 1.4296, -1.1964, -0.19773),
    (3.1647, -0.39612, -3.1161, 3.1295),
    (-0.13492, -0.9917, 1.5838, -0.011366),
    (-1.9905, 2.0759, 1.4925, -4.0967),
    (0.17576, 0.90153, -0.90898, -0.3281),
    (1.975, -0.029877, -1.2135, 0.79539),
    (-0.11063, -0.56354, 0.50126, -0.26624),
    (-0.069828, 0.94773, -1.4143, -1.4536),
    (0.25665, 0.23681, -0.18873, 0.68666),
    (0.80681, -0.53204, 0.15422, 0.45499),
    (-0.18781, -0.071537, 0.17294, -0.84792),
    (0.29821, 0.52768, -1.333, -0.15911),
    (0.48643, 0.0174, -0.2262, 0.59733),
    (0.33893, -0.68105, 0.14299, 0.25445),
    (-0.26851, -0.204, -0.045335, -0.21991),
    (0.096098, 0.14086, -0.40051, 0.47535),
    (0.2145, -0.057914, 0.20629, 0.15397),
    (0.06644, -0.44898, -0.069705, -0.073692),
    (-0.1321, -0.11454, -0.18254, -0.022654),
    (0.016378, -0.012005, -0.056307, 0.47256),
    (0.012367, -0.11932, 0.24282, 0.13061),
    (-0.16113, -0.24427, 0.079606, -0.061311),
    (-0.10536, 0.049882, -0.069503, 0.0097692),
    (-0.041139, 0.063587, 0.080075, 0.13102),
    (-0.0089569, -0.073611, 0.042156, -0.019047),
)
_B4_70_PD10 = (
    (2.6617, 0.0, -2.2945, 0.0),
    (17.802, -74.797, -26.989, 110.38),
    (1.3828, -1.3632, -1.8758, -0.52852),
    (2.7871, 10.246, -6.3552, -16.544),
    (-1.624, -1.0865, 2.1668, 1.929),
    (-5.3084, 4.7346, 7.653, -8.448),
    (0.1918, 1.1355, -0.56516, -0.90714),
    (3.8318, -0.9318, -6.2654, 3.1042),
    (-0.22892, -0.72471, 1.9211, 0.68648),
    (-1.8656, 2.3747, 3.3456, -4.5196),
    (0.349, 0.86208, -1.2956, -1.0928),
    (2.2321, 0.0070224, -3.1294, -0.044966),
    (-0.35976, -0.36422, 1.2475, 0.72404),
    (0.13606, 0.91758, -1.4351, -1.5284),
    (0.47192, 0.089383, -0.83201, -0.23983),
    (0.87235, -0.59364, 0.034868, 1.6074),
    (-0.35748, -0.070954, 0.89981, -0.66184),
    (0.35955, 0.48825, -1.4247, -1.2084),
    (0.52896, -0.090587, -1.1064, 0.58384),
    (0.21045, -0.81163, 0.27359, 1.3397),
    (-0.27057, -0.056659, 0.6759, -0.29095),
    (0.10509, 0.12011, -0.57328, -0.089605),
    (0.27733, -0.13042, -0.22609, 0.54988),
    (-0.11596, -0.48187, 0.70691, 0.14626),
    (-0.1745, 0.045412, -0.030228, -0.4838),
    (0.040782, -0.019469, -0.46043, 0.38709),
    (0.099247, -0.21858, 0.25629, 0.72114),
    (-0.3465, -0.16314, 0.76092, -0.13767),
    (-0.12357, 0.14865, 0.0026235, -0.45823),
    (0.063929, 0.10185, -0.19316, 0.1052),
    (0.061933, -0.16735, 0.31487, 0.27547),
)


def _to_coefficients(published) -> np.ndarray:
    """(4, N_TERMS) array A_T, B_T, A_Q, B_Q of C_T*, C_Q* from the report's 100 C_T*, -1000 C_Q* rows."""
    a = np.asarray(published, dtype=float).T.copy()
    a[0:2] /= 100.0
    a[2:4] /= -1000.0
    return a


#: COEFFICIENTS[i] belongs to TABLE_NAMES[i]: rows A_T, B_T, A_Q, B_Q (of C_T*, C_Q*), columns k = 0..30
COEFFICIENTS = np.stack([_to_coefficients(_B4_70_PD08), _to_coefficients(_B4_70_PD10)])


def table_code(name: str) -> int:
    """The packed code of a four-quadrant table name (0: none, ``""``)."""
    return 0 if name == "" else TABLE_NAMES.index(name) + 1


@njit(cache=True)
def ct_cq_star(code, beta):
    """C_T*(beta), C_Q*(beta) (-) of table ``code`` (1-based, :data:`TABLE_NAMES`) at advance angle beta (rad)."""
    c = COEFFICIENTS[code - 1]
    ct = 0.0
    cq = 0.0
    for k in range(N_TERMS):
        ck = math.cos(k * beta)
        sk = math.sin(k * beta)
        ct += c[0, k] * ck + c[1, k] * sk
        cq += c[2, k] * ck + c[3, k] * sk
    return ct, cq


@njit(cache=True)
def blended_coefficients(code, beta, ct_0, cq_0, ct_90, cq_90):
    """C_T, C_Q (-) outside the first quadrant (beta not in [0, 90 deg]) for a ship whose own first-quadrant
    curves give C_T*, C_Q* = (ct_0, cq_0) at beta = 0 (bollard ahead) and (ct_90, cq_90) at 90 deg (n = 0).

    The published curves are scaled by the ratio of the ship's bollard-ahead value to the series' (thrust
    and torque each by its own ratio), which carries the series' four-quadrant shape over to a propeller of
    known bollard coefficients and makes quadrant 4 meet quadrant 1 at beta = 0. In quadrant 2 (90..180
    deg: ship ahead, propeller astern, the crash stop) the scaled curve is further shifted by its
    difference from the ship's locked-propeller value at 90 deg, the shift fading linearly in beta to none
    at 180 deg. So T and Q are continuous everywhere and quadrant 1 keeps the ship's own curves.
    """
    e0t, e0q = ct_cq_star(code, 0.0)
    rt = ct_0 / e0t
    rq = cq_0 / e0q
    ct, cq = ct_cq_star(code, beta)
    ct *= rt
    cq *= rq
    half_pi = 0.5 * math.pi
    if beta >= half_pi:
        w = (math.pi - beta) / half_pi
        e9t, e9q = ct_cq_star(code, half_pi)
        ct += w * (ct_90 - rt * e9t)
        cq += w * (cq_90 - rq * e9q)
    return ct, cq
