"""Train agents for a budget of environment steps, evaluate them and the baselines, write ``docs/results.md``.

    python agents/results.py                                  # everything (the blocks' n_timesteps: hours)
    python agents/results.py --envs ZigZag-v0 --algos ppo --timesteps 300000
    python agents/results.py --skip-train                     # re-evaluate the saved models

For each environment and algorithm: ``train`` with the hyperparameter file's block for ``--timesteps``
environment steps (default the block's ``n_timesteps``; a step budget, so the result does not depend on how
loaded the machine was), with a periodic evaluation on the validation seeds, then ``evaluate`` the model and
the ``pid`` and ``scripted`` baselines over ``--episodes`` episodes of the test seed set (the same starts for
every agent, never used in training or model selection; ``agents/seeds.py``) with the block's
``eval_env_kwargs``. Extra evaluations (``EXTRA_EVALS``) run the same agents on other
configurations of the environment. Everything goes to ``<out>/results.json``; the tables replace the part
of ``--doc`` between the markers ``<!-- results:begin -->`` and ``<!-- results:end -->`` (the rest of the
page, the discussion, is kept).
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

if __package__ in (None, ""):  # run as a script: make the repository root importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from agents import seeds  # noqa: E402
from agents.common import (  # noqa: E402
    ALGOS,
    BASELINES,
    OneLineParser,
    UsageError,
    env_short_name,
    evaluate,
    json_safe,
    load_hyperparams,
    model_stem,
    positive,
    resolve_env_id,
    run_config,
    run_record,
    train,
)

DEFAULT_ENVS = ("ZigZag-v0", "HarbourApproach-v0", "TurningCircle-v0")
#: algorithms trained per environment unless --algos is given (SAC only where its update rate fits the
#: budget on a 2-core machine; see docs/results.md)
PLAN: dict[str, tuple[str, ...]] = {
    "vessel_gym/ZigZag-v0": ("ppo", "sac"),
    "vessel_gym/HarbourApproach-v0": ("ppo",),
    "vessel_gym/TurningCircle-v0": ("ppo",),
}
#: further evaluations of the same agents: env id -> [(label, env kwargs)]
EXTRA_EVALS: dict[str, list[tuple[str, dict[str, Any]]]] = {
    "vessel_gym/ZigZag-v0": [("IMO 10/10 schedule (registered default)", {})],
}
BEGIN, END = "<!-- results:begin -->", "<!-- results:end -->"
REPO = Path(__file__).resolve().parents[1]


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(prog="results.py", description="Train, evaluate and write the results table.")
    p.add_argument("--envs", nargs="+", default=list(DEFAULT_ENVS))
    p.add_argument(
        "--algos",
        nargs="+",
        type=str.lower,
        choices=sorted(ALGOS),
        default=None,
        help="algorithms for every env (default: PLAN, PPO everywhere and SAC on ZigZag)",
    )
    p.add_argument(
        "--timesteps",
        type=positive(int, "--timesteps"),
        default=None,
        help="environment steps per training run (default: each block's n_timesteps)",
    )
    p.add_argument("--episodes", type=positive(int, "--episodes"), default=20)
    p.add_argument(
        "--seed", type=int, default=0, help="training seed; evaluation episodes use the test seeds (seeds.py)"
    )
    p.add_argument("--out", default="runs/results", help="models, logs and results.json")
    p.add_argument("--doc", default=str(REPO / "docs" / "results.md"))
    p.add_argument("--skip-train", action="store_true", help="evaluate the models already in --out")
    p.add_argument("--threads", type=positive(int, "--threads"), default=1, help="torch threads")
    p.add_argument(
        "--eval-freq",
        type=positive(int, "--eval-freq"),
        default=50_000,
        help="periodic evaluation during training (steps); the best model is evaluated too",
    )
    return p


# --- formatting ------------------------------------------------------------------------------------------------
def _num(x: float | None, fmt: str = ".1f") -> str:
    return "—" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, fmt)


def _pm(s: dict[str, Any], key: str, fmt: str = ".1f") -> str:
    m, d = s.get(f"{key}_mean"), s.get(f"{key}_std")
    return "—" if m is None else f"{format(m, fmt)} ± {format(d, fmt)}"


def _agent_cells(row: dict[str, Any]) -> list[str]:
    tr = row.get("training")
    if tr is None:
        return [row["agent"], "—", "—"]
    steps = f"{tr['num_timesteps'] / 1000:.0f}k" + (" (budget)" if tr.get("budget_hit") else "")
    if tr.get("selected_at_timesteps") is not None:
        steps = f"best at {tr['selected_at_timesteps'] / 1000:.0f}k of {steps}"
    return [row["agent"], steps, f"{tr['train_time_s'] / 60:.1f} ({tr['cpu_time_s'] / 60:.1f})"]


def table(kind: str, rows: list[dict[str, Any]]) -> str:
    """Markdown table of evaluated agents of one environment configuration."""
    head = ["agent", "train steps", "train wall (CPU) min", "return"]
    if kind == "zigzag":
        head += ["mean \\|heading error\\| deg", "overshoot / course change deg", "max overshoot deg"]
        head += ["targets reached %"]
    elif kind == "harbour":
        head += ["success %", "outcomes", "min clearance m", "time s"]
    elif kind == "turning":
        head += ["mean \\|rate error\\| %"]
    head += ["mean \\|rudder\\| deg", "rudder rate deg/s"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for row in rows:
        s = row["summary"]
        cells = _agent_cells(row) + [_pm(s, "return")]
        if kind == "zigzag":
            cells += [
                _pm(s, "heading_error_deg"),
                _pm(s, "overshoot_deg", ".2f"),
                _pm(s, "max_overshoot_deg", ".1f"),
                _pm(s, "reached_pct", ".0f"),
            ]
        elif kind == "harbour":
            outcomes = ", ".join(f"{k} {v}" for k, v in sorted(s.get("outcomes", {}).items()))
            cells += [
                _num(100.0 * s["success_rate"], ".0f"),
                outcomes,
                _pm(s, "min_clearance_m"),
                _pm(s, "time_s", ".0f"),
            ]
        elif kind == "turning":
            cells += [_pm(s, "rate_error_pct")]
        cells += [_pm(s, "rudder_deg"), _pm(s, "rudder_rate_deg_s", ".2f")]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def verdict(kind: str, rows: list[dict[str, Any]]) -> str:
    """One sentence: does the best trained agent beat the PID baseline by the goal's criterion?"""
    pid = next((r for r in rows if r["agent"] == "pid"), None)
    rl = [r for r in rows if r.get("training") is not None]
    if pid is None or not rl:
        return ""
    P = pid["summary"]
    if kind == "zigzag":
        parts, wins = [], []
        for r in rl:
            S = r["summary"]
            he = S["heading_error_deg_mean"] < P["heading_error_deg_mean"]
            os_ok = S["overshoot_deg_mean"] <= P["overshoot_deg_mean"]
            rud = S["rudder_deg_mean"] / max(P["rudder_deg_mean"], 1e-9)
            rate = S["rudder_rate_deg_s_mean"] / max(P["rudder_rate_deg_s_mean"], 1e-9)
            if he and os_ok and rud <= 1.5 and rate <= 1.5:
                wins.append(r["agent"])
            parts.append(
                f"`{r['agent']}`: heading error {S['heading_error_deg_mean']:.1f} vs "
                f"{P['heading_error_deg_mean']:.1f} deg ({'lower' if he else 'not lower'}), overshoot per course "
                f"change {S['overshoot_deg_mean']:.2f} vs {P['overshoot_deg_mean']:.2f} deg "
                f"({'not larger' if os_ok else 'larger'}), rudder {rud:.1f}x and rudder rate {rate:.1f}x the PID's"
            )
        head = (
            f"**Beats the PID baseline** ({', '.join(wins)})"
            if wins
            else "**Does not beat the PID baseline**"
        )
        return (
            f"{head} by the criterion (lower mean heading error, overshoot not larger, rudder effort and "
            "rudder rate within 1.5x): " + "; ".join(parts) + "."
        )
    if kind == "harbour":
        best = max(rl, key=lambda r: (r["summary"]["success_rate"], r["summary"]["return_mean"]))
        s_rl, s_pid = best["summary"]["success_rate"], P["success_rate"]
        return (
            f"**{'Beats' if s_rl > s_pid else 'Does not beat'} the PID baseline** (higher success rate): best "
            f"agent `{best['agent']}` succeeds in {100 * s_rl:.0f} % of the episodes, the PID pilot in "
            f"{100 * s_pid:.0f} %."
        )
    if kind == "turning":
        best = min(rl, key=lambda r: r["summary"].get("rate_error_pct_mean") or math.inf)
        e_rl, e_pid = best["summary"].get("rate_error_pct_mean"), P.get("rate_error_pct_mean")
        if e_rl is None or e_pid is None:
            return ""
        return (
            f"Best agent `{best['agent']}`: mean rate error {e_rl:.1f} % vs {e_pid:.1f} % for the PI baseline "
            f"({'lower' if e_rl < e_pid else 'not lower'})."
        )
    return ""


