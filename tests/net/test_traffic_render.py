"""Env frames and the play window draw the scenario's traffic, simulated only for the frames."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401

pytest.importorskip("pygame")


def _traffic_pixels(frame: np.ndarray) -> int:
    from vessel_gym.ui.chart import TRAFFIC

    return int(np.all(frame == np.array(TRAFFIC), axis=-1).sum())


def test_harbour_frames_draw_the_traffic_moving():
    env = gym.make("vessel_gym/HarbourApproach-v2", render_mode="rgb_array")
    try:
        env.reset(seed=0)
        first = env.render()
        assert _traffic_pixels(first) > 20  # KVLCC2 LOOP and KVLCC2 PIER, 7 m x 1.27 m each
        for _ in range(80):  # 20 s: the loop ship makes 1.5 kn, about 15 m
            env.step(np.zeros(2, dtype=np.float32))
        later = env.render()
        base = env.unwrapped
        assert base._traffic.steps == 80  # caught up with the episode only when drawn
        moved = np.any(
            np.all(first == np.array((150, 60, 170)), axis=-1)
            != np.all(later == np.array((150, 60, 170)), axis=-1)
        )
        assert moved
        env.reset(seed=1)
        env.render()
        assert base._traffic.steps == 0  # a new episode restarts the traffic
    finally:
        env.close()


def test_frames_without_render_or_traffic_simulate_none():
    env = gym.make("vessel_gym/HarbourApproach-v2")
    env.reset(seed=0)
    env.step(np.zeros(2, dtype=np.float32))
    assert env.unwrapped._traffic is None
    env.close()
    zz = gym.make("vessel_gym/ZigZag-v1", render_mode="rgb_array")
    zz.reset(seed=0)
    assert zz.render().shape[2] == 3 and zz.unwrapped._traffic is None
    zz.close()
