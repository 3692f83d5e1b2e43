"""Train a Stable-Baselines3 agent on a vessel-gym environment.

    python agents/train.py --env vessel_gym/ZigZag-v1 --algo ppo --seed 0
    python agents/train.py --env ZigZag-v1 --algo sac --seed 1 --timesteps 50000 --n-envs 4 --vec dummy
    python agents/train.py --env HarbourApproach-v2 --algo ppo --seed 0 --timesteps 200000 \
        --eval-freq 20000 --eval-episodes 10 --test-episodes 20 --log-format csv tensorboard

The budget is a number of environment steps (``--timesteps``, all copies together), so a run does the same
work on a loaded machine as on an idle one. The copies are the ships of the environment's native vector
version (``--vec native``, the default) or single environments (``--vec dummy|subproc``). ``--eval-freq``
evaluates on the fixed validation seed set and keeps the best model; ``--test-episodes`` evaluates the final
(and best) model on the test seed set afterwards (``agents/seeds.py`` defines both sets).
Hyperparameters come from ``agents/hyperparams/<algo>.yml`` (the block of the env id); ``--timesteps`` and
``--n-envs`` override its ``n_timesteps``/``n_envs``, ``--hyperparams KEY=VALUE`` any key (YAML values,
dotted keys for nested ones: ``policy_kwargs.net_arch=[32,32]``, ``env_kwargs.schedule=imo``).
Writes ``<out>/<algo>_<env>_s<seed>.zip`` (loadable by ``evaluate.py``, ``vessel_gym.policy.load_policy``
and ``vessel-gym serve --agent``), its run record ``.yml``, the SB3 CSV log under ``<out>/logs/`` and
checkpoints under ``<out>/checkpoints/``. Bad arguments: exit code 2 and one line on stderr.
"""

from __future__ import annotations

import argparse
import math

from agents.cli_util import RL_MODULES
from agents.common import (
    ALGOS,
    VEC_KINDS,
    parse_assignments,
    resolve_env_id,
    train,
)
from vessel_gym.cli_args import OneLineParser, UsageError, error_line, int_in, require_extra


def _minutes(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--time-budget must be a number of minutes, got {text!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"--time-budget must be > 0 minutes, got {text}")
    return v


def build_parser(prog: str = "train.py") -> argparse.ArgumentParser:
    p = OneLineParser(prog=prog, description="Train an SB3 agent on a vessel-gym environment.")
    p.add_argument("--env", required=True, help="environment id, e.g. vessel_gym/ZigZag-v1 (or ZigZag-v1)")
    p.add_argument("--algo", required=True, type=str.lower, choices=sorted(ALGOS))
    p.add_argument("--seed", type=int_in("--seed", 0), default=0)
    p.add_argument("--timesteps", type=int_in("--timesteps", 1), default=None, help="override n_timesteps")
    p.add_argument("--n-envs", type=int_in("--n-envs", 1), default=None, help="override n_envs")
    p.add_argument(
        "--vec",
        choices=VEC_KINDS,
        default="native",
        help="native: all copies in one batched simulation (default); dummy/subproc: SB3's vector envs",
    )
    p.add_argument("--out", default="runs", help="output directory (default runs/)")
    p.add_argument(
        "--hyperparams-file", default=None, help="YAML file instead of agents/hyperparams/<algo>.yml"
    )
    p.add_argument("--hyperparams", nargs="+", metavar="KEY=VALUE", default=None, help="override keys")
    p.add_argument(
        "--log-format",
        nargs="+",
        choices=("stdout", "csv", "json", "log", "tensorboard"),
        default=["csv", "stdout"],
        help="SB3 logger outputs (default csv stdout)",
    )
    p.add_argument("--checkpoint-freq", type=int_in("--checkpoint-freq", 1), default=None, help="steps")
    p.add_argument(
        "--time-budget",
        type=_minutes,
        default=None,
        metavar="MIN",
        help="also stop after MIN minutes of wall clock (a safety cap; compare runs by --timesteps)",
    )
    p.add_argument(
        "--eval-freq",
        type=int_in("--eval-freq", 1),
        default=None,
        help="evaluate every STEPS steps on the validation seeds and keep the best model as <stem>_best.zip",
    )
    p.add_argument(
        "--eval-episodes",
        type=int_in("--eval-episodes", 1),
        default=10,
        help="validation episodes per periodic evaluation (default 10)",
    )
    p.add_argument(
        "--test-episodes",
        type=int_in("--test-episodes", 0),
        default=20,
        help="episodes of the test seed set for the final evaluation (default 20; 0: none)",
    )
    p.add_argument("--threads", type=int_in("--threads", 1), default=1, help="torch threads (default 1)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    return p


def main(argv: list[str] | None = None, prog: str = "train.py") -> int:
    """The command line (``vessel-gym train`` and ``python agents/train.py``); returns the exit code."""
    parser = build_parser(prog)
    args = parser.parse_args(argv)
    try:
        require_extra(RL_MODULES, "rl", "training")  # before any work: one line naming the extra
        env_id = resolve_env_id(args.env)
        result = train(
            args.algo,
            env_id,
            args.seed,
            timesteps=args.timesteps,
            n_envs=args.n_envs,
            vec=args.vec,
            out=args.out,
            hyperparams_file=args.hyperparams_file,
            overrides=parse_assignments(args.hyperparams, "--hyperparams"),
            log_formats=args.log_format,
            checkpoint_freq=args.checkpoint_freq,
            progress_bar=not args.no_progress,
            threads=args.threads,
            time_budget_s=None if args.time_budget is None else 60.0 * args.time_budget,
            eval_freq=args.eval_freq,
            eval_episodes=args.eval_episodes,
            test_episodes=args.test_episodes,
        )
    except UsageError as exc:
        error_line(f"{parser.prog}: error: {exc}")
        return 2
    evaluate_command = "vessel-gym evaluate" if prog.startswith("vessel-gym") else "python agents/evaluate.py"
    if result.best_model_path is not None:
        print(f"best model of the periodic evaluations: {result.best_model_path}")
    for label, test in result.test.items():
        rate = f", success rate {100.0 * test['success_rate']:.0f} %" if "success_rate" in test else ""
        print(
            f"test ({label} model, {test['episodes']} episodes, seeds {test['seeds']}): "
            f"mean return {test['return_mean']:.3f} +- {test['return_std']:.3f}{rate}"
        )
    print(
        f"saved {result.model_path} ({result.n_timesteps} steps in {result.wall_time_s:.1f} s); "
        f"evaluate: {evaluate_command} --env {env_id} --agent {result.model_path}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
