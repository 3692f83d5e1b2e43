"""Sea state: uniform current and irregular waves (spectrum and mean second-order drift loads).

Current direction is oceanographic ("towards", clockwise from north). Wave direction is "from".
First-order (wave-frequency) motions are out of scope: a manoeuvring model feels the mean drift.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from vessel_gym.physics import layout as lo
from vessel_gym.physics.params import BODY, WAVE_DRIFT
from vessel_gym.physics.units import G_M_S2


@njit(cache=True)
def current_earth(speed, towards):
    """Current velocity (north, east) in m/s from speed (m/s) and direction towards (rad)."""
    return speed * math.cos(towards), speed * math.sin(towards)


def jonswap(omega: np.ndarray, Hs: float, Tp: float, gamma: float = 3.3) -> np.ndarray:
    """JONSWAP spectrum S(omega) in m^2 s/rad (DNV-RP-C205 (2010) eq. 3.5.5.1).

    S = A_gamma S_PM gamma^exp(-(omega - omega_p)^2 / (2 sigma^2 omega_p^2)),
    S_PM = 5/16 Hs^2 omega_p^4 omega^-5 exp(-5/4 (omega/omega_p)^-4), A_gamma = 1 - 0.287 ln(gamma),
    sigma = 0.07 (omega <= omega_p), 0.09 (omega > omega_p). gamma = 1 gives Pierson-Moskowitz.
    """
    omega = np.asarray(omega, dtype=float)
    if Hs <= 0.0:
        return np.zeros_like(omega)
    wp = 2.0 * math.pi / Tp
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        spm = 5.0 / 16.0 * Hs**2 * wp**4 * omega**-5.0 * np.exp(-1.25 * (omega / wp) ** -4.0)
        sigma = np.where(omega <= wp, 0.07, 0.09)
        peak = gamma ** np.exp(-((omega - wp) ** 2) / (2.0 * sigma**2 * wp**2))
        s = (1.0 - 0.287 * math.log(gamma)) * spm * peak
    return np.where(omega > 0.0, np.nan_to_num(s), 0.0)


def waterline(L: float, B: float, C_wp: float, n: int = 200) -> tuple[np.ndarray, np.ndarray]:
    """A symmetric parametric waterline y = B/2 (1 - |2x/L|^p) with the waterplane coefficient C_wp.

    The area coefficient of that curve is p/(p+1), so p = C_wp/(1 - C_wp). Returns the closed polygon
    (x, y), counter-clockwise in (x fwd, y stbd) seen from above is clockwise -- orientation is handled by
    the caller through outward normals.
    """
    p = C_wp / (1.0 - C_wp)
    x = np.linspace(0.5 * L, -0.5 * L, n)
    y = 0.5 * B * (1.0 - np.abs(2.0 * x / L) ** p)
    xs = np.concatenate([x, x[::-1][1:]])
    ys = np.concatenate([y, -y[::-1][1:]])
    return xs, ys


def _waterline_elements(L: float, B: float, C_wp: float):
    """Midpoints (x, y), outward unit normals (n_x, n_y), unit tangents (t_x, t_y) and lengths dl of the
    segments of :func:`waterline` (body axes: x forward, y starboard)."""
    xs, ys = waterline(L, B, C_wp)
    # polygon runs bow -> stern along starboard, back along port: outward normal = (dy, -dx) rotated check
    dx = np.diff(xs)
    dy = np.diff(ys)
    xm = 0.5 * (xs[1:] + xs[:-1])
    ym = 0.5 * (ys[1:] + ys[:-1])
    dl = np.hypot(dx, dy)
    nx, ny = -dy / dl, dx / dl
    flip = (nx * xm + ny * ym) < 0.0  # make normals point away from the centre
    nx[flip] *= -1.0
    ny[flip] *= -1.0
    return xm, ym, nx, ny, dx / dl, dy / dl, dl


def _drift_tables(L: float, B: float, C_wp: float) -> tuple[np.ndarray, np.ndarray]:
    """The zero-speed and forward-speed drift coefficient tables (each 3 x WAVE_NA) of Faltinsen et al.
    (1980): the waterline integrals of the two terms of the integrand (see :func:`drift_coefficient_table`
    and :func:`drift_speed_table`)."""
    xm, ym, nx, ny, tx, ty, dl = _waterline_elements(L, B, C_wp)
    chis = np.linspace(0.0, 2.0 * math.pi, lo.WAVE_NA)
    tab = np.zeros((3, lo.WAVE_NA))
    tab_u = np.zeros((3, lo.WAVE_NA))
    for j, chi in enumerate(chis):
        kx, ky = -math.cos(chi), -math.sin(chi)  # waves travel towards the opposite of where they come from
        kn = kx * nx + ky * ny
        lit = kn < 0.0
        for out, w in (
            (tab, (kn**2) * dl * lit),
            # speed term per unit 2 omega_0 U / g: cos(theta) cos(theta + beta) - cos(beta) in the angles of
            # Faltinsen et al. (1980), written with the element's tangent t and the propagation direction k
            (tab_u, (tx * (tx * kx + ty * ky) - kx) * dl * lit),
        ):
            fx = -(w * nx).sum()
            fy = -(w * ny).sum()
            mz = -(w * (xm * ny - ym * nx)).sum()
            out[:, j] = fx / L, fy / L, mz / L**2
    return tab, tab_u


def drift_coefficient_table(L: float, B: float, C_wp: float) -> np.ndarray:
    """Mean drift coefficients C_X, C_Y, C_N (shape 3 x WAVE_NA) over the encounter angle chi, at zero speed.

    Faltinsen et al. (1980) short-wave asymptotic formula for a wall-sided hull (Faltinsen 1990, Sea Loads
    on Ships and Offshore Structures, eq. 5.40):  F_i = 1/2 rho g zeta_a^2 int_L1 sin^2(theta + beta) n_i dl,
    integrated over the illuminated part L1 of the waterline. sin^2(theta + beta) = (k . n)^2 for the
    waterline element with outward normal n and wave propagation direction k; the force pushes the element
    inwards. Coefficients are F / (1/2 rho g zeta_a^2 L) for X, Y and F / (1/2 rho g zeta_a^2 L^2) for N.
    chi is the direction the waves come *from*, relative to the bow, positive from starboard.
    """
    return _drift_tables(L, B, C_wp)[0]


def drift_speed_table(L: float, B: float, C_wp: float) -> np.ndarray:
    """Forward-speed drift coefficients C^U_X, C^U_Y, C^U_N (shape 3 x WAVE_NA) over chi, per unit
    2 omega_0 U / g: the second term of Faltinsen et al. (1980),
    F_i = 1/2 rho g zeta_a^2 int_L1 [sin^2(theta + beta) + 2 omega_0 U / g (cos theta cos(theta + beta) - cos beta)] n_i dl,
    with the same normalisation as :func:`drift_coefficient_table` (omega_0 the wave frequency, U the ship's
    forward speed). For a vertical transverse bow in head waves the bracket is 1 + 2 omega_0 U / g; for a side
    parallel to the ship's axis in beam waves the speed term vanishes."""
    return _drift_tables(L, B, C_wp)[1]


