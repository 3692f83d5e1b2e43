"""Evaluate a trained agent or a classical baseline over seeded episodes.

    python agents/evaluate.py --env vessel_gym/ZigZag-v0 --agent runs/ppo_ZigZag-v0_s0.zip --episodes 20
    python agents/evaluate.py --env ZigZag-v0 --agent pid --episodes 20 --seed 0 --json
    python agents/evaluate.py --env HarbourApproach-v0 --agent scripted --episodes 5

Episode i starts from ``reset(seed=seed + i)``, so every agent meets the same starts; without ``--seed``
the episodes are those of the test seed set (``agents/seeds.py``), never seen in training or model
selection (``--split validation`` for the validation set). ``--agent``: ``pid``
(heading PID with Nomoto pole-placement gains; HarbourApproach: the line-of-sight pilot with those gains;
TurningCircle: rate PI), ``scripted`` (IMO zig-zag rule / 35 deg turn / harbour pilot) or a model saved by
``train.py``. A model is evaluated with the environment arguments it was trained with (its run record
``<stem>.yml``) unless ``--env-kwargs`` is given; compare baselines with the same ``--env-kwargs``.
Bad arguments: exit code 2 and one line on stderr.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a script: make the repository root importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from agents import seeds  # noqa: E402
from agents.common import (  # noqa: E402
    OneLineParser,
    UsageError,
    evaluate,
    int_at_least,
    json_safe,
    parse_assignments,
)

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


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(
        prog="evaluate.py", description="Evaluate an agent or baseline on a vessel-gym environment."
    )
    p.add_argument("--env", required=True, help="environment id, e.g. vessel_gym/ZigZag-v0 (or ZigZag-v0)")
    p.add_argument("--agent", required=True, help="pid, scripted or a model .zip saved by train.py")
    p.add_argument("--episodes", type=int_at_least("--episodes", 1), default=20)
    p.add_argument(
        "--seed", type=int_at_least("--seed", 0), default=None, help="first episode seed (default: --split's)"
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
    return p


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


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        kwargs = parse_assignments(args.env_kwargs, "--env-kwargs") if args.env_kwargs is not None else None
        seed = args.seed if args.seed is not None else seeds.SPLITS[args.split]
        result = evaluate(args.env, args.agent, args.episodes, seed, kwargs)
    except UsageError as exc:
        print(f"evaluate.py: error: {exc}", file=sys.stderr)
        return 2
    print(json.dumps(json_safe(result)) if args.json else format_summary(result))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
