"""Shared machinery of the agent scripts: hyperparameter files, vector environments, training, evaluation.

The scripts (``train.py``, ``evaluate.py``, ``results.py``, ``tune_ray.py``) are thin command lines over
the functions here, so a notebook, a test or a Ray trial trains and evaluates exactly as the scripts do:

* :func:`load_hyperparams` reads ``agents/hyperparams/<algo>.yml`` (one block per env id, rl-zoo3 style)
  and :func:`run_config` checks every key against the algorithm's constructor;
* :func:`make_vec_env` builds the SB3 vector environment of a registered id: its native vector version
  (:mod:`vessel_gym.sb3`, the default), a ``DummyVecEnv`` or a ``SubprocVecEnv``;
* :func:`train` trains, logs (CSV), checkpoints and saves ``<out>/<algo>_<env>_s<seed>.zip`` with its
  run record ``<algo>_<env>_s<seed>.yml`` next to it;
* :func:`evaluate` runs seeded episodes of a baseline (``pid``, ``scripted``) or a saved model through
  :func:`vessel_gym.policy.load_policy` and reports per-task metrics.

Errors in user input (unknown env id, algorithm, hyperparameter key, bad value) raise :class:`UsageError`;
the command lines turn it into exit code 2 with one line on stderr.
"""

from __future__ import annotations

import argparse
import copy
import inspect
import math
import os
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from agents import seeds

HYPERPARAMS_DIR = Path(__file__).resolve().parent / "hyperparams"
ALGOS: dict[str, str] = {"ppo": "PPO", "sac": "SAC", "td3": "TD3", "a2c": "A2C"}
VEC_KINDS = ("native", "dummy", "subproc")
BASELINES = ("pid", "scripted")

#: keys of a hyperparameter block that are not constructor arguments of the algorithm
META_KEYS = (
    "n_timesteps",
    "policy",
    "n_envs",
    "normalize",
    "env_kwargs",
    "eval_env_kwargs",
    "env_wrapper",
    "noise_type",
    "noise_std",
)
NORMALIZE_KEYS = ("norm_obs", "norm_reward", "clip_obs", "clip_reward", "gamma", "epsilon")
ACTIVATIONS = ("tanh", "relu", "elu", "leaky_relu", "gelu", "silu")


class UsageError(ValueError):
    """Bad input from the user: an unknown id, algorithm or key, or a value out of range."""


# --- names -----------------------------------------------------------------------------------------------------
def json_safe(x: Any) -> Any:
    """``x`` with non-finite floats replaced by None (JSON has no NaN or inf), through dicts and lists."""
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, dict):
        return {k: json_safe(v) for k, v in x.items()}
    if isinstance(x, list):
        return [json_safe(v) for v in x]
    return x


def registered_ids() -> list[str]:
    """The vessel-gym environment ids."""
    from vessel_gym.envs.registration import ENVIRONMENTS, register_envs

    register_envs()
    return list(ENVIRONMENTS)


def resolve_env_id(name: str) -> str:
    """Full env id from ``vessel_gym/ZigZag-v0`` or the short ``ZigZag-v0``."""
    ids = registered_ids()
    if name in ids:
        return name
    if f"vessel_gym/{name}" in ids:
        return f"vessel_gym/{name}"
    raise UsageError(f"unknown environment {name!r} (have: {', '.join(ids)})")


def env_short_name(env_id: str) -> str:
    """``vessel_gym/ZigZag-v0`` -> ``ZigZag-v0`` (used in file names)."""
    return env_id.split("/")[-1]


def check_algo(algo: str) -> str:
    """Lower-case algorithm name, or :class:`UsageError`."""
    a = algo.lower()
    if a not in ALGOS:
        raise UsageError(f"unknown algorithm {algo!r} (have: {', '.join(ALGOS)})")
    return a


def model_stem(algo: str, env_id: str, seed: int) -> str:
    """File stem of a trained model, ``<algo>_<env>_s<seed>``; :func:`vessel_gym.policy.load_policy` reads the
    algorithm from the part before the first underscore."""
    return f"{check_algo(algo)}_{env_short_name(env_id)}_s{seed}"


def sidecar(model_path: str | Path, suffix: str) -> Path:
    """Companion file of a model: ``ppo_X_s0.zip`` -> ``ppo_X_s0<suffix>``."""
    p = Path(model_path)
    return p.with_name(p.stem + suffix)


