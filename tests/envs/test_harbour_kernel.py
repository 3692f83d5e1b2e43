"""Harbour task kernel: the threaded driver matches the serial one; the chart query's contact cases."""

import gymnasium as gym
import numpy as np
import pytest

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


def test_chart_query_contact_cases():
    """Contact when outlines cross, when the hull lies wholly in a polygon, and when a small rock lies wholly
    under the hull (no outline crossing in the last two)."""
    hull = np.array([(3.5, 0.0), (2.1, 0.6), (-3.5, 0.6), (-3.5, -0.6), (2.1, -0.6)])  # 7 m x 1.2 m
    beam_dirs = np.array([(1.0, 0.0), (0.0, 1.0)])
    scratch = (np.empty(2), np.empty(5), np.empty(5), np.empty((2, 2)))

    def query(polygon, n0=0.0, e0=0.0):
        edges, polys, pbox = kn.chart_tables([(1, polygon)])
        b, hn, he, bw = scratch
        return kn.chart_query(n0, e0, 0.0, hull, edges, polys, pbox, beam_dirs, 50.0, b, hn, he, bw)

    rock = [(-0.2, -0.2), (0.2, -0.2), (0.2, 0.2), (-0.2, 0.2)]
    assert query(rock)[0] == kn.CONTACT  # wholly under the hull
    island = [(-20.0, -20.0), (20.0, -20.0), (20.0, 20.0), (-20.0, 20.0)]
    assert query(island)[0] == kn.CONTACT  # hull wholly inside
    assert query(island, n0=22.0)[0] == kn.CONTACT  # bow over the edge: outlines cross
    flag, clearance = query(island, n0=30.0)
    assert flag == kn.OK and clearance == pytest.approx(30.0 - 3.5 - 20.0)
