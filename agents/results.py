"""Train each environment x algorithm over several seeds, evaluate, plot learning curves, write the table.

    python agents/results.py                                  # everything, real budgets (hours)
    python agents/results.py --envs ZigZagRandom-v1 --algos ppo --timesteps 300000 --seeds 5
    python agents/results.py --skip-train                     # re-evaluate the saved models
    python agents/results.py --resume                         # train only the models not yet in --out

For each environment and algorithm and each training seed ``--seed .. --seed + --seeds - 1`` (default 0..4):
``train`` with the hyperparameter file's block for ``--timesteps`` environment steps (default the block's
``n_timesteps``; a step budget, so the result does not depend on how loaded the machine was), evaluating on
the fixed validation seed set every ``--eval-freq`` steps (``--eval-episodes`` episodes; these evaluations
are the learning curves), then evaluate the final model and the ``pid`` and ``scripted`` baselines on
``--episodes`` episodes of the test seed set (the same starts for every agent, never used in training or
model selection; ``agents/seeds.py``) with the block's ``eval_env_kwargs``. An algorithm's row gives the
mean and standard deviation OVER SEEDS of the per-seed test means (success rate: mean over seeds; the
median is in the JSON). Where ``BC_PLAN`` names the environment, a row of the method that starts from the
classical pilot follows (``bc``: the PPO network cloned from the pilot by DAgger, ``agents/imitation.py``;
one model per training seed too; ``--no-bc`` leaves it out). Extra evaluations (``EXTRA_EVALS``) run the
same agents on other configurations of the environment.

``--select best`` tests and ships each run's best model of the periodic validation instead of its final one.

Writes ``<out>/results.json`` (every seed's test summary too), the learning curves
``<out>/curves/<env>_<algo>.png`` (mean over seeds of the validation return and its 95 % Student-t interval
over seeds; success rate too where the task has one; and each seed against training wall-clock minutes,
with the tuned ``pid`` on the same validation episodes), the time to solve per seed (:func:`time_to_solve`),
the trajectory plots of the test episodes
``<out>/tracks/<env>_<agent>.png`` (each baseline and the first seed's agent of each algorithm), replaces each environment's block of ``--doc`` between its markers
``<!-- results:begin ENV_ID -->`` and ``<!-- results:end ENV_ID -->`` (the rest of the page, the discussion and
other environments' blocks, is kept; default
``<out>/results.md``, so that the committed ``docs/results.md`` changes only when it is named) and, with
``--ship-dir DIR``, copies every trained model with its JSON sidecar to DIR (``agents/trained`` for the shipped
agents, see ``agents/shipped.py``).
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import math
import os
import platform
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from agents import seeds
from agents.cli_util import RL_MODULES
from agents.common import (
    ALGOS,
    BASELINES,
    env_short_name,
    evaluate,
    json_safe,
    load_hyperparams,
    model_stem,
    resolve_env_id,
    run_config,
    run_record,
    train,
)
from agents.results_doc import (  # noqa: F401  (table, verdict, markers: re-exported)
    BEGIN,
    END,
    HARBOUR_GOAL,
    markdown,
    table,
    verdict,
    write_doc,
)
from vessel_gym.cli_args import OneLineParser, UsageError, int_in, positive, require_extra
from vessel_gym.envs.registration import declaration

#: the results page's experiments: algorithms trained per environment unless --algos is given (SAC only where
#: its update rate fits the budget on a 2-core machine; see docs/results.md); ZigZagRandom-v1 is the
#: course-changing comparison task (overshoot per course change, unfinished included). Its ids are the
#: default --envs
PLAN: dict[str, tuple[str, ...]] = {
    "vessel_gym/ZigZagRandom-v1": ("ppo", "sac"),
    "vessel_gym/HarbourApproach-v1": ("ppo",),
    "vessel_gym/HarbourApproach-v3": ("ppo", "sac"),
    "vessel_gym/TurningCircle-v0": ("ppo",),
    "vessel_gym/Berthing-v0": ("ppo",),
}
#: environments with a row of the method that starts from the classical pilot: behaviour cloning by DAgger
#: (agents/imitation.py, settings in agents/hyperparams/bc.yml), models in <out>/bc/, shipped to <ship-dir>/bc/
BC_PLAN = ("vessel_gym/ZigZagRandom-v1", "vessel_gym/HarbourApproach-v1", "vessel_gym/HarbourApproach-v3")
DEFAULT_ENVS = tuple(env_short_name(i) for i in PLAN)
#: further evaluations of the same agents: env id -> [(label, env kwargs)]
EXTRA_EVALS: dict[str, list[tuple[str, dict[str, Any]]]] = {
    "vessel_gym/ZigZagRandom-v1": [("IMO 10/10 schedule (ZigZag-v1's)", {"schedule": "imo"})],
    # the harbour agents train on the built-in `harbour` only: the other built-in harbours for the L7 model and
    # a generated harbour of the held-out split are layouts they never saw
    "vessel_gym/HarbourApproach-v3": [
        ("layout never trained on", {"scenario": "harbour_east"}),
        ("layout never trained on", {"scenario": "harbour_channel"}),
        ("layout never trained on", {"layout": "procedural", "layout_split": "eval", "layout_index": 0}),
    ],
}


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(prog="results.py", description="Train, evaluate and write the results table.")
    p.add_argument("--envs", nargs="+", default=list(DEFAULT_ENVS))
    p.add_argument(
        "--algos",
        nargs="+",
        type=str.lower,
        choices=[*sorted(ALGOS), "bc"],
        default=None,
        help="algorithms for every env (default: PLAN, PPO everywhere and SAC on ZigZag); bc alone: only the "
        "behaviour-cloning row of a BC_PLAN environment, in a block of its own (<env id>:bc)",
    )
    p.add_argument(
        "--timesteps",
        type=positive(int, "--timesteps"),
        default=None,
        help="environment steps per training run (default: each block's n_timesteps)",
    )
    p.add_argument(
        "--episodes",
        type=positive(int, "--episodes"),
        default=20,
        help="test episodes per agent (default 20)",
    )
    p.add_argument(
        "--seed",
        type=int_in("--seed", 0),
        default=0,
        help="first training seed; evaluation episodes use the validation/test seeds (seeds.py)",
    )
    p.add_argument(
        "--seeds", type=positive(int, "--seeds"), default=5, help="training seeds per env and algorithm"
    )
    p.add_argument(
        "--eval-episodes",
        type=positive(int, "--eval-episodes"),
        default=10,
        help="validation episodes per periodic evaluation (default 10)",
    )
    p.add_argument(
        "--ship-dir",
        metavar="DIR",
        default=None,
        help="copy every seed's final model with its JSON sidecar to DIR (default: none are copied; "
        "name agents/trained to replace the shipped agents)",
    )
    p.add_argument("--out", default="runs/results", help="models, logs and results.json")
    p.add_argument(
        "--doc",
        metavar="FILE",
        default=None,
        help="the results page to write: its tables between the markers are replaced, the rest is kept "
        "(default: <out>/results.md; name docs/results.md to update the committed page)",
    )
    p.add_argument("--skip-train", action="store_true", help="evaluate the models already in --out")
    p.add_argument(
        "--resume", action="store_true", help="train only the models not yet in --out, evaluate all"
    )
    p.add_argument(
        "--select",
        choices=("final", "best"),
        default="final",
        help="which model of each run to test and ship: the final one, or the best of the periodic "
        "validation evaluations (<stem>_best.zip; model selection on the validation seeds only)",
    )
    p.add_argument("--no-bc", action="store_true", help="no behaviour-cloning rows (BC_PLAN)")
    p.add_argument("--threads", type=positive(int, "--threads"), default=1, help="torch threads")
    p.add_argument(
        "--jobs",
        type=positive(int, "--jobs"),
        default=1,
        help="training runs at once, each in its own process (default 1; wall times: of runs sharing the CPU)",
    )
    p.add_argument(
        "--time-budget",
        type=positive(float, "--time-budget"),
        default=None,
        metavar="MIN",
        help="also stop each training run after MIN minutes of wall clock (a safety cap: the budget is in steps)",
    )
    p.add_argument(
        "--eval-freq",
        type=positive(int, "--eval-freq"),
        default=50_000,
        help="periodic evaluation on the validation seeds during training (steps; the learning curves)",
    )
    return p


# --- running ---------------------------------------------------------------------------------------------------
def _log(msg: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", flush=True)


#: two-sided 95 % Student-t quantiles t(0.975, df) for df = 1..30 (beyond: the normal 1.960)
T975 = (12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145,
        2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048,
        2.045, 2.042)  # fmt: skip


def interval95(x: Any) -> tuple[np.ndarray, np.ndarray]:
    """Mean over axis 0 and the half-width of its 95 % Student-t interval (0 for one sample)."""
    a = np.asarray(x, dtype=np.float64)
    n = a.shape[0]
    mean = np.nanmean(a, axis=0)
    if n < 2:
        return mean, np.zeros_like(mean)
    t = T975[n - 2] if n - 1 <= len(T975) else 1.960
    return mean, t * np.nanstd(a, axis=0, ddof=1) / math.sqrt(n)


def learning_curves(logs: list[Path]) -> dict[str, Any] | None:
    """The periodic validation evaluations of several seeds' runs (SB3 ``evaluations.npz``), on the
    evaluation steps the runs share: ``{"timesteps", "return": [seed][eval], "success": ... or None,
    "wall_min"/"cpu_min": [seed][eval] or None}`` (training minutes until each evaluation, from
    ``eval_times.npz`` of :mod:`agents.training`; ``None`` for runs that did not record them)."""
    from agents.training import EVAL_TIMES_FILE

    runs = []
    for d in logs:
        f = d / "evaluations.npz"
        if f.is_file():
            with np.load(f) as z:
                succ = z["successes"] if "successes" in z.files and z["successes"].size else None
                times = None
                if (d / EVAL_TIMES_FILE).is_file():
                    with np.load(d / EVAL_TIMES_FILE) as tz:
                        times = (tz["wall_s"] / 60.0, tz["cpu_s"] / 60.0)
                runs.append(
                    (z["timesteps"], z["results"].mean(axis=1), None if succ is None else succ.mean(1), times)
                )
    if not runs:
        return None
    n = min(len(r[0]) for r in runs)
    out = {
        "timesteps": [int(t) for t in runs[0][0][:n]],
        "return": [[float(v) for v in r[1][:n]] for r in runs],
        "success": None,
        "wall_min": None,
        "cpu_min": None,
    }
    if all(r[2] is not None for r in runs):
        out["success"] = [[float(v) for v in r[2][:n]] for r in runs]
    if all(r[3] is not None and len(r[3][0]) >= n for r in runs):
        out["wall_min"] = [[float(v) for v in r[3][0][:n]] for r in runs]
        out["cpu_min"] = [[float(v) for v in r[3][1][:n]] for r in runs]
    return out


#: time to solve: the validation success rate first at least this (docs/results.md)
SOLVED_SUCCESS = 0.9


def time_to_solve(curves: dict[str, Any], pid_return: float | None = None) -> list[dict[str, Any]]:
    """Per seed: the first periodic validation evaluation at which the success rate reaches
    :data:`SOLVED_SUCCESS` (and, given ``pid_return``, the first at which the validation return reaches the
    pilot's on the same episodes): its steps and the training wall and CPU minutes until then (``None``:
    never within the run)."""
    out = []
    for i in range(len(curves["return"])):
        row: dict[str, Any] = {}
        tests = []
        if curves.get("success"):
            tests.append(("success", [v >= SOLVED_SUCCESS for v in curves["success"][i]]))
        if pid_return is not None:
            tests.append(("pid_return", [v >= pid_return for v in curves["return"][i]]))
        for name, hits in tests:
            j = next((k for k, h in enumerate(hits) if h), None)
            row[name] = None
            if j is not None:
                row[name] = {"steps": curves["timesteps"][j]}
                for key in ("wall_min", "cpu_min"):
                    row[name][key] = curves[key][i][j] if curves.get(key) else None
        out.append(row)
    return out


def plot_curves(curves: dict[str, Any], path: Path, title: str, pid: dict[str, float] | None = None) -> Path:
    """PNG of the validation return (and success rate) against steps (mean over seeds and 95 % interval)
    and, where the runs recorded it, against training wall-clock minutes (one line per seed); ``pid``:
    the pilot's validation ``return``/``success`` on the same episodes as a horizontal line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = [("return", "validation return")] + (
        [("success", "validation success rate")] if curves["success"] else []
    )
    walls = curves.get("wall_min")
    nrow = 2 if walls else 1
    fig, axes = plt.subplots(nrow, len(panels), figsize=(5.5 * len(panels), 4 * nrow), squeeze=False)
    t = np.asarray(curves["timesteps"], dtype=float)
    try:
        for ax, (key, _label) in zip(axes[0], panels):
            data = np.asarray(curves[key], dtype=float)
            mean, half = interval95(data)
            for row in data:
                ax.plot(t, row, color="0.75", lw=0.6)
            ax.plot(t, mean, color="C0", lw=1.5, label=f"mean of {data.shape[0]} seeds")
            ax.fill_between(t, mean - half, mean + half, color="C0", alpha=0.25, label="95 % interval")
            ax.set_xlabel("environment steps")
        if walls:
            for ax, (key, _label) in zip(axes[1], panels):
                for i, (w, row) in enumerate(zip(walls, curves[key])):
                    ax.plot(w, row, lw=1.0, marker=".", ms=3, label=f"seed {i}")
                ax.set_xlabel("training wall-clock minutes (validation time left out)")
        for ax, (key, label) in [(a, pk) for r in axes for a, pk in zip(r, panels)]:
            if pid and pid.get(key) is not None:
                ax.axhline(pid[key], color="k", ls="--", lw=0.8, label="pid (tuned)")
            ax.set_ylabel(label)
            ax.grid(True, lw=0.3)
            ax.legend(fontsize=7)
        fig.suptitle(title, fontsize=10)
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=90, bbox_inches="tight")
    finally:
        plt.close(fig)
    return path


