"""Physics step cost of this source tree against another checkout of the project, measured side by side.

    python benchmarks/bench_compare.py --against /path/to/other/checkout [--rounds 5]

Each round runs one child process per tree (``PYTHONPATH`` set to that tree, one numba thread, so the serial
driver is compared and load on the other core does not enter through thread waits), alternating A B A B, and
each child prints the CPU time (``time.process_time``) per vessel-step of ``Simulation.step`` for a few cases
(median of its repeats). CPU time rather than wall time: on a shared machine another process stretches the
wall clock of both trees alike but leaves the CPU time of each nearly untouched. The figures printed are the
medians over the rounds, their ratio this/other, and the median of the round-by-round ratios ("paired"),
which is what to quote: a drift of the machine's speed between rounds cancels in it. "p-min" is the same
median of round-by-round ratios taken over each child's fastest repeat instead of its median one, a check on
"paired" when the machine is loaded.
The kernels are compiled (and cached) in a warm-up child per tree before the rounds.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]

#: (ship, vessels, steps per repeat): one ship through the Python step call (dispatch dominates), and a batch of
#: 1024 where the compiled kernel dominates; kvlcc2 is the MMG model, mariner the Abkowitz one
CASES = (("kvlcc2", 1, 20000), ("kvlcc2", 1024, 200), ("mariner", 1024, 200))

CHILD = r"""
import json, statistics, time
from vessel_gym.physics.simulation import Simulation
out = {}
for ship, n, steps in CASES:
    sim = Simulation(ship, n=n, dt=0.1)
    sim.reset()
    for _ in range(20):
        sim.step()
    t = []
    for _ in range(5):
        c0 = time.process_time()
        for _ in range(steps):
            sim.step()
        t.append((time.process_time() - c0) / (steps * n) * 1e9)
    out[f"{ship} N={n}"] = (statistics.median(t), min(t))
print(json.dumps(out))
"""


def run_child(tree: Path) -> dict[str, list[float]]:
    env = dict(os.environ, PYTHONPATH=str(tree), NUMBA_NUM_THREADS="1", OMP_NUM_THREADS="1")
    code = f"CASES = {CASES!r}\n" + CHILD
    res = subprocess.run(
        [sys.executable, "-c", code], cwd=tree, env=env, capture_output=True, text=True, check=False
    )
    if res.returncode != 0:
        raise SystemExit(f"bench_compare: the child in {tree} failed:\n{res.stderr.strip().splitlines()[-1]}")
    return json.loads(res.stdout.strip().splitlines()[-1])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--against", required=True, type=Path, help="the other checkout (its top directory)")
    ap.add_argument("--rounds", type=int, default=5, help="A B rounds (median over them)")
    args = ap.parse_args()
    other = args.against.resolve()
    if not (other / "vessel_gym" / "physics" / "simulation.py").is_file():
        print(f"bench_compare: --against {other}: not a checkout of this project", file=sys.stderr)
        return 2
    if args.rounds < 1:
        print(f"bench_compare: --rounds must be >= 1, got {args.rounds}", file=sys.stderr)
        return 2
    run_child(HERE), run_child(other)  # warm-up: compile and cache both trees' kernels
    a: dict[str, list[float]] = {}
    b: dict[str, list[float]] = {}
    a_min: dict[str, list[float]] = {}
    b_min: dict[str, list[float]] = {}
    for _ in range(args.rounds):
        for store, store_min, tree in ((a, a_min, HERE), (b, b_min, other)):
            for case, (ns, ns_min) in run_child(tree).items():
                store.setdefault(case, []).append(ns)
                store_min.setdefault(case, []).append(ns_min)
    try:
        load = os.getloadavg()[0]
    except OSError:
        load = float("nan")
    print(f"CPU ns per vessel-step (median of {args.rounds} rounds; load average {load:.1f})")
    print(
        f"{'case':<16} {'this':>8} {'other':>8} {'this/other':>11} {'paired':>7} {'p-min':>6}   rounds this / other"
    )
    for case in a:
        ma, mb = statistics.median(a[case]), statistics.median(b[case])
        # the median of the round-by-round ratios: each pair ran back to back, so a drift of the machine's
        # speed between rounds cancels in it (the ratio of the medians does not cancel it)
        paired = statistics.median(x / y for x, y in zip(a[case], b[case]))
        # the same with each child's fastest repeat: a repeat slowed by another process sharing the core's
        # caches drops out of it (a check on "paired" when the machine is loaded)
        paired_min = statistics.median(x / y for x, y in zip(a_min[case], b_min[case]))
        spread = ", ".join(f"{x:.0f}" for x in a[case]) + " / " + ", ".join(f"{x:.0f}" for x in b[case])
        print(f"{case:<16} {ma:>8.0f} {mb:>8.0f} {ma / mb:>11.2f} {paired:>7.2f} {paired_min:>6.2f}   {spread}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
