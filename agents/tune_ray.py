"""Hyperparameter sweeps with Ray Tune, on this machine or on a Ray cluster.

    python agents/tune_ray.py --env ZigZag-v0 --algo ppo --samples 8 --timesteps 50000
    ray start --head                      # on the head node; `ray start --address HEAD:6379` on the others
    python agents/tune_ray.py --env ZigZag-v0 --algo ppo --samples 64 --address auto

Each trial samples a few hyperparameters of ``--algo`` (``SEARCH_SPACES``; the other keys come from the
hyperparameter file's block of ``--env``), trains SB3 for ``--timesteps`` steps with
:func:`agents.common.train` and reports the mean return of ``--eval-episodes`` episodes of the validation seed set
(``agents/seeds.py``; with the block's ``eval_env_kwargs``) as ``mean_return``. Every node needs ``pip install
"vessel-gym[rl,ray]"`` (the same Python); the ``agents`` package is shipped to the workers by the job's
``runtime_env``. The best trial's hyperparameters are written as a YAML block ready for
``agents/hyperparams/<algo>.yml``. Without ``--address`` a local Ray instance with ``--num-cpus`` CPUs
is started. Bad arguments: exit code 2 and one line on stderr.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a script: make the repository root importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from agents import seeds  # noqa: E402
from agents.common import (  # noqa: E402
    ALGOS,
    OneLineParser,
    UsageError,
    check_algo,
    evaluate,
    load_hyperparams,
    merge,
    positive,
    resolve_env_id,
    run_config,
    train,
)

AGENTS_DIR = Path(__file__).resolve().parent


def search_space(algo: str) -> dict[str, Any]:
    """The sampled hyperparameters of ``algo`` (Ray Tune distributions)."""
    from ray import tune

    common = {
        "learning_rate": tune.loguniform(1e-4, 3e-3),
        "gamma": tune.choice([0.98, 0.99, 0.995]),
    }
    spaces = {
        "ppo": {"n_steps": tune.choice([64, 128, 256]), "gae_lambda": tune.choice([0.9, 0.95, 0.98])},
        "a2c": {"n_steps": tune.choice([8, 16, 32]), "gae_lambda": tune.choice([0.9, 0.95, 1.0])},
        "sac": {"batch_size": tune.choice([128, 256]), "tau": tune.choice([0.005, 0.01, 0.02])},
        "td3": {"batch_size": tune.choice([128, 256]), "tau": tune.choice([0.005, 0.01, 0.02])},
    }
    return {**common, **spaces[check_algo(algo)]}


def trial(config: dict[str, Any]) -> None:
    """One Ray Tune trial: train with the sampled hyperparameters, evaluate, report ``mean_return``."""
    from ray import tune

    hp = dict(config["hp"])
    out = Path(tune.get_context().get_trial_dir() or ".") / "model"
    res = train(
        config["algo"],
        config["env_id"],
        config["seed"],
        timesteps=config["timesteps"],
        n_envs=config.get("n_envs"),
        out=out,
        hyperparams_file=config.get("hyperparams_file"),
        overrides=hp,
        threads=1,
    )
    # trials are compared on the validation seeds: the test seeds stay unseen until the final evaluation
    val0 = seeds.episode_seeds("validation", config["eval_episodes"])[0]
    ev = evaluate(config["env_id"], res.model_path, config["eval_episodes"], val0)
    s = ev["summary"]
    metrics = {
        "mean_return": s["return_mean"],
        "std_return": s["return_std"],
        "train_time_s": res.wall_time_s,
        "timesteps": res.n_timesteps,
    }
    for key in ("success_rate", "heading_error_deg_mean", "overshoot_deg_mean", "rate_error_pct_mean"):
        if s.get(key) is not None:
            metrics[key] = s[key]
    tune.report(metrics)


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(
        prog="tune_ray.py", description="Ray Tune hyperparameter sweep over a vessel-gym environment."
    )
    p.add_argument("--env", required=True, help="environment id, e.g. vessel_gym/ZigZag-v0 (or ZigZag-v0)")
    p.add_argument("--algo", required=True, type=str.lower, choices=sorted(ALGOS))
    p.add_argument("--samples", type=positive(int, "--samples"), default=8, help="number of trials")
    p.add_argument("--timesteps", type=positive(int, "--timesteps"), default=50_000, help="per trial")
    p.add_argument("--n-envs", type=positive(int, "--n-envs"), default=None, help="override n_envs")
    p.add_argument("--eval-episodes", type=positive(int, "--eval-episodes"), default=5)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument(
        "--hyperparams-file", default=None, help="YAML file instead of agents/hyperparams/<algo>.yml"
    )
    p.add_argument(
        "--address", default=None, help="Ray cluster address ('auto' after `ray start`); default local"
    )
    p.add_argument(
        "--num-cpus", type=positive(int, "--num-cpus"), default=None, help="local Ray: CPUs to use"
    )
    p.add_argument("--cpus-per-trial", type=positive(float, "--cpus-per-trial"), default=1.0)
    p.add_argument("--storage", default="runs/tune", help="results directory (made absolute)")
    p.add_argument("--name", default=None, help="experiment name (default <algo>_<env>)")
    return p


def sweep(
    env_id: str,
    algo: str,
    samples: int = 8,
    timesteps: int = 50_000,
    *,
    eval_episodes: int = 5,
    seed: int = 0,
    n_envs: int | None = None,
    hyperparams_file: str | None = None,
    address: str | None = None,
    num_cpus: int | None = None,
    cpus_per_trial: float = 1.0,
    storage: str | Path = "runs/tune",
    name: str | None = None,
    space: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """Run the sweep; returns ``{"best": {...hyperparameters}, "best_mean_return", "trials": [...],
    "block": the best block as YAML text}``. Connects to ``address`` or starts a local Ray instance."""
    import ray
    import yaml
    from ray import tune

    algo = check_algo(algo)
    env_id = resolve_env_id(env_id)
    base = load_hyperparams(algo, env_id, hyperparams_file)
    run_config(algo, env_id, base)  # fail early on a bad block
    space = search_space(algo) if space is None else space
    started = False
    if not ray.is_initialized():
        runtime_env = {"py_modules": [str(AGENTS_DIR)]}
        if address is None:
            ray.init(num_cpus=num_cpus, include_dashboard=False, runtime_env=runtime_env, log_to_driver=False)
        else:
            ray.init(address=address, runtime_env=runtime_env)
        started = True
    try:
        param_space = {
            "algo": algo,
            "env_id": env_id,
            "seed": seed,
            "timesteps": timesteps,
            "n_envs": n_envs,
            "eval_episodes": eval_episodes,
            "hyperparams_file": str(Path(hyperparams_file).resolve()) if hyperparams_file else None,
            "hp": space,
        }
        tuner = tune.Tuner(
            tune.with_resources(trial, {"cpu": cpus_per_trial}),
            param_space=param_space,
            tune_config=tune.TuneConfig(metric="mean_return", mode="max", num_samples=samples),
            run_config=tune.RunConfig(
                name=name or f"{algo}_{env_id.split('/')[-1]}",
                storage_path=str(Path(storage).resolve()),
                verbose=1,
            ),
        )
        grid = tuner.fit()
        trials = []
        for r in grid:
            if r.error is None and r.metrics and "mean_return" in r.metrics:
                trials.append({"hp": r.config["hp"], **{k: r.metrics[k] for k in r.metrics if k in _METRICS}})
        if not trials:
            errors = [str(r.error).splitlines()[0] for r in grid if r.error is not None]
            raise RuntimeError(f"no trial finished: {errors[:1]}")
        best = max(trials, key=lambda t: t["mean_return"])
        block = {env_id: merge(base, {**best["hp"], "n_timesteps": timesteps})}
        return {
            "best": best["hp"],
            "best_mean_return": best["mean_return"],
            "trials": sorted(trials, key=lambda t: -t["mean_return"]),
            "block": yaml.safe_dump(block, sort_keys=False),
            "path": str(Path(storage).resolve() / (name or f"{algo}_{env_id.split('/')[-1]}")),
        }
    finally:
        if started:
            ray.shutdown()


_METRICS = (
    "mean_return",
    "std_return",
    "train_time_s",
    "timesteps",
    "success_rate",
    "heading_error_deg_mean",
    "overshoot_deg_mean",
    "rate_error_pct_mean",
)


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        import ray  # noqa: F401
    except ImportError:
        print('tune_ray.py: error: Ray is not installed: pip install "vessel-gym[ray]"', file=sys.stderr)
        return 2
    try:
        result = sweep(
            args.env,
            args.algo,
            args.samples,
            args.timesteps,
            eval_episodes=args.eval_episodes,
            seed=args.seed,
            n_envs=args.n_envs,
            hyperparams_file=args.hyperparams_file,
            address=args.address,
            num_cpus=args.num_cpus,
            cpus_per_trial=args.cpus_per_trial,
            storage=args.storage,
            name=args.name,
        )
    except (UsageError, RuntimeError) as exc:
        print(f"tune_ray.py: error: {exc}", file=sys.stderr)
        return 2
    print(f"{len(result['trials'])} trials; best mean return {result['best_mean_return']:.3f}")
    for t in result["trials"]:
        hp = ", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in t["hp"].items())
        print(f"  {t['mean_return']:10.3f}  {hp}")
    best_file = Path(result["path"]) / f"best_{args.algo}.yml"
    best_file.parent.mkdir(parents=True, exist_ok=True)
    best_file.write_text(result["block"])
    print(f"best block written to {best_file}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
