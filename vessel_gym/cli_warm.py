"""``vessel-gym warm [ID ...] [--imo SHIP ...]``: compile the kernels of the chosen environments and IMO reports
now, one progress line each, so that a later first step (or ``vessel-gym imo SHIP``) loads them from the cache.

It moves the cold start, it does not remove it: each id costs here what its first step would have cost (tens of
seconds of CPU on a small machine, docs/performance.md "Start-up: cold and warm"), once per machine and per
version of the kernel sources (``vessel_gym/physics/jitcache.py``). An id is warmed by what its first step runs:
``gymnasium.make``, ``reset(seed=0)`` and one step; a ship by its IMO report. A vector environment
(``gymnasium.make_vec``) compiles its batch kernels on its own first step, which this does not cover.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

from vessel_gym.cli_args import UsageError


def add_parser(sub) -> None:
    wp = sub.add_parser(
        "warm",
        help="compile the kernels of environments (default: every registered id) and IMO reports now, "
        "so that their first use is warm",
    )
    wp.add_argument("ids", nargs="*", metavar="ID", help="environment id (the 'vessel_gym/' may be left out)")
    wp.add_argument(
        "--imo",
        nargs="+",
        default=None,
        metavar="SHIP",
        help="the IMO report of these ships (as 'vessel-gym imo')",
    )


def _resolve_ids(names: list[str]) -> list[str]:
    """Full ids of ``names`` (every registered id when none is named); an unknown one is a UsageError."""
    from vessel_gym.envs.registration import NAMESPACE, known_ids

    known = known_ids()
    out = []
    for name in names:
        full = name if "/" in name else f"{NAMESPACE}/{name}"
        if full not in known:
            raise UsageError(
                f"vessel-gym warm: {name!r} is no registered environment id (have: {', '.join(known)})"
            )
        out.append(full)
    return out


def _warm_env(env_id: str) -> None:
    import warnings

    import gymnasium as gym

    with warnings.catch_warnings():  # deprecated ids warn on make; warming them is not a use
        warnings.simplefilter("ignore")
        env = gym.make(env_id)
        try:
            env.reset(seed=0)
            env.action_space.seed(0)
            env.step(env.action_space.sample())
        finally:
            env.close()


def _warm_imo(ship) -> None:
    from vessel_gym.manoeuvres.imo import imo_report

    imo_report(ship)


def run(args: argparse.Namespace) -> int:
    from vessel_gym.physics import jitcache
    from vessel_gym.physics.shipfile import load_ship

    ships = [load_ship(s) for s in args.imo or ()]  # a bad ship fails here, before anything compiles
    if args.ids:
        ids = _resolve_ids(args.ids)
    else:  # nothing named: every registered id
        ids = [] if ships else sorted(_all_ids())
    os.environ[jitcache.NOTICE_ENV] = "0"  # the progress lines below say it instead
    jobs = [(i, lambda i=i: _warm_env(i)) for i in ids] + [(f"imo {s.name}", lambda s=s: _warm_imo(s)) for s in ships]
    total_wall, total_cpu = time.perf_counter(), time.process_time()
    for k, (name, job) in enumerate(jobs, 1):
        print(f"vessel-gym warm: [{k}/{len(jobs)}] {name} ...", end=" ", file=sys.stderr, flush=True)
        t, c = time.perf_counter(), time.process_time()
        job()
        print(
            f"{time.perf_counter() - t:.1f} s ({time.process_time() - c:.1f} s CPU)",
            file=sys.stderr,
            flush=True,
        )
    print(
        f"vessel-gym warm: {len(jobs)} done in {time.perf_counter() - total_wall:.1f} s "
        f"({time.process_time() - total_cpu:.1f} s CPU)",
        file=sys.stderr,
    )
    return 0


def _all_ids() -> list[str]:
    from vessel_gym.envs.registration import known_ids

    return known_ids()
