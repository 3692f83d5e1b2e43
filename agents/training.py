"""Training of one agent: the SB3 model of a :class:`~agents.config.RunConfig`, its callbacks (time budget,
validation), checkpoints, and the run record written next to the saved model.
"""

from __future__ import annotations

import os
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from agents import seeds
from agents.cli_util import json_safe
from agents.config import (
    ALGOS,
    RunConfig,
    UsageError,
    check_algo,
    load_hyperparams,
    model_stem,
    resolve_env_id,
    run_config,
    sidecar,
)
from agents.envs import make_env, make_vec_env
from agents.evaluation import evaluate


@dataclass
class TrainResult:
    model_path: Path
    record_path: Path
    vecnormalize_path: Path | None
    wall_time_s: float
    cpu_time_s: float
    n_timesteps: int  # steps actually trained (fewer than asked if the time budget ran out)
    budget_hit: bool
    config: RunConfig
    best_model_path: Path | None = None  # with eval_freq: the best model of the periodic evaluations
    test: dict[str, dict[str, Any]] = field(default_factory=dict)  # "final"/"best" -> test-set summary


def _stop_on_wall_clock(seconds: float) -> Any:
    """SB3 callback that ends training after ``seconds`` of wall-clock time."""
    from stable_baselines3.common.callbacks import BaseCallback

    class StopOnWallClock(BaseCallback):
        def __init__(self) -> None:
            super().__init__()
            self.deadline = 0.0
            self.hit = False

        def _on_training_start(self) -> None:
            self.deadline = time.perf_counter() + seconds

        def _on_step(self) -> bool:
            if time.perf_counter() >= self.deadline:
                self.hit = True
                return False
            return True

    return StopOnWallClock()


def curriculum_callback(spec: Mapping[str, Any], n_timesteps: int, n_envs: int) -> Any:
    """SB3 callback of a ``curriculum`` block (:func:`agents.config._curriculum`): the training episodes start
    at ``levels[0]`` (the training environment is made at it) and move to the next level, through the
    environment's ``set_difficulty`` (from each copy's next reset), when the success rate of the last
    ``window`` training episodes begun at the current level reaches ``promote_at``, or at the latest when
    training passes k / (len(levels) - 1) x ``final_by`` x ``n_timesteps`` for level k: a curriculum that
    ends on the task itself in every run. ``history``: (timesteps, level, why) of every change, for the run
    record."""
    from collections import deque

    from stable_baselines3.common.callbacks import BaseCallback

    levels = list(spec["levels"])
    last = len(levels) - 1
    deadlines = [k / last * spec["final_by"] * n_timesteps for k in range(len(levels))]

    class Curriculum(BaseCallback):
        def __init__(self) -> None:
            super().__init__()
            self.index = 0
            self.history: list[dict[str, Any]] = [{"timesteps": 0, "level": levels[0], "why": "start"}]
            self.recent: deque[bool] = deque(maxlen=spec["window"])
            # a copy's first episode to end after a change began at the level before it: not counted
            self.fresh = np.ones(n_envs, dtype=bool)

        def _on_step(self) -> bool:
            for i, (done, info) in enumerate(zip(self.locals["dones"], self.locals["infos"])):
                if not done:
                    continue
                if self.fresh[i]:
                    self.recent.append(bool(info.get("success", False)))
                self.fresh[i] = True
            self.logger.record("curriculum/level", self.index)  # learning curves over the levels
            if self.index < last:
                full = len(self.recent) == self.recent.maxlen
                if full and float(np.mean(self.recent)) >= spec["promote_at"]:
                    self._promote(f"success {np.mean(self.recent):.2f} over {len(self.recent)} episodes")
                elif self.num_timesteps >= deadlines[self.index + 1]:
                    self._promote("schedule")
            return True

        def _promote(self, why: str) -> None:
            self.index += 1
            self.training_env.env_method("set_difficulty", levels[self.index])
            self.history.append(
                {"timesteps": int(self.num_timesteps), "level": levels[self.index], "why": why}
            )
            self.recent.clear()
            self.fresh[:] = False

    return Curriculum()


#: per periodic evaluation, the training time spent until then (next to SB3's ``evaluations.npz``)
EVAL_TIMES_FILE = "eval_times.npz"


