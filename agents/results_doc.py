"""The generated part of docs/results.md: the tables per environment configuration, the goal verdicts under
them, and the marker-delimited rewrite of the page (``agents/results.py`` makes the numbers)."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Any

#: HarbourApproach goal: median success rate over the training seeds at least this (docs/results.md)
HARBOUR_GOAL = 0.95
#: ... and a better helmsman than the tuned pilot: shorter mean time, rudder rate at most this factor times the
#: pilot's, minimum clearance no smaller (docs/results.md)
HARBOUR_RATE_FACTOR = 2.0
#: (summary key, label, format) of the harbour goal's figures
HARBOUR_GOAL_KEYS = (
    ("success_rate", "success", ".2f"),
    ("time_s", "time", ".0f"),
    ("rudder_rate_deg_s", "rudder rate", ".2f"),
    ("min_clearance_m", "min clearance", ".2f"),
)
#: Berthing goal (issue: "PPO ... >= 90 % success on held-out seeds with no fender overload"): median success
#: rate over the training seeds at least this, and no test episode ending in a fender overload
BERTHING_GOAL = 0.90
#: the goal's training budget per seed on this 2-core machine (docs/results.md)
TRAIN_LIMIT_MIN = 20.0
BEGIN, END = "<!-- results:begin -->", "<!-- results:end -->"
#: ZigZagRandom-v1 goal: overshoot per course change at most the tuned PID's plus this (deg), rudder rate at
#: most this factor times the PID's; return higher and heading error lower (docs/results.md)
ZIGZAG_OVERSHOOT_MARGIN_DEG = 0.25
ZIGZAG_RATE_FACTOR = 1.5
#: (summary key, label, format, larger is better) of the ZigZag goal's figures
ZIGZAG_GOAL_KEYS = (
    ("return", "return", ".1f"),
    ("heading_error_deg", "heading error", ".2f"),
    ("overshoot_deg", "overshoot per course change", ".2f"),
    ("rudder_rate_deg_s", "rudder rate", ".2f"),
)


def zigzag_checks(fig: dict[str, float], pid: dict[str, float]) -> dict[str, bool]:
    """The ZigZag goal's four tests of one set of figures (``<key>_mean`` of a summary) against the PID's."""
    return {
        "return": fig["return_mean"] > pid["return_mean"],
        "heading_error_deg": fig["heading_error_deg_mean"] < pid["heading_error_deg_mean"],
        "overshoot_deg": fig["overshoot_deg_mean"] <= pid["overshoot_deg_mean"] + ZIGZAG_OVERSHOOT_MARGIN_DEG,
        "rudder_rate_deg_s": fig["rudder_rate_deg_s_mean"] <= ZIGZAG_RATE_FACTOR * pid["rudder_rate_deg_s_mean"],
    }


def _zigzag_goal(row: dict[str, Any], P: dict[str, Any]) -> tuple[bool, str]:
    """(met, sentence) of the ZigZag goal for one row of trained agents: the median over its seeds of each
    figure (the row's mean when it has no per-seed detail) against the PID's, the gap of every failed test,
    and how many seeds meet all four on their own."""
    per = [x["summary"] for x in row.get("per_seed") or []]
    if per:
        fig = {f"{k}_mean": float(_median([x[f"{k}_mean"] for x in per])) for k, *_ in ZIGZAG_GOAL_KEYS}
    else:
        fig = {f"{k}_mean": row["summary"][f"{k}_mean"] for k, *_ in ZIGZAG_GOAL_KEYS}
    checks = zigzag_checks(fig, P)
    limits = {
        "return": P["return_mean"],
        "heading_error_deg": P["heading_error_deg_mean"],
        "overshoot_deg": P["overshoot_deg_mean"] + ZIGZAG_OVERSHOOT_MARGIN_DEG,
        "rudder_rate_deg_s": ZIGZAG_RATE_FACTOR * P["rudder_rate_deg_s_mean"],
    }
    cells = []
    for key, label, fmt in ZIGZAG_GOAL_KEYS:
        v, lim = fig[f"{key}_mean"], limits[key]
        verdict = "ok" if checks[key] else f"misses by {abs(v - lim):{fmt}}"
        cells.append(f"{label} {v:{fmt}} vs {lim:{fmt}} ({verdict})")
    met = all(checks.values())
    alone = sum(all(zigzag_checks(x, P).values()) for x in per)
    what = "median over the seeds" if per else "mean"
    text = f"`{row['agent']}` ({what}): " + ", ".join(cells) + (" — **met**" if met else " — **not met**")
    if per:
        text += f"; {alone} of {len(per)} seeds meet all four on their own"
    return met, text


def zigzag_seed_table(row: dict[str, Any], P: dict[str, Any]) -> str:
    """Markdown table of one method's seeds on the ZigZag goal's figures (empty without per-seed detail)."""
    per = row.get("per_seed") or []
    if not per:
        return ""
    head = ["seed", "tested model", "return", "heading error deg", "overshoot / course change deg"]
    head += ["rudder rate deg/s", "success %", "goal"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for x in per:
        S, sel = x["summary"], x.get("selected_at_timesteps")
        model = f"best at {sel / 1000:.0f}k" if sel is not None else "final"
        checks = zigzag_checks(S, P)
        missed = [label for key, label, _ in ZIGZAG_GOAL_KEYS if not checks[key]]
        cells = [str(x.get("seed")), model, f"{S['return_mean']:.1f}", f"{S['heading_error_deg_mean']:.2f}"]
        cells += [f"{S['overshoot_deg_mean']:.2f}", f"{S['rudder_rate_deg_s_mean']:.2f}"]
        cells += [_num(100.0 * S["success_rate"], ".0f") if "success_rate" in S else "—"]
        cells += ["met" if not missed else "misses " + ", ".join(missed)]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _harbour_figures(S: dict[str, Any]) -> dict[str, float]:
    """The harbour goal's figures of one summary (success rate, then means)."""
    return {k: float(S[k] if k == "success_rate" else S[f"{k}_mean"]) for k, *_ in HARBOUR_GOAL_KEYS}


def harbour_checks(fig: dict[str, float], pid: dict[str, float]) -> dict[str, bool]:
    """The harbour goal's four tests of one set of figures (:func:`_harbour_figures`) against the pilot's."""
    return {
        "success_rate": fig["success_rate"] >= HARBOUR_GOAL,
        "time_s": fig["time_s"] < pid["time_s"],
        "rudder_rate_deg_s": fig["rudder_rate_deg_s"] <= HARBOUR_RATE_FACTOR * pid["rudder_rate_deg_s"],
        "min_clearance_m": fig["min_clearance_m"] >= pid["min_clearance_m"],
    }


def _harbour_helmsman(row: dict[str, Any], P: dict[str, Any]) -> str:
    """The harbour goal on the median over the row's seeds of each figure against the tuned pilot's: the gap
    of every failed test and how many seeds meet all four on their own ("" without per-seed detail)."""
    per = [_harbour_figures(x["summary"]) for x in row.get("per_seed") or []]
    if not per:
        return ""
    pid = _harbour_figures(P)
    fig = {k: float(_median([x[k] for x in per])) for k, *_ in HARBOUR_GOAL_KEYS}
    checks = harbour_checks(fig, pid)
    limits = {
        "success_rate": HARBOUR_GOAL,
        "time_s": pid["time_s"],
        "rudder_rate_deg_s": HARBOUR_RATE_FACTOR * pid["rudder_rate_deg_s"],
        "min_clearance_m": pid["min_clearance_m"],
    }
    cells = []
    for key, label, fmt in HARBOUR_GOAL_KEYS:
        v, lim = fig[key], limits[key]
        cells.append(f"{label} {v:{fmt}} vs {lim:{fmt}} ({'ok' if checks[key] else f'misses by {abs(v - lim):{fmt}}'})")
    alone = sum(all(harbour_checks(x, pid).values()) for x in per)
    return (
        f"Harbour goal, `{row['agent']}` (median over the seeds; success ≥ {HARBOUR_GOAL:.2f}, shorter mean time "
        f"than the tuned pid, rudder rate ≤ {HARBOUR_RATE_FACTOR:g}x its, minimum clearance no smaller): "
        + ", ".join(cells)
        + (" — **met**" if all(checks.values()) else " — **not met**")
        + f"; {alone} of {len(per)} seeds meet all four on their own."
    )


def harbour_seed_table(row: dict[str, Any], P: dict[str, Any]) -> str:
    """Markdown table of one method's seeds on the harbour goal's figures (empty without per-seed detail)."""
    per = row.get("per_seed") or []
    if not per:
        return ""
    pid = _harbour_figures(P)
    head = ["seed", "tested model", "success %", "mean time s", "rudder rate deg/s (x pid)", "min clearance m"]
    head += ["return", "goal"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for x in per:
        S, sel = x["summary"], x.get("selected_at_timesteps")
        fig = _harbour_figures(S)
        checks = harbour_checks(fig, pid)
        missed = [label for key, label, _ in HARBOUR_GOAL_KEYS if not checks[key]]
        ratio = fig["rudder_rate_deg_s"] / pid["rudder_rate_deg_s"] if pid["rudder_rate_deg_s"] > 0 else math.inf
        cells = [str(x.get("seed")), f"best at {sel / 1000:.0f}k" if sel is not None else "final"]
        cells += [f"{100 * fig['success_rate']:.0f}", f"{fig['time_s']:.0f}"]
        cells += [f"{fig['rudder_rate_deg_s']:.2f} ({ratio:.1f}x)", f"{fig['min_clearance_m']:.2f}"]
        cells += [f"{S['return_mean']:.1f}", "met" if not missed else "misses " + ", ".join(missed)]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _median(values: list[float]) -> float:
    v = sorted(float(x) for x in values)
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def time_to_solve_table(row: dict[str, Any], pid_return: float | None) -> str:
    """Markdown table of one method's time to solve per seed (``row["time_to_solve"]`` of results.py)."""
    solve = row.get("time_to_solve") or []
    if not solve:
        return ""
    head = ["seed", "validation success ≥ 90 %: steps", "wall (CPU) min"]
    if pid_return is not None:
        head += [f"validation return ≥ the pid's ({pid_return:.1f}): steps", "wall (CPU) min"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    seeds = [x.get("seed") for x in row.get("per_seed") or []] or list(range(len(solve)))

    def cell(hit: dict[str, Any] | None) -> list[str]:
        if hit is None:
            return ["not within the run", "—"]
        wall, cpu = hit.get("wall_min"), hit.get("cpu_min")
        t = "—" if wall is None else f"{wall:.2f} ({cpu:.2f})"
        return [f"{hit['steps'] / 1000:.0f}k", t]

    for seed, x in zip(seeds, solve):
        cells = [str(seed)] + cell(x.get("success"))
        if pid_return is not None:
            cells += cell(x.get("pid_return"))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)

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
    elif kind == "berthing":
        head += ["success %", "fender overload %", "outcomes", "contact speed m/s", "fender energy / rating"]
        head += ["time s", "thruster effort"]
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
        elif kind == "berthing":
            outcomes = ", ".join(f"{k} {v}" for k, v in sorted(s.get("outcomes", {}).items()))
            cells += [
                _num(100.0 * s["success_rate"], ".0f"),
                _num(100.0 * overload_rate(s), ".0f"),
                outcomes,
                _pm(s, "contact_speed_m_s", ".3f"),
                _pm(s, "max_fender_energy_fraction", ".3f"),
                _pm(s, "time_s", ".0f"),
                _pm(s, "assist_effort", ".2f"),
            ]
        cells += [_pm(s, "rudder_deg"), _pm(s, "rudder_rate_deg_s", ".2f")]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def overload_rate(summary: dict[str, Any]) -> float:
    """Share of a summary's episodes that ended in a fender overload."""
    return summary.get("outcomes", {}).get("fender_overload", 0) / max(summary.get("episodes", 0), 1)


def _berthing_verdict(rows: list[dict[str, Any]], rl: list[dict[str, Any]]) -> str:
    """The Berthing goal on each row of trained agents, against the scripted pilot's success."""
    pilot = next((r for r in rows if r["agent"] == "scripted"), None)
    parts = []
    for r in rl:
        s, tr = r["summary"], r.get("training") or {}
        med, over = s["success_rate_median"], overload_rate(s)
        wall = (tr.get("train_time_s") or math.nan) / 60.0
        if med >= BERTHING_GOAL and over == 0.0 and wall <= TRAIN_LIMIT_MIN:
            met = "**met**"
        else:
            gaps = [f"{100 * (BERTHING_GOAL - med):.0f} points of success short"] if med < BERTHING_GOAL else []
            gaps += [f"{100 * over:.0f} % of episodes overload a fender"] if over > 0.0 else []
            gaps += ["too slow to train"] if wall > TRAIN_LIMIT_MIN else []
            met = "**not met**: " + ", ".join(gaps)
        parts.append(f"`{r['agent']}` median success {100 * med:.0f} %, {wall:.1f} min wall per seed: {met}")
    text = (
        f"Goal (median success over the seeds ≥ {100 * BERTHING_GOAL:.0f} % on the test seeds, no fender "
        f"overload, each seed trained in ≤ {TRAIN_LIMIT_MIN:.0f} min): " + "; ".join(parts) + "."
    )
    if pilot is not None:
        text += f" The scripted pilot succeeds in {100 * pilot['summary']['success_rate']:.0f} % of the same episodes."
    return text


def verdict(kind: str, rows: list[dict[str, Any]]) -> str:
    """One sentence: does the best trained agent beat the PID baseline by the goal's criterion?"""
    pid = next((r for r in rows if r["agent"] == "pid"), None)
    rl = [r for r in rows if r.get("training") is not None]
    if kind == "berthing":  # no PID helm: the goal is absolute, the scripted pilot the reference
        return _berthing_verdict(rows, rl) if rl else ""
    if pid is None or not rl:
        return ""
    P = pid["summary"]
    if kind == "zigzag":
        parts, wins = [], []
        for r in rl:
            ok, text = _zigzag_goal(r, P)
            parts.append(text)
            if ok:
                wins.append(r["agent"])
        head = (
            f"**Beats the tuned PID** ({', '.join(wins)})" if wins else "**Does not beat the tuned PID**"
        )
        return (
            f"{head} by the goal's criterion on the median over the training seeds (higher mean return, lower "
            f"mean heading error, overshoot per course change at most the PID's + {ZIGZAG_OVERSHOOT_MARGIN_DEG}"
            f" deg, rudder rate at most {ZIGZAG_RATE_FACTOR}x the PID's): " + "; ".join(parts) + "."
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
            text += (
                f" Goal (median success over the seeds ≥ {100 * HARBOUR_GOAL:.0f} %, each seed trained in ≤ 20 "
                "min): " + "; ".join(goals) + "."
            )
        helm = [h for h in (_harbour_helmsman(r, P) for r in rl) if h]
        if helm:
            text += " " + " ".join(helm)
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


def begin_marker(name: str = "") -> str:
    """``<!-- results:begin -->`` or, for one environment's block, ``<!-- results:begin ENV_ID -->``."""
    return BEGIN if not name else f"<!-- results:begin {name} -->"


def end_marker(name: str = "") -> str:
    return END if not name else f"<!-- results:end {name} -->"


#: a generated block: its name (empty: the page-wide block) and text, markers included
_BLOCK_RE = re.compile(r"<!-- results:begin(?: (\S+))? -->.*?<!-- results:end(?: \1)? -->", re.S)


def markdown(results: dict[str, Any]) -> str:
    """The generated part of docs/results.md: one marker-delimited block per environment id (each with the
    facts of the run that made it), so a run over some environments replaces only their blocks."""
    blocks = list(dict.fromkeys(sec.get("block", sec["env_id"]) for sec in results["sections"]))
    return "\n\n".join(_env_block(results, block) for block in blocks)


def _env_block(results: dict[str, Any], block: str) -> str:
    """The block ``block`` (an environment id, or ``<env id>:bc`` for a behaviour-cloning row alone)."""
    m = results["machine"]
    steps = results.get("timesteps")
    budget = "each block's `n_timesteps`" if steps is None else f"{steps:,} environment steps"
    out = [
        begin_marker(block),
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
        "(train steps and times: per seed). Learning curves: `curves/` next to `results.json`."
        + (
            " Tested model of each run: the best of its periodic validation evaluations (selected on the "
            "validation seeds; `--select best`), its step in the train steps column."
            if results.get("select") == "best"
            else ""
        ),
        "",
    ]
    for sec in (x for x in results["sections"] if x.get("block", x["env_id"]) == block):
        kw = sec["env_kwargs"]
        cfg = ", ".join(f"{k}={json.dumps(v)}" for k, v in kw.items()) if kw else "registered defaults"
        what = sec["env_id"] + ("" if block == sec["env_id"] else " (behaviour cloning)")
        out += [f"### {what} — {sec['label']} ({cfg})", "", table(sec["kind"], sec["rows"]), ""]
        v = verdict(sec["kind"], sec["rows"]) if sec.get("main") else ""
        if v:
            out += [v, ""]
        pid = next((r for r in sec["rows"] if r["agent"] == "pid"), None)
        for row in sec["rows"] if sec.get("main") else []:
            if sec["kind"] == "zigzag" and pid is not None and row.get("per_seed"):
                out += [f"Per seed, `{row['agent']}` (test episodes):", "", zigzag_seed_table(row, pid["summary"]), ""]
            if sec["kind"] == "harbour" and pid is not None and row.get("per_seed"):
                out += [f"Per seed, `{row['agent']}` (test episodes):", "", harbour_seed_table(row, pid["summary"]), ""]
            curve = results.get("curves", {}).get(f"{sec['env_id']}:{row.get('algo')}") or {}
            pid_ret = (curve.get("pid_validation") or {}).get("return")
            t = time_to_solve_table(row, pid_ret)
            if t:
                out += [f"Time to solve, `{row['agent']}` (training time until the periodic validation "
                        f"evaluation that first reached it; every {results['validation']['every_steps']:,} "
                        f"steps, {results['validation']['episodes']} validation episodes; learning curves: "
                        f"`{Path(curve['png']).name}`):", "", t, ""]
    out.append(end_marker(block))
    return "\n".join(out)


def write_doc(path: Path, generated: str) -> None:
    """Replace each generated block of ``generated`` (between its markers) in ``path``; a block the page does
    not have yet goes after the page's last generated block (or at the end); a missing page is new."""
    text = path.read_text() if path.is_file() else ""
    if not text:
        text = "# Results\n\n" + generated + "\n"
    else:
        for block in _BLOCK_RE.finditer(generated):
            name = block.group(1) or ""
            mine = re.compile(re.escape(begin_marker(name)) + r".*?" + re.escape(end_marker(name)), re.S)
            found = mine.search(text)
            if found:
                text = text[: found.start()] + block.group(0) + text[found.end() :]
                continue
            last = list(_BLOCK_RE.finditer(text))
            at = last[-1].end() if last else len(text)
            text = text[:at] + "\n\n" + block.group(0) + text[at:]
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
