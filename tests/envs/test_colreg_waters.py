"""CollisionAvoidance in restricted waters (CollisionAvoidanceChannel-v0: the two-lane scheme colreg_tss,
grounding on land and shoals) and the range-sensor sweep over land and hull outlines."""

from __future__ import annotations

import math
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.envs.tasks.colreg_encounters import lanes
from vessel_gym.envs.tasks.colreg_geometry import (
    HEAD_ON,
    OVERTAKING,
    SAFE,
    place,
    polygon_edges,
    sector_minima,
    sweep,
    sweep_bearings,
)
from vessel_gym.physics.schema import SpecError
from vessel_gym.scenarios.geometry import hull_outline
from vessel_gym.scenarios.scenario import SCENARIO_DIR

CHANNEL = "vessel_gym/CollisionAvoidanceChannel-v0"
OPEN = "vessel_gym/CollisionAvoidance-v0"
L, B, T, U = 320.0, 58.0, 20.8, 7.97
EAST_BANK = 1300.0  # m east of the own lane's centre line (colreg_tss.toml)


def test_sweep_reads_a_hull_dead_ahead_and_a_coast_abeam():
    """Pure geometry: a ship lying across the bow 2000 m ahead (its near side B/2 nearer) is read at
    2000 - B/2 in sector 0 only; a straight coast 1300 m to starboard is read at 1300 m in the beam sector
    (90 deg, sector 6 of 24) and at 1300 / cos(off-beam angle of the nearest ray) in its neighbours; the
    port side reads the sensor range."""
    bearings = sweep_bearings(24)
    hull = place(hull_outline(L, B), 2000.0, 0.0, 0.5 * math.pi)
    coast = [(-5000.0, EAST_BANK), (5000.0, EAST_BANK), (5000.0, 3000.0), (-5000.0, 3000.0)]
    reads = sector_minima(sweep(0.0, 0.0, 0.0, bearings, polygon_edges([hull, coast]), 3200.0), 24)
    assert reads[0] == pytest.approx(2000.0 - B / 2.0)
    assert reads[6] == pytest.approx(EAST_BANK)
    # sector 5 (centre 75 deg): its rays at 69..81 deg; the nearest, at 81 deg, meets the coast at 1300 / sin
    assert reads[5] == pytest.approx(EAST_BANK / math.sin(math.radians(75.0 + 0.4 * 15.0)))
    assert np.all(reads[12:] == 3200.0)  # astern and to port: nothing within range
    # the same scene turned: own heading 90 deg (east), the coast now dead ahead, the hull on the port beam
    turned = sector_minima(sweep(0.0, 0.0, 0.5 * math.pi, bearings, polygon_edges([coast]), 3200.0), 24)
    assert turned[0] == pytest.approx(EAST_BANK)


def test_a_ship_dead_ahead_reads_its_range_in_the_forward_sector():
    """Imazu case 3 without jitter: a slow target on the own course 15 L ahead; the forward sector reads the
    range to its square stern (centre range - L/2)."""
    env = gym.make(
        OPEN,
        observation_type="physical",
        sensors=24,
        sensor_range_L=20.0,
        imazu_heading_jitter_deg=0.0,
        imazu_speed_jitter=0.0,
    )
    lay = env.unwrapped.observation_layout
    obs, _ = env.reset(seed=0, options={"scenario": "imazu:3", "heading_deg": 33.0})
    centre = lay.value(obs, "t0_range")
    assert centre == pytest.approx(15.0 * L, rel=1e-3)
    assert lay.value(obs, "sensor0") == pytest.approx(centre - L / 2.0, rel=1e-4)
    assert all(lay.value(obs, f"sensor{i}") == pytest.approx(20.0 * L) for i in range(2, 23))
    assert env.observation_space.shape == obs.shape
    env.close()


def test_the_channel_coast_to_starboard_reads_in_the_starboard_sectors():
    env = gym.make(CHANNEL, observation_type="physical")
    lay = env.unwrapped.observation_layout
    obs, info = env.reset(seed=0, options={"scenario": "lanes:overtaking"})
    n, e = env.unwrapped.task.sim.north[0], env.unwrapped.task.sim.east[0]
    assert (n, e) == pytest.approx((0.0, 0.0), abs=1e-6)
    assert lay.value(obs, "sensor6") == pytest.approx(EAST_BANK, rel=1e-6)  # the starboard beam
    assert lay.value(obs, "sensor4") < 3200.0 and lay.value(obs, "sensor8") < 3200.0
    # the port beam: separation zone and opposite lane, empty here; the west bank is 3.7 km off
    assert lay.value(obs, "sensor18") == pytest.approx(10.0 * L)
    assert info["grounding"] is False or not info["grounding"]
    env.close()


