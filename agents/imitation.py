"""Behaviour cloning from the classical pilot with DAgger: a method that starts from the pilot.

The learner is the policy network of the environment's PPO block (``agents/hyperparams/ppo.yml``, same
architecture), so the result is an ordinary SB3 PPO model: ``evaluate.py``, ``vessel_gym.policy.load_policy``
and ``vessel-gym serve --agent`` run it like any trained agent, and PPO can continue training it.

DAgger (Ross, Gordon & Bagnell 2011, "A reduction of imitation learning and structured prediction to no-regret
online learning", AISTATS): round 0 lets the pilot (``pid`` or ``scripted`` of
:func:`vessel_gym.policy.load_policy`) drive ``n_envs`` ships of the native vector environment for
``steps_per_round`` environment steps and records (observation, pilot's order); every later round lets the
current learner drive (its deterministic action) while the pilot, run alongside on the same observations
(so its waypoint and integral states follow the learner's track), labels each state with the order it would
give. After each round the network's mean action is fitted to all labels so far (mean squared error, Adam).
Plain behaviour cloning (round 0 only) learns from the pilot's states alone and drifts where the learner
leaves them; DAgger adds exactly those states.

Settings per environment live in ``agents/hyperparams/bc.yml``; the training seeds follow the rules of
:mod:`agents.seeds` (ships ``seed .. seed + n_envs - 1``), so no validation or test episode is seen.
"""

from __future__ import annotations

import os
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from agents import seeds
from agents.config import (
    UsageError,
    check_keys,
    load_hyperparams,
    model_stem,
    resolve_env_id,
    run_config,
    sidecar,
)
from agents.envs import make_vec_env
from agents.training import TrainResult, build_model

BC_FILE = Path(__file__).resolve().parent / "hyperparams" / "bc.yml"
#: settings of a bc.yml block and their defaults
DEFAULTS: dict[str, Any] = {
    "pilot": "pid",
    "rounds": 6,
    "steps_per_round": 16384,
    "epochs": 10,
    "batch_size": 256,
    "learning_rate": 1e-3,
    "n_envs": 16,
}


def load_bc_settings(env_id: str, path: str | Path | None = None) -> dict[str, Any]:
    """The bc.yml block of ``env_id`` over :data:`DEFAULTS`; unknown keys or bad values are a UsageError."""
    import yaml

    env_id = resolve_env_id(env_id)
    path = Path(path) if path is not None else BC_FILE
    data = yaml.safe_load(path.read_text()) if path.is_file() else None
    block = (data or {}).get(env_id)
    if block is None:
        raise UsageError(f"{path}: no behaviour-cloning block for {env_id}")
    check_keys(f"{path}: {env_id}", block, DEFAULTS)
    out = {**DEFAULTS, **block}
    if out["pilot"] not in ("pid", "scripted"):
        raise UsageError(f"{path}: {env_id}: pilot must be pid or scripted, got {out['pilot']!r}")
    for key in ("rounds", "steps_per_round", "epochs", "batch_size", "n_envs"):
        if not isinstance(out[key], int) or out[key] < 1:
            raise UsageError(f"{path}: {env_id}: {key} must be an integer >= 1, got {out[key]!r}")
    if not float(out["learning_rate"]) > 0.0:
        raise UsageError(f"{path}: {env_id}: learning_rate must be > 0, got {out['learning_rate']!r}")
    return out


def _mean_action(policy: Any, obs: Any) -> Any:
    """The policy network's mean action (its deterministic action before clipping to the action space)."""
    features = policy.extract_features(obs, policy.pi_features_extractor)
    return policy.action_net(policy.mlp_extractor.forward_actor(features))


def _fit(
    policy: Any,
    obs: np.ndarray,
    act: np.ndarray,
    epochs: int,
    batch: int,
    rng: np.random.Generator,
    optimizer: Any,
) -> float:
    """``epochs`` passes of minibatch MSE regression of the mean action on the labels; the last epoch's loss."""
    import torch

    x, y = torch.as_tensor(obs), torch.as_tensor(act)
    loss_sum = 0.0
    for _ in range(epochs):
        order = rng.permutation(len(x))
        loss_sum, count = 0.0, 0
        for i in range(0, len(x), batch):
            idx = torch.as_tensor(order[i : i + batch])
            loss = torch.nn.functional.mse_loss(_mean_action(policy, x[idx]), y[idx])
            optimizer.zero_grad()
            loss.backward()
            optimizer.step()
            loss_sum += loss.item() * len(idx)
            count += len(idx)
        loss_sum /= max(count, 1)
    return loss_sum


