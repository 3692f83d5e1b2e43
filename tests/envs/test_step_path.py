"""One step path: every step of an environment runs the same calls (helm, physics, task update), whatever its step
count; a paced step (the hook `vessel-gym serve` paces its physics with) makes the same physics steps as an
unpaced one, in slices, calling its tick after each; a helm override holds through the step, and a NaN action
changes nothing."""

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


def test_a_late_step_is_the_same_as_an_early_one():
    """No step implementation is swapped in after some steps: a fresh environment set to another's state
    makes the same step as the one that has stepped for 200 steps."""
    old, fresh = gym.make("vessel_gym/ZigZag-v1").unwrapped, gym.make("vessel_gym/ZigZag-v1").unwrapped
    old.reset(seed=4)
    old.action_space.seed(2)
    for _ in range(200):
        if any(old.step(old.action_space.sample())[2:4]):
            old.reset()
    fresh.reset(seed=4)
    for name in ("state", "inputs", "alive"):
        getattr(fresh.sim, name)[:] = getattr(old.sim, name)
    fresh.sim.t = old.sim.t
    fresh.task.ts[:] = old.task.ts
    fresh._elapsed = old._elapsed
    a = old.action_space.sample()
    r_old, r_fresh = old.step(a), fresh.step(a)
    assert np.array_equal(r_old[0], r_fresh[0]) and r_old[1:] == r_fresh[1:]


def test_helm_override_holds_through_the_step():
    """While a panel holds the helm, the step gives the orders through set_helm, which keeps the override."""
    env = gym.make("vessel_gym/ZigZag-v1")
    env.reset(seed=3)
    a = np.array([0.7], dtype=np.float32)
    env.step(a)
    env.unwrapped.sim.override_helm(0, rudder_order_rad=-0.2)
    for _ in range(5):
        env.step(a)
        assert env.unwrapped.sim.rudder_order[0] == -0.2
    env.unwrapped.sim.override_helm(0)  # handed back
    env.step(a)
    assert env.unwrapped.sim.rudder_order[0] != -0.2


@pytest.mark.parametrize("kw", [{}, {"engine_control": True}, {"action_type": "discrete"}])
def test_nan_action_raises_and_changes_nothing(kw):
    env = gym.make("vessel_gym/TurningCircle-v0", **kw)
    env.reset(seed=1)
    env.step(env.action_space.sample())
    sim = env.unwrapped.sim
    state, inputs, t = sim.state.copy(), sim.inputs.copy(), sim.t
    bad = np.full(env.action_space.shape or (1,), np.nan, dtype=np.float32)
    with pytest.raises(ValueError, match="NaN"):
        env.step(bad)
    assert np.array_equal(sim.state, state) and np.array_equal(sim.inputs, inputs) and sim.t == t


def test_no_code_replaces_a_step_method_on_an_instance():
    """Pacing is declared (ShipEnv.pace), not patched in: nothing in the package assigns to an object's
    ``advance``, ``update`` or ``step`` (serve once replaced the task's advance on the instance)."""
    import ast
    from pathlib import Path

    package = Path(vessel_gym.__file__).resolve().parent
    found = []
    for path in package.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            targets = node.targets if isinstance(node, ast.Assign) else []
            for t in targets:
                if isinstance(t, ast.Attribute) and t.attr in ("advance", "update", "step"):
                    found.append(f"{path.relative_to(package)}:{node.lineno}")
    assert not found, found