def _steer_to_starboard(env, seed=0):
    """Run with the own ship steered onto a heading of 60 deg (towards the east bank and coast) until the
    episode ends: (last info, east position m, last reward)."""
    env.reset(seed=seed, options={"scenario": "lanes:opposing"})
    task = env.unwrapped.task
    for _ in range(400):
        error = 60.0 - math.degrees(float(task.sim.heading[0]))  # deg, + to starboard
        action = np.array([np.clip(error / 30.0, -1.0, 1.0)], dtype=np.float32)
        _obs, reward, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            return info, float(task.sim.east[0]), reward
    raise AssertionError("the episode did not end")


def test_steering_onto_the_bank_ends_the_episode_as_a_grounding():
    env = gym.make(CHANNEL)
    info, east, _ = _steer_to_starboard(env)
    assert info["outcome"] == "grounding" and info["grounding"] and not info["collision"]
    assert not info["success"]
    assert info["reward_terms"]["grounding"] == -20.0  # weighted: -1 x the default weight
    # the hull reaches the bank (1300 m east) with its midship point at most half a length short of it
    assert EAST_BANK - L / 2.0 - 1.0 <= east <= EAST_BANK + L / 2.0
    env.close()


def test_the_under_keel_margin_decides_what_is_a_shoal(tmp_path: Path):
    """A copy of colreg_tss whose banks are 22 m deep (1.2 m under the 20.8 m keel): with the default 2 m
    margin the ship grounds on the bank (1300 m east); with no margin it crosses it onto the land (2400 m)."""
    text = (SCENARIO_DIR / "colreg_tss.toml").read_text().replace("depth_m = 14.0", "depth_m = 22.0")
    path = tmp_path / "banks22.toml"
    path.write_text(text)
    with_margin = gym.make(CHANNEL, waters=str(path))
    info, east, _ = _steer_to_starboard(with_margin)
    assert info["grounding"] and east < EAST_BANK + L / 2.0
    without = gym.make(CHANNEL, waters=str(path), under_keel_m=0.0)
    info, east, _ = _steer_to_starboard(without)
    assert info["grounding"] and east > 2400.0 - L / 2.0 - 1.0
    with pytest.raises(SpecError, match="water_depth_m"):
        gym.make(CHANNEL, waters=str(path), under_keel_m=10.0)


def test_lane_traffic_is_in_the_lanes():
    """Overtaking traffic starts ahead in the own lane on the own course, slower, and is classified as
    overtaking; opposing traffic runs on the reciprocal course about the opposite lane's centre line, passing
    far outside the risk distance (no risk: safe)."""
    rng = np.random.default_rng(3)
    enc = lanes(("overtaking", "opposing"), (2000.0, 2000.0), U, L, 7.5 * L, rng)
    over, opp = enc.targets
    assert over.situation == OVERTAKING and over.psi == 0.0 and over.speed < 0.5 * U + 1e-9
    assert over.n > 0.0 and abs(over.e) <= 0.5 * L
    assert opp.psi == pytest.approx(math.pi) and abs(opp.e + 7.5 * L) <= 1.5 * L
    assert opp.situation in (HEAD_ON, SAFE)
    d_over, t_over = enc.planned_cpa[0]
    assert t_over == pytest.approx(2000.0) and d_over == pytest.approx(abs(over.e))
    d_opp, _ = enc.planned_cpa[1]
    assert d_opp == pytest.approx(abs(opp.e)) and d_opp > 3.0 * L


def test_restricted_waters_fix_the_start_heading():
    env = gym.make(CHANNEL)
    with pytest.raises(ValueError, match="heading_deg"):
        env.reset(seed=0, options={"heading_deg": 90.0})
    env.close()


def test_velocity_obstacle_pilot_keeps_off_the_banks():
    """The baseline in the channel: overtaking a slow ship in a lane 5 L wide between the separation zone and
    the bank, it arrives without collision or grounding."""
    from agents.evaluation import evaluate

    result = evaluate(CHANNEL, "pid", episodes=3, seed=0)
    s = result["summary"]
    assert s["grounding_rate"] == 0.0 and s["collision_rate"] == 0.0 and s["success_rate"] == 1.0


