"""Large HarbourApproach batches run the task kernel on all threads: same results as the serial kernel."""

import gymnasium as gym
import numpy as np

import vessel_gym  # noqa: F401
from vessel_gym.envs import harbour
from vessel_gym.envs import kernels as kn


def test_threaded_harbour_kernel_matches_serial():
    n = harbour.PARALLEL_MIN_SHIPS
    threaded = gym.make_vec(
        "vessel_gym/HarbourApproach-v0", num_envs=n, vectorization_mode="vector_entry_point"
    )
    serial = gym.make_vec(
        "vessel_gym/HarbourApproach-v0", num_envs=n, vectorization_mode="vector_entry_point"
    )
    assert threaded.unwrapped.task.kernel is kn.harbour_update_parallel
    serial.unwrapped.task.kernel = kn.harbour_update
    o1, _ = threaded.reset(seed=5)
    o2, _ = serial.reset(seed=5)
    assert np.array_equal(o1, o2)
    threaded.action_space.seed(2)
    for _ in range(40):
        a = threaded.action_space.sample()
        r1 = threaded.step(a)
        r2 = serial.step(a)
        for x, y in zip(r1[:4], r2[:4]):
            assert np.array_equal(x, y)
        assert np.array_equal(r1[4]["min_clearance_m"], r2[4]["min_clearance_m"])
