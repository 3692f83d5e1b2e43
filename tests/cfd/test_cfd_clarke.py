"""Clarke, Gedling & Hine (1983) regressions and Söding's surge added mass."""

from __future__ import annotations

import math

import pytest

from cfd.clarke import clarke83, soding_surge_added_mass


def test_wigley_values_by_hand():
    # Wigley L = 1, B/L = 0.1, T/L = 0.0625, C_B = 4/9: s = pi (T/L)^2 = 0.0122718
    d = clarke83(1.0, 0.1, 0.0625, 4.0 / 9.0)
    s = math.pi * 0.0625**2
    assert d["Y_v"] == pytest.approx(-s * (1 + 0.4 * (4 / 9) * 1.6))
    assert d["Y_v"] == pytest.approx(-0.01576, abs=1e-5)
    assert d["Y_r"] == pytest.approx(0.005007, abs=1e-6)
    assert d["N_v"] == pytest.approx(-0.007977, abs=1e-6)
    assert d["N_r"] == pytest.approx(-0.003147, abs=1e-6)
    assert d["Y_vdot"] == pytest.approx(-0.013042, abs=1e-6)
    assert d["N_rdot"] == pytest.approx(-0.000766, abs=1e-6)


def test_signs_of_a_ship_like_hull_and_scale_invariance():
    d = clarke83(355.0, 51.0, 14.5, 0.661)
    assert d["Y_v"] < 0 and d["N_v"] < 0 and d["N_r"] < 0 and d["Y_vdot"] < 0 and d["N_rdot"] < 0
    assert d["Y_r"] > 0
    assert clarke83(5.976, 0.859, 0.244, 0.661) == pytest.approx(clarke83(355.0, 51.0, 14.5, 0.661), rel=0.01)


def test_normalisation_halves_without_the_half():
    a = clarke83(100.0, 16.0, 6.0, 0.7, "half_rho_L2_U2")
    b = clarke83(100.0, 16.0, 6.0, 0.7, "rho_L2_U2")
    for k in a:
        assert b[k] == pytest.approx(0.5 * a[k])


@pytest.mark.parametrize("args", [(0, 1, 1, 0.5), (1, 1, -1, 0.5), (1, 0.1, 0.05, 1.5)])
def test_bad_input(args):
    with pytest.raises(ValueError):
        clarke83(*args)
    with pytest.raises(ValueError, match="normalisation"):
        clarke83(1, 0.1, 0.05, 0.5, "mmg")


def test_soding_surge_added_mass():
    # A11 = 2.7 rho V^(5/3) / L^2; DTC full scale: about 5 % of the mass
    V, L, rho = 173467.0, 355.0, 1025.0
    a11 = soding_surge_added_mass(V, L, rho)
    assert a11 == pytest.approx(2.7 * rho * V ** (5 / 3) / L**2)
    assert 0.02 < a11 / (rho * V) < 0.1
