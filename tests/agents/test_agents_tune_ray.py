"""Ray Tune sweep (ASHA, checkpoints, a seed per trial) on a one-CPU local Ray instance (skipped only without ray)."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

pytestmark = pytest.mark.slow


def test_asha_sweep_three_tiny_trials_locally(tmp_path: Path) -> None:
    """Three trials of 256 steps on a one-CPU local Ray instance, a validation evaluation every 128 steps:
    each trial its own seed, reports with checkpoints, ASHA deciding at each evaluation."""
    pytest.importorskip("ray")
    from ray import tune

    from agents import seeds, tune_ray

    space = {"learning_rate": tune.choice([1e-3, 3e-4]), "n_steps": tune.choice([64])}
    result = tune_ray.sweep(
        "ZigZag-v1",
        "ppo",
        samples=3,
        timesteps=256,
        eval_every=128,
        eval_episodes=1,
        n_envs=2,
        num_cpus=1,
        storage=tmp_path / "tune",
        name="tiny",
        space=space,
    )
    trials = result["trials"]
    assert len(trials) == 3
    assert sorted(t["seed"] for t in trials) == [0, 2, 4]  # n_envs = 2: disjoint training copies
    for t in trials:
        assert t["hp"]["n_steps"] == 64 and t["hp"]["learning_rate"] in (1e-3, 3e-4)
        assert 1 <= t["evaluations"] <= 2 and t["stopped_early"] == (t["evaluations"] < 2)
        stem = f"ppo_ZigZag-v1_s{t['seed']}"
        assert t["checkpoint"] is not None and (Path(t["checkpoint"]) / f"{stem}.zip").is_file()
        rec = yaml.safe_load((Path(t["checkpoint"]) / f"{stem}.yml").read_text())
        assert rec["seed"] == t["seed"] and rec["num_timesteps"] == t["timesteps"]
    assert max(t["evaluations"] for t in trials) == 2  # the first trial runs to the end
    assert trials[0]["mean_return"] == result["best_mean_return"]
    block = yaml.safe_load(result["block"])["vessel_gym/ZigZag-v1"]
    assert block["n_steps"] == 64 and block["n_timesteps"] == 256
    assert (tmp_path / "tune" / "tiny").is_dir()
    # scored on the validation set, apart from the test set
    assert seeds.VALIDATION_START + 1 <= seeds.TEST_START


def test_sweep_rejects_bad_settings(tmp_path: Path) -> None:
    pytest.importorskip("ray")
    from agents import common, tune_ray

    with pytest.raises(common.UsageError, match="eval every"):
        tune_ray.sweep("ZigZag-v1", "ppo", samples=1, timesteps=100, eval_every=200, storage=tmp_path)
    with pytest.raises(common.UsageError, match="training seed"):
        tune_ray.sweep("ZigZag-v1", "ppo", samples=2, seed=seeds_limit(), n_envs=1, storage=tmp_path)


def seeds_limit() -> int:
    from agents import seeds

    return seeds.VALIDATION_START - 1


def test_search_spaces_cover_every_algorithm() -> None:
    pytest.importorskip("ray")
    from agents import common, tune_ray

    for algo in common.ALGOS:
        space = tune_ray.search_space(algo)
        assert {"learning_rate", "gamma"} <= set(space)
        hp = common.load_hyperparams(algo, "vessel_gym/ZigZag-v1", overrides={k: 0.99 for k in ("gamma",)})
        common.run_config(algo, "vessel_gym/ZigZag-v1", {**hp, **{k: 1 for k in space if k != "gamma"}})
