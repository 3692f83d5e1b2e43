"""Validation against published results. Each test names its source and justifies its tolerance."""

from __future__ import annotations

import pytest

from vessel_gym.manoeuvres import turning_circle, zigzag
from vessel_gym.physics.linear import nomoto


def test_mariner_nomoto_indices_match_published():
    """Mariner linearised at 15 kn: K = 0.185 1/s, T1 = 118 s, T2 = 7.8 s, T3 = 18.5 s.

    Source: Fossen's MSS toolbox, mssExamples/exNomoto.m and SIMmariner.m (Nomoto indices of the
    Chislett & Stroem-Tejsen 1965 model). Tolerance 2 % (the published values are rounded to 3 figures).
    """
    n = nomoto("mariner", 7.7175)
    assert n.K == pytest.approx(0.185, rel=0.02)
    assert n.T1 == pytest.approx(118.0, rel=0.02)
    assert n.T2 == pytest.approx(7.8, rel=0.02)
    assert n.T3 == pytest.approx(18.5, rel=0.02)
    assert n.T == pytest.approx(107.3, rel=0.02)  # SIMmariner.m: T = 107.3 s


# Kim, I.-T. et al. (2021). Numerical investigation of the maneuverability of KVLCC2 ... Int. J. Nav. Archit.
# Ocean Eng. 13:466-477, Tables 7 and 8 (as transcribed in MarineHydro.jl validation/kvlcc2_maneuvering/
# reference.toml): "system-based" = MMG simulation with the Yasukawa & Yoshimura (2015) set;
# "EFD" = SIMMAN 2008 MARIN free-running model tests. Positive angle = first execute to starboard.
MMG_SIM_ZIGZAG = {(10, 10): (5.0, 14.0), (-10, 10): (7.2, 9.1), (20, 20): (10.4,), (-20, 20): (13.9,)}
EFD_ZIGZAG = {(10, 10): (8.2, 21.9), (-10, 10): (9.5, 15.0), (20, 20): (13.7,), (-20, 20): (15.1,)}


@pytest.mark.parametrize("ship", ["kvlcc2", "kvlcc2_l7"])
def test_kvlcc2_turning_circle_35_port(ship):
    """35 deg turn to port: MMG simulation advance 3.06 L, tactical diameter 3.05 L (Kim et al. 2021,
    Table 7); free-running (SIMMAN 2008, MARIN): 3.11 L, 3.08 L.

    Tolerance +-0.1 L against the simulation of the same published set (differences come only from the
    unpublished rudder-rate and propeller-rpm details of that simulation); +-0.2 L against the free-running
    model test, which the MMG set itself reproduces to about that accuracy.
    """
    tc = turning_circle(ship, -35.0, until_deg=360.0)
    L = tc.L_m
    assert tc.advance_m / L == pytest.approx(3.06, abs=0.1)
    assert tc.tactical_diameter_m / L == pytest.approx(3.05, abs=0.1)
    assert tc.advance_m / L == pytest.approx(3.11, abs=0.2)
    assert tc.tactical_diameter_m / L == pytest.approx(3.08, abs=0.2)


@pytest.mark.parametrize(("rudder", "heading"), list(MMG_SIM_ZIGZAG))
def test_kvlcc2_zigzag_overshoots(rudder, heading):
    """10/10 and 20/20 zig-zags both ways against the MMG simulation of Kim et al. (2021), Table 8, within
    +-1 deg (the accuracy expected of a correct implementation of the published set). The free-running
    overshoots (EFD) are larger - the simulation underpredicts them in that table - so they are checked
    only for ordering: simulation <= free-running + 1 deg."""
    z = zigzag("kvlcc2", rudder, heading, n_overshoots=len(MMG_SIM_ZIGZAG[(rudder, heading)]))
    for got, want, efd in zip(
        z.overshoot_deg, MMG_SIM_ZIGZAG[(rudder, heading)], EFD_ZIGZAG[(rudder, heading)]
    ):
        assert got == pytest.approx(want, abs=1.0)
        assert got <= efd + 1.0
