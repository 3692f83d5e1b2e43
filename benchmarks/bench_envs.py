"""Throughput of the vessel-gym environments against CartPole-v1, measured in the same run.

    python benchmarks/bench_envs.py [--repeats 7] [--steps 2000] [--num-envs 1024] [--vector-steps 20]

Single: env.step() per second through ``gymnasium.make`` (with its wrappers), actions drawn beforehand,
reset on episode end. Vector: environment steps per second (num_envs x vector steps / s) of
``gymnasium.make_vec(..., vectorization_mode="vector_entry_point")``. Timing blocks of each environment are
interleaved so that all see the same machine load; medians over the repeats are printed with the ratio to
CartPole and each figure's goal (GOALS, for every registered id: single env >= 1.0 x CartPole-v1,
HarbourApproach >= 0.8 x; vector env >= 0.25 x and 0.15 x CartPole's vector env, and >= 0.1 x with a
busy-loop process on the machine). ``--load`` repeats the vector figures with a busy-loop process running;
``--setup N`` times building and resetting vector envs up to N ships (goal: 262144 in < 5 s, <= 2 kB per
ship); ``--setup-only`` prints only those, ``--setup-sizes`` chooses the sizes; ``--single-only`` only the
one-ship figures. ``--parts`` prints where a vector step's CPU time goes instead (physics, task kernel, helm,
automatic resets, the batched ``info``, the rest).
"""

from __future__ import annotations

import argparse
import gc
import os
import statistics
import subprocess
import sys
import time

import gymnasium as gym
import numpy as np

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.envs.registration import declaration, registered

IDS = tuple(registered())  # every registered id of the built-in tasks
BASE = "CartPole-v1"
# goals as multiples of CartPole's throughput in the same run: (single env, vector env, vector env under load);
# a task's goals hold for every version of it
DEFAULT_GOALS = (1.0, 0.25, 0.1)
# HarbourApproach: wind force, a chart query per control step and (v2) the depth under each ship
TASK_GOALS = {"HarbourApproachTask": (0.8, 0.15, 0.1)}
GOALS = {i: TASK_GOALS.get(declaration(i).name, DEFAULT_GOALS) for i in IDS}
SETUP_SIZES = (1024, 16384, 262144)
TARGET_SETUP_S = 5.0  # s, a vector env of 262144 ships built and reset
TARGET_BYTES_PER_SHIP = 2048  # B, resident memory of a vector env per ship


def _single_block(env: gym.Env, actions: list, steps: int) -> tuple[float, float]:
    """(steps per second of wall time, steps per second of this process's CPU time)."""
    t, c = time.perf_counter(), time.process_time()
    for i in range(steps):
        _o, _r, term, trunc, _i = env.step(actions[i % len(actions)])
        if term or trunc:
            env.reset()
    return steps / (time.perf_counter() - t), steps / max(time.process_time() - c, 1e-9)


def _vector_block(env, actions: list, steps: int) -> tuple[float, float]:
    """(env-steps per second of wall time, per second of CPU time of all this process's threads)."""
    t, c = time.perf_counter(), time.process_time()
    for i in range(steps):
        env.step(actions[i % len(actions)])
    n = steps * env.num_envs
    return n / (time.perf_counter() - t), n / max(time.process_time() - c, 1e-9)


def _medians(rates: dict[str, list[tuple[float, float]]]) -> dict[str, tuple[float, float]]:
    return {k: (statistics.median(w for w, _c in v), statistics.median(c for _w, c in v)) for k, v in rates.items()}


def bench_single(ids: tuple[str, ...], repeats: int, steps: int) -> dict[str, tuple[float, float]]:
    envs = {}
    for env_id in (BASE, *ids):
        env = gym.make(env_id)
        env.reset(seed=0)
        env.action_space.seed(0)
        acts = [env.action_space.sample() for _ in range(1000)]
        _single_block(env, acts, 200)  # warm-up (compiled kernels, caches)
        envs[env_id] = (env, acts)
    rates: dict[str, list[tuple[float, float]]] = {k: [] for k in envs}
    for _ in range(repeats):
        for env_id, (env, acts) in envs.items():
            rates[env_id].append(_single_block(env, acts, steps))
    for env, _a in envs.values():
        env.close()
    return _medians(rates)


