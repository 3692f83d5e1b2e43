"""The action filter of a hyperparameter block (agents/wrappers.py RudderRateLimit): the same on single and
native vector environments, applied in training and, from the run record or sidecar, in evaluation."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from agents import common

LIMIT = [{"RudderRateLimit": {"max_rate_deg_s": 2.32}}]


def _observations(venv, steps: int, seed: int = 0) -> np.ndarray:
    """Observations [step][ship] of random actions (the first one: the reset's)."""
    rng = np.random.default_rng(seed)
    obs = [venv.reset()]
    for _ in range(steps):
        obs.append(venv.step(rng.uniform(-1.0, 1.0, (venv.num_envs, 1)).astype(np.float32))[0])
    return np.asarray(obs)


def test_rate_limit_on_single_and_native_vector_environments_agree() -> None:
    """Random actions through the limit: the same observations on DummyVecEnv and the native vector
    environment (autoresets included), and no order changes faster than the limit."""
    kw = {"schedule": "random", "max_episode_steps": 29}
    ref = common.make_vec_env("vessel_gym/ZigZag-v1", 3, 4, "dummy", kw, env_wrapper=LIMIT)
    nat = common.make_vec_env("vessel_gym/ZigZag-v1", 3, 4, "native", kw, env_wrapper=LIMIT)
    try:
        a = _observations(ref, 70)
        b = _observations(nat, 70)
    finally:
        ref.close()
        nat.close()
    assert np.array_equal(a, b)
    env = common.make_env("vessel_gym/ZigZag-v1", kw)
    layout, dt = env.unwrapped.observation_layout, float(env.unwrapped.config.control_interval_s)
    env.close()
    order = np.degrees(a[..., layout.index("rudder_order")] * layout.scale[layout.index("rudder_order")])
    steps = np.abs(np.diff(order, axis=0))[:28]  # the first episode (29 steps) of every ship
    assert steps.max() == pytest.approx(2.32 * dt, rel=1e-4)  # random actions ask for more every step
    assert np.all(steps <= 2.32 * dt * (1 + 1e-5))


def test_evaluation_applies_the_filter() -> None:
    """The tuned pid behind a rate limit at the KVLCC2's full-scale gear rate (2.32 deg/s, far below the
    model's 15.8): mean order rate within the limit and a worse return than without it."""
    free = common.evaluate("ZigZagRandom-v1", "pid", 2, 2_000_000)
    slow = common.evaluate("ZigZagRandom-v1", "pid", 2, 2_000_000, action_filter=LIMIT)
    assert slow["action_filter"] == LIMIT and "action_filter" not in free
    assert max(e["rudder_rate_deg_s"] for e in slow["episodes"]) <= 2.32 + 1e-6
    assert free["summary"]["rudder_rate_deg_s_mean"] > 2.32
    assert slow["summary"]["return_mean"] < free["summary"]["return_mean"]


def test_a_bad_filter_is_refused_by_name() -> None:
    with pytest.raises(common.UsageError, match="no such wrapper class"):
        common.run_config("ppo", "vessel_gym/ZigZagRandom-v1", {"action_filter": ["NoSuchFilter"]})
    with pytest.raises(common.UsageError, match="max_rate_deg_s must be > 0"):
        common.make_env("vessel_gym/ZigZagRandom-v1", {}, [{"RudderRateLimit": {"max_rate_deg_s": 0.0}}])


@pytest.mark.slow
def test_training_records_the_filter_and_evaluation_reapplies_it(tmp_path: Path) -> None:
    """A tiny run with an action filter: the run record names it, and evaluate() of the saved model applies
    it without being told (the orders of its episodes stay within the limit)."""
    res = common.train(
        "ppo",
        "ZigZagRandom-v1",
        0,
        timesteps=256,
        n_envs=2,
        out=tmp_path,
        overrides={"action_filter": LIMIT},
    )
    assert common.run_record(res.model_path)["action_filter"] == LIMIT
    ev = common.evaluate("ZigZagRandom-v1", res.model_path, 1, 2_000_000)
    assert ev["action_filter"] == LIMIT
    assert ev["episodes"][0]["rudder_rate_deg_s"] <= 2.32 + 1e-6
    assert math.isfinite(ev["summary"]["return_mean"])
