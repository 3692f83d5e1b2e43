"""End to end: a few thousand training steps per environment, the saved model loads through evaluate.py's
function and ``vessel_gym.policy.load_policy`` and drives an episode or two."""

from __future__ import annotations

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import yaml

from agents import common, evaluate, train
from vessel_gym.policy import load_policy

pytestmark = pytest.mark.slow

ENV_IDS = ["vessel_gym/ZigZag-v1", "vessel_gym/TurningCircle-v0", "vessel_gym/HarbourApproach-v2"]
SMALL = {"n_steps": 256, "batch_size": 256, "n_epochs": 2}


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_ppo_trains_saves_loads_and_evaluates(env_id: str, tmp_path: Path) -> None:
    res = common.train("ppo", env_id, seed=1, timesteps=2048, n_envs=4, out=tmp_path, overrides=SMALL)
    stem = f"ppo_{env_id.split('/')[-1]}_s1"
    assert res.model_path == tmp_path / f"{stem}.zip" and res.model_path.is_file()
    assert res.n_timesteps >= 2048 and not res.budget_hit
    rec = yaml.safe_load(res.record_path.read_text())
    assert rec["env_id"] == env_id and rec["algo"] == "ppo" and rec["seed"] == 1
    progress = tmp_path / "logs" / stem / "progress.csv"
    assert progress.is_file() and "time/total_timesteps" in progress.read_text().splitlines()[0]
    assert list((tmp_path / "checkpoints").glob(f"{stem}_*_steps.zip"))

    # evaluate.py's function, with the environment arguments of the run record
    out = common.evaluate(env_id, res.model_path, episodes=2, seed=5)
    assert out["env_kwargs"] == rec["eval_env_kwargs"]
    assert out["summary"]["episodes"] == 2 and np.isfinite(out["summary"]["return_mean"])
    # the same episodes twice: deterministic
    again = common.evaluate(env_id, res.model_path, episodes=2, seed=5)
    assert again["summary"]["return_mean"] == pytest.approx(out["summary"]["return_mean"])

    # vessel_gym.policy.load_policy (what `vessel-gym serve --agent` uses)
    env = gym.make(env_id, **rec["eval_env_kwargs"])
    policy = load_policy(str(res.model_path), env)
    obs, _ = env.reset(seed=0)
    policy.reset()
    for _ in range(20):
        action = policy(obs)
        assert env.action_space.contains(np.asarray(action, dtype=np.float32))
        obs, *_ = env.step(action)
    env.close()


def test_sac_and_td3_train_and_load(tmp_path: Path) -> None:
    for algo in ("sac", "td3"):
        res = common.train(
            algo,
            "ZigZag-v1",
            seed=0,
            timesteps=600,
            out=tmp_path,
            overrides={"learning_starts": 200, "buffer_size": 1000, "batch_size": 64},
        )
        assert res.model_path.name == f"{algo}_ZigZag-v1_s0.zip"
        out = common.evaluate("ZigZag-v1", res.model_path, episodes=1)
        assert out["summary"]["episodes"] == 1


def test_a2c_subproc_vec_env(tmp_path: Path) -> None:
    """--vec subproc: the workers register the ids themselves."""
    res = common.train("a2c", "ZigZag-v1", seed=0, timesteps=320, n_envs=2, vec="subproc", out=tmp_path)
    rec = yaml.safe_load(res.record_path.read_text())
    assert rec["vec"] == "subproc" and rec["n_envs"] == 2
    assert common.evaluate("ZigZag-v1", res.model_path, episodes=1)["summary"]["episodes"] == 1


def test_vecnormalize_statistics_are_applied(tmp_path: Path) -> None:
    """normalize with norm_obs: the statistics are saved next to the model and used by evaluate()."""
    over = {**SMALL, "normalize": {"norm_obs": True, "norm_reward": True}}
    res = common.train("ppo", "ZigZag-v1", seed=0, timesteps=512, n_envs=2, out=tmp_path, overrides=over)
    assert res.vecnormalize_path is not None and res.vecnormalize_path.is_file()
    env = common.make_env("vessel_gym/ZigZag-v1", {"schedule": "random"})
    policy = common.load_agent(res.model_path, env)
    assert policy.stats is not None and policy.stats.norm_obs and not policy.stats.training
    obs, _ = env.reset(seed=0)
    assert env.action_space.contains(np.asarray(policy(obs), dtype=np.float32))


def test_time_budget_stops_training(tmp_path: Path) -> None:
    res = common.train(
        "ppo",
        "ZigZag-v1",
        seed=0,
        timesteps=10**7,
        n_envs=2,
        out=tmp_path,
        overrides=SMALL,
        time_budget_s=3.0,
    )
    assert res.budget_hit and res.n_timesteps < 10**7 and res.model_path.is_file()


def test_periodic_evaluation_keeps_the_best_model(tmp_path: Path) -> None:
    res = common.train(
        "ppo", "ZigZagRandom-v1", seed=0, timesteps=2048, n_envs=2, out=tmp_path, overrides=SMALL, eval_freq=1024
    )
    assert res.best_model_path == tmp_path / "ppo_ZigZagRandom-v1_s0_best.zip" and res.best_model_path.is_file()
    rec = yaml.safe_load(res.best_model_path.with_suffix(".yml").read_text())
    assert rec["selected_at_timesteps"] in (1024, 2048) and rec["selected_from"] == "ppo_ZigZagRandom-v1_s0.zip"
    env = gym.make("vessel_gym/ZigZagRandom-v1", **rec["eval_env_kwargs"])
    policy = load_policy(str(res.best_model_path), env)  # the <algo>_ prefix names the class
    obs, _ = env.reset(seed=0)
    assert env.action_space.contains(np.asarray(policy(obs), dtype=np.float32))
    assert common.evaluate("ZigZagRandom-v1", res.best_model_path, episodes=1)["env_kwargs"] == {}


def test_train_and_evaluate_command_lines(tmp_path: Path, capsys) -> None:
    argv = ["--env", "ZigZagRandom-v1", "--algo", "ppo", "--seed", "2", "--timesteps", "512", "--n-envs", "2"]
    argv += ["--out", str(tmp_path), "--no-progress", "--log-format", "csv", "--hyperparams", "n_steps=256"]
    assert train.main([*argv, "--test-episodes", "2"]) == 0
    model = tmp_path / "ppo_ZigZagRandom-v1_s2.zip"
    text = capsys.readouterr().out
    assert (
        model.is_file()
        and "saved" in text
        and "test (final model, 2 episodes, seeds 2000000..2000001)" in text
    )
    assert evaluate.main(["--env", "ZigZagRandom-v1", "--agent", str(model), "--episodes", "1"]) == 0
    text = capsys.readouterr().out
    assert "mean |heading error| (deg)" in text
    # a model of one environment is refused on another
    assert evaluate.main(["--env", "TurningCircle-v0", "--agent", str(model), "--episodes", "1"]) == 2
    assert "trained on vessel_gym/ZigZagRandom-v1" in capsys.readouterr().err
