"""PPO training throughput on the native vector environment (vessel_gym.sb3) against SB3's DummyVecEnv.

    python benchmarks/bench_sb3.py [--env vessel_gym/ZigZag-v1] [--num-envs 64] [--steps 20000] [--repeats 2]

Trains PPO (MlpPolicy 64x64, n_steps 128, batch 512, 5 epochs, one torch thread, CPU) for ``--steps``
environment steps with ``--num-envs`` ships, once per vector environment kind and repeat, the kinds
interleaved so that both see the same machine load. Prints steps per second of the whole ``learn()`` call
(environment stepping, policy inference and the gradient updates) and the share of that time spent in the
vector environment's ``reset``/``step``.
"""

from __future__ import annotations

import argparse
import statistics
import time


def _timed(venv):
    """``venv`` inside a VecEnvWrapper that sums the wall time of reset and step."""
    from stable_baselines3.common.vec_env import VecEnvWrapper

    class Timed(VecEnvWrapper):
        def __init__(self, venv) -> None:
            super().__init__(venv)
            self.seconds = 0.0

        def reset(self):
            t = time.perf_counter()
            obs = self.venv.reset()
            self.seconds += time.perf_counter() - t
            return obs

        def step_wait(self):
            t = time.perf_counter()
            out = self.venv.step_wait()
            self.seconds += time.perf_counter() - t
            return out

    return Timed(venv)


def run(env_id: str, kind: str, num_envs: int, steps: int, env_kwargs: dict) -> tuple[float, float]:
    """(steps per second of learn(), share of it in the vector environment) for one training run."""
    import torch
    from stable_baselines3 import PPO

    from agents.common import make_vec_env

    torch.set_num_threads(1)
    venv = _timed(make_vec_env(env_id, num_envs, 0, kind, env_kwargs))
    model = PPO(
        "MlpPolicy",
        venv,
        n_steps=128,
        batch_size=512,
        n_epochs=5,
        policy_kwargs={"net_arch": [64, 64]},
        device="cpu",
        seed=0,
    )
    t = time.perf_counter()
    model.learn(steps)
    wall = time.perf_counter() - t
    venv.close()
    return model.num_timesteps / wall, venv.seconds / wall


def main(argv: list[str] | None = None) -> dict[str, list[tuple[float, float]]]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--env", default="vessel_gym/ZigZag-v1")
    ap.add_argument("--num-envs", type=int, default=64)
    ap.add_argument("--steps", type=int, default=20_000)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--kinds", nargs="+", default=["native", "dummy"])
    args = ap.parse_args(argv)
    env_kwargs = {"schedule": "random"} if "ZigZag" in args.env else {}
    run(args.env, "native", 4, 512, env_kwargs)  # compile the kernels outside the timed runs
    runs: dict[str, list[tuple[float, float]]] = {k: [] for k in args.kinds}
    for _ in range(args.repeats):
        for kind in args.kinds:
            runs[kind].append(run(args.env, kind, args.num_envs, args.steps, env_kwargs))
    print(f"PPO on {args.env}, {args.num_envs} ships, {args.steps} steps (median of {args.repeats})")
    for kind, r in runs.items():
        sps = statistics.median(x[0] for x in r)
        share = statistics.median(x[1] for x in r)
        print(f"  {kind:8s} {sps:8.0f} steps/s   vector env {100 * share:4.1f} % of the training time")
    return runs


if __name__ == "__main__":
    main()
