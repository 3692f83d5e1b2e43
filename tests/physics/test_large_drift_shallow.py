"""Shallow water in the cross-flow hull (crossflow.yoshimura_forces_at_depth): the lateral cross-flow drag grows
with decreasing depth by the factor of UFC 4-159-03 (2005) eq. 11-13 (shallow_water.cross_flow_drag_factor),
the linear terms by the MMG polynomial's own factors, at the depth the MMG part gets.

Validation: the beam-on lateral current force of a loaded VLCC, shallow over deep, published by OCIMF (1994),
"Prediction of Wind and Current Loads on VLCCs", as reproduced in OCIMF MEG3 (2008) Annex A, Figure A10, at the
water depth/draught ratios 3.0, 1.5 and 1.2 (tests/physics/ocimf_reference.py: source, convention, digitisation).
A ship held beam-on in a current is a ship towed sideways through still water at u = 0, where the cross-flow
model is used alone and its sway force is -1/2 rho L d C_D v|v|: the ratio is the depth factor on C_D.

Tolerance, as a fraction of OCIMF's ratio: the tolerance of the deep-water oblique-towing comparison in Y'
(ocimf_reference.TOLERANCE_FRACTION["Y"], 23.5 %): the scatter band OCIMF draws about its curves (MEG3
Fig. A12, half-width 16.7 % of the peak; one curve per depth serves every loaded VLCC, the KVLCC2 is not
among the tested hulls) plus the digitising error of the lateral curves (6.8 %, from two independent readings of
the h/T = 1.1 curve). At 90 deg the lateral curves peak, so the fraction of the peak is the fraction of the value.
Both parts come from the published data, not from the model. OCIMF's deep-water curve is for h/T > 6 and is
taken as infinitely deep water. The same ratio over the other drift angles, in the ranges of the deep-water
comparison, has the same tolerance; ranges that miss are strict expected failures with their measured gaps
(docs/physics.md, "Shallow water in the cross-flow model").
"""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import ocimf_reference as ref
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.physics import layout as lo
from vessel_gym.physics.crossflow import mmg_weight, yoshimura_forces, yoshimura_forces_at_depth
from vessel_gym.physics.hull import hull_forces, hull_forces_at_depth
from vessel_gym.physics.shallow_water import H_MAX, H_OVER_T_MIN, cross_flow_drag_factor, hull_factors
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.vessel import pack

KVLCC2 = load_ship("kvlcc2")
P = pack(KVLCC2)
#: built-in ships with an MMG hull and a [large_drift] table: the ones the correction reaches
CROSS_FLOW_MMG = ("kvlcc2", "kvlcc2_full", "kvlcc2_l7_harbour")


def _beam_on_Y(P_row, H, v=1.0):
    """Hull sway force (N) of a ship moving sideways at v (m/s), no headway, no yaw, at T/h = H."""
    return hull_forces_at_depth(P_row, 0.0, v, 0.0, 0.0, H, True, True)[1]


@pytest.mark.parametrize("h_over_T", (3.0, 1.5, 1.2))
def test_beam_on_lateral_force_ratio_against_ocimf(h_over_T):
    beam = int(np.flatnonzero(ref.THETA_DEG == 90.0)[0])
    published = ref.C_YC_BY_DEPTH[h_over_T][beam] / ref.C_YC_DEEP[beam]
    model = _beam_on_Y(P, 1.0 / h_over_T) / _beam_on_Y(P, 0.0)
    assert mmg_weight(P, 0.0, 1.0, 0.0) == 0.0  # beam-on: the cross-flow model alone
    tol = ref.TOLERANCE_FRACTION["Y"] * published
    assert abs(model - published) <= tol, (
        f"h/T = {h_over_T}: beam-on Y(shallow)/Y(deep) {model:.3f} against OCIMF {published:.3f} "
        f"(tolerance {tol:.3f})"
    )


