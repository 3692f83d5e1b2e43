"""An action of the wrong kind (text, complex, booleans) is one clear ValueError on every helm path."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)

BAD = ["a", 1j, np.array([1j]), np.array(["x"]), np.array([True]), [object()]]


@pytest.mark.parametrize("env_id", ["vessel_gym/TurningCircle-v0", "vessel_gym/HarbourApproach-v2"])
@pytest.mark.parametrize("action", BAD, ids=repr)
def test_wrong_kind_of_action_is_refused_by_name(env_id, action):
    env = gym.make(env_id)
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"^action must be real numbers, got (text|complex|booleans|objects)"):
        env.step(action)
    env.step(np.zeros(env.action_space.shape, np.float32))  # the env still steps afterwards
    env.close()


def test_vector_env_refuses_complex_actions():
    envs = gym.make_vec("vessel_gym/TurningCircle-v0", num_envs=2)
    envs.reset(seed=0)
    with pytest.raises(ValueError, match=r"^actions must be real numbers, got complex"):
        envs.step(np.array([[1j], [0.0]]))
    envs.close()
