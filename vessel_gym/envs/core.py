"""The old home of what every environment shares; each piece now has its own module, re-exported here:

* observation layout: :mod:`vessel_gym.envs.observation` (``Feature`` from :mod:`vessel_gym.envs.declare`);
* helm (action types): :mod:`vessel_gym.envs.helm`;
* the task base and the physics step: :mod:`vessel_gym.envs.task`;
* the single environment and its native vector twin: :mod:`vessel_gym.envs.env`.
"""

from __future__ import annotations

from vessel_gym.envs.declare import Feature
from vessel_gym.envs.env import ShipEnv, ShipVectorEnv
from vessel_gym.envs.helm import ContinuousHelm, DiscreteHelm, Helm, make_helm
from vessel_gym.envs.observation import ObservationLayout
from vessel_gym.envs.task import (
    PHASE_RESET,
    PHASE_SKIP,
    PHASE_STEP,
    STEP_MARGIN,
    STEP_TRAVEL_L,
    Task,
    _uniform,
    physics_step,
)

__all__ = [
    "PHASE_RESET",
    "PHASE_SKIP",
    "PHASE_STEP",
    "STEP_MARGIN",
    "STEP_TRAVEL_L",
    "ContinuousHelm",
    "DiscreteHelm",
    "Feature",
    "Helm",
    "ObservationLayout",
    "ShipEnv",
    "ShipVectorEnv",
    "Task",
    "_uniform",
    "make_helm",
    "physics_step",
]
