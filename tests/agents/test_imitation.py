"""Behaviour cloning of the classical pilot by DAgger (agents/imitation.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from agents import common, imitation, results
from vessel_gym.envs.registration import declaration


def test_settings_block_checked(tmp_path: Path) -> None:
    st = imitation.load_bc_settings("HarbourApproach-v1")
    assert st["pilot"] == "pid" and st["rounds"] >= 2 and st["n_envs"] >= 1
    bad = tmp_path / "bc.yml"
    bad.write_text("vessel_gym/HarbourApproach-v1: {rounds: 2, epoch: 3}\n")
    with pytest.raises(common.UsageError, match="unknown key"):
        imitation.load_bc_settings("HarbourApproach-v1", bad)
    bad.write_text("vessel_gym/HarbourApproach-v1: {pilot: autopilot}\n")
    with pytest.raises(common.UsageError, match="pilot must be"):
        imitation.load_bc_settings("HarbourApproach-v1", bad)
    bad.write_text("vessel_gym/HarbourApproach-v1: [rounds, 2]\n")  # a list where a block belongs
    with pytest.raises(common.UsageError, match="HarbourApproach-v1: expected a mapping"):
        imitation.load_bc_settings("HarbourApproach-v1", bad)
    bad.write_text("vessel_gym/HarbourApproach-v1: {rounds: 0}\n")
    with pytest.raises(common.UsageError, match="rounds must be an integer >= 1"):
        imitation.load_bc_settings("HarbourApproach-v1", bad)
    with pytest.raises(common.UsageError, match="no behaviour-cloning block"):
        imitation.load_bc_settings("ZigZag-v1", bad)


@pytest.mark.parametrize("env_id", results.BC_PLAN)
def test_every_cloning_row_of_the_study_has_its_block(env_id: str) -> None:
    """results.py clones the pilot of every BC_PLAN environment: each has a bc.yml block whose pilot the
    task declares, so a study run does not stop at its cloning row."""
    st = imitation.load_bc_settings(env_id)
    assert st["pilot"] in declaration(env_id).pilots


def test_fit_regresses_the_mean_action_on_the_labels() -> None:
    """The supervised step drives the network's mean action to the labels (a smooth target in the
    action range); 30 epochs of Adam bring the MSE two orders of magnitude down from the start."""
    import torch
    from stable_baselines3 import PPO

    env = common.make_env(common.resolve_env_id("HarbourApproach-v1"))
    model = PPO("MlpPolicy", env, seed=0, device="cpu", policy_kwargs={"net_arch": [32, 32]})
    rng = np.random.default_rng(0)
    x = rng.uniform(-1, 1, (512, env.observation_space.shape[0])).astype(np.float32)
    y = np.tanh(x[:, :2] - 0.5 * x[:, 2:4]).astype(np.float32)
    opt = torch.optim.Adam(model.policy.parameters(), lr=3e-3)
    with torch.no_grad():
        pred = imitation._mean_action(model.policy, torch.as_tensor(x))
        start = float(torch.mean((pred - torch.as_tensor(y)) ** 2))
    end = imitation._fit(model.policy, x, y, 30, 64, rng, opt)
    assert end < start / 100.0
    env.close()


def test_clone_writes_a_ppo_model_and_its_record(tmp_path: Path) -> None:
    """Two short rounds on 2 ships: the saved file is an ordinary PPO model that evaluates in the
    registered environment, and its record says how it was made."""
    settings = {"rounds": 2, "steps_per_round": 64, "epochs": 1, "n_envs": 2}
    res = imitation.clone("HarbourApproach-v1", 3, out=tmp_path, settings=settings)
    assert res.model_path.name == "ppo_HarbourApproach-v1_s3.zip" and res.n_timesteps == 128
    rec = yaml.safe_load(res.record_path.read_text())
    assert rec["method"] == "bc" and rec["algo"] == "ppo" and rec["seed"] == 3 and rec["bc"]["rounds"] == 2
    assert [r["driver"] for r in rec["bc_rounds"]] == ["pilot", "learner"]
    assert rec["bc_rounds"][1]["mean_abs_action_gap"] >= 0.0
    ev = common.evaluate("HarbourApproach-v1", res.model_path, 1, 0, {})
    assert ev["summary"]["episodes"] == 1 and "success_rate" in ev["summary"]
    with pytest.raises(common.UsageError, match="seed"):
        imitation.clone("HarbourApproach-v1", 1_000_000, out=tmp_path, settings=settings)
