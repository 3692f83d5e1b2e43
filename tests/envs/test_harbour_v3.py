"""HarbourApproach-v3: v2 with the smooth helm (the rudder order follows the action as a first-order lag of one
ship time scale, at most a quarter of the steering gear's rate) and rudder changes charged 10x, in the single
and the vector environment."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.envs.tasks.harbour_helm import LagHelm
from vessel_gym.physics.schema import SpecError
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.policy import load_policy

ID = "vessel_gym/HarbourApproach-v3"
GEAR_DEG_S = load_ship("kvlcc2_l7_harbour").steering_gear.max_rate_deg_s  # 15.8 deg/s on the L7 model


def _order_deg(env, obs) -> float:
    return math.degrees(float(env.unwrapped.observation_layout.value(obs, "rudder_order")))


def test_v3_is_v2_with_the_smooth_helm_and_the_rudder_charge():
    v2, v3 = gym.make("vessel_gym/HarbourApproach-v2").unwrapped, gym.make(ID).unwrapped
    assert isinstance(v3.task.helm, LagHelm) and not isinstance(v2.task.helm, LagHelm)
    assert v3.config.rudder_action == "lag" and v3.config.rudder_rate_fraction == 0.25
    assert v3.config.rudder_lag_time_scales == 1.0
    assert v3.config.reward.rudder_activity == pytest.approx(10 * v2.config.reward.rudder_activity)
    assert v3.action_space == v2.action_space  # Box(-1, 1, (2,))
    assert v3.task.ship.name == v2.task.ship.name and v3.config.chart_depth


def test_the_order_lags_the_action_and_moves_at_most_the_capped_rate():
    """Time scale L / U_T = 5.93 s, control step 0.99 s: the lag closes 1 - exp(-0.99 / 5.93) = 15.4 % of the
    gap per step, capped at 0.25 x 15.8 deg/s x 0.99 s = 3.91 deg; hard over (35 deg) from amidships: capped
    (15.4 % would be 5.4 deg) until the gap is below 25.4 deg, then 15.4 % of it."""
    env = gym.make(ID)
    u = env.unwrapped
    time_scale = u.task.L / u.task.U_T
    gain = 1.0 - math.exp(-0.99 / time_scale)
    assert time_scale == pytest.approx(5.93, abs=0.01) and gain == pytest.approx(0.154, abs=0.001)
    cap = 0.25 * GEAR_DEG_S * 0.99
    assert cap == pytest.approx(3.91, abs=0.01)
    obs, _ = env.reset(seed=3)
    assert _order_deg(env, obs) == 0.0
    want, order = [], 0.0
    for _ in range(8):
        order += min(gain * (35.0 - order), cap)
        want.append(order)
    seen = []
    for _ in range(8):
        obs, *_ = env.step(np.array([1.0, 0.5], dtype=np.float32))
        seen.append(_order_deg(env, obs))
    assert np.allclose(seen, want, atol=1e-6)
    assert np.allclose(np.diff([0.0, *seen])[:3], cap, atol=1e-6)  # the cap acts first
    assert np.all(np.abs(np.diff([0.0, *seen])) <= cap + 1e-9)
    obs, *_ = env.step(np.array([5.0, 0.5], dtype=np.float32))  # clipped to 1: asks 35 deg again
    assert _order_deg(env, obs) == pytest.approx(seen[-1] + gain * (35.0 - seen[-1]), abs=1e-5)
    obs, *_ = env.step(np.array([-1.0, 0.5], dtype=np.float32))  # reversing: capped
    assert _order_deg(env, obs) == pytest.approx(seen[-1] + gain * (35.0 - seen[-1]) - cap, abs=1e-5)
    with pytest.raises(ValueError, match="NaN"):
        env.step(np.array([np.nan, 0.5], dtype=np.float32))


def test_single_and_native_vector_env_agree():
    n = 3
    venv = gym.make_vec(ID, num_envs=n, vectorization_mode="vector_entry_point")
    singles = [gym.make(ID) for _ in range(n)]
    seeds = [11, 12, 13]
    vobs, _ = venv.reset(seed=seeds)
    sobs = [e.reset(seed=s)[0] for e, s in zip(singles, seeds)]
    rng = np.random.default_rng(0)
    for _ in range(25):
        a = rng.uniform(-1.0, 1.0, size=(n, 2)).astype(np.float32)
        vobs, vrew, vterm, vtrunc, _ = venv.step(a)
        for k, e in enumerate(singles):
            o, r, term, trunc, _ = e.step(a[k])
            assert np.allclose(o, vobs[k], atol=1e-6) and r == pytest.approx(vrew[k], abs=1e-9)
            assert (term, trunc) == (bool(vterm[k]), bool(vtrunc[k]))
            sobs[k] = o


def test_rudder_changes_are_charged_by_the_v3_weight():
    env = gym.make(ID)
    env.reset(seed=5)
    _, _, _, _, info = env.step(np.array([1.0, 0.5], dtype=np.float32))
    # -|change of order| / (2 x 35 deg) x 0.5, the change capped at 3.91 deg
    assert info["reward_terms"]["rudder_activity"] == pytest.approx(-0.5 * 0.25 * GEAR_DEG_S * 0.99 / 70.0, rel=1e-6)


def test_the_pilot_steers_through_the_lag_and_arrives():
    env = gym.make(ID)
    pilot = load_policy("pid", env)
    obs, _ = env.reset(seed=9100)
    prev, biggest = 0.0, 0.0
    while True:
        obs, _, term, trunc, info = env.step(pilot(obs))
        order = _order_deg(env, obs)
        biggest, prev = max(biggest, abs(order - prev)), order
        if term or trunc:
            break
    assert info["success"] and biggest <= 0.25 * GEAR_DEG_S * 0.99 + 1e-6


def test_lag_needs_the_continuous_helm():
    with pytest.raises(SpecError, match="rudder_action"):
        gym.make(ID, action_type="discrete")
