"""The CollisionAvoidance results table: Wilson intervals, the command and its page block."""

from __future__ import annotations

import pytest

from agents import colreg_results


def test_wilson_interval_matches_the_published_formula():
    # Wilson (1927); e.g. Newcombe (1998), Stat. Med. 17, 857-872, Table I: 0/20 -> 0 to 0.1611, 10/20 -> 0.2993 to 0.7007
    lo, hi = colreg_results.wilson(0, 20)
    assert lo == 0.0 and hi == pytest.approx(0.1611, abs=1e-4)
    lo, hi = colreg_results.wilson(10, 20)
    assert lo == pytest.approx(0.2993, abs=1e-4) and hi == pytest.approx(0.7007, abs=1e-4)
    lo, hi = colreg_results.wilson(20, 20)
    assert lo == pytest.approx(0.8389, abs=1e-4) and hi == 1.0


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["--agents", "nope"], "no pilot"),
        (["--cases", "23"], "no Imazu case"),
        (["--set", "dnv", "--cases", "56"], "no DNV baseline case"),
        (["--write", "nope.md"], "no such"),
        (["--set", "narrow", "--cases", "4"], "no lane-traffic case (1..3)"),
    ],
)
def test_bad_arguments_exit_2_with_one_line(argv, needle, capsys):
    assert colreg_results.main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0]


def test_one_case_writes_the_block_of_the_page(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(f"# x\n\n{colreg_results.BEGIN}\nold\n{colreg_results.END}\ntail\n")
    assert colreg_results.main(["--episodes", "1", "--cases", "1", "--write", str(page)]) == 0
    text = page.read_text()
    assert "old" not in text and text.endswith(f"{colreg_results.END}\ntail\n")
    assert "| 1 | `scripted` | 0.0 [0.0, 79.3] | 100.0 [20.7, 100.0] |" in text
    assert "| 1 | `pid` | 100.0 [20.7, 100.0] | 0.0 [0.0, 79.3] |" in text


def test_a_dnv_situation_writes_its_own_block(tmp_path):
    page = tmp_path / "page.md"
    dnv = colreg_results.SETS["dnv"][2]
    page.write_text(
        f"{colreg_results.BEGIN}\nimazu\n{colreg_results.END}\n{dnv}\nold\n{colreg_results.END}\n"
    )
    argv = ["--set", "dnv", "--episodes", "1", "--cases", "7", "--write", str(page)]
    assert colreg_results.main(argv) == 0
    text = page.read_text()
    assert "imazu" in text and "old" not in text and "1 dnv cases" in text
    # situation 7 (head-on and crossing give-way): the route follower collides, the velocity obstacles pass
    assert "| 7 (HO, CR-GW) | `scripted` | 0.0 [0.0, 79.3] | 100.0 [20.7, 100.0] |" in text
    assert "| 7 (HO, CR-GW) | `pid` | 100.0 [20.7, 100.0] | 0.0 [0.0, 79.3] |" in text


def _fake_model(tmp_path, stem, record):
    path = tmp_path / f"{stem}.zip"
    path.write_bytes(b"")
    (tmp_path / f"{stem}.yml").write_text(record)
    return str(path)


def test_a_model_evaluated_on_other_encounters_is_refused(tmp_path, capsys):
    model = _fake_model(
        tmp_path,
        "ppo_CollisionAvoidance-v0_s0",
        "env_id: vessel_gym/CollisionAvoidance-v0\neval_env_kwargs: {encounters: generated}\n",
    )
    assert colreg_results.main(["--agents", model]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "not the Imazu cases" in err[0]


def test_models_of_several_seeds_get_a_pooled_row(tmp_path, monkeypatch, capsys):
    # the models' policies stand in as the VO pilot: the table's rows and the pooling are what is tested
    from vessel_gym.envs.registration import declaration

    vo = declaration(colreg_results.ENV_ID).pilots["pid"]
    monkeypatch.setattr(colreg_results, "_load_model", lambda path, env: vo(env))
    record = "env_id: vessel_gym/CollisionAvoidance-v0\neval_env_kwargs: {}\n"
    models = [_fake_model(tmp_path, f"ppo_CollisionAvoidance-v0_s{s}", record) for s in (0, 1)]
    assert colreg_results.main(["--episodes", "1", "--cases", "1", "--agents", *models]) == 0
    out = capsys.readouterr().out
    assert "| 1 | `ppo_CollisionAvoidance-v0_s0` | 100.0 [20.7, 100.0] |" in out
    assert "| all | `ppo (2 seeds)` | 100.0 [34.2, 100.0] | 0.0 [0.0, 65.8] |" in out
    # a named block of the page, totals only; the baselines' block is left as it was
    begin, end = colreg_results.markers("ppo")
    page = tmp_path / "page.md"
    page.write_text(f"{colreg_results.BEGIN}\nbase\n{colreg_results.END}\n{begin}\nold\n{end}\n")
    argv = ["--episodes", "1", "--cases", "1", "--agents", *models, "--block", "ppo", "--totals"]
    assert colreg_results.main([*argv, "--write", str(page)]) == 0
    text = page.read_text()
    assert "base" in text and "old" not in text and "| 1 |" not in text
    assert "| all | `ppo_CollisionAvoidance-v0_s1` | 100.0 [20.7, 100.0] |" in text
    assert colreg_results.main(["--agents", *models, "--block", "nope", "--write", str(page)]) == 2
    assert "no results block" in capsys.readouterr().err


def test_restricted_waters_run_the_open_sea_model_without_the_sweep_and_report_grounding(tmp_path):
    """--set narrow: the lane-traffic cases in CollisionAvoidanceNarrow-v0 with a grounding column; the shipped
    open-sea model (49 features) runs there with sensors=0, the pilots with the sweep."""
    page = tmp_path / "page.md"
    begin, end = colreg_results.markers(None, "narrow")
    page.write_text(f"{begin}\nold\n{end}\n")
    model = "agents/trained/ppo_CollisionAvoidance-v0_seed0.zip"
    argv = ["--set", "narrow", "--episodes", "1", "--cases", "2", "--agents", "scripted", model, "--write", str(page)]
    assert colreg_results.main(argv) == 0
    text = page.read_text()
    assert "vessel_gym/CollisionAvoidanceNarrow-v0" in text and "grounding % [95 % CI]" in text
    assert "2 (opposing)" in text and "without the range-sensor sweep (sensors=0): ppo_CollisionAvoidance-v0_seed0" in text
