"""The zig-zag rule and the overshoot tracker (MSC.137(76) §4.2.4) on analytic heading histories."""

from __future__ import annotations

import math

import pytest

from vessel_gym.control import (
    OVERSHOOT_IMO,
    OVERSHOOT_V1,
    OvershootTracker,
    overshoot_step,
    target_reached,
    zigzag_execute,
)


def test_execute_flips_the_target_about_the_original_course():
    assert not target_reached(1.0, 0.17, 0.2)
    assert target_reached(1.0, 0.2, 0.2) and target_reached(1.0, 0.25, 0.2)
    assert target_reached(-1.0, -0.3, -0.2) and not target_reached(-1.0, -0.1, -0.2)
    assert zigzag_execute(1.0, 1.0, 0.2) == (-1.0, 0.8)
    assert zigzag_execute(1.0, -1.0, 0.2) == (1.0, 1.2)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_overshoot_of_a_sinusoidal_swing(sign):
    """psi = sign A sin(w t): the overshoot past psi_z is A - psi_z at t = pi / (2 w), to sampling error
    A (w dt)^2 / 2 in angle and dt in time."""
    A, w, dt, psi_z = math.radians(18.0), 0.05, 0.1, math.radians(10.0)
    t = math.asin(psi_z / A) / w  # the execute, where the heading reaches psi_z
    tr = OvershootTracker(OVERSHOOT_IMO)
    tr.start(sign, sign * psi_z, sign * A * math.sin(w * t), t)
    while not tr.update(sign * A * math.sin(w * t), sign * A * w * math.cos(w * t), t):
        t += dt
    assert tr.overshoots_rad[0] == pytest.approx(A - psi_z, abs=A * (w * dt) ** 2 / 2)
    assert tr.times_s[0] == pytest.approx(math.pi / (2 * w), abs=dt)
    assert t > tr.times_s[0]


def test_modes_differ_on_a_zero_yaw_rate():
    """The trial ends the measurement once the yaw rate has strictly reversed; V1 never ends it itself."""
    peak = 0.1
    assert overshoot_step(1.0, 0.0, peak, 0.05, 0.0, OVERSHOOT_IMO) == (peak, False, False)
    assert overshoot_step(1.0, 0.0, peak, 0.05, -1e-3, OVERSHOOT_IMO) == (peak, False, True)
    assert overshoot_step(1.0, 0.0, peak, 0.05, -1e-3, OVERSHOOT_V1) == (peak, False, False)
    # the trial keeps the measurement open while the excursion grows, whatever the yaw rate
    assert overshoot_step(1.0, 0.0, peak, 0.2, -1e-3, OVERSHOOT_IMO) == (0.2, True, False)


def test_v1_keeps_the_largest_excursion_until_closed():
    """V1: the yaw rate never ends the measurement; a second swing past the target raises the overshoot only
    if it goes further; ``close`` counts it as it stands."""
    assert overshoot_step(1.0, 0.0, 0.1, 0.05, -1.0, OVERSHOOT_V1) == (0.1, False, False)
    assert overshoot_step(-1.0, 0.0, 0.1, -0.2, 1.0, OVERSHOOT_V1) == (0.2, True, False)
    tr = OvershootTracker(OVERSHOOT_V1)
    tr.start(1.0, 0.2, 0.21, 0.0)
    for t, (h, r) in enumerate([(0.25, 0.1), (0.22, -0.1), (0.1, -0.1), (0.24, 0.1), (0.27, 0.1)], start=1):
        assert not tr.update(h, r, float(t))
    tr.close()
    assert tr.overshoots_rad == [pytest.approx(0.07)] and tr.times_s == [5.0] and not tr.active
    tr.close()  # nothing open: nothing counted
    assert len(tr.overshoots_rad) == 1


def test_every_user_calls_the_same_functions():
    """One home: the trial, the trials helm, the task kernel and the evaluation use these objects."""
    from vessel_gym.control import zigzag as z
    from vessel_gym.envs.tasks import zigzag as task
    from vessel_gym.manoeuvres import helms, trials

    assert task.target_reached is z.target_reached and helms.target_reached is z.target_reached
    assert task.zigzag_execute is z.zigzag_execute and helms.zigzag_execute is z.zigzag_execute
    assert task.overshoot_step is z.overshoot_step
    assert trials.OvershootTracker is z.OvershootTracker
