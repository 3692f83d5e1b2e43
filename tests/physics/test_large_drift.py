"""The hull at any drift angle: Yoshimura, Nakao & Ishibashi (2009) cross-flow model (physics/crossflow.py), for
the MMG hull (KVLCC2) and the Abkowitz hulls (Mariner, DTC).

The oblique-towing sweep here checks the formulation's published limits (straight ahead, 90 deg and straight
astern, below); the KVLCC2's forces over 0-180 deg against measured ones (OCIMF current loads on a loaded VLCC)
are in test_oblique_towing.py.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.crossflow import mmg_weight
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.hull import hull_forces
from vessel_gym.physics.schema import read_toml
from vessel_gym.physics.sections import LargeDrift
from vessel_gym.physics.shipchecks import ShipFileError
from vessel_gym.physics.shipfile import load_ship, parse_ship, resolve_ship_path
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.vessel import pack

U_TOW = 4.0  # m/s, the speed of the measurement (+39.9 MN of surge force at 90 deg drift before)


@pytest.fixture(scope="module")
def kvlcc2():
    s = load_ship("kvlcc2")
    return s, pack(s), pack(dataclasses.replace(s, large_drift=None))


def _towed(P, beta_deg, U=U_TOW, r=0.0):
    """Hull forces at drift angle beta (MMG sign, beta = atan2(-v, u)), speed U, yaw rate r."""
    b = math.radians(beta_deg)
    return np.array(hull_forces(P, U * math.cos(b), -U * math.sin(b), r, 0.0))


def _coefficients(ship, F, U=U_TOW):
    p = ship.particulars
    q = 0.5 * p.rho_kg_m3 * p.L_m * p.T_m * U * U
    return F[0] / q, F[1] / q, F[2] / (q * p.L_m)


def test_surge_force_at_90_deg_drift_is_not_a_thrust(kvlcc2):
    """At 90 deg drift u = 0: the cross-flow model's surge force X'_0 u U vanishes (before: +39.9 MN at 4 m/s
    from X'_vvvv v'^4). Over the whole oblique-towing sweep the surge force opposes u."""
    ship, P, P_mmg = kvlcc2
    assert _towed(P_mmg, 90.0)[0] > 30e6  # the polynomial outside its range, as measured in the issue
    X90 = _towed(P, 90.0)[0]
    assert abs(X90) < 1.0  # N: exactly 0 up to rounding of cos(90 deg)
    for beta in np.arange(0.0, 360.0, 1.0):
        b = math.radians(beta)
        X = _towed(P, beta)[0]
        assert X * math.cos(b) <= 1e-6 * abs(X) + 1.0, beta  # resistive (or zero at 90/270 deg)


def test_oblique_towing_sweep_meets_the_published_limits(kvlcc2):
    """Yoshimura, Nakao & Ishibashi (2009): X' = X'_0F = -R'_0 straight ahead, -X'_0A = R'_0,astern straight
    astern (u = -U), Y' = -C_D at 90 deg drift (C_D is defined as the lateral drag coefficient on L d there)
    and N' = 0 at 90 deg (the cross-flow integral of pure sway has no moment, the linear terms vanish with u).
    Pure drift: Y' is even about 90 deg, N' odd (sternway mirrors the flow fore and aft). Rounding only."""
    ship, P, _ = kvlcc2
    ld = ship.large_drift
    X0, Y0, N0 = _coefficients(ship, _towed(P, 0.0))
    # the MMG term -R'_0 u/sqrt(u^2 + U_min^2) (hull.mmg_hull_forces) differs from -R'_0 by 8e-5 at 4 m/s
    assert (X0, Y0, N0) == pytest.approx((-ship.hull.R_0, 0.0, 0.0), rel=1e-4, abs=1e-12)
    X180 = _coefficients(ship, _towed(P, 180.0))[0]
    assert X180 == pytest.approx(ld.R_0_astern, rel=1e-9)
    _, Y90, N90 = _coefficients(ship, _towed(P, -90.0))  # v = +U, moving to starboard
    assert Y90 == pytest.approx(-ld.C_D, rel=1e-9)
    assert N90 == pytest.approx(0.0, abs=1e-12)
    for beta in np.arange(35.0, 90.0, 5.0):  # the pure cross-flow range of the built-in blend limits
        Fa = _coefficients(ship, _towed(P, beta))
        Fb = _coefficients(ship, _towed(P, 180.0 - beta))
        assert Fb[1] == pytest.approx(Fa[1], rel=1e-9)
        assert Fb[2] == pytest.approx(-Fa[2], rel=1e-9)


def test_published_mmg_set_is_unchanged_inside_its_fitted_range(kvlcc2):
    """Drift up to 22 deg and |r'| up to 1.2 (the KVLCC2's 35 deg turn reaches 19.4 deg and 0.89): the forces
    are the MMG polynomial's, bit for bit, so the published-set validation is untouched."""
    ship, P, P_mmg = kvlcc2
    L = ship.particulars.L_m
    for beta in (-22.0, -10.0, 0.0, 5.0, 19.4, 22.0):
        for rp in (-1.2, -0.5, 0.0, 0.89, 1.2):
            r = rp * U_TOW / L
            assert np.array_equal(_towed(P, beta, r=r), _towed(P_mmg, beta, r=r)), (beta, rp)


