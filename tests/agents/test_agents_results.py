"""results.py: the generated tables and verdicts, and the marker-delimited rewrite of docs/results.md."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from agents import results, results_doc, seeds


def _row(agent, trained=False, **summary):
    return {
        "agent": agent,
        "summary": {"episodes": 20, "return_mean": -40.0, "return_std": 5.0, **summary},
        "training": {"num_timesteps": 150000, "train_time_s": 600.0, "cpu_time_s": 200.0, "budget_hit": True}
        if trained
        else None,
    }


def _zz(agent, he, os_, rud, rate, trained=False, ret=-40.0):
    row = _row(
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
    row["summary"]["return_mean"] = ret
    return row


def test_zigzag_verdict() -> None:
    """The goal: higher return, lower heading error, overshoot <= the PID's + 0.25 deg, rudder rate <= 1.5x;
    judged on the median over the seeds where the row has them."""
    pid = _zz("pid", 13.0, 1.0, 4.0, 2.0)
    good = _zz("ppo_ZigZag-v1_s0", 9.0, 1.2, 14.0, 2.9, trained=True, ret=-30.0)  # rudder is not judged
    assert results.verdict("zigzag", [pid, good]).startswith("**Beats")
    for bad in (
        _zz("a", 9.0, 1.3, 5.0, 2.5, trained=True, ret=-30.0),  # overshoot 0.05 deg over the margin
        _zz("b", 9.0, 0.5, 5.0, 3.1, trained=True, ret=-30.0),  # rudder rate 1.55x
        _zz("c", 9.0, 0.5, 5.0, 2.5, trained=True, ret=-41.0),  # lower return
        _zz("d", 13.0, 0.5, 5.0, 2.5, trained=True, ret=-30.0),  # heading error not lower
    ):
        v = results.verdict("zigzag", [pid, bad])
        assert v.startswith("**Does not beat") and "**not met**" in v
    assert "overshoot per course change 1.30 vs 1.25 (misses by 0.05)" in results.verdict(
        "zigzag", [pid, _zz("a", 9.0, 1.3, 5.0, 2.5, trained=True, ret=-30.0)]
    )
    # per seed: the median of each figure; here 2 of 3 seeds meet all four, the median too
    seeds3 = _zz("ppo (3 seeds)", 0, 0, 0, 0, trained=True)
    seeds3["per_seed"] = [{"summary": _zz("s", he, 1.0, 5.0, 2.0, ret=r)["summary"]} for he, r in
                          ((9.0, -30.0), (10.0, -35.0), (14.0, -45.0))]  # fmt: skip
    v = results.verdict("zigzag", [pid, seeds3])
    assert v.startswith("**Beats") and "heading error 10.00 vs 13.00 (ok)" in v
    assert "2 of 3 seeds meet all four on their own" in v
    seeds3["per_seed"][2]["seed"], seeds3["per_seed"][2]["selected_at_timesteps"] = 7, 250_000
    rows = results_doc.zigzag_seed_table(seeds3, pid["summary"]).splitlines()
    assert rows[2].endswith("| met |") and rows[4].startswith("| 7 | best at 250k | -45.0 | 14.00 |")
    assert rows[4].endswith("| misses return, heading error |")
    table = results.table("zigzag", [pid, good])
    assert "| pid | — | — | -40.0 ± 5.0 | 13.0 ± 1.0 |" in table
    assert "150k (budget) | 10.0 (3.3)" in table
    assert "success %" not in table  # ZigZag-v1 has no success flag
    pid["summary"]["success_rate"], good["summary"]["success_rate"] = 0.0, 0.5
    assert "| 50 ± 10 | 50 | 14.0 ± 1.0 |" in results.table("zigzag", [pid, good])


def test_time_to_solve_per_seed() -> None:
    """The first periodic validation evaluation at which the success rate reaches 90 % (and the return the
    pilot's), with the training minutes until then; None where a seed never got there."""
    curves = {
        "timesteps": [100, 200, 300],
        "return": [[1.0, 5.0, 9.0], [0.0, 0.0, 1.0]],
        "success": [[0.5, 0.9, 1.0], [0.0, 0.2, 0.3]],
        "wall_min": [[1.0, 2.0, 3.0], [1.5, 3.0, 4.5]],
        "cpu_min": [[0.5, 1.0, 1.5], [1.0, 2.0, 3.0]],
    }
    solve = results.time_to_solve(curves, pid_return=8.0)
    assert solve[0]["success"] == {"steps": 200, "wall_min": 2.0, "cpu_min": 1.0}
    assert solve[0]["pid_return"]["steps"] == 300
    assert solve[1] == {"success": None, "pid_return": None}
    row = {"per_seed": [{"seed": 3}, {"seed": 4}], "time_to_solve": solve}
    table = results_doc.time_to_solve_table(row, 8.0)
    assert "| 3 | 0k | 2.00 (1.00) | 0k | 3.00 (1.50) |" in table  # steps in thousands
    assert "| 4 | not within the run | — | not within the run | — |" in table


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
    assert "`bc (5 seeds)` median 75 % over 5 seeds" in v and "**not met**, 20 points short" in v
    seeds5["training"]["train_time_s"] = 1500.0  # 25 min: over the goal's 20-minute limit
    assert "per seed: not met: too slow to train" in results.verdict("harbour", [pid, seeds5])
    assert "contact 15, success 5" in results.table("harbour", [pid, rl])


def test_harbour_helmsman_goal_per_seed() -> None:
    """The harbour goal beyond success: median over the seeds of time (shorter than the pid's), rudder rate (at
    most 2x its) and minimum clearance (no smaller), with the gap of every failed test."""
    pid = _row(
        "pid", success_rate=1.0, time_s_mean=300.0, rudder_rate_deg_s_mean=0.5, min_clearance_m_mean=5.0
    )

    def seed(k, success, time, rate, clear):
        return {"seed": k, "selected_at_timesteps": 500_000, "summary": {
            "success_rate": success, "time_s_mean": time, "rudder_rate_deg_s_mean": rate,
            "min_clearance_m_mean": clear, "return_mean": 40.0}}  # fmt: skip

    per = [seed(0, 1.0, 250.0, 0.8, 6.0), seed(1, 0.95, 260.0, 1.2, 4.0), seed(2, 0.9, 270.0, 0.9, 5.5)]
    row = _row("ppo (3 seeds)", True, success_rate=0.95, success_rate_median=0.95, seeds=3)
    row["per_seed"] = per
    text = results_doc._harbour_helmsman(row, pid["summary"])
    # medians: success 0.95, time 260, rate 0.9 (limit 1.0), clearance 5.5 (pid 5.0)
    assert "success 0.95 vs 0.95 (ok)" in text and "time 260 vs 300 (ok)" in text
    assert "rudder rate 0.90 vs 1.00 (ok)" in text and "min clearance 5.50 vs 5.00 (ok)" in text
    assert "**met**" in text and "1 of 3 seeds meet all four" in text
    per[2]["summary"]["rudder_rate_deg_s_mean"] = 1.5  # median rate 1.2: misses by 0.2
    text = results_doc._harbour_helmsman(row, pid["summary"])
    assert "rudder rate 1.20 vs 1.00 (misses by 0.20)" in text and "**not met**" in text
    table = results_doc.harbour_seed_table(row, pid["summary"])
    assert "| 0 | best at 500k | 100 | 250 | 0.80 (1.6x) | 6.00 | 40.0 | met |" in table
    assert (
        "| 1 | best at 500k | 95 | 260 | 1.20 (2.4x) | 4.00 | 40.0 | misses rudder rate, min clearance |"
        in table
    )


def test_write_doc_replaces_only_the_blocks_of_the_run(tmp_path: Path) -> None:
    """One block per environment id: a run over one environment leaves the others' blocks as they were and
    adds a block the page does not have after the page's generated blocks."""
    a0 = f"{results_doc.begin_marker('A')}\nold A\n{results_doc.end_marker('A')}"
    b0 = f"{results_doc.begin_marker('B')}\nold B\n{results_doc.end_marker('B')}"
    doc = tmp_path / "results.md"
    doc.write_text(f"# Results\n\nintro\n\n{a0}\n\n{b0}\n\ndiscussion\n")
    a1 = a0.replace("old A", "new A")
    c1 = f"{results_doc.begin_marker('C')}\nnew C\n{results_doc.end_marker('C')}"
    results.write_doc(doc, f"{a1}\n\n{c1}")
    text = doc.read_text()
    assert "new A" in text and "old A" not in text and "old B" in text and "new C" in text
    assert text.index("old B") < text.index("new C") < text.index("discussion")
    results.write_doc(doc, c1.replace("new C", "newer C"))
    assert doc.read_text().count("results:begin C") == 1 and "newer C" in doc.read_text()


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
    assert [r["agent"] for r in rows] == [
        "pid",
        "scripted",
        "ppo (2 seeds)",
        f"{results.ROW_NAMES['bc']} (2 seeds)",
    ]
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


def test_a_cloning_row_alone_has_a_block_of_its_own(tmp_path: Path) -> None:
    """``--algos bc`` writes its sections into ``<env id>:bc``: the environment's from-scratch block stays."""
    extra = {"min_clearance_m_mean": 6.0, "min_clearance_m_std": 1.0, "time_s_mean": 300.0, "time_s_std": 9.0}
    pid = _row("pid", success_rate=1.0, outcomes={"success": 20}, **extra)
    bc = _row("bc (5 seeds)", True, success_rate=0.95, success_rate_median=1.0, seeds=5, **extra)
    env = "vessel_gym/HarbourApproach-v3"
    res = {
        "argv": ["--algos", "bc"], "date": "2026-12-06", "episodes": 20, "eval_seed": seeds.TEST_START,
        "seeds": 5, "select": "final", "validation": {"episodes": 10, "every_steps": 50000},
        "machine": {"cpu_count": 2, "python": "3", "torch": "2", "torch_threads": 1, "sb3": "2",
                    "load_start": 1.0, "load_end": 1.0},
        "sections": [{"env_id": env, "block": f"{env}:bc", "label": "training configuration", "env_kwargs": {},
                      "main": True, "kind": "harbour", "rows": [pid, bc]}],
    }  # fmt: skip
    text = results_doc.markdown(res)
    assert text.startswith(results_doc.begin_marker(f"{env}:bc")) and text.endswith(
        results_doc.end_marker(f"{env}:bc")
    )
    assert f"### {env} (behaviour cloning) — training configuration" in text
    doc = tmp_path / "results.md"
    scratch = f"{results_doc.begin_marker(env)}\nfrom scratch\n{results_doc.end_marker(env)}"
    doc.write_text(f"# Results\n\n{scratch}\n")
    results.write_doc(doc, text)
    page = doc.read_text()
    assert "from scratch" in page and page.count("results:begin") == 2 and "bc (5 seeds)" in page


def test_cloning_alone_needs_an_environment_of_the_plan(tmp_path: Path, capsys) -> None:
    argv = ["--envs", "ZigZag-v1", "--algos", "bc", "--out", str(tmp_path)]
    assert results.main(argv) == 2
    assert "has no behaviour-cloning row" in capsys.readouterr().err


def _berth(agent, success, outcomes, trained=False):
    row = _row(
        agent,
        trained,
        success_rate=success,
        success_rate_median=success,
        outcomes=outcomes,
        contact_speed_m_s_mean=0.04,
        contact_speed_m_s_std=0.01,
        max_fender_energy_fraction_mean=0.02,
        max_fender_energy_fraction_std=0.01,
        time_s_mean=830.0,
        time_s_std=90.0,
        assist_effort_mean=0.4,
        assist_effort_std=0.1,
        rudder_deg_mean=4.0,
        rudder_deg_std=1.0,
        rudder_rate_deg_s_mean=0.1,
        rudder_rate_deg_s_std=0.01,
    )
    return row


def test_berthing_table_and_verdict() -> None:
    """Berthing has no PID helm: the goal is absolute (median success >= 90 %, no fender overload, <= 20 min per
    seed), the scripted pilot's success beside it; the table gives the overload share and the contact figures."""
    pilot = _berth("scripted", 1.0, {"success": 20})
    good = _berth("ppo (5 seeds)", 0.95, {"success": 19, "timeout": 1}, trained=True)
    text = results.verdict("berthing", [pilot, good])
    assert "**met**" in text and "scripted pilot succeeds in 100 %" in text
    over = _berth("ppo (5 seeds)", 0.95, {"success": 19, "fender_overload": 1}, trained=True)
    assert "**not met**: 5 % of episodes overload a fender" in results.verdict("berthing", [pilot, over])
    short = _berth("ppo (5 seeds)", 0.30, {"success": 6, "timeout": 14}, trained=True)
    assert "**not met**: 60 points of success short" in results.verdict("berthing", [pilot, short])
    table = results_doc.table("berthing", [pilot, over])
    head, _, first, second = table.splitlines()
    assert "fender overload %" in head and "contact speed m/s" in head
    assert "| 100 | 0 | success 20 | 0.040 ± 0.010 | 0.020 ± 0.010 | 830 ± 90 | 0.40 ± 0.10 |" in first
    assert "| 95 | 5 | fender_overload 1, success 19 |" in second


@pytest.mark.slow
def test_training_runs_in_parallel_give_the_models_of_one_at_a_time(tmp_path: Path) -> None:
    """--jobs 2 trains the runs of the plan in two worker processes: the same models as one after the other in
    this process (each run is seeded and single-threaded), each with its run record and its time budget."""
    import argparse
    import zipfile

    from agents.training import train

    env = "vessel_gym/ZigZag-v1"
    args = argparse.Namespace(
        jobs=2,
        out=str(tmp_path / "two"),
        threads=1,
        eval_freq=128,
        eval_episodes=1,
        time_budget=10.0,
        select="final",
    )
    runs = [("ppo", env, s, tmp_path / "two" / f"ppo_ZigZag-v1_s{s}.zip", 256) for s in (0, 1)]
    assert results._train_in_parallel(args, runs) == {r[3] for r in runs}
    one = train("ppo", env, 1, timesteps=256, out=tmp_path / "one", eval_freq=128, eval_episodes=1)
    with zipfile.ZipFile(one.model_path) as a, zipfile.ZipFile(runs[1][3]) as b:
        assert a.read("policy.pth") == b.read("policy.pth")
    for _, _, seed, path, _ in runs:
        record = yaml.safe_load(path.with_suffix(".yml").read_text())
        assert record["seed"] == seed and record["time_budget_s"] == 600.0 and not record["budget_hit"]
