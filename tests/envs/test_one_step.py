"""The one-ship step in one compiled call (vessel_gym/envs/onestep.py) gives the separate calls' results to the bit:
an environment stepping through it and a twin held on the separate calls (helm, Simulation.step, task update)
return the same observations, rewards, ends and infos over whole episodes; a helm override, a batch that no
longer fits the bound driver, a NaN action and Python components take or keep the separate calls' path; an
environment binds it only after ONE_CALL_AFTER_STEPS steps."""

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym  # noqa: F401
from vessel_gym.envs import env as env_module
from vessel_gym.physics.environment import Environment


@pytest.fixture(autouse=True)
def bind_at_once(monkeypatch):
    """The environments here bind their one-call step after their first step (not ONE_CALL_AFTER_STEPS)."""
    monkeypatch.setattr(env_module, "ONE_CALL_AFTER_STEPS", 1)

CASES = [
    ("vessel_gym/ZigZag-v1", {}),
    ("vessel_gym/ZigZag-v1", {"action_type": "discrete", "engine_control": True}),
    ("vessel_gym/ZigZagRandom-v1", {}),
    ("vessel_gym/TurningCircle-v0", {"engine_control": True}),
    ("vessel_gym/HarbourApproach-v1", {}),
    ("vessel_gym/HarbourApproach-v2", {}),
]


def _pair(env_id, kw, seed=3):
    fused, separate = gym.make(env_id, **kw), gym.make(env_id, **kw)
    separate.unwrapped._fast = False  # never bound: the separate calls at every step
    for env in (fused, separate):
        env.reset(seed=seed)
    return fused, separate


def _same_step(r1, r2):
    o1, rew1, term1, trunc1, info1 = r1
    o2, rew2, term2, trunc2, info2 = r2
    assert np.array_equal(o1, o2)
    assert (rew1, term1, trunc1) == (rew2, term2, trunc2)
    assert type(rew1) is type(rew2) and type(term1) is type(term2) and type(trunc1) is type(trunc2)
    assert dict(info1) == dict(info2)


@pytest.mark.parametrize("env_id,kw", CASES)
def test_one_compiled_call_equals_the_separate_calls(env_id, kw):
    fused, separate = _pair(env_id, kw)
    fused.action_space.seed(5)
    resets = 0
    for i in range(150):
        a = fused.action_space.sample()
        r1, r2 = fused.step(a), separate.step(a)
        _same_step(r1, r2)
        if i == 0:
            assert fused.unwrapped._fast, "bound after the first step"
        assert fused.unwrapped.sim.t == separate.unwrapped.sim.t
        if r1[2] or r1[3]:
            o1, i1 = fused.reset()
            o2, i2 = separate.reset()
            assert np.array_equal(o1, o2) and dict(i1) == dict(i2)
            resets += 1
    assert np.array_equal(fused.unwrapped.sim.state, separate.unwrapped.sim.state)
    assert np.array_equal(fused.unwrapped.task.ts, separate.unwrapped.task.ts)


def test_python_components_keep_the_separate_calls():
    """The supply ship's gearbox is a Python component: its steps go through Simulation.step's general path."""
    fused, separate = _pair("vessel_gym/ZigZag-v1", {"ship": "supply"})
    for _ in range(5):
        a = fused.action_space.sample()
        _same_step(fused.step(a), separate.step(a))
    assert fused.unwrapped._fast is False
    assert fused.unwrapped.sim.components


def test_helm_override_holds_through_the_step():
    """While a panel holds the helm, the step gives the orders through set_helm, which keeps the override."""
    fused, separate = _pair("vessel_gym/ZigZag-v1", {})
    a = np.array([0.7], dtype=np.float32)
    for env in (fused, separate):
        env.step(a)
        env.unwrapped.sim.override_helm(0, rudder_order_rad=-0.2)
    for _ in range(5):
        _same_step(fused.step(a), separate.step(a))
        assert fused.unwrapped.sim.rudder_order[0] == -0.2
    for env in (fused, separate):
        env.unwrapped.sim.override_helm(0)  # handed back
    for _ in range(5):
        _same_step(fused.step(a), separate.step(a))
    assert fused.unwrapped.sim.rudder_order[0] != -0.2


def test_a_batch_the_bound_driver_no_longer_fits_takes_the_separate_calls_once():
    """Shallow water set after the binding needs another driver kind: that step is integrated by
    Simulation.step, which chooses it, and the next steps bind it."""
    fused, separate = _pair("vessel_gym/HarbourApproach-v1", {})
    a = np.array([0.3, 0.5], dtype=np.float32)
    _same_step(fused.step(a), separate.step(a))
    bound = fused.unwrapped._fast
    for env in (fused, separate):
        env.unwrapped.sim.set_environment(Environment(depth_m=1.0))
    for _ in range(5):
        _same_step(fused.step(a), separate.step(a))
    assert fused.unwrapped._fast and fused.unwrapped._fast[1] is not bound[1]


def test_nan_action_raises_and_changes_nothing():
    env = gym.make("vessel_gym/TurningCircle-v0", engine_control=True)
    env.reset(seed=1)
    env.step(np.zeros(2, dtype=np.float32))
    assert env.unwrapped._fast
    sim = env.unwrapped.sim
    state, inputs, t = sim.state.copy(), sim.inputs.copy(), sim.t
    with pytest.raises(ValueError, match="NaN"):
        env.step(np.array([0.1, np.nan], dtype=np.float32))
    assert np.array_equal(sim.state, state) and np.array_equal(sim.inputs, inputs) and sim.t == t


def test_bound_only_after_the_steps_that_pay_for_it(monkeypatch):
    monkeypatch.setattr(env_module, "ONE_CALL_AFTER_STEPS", 4)
    env = gym.make("vessel_gym/ZigZag-v1")
    env.reset(seed=0)
    for _ in range(3):
        env.step(env.action_space.sample())
    assert env.unwrapped._fast is None
    env.reset(seed=1)  # counted over episodes
    env.step(env.action_space.sample())
    assert env.unwrapped._fast