def bench_vector(
    ids: tuple[str, ...], repeats: int, steps: int, num_envs: int
) -> dict[str, tuple[float, float]]:
    envs = {}
    for env_id in (BASE, *ids):
        env = gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point")
        env.reset(seed=0)
        env.action_space.seed(0)
        acts = [env.action_space.sample() for _ in range(50)]
        _vector_block(env, acts, 3)
        envs[env_id] = (env, acts)
    rates: dict[str, list[tuple[float, float]]] = {k: [] for k in envs}
    for _ in range(repeats):
        for env_id, (env, acts) in envs.items():
            n = steps * 50 if env_id == BASE else steps  # CartPole is fast: time a comparable block
            rates[env_id].append(_vector_block(env, acts, n))
    for env, _a in envs.values():
        env.close()
    return _medians(rates)


def bench_vector_parts(ids: tuple[str, ...], num_envs: int, steps: int) -> None:
    """Median CPU time (us) per vector step and of its parts, per id: the physics (``Task.advance``) and the
    task kernel in the process's CPU time (all threads), the helm and the batched ``info`` in this thread's; the automatic resets (``_reset_vessels`` within the steps) as a mean per step. Each part is timed
    in a call of its own after each step (the vessels advance twice per step: the figures are of timing only)."""
    from vessel_gym.envs.task import Task, batch_info

    pt, tt = time.process_time_ns, time.thread_time_ns
    print(f"vector step parts, num_envs={num_envs}, CPU us, median of {steps} steps  [{_load()}]")
    for env_id in ids:
        venv = gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point")
        env = venv.unwrapped
        env.reset(seed=0)
        env.action_space.seed(0)
        acts = [env.action_space.sample() for _ in range(8)]
        for i in range(3):
            env.step(acts[i])
        task, resets = env.task, [0, 0]
        reset_vessels = env._reset_vessels

        def timed_reset(idx, options, _r=reset_vessels, resets=resets):
            t = pt()
            _r(idx, options)
            resets[0] += pt() - t
            resets[1] += len(idx)

        env._reset_vessels = timed_reset
        depth = getattr(task, "_depth_call", None)
        acc: dict[str, list[float]] = {k: [] for k in ("step", "physics", "kernel", "depth", "helm", "info")}
        for i in range(steps):
            a = acts[i % len(acts)]
            t = pt()
            env.step(a)
            acc["step"].append(pt() - t)
            t = tt()
            task.helm.apply(task.helm.batch(a, num_envs))
            acc["helm"].append(tt() - t)
            t = pt()
            task.sim.step(task.nsub)
            acc["physics"].append(pt() - t)
            t = pt()
            Task.update(task, task.phase)
            acc["kernel"].append(pt() - t)
            if depth is not None:
                t = tt()
                depth[0](*depth[1])
                acc["depth"].append(tt() - t)
            t = tt()
            batch_info(task)
            acc["info"].append(tt() - t)
        env._reset_vessels = reset_vessels
        med = {k: statistics.median(v) / 1e3 for k, v in acc.items() if v}
        mean_resets = resets[0] / steps / 1e3
        parts = med["physics"] + med["kernel"] + med.get("depth", 0.0) + med["helm"] + med["info"]
        rest = med["step"] - parts - mean_resets
        print(
            f"  {env_id:32s} step {med['step']:7.0f}: physics {med['physics']:6.0f}, task kernel {med['kernel']:5.0f}"
            + (f", depth {med['depth']:4.0f}" if "depth" in med else "")
            + f", helm {med['helm']:4.0f}, info {med['info']:4.0f}, resets {mean_resets:5.0f}"
            f" ({resets[1] / steps:.2f} ships/step), rest {rest:5.0f}"
        )
        venv.close()


def _load() -> str:
    """The machine's load average over 1, 5 and 15 minutes (the figures depend on it: say it with them)."""
    try:
        return "load average {:.2f} {:.2f} {:.2f}".format(*os.getloadavg())
    except OSError:
        return "load average unknown"


def _report(title: str, rates: dict[str, tuple[float, float]], ids: tuple[str, ...], which: int) -> None:
    """Each id's rate (wall time) and its ratio to CartPole's against the goal; then the same ratio in CPU
    time, which a loaded machine disturbs less (it leaves out the time the process waited for a core)."""
    print(f"{title}  [{_load()} on {os.cpu_count()} CPUs]")
    print(f"  {BASE:32s} {rates[BASE][0]:12.0f}")
    for k in ids:
        r = rates[k][0] / rates[BASE][0]
        rc = rates[k][1] / rates[BASE][1]
        target = GOALS[k][which]
        verdict = "meets" if r >= target else "MISSES"
        verdict_cpu = "meets" if rc >= target else "MISSES"
        print(
            f"  {k:32s} {rates[k][0]:12.0f}   {r:5.3f} x CartPole   goal {target:.2f} {verdict:6s}"
            f"   (CPU time: {rc:5.3f} x, {verdict_cpu})"
        )


