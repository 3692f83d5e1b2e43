"""Evaluation of a baseline or a trained agent: loading it (with its saved observation normalisation), running
seeded episodes with per-task metrics, and summarising them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from agents.config import UsageError, resolve_env_id, sidecar
from agents.envs import make_env
from vessel_gym.policy import BASELINES as PILOTS  # every classical pilot's name (the tasks declare them)

#: ``evaluate(action_filter=RECORDED)``: the action filter named by the model's run record or sidecar
RECORDED = object()


def run_record(agent: str | Path) -> dict[str, Any]:
    """The run record ``<stem>.yml`` written next to a trained model, else the JSON sidecar of a shipped
    agent (``agents/shipped.py``), else empty."""
    if str(agent) in PILOTS:
        return {}
    path = sidecar(agent, ".yml")
    if path.is_file():
        import yaml  # the rl extra's; a baseline needs none of it

        data = yaml.safe_load(path.read_text())
        return data if isinstance(data, dict) else {}
    path = sidecar(agent, ".json")
    if not path.is_file():
        return {}
    data = load_json_sidecar(path)
    return data if isinstance(data, dict) else {}


def load_json_sidecar(path: Path) -> Any:
    """The content of the JSON sidecar ``path``; an unreadable or malformed one is a :class:`UsageError`."""
    import json

    try:
        return json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as exc:
        raise UsageError(f"{path}: not a readable JSON sidecar ({exc})") from None


def _same_task(a: str, b: str) -> bool:
    """Whether two registered ids are presets of one task (an agent may run on another preset of its task,
    e.g. CollisionAvoidance-v0's in the Channel, where its observation fits: :func:`load_agent` checks)."""
    from vessel_gym.envs.registration import declaration

    try:
        return declaration(a) is declaration(b)
    except KeyError:
        return False


def load_agent(agent: str | Path, env: Any) -> Any:
    """Policy ``action = policy(obs)`` with ``reset()`` for ``env``: a baseline name or a model path.

    Models load through :func:`vessel_gym.policy.load_policy`, which applies the observation statistics
    saved with the model (``<stem>_vecnormalize.pkl``) when training normalised observations.
    """
    from vessel_gym.policy import load_policy

    spec = str(agent)
    if spec not in PILOTS and not spec.endswith(".zip") and Path(spec + ".zip").is_file():
        spec += ".zip"
    try:
        policy = load_policy(spec, env)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    return policy


def run_episode(env: Any, policy: Any, seed: int) -> dict[str, Any]:
    """One episode of ``policy`` in ``env`` from ``reset(seed=seed)``; returns its metrics.

    Every task: ``return``, ``length``, ``rudder_deg`` (mean |rudder order|), ``rudder_rate_deg_s`` (mean
    |change of rudder order| per second: helm activity); then the metrics the task declares (``metrics`` of its
    ``register_task``, from the episode's ``info`` dicts: e.g. ZigZag's overshoot per course change,
    TurningCircle's rate error, HarbourApproach's outcome).
    """
    base = env.unwrapped
    layout = base.observation_layout
    dt = float(base.config.control_interval_s)
    metrics = getattr(getattr(base.task, "declaration", None), "metrics", None)
    obs, info = env.reset(seed=seed)
    policy.reset()
    ret, n = 0.0, 0
    prev_order = float(layout.value(obs, "rudder_order"))
    rudder: list[float] = []
    rudder_rate: list[float] = []
    infos: list[dict[str, Any]] = []
    while True:
        obs, reward, terminated, truncated, info = env.step(policy(obs))
        ret += float(reward)
        n += 1
        order = float(layout.value(obs, "rudder_order"))
        rudder.append(abs(order))
        rudder_rate.append(abs(order - prev_order) / dt)
        prev_order = order
        infos.append(dict(info))
        if terminated or truncated:
            break
    out: dict[str, Any] = {
        "seed": seed,
        "return": ret,
        "length": n,
        "rudder_deg": math.degrees(float(np.mean(rudder))),
        "rudder_rate_deg_s": math.degrees(float(np.mean(rudder_rate))),
    }
    if metrics is not None:
        out.update(metrics(infos, bool(terminated)))
    return out


#: the per-episode outcomes (0/1) summarised as rates ``<name>_rate``
RATES = ("success", "collision", "grounding")


def summarize(episodes: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """Mean and standard deviation over episodes of every numeric metric (NaN-aware; ``success``,
    ``collision`` and ``grounding`` as rates, ``outcome`` as counts)."""
    out: dict[str, Any] = {"episodes": len(episodes)}
    keys = [k for k in episodes[0] if k not in ("seed", "outcome")]
    for k in keys:
        x = np.array([float(e[k]) for e in episodes], dtype=np.float64)
        finite = x[np.isfinite(x)]
        if k in RATES:  # an outcome per episode (0/1): its rate
            out[f"{k}_rate"] = float(np.mean(x))
            continue
        out[f"{k}_mean"] = float(np.mean(finite)) if finite.size else None
        out[f"{k}_std"] = float(np.std(finite)) if finite.size else None
    if "outcome" in episodes[0]:
        counts: dict[str, int] = {}
        for e in episodes:
            counts[e["outcome"]] = counts.get(e["outcome"], 0) + 1
        out["outcomes"] = counts
    return out


def evaluate(
    env_id: str,
    agent: str | Path,
    episodes: int = 20,
    seed: int = 0,
    env_kwargs: Mapping[str, Any] | None = None,
    progress: Callable[[int, dict[str, Any]], None] | None = None,
    render_mode: str | None = None,
    wrap: Callable[[Any], Any] | None = None,
    action_filter: Any = RECORDED,
) -> dict[str, Any]:
    """Run ``episodes`` episodes (episode i from ``reset(seed=seed + i)``) of a baseline or trained agent.

    ``env_kwargs`` default to the evaluation arguments of the model's run record (``eval_env_kwargs`` of its
    hyperparameter block, which default to its ``env_kwargs``), else none. Returns
    ``{"env_id", "agent", "env_kwargs", "summary", "episodes"}``; see :func:`run_episode` for the metrics.
    ``render_mode`` is passed to ``gym.make``; ``wrap(env)`` may wrap the environment (recording tracks or
    frames, :mod:`agents.visual`) without changing what the agent sees. ``action_filter`` (the key of
    :mod:`agents.wrappers`: wrappers between the agent and the helm) defaults to the model's run record or
    sidecar; it is applied inside ``wrap``, so recorders see the orders the ship was given.
    """
    env_id = resolve_env_id(env_id)
    if episodes < 1:
        raise UsageError(f"episodes must be >= 1, got {episodes}")
    spec = str(agent)
    if spec not in PILOTS and not Path(spec).is_file() and not Path(spec + ".zip").is_file():
        raise UsageError(f"agent {spec!r}: not a baseline ({', '.join(PILOTS)}) and no such file")
    rec = run_record(spec)
    if rec.get("env_id") not in (None, env_id) and not _same_task(rec["env_id"], env_id):
        raise UsageError(
            f"agent {spec!r} was trained on {rec['env_id']}, not {env_id} (nor another preset of its task)"
        )
    recorded = rec.get("eval_env_kwargs", rec.get("env_kwargs"))
    kwargs = dict(recorded or {}) if env_kwargs is None else dict(env_kwargs)
    if action_filter is RECORDED:
        action_filter = rec.get("action_filter")
    env_kw = kwargs if render_mode is None else {**kwargs, "render_mode": render_mode}
    env = make_env(env_id, env_kw, action_filter)
    if wrap is not None:
        env = wrap(env)
    try:
        policy = load_agent(spec, env)
        eps = []
        for i in range(episodes):
            eps.append(run_episode(env, policy, seed + i))
            if progress is not None:
                progress(i, eps[-1])
    finally:
        env.close()
    out = {"env_id": env_id, "agent": spec, "env_kwargs": kwargs}
    if action_filter:
        out["action_filter"] = action_filter
    return {**out, "summary": summarize(eps), "episodes": eps}