def test_yaw_moment_of_the_cross_flow_drag_takes_the_same_factor():
    """UFC 4-159-03 (section 4-5.4, eq. 24) gives the current yaw moment as the lateral force times an
    eccentricity that does not depend on depth, so the drag's moment takes the lateral force's factor. A ship
    turning on the spot (u = v = 0) has the cross-flow drag moment alone: its ratio is the factor."""
    r = 0.01
    for hT in (3.0, 1.5, 1.2):
        H = 1.0 / hT
        N_deep = hull_forces_at_depth(P, 0.0, 0.0, r, 0.0, 0.0, True, True)[2]
        N_shallow = hull_forces_at_depth(P, 0.0, 0.0, r, 0.0, H, True, True)[2]
        assert N_deep < 0.0  # the turn is resisted
        assert N_shallow / N_deep == pytest.approx(cross_flow_drag_factor(P, H), rel=1e-12)


def test_linear_terms_take_the_mmg_polynomials_factors():
    """At oblique drift the cross-flow model's linear terms are the MMG set's, with the factors the polynomial
    gives them at the same depth (one correction per coefficient, shallow_water.hull_factors): sway at 60 deg
    drift, headway included, is the linear Y'_v term times Kijima's factor plus the drag term times UFC's."""
    H = 1.0 / 1.5
    chi = math.radians(60.0)
    u, v = math.cos(chi), math.sin(chi)
    q = 0.5 * KVLCC2.particulars.rho_kg_m3 * KVLCC2.particulars.L_m * KVLCC2.particulars.T_m
    C_D = KVLCC2.large_drift.C_D
    Y = yoshimura_forces_at_depth(P, u, v, 0.0, H)[1] / q
    f = hull_factors(P, H)
    expected = KVLCC2.hull.Y_v * f[5] * v * abs(u) - C_D * cross_flow_drag_factor(P, H) * abs(v) * v
    assert Y == pytest.approx(expected, rel=1e-12)
    N = yoshimura_forces_at_depth(P, u, v, 0.0, H)[2] / (q * KVLCC2.particulars.L_m)
    assert N == pytest.approx(KVLCC2.hull.N_v * f[11] * v * u, rel=1e-9, abs=1e-12)  # no drag moment in pure sway


@pytest.mark.parametrize("name", CROSS_FLOW_MMG)
def test_deep_water_is_unchanged(name):
    """At H = 0 (no depth given, or infinitely deep) no factor is evaluated: the forces are the deep-water
    model's bit for bit, for every state (large drift, sternway, turning on the spot), and beam-on Y' = -C_D
    (Yoshimura et al. 2009 at 90 deg drift)."""
    ship = load_ship(name)
    Pr = pack(ship)
    assert cross_flow_drag_factor(Pr, 0.0) == 1.0
    rng = np.random.default_rng(7)
    L = ship.particulars.L_m
    for _ in range(400):
        U, chi = rng.uniform(0.0, 3.0), rng.uniform(-math.pi, math.pi)
        u, v, r = U * math.cos(chi), U * math.sin(chi), rng.normal() * 2.0 * max(U, 0.1) / L
        assert yoshimura_forces_at_depth(Pr, u, v, r, 0.0) == yoshimura_forces(Pr, u, v, r)
        assert hull_forces_at_depth(Pr, u, v, r, 0.1, 0.0, True, True) == hull_forces(Pr, u, v, r, 0.1)
    p = ship.particulars
    q = 0.5 * p.rho_kg_m3 * p.L_m * p.T_m
    assert _beam_on_Y(Pr, 0.0) / q == pytest.approx(-ship.large_drift.C_D, rel=1e-12)


