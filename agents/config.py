"""Hyperparameters of the agent scripts: names of ids and algorithms, the hyperparameter files
(``agents/hyperparams/<algo>.yml``), schedules and the checked :class:`RunConfig` of a run.

Errors in user input raise :class:`UsageError`; the command lines turn it into exit code 2 with one line
on stderr.
"""

from __future__ import annotations

import copy
import inspect
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from vessel_gym.cli_args import UsageError  # bad input: an unknown id, algorithm or key, a value out of range

HYPERPARAMS_DIR = Path(__file__).resolve().parent / "hyperparams"
ALGOS: dict[str, str] = {"ppo": "PPO", "sac": "SAC", "td3": "TD3", "a2c": "A2C"}
#: the baselines every results table carries (every pilot name `--agent` takes: vessel_gym.policy.BASELINES)
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
    "action_filter",
    "noise_type",
    "noise_std",
    "curriculum",
)
#: keys of a ``curriculum`` block (agents.training.curriculum_callback)
CURRICULUM_KEYS = ("levels", "promote_at", "window", "final_by")
NORMALIZE_KEYS = ("norm_obs", "norm_reward", "clip_obs", "clip_reward", "gamma", "epsilon")
ACTIVATIONS = ("tanh", "relu", "elu", "leaky_relu", "gelu", "silu")


# --- names -----------------------------------------------------------------------------------------------------
def registered_ids() -> list[str]:
    """The registered task ids (from the task declarations: the built-in ones and any task imported)."""
    from vessel_gym.envs.registration import known_ids

    return known_ids()


def resolve_env_id(name: str) -> str:
    """Full env id from ``vessel_gym/ZigZag-v1`` or the short ``ZigZag-v1``."""
    ids = registered_ids()
    if name in ids:
        return name
    if f"vessel_gym/{name}" in ids:
        return f"vessel_gym/{name}"
    raise UsageError(f"unknown environment {name!r} (have: {', '.join(ids)})")


def env_short_name(env_id: str) -> str:
    """``vessel_gym/ZigZag-v1`` -> ``ZigZag-v1`` (used in file names)."""
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
#: what every task trains with unless its declaration says otherwise (its ``train`` blocks merge over this):
#: 16 ships in one native vector env, rewards normalised (the tasks' terms have different scales), observations
#: as the task scales them, a 1M-step budget (2-3 CPU-minutes of PPO on this size of machine, docs/agents.md)
TRAIN_DEFAULTS: dict[str, Any] = {
    "n_timesteps": 1_000_000,
    "policy": "MlpPolicy",
    "n_envs": 16,
    "normalize": {"norm_obs": False, "norm_reward": True},
}


def task_defaults(algo: str, env_id: str) -> dict[str, Any]:
    """The training hyperparameters of ``env_id``: :data:`TRAIN_DEFAULTS`, then what its task declares
    (``train`` of its ``register_task``: the ``common`` block, then the block of ``algo``)."""
    from vessel_gym.envs.registration import declaration

    try:
        train = declaration(env_id).train
    except KeyError as exc:
        raise UsageError(str(exc.args[0])) from None
    return merge(merge(TRAIN_DEFAULTS, train.get("common", {})), train.get(check_algo(algo), {}))


