"""Stable-Baselines3 on the native vector environments: an SB3 ``VecEnv`` over a Gymnasium ``VectorEnv``.

SB3 steps environments through its own ``VecEnv`` interface, whose ``DummyVecEnv`` calls N single
environments one after the other. The vessel-gym environments also exist as native vector environments
(``gymnasium.make_vec(id, num_envs=N, vectorization_mode="vector_entry_point")``): N ships in one simulation,
stepped in one batched call. :class:`VectorEnvAdapter` presents such an environment (or any Gymnasium 1.x
``VectorEnv``) to SB3::

    from stable_baselines3 import PPO
    from vessel_gym.sb3 import make_vec_env

    venv = make_vec_env("vessel_gym/ZigZagRandom-v1", num_envs=64, seed=0)
    PPO("MlpPolicy", venv).learn(100_000)

What SB3 expects and how it is produced from Gymnasium's conventions:

* **Autoreset.** SB3 resets a finished sub-environment within the same ``step`` call: the returned observation
  is the first of the next episode, the last observation of the finished one is in
  ``infos[i]["terminal_observation"]`` and ``infos[i]`` is the info of the final step. Gymnasium 1.x vector
  environments default to *next-step* autoreset (the finished sub-environment resets on the following
  ``step``, ignoring its action there), which cannot be translated without an extra step. The adapter
  therefore uses *same-step* autoreset (``info["final_obs"]``, ``info["final_info"]``) or *disabled*
  autoreset (it resets the finished sub-environments itself with ``reset(options={"reset_mask": done})``);
  :func:`make_vec_env` builds the environment in same-step mode, and a next-step environment is refused.
* ``infos[i]["TimeLimit.truncated"]`` is ``truncated and not terminated``, as SB3's ``DummyVecEnv`` sets it.
* **Seeding.** ``seed(s)`` seeds sub-environment i with ``s + i`` at the next ``reset()``, as every SB3
  ``VecEnv`` does; a vessel-gym vector environment seeded so reproduces ``DummyVecEnv`` over single
  environments seeded the same way, step for step (``tests/envs/test_sb3.py``).
* **Episode statistics**: wrap the adapter in SB3's ``VecMonitor`` (:func:`make_vec_env` does), which adds
  ``infos[i]["episode"]``; ``info["is_success"]`` of the final step reaches SB3's success-rate logging.
* **Rendering**: ``get_images()`` returns the frames of the vector environment's ``render()`` (vessel-gym
  draws its first four ships); SB3's ``render()`` tiles them.
* ``get_attr``/``set_attr``/``env_method`` reach the one vector environment behind all N sub-environments:
  ``get_attr`` and ``env_method`` return its answer once per requested index, and a method is called once.

Rewards are returned as float32, as ``DummyVecEnv`` stores them. ``reset_infos`` after an automatic reset are
empty (the vector environment reports the info of the final step, not that of the new start).

Stable-Baselines3 is imported by this module only; ``vessel_gym`` itself does not need it
(``pip install vessel-gym[rl]``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode

try:
    from stable_baselines3.common.vec_env import VecMonitor
    from stable_baselines3.common.vec_env.base_vec_env import VecEnv
except ImportError as exc:  # pragma: no cover - exercised only without the rl extra
    raise ImportError(
        "vessel_gym.sb3 needs stable-baselines3; install it with: pip install 'vessel-gym[rl]'"
    ) from exc


def _split(info: dict[str, Any], n: int, skip: Iterable[str] = ()) -> list[dict[str, Any]]:
    """Gymnasium's batched ``info`` (``info[key][i]``, optional mask ``info["_key"]``) as n dicts of Python
    scalars, nested dicts included."""
    out: list[dict[str, Any]] = [{} for _ in range(n)]
    skip = set(skip)
    for key, value in info.items():
        if key.startswith("_") or key in skip:
            continue
        mask = info.get(f"_{key}")
        if isinstance(value, dict):
            values: Sequence[Any] = _split(value, n)
        elif isinstance(value, np.ndarray):
            values = value.tolist() if value.dtype != object else list(value)
        else:
            values = list(value)
        if mask is None:
            for d, v in zip(out, values):
                d[key] = v
        else:
            for i in np.flatnonzero(mask):
                out[i][key] = values[i]
    return out


def _final_infos(final_info: Any, n: int) -> Sequence[Any]:
    """The final-step infos from ``info["final_info"]``, indexable by sub-environment: an object array of
    dicts (vessel-gym) or a batched dict with masks (Gymnasium's ``SyncVectorEnv``)."""
    if isinstance(final_info, dict):
        return _split(final_info, n)
    return [None if d is None else _python(d) for d in final_info]


def _python(d: dict[str, Any]) -> dict[str, Any]:
    """``d`` with NumPy scalars as Python scalars (as the single environments report them)."""
    return {
        k: _python(v) if isinstance(v, dict) else (v.item() if isinstance(v, np.generic) else v)
        for k, v in d.items()
    }


class VectorEnvAdapter(VecEnv):
    """An SB3 ``VecEnv`` over a Gymnasium ``VectorEnv`` in same-step or disabled autoreset mode (see the
    module docstring for the conventions translated)."""

    def __init__(self, venv: gym.vector.VectorEnv) -> None:
        mode = venv.metadata.get("autoreset_mode", AutoresetMode.NEXT_STEP)
        mode = AutoresetMode(mode)
        if mode == AutoresetMode.NEXT_STEP:
            raise ValueError(
                "VectorEnvAdapter needs a vector environment in same-step or disabled autoreset mode "
                "(SB3 expects the first observation of the next episode in the step that ends one); "
                "create it with autoreset_mode=gymnasium.vector.AutoresetMode.SAME_STEP"
            )
        self.venv = venv
        self.autoreset_mode = mode
        super().__init__(venv.num_envs, venv.single_observation_space, venv.single_action_space)
        self._actions: np.ndarray | None = None

    # --- SB3 VecEnv interface ----------------------------------------------------------------------------
    def reset(self) -> np.ndarray:
        seeds = None if all(s is None for s in self._seeds) else list(self._seeds)
        options = self._options[0] or None
        if any(o != self._options[0] for o in self._options):
            raise ValueError("a native vector environment takes one set of reset options for all ships")
        obs, info = self.venv.reset(seed=seeds, options=options)
        self.reset_infos = _split(info, self.num_envs)
        self._reset_seeds()
        self._reset_options()
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = actions

    def step_wait(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:
        obs, rewards, terminated, truncated, info = self.venv.step(self._actions)
        n = self.num_envs
        dones = np.logical_or(terminated, truncated)
        infos = _split(info, n, skip=("final_obs", "final_info"))
        time_limit = (np.asarray(truncated) & ~np.asarray(terminated)).tolist()
        for d, t in zip(infos, time_limit):
            d["TimeLimit.truncated"] = t
        if dones.any():
            idx = np.flatnonzero(dones)
            if self.autoreset_mode == AutoresetMode.SAME_STEP:
                final_obs, final_infos = info["final_obs"], _final_infos(info["final_info"], n)
                for i in idx:
                    d = final_infos[i]
                    d["TimeLimit.truncated"] = time_limit[i]
                    d["terminal_observation"] = final_obs[i]
                    infos[i] = d
                    self.reset_infos[i] = {}
            else:  # disabled: reset the finished sub-environments here
                obs = np.array(obs, copy=True)
                for i in idx:
                    infos[i]["terminal_observation"] = obs[i].copy()
                new_obs, new_info = self.venv.reset(options={"reset_mask": dones})
                obs[idx] = new_obs[idx]
                reset_infos = _split(new_info, n)
                for i in idx:
                    self.reset_infos[i] = reset_infos[i]
        return obs, np.asarray(rewards, dtype=np.float32), dones, infos

    def close(self) -> None:
        self.venv.close()

    def get_images(self) -> Sequence[np.ndarray | None]:
        frames = self.venv.render()
        return [] if frames is None else list(frames)

    def _count(self, indices: Any) -> int:
        return len(self._get_indices(indices))

    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
        try:
            value = getattr(self.venv, attr_name)
        except AttributeError:
            value = getattr(self.venv.unwrapped, attr_name)
        return [value] * self._count(indices)

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        setattr(self.venv, attr_name, value)

    def env_method(self, method_name: str, *method_args: Any, indices: Any = None, **method_kwargs: Any):
        result = getattr(self.venv, method_name)(*method_args, **method_kwargs)
        return [result] * self._count(indices)

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
        # the sub-environments of a native vector environment are not gymnasium.Env objects: none is wrapped
        return [False] * self._count(indices)


def make_vec_env(
    env_id: str,
    num_envs: int,
    seed: int | None = None,
    monitor: bool = True,
    vector_wrappers: Sequence[Callable[[gym.vector.VectorEnv], gym.vector.VectorEnv]] = (),
    **env_kwargs: Any,
) -> VecEnv:
    """The native vector environment of ``env_id`` (same-step autoreset) as an SB3 ``VecEnv``, inside
    ``VecMonitor`` unless ``monitor=False``; sub-environment i is seeded ``seed + i`` at the first reset.

    ``env_kwargs`` go to ``gymnasium.make_vec`` (environment configuration, ``max_episode_steps``,
    ``render_mode``); ``vector_wrappers`` (Gymnasium vector wrappers, first innermost) wrap the vector
    environment inside the adapter.
    """
    import vessel_gym.envs  # noqa: F401  (registers the ids)

    venv = gym.make_vec(
        env_id,
        num_envs=num_envs,
        vectorization_mode="vector_entry_point",
        autoreset_mode=AutoresetMode.SAME_STEP,
        **env_kwargs,
    )
    for wrap in vector_wrappers:
        venv = wrap(venv)
    adapter: VecEnv = VectorEnvAdapter(venv)
    if seed is not None:
        adapter.seed(seed)
    return VecMonitor(adapter) if monitor else adapter


__all__ = ["VectorEnvAdapter", "make_vec_env"]