def test_forces_vanish_at_rest_and_scale_with_speed_squared(kvlcc2):
    ship, P, _ = kvlcc2
    assert hull_forces(P, 0.0, 0.0, 0.0, 0.0) == (0.0, 0.0, 0.0)
    for beta in (45.0, 90.0, 135.0, 180.0, 250.0):  # the cross-flow model alone
        F1 = _towed(P, beta, U=1e-3)
        F2 = _towed(P, beta, U=2e-3)
        # every cross-flow term is quadratic in the velocities
        assert np.allclose(F2, 4.0 * F1, rtol=1e-9, atol=1e-12), beta
    # small drift is the MMG polynomial, whose low-speed form (U_min) is O(U U_min) below U_min
    assert np.all(np.abs(_towed(P, 10.0, U=1e-3)) < 1e-3 * np.abs(_towed(P, 10.0, U=1.0)))


def test_continuous_over_drift_0_to_360_and_through_u_v_zero(kvlcc2):
    """A 0.05 deg sweep over 0-360 deg changes no force by more than 1 % of its range between neighbours
    (the blend is C1, the model continuous; a jump of the size the old atan2 wrap caused would be ~100 %),
    and forces at +-1e-9 m/s of u or v agree to 1e-6 of their scale."""
    ship, P, _ = kvlcc2
    L = ship.particulars.L_m
    for r in (0.0, 0.3 * U_TOW / L):
        F = np.array([_towed(P, b, r=r) for b in np.arange(0.0, 360.0001, 0.05)])
        span = F.max(axis=0) - F.min(axis=0)
        assert np.all(np.abs(np.diff(F, axis=0)) <= 0.01 * span)
    scale = np.abs(_towed(P, 90.0)).max()
    eps = 1e-9
    for u, v in ((0.0, 2.0), (0.0, -2.0), (2.0, 0.0), (-2.0, 0.0)):
        for r in (0.0, 0.004, -0.004):
            a = np.array(hull_forces(P, u + eps, v + eps, r, 0.0))
            b = np.array(hull_forces(P, u - eps, v - eps, r, 0.0))
            assert np.all(np.abs(a - b) <= 1e-6 * scale), (u, v, r)


def test_port_starboard_mirror(kvlcc2):
    """(u, v, r) -> (u, -v, -r): X unchanged, Y and N change sign, at every drift angle, ahead and astern."""
    _, P, _ = kvlcc2
    rng = np.random.default_rng(12)
    for u, v, r in rng.uniform((-4.0, -4.0, -0.02), (4.0, 4.0, 0.02), size=(400, 3)):
        X, Y, N = hull_forces(P, u, v, r, 0.0)
        Xm, Ym, Nm = hull_forces(P, u, -v, -r, 0.0)
        assert Xm == pytest.approx(X, rel=1e-12, abs=1e-6)
        assert Ym == pytest.approx(-Y, rel=1e-12, abs=1e-6)
        assert Nm == pytest.approx(-N, rel=1e-12, abs=1e-6)


