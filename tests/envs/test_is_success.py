"""``info["is_success"]``, the key Stable-Baselines3 logs a success rate from, exists exactly where a task has
success (HarbourApproach; TurningCircle in reverse mode; ZigZag-v1 and ZigZagRandom-v1), equals ``info["success"]`` and is a Python bool in
the single environment and an array in the vector environment."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

CASES = [
    ("vessel_gym/HarbourApproach-v2", {}, True),
    ("vessel_gym/HarbourApproach-v1", {}, True),
    ("vessel_gym/HarbourApproach-v1", {"layout": "procedural", "difficulty": 0}, True),
    ("vessel_gym/TurningCircle-v0", {"mode": "reverse"}, True),
    ("vessel_gym/TurningCircle-v0", {"mode": "rate"}, False),
    ("vessel_gym/ZigZag-v1", {}, True),
    ("vessel_gym/ZigZagRandom-v1", {}, True),
]


@pytest.mark.parametrize(("env_id", "kwargs", "has"), CASES)
def test_is_success_where_the_task_has_success(env_id: str, kwargs: dict, has: bool) -> None:
    env = gym.make(env_id, **kwargs)
    _obs, info = env.reset(seed=0)
    _obs, _r, _term, _trunc, step_info = env.step(env.action_space.sample())
    for i in (info, step_info):
        assert ("is_success" in i) is has
        if has:
            assert i["is_success"] is i["success"] is False
    env.close()
    venv = gym.make_vec(env_id, 3, vectorization_mode="vector_entry_point", **kwargs)
    _obs, info = venv.reset(seed=0)
    assert ("is_success" in info) is has
    if has:
        np.testing.assert_array_equal(info["is_success"], info["success"])
        assert info["is_success"].dtype == np.bool_ and info["is_success"].shape == (3,)
    venv.close()


def test_turning_reverse_success_sets_is_success() -> None:
    """Hard over until the heading has changed by 180 deg: the terminating step reports is_success."""
    env = gym.make("vessel_gym/TurningCircle-v0", mode="reverse")
    env.reset(seed=0)
    for _ in range(480):
        _obs, _r, terminated, truncated, info = env.step(np.array([1.0], dtype=np.float32))
        if terminated or truncated:
            break
    assert terminated and info["is_success"] is True and info["success"] is True
    env.close()
