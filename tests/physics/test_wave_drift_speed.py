"""Mean wave drift with forward speed: the speed term of Faltinsen et al. (1980) (physics/seastate.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.seastate import (
    drift_coefficient_table,
    drift_speed_table,
    effective_omega_zeta2,
    effective_zeta2,
    wave_drift_forces,
    wave_drift_forces_at_speed,
)
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.units import DEG, G_M_S2
from vessel_gym.physics.vessel import pack

HEAD, BEAM, FOLLOWING = 0, (lo.WAVE_NA - 1) // 4, (lo.WAVE_NA - 1) // 2  # table columns at chi = 0, 90, 180 deg


def _wave_ship():
    """The KVLCC2 (its ship file has a [wave_drift] table)."""
    s = load_ship("kvlcc2")
    assert s.wave_drift is not None
    return s


def test_head_waves_scale_with_one_plus_two_omega_u_over_g() -> None:
    """Faltinsen et al. (1980), head waves: R_AW(U) = R_AW(0) (1 + 2 omega_0 U / g) for any waterline, since
    the speed bracket is then sin^2(theta) like the zero-speed one."""
    for L, B, C_wp in ((320.0, 58.0, 0.9), (7.0, 1.27, 0.85), (171.8, 23.2, 0.75)):
        c0 = drift_coefficient_table(L, B, C_wp)[:, HEAD]
        cu = drift_speed_table(L, B, C_wp)[:, HEAD]
        assert cu[0] == pytest.approx(c0[0], rel=1e-12)
    s = _wave_ship()
    P = pack(s)
    omega0, zeta2, u = 0.62, 1.0, 7.0  # a regular wave of lambda ~ 160 m; omega zeta^2 = omega_0 zeta^2
    X0 = wave_drift_forces(P, zeta2, 0.0, 0.0)[0]
    XU = wave_drift_forces_at_speed(P, zeta2, omega0 * zeta2, 0.0, 0.0, u)[0]
    assert X0 < 0.0
    assert XU / X0 == pytest.approx(1.0 + 2.0 * omega0 * u / G_M_S2, rel=1e-9)


def test_box_barge_bow_stern_and_side() -> None:
    """A wall-sided box (C_wp -> 1): the transverse bow in head waves takes 1/2 rho g zeta^2 B (1 + 2 omega U/g);
    the transom in following waves is pushed ahead by 1/2 rho g zeta^2 B (1 - 2 omega U/g), the ship running
    away from the waves; the side in beam waves is pushed by 1/2 rho g zeta^2 L, with no speed term."""
    L, B = 100.0, 20.0
    c0 = drift_coefficient_table(L, B, 0.999)
    cu = drift_speed_table(L, B, 0.999)
    assert c0[0, HEAD] * L / B == pytest.approx(-1.0, abs=0.01)
    assert cu[0, HEAD] * L / B == pytest.approx(-1.0, abs=0.01)
    assert c0[0, FOLLOWING] * L / B == pytest.approx(1.0, abs=0.01)
    assert cu[0, FOLLOWING] * L / B == pytest.approx(-1.0, abs=0.01)
    assert abs(c0[1, BEAM]) == pytest.approx(1.0, abs=0.02)
    assert abs(cu[1, BEAM]) < 1e-9


def test_zero_speed_and_sternway_keep_the_zero_speed_loads() -> None:
    s = _wave_ship()
    P = pack(s)
    for chi in np.linspace(0.0, 2.0 * math.pi, 13):
        rest = wave_drift_forces(P, 0.8, chi, 0.0)
        assert wave_drift_forces_at_speed(P, 0.8, 0.5, chi, 0.0, 0.0) == rest
        assert wave_drift_forces_at_speed(P, 0.8, 0.5, chi, 0.0, -2.0) == rest


def test_irregular_sea_moment_and_environment_row() -> None:
    """The irregular-sea speed term uses the first moment of the drift spectrum: omega zeta^2 = omega_m zeta^2
    with omega_m between the spectrum's limits, near the peak frequency for a narrow JONSWAP."""
    L, T = 320.0, 20.8
    z2 = effective_zeta2(4.0, 8.0, L, T)
    wz2 = effective_omega_zeta2(4.0, 8.0, L, T)
    wp = 2.0 * math.pi / 8.0
    assert 0.9 * wp < wz2 / z2 < 1.6 * wp
    e = Environment(Hs_m=4.0, Tp_s=8.0).row(L, T)
    assert e[lo.E_OMEGA_ZETA2] == wz2 and e[lo.E_ZETA2] == z2
    assert Environment().row(L, T)[lo.E_OMEGA_ZETA2] == 0.0


def test_more_added_resistance_ahead_in_bow_waves() -> None:
    s = _wave_ship()
    P = pack(s)
    X = [wave_drift_forces_at_speed(P, 1.0, 0.7, 30.0 * DEG, 0.0, u)[0] for u in (0.0, 3.0, 6.0)]
    assert X[0] > X[1] > X[2]
