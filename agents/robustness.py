"""Robustness of the harbour helmsmen: success rate against wind strength, current strength and sensor noise,
swept beyond the ranges the agents were trained in.

    python -m agents.robustness --episodes 20 --out runs/robust --plot docs/img/results/robustness_harbour.png --doc docs/results.md

Each helmsman of :data:`HELMSMEN` (the tuned ``pid`` pilot of HarbourApproach-v3, the best shipped v3 agent, the
behaviour clone of the v3 pilot and the clone of the v1 pilot on v1) sails ``--episodes`` episodes of the test
seed set (episode i from ``reset(seed=2000000 + i)``: the same starts for every helmsman and every point) at
every point of three sweeps (:data:`SWEEPS`):

* ``wind``: the true wind speed fixed at the point, its direction uniform per episode;
* ``current``: the current speed fixed at the point, its direction uniform per episode;
* ``noise``: the task's sensor noise (config ``position_noise_m``, ``heading_noise_deg``, ``speed_noise_m_s``)
  at a level ``s``: position fix s x 0.01 L per axis, heading s x 1 deg, speeds s x 0.01 U_T (standard
  deviations, white, drawn afresh each control step). Level 1 is about what a ship's GNSS, gyro and log give
  (3 m, 1 deg, 0.15 kn on the full-scale 320 m KVLCC2, Froude-scaled to the L7 model).

Everything not swept is drawn as in training: wind and current speed and direction uniform in the scenario's
``[weather]`` (the training ranges; :func:`training_ranges`), from a generator seeded by the episode's seed.
Success rates carry their Wilson 95 % score interval (:func:`wilson`). Writes ``<out>/robustness.json``, the
plot (one panel per sweep, one line per helmsman, the training range shaded) and the page's generated block
between ``<!-- results:begin robustness -->`` and ``<!-- results:end robustness -->``.
Bad arguments: exit code 2 and one line on stderr.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import math
import os
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from agents import seeds
from agents.cli_util import RL_MODULES, json_safe
from agents.evaluation import evaluate, run_record
from agents.results_doc import begin_marker, end_marker, write_doc
from vessel_gym.cli_args import OneLineParser, UsageError, error_line, int_in, require_extra

TRAINED = Path(__file__).resolve().parent / "trained"
#: (label, env id, agent): the helmsmen compared; a model file that is not there is left out with a note
HELMSMEN: tuple[tuple[str, str, str], ...] = (
    ("tuned pilot (pid), v3", "vessel_gym/HarbourApproach-v3", "pid"),
    ("PPO seed 0, v3", "vessel_gym/HarbourApproach-v3", str(TRAINED / "ppo_HarbourApproach-v3_seed0.zip")),
    ("BC of the pilot seed 0, v3", "vessel_gym/HarbourApproach-v3", str(TRAINED / "bc" / "ppo_HarbourApproach-v3_seed0.zip")),
    ("BC of the pilot seed 0, v1", "vessel_gym/HarbourApproach-v1", str(TRAINED / "bc" / "ppo_HarbourApproach-v1_seed0.zip")),
)  # fmt: skip
#: sweep name -> (axis label, points); wind and current in m/s at model scale (the L7 model, 7 m)
SWEEPS: dict[str, tuple[str, tuple[float, ...]]] = {
    "wind": ("true wind speed, m/s (L7 model scale)", (0.0, 0.75, 1.5, 2.0, 2.5, 3.0, 4.0)),
    "current": ("current speed, m/s (L7 model scale)", (0.0, 0.05, 0.075, 0.1, 0.125, 0.15, 0.2)),
    "noise": ("sensor noise level s (position s x 0.01 L, heading s deg, speed s x 0.01 U_T)", (0, 1, 2, 4, 8, 16, 32)),
}  # fmt: skip
#: the sensor noise of level 1 (see the module docstring): position per axis in ship lengths, heading in
#: degrees, speeds in test speeds
NOISE_UNIT = {"position_L": 0.01, "heading_deg": 1.0, "speed_U": 0.01}
#: the Environment fields each sweep fixes (speed) and draws uniformly per episode (direction)
SWEPT_FIELDS = {
    "wind": ("wind_speed_m_s", "wind_from_deg"),
    "current": ("current_speed_m_s", "current_to_deg"),
}


def wilson(k: int, n: int, z: float = 1.959964) -> tuple[float, float]:
    """The Wilson score interval (default 95 %) of a rate of ``k`` successes in ``n`` trials (Wilson 1927)."""
    if n <= 0:
        raise ValueError(f"wilson: n must be > 0, got {n}")
    p = k / n
    denom = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1.0 - p) / n + z * z / (4 * n * n)) / denom
    return max(0.0, centre - half), min(1.0, centre + half)


def training_ranges(env_id: str) -> dict[str, tuple[float, float]]:
    """The scenario's ``[weather]`` ranges the task draws each reset from (what the agents trained in)."""
    import gymnasium as gym

    env = gym.make(env_id)
    try:
        w = env.unwrapped.task.scenario.weather
        return {key: (float(getattr(w, key)[0]), float(getattr(w, key)[1])) for key in
                ("wind_speed_m_s", "wind_from_deg", "current_speed_m_s", "current_to_deg")}  # fmt: skip
    finally:
        env.close()


