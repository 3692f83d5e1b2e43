"""The DTC ship file: linear terms from one published regression, course-stable, a container ship's turn.

Sources: Clarke, Gedling & Hine (1983), Trans. RINA 125:45-68 (linear derivatives from L, B, T, C_b);
IMO MSC.137(76) Annex §5.3.1 (turning ability); Nomoto et al. (1957) / Fossen (2011) eq. 7.49 (indices).
"""

from __future__ import annotations

import math

import pytest

from vessel_gym.manoeuvres.trials import pull_out, turning_circle
from vessel_gym.physics.linear import nomoto
from vessel_gym.physics.shipfile import load_ship


def _clarke_1983(L: float, B: float, T: float, Cb: float) -> dict[str, float]:
    """Clarke, Gedling & Hine (1983) linear derivatives on 1/2 rho L^2 U^2 (1/2 rho L^3 U^2 for moments)."""
    k = math.pi * (T / L) ** 2
    BT, BL = B / T, B / L
    return {
        "Y_vdot": -k * (1 + 0.16 * Cb * BT - 5.1 * BL**2),
        "Y_rdot": -k * (0.67 * BL - 0.0033 * BT**2),
        "N_vdot": -k * (1.1 * BL - 0.041 * BT),
        "N_rdot": -k * (1 / 12 + 0.017 * Cb * BT - 0.33 * BL),
        "Y_v": -k * (1 + 0.40 * Cb * BT),
        "Y_r": -k * (-0.5 + 2.2 * BL - 0.080 * BT),
        "N_v": -k * (0.5 + 2.4 * T / L),
        "N_r": -k * (0.25 + 0.039 * BT - 0.56 * BL),
    }


def test_linear_terms_are_clarke_1983_for_the_dtc_particulars():
    """Every linear term is Clarke's regression for the file's own particulars, halved for the seed's
    rho L^2 U^2 normalisation (the file rounds to four significant figures: 0.1 %)."""
    s = load_ship("dtc")
    p = s.particulars
    assert s.hull.normalisation == "rho_L2_U2"
    for key, value in _clarke_1983(p.L_m, p.B_m, p.T_m, p.C_b).items():
        assert s.hull.derivatives[key] == pytest.approx(value / 2.0, rel=1e-3), key


def test_dtc_is_course_stable():
    """Linear course stability: Nomoto K > 0 with both time constants positive (an unstable ship has T1 or
    T2 < 0 and K < 0; the earlier mix of Table 3 and Clarke terms had K = -0.088 1/s, T2 = -113 s)."""
    n = nomoto("dtc")
    assert n.K > 0.0
    assert n.T1 > 0.0 and n.T2 > 0.0


def test_dtc_pull_out_returns_to_a_straight_course():
    """Pull-out (ITTC 7.5-04-02-01) from 20 deg turns to both sides: after the rudder is put midships the rate
    of turn decays towards zero. After 40 L/U each residual rate is below 5 % of the steady rate (the earlier
    unstable set kept 51 % of it); for a first-order decay exp(-t/T1) with the file's T1 ~ 220 s the
    residual would be about 3 %."""
    po = pull_out("dtc", rudder_deg=20.0)
    for steady, resid in zip(po.steady_rate_deg_s, po.residual_rate_deg_s):
        assert abs(steady) > 0.1  # a real turn, deg/s
        assert abs(resid) < 0.05 * abs(steady)
        # the residual turn is in the direction of the turn it came from (no turn the other way)
        assert resid * steady >= 0.0


@pytest.mark.parametrize("rudder_deg", [35.0, -35.0])
def test_dtc_turning_circle_meets_the_imo_turning_ability(rudder_deg):
    """35 deg turning circle at the 25 kn design speed: advance <= 4.5 L and tactical diameter <= 5 L, the
    turning-ability criteria of MSC.137(76) §5.3.1 that a container ship of the DTC's size (built after
    2004, L >= 100 m) must meet; no free-running DTC turning circle was available to compare with. The
    tactical diameter (transfer at 180 deg) exceeds the transfer at 90 deg, as on any circle entered from a
    straight course."""
    tc = turning_circle("dtc", rudder_deg, until_deg=360.0)
    L = tc.L_m
    assert tc.advance_m <= 4.5 * L
    assert tc.tactical_diameter_m <= 5.0 * L
    assert tc.tactical_diameter_m > tc.transfer_m
