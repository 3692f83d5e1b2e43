"""Hyperparameter files, run configuration, names and the evaluation metrics (fast)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import yaml

from agents import common
from agents.common import UsageError
from vessel_gym.envs.registration import registered
from vessel_gym.policy import sb3_algorithm

ENV_IDS = sorted(registered())


@pytest.mark.parametrize("algo", sorted(common.ALGOS))
def test_every_hyperparameter_block_is_valid(algo: str) -> None:
    """Every block of the file names a registered id, and every registered id gets a valid configuration (its
    task's defaults, with its block merged over them if it has one)."""
    data = yaml.safe_load((common.HYPERPARAMS_DIR / f"{algo}.yml").read_text())
    assert set(data) <= set(ENV_IDS), f"{algo}.yml has blocks of unregistered ids: {set(data) - set(ENV_IDS)}"
    for env_id in ENV_IDS:
        cfg = common.run_config(algo, env_id, common.load_hyperparams(algo, env_id))
        assert cfg.n_timesteps >= 1000 and cfg.n_envs >= 1
        common.make_env(env_id, cfg.env_kwargs).close()
        common.make_env(env_id, cfg.eval_env_kwargs).close()
        if cfg.normalize is not None:
            assert set(cfg.normalize) >= {"norm_obs", "norm_reward"}, f"{algo}.yml {env_id}: {cfg.normalize}"


def test_load_policy_applies_the_observation_statistics_saved_with_a_model() -> None:
    """A model trained on normalised observations (Berthing-v0's defaults) acts on them wherever it is loaded
    (``vessel_gym.policy.load_policy``: evaluation, ``serve``, the classroom), not on raw observations."""
    import numpy as np

    from vessel_gym.policy import load_policy

    path = common.HYPERPARAMS_DIR.parent / "trained" / "ppo_Berthing-v0_seed0.zip"
    env = common.make_env("vessel_gym/Berthing-v0", {})
    try:
        obs, _ = env.reset(seed=0)
        policy = load_policy(str(path), env)
        assert policy.stats is not None and policy.stats.norm_obs and not policy.stats.training
        normalised = policy.stats.normalize_obs(np.asarray(obs, dtype=np.float32))
        assert not np.allclose(normalised, obs)  # the statistics change what the model sees
        expected, _ = policy.model.predict(normalised, deterministic=True)
        assert np.array_equal(policy(obs), expected)
    finally:
        env.close()


def test_unknown_hyperparameter_is_named() -> None:
    hp = common.load_hyperparams("ppo", "vessel_gym/ZigZag-v1", overrides={"n_step": 64})
    with pytest.raises(UsageError, match="n_step"):
        common.run_config("ppo", "vessel_gym/ZigZag-v1", hp)


@pytest.mark.parametrize(
    "override, match",
    [
        ({"n_timesteps": -5}, "n_timesteps"),
        ({"n_envs": 1.5}, "n_envs"),
        ({"learning_rate": "fast"}, "learning_rate"),
        ({"policy_kwargs": {"activation_fn": "sigmoid"}}, "activation_fn"),
        ({"normalize": {"norm_obz": True}}, "norm_obz"),
        ({"env_kwargs": [1, 2]}, "env_kwargs"),
    ],
)
def test_bad_values_raise_with_the_key(override: dict, match: str) -> None:
    hp = common.load_hyperparams("ppo", "vessel_gym/ZigZag-v1", overrides=override)
    with pytest.raises(UsageError, match=match):
        common.run_config("ppo", "vessel_gym/ZigZag-v1", hp)


def test_linear_schedule_and_nested_overrides() -> None:
    over = common.parse_assignments(
        ["learning_rate=lin_1e-3", "policy_kwargs.net_arch=[32, 32]", "env_kwargs.reward.overshoot=2"], "x"
    )
    hp = common.load_hyperparams("ppo", "vessel_gym/ZigZagRandom-v1", overrides=over)
    cfg = common.run_config("ppo", "vessel_gym/ZigZagRandom-v1", hp)
    assert cfg.algo_kwargs["learning_rate"](0.5) == pytest.approx(5e-4)
    assert cfg.policy_kwargs["net_arch"] == [32, 32]
    assert cfg.env_kwargs["reward"]["overshoot"] == 2
    assert cfg.env_kwargs["reward"]["rudder_activity"] == 0.5  # merged into the file's other reward weights


def test_missing_block_and_file(tmp_path: Path) -> None:
    f = tmp_path / "h.yml"
    f.write_text("vessel_gym/ZigZag-v1: {n_timesteps: 1000}\n")
    assert common.load_hyperparams("ppo", "vessel_gym/ZigZag-v1", f)["n_timesteps"] == 1000
    # an id without a block trains on its task's declared defaults
    hp = common.load_hyperparams("ppo", "vessel_gym/HarbourApproach-v2", f)
    assert hp == common.task_defaults("ppo", "vessel_gym/HarbourApproach-v2") and hp["n_timesteps"] >= 100_000
    with pytest.raises(UsageError, match="no registered task id"):
        common.load_hyperparams("ppo", "vessel_gym/CartPole-v1", f)
    with pytest.raises(UsageError, match="cannot read"):
        common.load_hyperparams("ppo", "vessel_gym/ZigZag-v1", tmp_path / "nope.yml")
    f.write_text("[1, 2")
    with pytest.raises(UsageError, match="not valid YAML"):
        common.load_hyperparams("ppo", "vessel_gym/ZigZag-v1", f)


@pytest.mark.parametrize("bad", ["key", "=1", "a=[1,"])
def test_parse_assignments_rejects(bad: str) -> None:
    with pytest.raises(UsageError):
        common.parse_assignments([bad], "--hyperparams")


def test_names() -> None:
    assert common.resolve_env_id("ZigZag-v1") == "vessel_gym/ZigZag-v1"
    with pytest.raises(UsageError, match="unknown environment"):
        common.resolve_env_id("CartPole-v1")
    with pytest.raises(UsageError, match="unknown algorithm"):
        common.check_algo("dqn")
    for algo in common.ALGOS:
        stem = common.model_stem(algo, "vessel_gym/HarbourApproach-v2", 3)
        assert stem == f"{algo}_HarbourApproach-v2_s3"
        assert sb3_algorithm(f"runs/{stem}.zip") == common.ALGOS[algo]


def test_baseline_metrics_zigzag() -> None:
    kw = {"first_change_s": [0.0, 0.0]}  # the schedule from the first step on: the rule's rudder always 10 deg
    res = common.evaluate("ZigZag-v1", "scripted", episodes=1, seed=0, env_kwargs=kw)
    s = res["summary"]
    assert s["episodes"] == 1 and res["env_kwargs"] == kw
    # the scripted rule in the registered env is the IMO 10/10 zig-zag: +-10 deg rudder, overshoots measured
    assert s["rudder_deg_mean"] == pytest.approx(10.0, abs=1e-6)
    assert s["overshoot_deg_mean"] > 1.0 and s["reached_pct_mean"] > 50.0
    ep = res["episodes"][0]
    assert ep["length"] == 480 and math.isfinite(ep["return"])


def test_baseline_metrics_harbour_and_turning() -> None:
    h = common.evaluate("HarbourApproach-v2", "pid", episodes=1, seed=0)["summary"]
    assert h["success_rate"] == 1.0 and h["outcomes"] == {"success": 1}
    assert h["min_clearance_m_mean"] > 0.0
    t = common.evaluate("TurningCircle-v0", "pid", episodes=1, seed=0)["summary"]
    assert 0.0 < t["rate_error_pct_mean"] < 20.0


def test_evaluate_rejects_bad_input(tmp_path: Path) -> None:
    with pytest.raises(UsageError, match="no such file"):
        common.evaluate("ZigZag-v1", str(tmp_path / "ppo_x.zip"), 1)
    with pytest.raises(UsageError, match="episodes"):
        common.evaluate("ZigZag-v1", "pid", 0)
    with pytest.raises(UsageError, match="schedul"):
        common.evaluate("ZigZag-v1", "pid", 1, env_kwargs={"schedul": "random"})
    bogus = tmp_path / "ppo_bogus.zip"
    bogus.write_bytes(b"not a zip")
    with pytest.raises(UsageError, match="cannot load"):
        common.evaluate("ZigZag-v1", str(bogus), 1)


@pytest.mark.parametrize("env_id", ["vessel_gym/ZigZag-v1", "vessel_gym/ZigZagRandom-v1"])
def test_zigzag_v1_metrics_are_the_environments_own(env_id):
    """On ZigZag-v1 the evaluation reports the environment's per-course-change overshoot (the open
    measurement included), its targets reached and its success, not a recount."""
    import gymnasium as gym

    from vessel_gym.envs.policies import PIDHeadingAutopilot

    env = gym.make(env_id)
    policy = PIDHeadingAutopilot(env, Kp=3.0, Kd=1.5)
    m = common.run_episode(env, policy, seed=4)
    twin = gym.make(env_id)
    obs, _ = twin.reset(seed=4)
    policy.reset()
    while True:
        obs, _r, te, tr, info = twin.step(policy(obs))
        if te or tr:
            break
    assert m["overshoot_deg"] == info["overshoot_deg"] > 0.0
    assert m["max_overshoot_deg"] == info["max_overshoot_deg"]
    assert m["course_changes"] == info["course_changes"]
    assert m["reached_pct"] == pytest.approx(100.0 * info["targets_reached"] / info["course_changes"])
    assert m["success"] is info["is_success"]