def fixed_weather(env: Any, fixed: dict[str, float]) -> Any:
    """``env`` wrapped (for :func:`agents.evaluation.evaluate`'s ``wrap``) so that every episode resets under an
    :class:`~vessel_gym.physics.environment.Environment` of its own: the fields in ``fixed`` at their values,
    the others of the task's weather uniform in the scenario's ranges, drawn from ``default_rng(seed)`` of the
    episode's reset seed (the same draws at every point of a sweep). The start pose is the task's own."""
    import gymnasium as gym

    from vessel_gym.envs.tasks.harbour import WEATHER_DRAWS
    from vessel_gym.physics.environment import Environment

    weather = env.unwrapped.task.scenario.weather

    class FixedWeather(gym.Wrapper):
        def reset(self, *, seed: int | None = None, options: dict | None = None) -> Any:
            rng = np.random.default_rng(seed)
            fields = {}
            for key in WEATHER_DRAWS:
                lo, hi = (float(x) for x in getattr(weather, key))
                fields[key] = float(rng.uniform(lo, hi)) if hi > lo else lo
            fields.update(fixed)
            return self.env.reset(
                seed=seed, options={**(options or {}), "environment": Environment(**fields)}
            )

    return FixedWeather(env)


def noise_kwargs(level: float, env_id: str) -> dict[str, float]:
    """The sensor-noise config of ``level`` (:data:`NOISE_UNIT`) for the ship of ``env_id``."""
    import gymnasium as gym

    env = gym.make(env_id)
    try:
        task = env.unwrapped.task
        L, U = float(task.L), float(task.U_T)
    finally:
        env.close()
    return {
        "position_noise_m": level * NOISE_UNIT["position_L"] * L,
        "heading_noise_deg": level * NOISE_UNIT["heading_deg"],
        "speed_noise_m_s": level * NOISE_UNIT["speed_U"] * U,
    }


def sweep_point(env_id: str, agent: str, sweep: str, x: float, episodes: int, seed: int) -> dict[str, Any]:
    """One helmsman at one point of one sweep: successes, episodes, the rate and its Wilson interval, the
    outcomes."""
    kw = dict(run_record(agent).get("eval_env_kwargs") or {})
    wrap = None
    if sweep == "noise":
        kw.update(noise_kwargs(x, env_id))
    else:
        speed_key = SWEPT_FIELDS[sweep][0]
        wrap = lambda env: fixed_weather(env, {speed_key: float(x)})  # noqa: E731
    res = evaluate(env_id, agent, episodes, seed, kw, wrap=wrap)
    ok = int(sum(bool(e.get("success")) for e in res["episodes"]))
    lo, hi = wilson(ok, episodes)
    return {
        "x": x,
        "successes": ok,
        "episodes": episodes,
        "success_rate": ok / episodes,
        "wilson95": [lo, hi],
        "outcomes": res["summary"].get("outcomes", {}),
    }