def test_factor_is_continuous_and_tends_to_one_in_deep_water():
    """The factor rises smoothly and monotonically as the water shoals, tends to 1 as h/T grows (h/T = 1e4:
    within 1e-6), and so do the cross-flow forces at large drift and turning (no step anywhere in
    0 <= T/h <= 1/1.2)."""
    Hs = np.linspace(0.0, H_MAX, 2001)
    f = np.array([cross_flow_drag_factor(P, H) for H in Hs])
    assert f[0] == 1.0 and np.all(np.diff(f) > 0.0)
    assert np.max(np.abs(np.diff(f))) < 2e-3 * f[-1]
    assert cross_flow_drag_factor(P, 1e-4) - 1.0 < 1e-6
    for u, v, r in ((0.0, 1.0, 0.0), (-0.5, 0.8, 0.002), (0.4, -0.9, -0.003), (0.0, 0.0, 0.01)):
        F = np.array([yoshimura_forces_at_depth(P, u, v, r, H) for H in Hs])
        span = np.abs(F).max(axis=0)
        assert np.all(np.abs(np.diff(F, axis=0)) <= 5e-3 * span + 1e-9), (u, v, r)
        assert np.allclose(yoshimura_forces_at_depth(P, u, v, r, 1e-5), F[0], rtol=1e-3, atol=1e-6 * span.max())


def test_below_the_method_range_the_kernel_clamps():
    """The kernel evaluates no T/h beyond 1/1.2 (the range of the MMG corrections, the one home of h/T): OCIMF's
    h/T = 1.1 acts as 1.2. A depth below 1.2 T given by the user is refused (Environment, test_shallow_water);
    a charted one under a moving ship is clamped (shallow_water.set_charted_depth)."""
    assert cross_flow_drag_factor(P, 1.0 / 1.1) == cross_flow_drag_factor(P, 1.0 / H_OVER_T_MIN)
    assert _beam_on_Y(P, 1.0 / 1.1) == _beam_on_Y(P, H_MAX)
    beam = int(np.flatnonzero(ref.THETA_DEG == 90.0)[0])
    # below the range the published growth goes on (OCIMF 4.90 at h/T = 1.1) and the clamped model stops short
    assert ref.C_YC_WDT11[beam] / ref.C_YC_DEEP[beam] > cross_flow_drag_factor(P, H_MAX)


def test_harbour_v2_ship_gets_the_factor_through_the_env_path():
    """HarbourApproach-v2 writes the chart's depth under the ship into the simulation's environment row; the
    hull forces the simulation computes for its ship (kvlcc2_l7_harbour) drifting beam-on in the basin are
    the deep-water ones times the factor at that depth."""
    env = gym.make("vessel_gym/HarbourApproach-v2")
    u = env.unwrapped
    env.reset(seed=0, options={"north_m": 20.0, "east_m": 0.0, "heading_deg": 0.0, "speed_m_s": 0.3})
    sim = u.sim
    H = float(sim.env[0, lo.E_T_OVER_H])
    T = u.task.ship.particulars.T_m
    assert u.depth_m == 1.2 and H == pytest.approx(T / 1.2)  # the basin, h/T = 2.6
    sim.state[0, [lo.X_U, lo.X_V, lo.X_R]] = [0.0, 0.05, 0.0]
    Y = float(sim.named_forces()["mmg_hull"].Y[0])
    Pr = sim.Ps[int(sim.ship_index[0])]
    deep = _beam_on_Y(Pr, 0.0, v=0.05)
    assert Y == pytest.approx(deep * cross_flow_drag_factor(Pr, H), rel=1e-12)
    assert Y / deep == pytest.approx(1.0 + (3.2 / (0.22 * math.sqrt(320.0 / 58.0 / 0.81)) - 1.0) * H * H, rel=0.01)


#: flow angle chi from the bow (deg) of each range, cut where the model changes form, as in the deep-water
#: comparison (test_oblique_towing.RANGES) without 0 and 180 deg, where the lateral force and its ratio vanish
RANGES = {
    "ahead_mmg_polynomial": (10.0, 20.0),
    "bow_leading": (30.0, 40.0, 50.0, 60.0, 70.0, 80.0),
    "beam": (90.0,),
    "stern_leading": (100.0, 110.0, 120.0, 130.0, 140.0, 150.0),
    "sternway": (160.0, 170.0),
}

