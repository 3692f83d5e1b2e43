"""Kinematics accessors (physics/kinematics.py) against hand-worked cases and the textbook matrix forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vessel_gym.physics import kinematics as km
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.vessel import mass_matrix, pack


def test_rotation_is_orthogonal_and_clockwise_from_north():
    c, s = math.cos(math.radians(90.0)), math.sin(math.radians(90.0))
    n, e = km.body_to_earth(c, s, 1.0, 0.0)  # heading east: the bow points east
    assert (n, e) == pytest.approx((0.0, 1.0), abs=1e-15)
    n, e = km.body_to_earth(c, s, 0.0, 1.0)  # starboard points south
    assert (n, e) == pytest.approx((-1.0, 0.0), abs=1e-15)
    psi = 0.7
    c, s = math.cos(psi), math.sin(psi)
    x, y = km.earth_to_body(c, s, *km.body_to_earth(c, s, 3.0, -2.0))
    assert (x, y) == pytest.approx((3.0, -2.0), rel=1e-15)


def test_velocity_over_ground_adds_the_current():
    """Heading north at 2 m/s through the water in a 1 m/s current towards east: 2 m/s north, 1 m/s east over
    ground, the current to starboard in body axes; a ship heading west meets that current from ahead."""
    vn, ve = km.ground_velocity(2.0, 0.0, 1.0, 0.0, 0.0, 1.0)
    assert (vn, ve) == (2.0, 1.0)
    assert km.speed_over_ground(vn, ve) == pytest.approx(math.sqrt(5.0))
    assert km.ground_velocity_body(2.0, 0.0, 1.0, 0.0, 0.0, 1.0) == (2.0, 1.0)  # current to starboard
    c, s = math.cos(math.radians(270.0)), math.sin(math.radians(270.0))  # heading west
    uc, vc = km.current_body(c, s, 0.0, 1.0)
    assert (uc, vc) == pytest.approx((-1.0, 0.0), abs=1e-15)  # current from ahead: set back
    # body and earth forms agree for any heading
    psi, u, v, cn, ce = 2.1, 3.0, -0.4, 0.3, -0.8
    c, s = math.cos(psi), math.sin(psi)
    ug, vg = km.ground_velocity_body(u, v, c, s, cn, ce)
    assert km.body_to_earth(c, s, ug, vg) == pytest.approx(km.ground_velocity(u, v, c, s, cn, ce), rel=1e-14)


def test_relative_wind_conventions():
    """Still air, ship at 5 m/s: a 5 m/s head wind (gamma 0). A wind from the east on a ship stopped heading
    north comes from starboard (gamma +90 deg)."""
    V, g, cg, sg = km.relative_wind(5.0, 0.0, 1.0, 0.0, 0.0, 0.0)
    assert (V, g, cg, sg) == (5.0, 0.0, 1.0, 0.0)
    V, g, cg, sg = km.relative_wind(0.0, 0.0, 1.0, 0.0, 0.0, -10.0)  # air moving west, i.e. from the east
    assert V == 10.0 and g == pytest.approx(math.pi / 2) and (cg, sg) == pytest.approx((0.0, 1.0))


@pytest.mark.parametrize("name", ["kvlcc2", "dtc"])
def test_coriolis_is_that_of_the_mass_matrix(name):
    """-C(nu) nu with C from M = M_RB + M_A in Fossen's (2011) 3-DOF skew form (eq. 3.57 for the rigid body,
    eq. 6.43 for the added mass, diagonal added mass in surge):
    C(nu) = [[0, 0, -M22 v - M23 r], [0, 0, M11 u], [M22 v + M23 r, -M11 u, 0]] with the rigid body's
    and the added mass's M11, M22, M23 -- except the Munk moment (m_y - m_x) u v, which Yasukawa & Yoshimura
    (2015) eq. 4 leave out of the MMG equations (captive tests measure it as part of the hull's N_v).
    dtc (Abkowitz, "separate" Coriolis): the rigid body only."""
    s = load_ship(name)
    P = pack(s)
    m, xG = s.mass_kg, s.particulars.x_G_m
    M = mass_matrix(s)
    rigid_only = s.hull.__class__.__name__ == "AbkowitzHull"
    M11 = m if rigid_only else M[0, 0]
    M22 = m if rigid_only else M[1, 1]
    M23 = m * xG
    u, v, r = 3.0, -0.5, 0.02
    C = np.array([[0, 0, -M22 * v - M23 * r], [0, 0, M11 * u], [M22 * v + M23 * r, -M11 * u, 0]])
    tau = -C @ np.array([u, v, r])
    tau[2] += (M22 - M11) * u * v  # the Munk moment, in the hull model instead
    assert km.coriolis_forces(P, u, v, r) == pytest.approx(tuple(tau), rel=1e-12)
    Crb = np.array([[0, 0, -m * (xG * r + v)], [0, 0, m * u], [m * (xG * r + v), -m * u, 0]])
    tau_rb = -Crb @ np.array([u, v, r])
    assert km.rigid_body_coriolis_forces(P, u, v, r) == pytest.approx(tuple(tau_rb), rel=1e-12)
    total = np.add(km.added_mass_coriolis_forces(P, u, v, r), km.rigid_body_coriolis_forces(P, u, v, r))
    assert tuple(total) == pytest.approx(km.coriolis_forces(P, u, v, r), rel=1e-12)


def test_accessors_run_uncompiled_with_the_same_results():
    P = pack(load_ship("kvlcc2"))
    args = (1.5, -0.2, math.cos(0.3), math.sin(0.3), 0.4, -0.1)
    for f in (km.ground_velocity, km.ground_velocity_body, km.relative_wind):
        assert f.py_func(*args) == f(*args)
    assert km.coriolis_forces.py_func(P, 2.0, 0.1, 0.01) == km.coriolis_forces(P, 2.0, 0.1, 0.01)
