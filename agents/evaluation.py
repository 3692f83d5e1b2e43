"""Evaluation of a baseline or a trained agent: loading it (with its saved observation normalisation), running
seeded episodes with per-task metrics, and summarising them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from agents.config import BASELINES, UsageError, resolve_env_id, sidecar
from agents.envs import make_env


def run_record(agent: str | Path) -> dict[str, Any]:
    """The run record ``<stem>.yml`` written next to a trained model, else the JSON sidecar of a shipped
    agent (``agents/shipped.py``), else empty."""
    if str(agent) in BASELINES:
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


class _NormalizedObs:
    """A policy behind the observation normalisation of a ``VecNormalize`` saved with the model."""

    def __init__(self, policy: Any, stats: Any) -> None:
        self.policy = policy
        self.stats = stats

    def reset(self, mask: np.ndarray | None = None) -> None:
        self.policy.reset(mask)

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        return self.policy(self.stats.normalize_obs(np.asarray(obs, dtype=np.float32)))


def load_agent(agent: str | Path, env: Any) -> Any:
    """Policy ``action = policy(obs)`` with ``reset()`` for ``env``: a baseline name or a model path.

    Models load through :func:`vessel_gym.policy.load_policy`; if training used ``normalize`` with
    ``norm_obs``, the saved statistics (``<stem>_vecnormalize.pkl``) are applied to the observations.
    """
    from vessel_gym.policy import load_policy

    spec = str(agent)
    if spec not in BASELINES and not spec.endswith(".zip") and Path(spec + ".zip").is_file():
        spec += ".zip"
    try:
        policy = load_policy(spec, env)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    vn = sidecar(spec, "_vecnormalize.pkl") if spec not in BASELINES else None
    if vn is not None and vn.is_file():
        import pickle

        with open(vn, "rb") as f:
            stats = pickle.load(f)
        if getattr(stats, "norm_obs", False):
            stats.training = False
            policy = _NormalizedObs(policy, stats)
    return policy


def env_kind(env: Any) -> str:
    """``zigzag``, ``turning``, ``harbour`` (or the class name) of an environment."""
    name = type(env.unwrapped).__name__
    for key, kind in (("ZigZag", "zigzag"), ("Turning", "turning"), ("Harbour", "harbour")):
        if key in name:
            return kind
    return name


def run_episode(env: Any, policy: Any, seed: int) -> dict[str, Any]:
    """One episode of ``policy`` in ``env`` from ``reset(seed=seed)``; returns its metrics.

    Every task: ``return``, ``length``, ``rudder_deg`` (mean |rudder order|), ``rudder_rate_deg_s`` (mean
    |change of rudder order| per second: helm activity). ZigZag: ``heading_error_deg`` (mean |target -
    heading| over the steps), ``overshoot_deg`` (IMO overshoots summed over the episode / course changes: the
    mean excursion past the target per course change, 0 for a target not passed), ``max_overshoot_deg``,
    ``reached_pct`` (targets reached / course changes); ZigZag-v1 and ZigZagRandom-v1 report these from
    the environment's own per-course-change accounting (the open measurement included) and ``success``. TurningCircle: ``rate_error_pct`` (rate
    mode: mean |r - r_c| / |r_c|), ``success``. HarbourApproach: ``success``, ``outcome``,
    ``min_clearance_m``, ``time_s``.
    """
    from vessel_gym.control.zigzag import target_reached

    base = env.unwrapped
    layout = base.observation_layout
    dt = float(base.config.control_interval_s)
    kind = env_kind(env)
    obs, info = env.reset(seed=seed)
    policy.reset()
    ret, n = 0.0, 0
    prev_order = float(layout.value(obs, "rudder_order"))
    rudder: list[float] = []
    rudder_rate: list[float] = []
    heading_err: list[float] = []
    rate_err: list[float] = []
    overshoots: list[float] = []
    os_count = 0
    legs = reached = 0
    target = None
    side0 = 0.0
    leg_reached = False
    imo = kind == "zigzag" and getattr(base.config, "schedule", "") == "imo"
    while True:
        obs, reward, terminated, truncated, info = env.step(policy(obs))
        ret += float(reward)
        n += 1
        order = float(layout.value(obs, "rudder_order"))
        rudder.append(abs(order))
        rudder_rate.append(abs(order - prev_order) / dt)
        prev_order = order
        if kind == "zigzag":
            e = float(info["heading_error_deg"])
            heading_err.append(abs(e))
            if "overshoot_count" in info and int(info["overshoot_count"]) > os_count:  # v0's finished ones
                os_count = int(info["overshoot_count"])
                overshoots.append(abs(float(info["last_overshoot_deg"])))
            if not imo and "course_changes" not in info:
                tgt = float(info["target_heading_deg"])
                if target is None or abs(tgt - target) > 1e-9:
                    target, side0, leg_reached, legs = tgt, math.copysign(1.0, e), False, legs + 1
                # the heading error e = target - heading: the target is reached once the heading has passed it
                if not leg_reached and target_reached(side0, 0.0, e):
                    leg_reached, reached = True, reached + 1
        elif kind == "turning":
            rc = float(info.get("commanded_rate_deg_s", 0.0))
            if rc != 0.0:
                rate_err.append(abs(float(info["rate_of_turn_deg_s"]) - rc) / abs(rc))
        if terminated or truncated:
            break
    out: dict[str, Any] = {
        "seed": seed,
        "return": ret,
        "length": n,
        "rudder_deg": math.degrees(float(np.mean(rudder))),
        "rudder_rate_deg_s": math.degrees(float(np.mean(rudder_rate))),
    }
    if kind == "zigzag" and "course_changes" in info:
        # ZigZag-v1: the environment measures per course change, the open measurement included
        legs = int(info["course_changes"])
        out["heading_error_deg"] = float(np.mean(heading_err))
        out["overshoot_deg"] = float(info["overshoot_deg"])
        out["max_overshoot_deg"] = float(info["max_overshoot_deg"])
        out["reached_pct"] = 100.0 * int(info["targets_reached"]) / max(legs, 1)
        out["course_changes"] = legs
        out["success"] = bool(info["is_success"])
    elif kind == "zigzag":
        if imo:
            legs, reached = int(info["executes"]), int(info["executes"]) - 1
        out["heading_error_deg"] = float(np.mean(heading_err))
        out["overshoot_deg"] = float(np.sum(overshoots)) / max(legs, 1)
        out["max_overshoot_deg"] = float(np.max(overshoots)) if overshoots else 0.0
        out["reached_pct"] = 100.0 * reached / max(legs, 1)
        out["course_changes"] = legs
    elif kind == "turning":
        out["rate_error_pct"] = 100.0 * float(np.mean(rate_err)) if rate_err else math.nan
        out["success"] = bool(info.get("success", False))
        for key in ("advance_m", "transfer_m", "tactical_diameter_m"):
            out[key] = float(info[key])
    elif kind == "harbour":
        out["success"] = bool(info["success"])
        out["outcome"] = str(info["outcome"]) if terminated else "timeout"
        out["min_clearance_m"] = float(info["min_clearance_m"])
        out["time_s"] = float(info["time_s"])
    return out


def summarize(episodes: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """Mean and standard deviation over episodes of every numeric metric (NaN-aware; ``success`` as a rate,
    ``outcome`` as counts)."""
    out: dict[str, Any] = {"episodes": len(episodes)}
    keys = [k for k in episodes[0] if k not in ("seed", "outcome")]
    for k in keys:
        x = np.array([float(e[k]) for e in episodes], dtype=np.float64)
        finite = x[np.isfinite(x)]
        if k == "success":
            out["success_rate"] = float(np.mean(x))
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
) -> dict[str, Any]:
    """Run ``episodes`` episodes (episode i from ``reset(seed=seed + i)``) of a baseline or trained agent.

    ``env_kwargs`` default to the evaluation arguments of the model's run record (``eval_env_kwargs`` of its
    hyperparameter block, which default to its ``env_kwargs``), else none. Returns
    ``{"env_id", "agent", "env_kwargs", "summary", "episodes"}``; see :func:`run_episode` for the metrics.
    ``render_mode`` is passed to ``gym.make``; ``wrap(env)`` may wrap the environment (recording tracks or
    frames, :mod:`agents.visual`) without changing what the agent sees.
    """
    env_id = resolve_env_id(env_id)
    if episodes < 1:
        raise UsageError(f"episodes must be >= 1, got {episodes}")
    spec = str(agent)
    if spec not in BASELINES and not Path(spec).is_file() and not Path(spec + ".zip").is_file():
        raise UsageError(f"agent {spec!r}: not a baseline ({', '.join(BASELINES)}) and no such file")
    rec = run_record(spec)
    if rec.get("env_id") not in (None, env_id):
        raise UsageError(f"agent {spec!r} was trained on {rec['env_id']}, not {env_id}")
    recorded = rec.get("eval_env_kwargs", rec.get("env_kwargs"))
    kwargs = dict(recorded or {}) if env_kwargs is None else dict(env_kwargs)
    env = make_env(env_id, kwargs if render_mode is None else {**kwargs, "render_mode": render_mode})
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
    return {"env_id": env_id, "agent": spec, "env_kwargs": kwargs, "summary": summarize(eps), "episodes": eps}
