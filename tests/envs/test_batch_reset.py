"""The vector environments' batched reset: one Simulation.reset over an index array equals one scalar reset
per vessel, and the per-vessel generators are made only when drawn from, with the stream of seed + k."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils import seeding

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.envs.generators import SeedRange, VesselGenerators, pcg64_seed_words
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.simulation import Simulation


def test_reset_of_an_index_array_equals_scalar_resets():
    wind = Environment(wind_speed_m_s=12.0, wind_from_deg=30.0)
    idx = np.array([5, 1, 8, 2])
    speed = np.array([6.0, 7.5, 6.0, 8.0])  # m/s
    heading = np.array([10.0, 200.0, 10.0, 355.0])  # deg
    north, east = np.array([1.0, 2.0, 3.0, 4.0]), np.array([-1.0, 0.0, 5.0, 6.0])  # m
    batch = Simulation(["kvlcc2", "mariner"], n=10, ship_index=[0, 1] * 5)
    one = Simulation(["kvlcc2", "mariner"], n=10, ship_index=[0, 1] * 5)
    for sim in (batch, one):
        for k in (1, 8):  # directional environments: the heading is part of the solved approach
            sim.set_environment(wind, k)
        sim.step(3)  # the vessels not reset keep their state
    batch.reset(speed_m_s=speed, heading_deg=heading, x_m=north, y_m=east, k=idx)
    for j, k in enumerate(idx.tolist()):
        one.reset(speed_m_s=speed[j], heading_deg=heading[j], x_m=north[j], y_m=east[j], k=k)
    assert np.array_equal(batch.state, one.state)
    assert np.array_equal(batch.inputs, one.inputs)
    assert np.array_equal(batch.alive, one.alive)


def test_a_reset_that_draws_nothing_makes_no_generator():
    env = gym.make_vec("vessel_gym/ZigZag-v1", num_envs=4, vectorization_mode="vector_entry_point")
    fixed = gym.make_vec(
        "vessel_gym/ZigZag-v1", num_envs=4, vectorization_mode="vector_entry_point"
    )  # ZigZag-v1's defaults: heading 0, first side starboard, no draw
    env.reset(seed=7)
    fixed.reset(seed=7)
    assert all(g is None for g in fixed.unwrapped._rngs._made)
    for k in range(4):  # vessel k drew from seed 7 + k exactly what a single environment's reset draws
        single = gym.make("vessel_gym/ZigZag-v1")
        single.reset(seed=7 + k)
        assert env.unwrapped._rngs[k].bit_generator.state == single.unwrapped.np_random.bit_generator.state
        single.close()
    assert seeding.np_random(7)[0].bit_generator.state != env.unwrapped._rngs[0].bit_generator.state
    env.close()
    fixed.close()


@pytest.mark.parametrize("seed", [[0, -1], [0, 1.5]])
def test_a_bad_seed_is_refused_at_the_reset(seed):
    env = gym.make_vec("vessel_gym/ZigZag-v1", num_envs=2, vectorization_mode="vector_entry_point")
    with pytest.raises(gym.error.Error):
        env.reset(seed=seed)
    env.close()


def test_seed_words_hashed_at_once_equal_numpys_seed_sequence():
    seeds = np.r_[np.arange(0, 300), np.random.default_rng(1).integers(0, 2**32, 300), 2**32 - 1]
    words = pcg64_seed_words(seeds)
    for s, w in zip(seeds.tolist(), words):
        assert np.array_equal(w, np.random.SeedSequence(s).generate_state(4, np.uint64))
    gens = VesselGenerators([3, None, 2**40, 9])  # one-word seeds hashed at once, the others by numpy
    for k, s in ((0, 3), (2, 2**40), (3, 9)):
        assert gens[k].bit_generator.state == seeding.np_random(s)[0].bit_generator.state
    assert gens[1].random() != gens[1].random()


def test_batch_draws_are_each_vessels_numpy_stream_bit_for_bit():
    """Numbers drawn for many vessels at once (the PCG64 step and next_double in compiled code) are those each
    vessel's numpy Generator gives, in any mix with draws through the Generator itself (integers, normals:
    the stream passes between the two) and after a reseed."""
    seeds = [0, 1, None, 2**40, 2**32 - 1, 6]
    gens = VesselGenerators(seeds)
    refs = [seeding.np_random(s)[0] for s in seeds]
    refs[2] = gens[2]  # fresh entropy: its own generator is the reference
    idx = np.array([0, 1, 3, 4, 5])
    rng = np.random.default_rng(3)
    for _ in range(600):
        what = rng.random()
        if what < 0.3:
            lo, hi = np.sort(rng.normal(size=2) * 10.0 ** rng.integers(-3, 6))
            got, want = gens.draws(idx).uniform(lo, hi), [refs[k].uniform(lo, hi) for k in idx]
        elif what < 0.5:
            got, want = gens.draws(idx).random(), [refs[k].random() for k in idx]
        elif what < 0.75:
            k = int(rng.choice(idx))
            got, want = [gens[k].integers(0, 7)], [refs[k].integers(0, 7)]  # 32-bit draws, buffered
        else:
            k = int(rng.choice(idx))
            got, want = [gens[k].standard_normal()], [refs[k].standard_normal()]
        assert np.array_equal(got, want)
    for k in idx.tolist():
        assert gens[k].bit_generator.state == refs[k].bit_generator.state
    gens.reseed(SeedRange(2**32 - 2, 6))  # one-word seeds, then numpy's hash for the others
    draws = gens.draws(np.arange(6))
    assert np.array_equal(draws.random(), [seeding.np_random(2**32 - 2 + k)[0].random() for k in range(6)])