def test_turning_on_the_spot_is_damped(kvlcc2):
    """At u = v = 0 the blend is pure cross flow: the yaw moment opposes r, -C_D C_rN^2 r|r| L^2 /32 on
    1/2 rho L^2 d (the integral of |x'|x'^2 over the hull), and the sway force vanishes by symmetry."""
    ship, P, _ = kvlcc2
    p, ld = ship.particulars, ship.large_drift
    r = 0.01
    assert mmg_weight(P, 0.0, 0.0, r) == 0.0
    X, Y, N = hull_forces(P, 0.0, 0.0, r, 0.0)
    want = -0.5 * p.rho_kg_m3 * p.L_m**2 * p.T_m * ld.C_D * (ld.C_rN * r * p.L_m) ** 2 / 32.0
    assert N == pytest.approx(want, rel=0.005)  # 20-strip midpoint rule
    assert abs(Y) < 1e-9 * abs(N) / p.L_m and X == 0.0


def test_dead_ship_in_beam_sea_drifts_to_leeward_without_headway():
    """KVLCC2, engine stopped, rudder amidships, Hs 6 m, Tp 10 s, waves on the port beam (from the west, ship
    heading north), 1800 s from rest. Before, the polynomial's X'_vvvv drove the ship ahead at 0.5-0.8 m/s.
    Now it lies beam-on and drifts east; the only surge force is the drift force's small surge component
    (waves a degree off the beam), so |u| stays below 10 % of the leeward drift speed."""
    sim = Simulation("kvlcc2", dt=0.5, environment=Environment(Hs_m=6.0, Tp_s=10.0, wave_from_deg=270.0))
    sim.reset(speed_m_s=0.0)
    sim.set_helm(rudder_order_rad=0.0, rev_order=0.0)
    sim.advance(1800.0)
    assert sim.alive[0]
    c, s = math.cos(sim.heading[0]), math.sin(sim.heading[0])
    east = sim.u[0] * s + sim.v[0] * c
    assert sim.east[0] > 1000.0  # m to leeward
    assert east > 0.5  # m/s
    assert abs(sim.u[0]) < 0.1 * east
    assert abs(math.degrees(sim.heading[0])) < 10.0  # still beam-on


@pytest.mark.parametrize("ship", ["kvlcc2", "kvlcc2_l7"])
def test_rest_stays_rest(ship):
    """Engine stopped, still water, 600 s from rest: |u|, |v| < 0.01 m/s (issue 12 item 8)."""
    sim = Simulation(ship, dt=0.5)
    sim.reset(speed_m_s=0.0)
    sim.set_helm(rudder_order_rad=0.0, rev_order=0.0)
    sim.advance(600.0)
    assert abs(sim.u[0]) < 0.01 and abs(sim.v[0]) < 0.01


def test_table_is_checked():
    path = resolve_ship_path("kvlcc2")
    data = read_toml(path)
    bad = dict(data, large_drift=dict(data["large_drift"], cross_flow_drift_min_deg=10.0))
    with pytest.raises(ShipFileError, match=r"\[large_drift\] cross_flow_drift_min_deg"):
        parse_ship(bad, "k.toml")
    bad = dict(data, large_drift=dict(data["large_drift"], C_D=7.0))
    with pytest.raises(ShipFileError, match="C_D"):
        parse_ship(bad, "k.toml")
    assert isinstance(parse_ship(data, "k.toml").large_drift, LargeDrift)


def test_sternway_from_a_tiny_sway_of_either_sign_gives_mirrored_tracks():
    """KVLCC2 from rest at -80 rpm, rudder amidships, seeded with v = +-1e-6 m/s. No propeller side force is
    modelled, so the two tracks mirror each other. Going astern the Munk moment N'_v v u reverses and the hull
    is course-unstable, so the seed grows into a slow yaw (about 18 deg after 2400 s), the same way on both."""
    out = []
    for sign in (1.0, -1.0):
        sim = Simulation("kvlcc2", dt=0.5)
        sim.reset(speed_m_s=0.0)
        sim.state[0, lo.X_V] = sign * 1e-6
        sim.set_helm(rudder_order_rad=0.0, rev_order=-80.0 / 60.0)
        sim.advance(2400.0)
        assert sim.alive[0] and sim.u[0] < -3.0
        out.append((sim.north[0], sim.east[0], math.degrees(sim.heading[0]), sim.v[0], sim.r[0]))
    (n1, e1, h1, v1, r1), (n2, e2, h2, v2, r2) = out
    assert n2 == pytest.approx(n1, rel=1e-3)
    assert (e2, h2, v2, r2) == pytest.approx((-e1, -h1, -v1, -r1), rel=1e-2, abs=1e-6)


