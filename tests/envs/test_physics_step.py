"""The environments' default physics step: chosen from the ship's fastest mode, and converged.

The default is the longest whole fraction of the control interval within half of RK4's stable step
(|lambda| dt <= 2.785 on the real axis, Hairer & Wanner II sec. IV.2). These tests check the rule and that the
default step's discretisation error is negligible next to what the tasks report, against a reference with
ten times more steps per control interval (same seeds, same held helm orders).
"""

import math

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym  # noqa: F401
from vessel_gym.physics.linear import fastest_rate, stable_step
from vessel_gym.physics.schema import SpecError


def test_fastest_mode_of_the_model_ship_is_its_steering_gear():
    # kvlcc2_l7.toml: steering-gear lag time constant 0.1 s -> eigenvalue -10 1/s (the hull's are below 1 1/s)
    assert fastest_rate("kvlcc2_l7") == pytest.approx(10.0, rel=1e-4)
    assert stable_step("kvlcc2_l7") == pytest.approx(0.2785, rel=1e-4)
    assert stable_step("kvlcc2_l7", "euler") == pytest.approx(0.2, rel=1e-4)


@pytest.mark.parametrize(
    ("control_interval_s", "expected_dt"),
    [(0.25, 0.125), (0.5, 0.125), (0.1, 0.1), (1.0, 0.125)],
)
def test_default_step_is_a_whole_fraction_within_half_the_stable_step(control_interval_s, expected_dt):
    env = gym.make("vessel_gym/ZigZag-v0", control_interval_s=control_interval_s)
    task = env.unwrapped.task
    assert task.dt == pytest.approx(expected_dt)
    assert task.nsub * task.dt == pytest.approx(control_interval_s)
    assert task.dt <= 0.5 * stable_step("kvlcc2_l7") + 1e-12


def test_explicit_step_beyond_the_stable_step_raises():
    with pytest.raises(SpecError, match="dt_s = 0.3 s is beyond the stable rk4 step of ship 'kvlcc2_l7'"):
        gym.make("vessel_gym/ZigZag-v0", dt_s=0.3, control_interval_s=0.6)
    gym.make("vessel_gym/ZigZag-v0", dt_s=0.25)  # within the limit: the user's choice stands


def _rollout(env_id: str, dt_s: float | None, steps: int) -> np.ndarray:
    env = gym.make(env_id) if dt_s is None else gym.make(env_id, dt_s=dt_s)
    env.reset(seed=3)
    orders = np.random.default_rng(1).uniform(-1.0, 1.0, size=(steps // 20 + 1, env.action_space.shape[0]))
    sim = env.unwrapped.sim
    track = []
    for i in range(steps):
        _o, _r, term, trunc, _i = env.step(orders[i // 20].astype(np.float32))  # each order held 5 s
        track.append([sim.north[0], sim.east[0], math.degrees(sim.heading[0]), sim.rev[0]])
        assert not (term or trunc)
    return np.array(track)


# Tolerances: ZigZag reports overshoot angles to 0.1 deg, so the step may add at most a tenth of that in
# heading; positions to 0.001 L (7 mm). HarbourApproach decides contact and arrival on positions and a heading
# tolerance of degrees: 0.01 L (7 cm) and 0.1 deg. Shaft speed within 1 % of full ahead (11.85 rev/s).
@pytest.mark.parametrize(
    ("env_id", "pos_m", "heading_deg"),
    [("vessel_gym/ZigZag-v0", 0.007, 0.01), ("vessel_gym/HarbourApproach-v0", 0.07, 0.1)],
)
def test_default_step_matches_a_ten_times_finer_step(env_id, pos_m, heading_deg):
    steps = 400  # 100 s of random held helm orders (rudder; engine too in HarbourApproach)
    coarse = _rollout(env_id, None, steps)
    fine = _rollout(env_id, 0.0125, steps)
    err = np.abs(coarse - fine).max(axis=0)
    assert err[0] < pos_m and err[1] < pos_m
    assert err[2] < heading_deg
    assert err[3] < 0.01 * 11.85
