"""Component kernels one at a time: propeller, steering gear, engine map, wind, wave drift, atmosphere."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.atmosphere import air_density, apparent_wind, blendermann_wind_forces
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.params import BODY, ENGINE, PROPELLER, RUDDER, STEERING_GEAR
from vessel_gym.physics.propulsion import engine_torque, propeller_thrust_torque
from vessel_gym.physics.seastate import jonswap, wave_drift_forces
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.steering import steering_gear_rate
from vessel_gym.physics.units import DEG, P_ISA_PA, T_ISA_K
from vessel_gym.physics.vessel import pack


@pytest.fixture(scope="module")
def P_kvlcc2() -> np.ndarray:
    return pack(load_ship("kvlcc2"))


# --- propeller -----------------------------------------------------------------------------------------------


def test_first_quadrant_is_the_open_water_curve(P_kvlcc2):
    """Quadrant 1 is the published open-water model, T = rho n^2 D^4 K_T(J), Q = rho n^2 D^5 K_Q(J),
    J = u_a/(nD) (Yasukawa & Yoshimura 2015 eq. 13-14), to rounding (1e-12 relative)."""
    P = P_kvlcc2
    D, rho = P[PROPELLER.D_m], P[BODY.rho_kg_m3]
    n = 1.75
    for J in (0.0, 0.1, 0.3, 0.5):
        T, Q = propeller_thrust_torque(P, J * n * D, n)
        KT = P[PROPELLER.k_0] + P[PROPELLER.k_1] * J + P[PROPELLER.k_2] * J * J
        KQ = P[PROPELLER.q_0] + P[PROPELLER.q_1] * J + P[PROPELLER.q_2] * J * J
        assert T == pytest.approx(rho * n**2 * D**4 * KT, rel=1e-12)
        assert Q == pytest.approx(rho * n**2 * D**5 * KQ, rel=1e-12)


@pytest.mark.parametrize(
    ("n_sign", "ua_sign", "quadrant"),
    [
        (1, 1, "1: ahead, ship ahead"),
        (1, -1, "2: ahead, ship astern"),
        (-1, -1, "3: astern, ship astern"),
        (-1, 1, "4: astern, ship ahead (crash stop)"),
    ],
)
@pytest.mark.parametrize("ship", ["kvlcc2", "mariner", "dtc"])
def test_propeller_signs_in_four_quadrants(ship, n_sign, ua_sign, quadrant):
    """At moderate advance ratio (|J| = 0.3, below any zero of K_T) thrust and torque take the sign of the
    shaft speed in every quadrant: ahead rpm pushes ahead and absorbs positive torque, astern rpm pulls
    astern (a crash stop brakes the ship: quadrant 4 gives T < 0)."""
    P = pack(load_ship(ship))
    n = 2.0 * n_sign
    u_a = ua_sign * 0.3 * abs(n) * P[PROPELLER.D_m]
    T, Q = propeller_thrust_torque(P, u_a, n)
    assert np.sign(T) == n_sign, quadrant
    assert np.sign(Q) == n_sign, quadrant


def _jump(P, a, b):
    """Largest relative change of (T, Q) between the arguments a = (u_a, n) and b, scaled by bollard values."""
    Ta, Qa = propeller_thrust_torque(P, *a)
    Tb, Qb = propeller_thrust_torque(P, *b)
    T0, Q0 = propeller_thrust_torque(P, 0.0, 1.0)
    return max(abs(Ta - Tb) / T0, abs(Qa - Qb) / Q0)


EPS = 1e-9


@pytest.mark.parametrize(
    ("boundary", "a", "b"),
    [
        ("u_a = 0, n > 0 (quadrants 1|2)", (EPS, 1.5), (-EPS, 1.5)),
        ("u_a = 0, n < 0 (quadrants 3|4)", (EPS, -1.5), (-EPS, -1.5)),
        ("n = 0, u_a > 0 (quadrants 1|4)", (2.0, EPS), (2.0, -EPS)),
        ("n = 0, u_a < 0 (quadrants 2|3)", (-2.0, EPS), (-2.0, -EPS)),
    ],
)
@pytest.mark.parametrize("ship", ["kvlcc2", "mariner"])
def test_propeller_is_continuous_across_quadrant_boundaries(ship, boundary, a, b):
    """Thrust and torque are continuous across the four quadrant boundaries (an RK4 stage may straddle one
    during a crash stop): across a 2e-9 step the jump is below 1e-6 of the bollard values."""
    assert _jump(pack(load_ship(ship)), a, b) < 1e-6, boundary


# --- steering gear -------------------------------------------------------------------------------------------


def test_steering_gear_rate_limits(P_kvlcc2):
    """The gear's rate never exceeds delta_rate_max and the order is clipped at delta_max (kernel values)."""
    P = P_kvlcc2
    dmax, rmax = P[STEERING_GEAR.delta_max], P[STEERING_GEAR.delta_rate_max]
    for delta in np.linspace(-dmax, dmax, 15):
        for order in np.linspace(-2.0, 2.0, 21):  # well beyond +-35 deg
            rate = steering_gear_rate(P, delta, order)
            assert abs(rate) <= rmax
            target = min(max(order, -dmax), dmax)
            assert rate * (target - delta) >= 0.0  # moves towards the clipped order
    assert steering_gear_rate(P, dmax, 2.0) == 0.0  # at the stop with an order beyond it: no motion


