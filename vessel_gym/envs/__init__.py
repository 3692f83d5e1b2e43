"""Gymnasium environments: ZigZag (``-v1``; ``-v0`` deprecated), ZigZagRandom (``-v1``), TurningCircle and
HarbourApproach (``-v2``, ``-v1``; ``-v0`` deprecated), all as ``vessel_gym/<Name>-v<N>``.

Importing this package registers the ids (cheaply: entry points are strings); the environment classes,
configs and policies load on first attribute access.
"""

from __future__ import annotations

import importlib
from typing import Any

from vessel_gym.envs.registration import ENVIRONMENTS, register_envs

register_envs()

_LAZY = {
    "ZigZagEnv": "zigzag",
    "ZigZagVectorEnv": "zigzag",
    "ZigZagConfig": "zigzag",
    "ZigZagReward": "zigzag",
    "ZigZagV1Env": "zigzag",
    "ZigZagV1VectorEnv": "zigzag",
    "ZigZagV1Config": "zigzag",
    "ZigZagV1Reward": "zigzag",
    "ZigZagRandomEnv": "zigzag",
    "ZigZagRandomVectorEnv": "zigzag",
    "ZigZagRandomConfig": "zigzag",
    "DisturbedOpenWaterConfig": "disturbances",
    "TurningCircleEnv": "turning",
    "TurningCircleVectorEnv": "turning",
    "TurningCircleConfig": "turning",
    "TurningCircleReward": "turning",
    "HarbourApproachEnv": "harbour",
    "HarbourApproachVectorEnv": "harbour",
    "HarbourApproachConfig": "harbour",
    "HarbourApproachReward": "harbour",
    "HarbourApproachV1Env": "harbour",
    "HarbourApproachV1VectorEnv": "harbour",
    "HarbourApproachV1Config": "harbour",
    "HarbourApproachV1Reward": "harbour",
    "HarbourApproachV2Env": "harbour",
    "HarbourApproachV2VectorEnv": "harbour",
    "HarbourApproachV2Config": "harbour",
    "ShipEnvConfig": "config",
    "ObservationLayout": "observation",
    "Feature": "declare",
    "FeatureSpec": "declare",
    "Term": "declare",
    "TaskSpec": "declare",
}

__all__ = ["ENVIRONMENTS", "register_envs", *_LAZY]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(f"vessel_gym.envs.{_LAZY[name]}"), name)
    raise AttributeError(f"module 'vessel_gym.envs' has no attribute {name!r}")
