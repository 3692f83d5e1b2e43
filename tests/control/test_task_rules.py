"""The TurningCircle task applies the shared rules of vessel_gym.control, and its v0 behaviour is unchanged
(ZigZag-v0, whose overshoot accounting these tests also pinned, is removed; ZigZag-v1's is tested in
tests/envs/test_zigzag_v1.py and by the golden rollouts).

Two kinds of check on the same short fixed-action rollouts (tests/control/rollouts.py):

* replay: the overshoot and turning-circle figures in ``info`` equal those computed by the control rules from
  the simulation's own heading, yaw rate and position at every control step (exact: same rule, same samples);
* regression pin: reward sums, final observations and info of the rollouts as computed by the code before the
  rules moved to vessel_gym.control. These numbers are our own output, kept only to catch a change of v0's
  behaviour; tolerance 1e-9 relative (the runs are deterministic; the margin covers libm differences).
"""

from __future__ import annotations

import numpy as np
import pytest
from rollouts import rollout, turning_action

from vessel_gym.control import (
    ADVANCE_HEADING_RAD,
    TACTICAL_HEADING_RAD,
    at_crossing,
    course_axes,
    crossing_fraction,
)

PIN = pytest.approx  # regression pin: see the module docstring


@pytest.fixture(scope="module")
def reverse_run():
    return rollout("vessel_gym/TurningCircle-v0", turning_action, seed=7, mode="reverse")


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
