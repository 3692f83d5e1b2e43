"""Nomoto-based PID autopilot (Fossen 2011 pole placement)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vessel_gym.control import PidAutopilot, nomoto_pid_gains, wrap_pi
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
    assert abs(math.degrees(wrap_pi(sim.heading[0] - ref))) < 1.0
    assert abs(np.degrees(sim.r[0])) < 0.05 * 60 / L_over_U  # yaw rate has died out


def test_wrap_pi():
    assert wrap_pi(math.radians(350)) == pytest.approx(math.radians(-10))
    assert wrap_pi(math.pi) == pytest.approx(math.pi)