@pytest.mark.parametrize("ship", ["kvlcc2", "mariner", "kvlcc2_l7"])
def test_steering_gear_in_a_simulation_respects_rate_and_angle(ship):
    """Hard over from 35 deg port with a 60 deg starboard order: the rudder never passes the ship's
    maximum angle (tolerance 1e-12 rad: RK4 of the rate-limited lag cannot overshoot for dt/T_delta <= 1),
    never moves faster than the rated speed (1e-12 rad/s for rounding), and needs at least
    65 deg / rate to travel from 35 deg port to 30 deg starboard (SOLAS II-1/29 swing)."""
    sim = Simulation(ship)
    sim.reset()
    P = sim.Ps[0]
    dmax, rmax = P[STEERING_GEAR.delta_max], P[STEERING_GEAR.delta_rate_max]
    sim.state[0, lo.X_DELTA] = -35.0 * DEG
    sim.set_helm(rudder_order_rad=60.0 * DEG)
    deltas = [sim.rudder[0]]
    for _ in range(round(120.0 / sim.dt)):
        sim.step(1)
        deltas.append(sim.rudder[0])
    d = np.array(deltas)
    assert d.max() <= dmax + 1e-12
    assert d[-1] == pytest.approx(dmax, abs=1e-6)
    assert np.abs(np.diff(d)).max() <= rmax * sim.dt + 1e-12
    t30 = np.argmax(d >= 30.0 * DEG) * sim.dt
    assert t30 >= 65.0 * DEG / rmax


# --- engine --------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("ship", ["kvlcc2", "mariner", "kvlcc2_l7", "dtc"])
def test_engine_torque_map_is_bilinear(ship):
    """At every node the torque is the tabulated value x rated torque; at every cell centre the mean of
    the four corners (bilinear interpolation); outside the map the nearest edge. 1e-12 relative (the node
    speed is passed as s n_rated, which may round by one ulp)."""
    s = load_ship(ship)
    P = pack(s)
    eng = s.engine
    Q_rated, n_rated = P[ENGINE.Q_e_rated], P[ENGINE.n_e_rated]
    tab = np.asarray(eng.torque_map)
    spd, fuel = eng.torque_map_speed, eng.torque_map_fuel
    tol = 1e-12 * Q_rated
    for i, si in enumerate(spd):
        for j, fj in enumerate(fuel):
            assert engine_torque(P, si * n_rated, fj) == pytest.approx(tab[i, j] * Q_rated, abs=tol)
    for i in range(len(spd) - 1):
        for j in range(len(fuel) - 1):
            sc, fc = 0.5 * (spd[i] + spd[i + 1]), 0.5 * (fuel[j] + fuel[j + 1])
            want = 0.25 * (tab[i, j] + tab[i + 1, j] + tab[i, j + 1] + tab[i + 1, j + 1]) * Q_rated
            assert engine_torque(P, sc * n_rated, fc) == pytest.approx(want, abs=tol)
    assert engine_torque(P, 2.0 * spd[-1] * n_rated, 2.0) == pytest.approx(tab[-1, -1] * Q_rated, abs=tol)
    assert engine_torque(P, -1.0, -1.0) == pytest.approx(tab[0, 0] * Q_rated, abs=tol)


