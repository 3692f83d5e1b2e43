"""Short fixed-action rollouts of TurningCircle-v0 (shared by the regression tests)."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np

import vessel_gym  # noqa: F401 (registers the ids)

STEPS = 480  # 120 s at the default 0.25 s control interval


def turning_action(i: int) -> np.ndarray:
    """Hard to starboard (the IMO turning circle), eased to 60 % after a minute."""
    return np.array([1.0 if i < 240 else 0.6], np.float32)


def rollout(env_id: str, action, seed: int, **kw):
    """(reward sum, final observation, final info, per-step (heading, r, north, east), infos) of one
    episode of at most STEPS steps."""
    env = gym.make(env_id, max_episode_steps=STEPS, **kw)
    obs, info = env.reset(seed=seed)
    sim = env.unwrapped.task.sim
    motion = [(float(sim.heading[0]), float(sim.r[0]), float(sim.north[0]), float(sim.east[0]))]
    infos = [info]
    rewards = []
    for i in range(STEPS):
        obs, r, term, trunc, info = env.step(action(i))
        rewards.append(float(r))
        motion.append((float(sim.heading[0]), float(sim.r[0]), float(sim.north[0]), float(sim.east[0])))
        infos.append(info)
        if term or trunc:
            break
    env.close()
    return math.fsum(rewards), obs, info, motion, infos
