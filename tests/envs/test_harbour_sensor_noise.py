"""HarbourApproach's sensor noise (config position_noise_m, heading_noise_deg, speed_noise_m_s): the observation
reports a noisy position fix, heading and speeds; the physics, reward, outcome and info keep the truth."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym  # noqa: F401  (registers the ids)
from vessel_gym.physics.schema import SpecError

NOISE = {"position_noise_m": 0.5, "heading_noise_deg": 2.0, "speed_noise_m_s": 0.05}


def _sail(seed: int = 5, steps: int = 150, **kw: float) -> np.ndarray:
    """Per step: (observed goal distance, true one, observed heading error deg, true one, observed sog, true
    one, reward, observed u) of a fixed helm and engine order."""
    env = gym.make("vessel_gym/HarbourApproach-v3", **kw)
    lay = env.unwrapped.observation_layout
    env.reset(seed=seed)
    rows = []
    for _ in range(steps):
        obs, r, term, trunc, info = env.step(np.array([0.1, 0.6], dtype=np.float32))
        rows.append((lay.value(obs, "goal_distance"), info["distance_to_goal_m"],
                     math.degrees(lay.value(obs, "goal_heading_error")), info["heading_error_deg"],
                     lay.value(obs, "sog"), info["speed_over_ground_m_s"], r, lay.value(obs, "u")))  # fmt: skip
        if term or trunc:
            break
    env.close()
    return np.array(rows, dtype=float)


def test_noise_is_in_the_observation_only_with_the_configured_spread():
    clean = _sail()
    noisy = _sail(**NOISE)
    assert len(clean) == len(noisy) > 100
    # the truth (info, reward) is the same ship's: the noise steers nothing by itself
    np.testing.assert_array_equal(clean[:, [1, 3, 5, 6]], noisy[:, [1, 3, 5, 6]])
    # without noise the observation is the truth (float32 observations)
    assert np.abs(clean[:, 0] - clean[:, 1]).max() < 1e-4 and np.abs(clean[:, 2] - clean[:, 3]).max() < 1e-3
    # with it: errors of zero mean and the configured standard deviation (the fix's error along the line of
    # sight for the distance); ~130 samples: the sample sd within 25 % of the true one
    for col, sd in (
        (0, NOISE["position_noise_m"]),
        (2, NOISE["heading_noise_deg"]),
        (4, NOISE["speed_noise_m_s"]),
    ):
        err = noisy[:, col] - noisy[:, col + 1]
        assert np.std(err) == pytest.approx(sd, rel=0.25)
        assert abs(np.mean(err)) < 4 * sd / math.sqrt(len(err))
    du = noisy[:, 7] - clean[:, 7]  # the log's speed: its own draw, same spread
    assert np.std(du) == pytest.approx(NOISE["speed_noise_m_s"], rel=0.25)
    assert np.corrcoef(du, noisy[:, 4] - noisy[:, 5])[0, 1] < 0.5


def test_noise_follows_the_reset_seed():
    a, b = _sail(seed=7, steps=40, **NOISE), _sail(seed=7, steps=40, **NOISE)
    c = _sail(seed=8, steps=40, **NOISE)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a[:, 0] - a[:, 1], c[:, 0] - c[:, 1])


def test_noise_keys_checked():
    with pytest.raises(SpecError, match="position_noise_m"):
        gym.make("vessel_gym/HarbourApproach-v3", position_noise_m=-1.0)