# --- Abkowitz hulls (Mariner, DTC): the same model, its linear terms converted from the Abkowitz set ---------


@pytest.fixture(scope="module", params=["mariner", "dtc"])
def abkowitz(request):
    s = load_ship(request.param)
    return s, pack(s), pack(dataclasses.replace(s, large_drift=None))


def _forces(P, u, v, r=0.0, delta=0.0):
    return np.array(hull_forces(P, u, v, r, delta))


def test_abkowitz_surge_force_at_90_deg_drift_is_zero_and_resistive_elsewhere(abkowitz):
    """Before: the Mariner's X_vv v'^2 gave X' = -0.176 at 90 deg drift (u = 0), so a ship drifting sideways
    was driven astern; the DTC's -0.095. Now X = X'_vr v r L only, 0 in pure sway; over the sweep X opposes u."""
    ship, P, P_poly = abkowitz
    assert _coefficients(ship, _towed(P_poly, 90.0))[0] < -0.05  # the polynomial, as measured before
    assert abs(_towed(P, 90.0)[0]) < 1.0
    for beta in np.arange(0.0, 360.0, 1.0):
        X = _towed(P, beta)[0]
        assert X * math.cos(math.radians(beta)) <= 1e-6 * abs(X) + 1.0, beta


def test_abkowitz_sweep_meets_the_published_limits(abkowitz):
    """Yoshimura et al. (2009): X' = -R'_0 straight ahead (the ship's resistance curve), +R'_0,astern straight
    astern, Y' = -C_D and N' = 0 at 90 deg; Y even and N odd about 90 deg in pure drift. Rounding only."""
    ship, P, _ = abkowitz
    ld, h, p = ship.large_drift, ship.hull, ship.particulars
    R0 = h.resistance_N / h.resistance_speed_m_s**2 / (0.5 * p.rho_kg_m3 * p.L_m * p.T_m)
    X180 = _coefficients(ship, _towed(P, 180.0))[0]
    assert X180 == pytest.approx(ld.R_0_astern, rel=1e-9)
    U = h.U_ref_m_s or U_TOW  # the Mariner's polynomial straight ahead: its resistance curve at U_ref
    assert _coefficients(ship, _towed(P, 0.0, U=U), U=U)[0] == pytest.approx(-R0, rel=1e-9)
    _, Y90, N90 = _coefficients(ship, _towed(P, -90.0))
    assert Y90 == pytest.approx(-ld.C_D, rel=1e-9)
    assert N90 == pytest.approx(0.0, abs=1e-12)
    for beta in np.arange(35.0, 90.0, 5.0):
        Fa = _coefficients(ship, _towed(P, beta))
        Fb = _coefficients(ship, _towed(P, 180.0 - beta))
        assert Fb[1] == pytest.approx(Fa[1], rel=1e-9)
        assert Fb[2] == pytest.approx(-Fa[2], rel=1e-9)


def test_abkowitz_set_is_unchanged_inside_its_fitted_range(abkowitz):
    """Drift up to 22 deg, |r'| up to 1.2 and, for the Mariner's perturbation form, |u'| up to 0.8 (speed down
    to 0.56 U_ref): the forces are the published polynomial's bit for bit, rudder terms included, so the
    Nomoto indices, turning circles and zig-zags are untouched (the Mariner's 35 deg turn reaches 8.5 deg of
    drift and u' = -0.26, the DTC's 14 deg)."""
    ship, P, P_poly = abkowitz
    L = ship.particulars.L_m
    U = ship.hull.U_ref_m_s or ship.particulars.test_speed_kn * 1852.0 / 3600.0
    for speed in (U, 0.6 * U):
        for beta in (-22.0, -8.0, 0.0, 14.0, 22.0):
            for rp in (-1.2, 0.0, 0.5, 1.2):
                for delta in (-0.6, 0.0, 0.35):
                    b = math.radians(beta)
                    u, v, r = speed * math.cos(b), -speed * math.sin(b), rp * speed / L
                    assert np.array_equal(_forces(P, u, v, r, delta), _forces(P_poly, u, v, r, delta))