def run(args: argparse.Namespace) -> dict[str, Any]:
    import torch

    torch.set_num_threads(1)
    seed = seeds.TEST_START
    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    helmsmen, missing = [], []
    for label, env_id, agent in HELMSMEN:
        if agent != "pid" and not Path(agent).is_file():
            missing.append(f"{label} ({agent})")
            continue
        helmsmen.append((label, env_id, agent))
    out: dict[str, Any] = {
        "date": dt.date.today().isoformat(),
        "episodes": args.episodes,
        "first_seed": seed,
        "noise_unit": NOISE_UNIT,
        "training_ranges": {e: training_ranges(e) for e in dict.fromkeys(h[1] for h in helmsmen)},
        "sweeps": {s: {"axis": SWEEPS[s][0], "points": list(SWEEPS[s][1])} for s in args.sweeps},
        "missing": missing,
        "helmsmen": [],
    }
    for label, env_id, agent in helmsmen:
        curves = {}
        for s in args.sweeps:
            pts = []
            for x in SWEEPS[s][1]:
                pts.append(sweep_point(env_id, agent, s, x, args.episodes, seed))
                print(f"[{time.strftime('%H:%M:%S')}] {label} {s}={x:g}: {pts[-1]['successes']}/{args.episodes}",
                      file=sys.stderr, flush=True)  # fmt: skip
            curves[s] = pts
        shown = agent if agent == "pid" else str(Path(agent).relative_to(TRAINED.parent.parent))
        out["helmsmen"].append({"label": label, "env_id": env_id, "agent": shown, "sweeps": curves})
    out["machine"] = {"cpu_count": os.cpu_count(), "load_start": load, "load_end": os.getloadavg()[0],
                      "wall_s": round(time.perf_counter() - t0, 1)}  # fmt: skip
    return out


