"""The classical pilots' tuning (agents/tune_pilot.py): the search runs the validation episodes of evaluate.py,
writes only where told, and the tuned ZigZagRandom pilot is a baseline worth beating."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from agents import seeds, tune_pilot
from agents.evaluation import evaluate
from vessel_gym.envs.registration import registered
from vessel_gym.policy import read_pilots

REPO = Path(__file__).resolve().parents[2]


def test_search_runs_the_validation_episodes_of_evaluate():
    """The vector search's mean return of a candidate is evaluate.py's over the same validation seeds."""
    result = tune_pilot.search("ZigZagRandom-v1", {"omega_n_UL": [0.6, 1.5], "zeta": [0.9]}, episodes=3)
    assert result["seeds"] == [seeds.VALIDATION_START, seeds.VALIDATION_START + 2]
    untuned, faster = result["rows"]
    assert untuned["params"] == {"omega_n_UL": 0.6, "zeta": 0.9}
    ev = evaluate("ZigZagRandom-v1", "pid-nomoto", 3, seeds.VALIDATION_START)  # the design's defaults
    assert untuned["return_mean"] == pytest.approx(ev["summary"]["return_mean"], rel=1e-9, abs=1e-9)
    assert result["best"] is faster  # the untuned design reaches no target: a faster loop earns more


def test_every_recorded_search_brackets_the_untuned_design_and_the_file_names_real_parameters():
    import inspect

    tuned = read_pilots()
    for env_id, rec in tune_pilot.SEARCHES.items():
        factory = tune_pilot.untuned_factory(env_id)
        defaults = {k: p.default for k, p in inspect.signature(factory).parameters.items() if k != "env"}
        for name, values in rec["grid"].items():
            if name in defaults and defaults[name] is not inspect.Parameter.empty:
                assert min(values) <= defaults[name] <= max(values), (env_id, name)
        assert rec["episodes"] <= 100
        assert set(tuned[env_id]["pid"]) == set(rec["grid"]), env_id
    # a task with a `pid` pilot keeps its untuned design by name beside it (a task whose classical pilot is
    # another kind, Berthing's DP pilot `scripted`, has none), and every tuned entry is a registered id
    for env_id, decl in registered().items():
        if "pid" in decl.pilots:
            assert "pid-nomoto" in decl.pilots, env_id
    assert set(tuned) <= set(registered())


@pytest.mark.parametrize("agent", ["pid", "pid-nomoto", "scripted"])
def test_pilots_by_name_in_evaluation(agent):
    out = evaluate("TurningCircle-v0", agent, episodes=1, seed=seeds.TEST_START)
    assert out["agent"] == agent and out["summary"]["episodes"] == 1


def test_tuned_zigzag_random_pilot_reaches_targets_and_beats_the_untuned_design():
    """On test seeds the search never saw: the tuned PID reaches its targets (so it overshoots some) and earns
    more than the untuned design, which reaches none."""
    tuned = evaluate("ZigZagRandom-v1", "pid", episodes=3, seed=seeds.TEST_START)["summary"]
    untuned = evaluate("ZigZagRandom-v1", "pid-nomoto", episodes=3, seed=seeds.TEST_START)["summary"]
    assert untuned["reached_pct_mean"] == 0.0
    assert tuned["reached_pct_mean"] > 50.0 and tuned["overshoot_deg_mean"] > 0.0
    assert tuned["return_mean"] > untuned["return_mean"] + 10.0
    assert tuned["heading_error_deg_mean"] < untuned["heading_error_deg_mean"]


def test_write_sets_one_entry_and_replaces_another_value_only_with_force(tmp_path):
    path = tmp_path / "pilots.toml"
    assert tune_pilot.write_gains(path, "vessel_gym/ZigZag-v1", {"omega_n_UL": 1.5, "zeta": 0.5}, False)
    assert not tune_pilot.write_gains(path, "vessel_gym/ZigZag-v1", {"omega_n_UL": 1.5, "zeta": 0.5}, False)
    assert tune_pilot.write_gains(path, "vessel_gym/TurningCircle-v0", {"omega_UL": 0.5, "zeta": 2}, False)
    with pytest.raises(tune_pilot.UsageError, match="use --force"):
        tune_pilot.write_gains(path, "vessel_gym/ZigZag-v1", {"omega_n_UL": 1.2, "zeta": 0.3}, False)
    assert read_pilots(path)["vessel_gym/ZigZag-v1"]["pid"] == {"omega_n_UL": 1.5, "zeta": 0.5}
    assert tune_pilot.write_gains(path, "vessel_gym/ZigZag-v1", {"omega_n_UL": 1.2, "zeta": 0.3}, True)
    data = read_pilots(path)
    assert data["vessel_gym/ZigZag-v1"]["pid"] == {"omega_n_UL": 1.2, "zeta": 0.3}
    assert data["vessel_gym/TurningCircle-v0"]["pid"] == {"omega_UL": 0.5, "zeta": 2.0}


def test_command_prints_the_table_and_the_best(tmp_path, capsys):
    out = tmp_path / "gains.toml"
    argv = ["--env", "ZigZag-v1", "--grid", "omega_n_UL=0.6,1.8", "zeta=0.6", "--episodes", "2", "--write", str(out)]
    assert tune_pilot.main(argv) == 0
    text = capsys.readouterr().out
    assert "| omega_n_UL \\ zeta | 0.6 |" in text and "best: omega_n_UL=" in text
    assert read_pilots(out)["vessel_gym/ZigZag-v1"]["pid"]["zeta"] == 0.6


BAD = [
    ["--env", "ZigZag-v1", "--grid", "omega=1"],  # no such parameter
    ["--env", "ZigZag-v1", "--grid", "zeta=a,b"],
    ["--env", "ZigZag-v1", "--grid", "zeta"],
    ["--env", "ZigZag-v1", "--grid", "zeta=-1", "--episodes", "1"],
    ["--env", "Nope-v0"],
    ["--env", "ZigZag-v1", "--episodes", "0"],
    ["--docs", "/nonexistent.md"],
    ["--docs", "README.md", "--episodes", "3"],
]


@pytest.mark.parametrize("argv", BAD)
def test_bad_arguments_exit_2_in_one_line(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        code = tune_pilot.main(argv)
        raise SystemExit(code)
    assert exc.value.code == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_runs_as_a_script():
    path = REPO / "agents" / "tune_pilot.py"
    ok = subprocess.run([sys.executable, str(path), "--help"], capture_output=True, text=True, cwd="/")
    assert ok.returncode == 0 and "usage" in ok.stdout


def test_docs_section_states_the_gains_the_pilots_file_holds():
    """docs/agents.md's generated section (``--docs``) names, per recorded search, the gains pid runs with."""
    text = (REPO / "docs" / "agents.md").read_text()
    block = text[text.index(tune_pilot.BEGIN) : text.index(tune_pilot.END)]
    tuned = read_pilots()
    for env_id in tune_pilot.SEARCHES:
        chosen = ", ".join(f"{k} = {v:g}" for k, v in tuned[env_id]["pid"].items())
        assert f"**`{env_id}`**" in block and f"chosen {chosen} (" in block, env_id
        assert f"| `{env_id.split('/')[-1]}` | `pid` | {chosen} |" in block, env_id


def test_evaluate_command_takes_the_untuned_pilot_by_name(capsys):
    """``evaluate.py --agent pid-nomoto --json``: the same flat keys as ``pid``, the untuned design's numbers."""
    import json

    from agents import evaluate as evaluate_cli

    outs = {}
    for agent in ("pid", "pid-nomoto"):
        argv = ["--env", "ZigZagRandom-v1", "--agent", agent, "--episodes", "2", "--json"]
        assert evaluate_cli.main(argv) == 0
        outs[agent] = json.loads(capsys.readouterr().out)
    assert outs["pid-nomoto"]["agent"] == "pid-nomoto"
    assert list(outs["pid"]) == list(outs["pid-nomoto"])
    assert outs["pid-nomoto"]["mean_overshoot_deg"] == 0.0 < outs["pid"]["mean_overshoot_deg"]