def _rss_bytes() -> int:
    """Resident set size of this process, bytes (Linux /proc; 0 elsewhere)."""
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError):
        return 0


WARM_UP_SHIPS = 4096  # ships of the set-up benchmark's warm-up build and reset (physics.steady.STEADY_THREADED_MIN)


def bench_setup(ids: tuple[str, ...], max_n: int, sizes: tuple[int, ...] = SETUP_SIZES) -> None:
    """Wall time to build a vector env of N ships and reset it (one run each, after a warm-up build), the CPU time
    of all the process's threads for both, and the growth of the resident set per ship (goal <= 2 kB)."""
    print(
        f"vector env set-up: build + reset(seed=0), wall, one run; goal N = 262144 in < {TARGET_SETUP_S:g} s, "
        f"<= {TARGET_BYTES_PER_SHIP} B per ship (resident set growth)"
    )
    print(f"  [{_load()} on {os.cpu_count()} CPUs]")
    print(f"  {'id':32s} {'N':>7s} {'build s':>8s} {'reset s':>8s} {'us/ship':>8s} {'CPU s':>7s} {'B/ship':>8s}")
    for env_id in ids:
        # warm-up: loads the compiled kernels, those of a large reset too (threaded steady solves from 4096 ships)
        gym.make_vec(env_id, num_envs=WARM_UP_SHIPS, vectorization_mode="vector_entry_point").reset(seed=0)
        for n in (n for n in sizes if n <= max_n):
            gc.collect()
            rss0 = _rss_bytes()
            t0, c0 = time.perf_counter(), time.process_time()
            env = gym.make_vec(env_id, num_envs=n, vectorization_mode="vector_entry_point")
            t1 = time.perf_counter()
            env.reset(seed=0)
            t2, c2 = time.perf_counter(), time.process_time()
            per_ship = (_rss_bytes() - rss0) / n
            goal = "meets" if per_ship <= TARGET_BYTES_PER_SHIP else "MISSES"
            goal = f"memory goal {goal}"
            if n == 262144:
                goal += ", time goal " + ("meets" if t2 - t0 < TARGET_SETUP_S else "MISSES")
            print(
                f"  {env_id:32s} {n:7d} {t1 - t0:8.2f} {t2 - t1:8.2f} {(t2 - t0) / n * 1e6:8.1f} {c2 - c0:7.2f} "
                f"{per_ship:8.0f}  {goal}"
            )
            env.close()
            del env


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--steps", type=int, default=2000, help="single env steps per timing block")
    ap.add_argument("--num-envs", type=int, default=1024)
    ap.add_argument("--vector-steps", type=int, default=20, help="vector steps per timing block")
    ap.add_argument("--ids", nargs="*", default=list(IDS))
    ap.add_argument("--load", action="store_true", help="vector figures again with a busy-loop process")
    ap.add_argument("--setup", type=int, default=0, metavar="N", help="time build + reset up to N ships")
    ap.add_argument("--setup-only", action="store_true", help="only the set-up figures (with --setup)")
    ap.add_argument("--single-only", action="store_true", help="only the one-ship figures")
    ap.add_argument("--setup-sizes", type=int, nargs="*", default=list(SETUP_SIZES), metavar="N")
    ap.add_argument("--parts", type=int, default=0, metavar="STEPS", help="only the vector step's parts")
    args = ap.parse_args(argv)
    ids = tuple(args.ids)
    if args.parts:
        bench_vector_parts(ids, args.num_envs, args.parts)
        return {}
    if args.setup_only:
        bench_setup(ids, args.setup or max(args.setup_sizes), tuple(args.setup_sizes))
        return {}
    single = bench_single(ids, args.repeats, args.steps)
    _report(f"single env: env.step/s through gymnasium.make (median of {args.repeats})", single, ids, 0)
    if args.single_only:
        return {"single": single}
    vector = bench_vector(ids, args.repeats, args.vector_steps, args.num_envs)
    title = (
        f"vector env: env-steps/s, num_envs={args.num_envs}, vector_entry_point (median of {args.repeats})"
    )
    _report(title, vector, ids, 1)
    out = {"single": single, "vector": vector}
    if args.load:
        hog = subprocess.Popen([sys.executable, "-c", "while True: pass"])  # another process on a core
        try:
            out["vector_loaded"] = bench_vector(ids, args.repeats, args.vector_steps, args.num_envs)
        finally:
            hog.kill()
            hog.wait()
        _report(f"{title}, with a busy-loop process", out["vector_loaded"], ids, 2)
    if args.setup:
        bench_setup(ids, args.setup, tuple(args.setup_sizes))
    return out


if __name__ == "__main__":
    np.set_printoptions(precision=3)
    main()
