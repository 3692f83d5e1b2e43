"""The tanker at its jetty in stronger weather: the scripted pilot on BerthingTanker-v0 (two 60 t tugs) over a
grid of wind and current speeds, directions drawn from the scenario's [weather] (any), and the static limit
where the tugs' bollard pull no longer holds the ship against beam wind and current.

    python benchmarks/bench_berthing_weather.py                          # 4 x 3 cells, 5 episodes each
    python benchmarks/bench_berthing_weather.py --wind 6 12 --current 0.1 --episodes 3

Per cell: success, outcomes, mean first-contact speed against the PIANC limit and the largest fender energy
of any episode against the fender's rating (a markdown table, docs/berthing.md "The tanker in stronger
weather"). The static limit: the side force of the model's windage at beam wind and of its hull at rest in a
beam current (sway through the water = the current), against the sum of the tugs' bollard pulls.
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import numpy as np

ENV = "vessel_gym/BerthingTanker-v0"


def beam_loads(winds: list[float], currents: list[float]) -> tuple[dict[float, float], dict[float, float], float]:
    """(beam wind side force N by wind speed, beam current side force N by current speed, total tug pull N)."""
    import gymnasium as gym

    import vessel_gym.envs  # noqa: F401  (registers the ids)
    from vessel_gym.physics import layout as lo

    env = gym.make(ENV, weather=False)
    try:
        env.reset(seed=0)
        task = env.unwrapped.task
        sim = task.sim
        wind, cur = {}, {}
        for w in winds:
            sim.reset(speed_m_s=0.0)
            # wind from the starboard beam at rest
            sim.set_environments(np.array([0]), wind_speed_m_s=w, wind_from_deg=math.degrees(sim.heading[0]) + 90.0)
            wind[w] = abs(float(sim.named_forces()["windage"].Y[0]))
        for c in currents:
            sim.reset(speed_m_s=0.0)
            sim.set_environments(np.array([0]), wind_speed_m_s=0.0)
            sim.state[0, lo.X_V] = c  # at rest over ground in a beam current: sway through the water
            f = sim.named_forces()
            cur[c] = abs(sum(float(f[k].Y[0]) for k in f if k != "windage"))
        pull = sum(a.F_max for a in task.assist)
    finally:
        env.close()
    return wind, cur, pull


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--wind", type=float, nargs="+", default=[6.0, 12.0, 18.0, 24.0], help="wind speeds, m/s")
    p.add_argument("--current", type=float, nargs="+", default=[0.1, 0.3, 0.5], help="current speeds, m/s")
    p.add_argument("--episodes", type=int, default=5)
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args(argv)
    if args.episodes < 1 or any(w < 0 for w in args.wind) or any(c < 0 for c in args.current):
        print("bench_berthing_weather: episodes >= 1, speeds >= 0", file=sys.stderr)
        return 2
    from agents.evaluation import evaluate

    wind, cur, pull = beam_loads(args.wind, args.current)
    print(f"tugs' bollard pull together: {pull / 1e3:.0f} kN")
    print("| wind m/s | current m/s | beam load / tug pull | success | outcomes | contact speed m/s (limit) | "
          "max fender energy / rating |")
    print("|---|---|---|---|---|---|---|")
    t0 = time.time()
    for w in args.wind:
        for c in args.current:
            kw = {"wind_m_s": [w, w], "current_m_s": [c, c]}
            ev = evaluate(ENV, "scripted", args.episodes, args.seed, kw)
            s, eps = ev["summary"], ev["episodes"]
            ok = sum(bool(e["success"]) for e in eps)
            outcomes = ", ".join(f"{k} {v}" for k, v in sorted(s["outcomes"].items()))
            touched = [e["contact_speed_m_s"] for e in eps if e["contact_speed_m_s"] > 0.0]
            v = f"{np.mean(touched):.4f}" if touched else "-"
            lim = eps[0]["contact_speed_limit_m_s"]
            energy = max(e["max_fender_energy_fraction"] for e in eps)
            load = (wind[w] + cur[c]) / pull
            print(f"| {w:g} | {c:g} | {load:.2f} | {ok} / {len(eps)} | {outcomes} | {v} ({lim:.3f}) | {energy:.3f} |",
                  flush=True)
    print(f"({time.time() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
