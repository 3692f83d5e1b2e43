"""The scripted reference helms run in the environments reproduce the `vessel-gym manoeuvre` figures:
same physics, same start (steady approach), same helm rule checked at every physics step when the control
interval equals the physics step. The only difference is that the policies read float32 observations, so
the figures agree to float32 round-off (tolerances 1e-4 deg and 1 mm)."""

from __future__ import annotations

import gymnasium as gym
import pytest

import vessel_gym  # noqa: F401 (registers the ids)
from vessel_gym.envs.policies import TurningRule, ZigZagRule
from vessel_gym.manoeuvres import trial_dt, turning_circle, zigzag
from vessel_gym.physics.shipfile import load_ship

SHIP = "kvlcc2_l7"


def _dt():
    s = load_ship(SHIP)
    return trial_dt(s, s.test_speed_m_s)


@pytest.mark.parametrize("rudder", [10.0, 20.0])
def test_zigzag_rule_in_env_reproduces_manoeuvre(rudder):
    dt = _dt()
    env = gym.make("vessel_gym/ZigZag-v1", ship=SHIP, dt_s=dt, control_interval_s=dt, zigzag_heading_deg=rudder,
                   first_side="starboard", first_change_s=[0.0, 0.0], initial_heading_deg=[0.0, 0.0],
                   max_episode_steps=100_000)
    policy = ZigZagRule(env, rudder)
    obs, info = env.reset(seed=0)
    while info["overshoot_2_deg"] == 0.0:  # the first two overshoots, closed as the IMO trial measures them
        obs, _r, term, trunc, info = env.step(policy(obs))
        assert not (term or trunc)
    ref = zigzag(SHIP, rudder, rudder, dt=dt, n_overshoots=2)
    assert info["overshoot_1_deg"] == pytest.approx(ref.overshoot_deg[0], abs=1e-4)
    assert info["overshoot_2_deg"] == pytest.approx(ref.overshoot_deg[1], abs=1e-4)


def test_turning_rule_in_env_reproduces_manoeuvre():
    dt = _dt()
    env = gym.make("vessel_gym/TurningCircle-v0", ship=SHIP, dt_s=dt, control_interval_s=dt,
                   max_episode_steps=100_000)
    policy = TurningRule(env, 35.0, side=1.0)
    obs, info = env.reset(seed=0)
    while not info.get("reached_180", False):
        obs, _r, term, trunc, info = env.step(policy(obs))
        assert not trunc
    ref = turning_circle(SHIP, 35.0, dt=dt, until_deg=180.0)
    assert info["advance_m"] == pytest.approx(ref.advance_m, abs=1e-3)
    assert info["transfer_m"] == pytest.approx(ref.transfer_m, abs=1e-3)
    assert info["tactical_diameter_m"] == pytest.approx(ref.tactical_diameter_m, abs=1e-3)