def aggregate(summaries: list[dict[str, Any]]) -> dict[str, Any]:
    """One table row from several seeds' test summaries: ``<metric>_mean`` / ``_std`` over seeds of the
    per-seed means; ``success_rate`` the mean over seeds (``success_rate_median`` too); outcomes summed."""
    out: dict[str, Any] = {"episodes": sum(s["episodes"] for s in summaries), "seeds": len(summaries)}
    keys = [k[:-5] for k in summaries[0] if k.endswith("_mean")]
    for k in keys:
        x = np.array([np.nan if s.get(f"{k}_mean") is None else s[f"{k}_mean"] for s in summaries], float)
        x = x[np.isfinite(x)]
        out[f"{k}_mean"] = float(np.mean(x)) if x.size else None
        out[f"{k}_std"] = float(np.std(x)) if x.size else None
    if "success_rate" in summaries[0]:
        rates = [float(s["success_rate"]) for s in summaries]
        out["success_rate"] = float(np.mean(rates))
        out["success_rate_median"] = float(np.median(rates))
        out["success_rate_per_seed"] = rates
    if "outcomes" in summaries[0]:
        counts: dict[str, int] = {}
        for s in summaries:
            for k, v in s["outcomes"].items():
                counts[k] = counts.get(k, 0) + v
        out["outcomes"] = counts
    return out


