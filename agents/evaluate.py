"""Evaluate a trained agent or a classical baseline over seeded episodes.

    python agents/evaluate.py --env vessel_gym/ZigZag-v1 --agent runs/ppo_ZigZag-v1_s0.zip --episodes 20
    python agents/evaluate.py --env ZigZag-v1 --agent pid --episodes 20 --seed 0 --json
    python agents/evaluate.py --env HarbourApproach-v2 --agent scripted --episodes 5

Episode i starts from ``reset(seed=seed + i)``, so every agent meets the same starts; without ``--seed``
the episodes are those of the test seed set (``agents/seeds.py``), never seen in training or model
selection (``--split validation`` for the validation set). ``--agent``: ``pid``
(heading PID by Nomoto pole placement with the natural frequency and damping tuned for the id,
``agents/tune_pilot.py``; HarbourApproach: the line-of-sight pilot with those gains; TurningCircle: rate PI),
``pid-nomoto`` (the same pilot with the untuned design), ``scripted`` (IMO zig-zag rule / 35 deg turn /
harbour pilot) or a model saved by ``train.py``. A model is evaluated with the environment arguments it was trained with (its run record
``<stem>.yml``) unless ``--env-kwargs`` is given; compare baselines with the same ``--env-kwargs``.
Bad arguments: exit code 2 and one line on stderr.

``--json`` prints ONE JSON object on stdout (progress goes to stderr): ``episodes`` (count),
``mean_return``, ``std_return`` and, where the task has them, ``success_rate``, ``mean_heading_error_deg``,
``mean_overshoot_deg`` (per course change; the environment's own accounting where it has one, the
unfinished overshoot included), ``mean_rudder_deg``, ``mean_rudder_rate_deg_s``, and every other summary
metric as ``mean_<metric>``; ``summary`` and ``per_episode`` carry the full detail.
A shipped agent (``agents/trained/<algo>_<env>_seed<N>.zip`` with its JSON sidecar, ``agents/shipped.py``)
is evaluated with the environment arguments its sidecar names.

Pictures (``agents/visual.py``): ``--render DIR`` writes chart frames ``DIR/ep<i>_<step>.png`` every
``--frame-every`` steps and the trajectory plot ``DIR/trajectories_<agent>.png``; ``--plot FILE`` writes
the trajectory plot elsewhere; ``--video FILE`` an animated ``.gif`` (Pillow) or ``.mp4`` (needs imageio and
imageio-ffmpeg).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from agents import seeds
from agents.cli_util import RL_MODULES
from agents.common import (
    BASELINES,
    evaluate,
    json_safe,
    parse_assignments,
)
from agents.evaluation import RATES
from vessel_gym.cli_args import OneLineParser, UsageError, error_line, int_in, require_extra

#: summary keys printed (when present) with their labels
LABELS = (
    ("return", "return"),
    ("success_rate", "success rate"),
    ("heading_error_deg", "mean |heading error| (deg)"),
    ("overshoot_deg", "overshoot per course change (deg)"),
    ("max_overshoot_deg", "max overshoot (deg)"),
    ("reached_pct", "targets reached (%)"),
    ("rate_error_pct", "mean |rate error| (%)"),
    ("min_clearance_m", "min clearance (m)"),
    ("time_s", "episode time (s)"),
    ("rudder_deg", "mean |rudder order| (deg)"),
    ("rudder_rate_deg_s", "mean |rudder order rate| (deg/s)"),
    ("length", "episode length (steps)"),
)


def build_parser(prog: str = "evaluate.py") -> argparse.ArgumentParser:
    p = OneLineParser(prog=prog, description="Evaluate an agent or baseline on a vessel-gym environment.")
    p.add_argument("--env", required=True, help="environment id, e.g. vessel_gym/ZigZag-v1 (or ZigZag-v1)")
    p.add_argument(
        "--agent", required=True, help="pid, pid-nomoto, scripted or a model .zip saved by train.py"
    )
    p.add_argument("--episodes", type=int_in("--episodes", 1), default=20)
    p.add_argument(
        "--seed", type=int_in("--seed", 0), default=None, help="first episode seed (default: --split's)"
    )
    p.add_argument(
        "--split",
        choices=sorted(seeds.SPLITS),
        default="test",
        help="seed set used without --seed (default test)",
    )
    p.add_argument(
        "--env-kwargs",
        nargs="+",
        metavar="KEY=VALUE",
        default=None,
        help="environment arguments (YAML values)",
    )
    p.add_argument("--json", action="store_true", help="print the result as one JSON object")
    p.add_argument("--render", metavar="DIR", default=None, help="write chart frames and the trajectory plot")
    p.add_argument(
        "--frame-every",
        type=int_in("--frame-every", 1),
        default=4,
        help="with --render/--video: one frame every N steps (default 4)",
    )
    p.add_argument("--video", metavar="FILE", default=None, help="animated .gif or .mp4 of the episodes")
    p.add_argument("--plot", metavar="FILE", default=None, help="trajectory plot (PNG) of the episodes")
    return p


#: the flat metrics of the --json contract: output key -> summary key
CONTRACT = (
    ("mean_return", "return_mean"),
    ("std_return", "return_std"),
    ("mean_heading_error_deg", "heading_error_deg_mean"),
    ("mean_overshoot_deg", "overshoot_deg_mean"),
    ("mean_rudder_deg", "rudder_deg_mean"),
    ("mean_rudder_rate_deg_s", "rudder_rate_deg_s_mean"),
)


def contract(result: dict[str, Any], files: dict[str, str] | None = None) -> dict[str, Any]:
    """The ``--json`` object: the contract's flat keys first, then every other metric, then the detail."""
    s = result["summary"]
    out: dict[str, Any] = {
        "env_id": result["env_id"],
        "agent": result["agent"],
        "env_kwargs": result["env_kwargs"],
        "episodes": s["episodes"],
        "seeds": [e["seed"] for e in result["episodes"]],
    }
    for key, src in CONTRACT:
        if src in s:
            out[key] = s[src]
    for rate in (f"{name}_rate" for name in RATES):
        if rate in s:
            out[rate] = s[rate]
    for k, v in s.items():
        if k.endswith("_mean") and f"mean_{k[:-5]}" not in out:
            out[f"mean_{k[:-5]}"] = v
    if "outcomes" in s:
        out["outcomes"] = s["outcomes"]
    out["files"] = files or {}
    out["summary"] = s
    out["per_episode"] = result["episodes"]
    return out