# --- wind ----------------------------------------------------------------------------------------------------


def test_blendermann_signs_and_symmetry(P_kvlcc2):
    """Blendermann (1994) as in Fossen (2011) eq. 8.27-8.30, gamma = angle the wind comes from relative to
    the bow, positive from starboard: head wind pushes aft (X < 0), stern wind ahead, wind from starboard
    pushes to port (Y < 0). Mirror symmetry X(-g) = X(g), Y(-g) = -Y(g), N(-g) = -N(g) is exact."""
    P = P_kvlcc2
    X, Y, N = blendermann_wind_forces(P, 20.0, 0.0, 1.225)
    assert X < 0.0 and Y == 0.0 and N == 0.0
    assert blendermann_wind_forces(P, 20.0, math.pi, 1.225)[0] > 0.0
    assert blendermann_wind_forces(P, 20.0, 0.5 * math.pi, 1.225)[1] < 0.0
    assert blendermann_wind_forces(P, 20.0, -0.5 * math.pi, 1.225)[1] > 0.0
    for g in np.linspace(0.05, math.pi - 0.05, 20):
        Xs, Ys, Ns = blendermann_wind_forces(P, 20.0, g, 1.225)
        Xp, Yp, Np = blendermann_wind_forces(P, 20.0, -g, 1.225)
        assert Ys < 0.0
        assert (Xp, Yp, Np) == (Xs, -Ys, -Ns)


def test_apparent_wind_angle_convention():
    """A stopped ship heading north in a wind from the east feels it from starboard (+90 deg); heading
    east, the same wind is a head wind; a ship making 5 m/s in still air feels 5 m/s from ahead."""
    V, g = apparent_wind(0.0, 0.0, 0.0, 10.0, 90.0 * DEG)
    assert V == pytest.approx(10.0) and g == pytest.approx(90.0 * DEG)
    V, g = apparent_wind(0.0, 0.0, 90.0 * DEG, 10.0, 90.0 * DEG)
    assert V == pytest.approx(10.0) and g == pytest.approx(0.0, abs=1e-12)
    V, g = apparent_wind(5.0, 0.0, 1.0, 0.0, 0.0)
    assert V == pytest.approx(5.0) and g == pytest.approx(0.0, abs=1e-15)


# --- waves ---------------------------------------------------------------------------------------------------


def test_wave_drift_directions(P_kvlcc2):
    """Mean drift (Faltinsen 1990 eq. 5.40, short-wave limit): head seas push aft, beam seas from starboard
    push to port, following seas push ahead; port/starboard mirror symmetric to 1e-9 of the load (the
    coefficient table is a sum over a mirror-symmetric waterline polygon, exact but for summation order)."""
    P = P_kvlcc2
    X, Y, N = wave_drift_forces(P, 1.0, 0.0, 0.0)
    assert X < 0.0 and abs(Y) < 1e-9 * abs(X)
    X, Y, N = wave_drift_forces(P, 1.0, 90.0 * DEG, 0.0)
    assert Y < 0.0 and abs(Y) > 10.0 * abs(X)
    assert wave_drift_forces(P, 1.0, 180.0 * DEG, 0.0)[0] > 0.0
    assert wave_drift_forces(P, 1.0, -90.0 * DEG, 0.0)[1] > 0.0
    for chi in np.linspace(10.0, 170.0, 9) * DEG:
        Xs, Ys, Ns = wave_drift_forces(P, 1.0, chi, 0.0)
        Xp, Yp, Np = wave_drift_forces(P, 1.0, -chi, 0.0)
        F = 1e-9 * math.hypot(Xs, Ys)
        assert Xp == pytest.approx(Xs, abs=F)
        assert Yp == pytest.approx(-Ys, abs=F)
        assert Np == pytest.approx(-Ns, abs=F * P[BODY.L_m])
    # heading and wave direction enter only through their difference
    assert wave_drift_forces(P, 1.0, 120.0 * DEG, 30.0 * DEG) == pytest.approx(
        wave_drift_forces(P, 1.0, 90.0 * DEG, 0.0)
    )


