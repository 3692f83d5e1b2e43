"""Nomoto-based PID autopilot (Fossen 2011 pole placement)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vessel_gym.control import PidAutopilot, nomoto_pid_gains, nomoto_rate_pi_gains, wrap_pi_upper
from vessel_gym.control.pid import pid_integral, pid_integral_batch, pid_rudder, pid_rudder_batch
from vessel_gym.physics.linear import nomoto
from vessel_gym.physics.simulation import Simulation


def test_gains_follow_pole_placement_formulas():
    g = nomoto_pid_gains("mariner", 7.7175, omega_n=0.05, zeta=1.0)
    K, T = g.model.K, g.model.T
    assert g.K_p == pytest.approx(T * 0.05**2 / K)
    assert g.K_d == pytest.approx((2 * 1.0 * 0.05 * T - 1) / K)
    assert g.K_i == pytest.approx(0.05 * g.K_p / 10)


@pytest.mark.parametrize("ship", ["mariner", "kvlcc2_l7"])
def test_pid_brings_ship_to_new_course(ship):
    """A 20 deg course change settles within 1 deg (course-stable Mariner and course-unstable KVLCC2)."""
    sim = Simulation(ship, dt=0.05)
    sim.reset()
    ap = PidAutopilot.for_ship(ship)
    s = sim.ship()
    L_over_U = s.particulars.L_m / s.test_speed_m_s
    ref = math.radians(20.0)
    for _ in range(int(25 * L_over_U / 0.5)):
        sim.set_helm(ap.order(sim.heading[0], sim.r[0], ref, 0.5))
        sim.advance(0.5)
    assert abs(math.degrees(wrap_pi_upper(sim.heading[0] - ref))) < 1.0
    assert abs(np.degrees(sim.r[0])) < 0.05 * 60 / L_over_U  # yaw rate has died out


def test_rate_pi_gains_place_the_closed_loop_poles():
    """T s^2 + (1 + K K_p) s + K K_i = T (s^2 + 2 zeta omega s + omega^2) on Nomoto's first-order model."""
    for ship in ("mariner", "kvlcc2_l7"):  # course-stable and course-unstable
        m = nomoto(ship)
        Kp, Ki = nomoto_rate_pi_gains(m, 0.1, zeta=0.8)
        assert (1.0 + m.K * Kp) / m.T == pytest.approx(2 * 0.8 * 0.1)
        assert m.K * Ki / m.T == pytest.approx(0.1**2)


def test_conditional_integration_and_clamp():
    assert pid_integral(0.2, 0.1, 2.0, 1.0, 0.5) == pytest.approx(0.4)
    assert pid_integral(0.2, 0.6, 2.0, 1.0, 0.5) == 0.2  # |e| above the threshold: held
    assert pid_integral(0.9, 0.1, 2.0, 1.0, 0.5) == 1.0  # clamped
    assert pid_integral(-0.9, -0.1, 2.0, 1.0, 0.5) == -1.0


def test_law_and_clip():
    assert pid_rudder(0.1, 0.5, 0.02, 2.0, 0.1, 10.0, 0.6) == pytest.approx(2.0 * 0.1 + 0.1 * 0.5 - 10.0 * 0.02)
    assert pid_rudder(1.0, 0.0, 0.0, 2.0, 0.1, 10.0, 0.6) == 0.6
    assert pid_rudder(-1.0, 0.0, 0.0, 2.0, 0.1, 10.0, 0.6) == -0.6


def test_batch_forms_are_the_same_law():
    rng = np.random.default_rng(0)
    e, i, r = rng.normal(0, 0.5, (3, 50))
    batch = pid_rudder_batch(e, i, r, 1.5, 0.02, 8.0, 0.6)
    assert batch.tolist() == [pid_rudder(a, b, c, 1.5, 0.02, 8.0, 0.6) for a, b, c in zip(e, i, r)]
    batch = pid_integral_batch(i, e, 0.25, 0.4, 0.3)
    assert batch.tolist() == [pid_integral(b, a, 0.25, 0.4, 0.3) for a, b in zip(e, i)]


def test_autopilot_is_the_textbook_law():
    """delta = -(K_p e + K_i int e dt + K_d r), e = psi - psi_ref, integral while |e| < 5 deg (Fossen 2011)."""
    ap = PidAutopilot.for_ship("mariner")
    g, lim = ap.gains, ap.max_rudder_rad
    integral = 0.0
    for psi, r in [(0.01, 0.001), (0.05, -0.002), (0.3, 0.004), (-0.02, 0.0)]:
        e = psi - 0.0
        if abs(e) < math.radians(5.0):
            integral = min(max(integral + e * 0.5, -lim / g.K_i), lim / g.K_i)
        want = min(max(-(g.K_p * e + g.K_i * integral + g.K_d * r), -lim), lim)
        assert ap.order(psi, r, 0.0, 0.5) == pytest.approx(want, rel=1e-12, abs=1e-15)
        assert ap.integral == pytest.approx(integral, rel=1e-12, abs=1e-15)