def _progress(i: int, ep: dict[str, Any]) -> None:
    print(f"episode {i + 1} (seed {ep['seed']}): return {ep['return']:.3f}", file=sys.stderr, flush=True)


def format_summary(result: dict[str, Any]) -> str:
    """Human-readable summary of :func:`agents.common.evaluate`'s result."""
    s = result["summary"]
    lines = [
        f"{result['agent']} on {result['env_id']} {result['env_kwargs'] or ''}: {s['episodes']} episodes"
    ]
    for key, label in LABELS:
        if key == "success_rate" and key in s:
            lines.append(f"  {label:34s} {100.0 * s[key]:.0f} %")
        elif f"{key}_mean" in s:
            m, d = s[f"{key}_mean"], s[f"{key}_std"]
            lines.append(f"  {label:34s} " + ("n/a" if m is None else f"{m:.3f} +- {d:.3f}"))
    if "outcomes" in s:
        lines.append(
            "  outcomes                           " + ", ".join(f"{k} {v}" for k, v in s["outcomes"].items())
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None, prog: str = "evaluate.py") -> int:
    """The command line (``vessel-gym evaluate`` and ``python agents/evaluate.py``); returns the exit code."""
    parser = build_parser(prog)
    args = parser.parse_args(argv)
    try:
        if args.agent not in BASELINES:  # a saved model; pid and scripted need no RL packages
            require_extra(RL_MODULES, "rl", f"--agent {args.agent}")
        kwargs = parse_assignments(args.env_kwargs, "--env-kwargs") if args.env_kwargs is not None else None
        seed = args.seed if args.seed is not None else seeds.SPLITS[args.split]
        result, files = run(args, seed, kwargs)
    except UsageError as exc:
        error_line(f"{parser.prog}: error: {exc}")
        return 2
    if args.json:
        print(json.dumps(json_safe(contract(result, files))))
    else:
        print(format_summary(result))
        for what, path in files.items():
            print(f"  {what:34s} {path}")
    return 0


def run(args: argparse.Namespace, seed: int, kwargs: dict[str, Any] | None) -> tuple[dict[str, Any], dict]:
    """Evaluate as the arguments say; returns the result and the picture files written."""
    from agents import visual

    pictures = args.render is not None or args.video is not None or args.plot is not None
    for opt, value in (("--render", args.render), ("--plot", args.plot), ("--video", args.video)):
        if value is not None:  # trajectory plots (matplotlib), frames and GIF (Pillow, with matplotlib)
            require_extra(("matplotlib", "PIL"), "plot", opt)
    if args.video is not None:
        visual.check_video_path(args.video)
    for opt, path in (("--video", args.video), ("--plot", args.plot)):
        if path is not None and Path(path).exists():
            raise UsageError(f"{opt} {path}: file exists (not overwritten)")
    if args.plot is not None and Path(args.plot).suffix.lower() != ".png":
        raise UsageError(f"--plot {args.plot}: expected a file ending in .png")
    if args.render is not None and Path(args.render).is_file():
        raise UsageError(f"--render {args.render}: is a file, expected a directory")
    if args.render is not None and Path(args.render).is_dir() and any(Path(args.render).iterdir()):
        raise UsageError(f"--render {args.render}: directory is not empty (nothing is overwritten)")
    recorders: list[Any] = []

    def wrap(env: Any) -> Any:
        rec = visual.Recorder(
            env, frames_dir=args.render, frame_every=args.frame_every, keep_frames=args.video is not None
        )
        recorders.append(rec)
        return rec

    frames = args.render is not None or args.video is not None
    result = evaluate(
        args.env,
        args.agent,
        args.episodes,
        seed,
        kwargs,
        progress=_progress,
        render_mode="rgb_array" if frames else None,
        wrap=wrap if pictures else None,
    )
    files: dict[str, str] = {}
    if not recorders:
        return result, files
    rec = recorders[0]
    name = Path(result["agent"]).stem
    title = f"{name} on {result['env_id']}: {len(rec.tracks)} episodes"
    labels = [f"seed {e['seed']}" for e in result["episodes"]]
    plots = [Path(args.plot)] if args.plot is not None else []
    if args.render is not None:
        plots.append(Path(args.render) / f"trajectories_{name}.png")
        files["frames"] = f"{args.render} ({len(rec.frame_files)} PNG)"
    for i, p in enumerate(plots):
        files["trajectory plot" if i == 0 else f"trajectory plot {i + 1}"] = str(
            visual.plot_trajectories(rec.tracks, rec, p, title, labels)
        )
    if args.video is not None:
        dt = float(rec.unwrapped.config.control_interval_s)
        # real time would be slow to watch: ten times faster than the simulation
        fps = min(max(10.0 / (dt * args.frame_every), 1.0), 30.0)
        files["video"] = str(visual.write_video(rec.frames, args.video, fps))
    return result, files


if __name__ == "__main__":
    raise SystemExit(main())
