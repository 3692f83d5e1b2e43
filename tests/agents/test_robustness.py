"""The robustness sweeps of the harbour helmsmen (agents/robustness.py)."""

from __future__ import annotations

import json
from pathlib import Path

import gymnasium as gym
import pytest

import vessel_gym  # noqa: F401  (registers the ids)
from agents import robustness


def test_wilson_interval_textbook_values():
    # Wilson (1927) 95 % score intervals: 0/20 -> [0, 0.161], 10/20 -> [0.299, 0.701], 20/20 -> [0.839, 1]
    assert robustness.wilson(0, 20) == pytest.approx((0.0, 0.1611), abs=1e-4)
    assert robustness.wilson(10, 20) == pytest.approx((0.2993, 0.7007), abs=1e-4)
    assert robustness.wilson(20, 20) == pytest.approx((0.8389, 1.0), abs=1e-4)
    with pytest.raises(ValueError):
        robustness.wilson(0, 0)


def test_sweeps_go_beyond_the_training_ranges():
    r = robustness.training_ranges("vessel_gym/HarbourApproach-v3")
    assert max(robustness.SWEEPS["wind"][1]) >= 2 * r["wind_speed_m_s"][1]
    assert max(robustness.SWEEPS["current"][1]) >= 2 * r["current_speed_m_s"][1]
    assert min(robustness.SWEEPS["noise"][1]) == 0  # the noiseless reference is a point of the sweep


def test_fixed_weather_sets_the_swept_field_and_draws_the_rest_per_seed():
    env = robustness.fixed_weather(gym.make("vessel_gym/HarbourApproach-v3"), {"wind_speed_m_s": 3.0})
    envs = []
    for seed in (11, 11, 12):
        env.reset(seed=seed)
        envs.append(env.unwrapped.task.sim.environments[0])
    env.close()
    r = robustness.training_ranges("vessel_gym/HarbourApproach-v3")
    assert all(e.wind_speed_m_s == 3.0 for e in envs)
    assert all(r["current_speed_m_s"][0] <= e.current_speed_m_s <= r["current_speed_m_s"][1] for e in envs)
    assert envs[0] == envs[1] and envs[0].wind_from_deg != envs[2].wind_from_deg


def test_noise_levels_scale_with_the_ship():
    kw = robustness.noise_kwargs(2.0, "vessel_gym/HarbourApproach-v3")  # the L7 model: L = 7 m
    assert kw["position_noise_m"] == pytest.approx(0.14)
    assert kw["heading_noise_deg"] == 2.0 and kw["speed_noise_m_s"] > 0.0


def test_bad_arguments_exit_2(capsys):
    assert robustness.main(["--plot", "x.jpg"]) == 2
    assert "expected a file ending in .png" in capsys.readouterr().err
    with pytest.raises(SystemExit) as e:
        robustness.main(["--episodes", "0"])
    assert e.value.code == 2


def test_a_small_sweep_writes_json_plot_and_block(tmp_path: Path, monkeypatch):
    monkeypatch.setattr(
        robustness,
        "HELMSMEN",
        (
            ("pilot", "vessel_gym/HarbourApproach-v3", "pid"),
            ("absent", "vessel_gym/HarbourApproach-v3", "no/such.zip"),
        ),
    )
    monkeypatch.setattr(robustness, "SWEEPS", {"wind": ("wind", (0.0, 4.0)), "noise": ("noise", (0, 1))})
    doc = tmp_path / "page.md"
    doc.write_text("# Page\n\ntext kept\n")
    assert robustness.main(["--episodes", "1", "--out", str(tmp_path), "--doc", str(doc)]) == 0
    res = json.loads((tmp_path / "robustness.json").read_text())
    assert [h["label"] for h in res["helmsmen"]] == ["pilot"] and "absent" in res["missing"][0]
    pts = res["helmsmen"][0]["sweeps"]["wind"]
    assert [p["x"] for p in pts] == [0.0, 4.0] and all(p["episodes"] == 1 for p in pts)
    assert pts[0]["successes"] == 1  # the tuned pilot arrives in calm weather on the first test episode
    assert (tmp_path / "robustness.png").stat().st_size > 1000
    text = doc.read_text()
    assert "text kept" in text and "<!-- results:begin robustness -->" in text and "| pilot |" in text
