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

Each job lives in its own module, and every name is importable from here as well:
:mod:`agents.config` (hyperparameter files, :class:`RunConfig`, schedules), :mod:`agents.envs` (environment
factories, vector environments), :mod:`agents.training` (:func:`train`, :func:`build_model`, callbacks),
:mod:`agents.evaluation` (:func:`load_agent`, :func:`run_episode`, :func:`summarize`, :func:`evaluate`) and
:mod:`agents.cli_util` (``KEY=VALUE`` assignments, :func:`json_safe`); the parser and argument types of
every command line are :mod:`vessel_gym.cli_args`'s.
"""

from agents.cli_util import json_safe, parse_assignments  # noqa: F401  (re-exported: one import for users)
from agents.config import (  # noqa: F401
    ACTIVATIONS,
    ALGOS,
    BASELINES,
    HYPERPARAMS_DIR,
    META_KEYS,
    NORMALIZE_KEYS,
    LinearSchedule,
    RunConfig,
    UsageError,
    check_algo,
    check_keys,
    env_short_name,
    load_hyperparams,
    merge,
    model_stem,
    registered_ids,
    resolve_env_id,
    run_config,
    sidecar,
    task_defaults,
)
from agents.envs import VEC_KINDS, EnvFactory, make_env, make_vec_env  # noqa: F401
from agents.evaluation import (  # noqa: F401
    evaluate,
    load_agent,
    load_json_sidecar,
    run_episode,
    run_record,
    summarize,
)
from agents.training import TrainResult, build_model, curriculum_callback, train  # noqa: F401

__all__ = [
    "ALGOS",
    "BASELINES",
    "EnvFactory",
    "LinearSchedule",
    "RunConfig",
    "TrainResult",
    "UsageError",
    "build_model",
    "curriculum_callback",
    "env_short_name",
    "evaluate",
    "load_agent",
    "load_hyperparams",
    "make_env",
    "make_vec_env",
    "model_stem",
    "parse_assignments",
    "resolve_env_id",
    "task_defaults",
    "run_config",
    "run_episode",
    "summarize",
    "train",
]