def clone(
    env_id: str,
    seed: int = 0,
    *,
    out: str | Path = "runs",
    settings: Mapping[str, Any] | None = None,
    bc_file: str | Path | None = None,
    threads: int | None = 1,
) -> TrainResult:
    """Clone the pilot into the PPO network of ``env_id`` by DAgger; save ``<out>/ppo_<env>_s<seed>.zip`` and
    its run record ``.yml`` (``method: bc``, the settings, steps collected, times, per-round agreement).

    ``settings`` override the bc.yml block (``bc_file``, default ``agents/hyperparams/bc.yml``).
    """
    import stable_baselines3 as sb3
    import torch
    import yaml

    from vessel_gym.policy import load_policy

    env_id = resolve_env_id(env_id)
    st = {**load_bc_settings(env_id, bc_file), **dict(settings or {})}
    cfg = run_config("ppo", env_id, load_hyperparams("ppo", env_id, None, {"n_envs": st["n_envs"]}))
    try:
        seeds.check_training_seed(seed, st["n_envs"])
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    if threads:
        torch.set_num_threads(threads)
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    # the registered task (eval_env_kwargs): training wrappers and reward shaping play no part in imitation
    venv = make_vec_env(env_id, st["n_envs"], seed, "native", cfg.eval_env_kwargs)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        model = build_model(cfg, venv, seed)
        policy = model.policy
        pilot = load_policy(st["pilot"], venv.venv.venv)  # VecMonitor -> adapter -> native vector env
        optimizer = torch.optim.Adam(policy.parameters(), lr=float(st["learning_rate"]))
        xs: list[np.ndarray] = []
        ys: list[np.ndarray] = []
        rounds: list[dict[str, Any]] = []
        obs = venv.reset()
        pilot.reset()
        for k in range(st["rounds"]):
            n_steps = -(-st["steps_per_round"] // st["n_envs"])
            ends = successes = 0
            gap = 0.0
            for _ in range(n_steps):
                label = np.asarray(pilot(obs), dtype=np.float32)
                if k == 0:
                    act = label
                else:
                    act, _ = model.predict(obs, deterministic=True)
                    gap += float(np.mean(np.abs(act - label)))
                xs.append(np.asarray(obs, dtype=np.float32).copy())
                ys.append(label)
                obs, _, done, infos = venv.step(act)
                if done.any():
                    pilot.reset(mask=done)
                    ends += int(done.sum())
                    successes += sum(bool(infos[i].get("is_success", False)) for i in np.flatnonzero(done))
            policy.set_training_mode(True)
            loss = _fit(
                policy, np.concatenate(xs), np.concatenate(ys), st["epochs"], st["batch_size"], rng, optimizer
            )
            policy.set_training_mode(False)
            rounds.append(
                {
                    "driver": "pilot" if k == 0 else "learner",
                    "episodes_ended": ends,
                    "success_rate": successes / ends if ends else None,
                    "mean_abs_action_gap": None if k == 0 else gap / n_steps,
                    "fit_mse": loss,
                }
            )
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        stem = model_stem("ppo", env_id, seed)
        model_path = out / f"{stem}.zip"
        model.save(str(model_path))
    finally:
        venv.close()
    collected = int(sum(len(x) for x in xs))
    record = {
        "env_id": env_id,
        "algo": "ppo",
        "method": "bc",
        "method_detail": f"behaviour cloning of the {st['pilot']} pilot by DAgger, {st['rounds']} rounds",
        "bc": dict(st),
        "bc_rounds": rounds,
        "seed": seed,
        "n_timesteps": collected,
        "num_timesteps": collected,
        "n_envs": st["n_envs"],
        "vec": "native",
        "hyperparams": cfg.hyperparams,
        "env_kwargs": cfg.eval_env_kwargs,
        "eval_env_kwargs": cfg.eval_env_kwargs,
        "env_wrapper": None,
        "vecnormalize": None,
        "train_time_s": round(wall, 2),
        "cpu_time_s": round(cpu, 2),
        "time_budget_s": None,
        "budget_hit": False,
        "load_average_start": load,
        "cpu_count": os.cpu_count(),
        "torch_threads": torch.get_num_threads(),
        "stable_baselines3": str(sb3.__version__),
        "torch": str(torch.__version__),
    }
    record_path = sidecar(model_path, ".yml")
    record_path.write_text(yaml.safe_dump(record, sort_keys=False))
    return TrainResult(model_path, record_path, None, wall, cpu, collected, False, cfg)


__all__ = ["BC_FILE", "DEFAULTS", "clone", "load_bc_settings"]
