"""results.py: the generated tables and verdicts, and the marker-delimited rewrite of docs/results.md."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from agents import results, seeds


def _row(agent, trained=False, **summary):
    return {
        "agent": agent,
        "summary": {"episodes": 20, "return_mean": -40.0, "return_std": 5.0, **summary},
        "training": {"num_timesteps": 150000, "train_time_s": 600.0, "cpu_time_s": 200.0, "budget_hit": True}
        if trained
        else None,
    }


def _zz(agent, he, os_, rud, rate, trained=False):
    return _row(
        agent,
        trained,
        heading_error_deg_mean=he,
        heading_error_deg_std=1.0,
        overshoot_deg_mean=os_,
        overshoot_deg_std=0.1,
        reached_pct_mean=50.0,
        reached_pct_std=10.0,
        rudder_deg_mean=rud,
        rudder_deg_std=1.0,
        rudder_rate_deg_s_mean=rate,
        rudder_rate_deg_s_std=0.1,
    )


def test_zigzag_verdict() -> None:
    pid = _zz("pid", 13.0, 1.0, 4.0, 2.0)
    good = _zz("ppo_ZigZag-v1_s0", 9.0, 0.5, 5.0, 2.5, trained=True)
    bad = _zz("ppo_ZigZag-v1_s0", 9.0, 0.5, 14.0, 7.0, trained=True)
    assert results.verdict("zigzag", [pid, good]).startswith("**Beats")
    assert results.verdict("zigzag", [pid, bad]).startswith("**Does not beat")
    table = results.table("zigzag", [pid, good])
    assert "| pid | — | — | -40.0 ± 5.0 | 13.0 ± 1.0 |" in table
    assert "150k (budget) | 10.0 (3.3)" in table
    assert "success %" not in table  # ZigZag-v1 has no success flag
    pid["summary"]["success_rate"], good["summary"]["success_rate"] = 0.0, 0.5
    assert "| 50 ± 10 | 50 | 5.0 ± 1.0 |" in results.table("zigzag", [pid, good])


def test_harbour_verdict_and_table() -> None:
    extra = {"min_clearance_m_mean": 6.0, "min_clearance_m_std": 1.0, "time_s_mean": 300.0, "time_s_std": 9.0}
    extra |= {"rudder_deg_mean": 7.0, "rudder_deg_std": 1.0, "rudder_rate_deg_s_mean": 0.4}
    extra |= {"rudder_rate_deg_s_std": 0.1}
    pid = _row("pid", success_rate=1.0, outcomes={"success": 20}, **extra)
    rl = _row(
        "sac_HarbourApproach-v2_s0", True, success_rate=0.25, outcomes={"success": 5, "contact": 15}, **extra
    )
    assert results.verdict("harbour", [pid, rl]).startswith("**Does not beat")
    seeds5 = _row("ppo (5 seeds)", True, success_rate=0.9, success_rate_median=0.95, seeds=5, **extra)
    seeds5["summary"]["outcomes"] = {"success": 90, "timeout": 10}
    v = results.verdict("harbour", [pid, seeds5])
    assert "`ppo (5 seeds)` median 95 % over 5 seeds, 10.0 min wall (3.3 min CPU) per seed: **met**" in v
    short = _row("bc (5 seeds)", True, success_rate=0.7, success_rate_median=0.75, seeds=5, **extra)
    short["summary"]["outcomes"] = {"success": 70, "timeout": 30}
    v = results.verdict("harbour", [pid, seeds5, short])
    assert "`bc (5 seeds)` median 75 % over 5 seeds" in v and "**not met**, 15 points short" in v
    seeds5["training"]["train_time_s"] = 1500.0  # 25 min: over the goal's 20-minute limit
    assert "per seed: not met: too slow to train" in results.verdict("harbour", [pid, seeds5])
    assert "contact 15, success 5" in results.table("harbour", [pid, rl])


def test_write_doc_keeps_the_discussion(tmp_path: Path) -> None:
    doc = tmp_path / "results.md"
    doc.write_text(f"# Results\n\nintro\n\n{results.BEGIN}\nold\n{results.END}\n\ndiscussion\n")
    results.write_doc(doc, f"{results.BEGIN}\nnew\n{results.END}")
    text = doc.read_text()
    assert "intro" in text and "discussion" in text and "new" in text and "old" not in text
    fresh = tmp_path / "fresh.md"
    results.write_doc(fresh, f"{results.BEGIN}\nnew\n{results.END}")
    assert fresh.read_text().startswith("# Results")


@pytest.mark.slow
def test_results_end_to_end_tiny(tmp_path: Path, monkeypatch) -> None:
    """A whole results.py run on one environment, 2 seeds x 256 steps with a validation evaluation every 128:
    curves, table, JSON, shipped agents with sidecars, the behaviour-cloning row; then --skip-train and --resume."""
    from agents import imitation, shipped

    monkeypatch.setattr(results, "EXTRA_EVALS", {})
    # the behaviour-cloning row too, on this environment, with two tiny DAgger rounds
    monkeypatch.setattr(results, "BC_PLAN", ("vessel_gym/ZigZag-v1",))
    bc_file = tmp_path / "bc.yml"
    bc_file.write_text("vessel_gym/ZigZag-v1: {rounds: 2, steps_per_round: 64, epochs: 1, n_envs: 2}\n")
    monkeypatch.setattr(imitation, "BC_FILE", bc_file)
    doc = tmp_path / "results.md"
    ship_dir = tmp_path / "trained"
    argv = ["--envs", "ZigZag-v1", "--algos", "ppo", "--timesteps", "256", "--episodes", "1"]
    argv += ["--seeds", "2", "--eval-freq", "128", "--eval-episodes", "2"]
    argv += ["--out", str(tmp_path / "out"), "--doc", str(doc), "--ship-dir", str(ship_dir)]
    assert results.main(argv) == 0
    data = json.loads((tmp_path / "out" / "results.json").read_text())
    rows = data["sections"][0]["rows"]
    assert [r["agent"] for r in rows] == ["pid", "scripted", "ppo (2 seeds)", f"{results.ROW_NAMES['bc']} (2 seeds)"]
    assert rows[3]["training"]["num_timesteps"] == 128 and rows[3]["summary"]["seeds"] == 2
    rl = rows[2]
    assert [p["seed"] for p in rl["per_seed"]] == [0, 1] and rl["summary"]["seeds"] == 2
    assert rl["summary"]["return_std"] is not None and rl["training"]["seeds"] == 2
    curves = data["curves"]["vessel_gym/ZigZag-v1:ppo"]
    assert curves["timesteps"] and len(curves["return"]) == 2
    assert Path(curves["png"]).stat().st_size > 0
    assert sorted(Path(t).name for t in data["tracks"].values()) == [
        "ZigZag-v1_pid.png",
        "ZigZag-v1_ppo_ZigZag-v1_s0.png",
        "ZigZag-v1_scripted.png",
    ]
    text = doc.read_text()
    assert "### vessel_gym/ZigZag-v1" in text and "256 environment steps per run" in text
    assert "over the 2 training seeds" in text
    assert data["eval_seed"] == seeds.TEST_START and data["training_seeds"] == [0, 1]
    names = sorted(str(p.relative_to(ship_dir)) for p in shipped.list_shipped(ship_dir))
    assert names == [
        "bc/ppo_ZigZag-v1_seed0.zip",
        "bc/ppo_ZigZag-v1_seed1.zip",
        "ppo_ZigZag-v1_seed0.zip",
        "ppo_ZigZag-v1_seed1.zip",
    ]
    assert shipped.read_sidecar(ship_dir / names[0])["method"] == "bc"
    meta = shipped.read_sidecar(ship_dir / names[1])
    assert set(shipped.REQUIRED_KEYS) <= set(meta) and meta["seed"] == 1 and meta["env_version"] == 1
    assert meta["test_seeds"] == f"{seeds.TEST_START}..{seeds.TEST_START}"
    shipped_before = sorted(ship_dir.rglob("*"))
    assert results.main([*argv[:-2], "--skip-train"]) == 0  # without --ship-dir: nothing shipped
    # --resume trains only what is missing: one PPO and one cloned model
    (tmp_path / "out" / "ppo_ZigZag-v1_s1.zip").unlink()
    (tmp_path / "out" / "bc" / "ppo_ZigZag-v1_s0.zip").unlink()
    kept = (tmp_path / "out" / "ppo_ZigZag-v1_s0.zip").stat().st_mtime_ns
    assert results.main([*argv[:-2], "--resume"]) == 0
    assert sorted(ship_dir.rglob("*")) == shipped_before
    assert (tmp_path / "out" / "ppo_ZigZag-v1_s1.zip").is_file()
    assert (tmp_path / "out" / "bc" / "ppo_ZigZag-v1_s0.zip").is_file()
    assert (tmp_path / "out" / "ppo_ZigZag-v1_s0.zip").stat().st_mtime_ns == kept


def test_interval95_and_aggregate() -> None:
    """The 95 % interval of two seeds uses t(0.975, 1) = 12.706; one seed has none."""
    import numpy as np

    mean, half = results.interval95([[1.0, 2.0], [3.0, 2.0]])
    assert np.allclose(mean, [2.0, 2.0]) and np.allclose(half, [12.706 * np.sqrt(2.0) / np.sqrt(2.0), 0.0])
    assert np.allclose(results.interval95([[5.0]])[1], 0.0)
    a = {"episodes": 3, "return_mean": -10.0, "return_std": 1.0, "success_rate": 0.0, "outcomes": {"x": 3}}
    b = {"episodes": 3, "return_mean": -20.0, "return_std": 1.0, "success_rate": 1.0, "outcomes": {"y": 3}}
    agg = results.aggregate([a, b])
    assert agg["return_mean"] == -15.0 and agg["return_std"] == 5.0 and agg["seeds"] == 2
    assert agg["success_rate"] == 0.5 and agg["outcomes"] == {"x": 3, "y": 3}