def _training(recs: list[dict[str, Any]]) -> dict[str, Any]:
    """Per-seed training facts averaged for the table (the JSON keeps every seed's)."""

    def mean(key: str) -> float | None:
        v = [r[key] for r in recs if r.get(key) is not None]
        return float(np.mean(v)) if v else None

    return {
        "selected_at_timesteps": mean("selected_at_timesteps"),
        "num_timesteps": mean("num_timesteps"),
        "train_time_s": mean("train_time_s"),
        "cpu_time_s": mean("cpu_time_s"),
        "budget_hit": any(r.get("budget_hit") for r in recs),
        "n_envs": recs[0].get("n_envs"),
        "seeds": len(recs),
    }


def _test_eval(
    env_id: str,
    agent: str | Path,
    episodes: int,
    seed: int,
    kw: dict[str, Any],
    plots: Path | None,
    tracks: dict[str, str],
) -> dict[str, Any]:
    """Test-set evaluation; with ``plots``, the trajectory plot of its episodes goes to
    ``plots/tracks/<env>_<agent>.png`` and its path into ``tracks``."""
    from agents.visual import Recorder, plot_trajectories

    if plots is None:
        return evaluate(env_id, agent, episodes, seed, kw)
    rec: list[Any] = []

    def wrap(env: Any) -> Any:
        rec.append(Recorder(env))
        return rec[-1]

    ev = evaluate(env_id, agent, episodes, seed, kw, wrap=wrap)
    name = Path(agent).stem
    png = plots / "tracks" / f"{env_short_name(env_id)}_{name}.png"
    title = f"{name} on {env_id}: test episodes"
    tracks[f"{env_id}:{name}"] = str(plot_trajectories(rec[0].tracks, rec[0], png, title))
    return ev


