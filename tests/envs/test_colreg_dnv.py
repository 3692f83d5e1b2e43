"""DNV's 55 baseline traffic situations, shipped as the generator wrote them, run through the task's own
maritime-schema reader."""

from __future__ import annotations

import json
import math

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.envs.tasks.colreg import DNV_TARGETS
from vessel_gym.envs.tasks.colreg_geometry import GIVE_WAY, HEAD_ON, OVERTAKEN, OVERTAKING, STAND_ON
from vessel_gym.envs.tasks.colreg_situation import DNV_COUNT, DNV_DIR, dnv_situation, read_situation

ID = "vessel_gym/CollisionAvoidance-v0"
#: DNV's situation codes and the task's classification of the same start (rules 13-15)
CODES = {"HO": HEAD_ON, "CR-GW": GIVE_WAY, "CR-SO": STAND_ON, "OT-GW": OVERTAKING, "OT-SO": OVERTAKEN}


def test_the_55_files_are_shipped_with_their_licence():
    files = sorted(DNV_DIR.glob("traffic_situation_*.json"))
    assert len(files) == DNV_COUNT == 55
    assert "MIT License" in (DNV_DIR / "LICENSE").read_text()
    assert "dnv-opensource/ship-traffic-generator" in (DNV_DIR / "README.md").read_text()


@pytest.mark.parametrize("number", range(1, 56))
def test_every_situation_reads_unchanged_and_is_classified_as_dnv_says(number):
    """Each file reads as it is (schema 0.2: the start on the first waypoint), with DNV's number of targets,
    each target on a collision course (DNV's meeting distance 0: planned DCPA below 30 m) and in the situation
    its title names, classified by the task's own sectors."""
    path = DNV_DIR / f"traffic_situation_{number:02d}.json"
    title = json.loads(path.read_text())["title"]
    enc = dnv_situation(number)
    assert enc.name == f"dnv:{number}" and len(enc.targets) == DNV_TARGETS[number - 1]
    assert enc.speed == pytest.approx(10.0 * 1852.0 / 3600.0)
    assert enc.goal == pytest.approx((9259.0, 0.0), abs=2.0)  # 5 nm north
    codes = [c.strip() for c in title.split(",")]
    assert sorted(CODES[c] for c in codes) == sorted(t.situation for t in enc.targets)
    assert all(d < 30.0 and t > 0.0 for d, t in enc.planned_cpa)
    assert read_situation(path).targets == enc.targets


def test_a_dnv_situation_runs_and_its_target_starts_where_the_file_says():
    env = gym.make(ID, observation_type="physical")
    lay = env.unwrapped.observation_layout
    obs, info = env.reset(seed=0, options={"scenario": "dnv:1", "heading_deg": 0.0})
    assert info["scenario"] == "dnv:1"
    t = dnv_situation(1).targets[0]
    assert lay.value(obs, "t0_range") == pytest.approx(math.hypot(t.n, t.e), rel=1e-4)
    assert lay.value(obs, "t0_head_on") == 1.0
    _obs, _r, te, tr, info = env.step(np.zeros(1, dtype=np.float32))
    assert not (te or tr)


def test_dnv_options_are_checked():
    env = gym.make(ID)
    with pytest.raises(ValueError, match="dnv:56 does not exist"):
        env.reset(seed=0, options={"scenario": "dnv:56"})
    with pytest.raises(ValueError, match="a number"):
        env.reset(seed=0, options={"scenario": "dnv:x"})
    env1 = gym.make(ID, max_targets=1, encounters="dnv")
    for seed in range(5):
        _obs, info = env1.reset(seed=seed)
        assert info["scenario"] in {f"dnv:{i}" for i in range(1, 6)}


def test_a_situation_faster_than_the_ship_runs_slower_on_the_same_paths():
    """Situation 25's overtaking target makes 19.1 kn, beyond the KVLCC2's engine: every speed is scaled so
    that it makes the test speed; the positions, courses and planned DCPA are the file's, the TCPA longer."""
    from vessel_gym.envs.tasks.colreg_situation import within_speed

    enc = dnv_situation(25)
    top = 15.5 * 1852.0 / 3600.0
    slow = within_speed(enc, top)
    f = top / max(t.speed for t in enc.targets)
    assert f < 0.85 and max(t.speed for t in slow.targets) == pytest.approx(top)
    assert slow.speed == pytest.approx(enc.speed * f)
    for a, b, (d0, t0), (d1, t1) in zip(enc.targets, slow.targets, enc.planned_cpa, slow.planned_cpa):
        assert (b.n, b.e, b.psi) == (a.n, a.e, a.psi) and b.speed == pytest.approx(a.speed * f)
        assert d1 == pytest.approx(d0) and t1 == pytest.approx(t0 / f)
    assert within_speed(dnv_situation(1), top) == dnv_situation(1)
    env = gym.make(ID)
    _obs, info = env.reset(seed=0, options={"scenario": "dnv:25"})
    assert info["scenario"] == "dnv:25"