#: measured gaps beyond the tolerance, as of this commit (docs/physics.md, "Shallow water in the cross-flow model")
_POLY = "the MMG polynomial's factors (Kijima et al. 1990 on Y'_v) grow Y' less than OCIMF at small drift"
_BLEND = "the blend of polynomial and cross-flow model (22-35 deg) carries the polynomial's smaller growth"
_ASTERN = "at small drift astern the linear term Y'_v v|u|, with Kijima's factor, carries half the force"
GAPS: dict[tuple[float, str], str] = {
    (3.0, "ahead_mmg_polynomial"): f"{_POLY}: 1.10 against 1.95 at 10 deg (43 %)",
    (3.0, "bow_leading"): f"{_BLEND}: 1.28 against 1.72 at 30 deg (26 %)",
    (3.0, "stern_leading"): f"{_ASTERN}: 1.36 against 1.89 at 150 deg (28 %)",
    (3.0, "sternway"): f"{_ASTERN}: 1.32 against 1.90 at 160 deg (31 %)",
    (1.5, "ahead_mmg_polynomial"): f"{_POLY}: 2.01 against 4.43 at 10 deg (55 %)",
    (1.5, "bow_leading"): f"{_BLEND}: 2.43 against 4.07 at 30 deg (40 %)",
    (1.5, "stern_leading"): f"{_ASTERN}: 2.67 against 3.96 at 150 deg (33 %)",
    (1.5, "sternway"): f"{_ASTERN}: 2.56 against 4.18 at 160 deg (39 %)",
    (1.2, "ahead_mmg_polynomial"): f"{_POLY}: 4.04 against 6.25 at 20 deg (35 %)",
    (1.2, "bow_leading"): f"{_BLEND}: 4.11 against 5.61 at 30 deg (27 %)",
    (1.2, "sternway"): f"{_ASTERN}: 4.19 against 6.69 at 160 deg (37 %)",
}


def _ratio_case(h_over_T, name):
    reason = GAPS.get((h_over_T, name))
    marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
    return pytest.param(h_over_T, name, marks=marks, id=f"hT{h_over_T:g}-{name}")


@pytest.mark.parametrize("h_over_T, name", [_ratio_case(h, n) for h in (3.0, 1.5, 1.2) for n in RANGES])
def test_lateral_force_ratio_over_the_drift_angle_against_ocimf(h_over_T, name):
    """Y' shallow over deep at every drift angle of a range (ship moving to starboard, hull forces as the
    simulation computes them: the polynomial, the blend or the cross-flow model), against OCIMF Figure A10's
    C_Yc at that depth over its deep curve; the tolerance of the beam-on test, 23.5 % of OCIMF's ratio."""
    H = 1.0 / h_over_T
    worst = (0.0, 0.0, 0.0, 0.0)
    for chi in RANGES[name]:
        i = int(np.flatnonzero(ref.THETA_DEG == 180.0 - chi)[0])
        published = ref.C_YC_BY_DEPTH[h_over_T][i] / ref.C_YC_DEEP[i]
        c = math.radians(chi)
        u, v = math.cos(c), math.sin(c)
        model = hull_forces_at_depth(P, u, v, 0.0, 0.0, H, True, True)[1] / hull_forces_at_depth(P, u, v, 0.0, 0.0, 0.0, True, True)[1]
        gap = abs(model / published - 1.0)
        worst = max(worst, (gap, chi, model, published))
    gap, chi, model, published = worst
    assert gap <= ref.TOLERANCE_FRACTION["Y"], (
        f"h/T = {h_over_T}: Y(shallow)/Y(deep) {model:.2f} against OCIMF {published:.2f} at chi = {chi:g} deg "
        f"({100 * gap:.1f} %, tolerance {100 * ref.TOLERANCE_FRACTION['Y']:.1f} %)"
    )
