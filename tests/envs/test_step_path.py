"""One step path: a paced step (the hook `vessel-gym serve` paces its physics with) makes the same physics steps
as an unpaced one, in slices, calling its tick after each."""

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym  # noqa: F401


def _twins(env_id, ticks_per_step):
    """Two environments of ``env_id`` whose control step is four physics steps, one of them paced."""
    probe = gym.make(env_id).unwrapped
    dt = probe.config.control_interval_s / 4
    plain, paced = gym.make(env_id, dt_s=dt).unwrapped, gym.make(env_id, dt_s=dt).unwrapped
    assert paced.task.nsub == 4
    ticks: list[tuple[int, float]] = []
    paced.pace(ticks_per_step, lambda i: ticks.append((i, paced.sim.t)))
    return plain, paced, ticks


@pytest.mark.parametrize("ticks_per_step", [1, 2, 4, 6])
def test_a_paced_step_ticks_after_each_slice_and_makes_the_same_steps(ticks_per_step):
    plain, paced, ticks = _twins("vessel_gym/ZigZag-v1", ticks_per_step)
    for env in (plain, paced):
        env.reset(seed=3)
        env.action_space.seed(1)
    dt = paced.task.dt
    for step in range(6):
        a = plain.action_space.sample()
        r1, r2 = plain.step(a), paced.step(a)
        assert np.array_equal(r1[0], r2[0]) and r1[1:4] == r2[1:4] and r1[4] == r2[4]
        got = ticks[step * ticks_per_step : (step + 1) * ticks_per_step]
        assert [i for i, _t in got] == list(range(1, ticks_per_step + 1))
        # after slice i the physics has made i * nsub // ticks of this control step's four steps
        t0 = step * 4 * dt
        made = [round((t - t0) / dt) for _i, t in got]
        assert made == [i * 4 // ticks_per_step for i in range(1, ticks_per_step + 1)]
    assert len(ticks) == 6 * ticks_per_step
    assert np.array_equal(plain.sim.state, paced.sim.state)


def test_pace_without_a_tick_steps_at_once_again():
    _plain, paced, ticks = _twins("vessel_gym/ZigZag-v1", 2)
    paced.reset(seed=0)
    paced.step(paced.action_space.sample())
    paced.pace()
    paced.step(paced.action_space.sample())
    assert len(ticks) == 2


def test_pace_refuses_fewer_than_one_tick():
    env = gym.make("vessel_gym/ZigZag-v1").unwrapped
    with pytest.raises(ValueError, match="ticks must be >= 1"):
        env.pace(0, print)