def test_abkowitz_linear_terms_agree_with_the_set(abkowitz):
    """At u = U_ref the cross-flow model alone has the set's linear sway and yaw derivatives, Coriolis terms of
    the equations of motion included (crossflow._abkowitz_linear_terms): the two models meet to first order."""
    from vessel_gym.physics.crossflow import yoshimura_forces
    from vessel_gym.physics.kinematics import coriolis_forces

    ship, P, P_poly = abkowitz
    U = ship.hull.U_ref_m_s or 10.0
    dv, dr = 1e-4 * U, 1e-4 * U / ship.particulars.L_m

    def total_poly(v, r):
        return _forces(P_poly, U, v, r) + np.array(coriolis_forces(P_poly, U, v, r))

    def total_xf(v, r):
        return np.array(yoshimura_forces(P, U, v, r)) + np.array(coriolis_forces(P, U, v, r))

    for dvr in ((dv, 0.0), (0.0, dr)):
        a = (total_poly(*dvr) - total_poly(-dvr[0], -dvr[1]))[1:]
        b = (total_xf(*dvr) - total_xf(-dvr[0], -dvr[1]))[1:]
        # the cross-flow integral is quadratic: at 1e-4 of U its share is ~1e-4 of the linear term
        assert b == pytest.approx(a, rel=2e-3), dvr


def test_abkowitz_continuous_mirrored_and_zero_at_rest(abkowitz):
    ship, P, _ = abkowitz
    assert hull_forces(P, 0.0, 0.0, 0.0, 0.0) == (0.0, 0.0, 0.0)
    L = ship.particulars.L_m
    for r in (0.0, 0.3 * U_TOW / L):
        F = np.array([_towed(P, b, r=r) for b in np.arange(0.0, 360.0001, 0.05)])
        span = F.max(axis=0) - F.min(axis=0)
        assert np.all(np.abs(np.diff(F, axis=0)) <= 0.01 * span)
    scale = np.abs(_towed(P, 90.0)).max()
    for u, v in ((0.0, 2.0), (0.0, -2.0), (2.0, 0.0), (-2.0, 0.0)):
        for r, delta in ((0.0, 0.0), (0.004, 0.3), (-0.004, -0.3)):
            a = _forces(P, u + 1e-9, v + 1e-9, r, delta)
            b = _forces(P, u - 1e-9, v - 1e-9, r, delta)
            assert np.all(np.abs(a - b) <= 1e-6 * scale), (u, v, r)
    # mirror (u, v, r, delta) -> (u, -v, -r, -delta); the Mariner's single-screw bias terms Y_0, N_0 (published)
    # break it inside the polynomial's range, so there only the cross-flow range is checked
    rng = np.random.default_rng(12)
    for u, v, r, delta in rng.uniform((-4.0, -4.0, -0.02, -0.6), (4.0, 4.0, 0.02, 0.6), size=(400, 4)):
        if ship.name == "mariner" and mmg_weight(P, u, v, r) > 0.0:
            continue
        F, Fm = _forces(P, u, v, r, delta), _forces(P, u, -v, -r, -delta)
        assert Fm == pytest.approx(F * np.array([1.0, -1.0, -1.0]), rel=1e-12, abs=1e-6)


def test_mariner_rudder_reverses_in_sternway():
    """The Mariner's rudder is in its derivatives (Y_d delta U^2 ...). In the cross-flow range those pure rudder
    terms act at u|u|: going astern a starboard rudder turns the ship the other way, and at 90 deg drift the
    rudder gives no lift. Ahead (polynomial) Y_d delta < 0 with delta > 0 (vessel-gym's sign)."""
    ship = load_ship("mariner")
    P = pack(ship)
    d = math.radians(20.0)
    ahead = _forces(P, 7.0, 0.0, 0.0, d) - _forces(P, 7.0, 0.0, 0.0, 0.0)
    astern = _forces(P, -3.0, 0.0, 0.0, d) - _forces(P, -3.0, 0.0, 0.0, 0.0)
    beam = _forces(P, 0.0, 3.0, 0.0, d) - _forces(P, 0.0, 3.0, 0.0, 0.0)
    assert ahead[1] < 0.0 < astern[1] and ahead[2] > 0.0 > astern[2]
    q = 0.5 * ship.particulars.rho_kg_m3 * ship.particulars.L_m**2
    hd = ship.hull.derivatives
    Yd = hd["Y_d"] * d + hd["Y_ddd"] * d**3
    assert astern[1] == pytest.approx(-q * 9.0 * Yd, rel=1e-9)
    assert np.all(np.abs(beam) < 1e-6)