def parse_assignments(items: Sequence[str] | None, what: str) -> dict[str, Any]:
    """``["gamma=0.995", "policy_kwargs.net_arch=[64, 64]"]`` -> a nested mapping (values parsed as YAML)."""
    import yaml

    out: dict[str, Any] = {}
    for item in items or ():
        key, sep, text = item.partition("=")
        if not sep or not key.strip():
            raise UsageError(f"{what}: expected KEY=VALUE, got {item!r}")
        try:
            value = yaml.safe_load(text) if text.strip() else None
        except yaml.YAMLError:
            raise UsageError(f"{what}: cannot parse the value of {key!r}: {text!r}") from None
        node = out
        parts = key.strip().split(".")
        for part in parts[:-1]:
            node = node.setdefault(part, {})
            if not isinstance(node, dict):
                raise UsageError(f"{what}: {key!r} conflicts with an earlier assignment")
        node[parts[-1]] = value
    return out


def merge(base: Mapping[str, Any], over: Mapping[str, Any]) -> dict[str, Any]:
    """Copy of ``base`` with ``over`` applied; nested mappings merge key by key."""
    out = copy.deepcopy(dict(base))
    for k, v in over.items():
        if isinstance(v, Mapping) and isinstance(out.get(k), Mapping):
            out[k] = merge(out[k], v)
        else:
            out[k] = copy.deepcopy(v)
    return out


