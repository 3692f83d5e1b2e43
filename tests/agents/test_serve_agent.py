"""`vessel-gym serve --agent PATH` puts a trained SB3 agent on the helm."""

from __future__ import annotations

import gymnasium as gym
import pytest

import vessel_gym  # noqa: F401 (registers the ids)

sb3 = pytest.importorskip("stable_baselines3")


def test_serve_runs_a_trained_agent(tmp_path, capsys):
    from vessel_gym.net.serve import serve

    env = gym.make("vessel_gym/HarbourApproach-v3")
    model = sb3.PPO("MlpPolicy", env, n_steps=64, batch_size=64, n_epochs=1, seed=0, device="cpu")
    model.learn(64)
    path = tmp_path / "ppo_HarbourApproach-v3_s0.zip"
    model.save(path)
    code = serve(
        "harbour",
        agent=str(path),
        json_bind=("127.0.0.1", 0),
        nmea=[],
        time_factor=20.0,
        duration_s=1.0,
        seed=0,
    )
    out = capsys.readouterr().out
    assert code == 0
    assert str(path) in out or "ppo" in out.lower()
