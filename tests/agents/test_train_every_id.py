"""Every registered id trains: ``agents/train.py --env <id>`` finds its hyperparameters (the task's declared
defaults, with the id's block of agents/hyperparams/<algo>.yml merged over them) and runs a tiny budget."""

from __future__ import annotations

from pathlib import Path

import pytest

from agents import train
from agents.config import load_hyperparams, run_config
from vessel_gym.envs.registration import registered

IDS = sorted(registered())


@pytest.mark.parametrize("algo", ["ppo", "a2c", "sac", "td3"])
@pytest.mark.parametrize("env_id", IDS)
def test_every_id_has_hyperparameters(env_id: str, algo: str) -> None:
    pytest.importorskip("stable_baselines3")
    cfg = run_config(algo, env_id, load_hyperparams(algo, env_id))
    assert cfg.n_timesteps >= 100_000 and cfg.n_envs >= 1 and cfg.policy == "MlpPolicy"


@pytest.mark.parametrize("env_id", IDS)  # 0.4-8 s each (the first of a task compiles its kernels)
def test_train_py_runs_every_id(env_id: str, tmp_path: Path) -> None:
    pytest.importorskip("stable_baselines3")
    argv = ["--env", env_id.split("/")[1], "--algo", "ppo", "--timesteps", "256", "--n-envs", "2", "--out"]
    argv += [str(tmp_path), "--hyperparams", "n_steps=64", "batch_size=64", "n_epochs=1", "--test-episodes", "0"]
    argv += ["--no-progress", "--log-format", "csv"]
    assert train.main(argv) == 0
    assert (tmp_path / f"ppo_{env_id.split('/')[1]}_s0.zip").is_file()