def load_hyperparams(
    algo: str,
    env_id: str,
    path: str | Path | None = None,
    overrides: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """The hyperparameters of ``env_id``: its task's defaults (:func:`task_defaults`), the block of ``env_id``
    in ``path`` (default ``agents/hyperparams/<algo>.yml``; an id without a block trains on the defaults) merged
    over them, then ``overrides``."""
    import yaml

    algo = check_algo(algo)
    defaults = task_defaults(algo, env_id)
    file = Path(path) if path is not None else HYPERPARAMS_DIR / f"{algo}.yml"
    if path is None and not file.is_file():
        return merge(defaults, overrides or {})
    try:
        data = yaml.safe_load(file.read_text())
    except OSError as exc:
        raise UsageError(f"cannot read hyperparameters {file}: {exc.strerror or exc}") from None
    except yaml.YAMLError as exc:
        raise UsageError(f"{file}: not valid YAML ({str(exc).splitlines()[0]})") from None
    if not isinstance(data, dict):
        raise UsageError(f"{file}: expected a mapping of env id -> hyperparameters")
    block = data.get(env_id, data.get(env_short_name(env_id), {}))
    if not isinstance(block, dict):
        raise UsageError(f"{file}: the block of {env_id} is not a mapping")
    return merge(merge(defaults, block), overrides or {})


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


def check_keys(what: str, block: Any, allowed: Iterable[str], expected: str = "a mapping") -> None:
    """A settings block (``what``: where it stands, for the message) that must be a mapping of ``allowed``
    keys only; anything else is a one-line UsageError naming it, the keys it got wrong and those allowed."""
    if not isinstance(block, Mapping):
        raise UsageError(f"{what}: expected {expected}, got {block!r}")
    allowed = list(allowed)
    bad = sorted(str(key) for key in set(block) - set(allowed))
    if bad:
        raise UsageError(f"{what}: unknown key(s) {', '.join(bad)} (allowed: {', '.join(allowed)})")


def _normalize(value: Any) -> dict[str, Any] | None:
    if value in (None, False):
        return None
    if value is True:
        return {"norm_obs": True, "norm_reward": True}
    check_keys("hyperparameter normalize", value, NORMALIZE_KEYS, "true/false or a mapping")
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
    action_filter: Any  # wrappers of agents.wrappers applied in training and evaluation (run record, sidecar)
    curriculum: dict[str, Any] | None  # see _curriculum: difficulty levels of the training episodes
    policy_kwargs: dict[str, Any]
    algo_kwargs: dict[str, Any]
    noise: tuple[str, float] | None
    hyperparams: dict[str, Any] = field(default_factory=dict)  # the block as written (for the run record)


def _curriculum(block: Any) -> dict[str, Any] | None:
    """The ``curriculum`` key checked: ``levels`` (the training episodes' ``difficulty``, easiest first,
    at least two), ``promote_at`` (success rate over the last ``window`` finished training episodes that moves
    to the next level, in (0, 1]) and ``final_by`` (fraction of ``n_timesteps`` by which the last level is
    reached whatever the success: level k at the latest at k / (len(levels) - 1) x final_by)."""
    if block is None:
        return None
    check_keys("hyperparameter curriculum", block, CURRICULUM_KEYS)
    levels = block.get("levels")
    if not isinstance(levels, list) or len(levels) < 2 or not all(isinstance(v, (int, str)) for v in levels):
        raise UsageError(
            f"hyperparameter curriculum.levels: expected a list of at least two levels, got {levels!r}"
        )
    out: dict[str, Any] = {"levels": list(levels)}
    for key, default, lo, hi in (("promote_at", 0.8, 0.0, 1.0), ("final_by", 0.5, 0.0, 1.0)):
        v = block.get(key, default)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not lo < float(v) <= hi:
            raise UsageError(
                f"hyperparameter curriculum.{key}: expected a number in ({lo:g}, {hi:g}], got {v!r}"
            )
        out[key] = float(v)
    w = block.get("window", 100)
    if isinstance(w, bool) or not isinstance(w, int) or w < 1:
        raise UsageError(f"hyperparameter curriculum.window: expected a positive integer, got {w!r}")
    out["window"] = w
    return out


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
        wrappers.resolve(hp.get("action_filter"))
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
        action_filter=copy.deepcopy(hp.get("action_filter")),
        curriculum=_curriculum(hp.get("curriculum")),
        policy_kwargs=kwargs.pop("policy_kwargs"),
        algo_kwargs=kwargs,
        noise=noise,
        hyperparams=copy.deepcopy(dict(hyperparams)),
    )