def _drift_spectrum(Hs: float, Tp: float, L: float, T: float, gamma: float) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies omega (rad/s) and 2 S(omega) alpha_T(omega) (m^2 s/rad) of :func:`effective_zeta2`."""
    w = np.linspace(0.2, 4.0, 600) * (2.0 * math.pi / Tp)
    S = jonswap(w, Hs, Tp, gamma)
    lam = 2.0 * math.pi * G_M_S2 / w**2
    alpha = np.where(lam / L <= 2.5, 1.0 - np.exp(-4.0 * math.pi * (T / lam - T / (2.5 * L))), 0.0)
    alpha = np.clip(alpha, 0.0, 1.0)
    return w, 2.0 * S * alpha


def effective_omega_zeta2(Hs: float, Tp: float, L: float, T: float, gamma: float = 3.3) -> float:
    """Effective omega_0 zeta_a^2 (m^2 rad/s) of an irregular sea for the forward-speed term of the drift
    formula (:func:`drift_speed_table`): the integral of omega 2 S(omega) alpha_T(omega) d omega, with the
    draught factor of :func:`effective_zeta2`."""
    if Hs <= 0.0:
        return 0.0
    w, f = _drift_spectrum(Hs, Tp, L, T, gamma)
    return float(np.trapezoid(w * f, w))


def effective_zeta2(Hs: float, Tp: float, L: float, T: float, gamma: float = 3.3) -> float:
    """Effective zeta_a^2 (m^2) of an irregular sea for the short-wave drift formula.

    For each spectral component the regular-wave result applies with zeta_a^2 = 2 S(omega) d omega; the
    short-wave limit is reduced for longer waves with the draught factor of Liu & Papanikolaou (2016, Ocean
    Eng. 127): alpha_T = 1 - exp(-4 pi (T/lambda - T/(2.5 L))) for lambda/L <= 2.5, else 0.
    Deep-water dispersion lambda = 2 pi g / omega^2.
    """
    if Hs <= 0.0:
        return 0.0
    w, f = _drift_spectrum(Hs, Tp, L, T, gamma)
    return float(np.trapezoid(f, w))


@njit(cache=True)
def wave_drift_forces(P, zeta2, wave_from, psi):
    """Mean second-order wave drift loads (X, Y, N) in N, N, N m of a ship at rest in the water
    (:func:`wave_drift_forces_at_speed` at u = 0)."""
    return wave_drift_forces_at_speed(P, zeta2, 0.0, wave_from, psi, 0.0)


@njit(cache=True)
def wave_drift_forces_at_speed(P, zeta2, omega_zeta2, wave_from, psi, u):
    """Mean second-order wave drift loads (X, Y, N) in N, N, N m, from the ship's coefficient tables, at
    surge speed u (m/s) through the water.

    zeta2 is :func:`effective_zeta2` of the sea state, omega_zeta2 :func:`effective_omega_zeta2`; the tables
    are :func:`drift_coefficient_table` and :func:`drift_speed_table`:
    F = 1/2 rho g L (zeta2 C(chi) + 2 U omega_zeta2 / g C^U(chi)), U = max(u, 0): Faltinsen et al. (1980)
    derive the speed term for a ship moving ahead; going astern the zero-speed loads are used.
    """
    if P[WAVE_DRIFT.on] == 0.0 or zeta2 <= 0.0:
        return 0.0, 0.0, 0.0
    chi = (wave_from - psi) % (2.0 * math.pi)
    step = 2.0 * math.pi / (lo.WAVE_NA - 1)
    j = min(int(chi / step), lo.WAVE_NA - 2)
    t = chi / step - j
    b = WAVE_DRIFT.table
    na = lo.WAVE_NA
    cx = (1 - t) * P[b + j] + t * P[b + j + 1]
    cy = (1 - t) * P[b + na + j] + t * P[b + na + j + 1]
    cn = (1 - t) * P[b + 2 * na + j] + t * P[b + 2 * na + j + 1]
    q = 0.5 * P[BODY.rho_kg_m3] * G_M_S2 * zeta2
    L = P[BODY.L_m]
    X = q * L * cx
    Y = q * L * cy
    N = q * L * L * cn
    if u > 0.0 and omega_zeta2 > 0.0:
        bu = WAVE_DRIFT.speed_table
        qu = 0.5 * P[BODY.rho_kg_m3] * G_M_S2 * (2.0 * u * omega_zeta2 / G_M_S2)
        X += qu * L * ((1 - t) * P[bu + j] + t * P[bu + j + 1])
        Y += qu * L * ((1 - t) * P[bu + na + j] + t * P[bu + na + j + 1])
        N += qu * L * L * ((1 - t) * P[bu + 2 * na + j] + t * P[bu + 2 * na + j + 1])
    return X, Y, N
