"""The generated part of docs/results.md: the tables per environment configuration, the goal verdicts under
them, and the marker-delimited rewrite of the page (``agents/results.py`` makes the numbers)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

#: HarbourApproach goal: median success rate over the training seeds at least this (docs/results.md)
HARBOUR_GOAL = 0.9
#: the goal's training budget per seed on this 2-core machine (docs/results.md)
TRAIN_LIMIT_MIN = 20.0
BEGIN, END = "<!-- results:begin -->", "<!-- results:end -->"

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
    if tr.get("seeds"):
        steps += f" × {tr['seeds']} seeds"
    return [row["agent"], steps, f"{tr['train_time_s'] / 60:.1f} ({tr['cpu_time_s'] / 60:.1f})"]


def table(kind: str, rows: list[dict[str, Any]]) -> str:
    """Markdown table of evaluated agents of one environment configuration."""
    head = ["agent", "train steps", "train wall (CPU) min", "return"]
    zz_success = kind == "zigzag" and all("success_rate" in r["summary"] for r in rows)
    if kind == "zigzag":
        head += ["mean \\|heading error\\| deg", "overshoot / course change deg", "max overshoot deg"]
        head += ["targets reached %"] + (["success %"] if zz_success else [])
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
            if zz_success:
                cells.append(_num(100.0 * s["success_rate"], ".0f"))
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
        text = (
            f"**{'Beats' if s_rl > s_pid else 'Does not beat'} the PID baseline** (higher success rate): best "
            f"agent `{best['agent']}` succeeds in {100 * s_rl:.0f} % of the episodes, the PID pilot in "
            f"{100 * s_pid:.0f} %."
        )
        goals = [_harbour_goal(r) for r in rl if r["summary"].get("success_rate_median") is not None]
        if goals:
            text += " Goal (median success over the seeds ≥ 90 %, each seed trained in ≤ 20 min): " + "; ".join(
                goals
            ) + "."
        return text
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


def _harbour_goal(row: dict[str, Any]) -> str:
    """The harbour goal's verdict for one row of trained agents."""
    s, tr = row["summary"], row.get("training") or {}
    med, n = s["success_rate_median"], s["seeds"]
    wall = (tr.get("train_time_s") or math.nan) / 60.0
    cpu = (tr.get("cpu_time_s") or math.nan) / 60.0
    in_time = wall <= TRAIN_LIMIT_MIN
    if med >= HARBOUR_GOAL and in_time:
        met = "**met**"
    elif med >= HARBOUR_GOAL:
        met = "not met: too slow to train"
    else:
        met = f"**not met**, {100 * (HARBOUR_GOAL - med):.0f} points short"
    return (
        f"`{row['agent']}` median {100 * med:.0f} % over {n} seeds, {wall:.1f} min wall ({cpu:.1f} min CPU) "
        f"per seed: {met}"
    )


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
        f"episode i from `reset(seed={results['eval_seed']} + i)` for every agent. Baselines: mean ± "
        "standard deviation over the episodes. Trained agents: one row per method, mean ± standard "
        f"deviation over the {results.get('seeds', 1)} training seeds of each seed's mean over the episodes "
        "(train steps and times: per seed). Learning curves: `curves/` next to `results.json`.",
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
