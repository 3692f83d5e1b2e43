"""The ZigZag and TurningCircle tasks apply the shared rules of vessel_gym.control, and their v0 behaviour
is unchanged.

Two kinds of check on the same short fixed-action rollouts (tests/control/rollouts.py):

* replay: the overshoot and turning-circle figures in ``info`` equal those computed by the control rules from
  the simulation's own heading, yaw rate and position at every control step (exact: same rule, same samples);
* regression pin: reward sums, final observations and info of the rollouts as computed by the code before the
  rules moved to vessel_gym.control. These numbers are our own output, kept only to catch a change of v0's
  behaviour; tolerance 1e-9 relative (the runs are deterministic; the margin covers libm differences).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from rollouts import rollout, turning_action, zigzag_action

from vessel_gym.control import (
    ADVANCE_HEADING_RAD,
    OVERSHOOT_V0,
    TACTICAL_HEADING_RAD,
    at_crossing,
    course_axes,
    crossing_fraction,
    overshoot_excursion,
    overshoot_step,
    target_reached,
    zigzag_execute,
)

PIN = pytest.approx  # regression pin: see the module docstring


@pytest.fixture(scope="module")
def zigzag_run():
    return rollout("vessel_gym/ZigZag-v1", zigzag_action, seed=3)


@pytest.fixture(scope="module")
def reverse_run():
    return rollout("vessel_gym/TurningCircle-v0", turning_action, seed=7, mode="reverse")


def replay_zigzag_v0(motion, psi_z):
    """The IMO schedule and the v0 overshoot accounting over the samples (heading, r, north, east)."""
    psi0 = motion[0][0]
    side, target = 1.0, psi0 + psi_z  # first target to starboard (the default first_side)
    on, sign, ref, peak = False, 0.0, 0.0, 0.0
    overshoots, executes = [], 1
    for psi, r, _n, _e in motion[1:]:
        if on:
            peak, _rose, finished = overshoot_step(sign, ref, peak, psi, r, OVERSHOOT_V0)
            if finished:
                overshoots.append(peak)
                on = False
        if target_reached(side, psi, target):
            if on:
                overshoots.append(peak)
            on, sign, ref = True, side, target
            peak = overshoot_excursion(sign, ref, psi)
            side, target = zigzag_execute(psi0, side, psi_z)
            executes += 1
    return overshoots, executes


def test_zigzag_info_is_the_shared_rule(zigzag_run):
    _tot, _obs, info, motion, _infos = zigzag_run
    overshoots, executes = replay_zigzag_v0(motion, math.radians(10.0))
    assert len(overshoots) >= 3  # the rollout exercises the tracker
    assert info["executes"] == executes
    assert info["overshoot_count"] == len(overshoots)
    assert info["overshoot_1_deg"] == math.degrees(overshoots[0])
    assert info["overshoot_2_deg"] == math.degrees(overshoots[1])
    assert info["last_overshoot_deg"] == math.degrees(overshoots[-1])


def test_turning_info_is_the_shared_rule(reverse_run):
    _tot, _obs, info, motion, _infos = reverse_run
    psi0, n0, e0 = motion[0][0], motion[0][2], motion[0][3]
    found = {}
    prev_turned, prev_adv, prev_trf = 0.0, 0.0, 0.0
    for psi, _r, n, e in motion[1:]:
        adv, trf = course_axes(psi0, n0, e0, n, e)
        turned = abs(psi - psi0)
        for name, level in (("90", ADVANCE_HEADING_RAD), ("180", TACTICAL_HEADING_RAD)):
            if name not in found and turned >= level:
                f = crossing_fraction(prev_turned, turned, level)
                found[name] = (at_crossing(prev_adv, adv, f), at_crossing(prev_trf, trf, f))
        prev_turned, prev_adv, prev_trf = turned, adv, trf
    assert info["reached_180"] and info["success"]
    assert info["advance_m"] == found["90"][0]
    assert info["transfer_m"] == abs(found["90"][1])
    assert info["tactical_diameter_m"] == abs(found["180"][1])


def test_zigzag_v0_regression_pin(zigzag_run):
    tot, obs, info, motion, _infos = zigzag_run
    assert len(motion) - 1 == 480
    assert tot == PIN(-208.9928407908321, rel=1e-9)
    assert np.asarray(obs, float) == PIN(
        [0.434635728597641, 0.07362264394760132, 0.04718291759490967, 1.0, 1.0, 0.15461014211177826,
         -0.09905458986759186, 0.0555555559694767], rel=1e-6, abs=1e-7)
    assert info["executes"] == 5 and info["overshoot_count"] == 4
    assert info["target_heading_deg"] == PIN(10.0, rel=1e-9)
    assert info["heading_error_deg"] == PIN(27.829826774679994, rel=1e-9)
    assert info["overshoot_1_deg"] == PIN(30.006833509151246, rel=1e-9)
    assert info["overshoot_2_deg"] == PIN(2.137455462942732, rel=1e-9)
    assert info["last_overshoot_deg"] == PIN(8.948693450956567, rel=1e-9)
    assert info["reward_terms"] == PIN(
        {"heading_error": -0.15461014874822218, "overshoot": 0.0, "rudder_activity": 0.0,
         "speed_loss": -0.17350399967815938}, rel=1e-9, abs=1e-12)


def test_turning_reverse_regression_pin(reverse_run):
    tot, obs, info, motion, _infos = reverse_run
    assert len(motion) - 1 == 206
    assert tot == PIN(-8.935581142221798, rel=1e-9)
    assert np.asarray(obs, float) == PIN(
        [0.28035134077072144, -0.28180715441703796, 0.17249032855033875, 1.0, 1.0, 0.5016593933105469,
         0.22084200382232666, 0.3124781847000122], rel=1e-6, abs=1e-7)
    assert info["heading_change_deg"] == PIN(180.59738544930974, rel=1e-9)
    assert info["advance_m"] == PIN(21.551646933592, rel=1e-9)
    assert info["transfer_m"] == PIN(9.328799692449918, rel=1e-9)
    assert info["tactical_diameter_m"] == PIN(21.843933828795965, rel=1e-9)
    assert info["reward_terms"] == PIN(
        {"tracking_error": 0.0, "progress": 0.006532370234148475, "footprint": -0.005881228135645448,
         "rudder_activity": 0.0, "speed_loss": -0.05564948979713248, "time": -0.004210727777777778},
        rel=1e-9, abs=1e-12)


def test_turning_rate_regression_pin():
    tot, _obs, info, motion, _infos = rollout("vessel_gym/TurningCircle-v0", turning_action, seed=7)
    assert len(motion) - 1 == 480
    assert tot == PIN(-501.3346427693072, rel=1e-9)
    assert info["commanded_rate_deg_s"] == PIN(-2.647104335542724, rel=1e-9)
    assert info["heading_change_deg"] == PIN(371.6621512688302, rel=1e-9)
    assert info["tactical_diameter_m"] == PIN(21.843933828795965, rel=1e-9)
