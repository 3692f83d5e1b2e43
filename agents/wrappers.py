"""Environment wrappers named by the ``env_wrapper`` and ``action_filter`` keys of a hyperparameter block.

No wrapper here changes the observation or action spaces. Two kinds:

* ``env_wrapper`` (training only): changes what the agent is trained on (e.g. an extra reward term), so a
  trained model still runs in the unwrapped registered environment (``evaluate.py``,
  :func:`vessel_gym.policy.load_policy`, ``vessel-gym serve --agent``). Evaluation always uses the
  registered reward, so returns of all agents stay comparable.
* ``action_filter`` (training AND evaluation): changes how an action becomes a helm order (e.g. a rate limit
  on the rudder order), part of the agent as much as its network. The run record and the shipped sidecar
  carry the key, and ``evaluate.py`` (:func:`agents.evaluation.evaluate`) applies it around the registered
  environment; the reward is still the registered one.

In a hyperparameter block (rl-baselines3-zoo form; a bare class name means this module)::

    env_wrapper:
      - RudderEffortPenalty: {weight: 0.3}
    action_filter:
      - RudderRateLimit: {max_rate_deg_s: 4.64}
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from typing import Any

import gymnasium as gym
import numpy as np


def _effort_setup(env: gym.Env | gym.vector.VectorEnv, weight: float) -> tuple[float, Any, float]:
    """(weight, observation layout, rudder limit in the observation's units) of a rudder-effort term;
    ``ValueError`` for a negative or non-finite weight."""
    if not np.isfinite(weight) or weight < 0.0:
        raise ValueError(f"RudderEffortPenalty weight must be >= 0, got {weight}")
    layout = env.unwrapped.observation_layout
    return float(weight), layout, float(layout.scale[layout.index("rudder_order")])


class RudderEffortPenalty(gym.Wrapper):
    """Adds the reward term ``rudder_effort = -weight * |rudder order| / rudder limit`` per step.

    The registered rewards charge the helm only for changes of the rudder order (``rudder_activity``);
    this term also charges holding rudder, i.e. the drag and speed loss of large angles, so the agent learns
    to reach a course with the rudder effort of a classical autopilot. The term is reported in
    ``info["reward_terms"]["rudder_effort"]`` (the terms still sum to the reward).
    """

    def __init__(self, env: gym.Env, weight: float = 0.1) -> None:
        super().__init__(env)
        self.weight, self._layout, self._limit = _effort_setup(env, weight)

    def step(self, action: Any) -> tuple[Any, float, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step(action)
        term = -self.weight * abs(float(self._layout.value(obs, "rudder_order"))) / self._limit
        info = dict(info)
        info["reward_terms"] = {**info.get("reward_terms", {}), "rudder_effort": term}
        return obs, float(reward) + term, terminated, truncated, info


class RudderEffortPenaltyVector(gym.vector.VectorWrapper):
    """:class:`RudderEffortPenalty` over a native vector environment (whose ships are not single
    ``gymnasium.Env`` objects to wrap): the same term, from the observation each ship's step ends in (the
    final one, ``info["final_obs"]``, where a same-step autoreset began a new episode); the term joins
    ``info["reward_terms"]`` and, for finished ships, their ``info["final_info"]``."""

    def __init__(self, env: gym.vector.VectorEnv, weight: float = 0.1) -> None:
        super().__init__(env)
        self.weight, self._layout, self._limit = _effort_setup(env, weight)

    def step(self, actions: Any) -> tuple[Any, Any, Any, Any, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step(actions)
        last = obs
        finished = np.flatnonzero(info.get("_final_obs", ()))
        if finished.size:
            last = np.array(obs, copy=True)
            for i in finished:
                last[i] = info["final_obs"][i]
        terms = -self.weight * np.abs(self._layout.value(last, "rudder_order")) / self._limit
        info = dict(info)
        info["reward_terms"] = {**info.get("reward_terms", {}), "rudder_effort": terms}
        final_info = info.get("final_info")
        if isinstance(final_info, np.ndarray):  # vessel-gym: one dict per finished ship
            final_info = final_info.copy()
            for i in finished:
                d = dict(final_info[i])
                d["reward_terms"] = {**d.get("reward_terms", {}), "rudder_effort": float(terms[i])}
                final_info[i] = d
            info["final_info"] = final_info
        elif isinstance(final_info, dict):  # Gymnasium's SyncVectorEnv: batched, with masks
            rt = dict(final_info.get("reward_terms", {}))
            rt["rudder_effort"], rt["_rudder_effort"] = terms.copy(), np.asarray(info["_final_obs"]).copy()
            info["final_info"] = {**final_info, "reward_terms": rt}
        return obs, np.asarray(reward, dtype=np.float64) + terms, terminated, truncated, info


def _rate_setup(env: gym.Env | gym.vector.VectorEnv, max_rate_deg_s: float) -> tuple[Any, float]:
    """(observation layout, largest change of the rudder order per control interval as a fraction of the
    rudder limit) of a rudder rate limit; ``ValueError`` for a non-positive or non-finite rate."""
    if not np.isfinite(max_rate_deg_s) or max_rate_deg_s <= 0.0:
        raise ValueError(f"RudderRateLimit max_rate_deg_s must be > 0, got {max_rate_deg_s}")
    base = env.unwrapped
    layout = base.observation_layout
    limit = float(layout.scale[layout.index("rudder_order")])  # rad: an action of 1 orders the rudder limit
    step = np.radians(float(max_rate_deg_s)) * float(base.config.control_interval_s)  # rad per interval
    return layout, step / limit


def _rate_limited(actions: np.ndarray, order: np.ndarray, step: float) -> np.ndarray:
    """``actions`` (rows: ships) with the rudder column moved from ``order`` (the present rudder order as a
    fraction of the limit) towards the requested order by at most ``step``."""
    out = np.clip(np.asarray(actions, dtype=np.float32), -1.0, 1.0).copy()
    out[:, 0] = order + np.clip(out[:, 0] - order, -step, step)
    return out


class RudderRateLimit(gym.Wrapper):
    """Rate limit of the rudder order: the action still asks for a rudder order (fraction of the limit), the
    order given moves towards it by at most ``max_rate_deg_s`` x control interval per step, starting from the
    order in force (``rudder_order`` of the last observation).

    A mean |change of rudder order| per second above ``max_rate_deg_s`` is then impossible, so a helm cannot
    chatter between the stops whatever the network asks, and the exploration noise of training reaches the
    rudder low-passed. The steering gear itself turns the rudder at ``max_rate_deg_s`` of the ship file
    (2.32 deg/s on the KVLCC2); a limit of about twice that lets the order lead the rudder without binding
    the manoeuvre. An action filter (``action_filter`` key): applied in training and evaluation alike.
    """

    def __init__(self, env: gym.Env, max_rate_deg_s: float = 4.64) -> None:
        super().__init__(env)
        self.max_rate_deg_s = float(max_rate_deg_s)
        self._layout, self._step = _rate_setup(env, self.max_rate_deg_s)
        self._order = 0.0
        self._limit = float(self._layout.scale[self._layout.index("rudder_order")])

    def _track(self, obs: Any) -> None:
        self._order = float(self._layout.value(obs, "rudder_order")) / self._limit

    def reset(self, **kwargs: Any) -> tuple[Any, dict[str, Any]]:
        obs, info = self.env.reset(**kwargs)
        self._track(obs)
        return obs, info

    def step(self, action: Any) -> tuple[Any, float, bool, bool, dict[str, Any]]:
        a = np.asarray(action, dtype=np.float32).reshape(1, -1)
        limited = _rate_limited(a, np.array([self._order]), self._step)[0]
        obs, reward, terminated, truncated, info = self.env.step(limited.reshape(np.shape(action)))
        self._track(obs)
        return obs, reward, terminated, truncated, info


class RudderRateLimitVector(gym.vector.VectorWrapper):
    """:class:`RudderRateLimit` over a native vector environment with same-step autoreset: each ship's order
    in force is that of the observation last returned (a new episode's first one after an autoreset)."""

    def __init__(self, env: gym.vector.VectorEnv, max_rate_deg_s: float = 4.64) -> None:
        super().__init__(env)
        self.max_rate_deg_s = float(max_rate_deg_s)
        self._layout, self._step = _rate_setup(env, self.max_rate_deg_s)
        self._limit = float(self._layout.scale[self._layout.index("rudder_order")])
        self._order = np.zeros(self.num_envs)

    def _track(self, obs: Any) -> None:
        self._order = np.asarray(self._layout.value(obs, "rudder_order"), dtype=np.float64) / self._limit

    def reset(self, **kwargs: Any) -> tuple[Any, dict[str, Any]]:
        obs, info = self.env.reset(**kwargs)
        self._track(obs)
        return obs, info

    def step(self, actions: Any) -> tuple[Any, Any, Any, Any, dict[str, Any]]:
        a = np.asarray(actions, dtype=np.float32)
        limited = _rate_limited(a.reshape(self.num_envs, -1), self._order, self._step).reshape(a.shape)
        obs, reward, terminated, truncated, info = self.env.step(limited)
        self._track(obs)
        return obs, reward, terminated, truncated, info


#: the vector-environment twin of each wrapper (used with the native vector environments)
VECTOR_TWINS: dict[type, type] = {
    RudderEffortPenalty: RudderEffortPenaltyVector,
    RudderRateLimit: RudderRateLimitVector,
}


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


def join(*specs: Any) -> list[Any]:
    """Several ``env_wrapper``/``action_filter`` values as one list, in order (``None`` contributes none)."""
    out: list[Any] = []
    for spec in specs:
        if spec is not None:
            out += spec if isinstance(spec, list) else [spec]
    return out


def apply(env: gym.Env, wrappers: list[tuple[type, dict[str, Any]]]) -> gym.Env:
    """``env`` inside the wrappers, first entry innermost."""
    for cls, kwargs in wrappers:
        env = cls(env, **kwargs)
    return env


def vector_twins(wrappers: list[tuple[type, dict[str, Any]]]) -> list[Any]:
    """The vector-environment twins of ``wrappers`` as callables ``vector env -> wrapped vector env`` (first
    innermost); ``ValueError`` if a wrapper has none (train that block with ``--vec dummy``)."""
    out = []
    for cls, kwargs in wrappers:
        twin = VECTOR_TWINS.get(cls)
        if twin is None:
            raise ValueError(
                f"env_wrapper {cls.__name__} wraps single environments only; train with --vec dummy or subproc"
            )
        out.append(lambda env, twin=twin, kwargs=kwargs: twin(env, **kwargs))
    return out


__all__ = [
    "VECTOR_TWINS",
    "RudderEffortPenalty",
    "RudderEffortPenaltyVector",
    "RudderRateLimit",
    "RudderRateLimitVector",
    "apply",
    "join",
    "resolve",
    "vector_twins",
]
