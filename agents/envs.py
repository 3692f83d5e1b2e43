"""Environments of the agent scripts: picklable factories of registered ids and the SB3 vector environments
(native, ``DummyVecEnv`` or ``SubprocVecEnv``) that training and evaluation run on.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from typing import Any

from agents.config import UsageError

VEC_KINDS = ("native", "dummy", "subproc")


class EnvFactory:
    """Picklable ``() -> env`` for SB3 vector environments (``SubprocVecEnv`` workers import vessel_gym
    themselves, so the ids are registered in every process). ``env_wrapper``: the hyperparameter key
    (training-time wrappers of :mod:`agents.wrappers`)."""

    def __init__(
        self, env_id: str, env_kwargs: Mapping[str, Any] | None = None, env_wrapper: Any = None
    ) -> None:
        self.env_id = env_id
        self.env_kwargs = dict(env_kwargs or {})
        self.env_wrapper = copy.deepcopy(env_wrapper)

    def __call__(self) -> Any:
        import gymnasium as gym

        import vessel_gym.envs  # noqa: F401  (registers the ids)
        from agents import wrappers

        env = gym.make(self.env_id, **self.env_kwargs)
        return wrappers.apply(env, wrappers.resolve(self.env_wrapper))


def make_env(env_id: str, env_kwargs: Mapping[str, Any] | None = None, env_wrapper: Any = None) -> Any:
    """One environment of a registered id; bad keyword arguments raise :class:`UsageError`."""
    from vessel_gym.physics.schema import SpecError

    try:
        return EnvFactory(env_id, env_kwargs, env_wrapper)()
    except (SpecError, TypeError, ValueError) as exc:
        raise UsageError(f"{env_id}: {exc}") from None


def make_vec_env(
    env_id: str,
    n_envs: int = 1,
    seed: int = 0,
    vec: str = "native",
    env_kwargs: Mapping[str, Any] | None = None,
    start_method: str | None = None,
    env_wrapper: Any = None,
) -> Any:
    """SB3 vector environment of ``n_envs`` copies of ``env_id`` seeded ``seed, seed + 1, ...``, with episode
    statistics (``VecMonitor``). ``vec="native"``: the environment's native vector version (all ships in one
    batched simulation) through :class:`vessel_gym.sb3.VectorEnvAdapter`, training wrappers as their
    vector-environment twins; ``"dummy"``: SB3's ``DummyVecEnv`` over single environments; ``"subproc"``:
    each copy in its own process."""
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecMonitor

    if vec not in VEC_KINDS:
        raise UsageError(f"unknown vector environment {vec!r} (have: {', '.join(VEC_KINDS)})")
    make_env(env_id, env_kwargs, env_wrapper).close()  # fail early, in this process, with a clear message
    if vec == "native":
        from agents import wrappers
        from vessel_gym.sb3 import make_vec_env as native_vec_env

        try:
            twins = wrappers.vector_twins(wrappers.resolve(env_wrapper))
        except ValueError as exc:
            raise UsageError(str(exc)) from None
        return native_vec_env(env_id, n_envs, seed=seed, vector_wrappers=twins, **dict(env_kwargs or {}))
    fns = [EnvFactory(env_id, env_kwargs, env_wrapper) for _ in range(n_envs)]
    venv = DummyVecEnv(fns) if vec == "dummy" else SubprocVecEnv(fns, start_method=start_method)
    venv.seed(seed)
    return VecMonitor(venv)
