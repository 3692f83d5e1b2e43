"""Hyperparameter sweeps with Ray Tune and early stopping, on this machine or on a Ray cluster.

    python agents/tune_ray.py --env ZigZag-v1 --algo ppo --samples 8 --timesteps 50000 --eval-every 10000
    ray start --head                      # on the head node; `ray start --address HEAD:6379` on the others
    python agents/tune_ray.py --env ZigZag-v1 --algo ppo --samples 64 --address auto

Each trial samples a few hyperparameters of ``--algo`` (:func:`search_space`; the other keys come from the
hyperparameter file's block of ``--env``) and trains SB3 for ``--timesteps`` steps with
:func:`agents.common.train`. Every ``--eval-every`` steps it evaluates the deterministic policy on the same
``--eval-episodes`` episodes of the VALIDATION seed set (``agents/seeds.py``; with the block's
``eval_env_kwargs``) and reports ``mean_return`` to Tune together with a checkpoint (``tune.Checkpoint``:
the model zip at that point and its run record). The ASHA scheduler (``ASHAScheduler``, asynchronous
successive halving) compares trials at the same number of evaluations and stops the worse ones early
(``--grace-period`` evaluations before any stop, ``--reduction-factor``). Trial i trains with seed
``--seed + i * n_envs``, so no two trials share a training episode, and the test seed set is never used:
it stays for the final numbers of ``results.py``. The best trial's hyperparameters are written as a YAML
block ready for ``agents/hyperparams/<algo>.yml``, with the path of its best checkpoint. Every node needs
``pip install "vessel-gym[rl,ray]"`` (the same Python); the ``agents`` package is shipped to the workers by
the job's ``runtime_env``. Without ``--address`` a local Ray instance with ``--num-cpus`` CPUs is started.
Bad arguments: exit code 2 and one line on stderr.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from agents import seeds
from agents.cli_util import RL_MODULES
from agents.common import (
    ALGOS,
    check_algo,
    evaluate,
    load_hyperparams,
    merge,
    model_stem,
    resolve_env_id,
    run_config,
    sidecar,
    train,
)
from vessel_gym.cli_args import OneLineParser, UsageError, error_line, int_in, positive, require_extra

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


def _reporter(config: dict[str, Any]) -> Any:
    """SB3 callback: every ``eval_every`` steps, evaluate on the validation seeds and ``tune.report`` the
    metrics with the model as a checkpoint."""
    import tempfile

    import yaml
    from ray import tune
    from stable_baselines3.common.callbacks import BaseCallback

    val0 = seeds.episode_seeds("validation", config["eval_episodes"])[0]

    class ReportToTune(BaseCallback):
        def __init__(self) -> None:
            super().__init__()
            self.next_eval = config["eval_every"]
            self.reported_at = -1
            self.t0 = 0.0

        def _on_training_start(self) -> None:
            import time

            self.t0 = time.perf_counter()

        def _on_step(self) -> bool:
            if self.num_timesteps >= self.next_eval:
                self.next_eval += config["eval_every"]
                self.report()
            return True

        def report(self) -> None:
            import time

            # outside the trial directory: Ray's syncer lists that directory in the background, and a
            # temporary directory deleted while it lists made the trial's results go missing
            # (tune.report persists the checkpoint before it returns)
            with tempfile.TemporaryDirectory(prefix="vessel-gym-tune-") as d:
                # load_policy reads the algorithm from the file name
                path = Path(d) / f"{model_stem(config['algo'], config['env_id'], config['seed'])}.zip"
                self.model.save(str(path))
                vn = self.model.get_vec_normalize_env()
                if vn is not None:
                    vn.save(str(sidecar(path, "_vecnormalize.pkl")))
                record = {
                    "env_id": config["env_id"],
                    "algo": config["algo"],
                    "seed": config["seed"],
                    "num_timesteps": int(self.num_timesteps),
                    "hyperparams": config["hp"],
                    "eval_env_kwargs": config["eval_env_kwargs"],
                }
                sidecar(path, ".yml").write_text(yaml.safe_dump(record, sort_keys=False))
                ev = evaluate(
                    config["env_id"], path, config["eval_episodes"], val0, config["eval_env_kwargs"]
                )
                s = ev["summary"]
                metrics = {
                    "mean_return": s["return_mean"],
                    "std_return": s["return_std"],
                    "timesteps": int(self.num_timesteps),
                    "train_time_s": time.perf_counter() - self.t0,
                    "seed": config["seed"],
                    "validation_first_seed": val0,
                }
                for key in _METRICS:
                    if s.get(key) is not None and key not in metrics:
                        metrics[key] = s[key]
                tune.report(metrics, checkpoint=tune.Checkpoint.from_directory(d))
            self.reported_at = int(self.num_timesteps)

    return ReportToTune()


def trial(config: dict[str, Any]) -> None:
    """One Ray Tune trial: train with the sampled hyperparameters and the trial's seed, reporting a
    validation evaluation and a checkpoint every ``eval_every`` steps (and at the end)."""
    from ray import tune

    work = Path(tune.get_context().get_trial_dir() or ".")
    work.mkdir(parents=True, exist_ok=True)
    reporter = _reporter(config)
    train(
        config["algo"],
        config["env_id"],
        config["seed"],
        timesteps=config["timesteps"],
        n_envs=config.get("n_envs"),
        out=work / "run",
        hyperparams_file=config.get("hyperparams_file"),
        overrides=dict(config["hp"]),
        threads=1,
        checkpoint_freq=config["timesteps"],  # Tune keeps the checkpoints; SB3's own: the end only
        callbacks=[reporter],
    )
    if reporter.reported_at < reporter.num_timesteps:  # the last steps since the last evaluation
        reporter.report()


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(
        prog="tune_ray.py", description="Ray Tune hyperparameter sweep over a vessel-gym environment."
    )
    p.add_argument("--env", required=True, help="environment id, e.g. vessel_gym/ZigZag-v1 (or ZigZag-v1)")
    p.add_argument("--algo", required=True, type=str.lower, choices=sorted(ALGOS))
    p.add_argument("--samples", type=positive(int, "--samples"), default=8, help="number of trials")
    p.add_argument("--timesteps", type=positive(int, "--timesteps"), default=50_000, help="per trial")
    p.add_argument(
        "--eval-every",
        type=positive(int, "--eval-every"),
        default=None,
        help="steps between validation evaluations (default a fifth of --timesteps)",
    )
    p.add_argument(
        "--grace-period",
        type=positive(int, "--grace-period"),
        default=1,
        help="ASHA: evaluations before a trial may be stopped (default 1)",
    )
    p.add_argument(
        "--reduction-factor",
        type=positive(float, "--reduction-factor"),
        default=2.0,
        help="ASHA: keep the best 1/factor of the trials at each rung (default 2)",
    )
    p.add_argument("--n-envs", type=positive(int, "--n-envs"), default=None, help="override n_envs")
    p.add_argument(
        "--eval-episodes",
        type=positive(int, "--eval-episodes"),
        default=10,
        help="validation episodes per evaluation (default 10)",
    )
    p.add_argument("--seed", type=int_in("--seed", 0), default=0, help="seed of trial 0")
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
    eval_every: int | None = None,
    eval_episodes: int = 10,
    seed: int = 0,
    n_envs: int | None = None,
    hyperparams_file: str | None = None,
    address: str | None = None,
    num_cpus: int | None = None,
    cpus_per_trial: float = 1.0,
    storage: str | Path = "runs/tune",
    name: str | None = None,
    space: dict[str, Any] | None = None,
    grace_period: int = 1,
    reduction_factor: float = 2.0,
) -> dict[str, Any]:
    """Run the sweep; returns ``{"best": {...hyperparameters}, "best_mean_return", "best_checkpoint",
    "trials": [...], "block": the best block as YAML text, "path"}``. A trial's score is its best
    ``mean_return`` on the validation seeds; ``trials[i]["evaluations"]`` counts its reports (fewer than
    the others' when ASHA stopped it). Connects to ``address`` or starts a local Ray instance."""
    import ray
    import yaml
    from ray import tune
    from ray.tune.schedulers import ASHAScheduler

    algo = check_algo(algo)
    env_id = resolve_env_id(env_id)
    base = load_hyperparams(algo, env_id, hyperparams_file, {"n_envs": n_envs} if n_envs else None)
    cfg = run_config(algo, env_id, base)  # fail early on a bad block
    if reduction_factor <= 1.0:
        raise UsageError(f"reduction factor must be > 1, got {reduction_factor}")
    eval_every = eval_every or max(timesteps // 5, 1)
    if eval_every > timesteps:
        raise UsageError(f"eval every {eval_every} steps is more than the {timesteps} steps of a trial")
    # trial i: copies seed + i * n_envs ... + n_envs - 1, disjoint between trials, below the validation set
    trial_seeds = [seed + i * cfg.n_envs for i in range(samples)]
    try:
        seeds.check_training_seed(trial_seeds[-1], cfg.n_envs)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    max_evals = -(-timesteps // eval_every)  # reports per finished trial (the last one at the end)
    space = search_space(algo) if space is None else space
    started = False
    if not ray.is_initialized():
        runtime_env = {"py_modules": [str(AGENTS_DIR)]}
        if address is None:
            ray.init(num_cpus=num_cpus, include_dashboard=False, runtime_env=runtime_env, log_to_driver=False)
        else:
            ray.init(address=address, runtime_env=runtime_env)
        started = True
    exp = name or f"{algo}_{env_id.split('/')[-1]}"
    try:
        param_space = {
            "algo": algo,
            "env_id": env_id,
            # one grid point per trial: each trial its own seed, its hyperparameters sampled independently
            "seed": tune.grid_search(trial_seeds),
            "timesteps": timesteps,
            "eval_every": eval_every,
            "n_envs": n_envs,
            "eval_episodes": eval_episodes,
            "eval_env_kwargs": cfg.eval_env_kwargs,
            "hyperparams_file": str(Path(hyperparams_file).resolve()) if hyperparams_file else None,
            "hp": space,
        }
        scheduler = ASHAScheduler(
            time_attr="training_iteration",  # one iteration = one validation evaluation
            max_t=max_evals,
            grace_period=min(grace_period, max_evals),
            reduction_factor=reduction_factor,
        )
        tuner = tune.Tuner(
            tune.with_resources(trial, {"cpu": cpus_per_trial}),
            param_space=param_space,
            tune_config=tune.TuneConfig(metric="mean_return", mode="max", num_samples=1, scheduler=scheduler),
            run_config=tune.RunConfig(
                name=exp,
                storage_path=str(Path(storage).resolve()),
                verbose=1,
                checkpoint_config=tune.CheckpointConfig(
                    num_to_keep=2, checkpoint_score_attribute="mean_return", checkpoint_score_order="max"
                ),
            ),
        )
        grid = tuner.fit()
        trials = []
        for r in grid:
            if r.error is not None or r.metrics_dataframe is None or "mean_return" not in r.metrics_dataframe:
                continue
            df = r.metrics_dataframe
            i = int(df["mean_return"].idxmax())
            best_ckpt = r.get_best_checkpoint("mean_return", "max")
            row = {k: _plain(df[k][i]) for k in df.columns if k in _METRICS}
            trials.append(
                {
                    "hp": r.config["hp"],
                    "seed": r.config["seed"],
                    "evaluations": len(df),
                    "stopped_early": len(df) < max_evals,
                    "checkpoint": best_ckpt.path if best_ckpt is not None else None,
                    **row,
                }
            )
        if not trials:
            errors = [str(r.error).splitlines()[0] for r in grid if r.error is not None]
            raise RuntimeError(f"no trial finished: {errors[:1]}")
        best = max(trials, key=lambda t: t["mean_return"])
        block = {env_id: merge(base, {**best["hp"], "n_timesteps": timesteps})}
        return {
            "best": best["hp"],
            "best_mean_return": best["mean_return"],
            "best_checkpoint": best["checkpoint"],
            "trials": sorted(trials, key=lambda t: -t["mean_return"]),
            "block": yaml.safe_dump(block, sort_keys=False),
            "path": str(Path(storage).resolve() / exp),
        }
    finally:
        if started:
            ray.shutdown()


def _plain(x: Any) -> Any:
    """numpy scalar -> Python scalar (for JSON and YAML)."""
    return x.item() if hasattr(x, "item") else x


_METRICS = (
    "mean_return",
    "std_return",
    "train_time_s",
    "timesteps",
    "success_rate",
    "heading_error_deg_mean",
    "overshoot_deg_mean",
    "rudder_deg_mean",
    "rudder_rate_deg_s_mean",
    "rate_error_pct_mean",
)


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        require_extra(RL_MODULES, "rl", "tuning")
    except UsageError as exc:
        error_line(f"tune_ray.py: error: {exc}")
        return 2
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
            eval_every=args.eval_every,
            eval_episodes=args.eval_episodes,
            seed=args.seed,
            n_envs=args.n_envs,
            hyperparams_file=args.hyperparams_file,
            address=args.address,
            num_cpus=args.num_cpus,
            cpus_per_trial=args.cpus_per_trial,
            storage=args.storage,
            name=args.name,
            grace_period=args.grace_period,
            reduction_factor=args.reduction_factor,
        )
    except (UsageError, RuntimeError) as exc:
        print(f"tune_ray.py: error: {exc}", file=sys.stderr)
        return 2
    print(f"{len(result['trials'])} trials; best mean return {result['best_mean_return']:.3f}")
    for t in result["trials"]:
        hp = ", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in t["hp"].items())
        stop = f"stopped after {t['evaluations']} evaluations" if t["stopped_early"] else "ran to the end"
        print(f"  {t['mean_return']:10.3f}  seed {t['seed']}, {stop}: {hp}")
    print(f"best checkpoint: {result['best_checkpoint']}")
    best_file = Path(result["path"]) / f"best_{args.algo}.yml"
    best_file.parent.mkdir(parents=True, exist_ok=True)
    best_file.write_text(result["block"])
    print(f"best block written to {best_file}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
