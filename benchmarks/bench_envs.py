"""Throughput of the vessel-gym environments against CartPole-v1, measured in the same run.

    python benchmarks/bench_envs.py [--repeats 7] [--steps 2000] [--num-envs 1024] [--vector-steps 20]

Single: env.step() per second through ``gymnasium.make`` (with its wrappers), actions drawn beforehand,
reset on episode end. Vector: environment steps per second (num_envs x vector steps / s) of
``gymnasium.make_vec(..., vectorization_mode="vector_entry_point")``. Timing blocks of each environment are
interleaved so that all see the same machine load; medians over the repeats are printed with the ratio to
CartPole and the targets (single >= 0.5 x CartPole-v1, vector >= 0.1 x CartPole's vector env).
"""

from __future__ import annotations

import argparse
import statistics
import time

import gymnasium as gym
import numpy as np

import vessel_gym.envs  # noqa: F401  (registers the ids)

IDS = (
    "vessel_gym/ZigZag-v0",
    "vessel_gym/ZigZag-v1",
    "vessel_gym/TurningCircle-v0",
    "vessel_gym/HarbourApproach-v0",
    "vessel_gym/HarbourApproach-v1",
)
BASE = "CartPole-v1"


def _single_block(env: gym.Env, actions: list, steps: int) -> float:
    t = time.perf_counter()
    for i in range(steps):
        _o, _r, term, trunc, _i = env.step(actions[i % len(actions)])
        if term or trunc:
            env.reset()
    return steps / (time.perf_counter() - t)


def _vector_block(env, actions: list, steps: int) -> float:
    t = time.perf_counter()
    for i in range(steps):
        env.step(actions[i % len(actions)])
    return steps * env.num_envs / (time.perf_counter() - t)


def bench_single(ids: tuple[str, ...], repeats: int, steps: int) -> dict[str, float]:
    envs = {}
    for env_id in (BASE, *ids):
        env = gym.make(env_id)
        env.reset(seed=0)
        env.action_space.seed(0)
        acts = [env.action_space.sample() for _ in range(1000)]
        _single_block(env, acts, 200)  # warm-up (compiled kernels, caches)
        envs[env_id] = (env, acts)
    rates: dict[str, list[float]] = {k: [] for k in envs}
    for _ in range(repeats):
        for env_id, (env, acts) in envs.items():
            rates[env_id].append(_single_block(env, acts, steps))
    for env, _a in envs.values():
        env.close()
    return {k: statistics.median(v) for k, v in rates.items()}


def bench_vector(ids: tuple[str, ...], repeats: int, steps: int, num_envs: int) -> dict[str, float]:
    envs = {}
    for env_id in (BASE, *ids):
        env = gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point")
        env.reset(seed=0)
        env.action_space.seed(0)
        acts = [env.action_space.sample() for _ in range(50)]
        _vector_block(env, acts, 3)
        envs[env_id] = (env, acts)
    rates: dict[str, list[float]] = {k: [] for k in envs}
    for _ in range(repeats):
        for env_id, (env, acts) in envs.items():
            n = steps * 50 if env_id == BASE else steps  # CartPole is fast: time a comparable block
            rates[env_id].append(_vector_block(env, acts, n))
    for env, _a in envs.values():
        env.close()
    return {k: statistics.median(v) for k, v in rates.items()}


def _report(title: str, rates: dict[str, float], ids: tuple[str, ...], target: float) -> None:
    print(title)
    print(f"  {BASE:32s} {rates[BASE]:12.0f}")
    for k in ids:
        r = rates[k] / rates[BASE]
        verdict = "ok" if r >= target else "MISSED"
        print(f"  {k:32s} {rates[k]:12.0f}   {r:5.3f} x CartPole   target {target:.2f} {verdict}")


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--steps", type=int, default=2000, help="single env steps per timing block")
    ap.add_argument("--num-envs", type=int, default=1024)
    ap.add_argument("--vector-steps", type=int, default=20, help="vector steps per timing block")
    ap.add_argument("--ids", nargs="*", default=list(IDS))
    args = ap.parse_args(argv)
    ids = tuple(args.ids)
    single = bench_single(ids, args.repeats, args.steps)
    vector = bench_vector(ids, args.repeats, args.vector_steps, args.num_envs)
    _report(f"single env: env.step/s through gymnasium.make (median of {args.repeats})", single, ids, 0.5)
    _report(
        f"vector env: env-steps/s, num_envs={args.num_envs}, vector_entry_point (median of {args.repeats})",
        vector,
        ids,
        0.1,
    )
    return {"single": single, "vector": vector}


if __name__ == "__main__":
    np.set_printoptions(precision=3)
    main()