# --- hyperparameters -------------------------------------------------------------------------------------------
def load_hyperparams(
    algo: str,
    env_id: str,
    path: str | Path | None = None,
    overrides: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """The hyperparameter block of ``env_id`` in ``path`` (default ``agents/hyperparams/<algo>.yml``),
    with ``overrides`` merged in."""
    import yaml

    algo = check_algo(algo)
    file = Path(path) if path is not None else HYPERPARAMS_DIR / f"{algo}.yml"
    try:
        data = yaml.safe_load(file.read_text())
    except OSError as exc:
        raise UsageError(f"cannot read hyperparameters {file}: {exc.strerror or exc}") from None
    except yaml.YAMLError as exc:
        raise UsageError(f"{file}: not valid YAML ({str(exc).splitlines()[0]})") from None
    if not isinstance(data, dict):
        raise UsageError(f"{file}: expected a mapping of env id -> hyperparameters")
    block = data.get(env_id, data.get(env_short_name(env_id)))
    if block is None:
        raise UsageError(f"{file}: no hyperparameters for {env_id} (have: {', '.join(map(str, data))})")
    if not isinstance(block, dict):
        raise UsageError(f"{file}: the block of {env_id} is not a mapping")
    return merge(block, overrides or {})


class LinearSchedule:
    """SB3 schedule ``progress_remaining -> value``: falls linearly from ``initial`` to 0 (rl-zoo ``lin_X``)."""

    def __init__(self, initial: float) -> None:
        self.initial = float(initial)

    def __call__(self, progress_remaining: float) -> float:
        return progress_remaining * self.initial

    def __repr__(self) -> str:
        return f"lin_{self.initial:g}"


def _schedule(key: str, value: Any) -> Any:
    if isinstance(value, str) and value.startswith("lin_"):
        try:
            return LinearSchedule(float(value[4:]))
        except ValueError:
            raise UsageError(f"hyperparameter {key}: bad schedule {value!r} (expected lin_<float>)") from None
    if isinstance(value, str):
        try:
            return float(value)
        except ValueError:
            raise UsageError(
                f"hyperparameter {key}: expected a number or lin_<float>, got {value!r}"
            ) from None
    return value


def _policy_kwargs(value: Any) -> dict[str, Any]:
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise UsageError(f"hyperparameter policy_kwargs: expected a mapping, got {value!r}")
    out = dict(value)
    act = out.get("activation_fn")
    if act is not None:
        import torch.nn as nn

        if not isinstance(act, str) or act.lower() not in ACTIVATIONS:
            raise UsageError(
                f"policy_kwargs.activation_fn: expected one of {', '.join(ACTIVATIONS)}, got {act!r}"
            )
        names = {
            "tanh": nn.Tanh,
            "relu": nn.ReLU,
            "elu": nn.ELU,
            "leaky_relu": nn.LeakyReLU,
            "gelu": nn.GELU,
            "silu": nn.SiLU,
        }
        out["activation_fn"] = names[act.lower()]
    return out


def _normalize(value: Any) -> dict[str, Any] | None:
    if value in (None, False):
        return None
    if value is True:
        return {"norm_obs": True, "norm_reward": True}
    if not isinstance(value, Mapping):
        raise UsageError(f"hyperparameter normalize: expected true/false or a mapping, got {value!r}")
    bad = sorted(set(value) - set(NORMALIZE_KEYS))
    if bad:
        raise UsageError(
            f"hyperparameter normalize: unknown key(s) {bad} (allowed: {', '.join(NORMALIZE_KEYS)})"
        )
    return {"norm_obs": True, "norm_reward": True, **value}


@dataclass
class RunConfig:
    """A hyperparameter block split into what the run needs (see ``docs/agents.md``)."""

    algo: str
    env_id: str
    n_timesteps: int
    policy: str
    n_envs: int
    normalize: dict[str, Any] | None
    env_kwargs: dict[str, Any]
    eval_env_kwargs: dict[str, Any]
    env_wrapper: Any
    policy_kwargs: dict[str, Any]
    algo_kwargs: dict[str, Any]
    noise: tuple[str, float] | None
    hyperparams: dict[str, Any] = field(default_factory=dict)  # the block as written (for the run record)


def run_config(algo: str, env_id: str, hyperparams: Mapping[str, Any]) -> RunConfig:
    """Check a hyperparameter block against the algorithm's constructor and split it."""
    import stable_baselines3 as sb3

    algo = check_algo(algo)
    hp = dict(hyperparams)
    cls = getattr(sb3, ALGOS[algo])
    accepted = set(inspect.signature(cls.__init__).parameters) - {"self", "policy", "env", "seed", "device"}
    bad = sorted(k for k in hp if k not in META_KEYS and k not in accepted)
    if bad:
        raise UsageError(
            f"hyperparameter(s) {', '.join(bad)} not accepted by {ALGOS[algo]} for {env_id} "
            f"(allowed: {', '.join(sorted(set(META_KEYS) | accepted))})"
        )

    def positive_int(key: str, default: int) -> int:
        v = hp.get(key, default)
        try:
            f = float(v)
        except (TypeError, ValueError):
            raise UsageError(f"hyperparameter {key}: expected a positive integer, got {v!r}") from None
        if not math.isfinite(f) or f < 1 or f != int(f):
            raise UsageError(f"hyperparameter {key}: expected a positive integer, got {v!r}")
        return int(f)

    env_kwargs = hp.get("env_kwargs") or {}
    eval_env_kwargs = hp.get("eval_env_kwargs", env_kwargs) or {}
    for key, value in (("env_kwargs", env_kwargs), ("eval_env_kwargs", eval_env_kwargs)):
        if not isinstance(value, Mapping):
            raise UsageError(f"hyperparameter {key}: expected a mapping, got {value!r}")
    from agents import wrappers

    try:
        wrappers.resolve(hp.get("env_wrapper"))
    except ValueError as exc:
        raise UsageError(f"hyperparameter {exc}") from None
    kwargs = {k: v for k, v in hp.items() if k not in META_KEYS}
    for key in ("learning_rate", "clip_range", "clip_range_vf"):
        if key in kwargs and kwargs[key] is not None:
            kwargs[key] = _schedule(key, kwargs[key])
    if "train_freq" in kwargs and isinstance(kwargs["train_freq"], list):
        kwargs["train_freq"] = tuple(kwargs["train_freq"])
    for key in ("buffer_size", "learning_starts", "batch_size", "n_steps", "n_epochs", "gradient_steps"):
        if key in kwargs and isinstance(kwargs[key], float) and kwargs[key] == int(kwargs[key]):
            kwargs[key] = int(kwargs[key])
    kwargs["policy_kwargs"] = _policy_kwargs(kwargs.get("policy_kwargs"))
    noise = None
    if hp.get("noise_type") is not None:
        kind = str(hp["noise_type"])
        if kind not in ("normal", "ornstein-uhlenbeck"):
            raise UsageError(
                f"hyperparameter noise_type: expected normal or ornstein-uhlenbeck, got {kind!r}"
            )
        noise = (kind, float(hp.get("noise_std", 0.1)))
    return RunConfig(
        algo=algo,
        env_id=env_id,
        n_timesteps=positive_int("n_timesteps", 100_000),
        policy=str(hp.get("policy", "MlpPolicy")),
        n_envs=positive_int("n_envs", 1),
        normalize=_normalize(hp.get("normalize")),
        env_kwargs=dict(env_kwargs),
        eval_env_kwargs=dict(eval_env_kwargs),
        env_wrapper=copy.deepcopy(hp.get("env_wrapper")),
        policy_kwargs=kwargs.pop("policy_kwargs"),
        algo_kwargs=kwargs,
        noise=noise,
        hyperparams=copy.deepcopy(dict(hyperparams)),
    )


# --- environments ----------------------------------------------------------------------------------------------
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


# --- training --------------------------------------------------------------------------------------------------
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


def _validation_callback(seed0: int) -> type:
    """SB3 ``EvalCallback`` that reseeds its environment (copy i: ``seed0 + i``) before every evaluation."""
    from stable_baselines3.common.callbacks import EvalCallback

    class ValidationCallback(EvalCallback):
        def _on_step(self) -> bool:
            if self.eval_freq > 0 and self.n_calls % self.eval_freq == 0:
                self.eval_env.seed(seed0)
            return super()._on_step()

    return ValidationCallback


def _test_evaluation(
    env_id: str, model: Path, episodes: int, env_kwargs: Mapping[str, Any]
) -> dict[str, Any]:
    """:func:`evaluate` of a trained model on the first ``episodes`` test seeds, for the run record."""
    start = seeds.episode_seeds("test", episodes)[0]
    summary = evaluate(env_id, model, episodes, start, env_kwargs)["summary"]
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

    venv = make_vec_env(env_id, cfg.n_envs, seed, vec, cfg.env_kwargs, env_wrapper=cfg.env_wrapper)
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
        evaluator = None
        if eval_freq:
            # one copy per validation episode, all reseeded before every evaluation: the same episodes each time
            val0 = seeds.episode_seeds("validation", eval_episodes)[0]
            eval_vec = "native" if vec == "native" else "dummy"
            eval_venv = make_vec_env(env_id, eval_episodes, val0, eval_vec, cfg.eval_env_kwargs)
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
        record["test"] = _test_evaluation(env_id, model_path, test_episodes, cfg.eval_env_kwargs)
    record_path = sidecar(model_path, ".yml")
    record_path.write_text(yaml.safe_dump(record, sort_keys=False))
    if best_path is not None:
        best_record = {**record, "selected_at_timesteps": best_step, "selected_from": model_path.name}
        if test_episodes:
            best_record["test"] = _test_evaluation(env_id, best_path, test_episodes, cfg.eval_env_kwargs)
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


# --- evaluation ------------------------------------------------------------------------------------------------
def run_record(agent: str | Path) -> dict[str, Any]:
    """The run record ``<stem>.yml`` written next to a trained model, else the JSON sidecar of a shipped
    agent (``agents/shipped.py``), else empty."""
    import yaml

    if str(agent) in BASELINES:
        return {}
    path = sidecar(agent, ".yml")
    if path.is_file():
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


__all__ = [
    "ALGOS",
    "BASELINES",
    "EnvFactory",
    "LinearSchedule",
    "RunConfig",
    "TrainResult",
    "UsageError",
    "build_model",
    "env_short_name",
    "evaluate",
    "load_agent",
    "load_hyperparams",
    "make_env",
    "make_vec_env",
    "model_stem",
    "parse_assignments",
    "resolve_env_id",
    "run_config",
    "run_episode",
    "summarize",
    "train",
]


# --- command-line helpers shared by the scripts --------------------------------------------------------------
class OneLineParser(argparse.ArgumentParser):
    """argparse with a one-line error on stderr and exit code 2 (argparse prints the usage too)."""

    def error(self, message: str) -> None:
        print(f"{self.prog}: error: {message}", file=sys.stderr)
        raise SystemExit(2)


def int_at_least(name: str, lo: int):
    """argparse type: an integer >= lo, the message naming the option."""

    def parse(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be an integer, got {text!r}") from None
        if v < lo:
            raise argparse.ArgumentTypeError(f"{name} must be >= {lo}, got {v}")
        return v

    return parse


def positive(kind: type, name: str):
    """argparse type: a finite number > 0 of ``kind`` (int or float), the message naming the option."""

    def parse(text: str) -> Any:
        try:
            v = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name}: not a number: {text!r}") from None
        if not (math.isfinite(v) and v > 0):
            raise argparse.ArgumentTypeError(f"{name} must be > 0, got {text}")
        return v

    return parse
