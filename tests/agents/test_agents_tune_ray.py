"""Ray Tune sweep on a one-CPU local Ray instance with one tiny trial (skipped only without ray)."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

pytestmark = pytest.mark.slow


def test_sweep_one_tiny_trial_locally(tmp_path: Path) -> None:
    pytest.importorskip("ray")
    from ray import tune

    from agents import tune_ray

    space = {"learning_rate": tune.choice([1e-3]), "n_steps": tune.choice([64])}
    result = tune_ray.sweep(
        "ZigZag-v0",
        "ppo",
        samples=1,
        timesteps=256,
        eval_episodes=1,
        n_envs=2,
        num_cpus=1,
        storage=tmp_path / "tune",
        name="tiny",
        space=space,
    )
    assert len(result["trials"]) == 1
    trial = result["trials"][0]
    assert trial["hp"] == {"learning_rate": 1e-3, "n_steps": 64}
    assert trial["timesteps"] >= 256 and trial["mean_return"] == result["best_mean_return"]
    block = yaml.safe_load(result["block"])["vessel_gym/ZigZag-v0"]
    assert block["n_steps"] == 64 and block["learning_rate"] == 1e-3 and block["n_timesteps"] == 256
    assert (tmp_path / "tune" / "tiny").is_dir()


def test_search_spaces_cover_every_algorithm() -> None:
    pytest.importorskip("ray")
    from agents import common, tune_ray

    for algo in common.ALGOS:
        space = tune_ray.search_space(algo)
        assert {"learning_rate", "gamma"} <= set(space)
        hp = common.load_hyperparams(algo, "vessel_gym/ZigZag-v0", overrides={k: 0.99 for k in ("gamma",)})
        common.run_config(algo, "vessel_gym/ZigZag-v0", {**hp, **{k: 1 for k in space if k != "gamma"}})
