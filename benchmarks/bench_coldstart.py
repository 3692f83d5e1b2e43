"""Cold and warm start of the command line and of each environment's first step.

    python benchmarks/bench_coldstart.py [--repeats 2] [--keep DIR] [--ids ID ...]

Each figure is the wall time of a fresh Python process (``python -m vessel_gym.cli imo kvlcc2``, or a process
that makes an environment, resets it and takes one step), so it includes interpreter start, imports, loading or
compiling the numba kernels and the work itself. The child's CPU time (user + system) is printed beside the wall
time: on a shared machine the wall time grows with the load, the CPU time much less. "Cold" runs against an empty numba cache directory
(``NUMBA_CACHE_DIR`` set to a fresh temporary directory, so nothing is reused from earlier runs); "warm" runs
again against the cache that the cold run filled. The environments are timed each in its own cold cache, so a
figure is what a user sees when that environment is the first thing they run. The environments are every id
the package registers (``vessel_gym.envs.registration.known_ids``: the built-in tasks' declarations, read from
their sources), or those named with ``--ids``.

Targets on the 2-core reference machine: cold ``imo kvlcc2`` <= 10 s, cold first env step <= 8 s, warm <= 2 s.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ENV_STEP = (
    "import warnings, gymnasium as gym, vessel_gym.envs; warnings.simplefilter('ignore'); "
    "env = gym.make({id!r}); env.reset(seed=0); env.step(env.action_space.sample())"
)
TARGET_COLD_IMO_S = 10.0  # s, cold `vessel-gym imo kvlcc2`
TARGET_COLD_ENV_S = 8.0  # s, cold process up to the first env step
TARGET_WARM_S = 2.0  # s, any of the above with a filled cache


def _timed(argv: list[str], cache: Path) -> tuple[float, float, str]:
    """(wall s, CPU s of the child, its stderr)."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), PYTHONPATH=str(ROOT), VESSEL_GYM_COMPILE_NOTICE="1")
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    proc = subprocess.run(argv, env=env, cwd=ROOT, capture_output=True, text=True, timeout=900)
    dt = time.perf_counter() - t
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        sys.exit(f"bench_coldstart: {argv} failed ({proc.returncode}): {proc.stderr.strip()[-400:]}")
    return dt, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime), proc.stderr


def _case(name: str, argv: list[str], repeats: int, keep: Path | None) -> tuple[list, str]:
    """Medians of (cold wall, cold CPU, warm wall, warm CPU) and a note on the compile line."""
    rows, note = [], ""
    for _ in range(repeats):
        cache = Path(tempfile.mkdtemp(prefix="vg-numba-"))
        try:
            cold_wall, cold_cpu, err = _timed(argv, cache)
            note = "compile line shown" if "compiling kernels" in err else "NO compile line"
            warm_wall, warm_cpu, err = _timed(argv, cache)
            rows.append((cold_wall, cold_cpu, warm_wall, warm_cpu))
            note += "; warm run compiled again" if "compiling kernels" in err else "; none when warm"
        finally:
            if keep is None:
                shutil.rmtree(cache, ignore_errors=True)
            else:
                shutil.move(str(cache), keep / f"{name.replace('/', '_')}-{cache.name}")
    return [statistics.median(col) for col in zip(*rows)], note


def registered_ids() -> list[str]:
    """Every environment id the package registers (vessel_gym.envs.registration), sorted."""
    from vessel_gym.envs.registration import known_ids

    return sorted(known_ids())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=2, help="cold+warm pairs per case (median printed)")
    ap.add_argument("--keep", type=Path, default=None, help="move the filled cache directories here")
    ap.add_argument("--ids", nargs="*", default=None, help="environment ids (default: every registered one)")
    ap.add_argument("--no-cli", action="store_true", help="skip `imo kvlcc2`")
    args = ap.parse_args()
    if args.keep is not None:
        args.keep.mkdir(parents=True, exist_ok=True)
    py = sys.executable
    cases = [] if args.no_cli else [("imo kvlcc2", [py, "-m", "vessel_gym.cli", "imo", "kvlcc2"])]
    cases += [(i, [py, "-c", ENV_STEP.format(id=i)]) for i in (args.ids or registered_ids())]
    print(f"load average at the start: {_load()}")
    print(
        f"{'case':<32}{'cold wall':>10}{'cold CPU':>10}{'warm wall':>10}{'warm CPU':>10}   target cold/warm"
    )
    for name, argv in cases:
        (cw, cc, ww, wc), note = _case(name, argv, args.repeats, args.keep)
        target = TARGET_COLD_IMO_S if name.startswith("imo") else TARGET_COLD_ENV_S
        print(
            f"{name:<32}{cw:10.2f}{cc:10.2f}{ww:10.2f}{wc:10.2f}   {target:.0f} s / {TARGET_WARM_S:.0f} s   ({note})",
            flush=True,
        )
    print(f"load average at the end: {_load()}")


def _load() -> str:
    return f"{' '.join(f'{x:.2f}' for x in os.getloadavg())} on {os.cpu_count()} cores"


if __name__ == "__main__":
    main()