#: table row names of methods that are not a plain SB3 algorithm
ROW_NAMES = {"bc": "bc (PPO network, DAgger from the pilot)"}


def _cloned(env_id: str, train_seeds: list[int], out: Path, args: argparse.Namespace) -> list[Path]:
    """The behaviour-cloning models of ``env_id`` for each training seed (cloned unless they exist and
    --skip-train or --resume says so)."""
    from agents.imitation import clone

    paths = []
    for seed in train_seeds:
        path = out / f"{model_stem('ppo', env_id, seed)}.zip"
        if not args.skip_train and not (args.resume and path.is_file()):
            _log(f"behaviour cloning on {env_id}, seed {seed}")
            res = clone(env_id, seed, out=out, threads=args.threads)
            _log(f"  {res.n_timesteps} steps in {res.wall_time_s / 60:.1f} min -> {res.model_path}")
        if not path.is_file():
            raise UsageError(f"no model {path} (train first, without --skip-train)")
        paths.append(path)
    return paths


def _pid_validation(env_id: str, episodes: int, kw: dict[str, Any]) -> dict[str, Any]:
    """The tuned pilot on the validation episodes of the learning curves: mean ``return`` and ``success``
    rate (``None`` where the task has none), the reference line of the curves and of the time to solve."""
    pilots = declaration(env_id).pilots
    pilot = "pid" if "pid" in pilots else next(a for a in BASELINES if a in pilots)  # a task without a PID
    ev = evaluate(env_id, pilot, episodes, seeds.VALIDATION_START, kw)["summary"]
    return {"return": ev["return_mean"], "success": ev.get("success_rate")}


