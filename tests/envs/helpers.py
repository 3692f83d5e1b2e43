"""Shared helpers of the environment tests."""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from vessel_gym.envs.registration import registered

#: every registered id, from the task declarations
ENV_IDS = sorted(registered())

# config variants exercised by the API tests besides the defaults
VARIANTS = [
    ("vessel_gym/ZigZag-v1", {"engine_control": True, "observation_type": "physical"}),
    ("vessel_gym/ZigZag-v1", {"action_type": "discrete", "first_change_s": [0.0, 0.0]}),
    (
        "vessel_gym/ZigZag-v1",
        {
            "ship": "mariner",
            "wind_speed_m_s": [5.0, 15.0],
            "current_speed_m_s": [0.2, 1.0],
            "Hs_m": [1.0, 3.0],
        },
    ),
    ("vessel_gym/ZigZagRandom-v1", {"leg_time_s": [2.0, 4.0], "engine_control": True}),
    ("vessel_gym/TurningCircle-v0", {"mode": "radius"}),
    ("vessel_gym/TurningCircle-v0", {"current_speed_m_s": [0.05, 0.2], "current_to_rel_deg": [60.0, 120.0]}),
    ("vessel_gym/TurningCircle-v0", {"mode": "reverse", "action_type": "discrete", "engine_control": True}),
    ("vessel_gym/HarbourApproach-v1", {"action_type": "discrete"}),
    ("vessel_gym/HarbourApproach-v2", {"observation_type": "physical", "n_beams": 4}),
]


def rollout(env: gym.Env, seed: int, steps: int, action_seed: int = 0):
    """(observations, rewards, terminated, truncated, infos) of a random-action rollout with resets."""
    env.action_space.seed(action_seed)
    obs, info = env.reset(seed=seed)
    out = [(obs, 0.0, False, False, info)]
    for _ in range(steps):
        obs, r, te, tr, info = env.step(env.action_space.sample())
        out.append((obs, r, te, tr, info))
        if te or tr:
            obs, info = env.reset()
            out.append((obs, 0.0, False, False, info))
    return out


def same(a, b) -> bool:
    """Exact equality of nested rollout data."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray):
        return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a, b)
    return a == b