def markdown(results: dict[str, Any]) -> str:
    """The generated part of docs/results.md."""
    m = results["machine"]
    steps = results.get("timesteps")
    budget = "each block's `n_timesteps`" if steps is None else f"{steps:,} environment steps"
    out = [
        BEGIN,
        "",
        f"Generated by `python agents/results.py {' '.join(results['argv'])}`".rstrip()
        + f" on {results['date']}: "
        f"{m['cpu_count']} CPUs, Python {m['python']}, torch {m['torch']} (threads {m['torch_threads']}), "
        f"stable-baselines3 {m['sb3']}; load average {m['load_start']:.1f} at the start and "
        f"{m['load_end']:.1f} at the end (a shared machine: wall times include waiting for the CPU, the "
        "CPU time in brackets does not). Training budget "
        f"{budget} per run; {results['episodes']} evaluation episodes per agent from the test seed set, "
        f"episode i from `reset(seed={results['eval_seed']} + i)` for every agent. Mean ± standard deviation "
        "over the episodes.",
        "",
    ]
    for sec in results["sections"]:
        kw = sec["env_kwargs"]
        cfg = ", ".join(f"{k}={json.dumps(v)}" for k, v in kw.items()) if kw else "registered defaults"
        out += [f"### {sec['env_id']} — {sec['label']} ({cfg})", "", table(sec["kind"], sec["rows"]), ""]
        v = verdict(sec["kind"], sec["rows"]) if sec.get("main") else ""
        if v:
            out += [v, ""]
    out.append(END)
    return "\n".join(out)