def test_jonswap_carries_the_significant_wave_height():
    """The spectrum's zeroth moment is H_s^2 / 16 (DNV-RP-C205 (2010) 3.5.5). The normalising factor
    A_gamma = 1 - 0.287 ln(gamma) is the standard's own approximation, good to about 1 % for gamma = 3.3,
    so the tolerance is 2 %; gamma = 1 (Pierson-Moskowitz) is exact to quadrature error (0.1 %)."""
    w = np.linspace(0.01, 6.0, 60001)
    for gamma, tol in ((3.3, 0.02), (1.0, 1e-3)):
        m0 = np.trapezoid(jonswap(w, 4.0, 10.0, gamma), w)
        assert m0 == pytest.approx(4.0**2 / 16.0, rel=tol)


# --- atmosphere ----------------------------------------------------------------------------------------------


def test_air_density_at_isa_sea_level():
    """ISA sea level (101 325 Pa, 288.15 K): 1.2250 kg/m^3 (ISO 2533:1975), tolerance half the last digit."""
    assert air_density() == pytest.approx(1.2250, abs=5e-5)
    assert air_density(P_ISA_PA, T_ISA_K) == Environment().rho_air_kg_m3
    assert Environment().row(320.0, 20.8)[lo.E_RHO_AIR] == air_density()
    with pytest.raises(ValueError, match="positive"):
        air_density(101325.0, 0.0)


# --- the vessel's combined kernel -------------------------------------------------------------------------------


@pytest.mark.parametrize("ship", ["kvlcc2", "mariner"])
def test_vessel_forces_equal_the_component_functions(ship):
    """vessel.forces evaluates the rudder, wind and hull through their fast forms (one drift angle, wind
    direction as a unit vector, Abkowitz monomials merged); they equal the documented component functions."""
    from vessel_gym.physics.hull import hull_forces
    from vessel_gym.physics.steering import mmg_rudder_forces
    from vessel_gym.physics.vessel import N_OUT, forces

    P = pack(load_ship(ship))
    rng = np.random.default_rng(3)
    for _ in range(200):
        x = np.zeros(lo.NX)
        x[[lo.X_U, lo.X_V, lo.X_R, lo.X_PSI, lo.X_DELTA, lo.X_REV]] = rng.uniform(
            [-2.0, -2.0, -0.02, -4.0, -0.6, -1.0], [10.0, 2.0, 0.02, 4.0, 0.6, 2.0]
        )
        e = Environment(
            wind_speed_m_s=rng.uniform(0.0, 25.0),
            wind_from_deg=rng.uniform(0.0, 360.0),
            current_speed_m_s=rng.uniform(0.0, 2.0),
            current_to_deg=rng.uniform(0.0, 360.0),
        ).row(P[BODY.L_m], P[BODY.T_m])
        f = forces(P, x, np.zeros(lo.NU), e, np.zeros(N_OUT))
        u, v, r, psi, delta = x[[lo.X_U, lo.X_V, lo.X_R, lo.X_PSI, lo.X_DELTA]]
        np.testing.assert_allclose(f[0:3], hull_forces(P, u, v, r, delta), rtol=1e-12, atol=1e-9)
        if P[RUDDER.kind] == lo.RUDDER_MMG:
            rudder = mmg_rudder_forces(P, u, v, r, delta, f[15], f[13])
            np.testing.assert_allclose(f[4:7], rudder, rtol=1e-12, atol=1e-9)
        ug = u + math.cos(psi) * f[18] + math.sin(psi) * f[19]
        vg = v - math.sin(psi) * f[18] + math.cos(psi) * f[19]
        V, g = apparent_wind(ug, vg, psi, e[lo.E_WIND_SPEED], e[lo.E_WIND_FROM])
        assert f[16] == pytest.approx(V, rel=1e-12) and f[17] == pytest.approx(g, rel=1e-12, abs=1e-12)
        wind = blendermann_wind_forces(P, V, g, e[lo.E_RHO_AIR])
        np.testing.assert_allclose(f[7:10], wind, rtol=1e-9, atol=1e-9)