def _algos(args: argparse.Namespace, env_id: str) -> list[str]:
    """The trained algorithms of ``env_id`` in this run (``bc`` rows are made by :func:`_cloned`)."""
    return [a for a in (args.algos or PLAN.get(env_id, ("ppo",))) if a != "bc"]


def _train_options(args: argparse.Namespace, steps: int) -> dict[str, Any]:
    """The keyword arguments of :func:`train` for one run of the plan."""
    return {
        "timesteps": steps,
        "out": Path(args.out),
        "threads": args.threads,
        "eval_freq": min(args.eval_freq, steps),
        "eval_episodes": args.eval_episodes,
        "time_budget_s": args.time_budget * 60.0 if args.time_budget else None,
    }


def _trained(res: Any, path: Path, args: argparse.Namespace) -> None:
    _log(f"  {res.n_timesteps} steps in {res.wall_time_s / 60:.1f} min -> {res.model_path}")
    if args.select == "final":  # no stale "best" of an earlier run next to the final model
        path.with_name(path.stem + "_best.zip").unlink(missing_ok=True)
        path.with_name(path.stem + "_best.yml").unlink(missing_ok=True)


def _train_in_parallel(args: argparse.Namespace, runs: list[tuple[str, str, int, Path, int]]) -> set[Path]:
    """``--jobs``: the training runs ``(algo, env id, seed, model path, steps)`` in ``args.jobs`` worker
    processes (spawned: each imports torch and the kernels afresh); the model paths trained."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    done: set[Path] = set()
    with ProcessPoolExecutor(args.jobs, mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = {}
        for algo, env_id, seed, path, steps in runs:
            _log(f"train {algo} on {env_id}, seed {seed} ({steps} steps; {args.jobs} at once)")
            futures[pool.submit(train, algo, env_id, seed, **_train_options(args, steps))] = path
        for fut in as_completed(futures):
            _trained(fut.result(), futures[fut], args)
            done.add(futures[fut])
    return done


def run(args: argparse.Namespace, argv: list[str]) -> dict[str, Any]:
    import stable_baselines3 as sb3
    import torch

    from agents import shipped

    torch.set_num_threads(args.threads)
    out = Path(args.out)
    envs = [resolve_env_id(e) for e in args.envs]
    train_seeds = list(range(args.seed, args.seed + args.seeds))
    load_start = os.getloadavg()[0]
    eval_seed = seeds.episode_seeds("test", args.episodes)[0]  # never seen in training or model selection
    sections, curves_out, shipped_files = [], {}, []
    trained_now: set[Path] = set()
    if args.jobs > 1 and not args.skip_train:
        runs = []
        for env_id in envs:
            for algo in _algos(args, env_id):
                steps = args.timesteps or run_config(algo, env_id, load_hyperparams(algo, env_id)).n_timesteps
                for seed in train_seeds:
                    path = out / f"{model_stem(algo, env_id, seed)}.zip"
                    if not (args.resume and path.is_file()):
                        runs.append((algo, env_id, seed, path, steps))
        trained_now = _train_in_parallel(args, runs)
    tracks: dict[str, str] = {}
    for env_id in envs:
        trained: list[tuple[str, list[Path]]] = []
        eval_kwargs: dict[str, Any] | None = None
        pid_val: dict[str, Any] | None = None
        solved: dict[str, list[dict[str, Any]]] = {}
        algos = _algos(args, env_id)
        bc_only = not algos  # --algos bc: the behaviour-cloning row alone, in a block of its own
        if bc_only and (env_id not in BC_PLAN or args.no_bc):
            raise UsageError(
                f"--algos bc: {env_id} has no behaviour-cloning row (BC_PLAN: {', '.join(BC_PLAN)})"
            )
        if bc_only:
            eval_kwargs = run_config("ppo", env_id, load_hyperparams("ppo", env_id)).eval_env_kwargs
        for algo in algos:
            cfg = run_config(algo, env_id, load_hyperparams(algo, env_id))
            if eval_kwargs is None:
                eval_kwargs = cfg.eval_env_kwargs
            elif cfg.eval_env_kwargs != eval_kwargs:
                raise UsageError(f"{env_id}: the algorithms' eval_env_kwargs differ; the table needs one")
            paths = []
            for seed in train_seeds:
                path = out / f"{model_stem(algo, env_id, seed)}.zip"
                fresh = path in trained_now
                if not args.skip_train and not fresh and not (args.resume and path.is_file()):
                    steps = args.timesteps or cfg.n_timesteps
                    _log(f"train {algo} on {env_id}, seed {seed} ({steps} steps)")
                    _trained(train(algo, env_id, seed, **_train_options(args, steps)), path, args)
                if not path.is_file():
                    raise UsageError(f"no model {path} (train first, without --skip-train)")
                if args.select == "best":
                    path = path.with_name(path.stem + "_best.zip")
                    if not path.is_file():
                        raise UsageError(f"no model {path} (--select best needs the periodic evaluations)")
                paths.append(path)
            trained.append((algo, paths))
            curves = learning_curves([out / "logs" / model_stem(algo, env_id, s) for s in train_seeds])
            if curves is not None:
                if pid_val is None:
                    pid_val = _pid_validation(env_id, args.eval_episodes, eval_kwargs or {})
                png = out / "curves" / f"{env_short_name(env_id)}_{algo}.png"
                title = f"{algo} on {env_id}: validation episodes, {len(paths)} seeds"
                solve = time_to_solve(curves, pid_val["return"])
                curves_out[f"{env_id}:{algo}"] = {
                    **curves,
                    "png": str(plot_curves(curves, png, title, pid_val)),
                    "pid_validation": pid_val,
                    "time_to_solve": solve,
                }
                solved[algo] = solve
        if env_id in BC_PLAN and not args.no_bc:
            trained.append(("bc", _cloned(env_id, train_seeds, out / "bc", args)))
        configs = [("training configuration", eval_kwargs or {}, True)]
        configs += [(label, kw, False) for label, kw in EXTRA_EVALS.get(env_id, []) if kw != eval_kwargs]
        for label, kw, main in configs:
            rows = []

            for agent in (a for a in BASELINES if a in declaration(env_id).pilots):  # the pilots it declares
                _log(f"evaluate {agent} on {env_id} {kw}")
                ev = _test_eval(env_id, agent, args.episodes, eval_seed, kw, out if main else None, tracks)
                rows.append(
                    {"agent": agent, "summary": ev["summary"], "episodes": ev["episodes"], "training": None}
                )
            for algo, paths in trained:
                per_seed = []
                for p in paths:
                    _log(f"evaluate {p.name} on {env_id} {kw}")
                    plots = out if main and p == paths[0] else None  # tracks: the first seed's agent
                    ev = _test_eval(env_id, p, args.episodes, eval_seed, kw, plots, tracks)
                    rec = run_record(p)
                    per_seed.append(
                        {
                            "path": str(p),
                            "seed": rec.get("seed"),
                            "selected_at_timesteps": rec.get("selected_at_timesteps"),
                            "summary": ev["summary"],
                            "record": rec,
                        }
                    )
                    if main and args.ship_dir is not None:
                        meta = shipped.make_sidecar(
                            {**rec, "test": json_safe(ev["summary"])}, args.eval_episodes, args.episodes
                        )
                        meta["test_episodes"] = json_safe(ev["episodes"])  # per episode, for re-checks
                        dest = Path(args.ship_dir) / ("bc" if algo == "bc" else "")
                        shipped_files.append(str(shipped.ship(p, meta, dest)))
                rows.append(
                    {
                        "algo": algo,
                        "time_to_solve": solved.get(algo) if main else None,
                        "agent": f"{ROW_NAMES.get(algo, algo)} ({len(paths)} seeds)",
                        "summary": aggregate([r["summary"] for r in per_seed]),
                        "training": _training([r["record"] for r in per_seed]),
                        "per_seed": [{k: v for k, v in r.items() if k != "record"} for r in per_seed],
                    }
                )
            sections.append(
                {
                    "env_id": env_id,
                    # the page's block: the environment's, or its own for the cloning row alone
                    "block": f"{env_id}:bc" if bc_only else env_id,
                    "label": label,
                    "env_kwargs": kw,
                    "main": main,
                    # the table's columns follow the task's module (results_doc: zigzag, harbour, turning)
                    "kind": declaration(env_id).module.rsplit(".", 1)[-1],
                    "rows": rows,
                }
            )
    return {
        "argv": argv,
        "date": dt.date.today().isoformat(),
        "timesteps": args.timesteps,
        "select": args.select,
        "seeds": args.seeds,
        "training_seeds": train_seeds,
        "episodes": args.episodes,
        "eval_seed": eval_seed,
        "validation": {
            "episodes": args.eval_episodes,
            "every_steps": args.eval_freq,
            "first_seed": seeds.VALIDATION_START,
        },
        "machine": {
            "cpu_count": os.cpu_count(),
            "python": platform.python_version(),
            "torch": torch.__version__,
            "torch_threads": torch.get_num_threads(),
            "sb3": sb3.__version__,
            "load_start": load_start,
            "load_end": os.getloadavg()[0],
        },
        "curves": curves_out,
        "tracks": tracks,
        "shipped": shipped_files,
        "sections": sections,
    }


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    args = build_parser().parse_args(argv)
    try:
        require_extra(RL_MODULES, "rl", "training")
        results = run(args, argv)
    except UsageError as exc:
        print(f"results.py: error: {exc}", file=sys.stderr)
        return 2
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "results.json").write_text(json.dumps(json_safe(results), indent=1))
    doc = Path(args.doc) if args.doc is not None else out / "results.md"
    write_doc(doc, markdown(results))
    _log(f"wrote {out / 'results.json'} and {doc}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
