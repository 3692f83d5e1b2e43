"""Line-of-sight guidance (Fossen 2011 §10.3.2) on simple geometry."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vessel_gym.control import leg_frame, los_heading, pursuit_heading, waypoint_reached


def test_leg_frame_on_an_eastward_leg():
    alpha, along, cross, length = leg_frame(0.0, 0.0, 0.0, 100.0, -10.0, 30.0)
    assert alpha == pytest.approx(math.pi / 2)
    assert along == pytest.approx(30.0)
    assert cross == pytest.approx(10.0)  # 10 m south of an eastward leg is to starboard of it
    assert length == pytest.approx(100.0)


def test_los_steers_back_to_the_leg():
    assert los_heading(0.3, 0.0, 50.0) == pytest.approx(0.3)  # on the leg: along it
    # cross-track error equal to the look-ahead distance: 45 deg towards the leg
    assert los_heading(0.0, 50.0, 50.0) == pytest.approx(-math.pi / 4)
    assert los_heading(0.0, -50.0, 50.0) == pytest.approx(math.pi / 4)


def test_pursuit_and_acceptance_scalar_and_batch():
    assert pursuit_heading(0.0, 0.0, 0.0, 10.0) == pytest.approx(math.pi / 2)
    assert pursuit_heading(0.0, 0.0, -10.0, 0.0) == pytest.approx(math.pi)
    assert waypoint_reached(0.0, 0.0, 3.0, 4.0, 5.01) and not waypoint_reached(0.0, 0.0, 3.0, 4.0, 5.0)
    n = np.array([0.0, 1.0])
    assert pursuit_heading.py_func(n, 0.0, 10.0, 10.0).tolist() == [
        pursuit_heading(0.0, 0.0, 10.0, 10.0),
        pursuit_heading(1.0, 0.0, 10.0, 10.0),
    ]
