"""Turning-circle geometry (MSC.137(76) §4.2.2) on an exact circle: advance = transfer = R at 90 deg,
tactical diameter = 2 R at 180 deg."""

from __future__ import annotations

import math

import pytest

from vessel_gym.control import (
    ADVANCE_HEADING_RAD,
    TACTICAL_HEADING_RAD,
    at_crossing,
    course_axes,
    crossing_fraction,
)


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_circle(side):
    R, psi0, n0, e0 = 250.0, math.radians(30.0), 1000.0, -400.0
    step = math.radians(1.7)  # samples that do not fall on 90 or 180 deg
    c, s = math.cos(psi0), math.sin(psi0)
    found = {}
    prev = (0.0, 0.0, 0.0)
    th = 0.0
    while th < math.radians(200.0):
        th += step
        x, y = R * math.sin(th), side * R * (1.0 - math.cos(th))  # along / across the original course
        n, e = n0 + c * x - s * y, e0 + s * x + c * y
        adv, trf = course_axes(psi0, n0, e0, n, e)
        assert (adv, trf) == pytest.approx((x, y), abs=1e-9)
        for level in (ADVANCE_HEADING_RAD, TACTICAL_HEADING_RAD):
            if level not in found and th >= level:
                f = crossing_fraction(prev[0], th, level)
                found[level] = (at_crossing(prev[1], adv, f), at_crossing(prev[2], trf, f))
        prev = (th, adv, trf)
    tol = R * step**2 / 8  # linear interpolation of R sin / R cos over one sample
    assert found[ADVANCE_HEADING_RAD][0] == pytest.approx(R, abs=tol)
    assert abs(found[ADVANCE_HEADING_RAD][1]) == pytest.approx(R, abs=tol)
    assert abs(found[TACTICAL_HEADING_RAD][1]) == pytest.approx(2 * R, abs=tol)


def test_crossing_fraction():
    assert crossing_fraction(1.0, 2.0, 1.25) == 0.25
    assert crossing_fraction(2.0, 2.0, 1.5) == 1.0  # heading change did not grow: the present sample
    assert at_crossing(10.0, 20.0, 0.25) == 12.5
