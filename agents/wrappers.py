"""Training-time environment wrappers named by the ``env_wrapper`` key of a hyperparameter block.

A wrapper here changes what the agent is trained on (e.g. an extra reward term), never the observation or
action spaces, so a trained model still runs in the unwrapped registered environment
(``evaluate.py``, :func:`vessel_gym.policy.load_policy`, ``vessel-gym serve --agent``). Evaluation always
uses the registered reward, so returns of all agents stay comparable.

In a hyperparameter block (rl-baselines3-zoo form; a bare class name means this module)::

    env_wrapper:
      - RudderEffortPenalty: {weight: 0.3}
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from typing import Any

import gymnasium as gym
import numpy as np


class RudderEffortPenalty(gym.Wrapper):
    """Adds the reward term ``rudder_effort = -weight * |rudder order| / rudder limit`` per step.

    The registered rewards charge the helm only for changes of the rudder order (``rudder_activity``);
    this term also charges holding rudder, i.e. the drag and speed loss of large angles, so the agent learns
    to reach a course with the rudder effort of a classical autopilot. The term is reported in
    ``info["reward_terms"]["rudder_effort"]`` (the terms still sum to the reward).
    """

    def __init__(self, env: gym.Env, weight: float = 0.1) -> None:
        super().__init__(env)
        if not np.isfinite(weight) or weight < 0.0:
            raise ValueError(f"RudderEffortPenalty weight must be >= 0, got {weight}")
        self.weight = float(weight)
        layout = env.unwrapped.observation_layout
        self._layout = layout
        self._limit = float(layout.scale[layout.index("rudder_order")])

    def step(self, action: Any) -> tuple[Any, float, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step(action)
        term = -self.weight * abs(float(self._layout.value(obs, "rudder_order"))) / self._limit
        info = dict(info)
        info["reward_terms"] = {**info.get("reward_terms", {}), "rudder_effort": term}
        return obs, float(reward) + term, terminated, truncated, info


def resolve(spec: Any) -> list[tuple[type, dict[str, Any]]]:
    """``env_wrapper`` value -> [(wrapper class, kwargs)]; raises ``ValueError`` naming a bad entry.

    Accepts a name, a mapping ``{name: kwargs}`` or a list of either; a name without a dot is a class of
    this module, a dotted name ``package.module.Class`` is imported."""
    if spec is None:
        return []
    items = spec if isinstance(spec, list) else [spec]
    out = []
    for item in items:
        if isinstance(item, str):
            name, kwargs = item, {}
        elif isinstance(item, Mapping) and len(item) == 1:
            name, kwargs = next(iter(item.items()))
            kwargs = dict(kwargs or {})
        else:
            raise ValueError(f"env_wrapper entry {item!r}: expected a name or {{name: {{kwargs}}}}")
        module, _, cls_name = str(name).rpartition(".")
        try:
            cls = getattr(importlib.import_module(module or __name__), cls_name)
        except (ImportError, AttributeError):
            raise ValueError(f"env_wrapper {name!r}: no such wrapper class") from None
        if not (isinstance(cls, type) and issubclass(cls, gym.Wrapper)):
            raise ValueError(f"env_wrapper {name!r}: not a gymnasium.Wrapper")
        out.append((cls, kwargs))
    return out


def apply(env: gym.Env, wrappers: list[tuple[type, dict[str, Any]]]) -> gym.Env:
    """``env`` inside the wrappers, first entry innermost."""
    for cls, kwargs in wrappers:
        env = cls(env, **kwargs)
    return env


__all__ = ["RudderEffortPenalty", "apply", "resolve"]