def _validation_callback(seed0: int) -> type:
    """SB3 ``EvalCallback`` that reseeds its environment (copy i: ``seed0 + i``) before every evaluation and
    writes :data:`EVAL_TIMES_FILE`: ``timesteps``, ``wall_s`` and ``cpu_s`` of training until each evaluation
    (the evaluations' own time left out: they measure, they do not train), for learning curves over wall time
    and the time to solve."""
    from stable_baselines3.common.callbacks import EvalCallback

    class ValidationCallback(EvalCallback):
        def _on_training_start(self) -> None:
            super()._on_training_start()
            self._t0, self._c0 = time.perf_counter(), time.process_time()
            self._eval_wall = self._eval_cpu = 0.0
            self.eval_times: dict[str, list[float]] = {"timesteps": [], "wall_s": [], "cpu_s": []}

        def _on_step(self) -> bool:
            if not (self.eval_freq > 0 and self.n_calls % self.eval_freq == 0):
                return super()._on_step()
            self.eval_env.seed(seed0)
            w, c = time.perf_counter(), time.process_time()
            self.eval_times["timesteps"].append(self.num_timesteps)
            self.eval_times["wall_s"].append(w - self._t0 - self._eval_wall)
            self.eval_times["cpu_s"].append(c - self._c0 - self._eval_cpu)
            go_on = super()._on_step()
            self._eval_wall += time.perf_counter() - w
            self._eval_cpu += time.process_time() - c
            if self.log_path is not None:
                np.savez(Path(self.log_path).parent / EVAL_TIMES_FILE, **self.eval_times)
            return go_on

    return ValidationCallback


def _test_evaluation(
    env_id: str, model: Path, episodes: int, env_kwargs: Mapping[str, Any], action_filter: Any
) -> dict[str, Any]:
    """:func:`evaluate` of a trained model on the first ``episodes`` test seeds, for the run record."""
    start = seeds.episode_seeds("test", episodes)[0]
    summary = evaluate(env_id, model, episodes, start, env_kwargs, action_filter=action_filter)["summary"]
    return {"seeds": f"{start}..{start + episodes - 1}", **json_safe(summary)}


def build_model(cfg: RunConfig, venv: Any, seed: int, verbose: int = 0) -> Any:
    """The SB3 model of a run configuration on ``venv``."""
    import stable_baselines3 as sb3

    kwargs = dict(cfg.algo_kwargs)
    if cfg.noise is not None:
        from stable_baselines3.common.noise import NormalActionNoise, OrnsteinUhlenbeckActionNoise

        n = venv.action_space.shape[0]
        kind, std = cfg.noise
        cls = NormalActionNoise if kind == "normal" else OrnsteinUhlenbeckActionNoise
        kwargs["action_noise"] = cls(mean=np.zeros(n), sigma=std * np.ones(n))
    try:
        return getattr(sb3, ALGOS[cfg.algo])(
            cfg.policy,
            venv,
            seed=seed,
            device="cpu",
            verbose=verbose,
            policy_kwargs=cfg.policy_kwargs or None,
            **kwargs,
        )
    except (TypeError, ValueError, AssertionError) as exc:
        raise UsageError(f"{ALGOS[cfg.algo]} on {cfg.env_id}: {exc}") from None