def write_doc(path: Path, generated: str) -> None:
    """Replace the generated part of ``path`` (between the markers), or write a new page."""
    text = path.read_text() if path.is_file() else ""
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        tail = rest.split(END, 1)[1]
        text = head + generated + tail
    else:
        text = "# Results\n\n" + generated + "\n"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


# --- running ---------------------------------------------------------------------------------------------------
def _log(msg: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", flush=True)


def run(args: argparse.Namespace, argv: list[str]) -> dict[str, Any]:
    import stable_baselines3 as sb3
    import torch

    torch.set_num_threads(args.threads)
    out = Path(args.out)
    envs = [resolve_env_id(e) for e in args.envs]
    load_start = os.getloadavg()[0]
    eval_seed = seeds.episode_seeds("test", args.episodes)[0]  # never seen in training or model selection
    sections = []
    for env_id in envs:
        trained: list[tuple[str, Path, dict[str, Any]]] = []
        eval_kwargs: dict[str, Any] | None = None
        for algo in args.algos or PLAN.get(env_id, ("ppo",)):
            cfg = run_config(algo, env_id, load_hyperparams(algo, env_id))
            if eval_kwargs is None:
                eval_kwargs = cfg.eval_env_kwargs
            elif cfg.eval_env_kwargs != eval_kwargs:
                raise UsageError(f"{env_id}: the algorithms' eval_env_kwargs differ; the table needs one")
            path = out / f"{model_stem(algo, env_id, args.seed)}.zip"
            if not args.skip_train:
                path.with_name(path.stem + "_best.zip").unlink(missing_ok=True)  # no stale best model
                steps = args.timesteps or cfg.n_timesteps
                _log(f"train {algo} on {env_id} ({steps} steps)")
                res = train(
                    algo,
                    env_id,
                    args.seed,
                    timesteps=steps,
                    out=out,
                    threads=args.threads,
                    eval_freq=args.eval_freq,
                )
                _log(f"  {res.n_timesteps} steps in {res.wall_time_s / 60:.1f} min -> {res.model_path}")
            if not path.is_file():
                raise UsageError(f"no model {path} (train first, without --skip-train)")
            trained.append((algo, path, run_record(path)))
            best = path.with_name(path.stem + "_best.zip")
            if best.is_file():
                trained.append((algo, best, run_record(best)))
        configs = [("training configuration", eval_kwargs or {}, True)]
        configs += [(label, kw, False) for label, kw in EXTRA_EVALS.get(env_id, []) if kw != eval_kwargs]
        for label, kw, main in configs:
            rows = []
            for agent in [*BASELINES, *(str(p) for _a, p, _r in trained)]:
                _log(f"evaluate {Path(agent).name} on {env_id} {kw}")
                ev = evaluate(env_id, agent, args.episodes, eval_seed, kw)
                rec = run_record(agent)
                rows.append(
                    {
                        "agent": Path(agent).stem if agent not in BASELINES else agent,
                        "path": agent,
                        "summary": ev["summary"],
                        "episodes": ev["episodes"],
                        "training": {
                            k: rec.get(k)
                            for k in (
                                "num_timesteps",
                                "train_time_s",
                                "cpu_time_s",
                                "budget_hit",
                                "n_envs",
                                "selected_at_timesteps",
                            )
                        }
                        if rec
                        else None,
                    }
                )
            kind = {"ZigZag": "zigzag", "Harbour": "harbour", "Turning": "turning"}
            sections.append(
                {
                    "env_id": env_id,
                    "label": label,
                    "env_kwargs": kw,
                    "main": main,
                    "kind": next(v for k, v in kind.items() if k in env_short_name(env_id)),
                    "rows": rows,
                }
            )
    return {
        "argv": argv,
        "date": dt.date.today().isoformat(),
        "timesteps": args.timesteps,
        "episodes": args.episodes,
        "eval_seed": eval_seed,
        "machine": {
            "cpu_count": os.cpu_count(),
            "python": platform.python_version(),
            "torch": torch.__version__,
            "torch_threads": torch.get_num_threads(),
            "sb3": sb3.__version__,
            "load_start": load_start,
            "load_end": os.getloadavg()[0],
        },
        "sections": sections,
    }


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    args = build_parser().parse_args(argv)
    try:
        results = run(args, argv)
    except UsageError as exc:
        print(f"results.py: error: {exc}", file=sys.stderr)
        return 2
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "results.json").write_text(json.dumps(json_safe(results), indent=1))
    write_doc(Path(args.doc), markdown(results))
    _log(f"wrote {out / 'results.json'} and {args.doc}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
