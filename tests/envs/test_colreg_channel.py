"""Rule 9 (narrow channels): the checks of colreg_rules.narrow_channel on hand-built tracks (each must pass
and fail), and CollisionAvoidanceNarrow-v0 (the narrow channel colreg_narrow) timing them per step."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.envs.tasks.colreg_geometry import HEAD_ON, OVERTAKING, SAFE
from vessel_gym.envs.tasks.colreg_rules import episode_metrics, narrow_channel

NARROW = "vessel_gym/CollisionAvoidanceNarrow-v0"
L = 320.0
HALF, ALONG, RISK, PASS = 800.0, math.radians(45.0), 3.0 * L, 1.0 * L  # the Narrow preset's, m and rad


def breaches(track, others_at=lambda i: []):
    """Seconds (10 s steps) in each breach over a track of (offset m, heading off the channel rad)."""
    out = np.zeros(3)
    for i, (off, head) in enumerate(track):
        out += 10.0 * np.array(narrow_channel(off, head, others_at(i), HALF, ALONG, RISK, PASS), dtype=float)
    return out


def test_rule_9a_keeping_to_the_starboard_half_passes_and_the_port_half_fails():
    up = [(400.0, 0.0)] * 10  # northbound, 400 m to starboard of the centre line
    assert breaches(up)[0] == 0.0
    drift = [(400.0 - 100.0 * i, 0.05) for i in range(10)]  # drifts across the centre line at step 4
    assert breaches(drift)[0] == pytest.approx(50.0)  # offsets 0 (not port) then -100 .. -500: 5 steps
    down = [(-400.0, math.pi)] * 3  # southbound: its starboard side is the west (negative) half
    assert breaches(down)[0] == 0.0 and breaches([(400.0, math.pi)] * 3)[0] == pytest.approx(30.0)
    outside = [(-900.0, 0.0)] * 3  # beyond the channel's limit (800 m): rule 9 does not speak of it
    assert breaches(outside).sum() == 0.0


def test_rule_9d_crossing_impedes_a_ship_in_the_channel_only_when_there_is_a_risk():
    crossing = [(0.0, math.radians(90.0))] * 4
    ship_in_channel = (-400.0, math.pi, 200.0, 300.0, 2000.0, SAFE)  # southbound, DCPA 200 m, closing
    assert breaches(crossing, lambda i: [ship_in_channel])[1] == pytest.approx(40.0)
    far_pass = (-400.0, math.pi, 2000.0, 300.0, 2000.0, SAFE)  # DCPA beyond the risk distance
    opened = (-400.0, math.pi, 200.0, -30.0, 2000.0, SAFE)  # past its CPA
    crossing_too = (-400.0, math.radians(-90.0), 200.0, 300.0, 2000.0, SAFE)  # not along the channel
    outside = (-1000.0, math.pi, 200.0, 300.0, 2000.0, SAFE)
    for other in (far_pass, opened, crossing_too, outside):
        assert breaches(crossing, lambda i, o=other: [o])[1] == 0.0, other
    along = [(300.0, math.radians(30.0))] * 4  # within 45 deg of the channel: along it, not crossing
    assert breaches(along, lambda i: [ship_in_channel])[1] == 0.0


def test_rule_9e_overtaking_closer_than_the_passing_distance_fails():
    track = [(300.0, 0.0)] * 6
    ranges = [1500.0, 900.0, 400.0, 250.0, 300.0, 700.0]  # the pass: 250 and 300 m < 320 m
    close = lambda i: [(250.0, 0.0, 100.0, 60.0, ranges[i], OVERTAKING)]  # noqa: E731
    assert breaches(track, close)[2] == pytest.approx(20.0)
    wide = lambda i: [(-300.0, 0.0, 600.0, 60.0, max(ranges[i], 600.0), OVERTAKING)]  # noqa: E731
    assert breaches(track, wide)[2] == 0.0
    meeting = lambda i: [(-400.0, math.pi, 100.0, 60.0, ranges[i], HEAD_ON)]  # noqa: E731  (not overtaking)
    assert breaches(track, meeting)[2] == 0.0


def test_the_narrow_channel_times_rule_9_and_its_banks_ground():
    """CollisionAvoidanceNarrow-v0: the route runs 400 m to starboard of the channel's centre line; a ship
    holding 20 deg to port of the channel crosses the centre line (rule 9(a) timed from then) and grounds on
    the west bank at 1200 m to port; the route follower overtaking a slow ship on the own line passes within
    1 L (9(e))."""
    env = gym.make(NARROW, observation_type="physical")
    _obs, info = env.reset(seed=1, options={"scenario": "lanes:opposing"})
    assert info["channel_scored"] and not info["tss_scored"]
    task = env.unwrapped.task
    infos = []
    for _ in range(200):
        sim = task.sim  # a heading hold on -20 deg (PD, rudder as a fraction of its limit)
        order = np.clip(3.0 * (math.radians(-20.0) - float(sim.heading[0])) - 60.0 * float(sim.r[0]), -1, 1)
        _obs, _r, te, tr, info = env.step(np.array([order], dtype=np.float32))
        infos.append(info)
        east = float(task.sim.east[0])
        if east > -400.0 + 10.0:  # still on the starboard half (the midship point)
            assert info["rule9_port_side_s"] == 0.0
        if te or tr:
            break
    assert info["outcome"] == "grounding" and info["rule9_port_side_s"] > 0.0
    m = episode_metrics(infos, True)
    assert m["rule9_violation"] == 1.0 and m["rule9_port_side_s"] == info["rule9_port_side_s"]
    from vessel_gym.envs.debrief import colreg_debrief

    last = colreg_debrief(task, info, "grounding")[-1]
    assert last.startswith(f"  rule 9: {info['rule9_port_side_s']:.0f} s on the channel's port half (9(a)), 0 s")
    from vessel_gym.policy import load_policy

    pilot = load_policy("scripted", env)
    obs, info = env.reset(seed=2, options={"scenario": "lanes:overtaking"})
    pilot.reset()
    for _ in range(300):
        obs, _r, te, tr, info = env.step(pilot(obs))
        if te or tr:
            break
    assert info["rule9_close_overtake_s"] > 0.0 and info["rule9_port_side_s"] == 0.0
    _obs, info = gym.make("vessel_gym/CollisionAvoidanceChannel-v0").reset(seed=0)
    assert not info["channel_scored"] and "rule9_violation" not in episode_metrics([info], False)


def test_narrow_lane_traffic_is_inside_the_channel():
    env = gym.make(NARROW)
    for seed in range(4):
        env.reset(seed=seed)
        task = env.unwrapped.task
        members = task.world.members[0]
        for j in members[1:]:
            if task.world.active[j]:
                assert -1200.0 + 60.0 < float(task.sim.east[j]) < 400.0 - 60.0


def test_the_open_sea_agent_runs_in_the_narrow_channel_only_without_the_sweep():
    """An agent may run on another preset of its task where its observation fits: the shipped open-sea PPO
    (no sweep) in the narrow channel with sensors=0; with the preset's 24 sectors, one clear error."""
    from agents.config import UsageError
    from agents.evaluation import evaluate

    model = "agents/trained/ppo_CollisionAvoidance-v0_seed0.zip"
    out = evaluate(NARROW, model, episodes=1, seed=3, env_kwargs={"sensors": 0})
    assert out["summary"]["episodes"] == 1 and "grounding_rate" in out["summary"]
    with pytest.raises(UsageError, match=r"observation shape \(49,\) does not match the environment's \(73,\)"):
        evaluate(NARROW, model, episodes=1, env_kwargs={})
    with pytest.raises(UsageError, match="nor another preset of its task"):
        evaluate("vessel_gym/ZigZag-v1", model, episodes=1)