def test_hoerner_drag_and_the_model_are_not_added(tmp_path):
    """The supply vessel's Abkowitz hull carries a Hoerner cross-flow drag (C_d 0.71): with a [large_drift]
    table the polynomial side keeps it and the cross-flow side has its own C_D integral; the weights sum to
    one, so at 90 deg drift Y' = -C_D, not -(C_D + C_d). An Abkowitz hull without a resistance curve cannot
    opt in (the model's surge force is that resistance turned with the flow angle)."""
    data = read_toml(resolve_ship_path("supply"))
    table = {"model": "yoshimura_2009", "C_D": 0.71, "C_rY": 1.0, "C_rN": 1.0, "R_0_astern": 0.02}
    with pytest.raises(ShipFileError, match=r"\[large_drift\].*resistance_N"):
        parse_ship(dict(data, large_drift=table), "s.toml")
    hull = dict(data["hull"], resistance_N=2.0e4, resistance_speed_m_s=2.0)
    ship = parse_ship(dict(data, hull=hull, large_drift=table), "s.toml")
    assert ship.hull.cross_flow_Cd == 0.71
    _, Y90, N90 = _coefficients(ship, _towed(pack(ship), -90.0))
    assert Y90 == pytest.approx(-0.71, rel=1e-9) and N90 == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("ship", ["mariner", "dtc", "supply"])
def test_rest_stays_rest_abkowitz(ship):
    """Engine stopped, still water, 600 s from rest: |u|, |v| < 0.01 m/s (issue 12 item 8)."""
    sim = Simulation(ship, dt=0.5)
    sim.reset(speed_m_s=0.0)
    sim.set_helm(rudder_order_rad=0.0, rev_order=0.0)
    sim.advance(600.0)
    assert abs(sim.u[0]) < 0.01 and abs(sim.v[0]) < 0.01


@pytest.mark.parametrize("name", ["mariner", "dtc"])
def test_abkowitz_dead_ship_in_beam_sea_drifts_to_leeward_without_headway(name):
    """Engine stopped, rudder amidships, Hs 4 m, Tp 9 s on the port beam, 1800 s from rest: the ship drifts
    east (leeward) at over 1 m/s; its speed along the original course (north) stays below 2 % of that (the
    only surge force is the wave drift force's small surge component)."""
    sim = Simulation(name, dt=0.5, environment=Environment(Hs_m=4.0, Tp_s=9.0, wave_from_deg=270.0))
    sim.reset(speed_m_s=0.0)
    sim.set_helm(rudder_order_rad=0.0, rev_order=0.0)
    sim.advance(1800.0)
    assert sim.alive[0]
    c, s = math.cos(sim.heading[0]), math.sin(sim.heading[0])
    east, north = sim.u[0] * s + sim.v[0] * c, sim.u[0] * c - sim.v[0] * s
    assert sim.east[0] > 1000.0 and east > 1.0
    assert abs(north) < 0.02 * east


@pytest.mark.parametrize("name", ["mariner", "dtc"])
def test_abkowitz_sternway_from_a_tiny_sway_of_either_sign_gives_mirrored_tracks(name):
    """From rest at -60 rpm, rudder amidships, v = +-1e-6 m/s: astern the hull is pure cross-flow model (no
    single-screw bias term, no propeller side force modelled), so the tracks mirror each other."""
    out = []
    for sign in (1.0, -1.0):
        sim = Simulation(name, dt=0.5)
        sim.reset(speed_m_s=0.0)
        sim.state[0, lo.X_V] = sign * 1e-6
        sim.set_helm(rudder_order_rad=0.0, rev_order=-1.0)
        sim.advance(1800.0)
        assert sim.alive[0] and sim.u[0] < -3.0
        out.append((sim.north[0], sim.east[0], math.degrees(sim.heading[0]), sim.v[0], sim.r[0]))
    (n1, e1, h1, v1, r1), (n2, e2, h2, v2, r2) = out
    assert n2 == pytest.approx(n1, rel=1e-6)
    assert (e2, h2, v2, r2) == pytest.approx((-e1, -h1, -v1, -r1), rel=1e-6, abs=1e-12)
