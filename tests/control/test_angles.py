"""Angle wrapping: each function keeps its documented range, also on the boundary."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vessel_gym.control import wrap_pi, wrap_pi_upper


def test_ranges_on_the_boundary():
    assert wrap_pi(math.pi) == -math.pi
    assert wrap_pi(-math.pi) == -math.pi
    assert wrap_pi_upper(math.pi) == math.pi
    assert wrap_pi_upper(-math.pi) == math.pi
    assert wrap_pi(0.0) == 0.0 and wrap_pi_upper(0.0) == 0.0


@pytest.mark.parametrize("deg, want", [(350.0, -10.0), (-350.0, 10.0), (190.0, -170.0), (725.0, 5.0)])
def test_wraps_to_the_same_direction(deg, want):
    for f in (wrap_pi, wrap_pi_upper):
        assert math.degrees(f(math.radians(deg))) == pytest.approx(want)


def test_the_two_agree_inside_and_run_on_arrays():
    a = np.random.default_rng(1).uniform(-20.0, 20.0, 2000)
    inside = [wrap_pi(x) for x in a]
    assert inside == [wrap_pi_upper(x) for x in a]
    assert all(-math.pi <= x < math.pi for x in inside)
    assert wrap_pi.py_func(a).tolist() == inside  # the un-jitted body on a batch