def train(
    algo: str,
    env_id: str,
    seed: int = 0,
    *,
    timesteps: int | None = None,
    n_envs: int | None = None,
    vec: str = "native",
    out: str | Path = "runs",
    hyperparams_file: str | Path | None = None,
    overrides: Mapping[str, Any] | None = None,
    log_formats: Sequence[str] = ("csv",),
    checkpoint_freq: int | None = None,
    progress_bar: bool = False,
    threads: int | None = 1,
    callbacks: Sequence[Any] = (),
    time_budget_s: float | None = None,
    eval_freq: int | None = None,
    eval_episodes: int = 10,
    test_episodes: int = 0,
    verbose: int = 0,
) -> TrainResult:
    """Train ``algo`` on ``env_id`` with the hyperparameters of its block; save the model under ``out``.

    ``timesteps`` and ``n_envs`` override the block's ``n_timesteps``/``n_envs``; ``overrides`` any key.
    Writes ``<out>/<stem>.zip``, the run record ``<stem>.yml``, ``<stem>_vecnormalize.pkl`` (only with
    ``normalize``), the SB3 log ``<out>/logs/<stem>/progress.csv`` and checkpoints
    ``<out>/checkpoints/<stem>_<steps>_steps.zip`` every ``checkpoint_freq`` steps (default: a tenth of
    the run). ``time_budget_s`` stops training early (the model is saved as it is then).
    ``eval_freq``: every ``eval_freq`` steps, evaluate the deterministic policy on the same ``eval_episodes``
    episodes of the validation seed set (:mod:`agents.seeds`) of the evaluation environment
    (``eval_env_kwargs``, registered reward, no training wrappers) and keep the best as ``<stem>_best.zip``
    with its own run record (``selected_at_timesteps``). ``test_episodes``: after training, evaluate the
    final (and the best) model on that many episodes of the test seed set; the summaries go to the run
    records (``test``). ``vec``: see :func:`make_vec_env` (default the native vector environment).
    ``threads``: torch threads (1 is fastest for these small networks on a shared CPU).
    """
    import stable_baselines3 as sb3
    import torch
    import yaml
    from stable_baselines3.common.callbacks import CheckpointCallback
    from stable_baselines3.common.logger import configure
    from stable_baselines3.common.vec_env import VecNormalize

    algo = check_algo(algo)
    env_id = resolve_env_id(env_id)
    if seed < 0:
        raise UsageError(f"seed must be >= 0, got {seed}")
    if eval_freq and eval_episodes < 1:
        raise UsageError(f"eval_episodes must be >= 1, got {eval_episodes}")
    if test_episodes < 0:
        raise UsageError(f"test_episodes must be >= 0, got {test_episodes}")
    over = dict(overrides or {})
    if timesteps is not None:
        over["n_timesteps"] = timesteps
    if n_envs is not None:
        over["n_envs"] = n_envs
    cfg = run_config(algo, env_id, load_hyperparams(algo, env_id, hyperparams_file, over))
    try:
        seeds.check_training_seed(seed, cfg.n_envs)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    if threads:
        torch.set_num_threads(threads)
    out = Path(out)
    stem = model_stem(algo, env_id, seed)
    out.mkdir(parents=True, exist_ok=True)

    from agents.wrappers import join

    train_wrappers = join(cfg.action_filter, cfg.env_wrapper)  # the filter innermost: it is the agent's
    train_kwargs = dict(cfg.env_kwargs)
    if cfg.curriculum is not None:
        # every level through the task's own config check now (a task without `difficulty`, a level out of
        # its range: one line before training), not at a promotion mid-run; the first episodes at the first
        for level in reversed(cfg.curriculum["levels"]):
            train_kwargs["difficulty"] = level
            make_env(env_id, train_kwargs).close()
    venv = make_vec_env(env_id, cfg.n_envs, seed, vec, train_kwargs, env_wrapper=train_wrappers or None)
    try:
        if cfg.normalize is not None:
            norm = dict(cfg.normalize)
            norm.setdefault("gamma", cfg.algo_kwargs.get("gamma", 0.99))
            venv = VecNormalize(venv, **norm)
        model = build_model(cfg, venv, seed, verbose=verbose)
        model.set_logger(configure(str(out / "logs" / stem), list(log_formats)))
        freq = checkpoint_freq if checkpoint_freq is not None else max(cfg.n_timesteps // 10, 1)
        cbs = [CheckpointCallback(max(freq // cfg.n_envs, 1), str(out / "checkpoints"), name_prefix=stem)]
        stopper = _stop_on_wall_clock(time_budget_s) if time_budget_s else None
        if stopper is not None:
            cbs.append(stopper)
        teacher = None
        if cfg.curriculum is not None:
            teacher = curriculum_callback(cfg.curriculum, cfg.n_timesteps, cfg.n_envs)
            cbs.append(teacher)
        evaluator = None
        if eval_freq:
            # one copy per validation episode, all reseeded before every evaluation: the same episodes each time
            val0 = seeds.episode_seeds("validation", eval_episodes)[0]
            eval_vec = "native" if vec == "native" else "dummy"
            eval_venv = make_vec_env(
                env_id, eval_episodes, val0, eval_vec, cfg.eval_env_kwargs, env_wrapper=cfg.action_filter
            )
            if cfg.normalize is not None:
                eval_venv = VecNormalize(
                    eval_venv, training=False, norm_obs=cfg.normalize["norm_obs"], norm_reward=False
                )
            evaluator = _validation_callback(val0)(
                eval_venv,
                n_eval_episodes=eval_episodes,
                eval_freq=max(eval_freq // cfg.n_envs, 1),
                best_model_save_path=str(out / "best" / stem),
                log_path=str(out / "logs" / stem),
                deterministic=True,
                verbose=0,
            )
            cbs.append(evaluator)
        load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
        t0, c0 = time.perf_counter(), time.process_time()
        model.learn(cfg.n_timesteps, callback=[*cbs, *callbacks], progress_bar=progress_bar)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        model_path = out / f"{stem}.zip"
        model.save(str(model_path))
        vn_path = None
        if cfg.normalize is not None:
            vn_path = sidecar(model_path, "_vecnormalize.pkl")
            venv.save(str(vn_path))
    finally:
        venv.close()
    best_path, best_step = None, None
    if evaluator is not None:
        evaluator.eval_env.close()
        saved = out / "best" / stem / "best_model.zip"
        if saved.is_file() and evaluator.evaluations_results:
            means = [float(np.mean(r)) for r in evaluator.evaluations_results]
            best_step = int(evaluator.evaluations_timesteps[int(np.argmax(means))])
            best_path = out / f"{stem}_best.zip"
            saved.replace(best_path)
    record = {
        "env_id": env_id,
        "algo": algo,
        "seed": seed,
        "n_timesteps": cfg.n_timesteps,
        "num_timesteps": int(model.num_timesteps),
        "n_envs": cfg.n_envs,
        "vec": vec,
        "hyperparams": cfg.hyperparams,
        "env_kwargs": cfg.env_kwargs,
        "eval_env_kwargs": cfg.eval_env_kwargs,
        "env_wrapper": cfg.env_wrapper,
        "action_filter": cfg.action_filter,
        "curriculum": cfg.curriculum,
        "curriculum_history": teacher.history if teacher is not None else None,
        "vecnormalize": vn_path.name if vn_path else None,
        "train_time_s": round(wall, 2),
        "cpu_time_s": round(cpu, 2),
        "time_budget_s": time_budget_s,
        "budget_hit": bool(stopper is not None and stopper.hit),
        "load_average_start": load,
        "cpu_count": os.cpu_count(),
        "torch_threads": torch.get_num_threads(),
        "stable_baselines3": str(sb3.__version__),
        "torch": str(torch.__version__),
    }
    if eval_freq:
        record["eval_freq"] = eval_freq
        record["eval_episodes"] = eval_episodes
        record["validation_seeds"] = f"{val0}..{val0 + eval_episodes - 1}"
    if test_episodes:
        record["test"] = _test_evaluation(
            env_id, model_path, test_episodes, cfg.eval_env_kwargs, cfg.action_filter
        )
    record_path = sidecar(model_path, ".yml")
    record_path.write_text(yaml.safe_dump(record, sort_keys=False))
    if best_path is not None:
        best_record = {**record, "selected_at_timesteps": best_step, "selected_from": model_path.name}
        if test_episodes:
            best_record["test"] = _test_evaluation(
                env_id, best_path, test_episodes, cfg.eval_env_kwargs, cfg.action_filter
            )
        if vn_path is not None:  # observation statistics of the end of the run (exact without norm_obs)
            best_vn = sidecar(best_path, "_vecnormalize.pkl")
            best_vn.write_bytes(vn_path.read_bytes())
            best_record["vecnormalize"] = best_vn.name
        sidecar(best_path, ".yml").write_text(yaml.safe_dump(best_record, sort_keys=False))
    hit = bool(stopper is not None and stopper.hit)
    test = {"final": record["test"]} if test_episodes else {}
    if test_episodes and best_path is not None:
        test["best"] = best_record["test"]
    return TrainResult(
        model_path, record_path, vn_path, wall, cpu, int(model.num_timesteps), hit, cfg, best_path, test
    )