def test_velocity_obstacle_pilot_blocks_headings_into_land():
    """A slow ship dead ahead in the own lane: with clear sensors the pilot passes it to port (its first free
    heading); with land read within 6 L on the port bow (sectors 18-23: 270-345 deg) it turns to starboard
    instead, onto a heading whose sector reads clear."""
    from vessel_gym.envs.tasks.colreg_pilots import VelocityObstaclePilot

    env = gym.make(CHANNEL, observation_type="physical")
    lay = env.unwrapped.observation_layout
    obs, _ = env.reset(seed=0, options={"scenario": "lanes:overtaking"})
    assert lay.value(obs, "t0_overtaking") == 1.0
    clear = obs.copy()
    for i in range(24):
        clear[lay.index(f"sensor{i}")] = 10.0 * L
    free = VelocityObstaclePilot(env).heading_error(clear)
    assert free < -math.radians(5.0)  # to port
    coast = clear.copy()
    for i in range(18, 24):
        coast[lay.index(f"sensor{i}")] = 2.0 * L
    c = VelocityObstaclePilot(env).heading_error(coast)
    assert c > math.radians(5.0)  # to starboard
    sector = int(round((c % (2.0 * math.pi)) / math.radians(15.0))) % 24
    assert lay.value(coast, f"sensor{sector}") >= 6.0 * L
    env.close()


def test_evaluate_json_reports_the_grounding_rate(capsys):
    import json

    from agents.evaluate import main
    from agents.evaluation import summarize

    assert main(["--env", CHANNEL, "--agent", "pid", "--episodes", "1", "--seed", "0", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["grounding_rate"] == 0.0 and out["collision_rate"] == 0.0 and out["success_rate"] == 1.0
    assert out["per_episode"][0]["grounding"] == 0.0
    # a rate over episodes, not a mean of a metric
    s = summarize(
        [{"seed": 0, "grounding": 1.0}, {"seed": 1, "grounding": 0.0}, {"seed": 2, "grounding": 0.0}]
    )
    assert s["grounding_rate"] == pytest.approx(1.0 / 3.0) and "grounding_mean" not in s


def test_rule_10_times_in_the_zone_the_opposite_lane_and_against_the_flow():
    """Channel: a ship swinging to port leaves its lane (centre line east 0, half width 2.5 L = 800 m) with its
    heading off the flow (counted while in the lane), crosses the separation zone (800-1600 m to port) and
    enters the southbound lane; each is timed by where the midship point is. Open sea: not scored."""
    from vessel_gym.envs.tasks.colreg_rules import episode_metrics

    env = gym.make(CHANNEL, observation_type="physical")
    env.reset(seed=1, options={"scenario": "lanes:overtaking"})
    task = env.unwrapped.task
    seen = {"against": False, "zone": False, "wrong": False}
    infos = []
    for _ in range(120):
        _obs, _r, te, tr, info = env.step(np.array([-0.15], dtype=np.float32))
        infos.append(info)
        east = float(task.sim.east[0])
        if -800.0 < east and info["tss_against_flow_s"] > 0.0:
            seen["against"] = True
        if -1600.0 < east < -800.0:
            seen["zone"] = True
            assert info["tss_wrong_lane_s"] == 0.0
        if east < -1600.0:
            seen["wrong"] = info["tss_zone_s"] > 0.0 and info["tss_wrong_lane_s"] > 0.0
            break
        if te or tr:
            break
    assert all(seen.values()), seen
    assert info["tss_scored"] and episode_metrics(infos, False)["rule10_violation"] == 1.0
    from vessel_gym.envs.debrief import colreg_debrief

    last = colreg_debrief(task, info, "running")[-1]
    assert last == (
        f"  rule 10: {info['tss_zone_s']:.0f} s in the separation zone, {info['tss_wrong_lane_s']:.0f} s in the "
        f"opposite lane, {info['tss_against_flow_s']:.0f} s against the flow"
    )
    _obs, info = gym.make("vessel_gym/CollisionAvoidance-v0").reset(seed=0)
    assert not info["tss_scored"] and "rule10_violation" not in episode_metrics([info], False)
