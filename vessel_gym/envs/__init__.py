"""Gymnasium environments, one per task of :mod:`vessel_gym.envs.tasks`, each id a preset of its task's config
(``vessel_gym/<Name>-v<N>``; :func:`vessel_gym.envs.registration.registered` lists them with their declarations).

Importing this package registers the ids (cheaply: the declarations are read from the task files' source and
the entry points are strings); each task's classes (``<Name>Task``, ``<Name>Config``, ``<Name>Reward``,
``<Name>Env``, ``<Name>VectorEnv``) and the shared declaration types load on first attribute access.
"""

from __future__ import annotations

import importlib
from typing import Any

from vessel_gym.envs.registration import builtin_declarations, register_envs

register_envs()

_SHARED = {
    "DisturbedOpenWaterConfig": "vessel_gym.envs.disturbances",
    "ShipEnvConfig": "vessel_gym.envs.config",
    "ObservationLayout": "vessel_gym.envs.observation",
    "Feature": "vessel_gym.envs.declare",
    "FeatureSpec": "vessel_gym.envs.declare",
    "Term": "vessel_gym.envs.declare",
    "TaskSpec": "vessel_gym.envs.declare",
}


def _lazy_names() -> dict[str, str]:
    """Class name -> module, derived from the task declarations."""
    out = dict(_SHARED)
    for decl in builtin_declarations():
        env_entry, vec_entry = decl.entry_points()
        stem = decl.name.removesuffix("Task")
        out.update({decl.name: decl.module, f"{stem}Config": decl.module, f"{stem}Reward": decl.module})
        for entry in (env_entry, vec_entry):
            module, name = entry.split(":")
            out[name] = module
    return out


_LAZY = _lazy_names()

__all__ = ["register_envs", *_LAZY]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'vessel_gym.envs' has no attribute {name!r}")
