"""Training on the native vector environment (the default): a few hundred PPO steps on 4 ships with the
periodic evaluation on the validation seeds, the final evaluation on the test seeds, TensorBoard logging and
the success rate of HarbourApproach logged from ``info["is_success"]``."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
import yaml

from agents import common, seeds, train

SMALL = {"n_steps": 64, "batch_size": 128, "n_epochs": 1}


@pytest.mark.slow  # about 10 s: HarbourApproach's first compile, training, 2 evaluations, 2 test episodes
def test_ppo_on_native_vector_ships_validates_and_tests(tmp_path: Path) -> None:
    pytest.importorskip("tensorboard")
    over = {**SMALL, "env_kwargs": {"max_episode_steps": 40}, "eval_env_kwargs": {"max_episode_steps": 40}}
    res = common.train(
        "ppo",
        "HarbourApproach-v2",
        seed=3,
        timesteps=512,
        n_envs=4,
        out=tmp_path,
        overrides=over,
        log_formats=("csv", "tensorboard"),
        eval_freq=256,
        eval_episodes=3,
        test_episodes=2,
    )
    stem = "ppo_HarbourApproach-v2_s3"
    rec = yaml.safe_load(res.record_path.read_text())
    assert rec["vec"] == "native" and rec["num_timesteps"] == 512
    assert rec["validation_seeds"] == f"{seeds.VALIDATION_START}..{seeds.VALIDATION_START + 2}"
    # the final evaluation: test seeds, the metrics of evaluate()
    assert rec["test"]["seeds"] == f"{seeds.TEST_START}..{seeds.TEST_START + 1}"
    assert rec["test"]["episodes"] == 2 and "success_rate" in rec["test"]
    assert res.test["final"] == rec["test"] and "best" in res.test
    again = common.evaluate("HarbourApproach-v2", res.model_path, 2, seeds.TEST_START)["summary"]
    assert again["return_mean"] == pytest.approx(rec["test"]["return_mean"])

    logs = tmp_path / "logs" / stem
    assert list(logs.glob("events.out.tfevents.*"))  # --log-format tensorboard
    rows = list(csv.DictReader((logs / "progress.csv").open()))
    header = rows[0].keys()
    assert "rollout/success_rate" in header and "eval/success_rate" in header  # from info["is_success"]
    # every periodic evaluation ran the same validation episodes: deterministic policy, same starts
    ev = np.load(logs / "evaluations.npz")
    assert ev["results"].shape == (2, 3) and ev["timesteps"].tolist() == [256, 512]


def test_fixed_validation_episodes_do_not_change_between_evaluations(tmp_path: Path) -> None:
    """With learning_rate 0 the policy stays the same, so every periodic evaluation must score the same."""
    over = {**SMALL, "learning_rate": 0.0, "env_kwargs": {"max_episode_steps": 30}}
    over["eval_env_kwargs"] = {"schedule": "random", "max_episode_steps": 30}
    over["env_kwargs"]["schedule"] = "random"
    common.train(
        "ppo",
        "ZigZag-v1",
        seed=0,
        timesteps=768,
        n_envs=4,
        out=tmp_path,
        overrides=over,
        eval_freq=256,
        eval_episodes=3,
    )
    ev = np.load(tmp_path / "logs" / "ppo_ZigZag-v1_s0" / "evaluations.npz")
    assert ev["results"].shape == (3, 3)
    np.testing.assert_array_equal(ev["results"][1:], np.broadcast_to(ev["results"][0], (2, 3)))


def test_training_seed_must_stay_below_the_validation_set(tmp_path: Path, capsys) -> None:
    argv = ["--env", "ZigZag-v1", "--algo", "ppo", "--seed", str(seeds.VALIDATION_START - 2)]
    argv += ["--n-envs", "4", "--out", str(tmp_path)]
    assert train.main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "validation and test episodes use seeds" in err