def plot(res: dict[str, Any], path: str | Path) -> Path:
    """Success rate against each sweep's strength, one line per helmsman with its Wilson 95 % band; the
    training range shaded (wind, current) or marked (noise: none in training)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sweeps = list(res["sweeps"])
    fig, axes = plt.subplots(1, len(sweeps), figsize=(4.2 * len(sweeps), 3.6), sharey=True, squeeze=False)
    ranges = next(iter(res["training_ranges"].values()))
    for ax, s in zip(axes[0], sweeps):
        for h in res["helmsmen"]:
            pts = h["sweeps"][s]
            x = np.array([p["x"] for p in pts], dtype=float)
            y = 100.0 * np.array([p["success_rate"] for p in pts])
            lo = 100.0 * np.array([p["wilson95"][0] for p in pts])
            hi = 100.0 * np.array([p["wilson95"][1] for p in pts])
            (line,) = ax.plot(x, y, marker="o", ms=3, label=h["label"])
            ax.fill_between(x, lo, hi, color=line.get_color(), alpha=0.12, lw=0)
        key = {"wind": "wind_speed_m_s", "current": "current_speed_m_s"}.get(s)
        if key is not None:
            a, b = ranges[key]
            ax.axvspan(a, b, color="0.85", zorder=0, label="training range")
        ax.set_xlabel(res["sweeps"][s]["axis"], fontsize=7)
        ax.set_title(s, fontsize=9)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("success, % (Wilson 95 %)")
    axes[0][0].set_ylim(-3, 103)
    axes[0][0].legend(fontsize=6, loc="lower left")
    fig.suptitle(f"HarbourApproach: success against weather and sensor noise ({res['episodes']} test episodes per point)",
                 fontsize=9)  # fmt: skip
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path


def markdown(res: dict[str, Any], argv: Sequence[str], png: str | None) -> str:
    """The page's generated block: how it was made, the training ranges and one table per sweep."""
    m = res["machine"]
    name = "robustness"
    out = [
        begin_marker(name),
        "",
        f"Generated by `python -m agents.robustness {' '.join(argv)}`".rstrip() + f" on {res['date']} "
        f"({m['wall_s'] / 60:.1f} min wall on {m['cpu_count']} CPUs, load average {m['load_start']:.1f} at the "
        f"start and {m['load_end']:.1f} at the end): {res['episodes']} episodes per helmsman and point, episode "
        f"i from `reset(seed={res['first_seed']} + i)` (test seeds), the same starts at every point. Cells: "
        "successes in % [Wilson 95 % interval]."
        + (f" Plot: [{Path(png).name}](img/results/{Path(png).name})." if png else ""),
        "",
    ]
    for env_id, r in res["training_ranges"].items():
        out.append(f"Training ranges of {env_id} (the `harbour` scenario's `[weather]`, drawn uniformly each "
                   f"reset): wind {r['wind_speed_m_s'][0]:g}–{r['wind_speed_m_s'][1]:g} m/s, current "
                   f"{r['current_speed_m_s'][0]:g}–{r['current_speed_m_s'][1]:g} m/s, any direction; no sensor "
                   "noise.")  # fmt: skip
    if res["missing"]:
        out.append("Left out (no model file): " + "; ".join(res["missing"]) + ".")
    out.append("")
    for s, sw in res["sweeps"].items():
        head = "| helmsman | " + " | ".join(f"{x:g}" for x in sw["points"]) + " |"
        out += [f"**{s}** — {sw['axis']}:", "", head, "|---" * (len(sw["points"]) + 1) + "|"]
        for h in res["helmsmen"]:
            cells = [f"{100 * p['success_rate']:.0f} [{100 * p['wilson95'][0]:.0f}, {100 * p['wilson95'][1]:.0f}]"
                     for p in h["sweeps"][s]]  # fmt: skip
            out.append(f"| {h['label']} | " + " | ".join(cells) + " |")
        out.append("")
    out.append(end_marker(name))
    return "\n".join(out)


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(prog="python -m agents.robustness", description=__doc__.split("\n\n")[0])
    p.add_argument(
        "--episodes", type=int_in("--episodes", 1), default=20, help="test episodes per point (20)"
    )
    p.add_argument("--sweeps", nargs="+", choices=list(SWEEPS), default=list(SWEEPS), help="which sweeps")
    p.add_argument("--out", default="runs/robust", help="directory of robustness.json (runs/robust)")
    p.add_argument(
        "--plot", metavar="FILE", default=None, help="the plot (PNG; default <out>/robustness.png)"
    )
    p.add_argument("--doc", metavar="FILE", default=None,
                   help="the page whose robustness block is replaced (default <out>/robustness.md)")  # fmt: skip
    return p


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        require_extra(RL_MODULES, "rl", "the trained helmsmen")
        require_extra(("matplotlib",), "plot", "the robustness plot")
        if args.plot is not None and Path(args.plot).suffix.lower() != ".png":
            raise UsageError(f"--plot {args.plot}: expected a file ending in .png")
        res = run(args)
    except UsageError as exc:
        error_line(f"{parser.prog}: error: {exc}")
        return 2
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "robustness.json").write_text(json.dumps(json_safe(res), indent=1))
    png = plot(res, args.plot if args.plot is not None else out / "robustness.png")
    doc = Path(args.doc) if args.doc is not None else out / "robustness.md"
    write_doc(doc, markdown(res, argv, str(png)))
    print(f"wrote {out / 'robustness.json'}, {png} and {doc}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
