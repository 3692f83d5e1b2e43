"""CollisionAvoidance: hull contact, CPA, the COLREG situations, the Imazu cases and the generator, the frame
convention of the observation, the rule checks and the baselines."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.envs.tasks.colreg_encounters import IMAZU, generate, imazu
from vessel_gym.envs.tasks.colreg_geometry import (
    GIVE_WAY,
    HEAD_ON,
    OVERTAKEN,
    OVERTAKING,
    SAFE,
    STAND_ON,
    classify,
    cpa,
    hulls_touch,
    place,
)
from vessel_gym.envs.tasks.colreg_rules import R, detect, new_record, pair_checks, track
from vessel_gym.scenarios.geometry import hull_outline

ID = "vessel_gym/CollisionAvoidance-v0"
L, B, U = 320.0, 58.0, 7.97


def test_hull_contact_is_of_outlines_not_circles():
    """Parallel ships 1.2 beams apart (centres 70 m, far inside a circle of a ship length) do not touch; at 0.9
    beams they do. Head-on, the pointed bows touch at 320 m between centres only when in line: offset by 0.6
    beam, the bows' tapers (the last 0.2 L) pass where rectangles would overlap."""
    hull = hull_outline(L, B)
    a = place(hull, 0.0, 0.0, 0.0)
    assert not hulls_touch(a, place(hull, 0.0, 1.2 * B, 0.0))
    assert hulls_touch(a, place(hull, 0.0, 0.9 * B, 0.0))
    assert hulls_touch(a, place(hull, L - 1.0, 0.0, math.pi))
    assert not hulls_touch(a, place(hull, L + 1.0, 0.0, math.pi))
    # bow to bow, offset by 0.6 B: the rectangles would overlap by 0.4 B at centres L - 0.3 B apart
    assert not hulls_touch(a, place(hull, L - 0.3 * B, 0.6 * B, math.pi))
    # a ship across another's bow: touches only within its beam of the stem
    assert hulls_touch(a, place(hull, 0.5 * L + 0.4 * B, 0.0, 0.5 * math.pi))
    assert not hulls_touch(a, place(hull, 0.5 * L + 0.6 * B, 0.0, 0.5 * math.pi))


def test_cpa_analytic():
    # head-on, 10 km apart, both at U: meet after 10 km / 2U
    d, t = cpa(10_000.0, 0.0, -2.0 * U, 0.0)
    assert d == pytest.approx(0.0, abs=1e-9) and t == pytest.approx(10_000.0 / (2.0 * U))
    # a target 1 km to starboard on a parallel course, 5 km ahead and slower: passes at 1 km abeam
    d, t = cpa(5_000.0, 1_000.0, -3.0, 0.0)
    assert d == pytest.approx(1_000.0) and t == pytest.approx(5_000.0 / 3.0)
    # opening: the closest point is behind; DCPA is the present range
    d, t = cpa(3_000.0, 4_000.0, 1.0, 0.0)
    assert t < 0.0 and d == pytest.approx(5_000.0)


@pytest.mark.parametrize(
    "case, want",
    [
        (1, [HEAD_ON]),
        (2, [GIVE_WAY]),
        (3, [OVERTAKING]),
        (4, [STAND_ON]),
        (13, [HEAD_ON, STAND_ON, STAND_ON]),
    ],
)
def test_imazu_cases_are_classified_as_the_rules_say(case, want):
    enc = imazu(case, L, U, 25.0, np.random.default_rng(0), (0.0, 0.0))
    assert [t.situation for t in enc.targets] == want
    for d, tc in enc.planned_cpa:
        assert d == pytest.approx(0.0, abs=1e-6)  # every Imazu target is on a collision course
        assert tc == pytest.approx(25.0 * L / U)


def test_imazu_table_has_the_22_cases_with_one_to_three_targets():
    assert sorted(IMAZU) == list(range(1, 23))
    assert [len(IMAZU[i]) for i in (1, 4, 5, 11, 12, 22)] == [1, 1, 2, 2, 3, 3]


def test_classification_sectors():
    north = 0.0
    # a target 2 km dead astern, same course, faster: it overtakes the own ship
    assert classify(-2000.0, 0.0, north, north, True) == OVERTAKEN
    # the own ship 2 km astern of a target: the own ship overtakes
    assert classify(2000.0, 0.0, north, north, True) == OVERTAKING
    # fine on the starboard bow, heading west: crossing, give way; mirrored to port: stand on
    assert classify(2000.0, 1000.0, north, -0.5 * math.pi, True) == GIVE_WAY
    assert classify(2000.0, -1000.0, north, 0.5 * math.pi, True) == STAND_ON
    assert classify(2000.0, 1000.0, north, -0.5 * math.pi, False) == SAFE


@pytest.mark.parametrize("kind", ["head_on", "overtaking", "give_way", "stand_on"])
def test_generator_works_back_from_situation_dcpa_and_tcpa(kind):
    rng = np.random.default_rng(5)
    enc = generate((kind,), (400.0,), (900.0,), U, rng)
    (t,), ((d, tc),) = enc.targets, enc.planned_cpa
    assert t.situation == {"head_on": HEAD_ON, "overtaking": OVERTAKING, "give_way": GIVE_WAY}.get(
        kind, STAND_ON
    )
    assert classify(t.n, t.e, 0.0, t.psi, True) == t.situation
    assert d == pytest.approx(400.0, rel=1e-9) and tc == pytest.approx(900.0, rel=1e-9)


def test_realised_cpa_of_a_generated_encounter_is_the_planned_one():
    """With the rudder amidships both ships hold course: the closest range the simulation reaches is the
    generator's DCPA (the ships' steady starts keep their speeds)."""
    env = gym.make(ID, generated_dcpa_L=[3.0, 3.0], generated_tcpa_fraction=[1.0, 1.0])
    _obs, info = env.reset(seed=3, options={"scenario": "generated:give_way", "heading_deg": 30.0})
    planned = info["planned_dcpa_m"]
    assert planned == pytest.approx(3.0 * L, rel=1e-9)
    while True:
        _obs, _r, te, tr, info = env.step(np.zeros(1, dtype=np.float32))
        if te or tr:
            break
    assert info["outcome"] == "arrived" and not info["collision"]
    assert info["min_separation_m"] == pytest.approx(planned, rel=0.02)


def test_targets_share_the_own_ships_simulation():
    env = gym.make(ID, max_targets=3)
    assert env.unwrapped.task.sim.n == 4
    venv = gym.make_vec(ID, num_envs=2, vectorization_mode="vector_entry_point")
    assert venv.unwrapped.task.sim.n == 2 + 2 * 3
    venv.close()


def test_the_frame_convention_body_frame_bearings_clockwise_from_the_bow():
    """The observation does not change when the whole encounter is turned (own heading 0 or 137 deg); a
    give-way target is on the starboard side (bearing sin > 0), a stand-on target to port; a head-on target
    is dead ahead closing (rel_u < 0, TCPA > 0)."""
    env = gym.make(ID, observation_type="physical")
    lay = env.unwrapped.observation_layout
    a, _ = env.reset(seed=7, options={"scenario": "imazu:13", "heading_deg": 0.0})
    b, _ = env.reset(seed=7, options={"scenario": "imazu:13", "heading_deg": 137.0})
    np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-3)
    obs, _ = env.reset(seed=1, options={"scenario": "imazu:2", "heading_deg": 250.0})
    assert lay.value(obs, "t0_give_way") == 1.0 and lay.value(obs, "t0_bearing_sin") > 0.5
    assert lay.value(obs, "t0_valid") == 1.0 and lay.value(obs, "t1_valid") == 0.0
    assert lay.value(obs, "t1_range") == 0.0  # an empty slot is all zeros
    obs, _ = env.reset(seed=1, options={"scenario": "imazu:4", "heading_deg": 10.0})
    assert lay.value(obs, "t0_stand_on") == 1.0 and lay.value(obs, "t0_bearing_sin") < -0.5
    obs, _ = env.reset(seed=1, options={"scenario": "imazu:1", "heading_deg": 300.0})
    assert lay.value(obs, "t0_head_on") == 1.0 and lay.value(obs, "t0_bearing_cos") > 0.99
    assert lay.value(obs, "t0_rel_u") < -1.5 * U and lay.value(obs, "t0_tcpa") > 0.0
    assert abs(lay.value(obs, "goal_sin")) < 1e-6 and lay.value(obs, "goal_cos") == pytest.approx(1.0)


def test_target_list_is_ordered_by_danger():
    env = gym.make(ID, observation_type="physical")
    lay = env.unwrapped.observation_layout
    obs, _ = env.reset(seed=2, options={"scenario": "imazu:12"})
    keys = [lay.value(obs, f"t{j}_dcpa") + 0.1 * lay.value(obs, f"t{j}_range") for j in range(3)]
    assert keys == sorted(keys) and all(lay.value(obs, f"t{j}_valid") == 1.0 for j in range(3))


def test_scenario_options_are_checked():
    env = gym.make(ID)
    with pytest.raises(ValueError, match="does not exist"):
        env.reset(seed=0, options={"scenario": "imazu:23"})
    with pytest.raises(ValueError, match="unknown scenario"):
        env.reset(seed=0, options={"scenario": "nope:1"})
    with pytest.raises(ValueError, match="unknown reset option"):
        env.reset(seed=0, options={"scenari": "imazu:1"})
    with pytest.raises(ValueError, match="takes 0 to 1"):
        gym.make(ID, max_targets=1).reset(seed=0, options={"scenario": "imazu:12"})
    _o, info = env.reset(seed=0, options={"scenario": "imazu:12"})
    assert info["scenario"] == "imazu:12"


def _record(situation, headings, ranges, tcpas, ahead=False):
    row = np.zeros(len(R))
    new_record(row)
    detect(row, situation, 0.0, 0.0, U, ranges[0], tcpas[0])
    for i, (h, r, t) in enumerate(zip(headings, ranges, tcpas)):
        track(row, 10.0 * i, math.radians(h), U, r, t, ahead, math.radians(5.0), 4 * L)
    return pair_checks(row, 0.5, math.radians(30.0), math.radians(10.0), 0.1)


def test_rule_checks():
    ranges, tcpas = [16000, 12000, 8000, 4000, 1000, 3000], [1000, 750, 500, 250, 60, -100]
    # head-on: an early, substantial turn to starboard passes every check
    assert _record(HEAD_ON, [0, 35, 40, 40, 20, 0], ranges, tcpas) == {
        "early": True,
        "substantial": True,
        "starboard": True,
    }
    # the same turn to port fails starboard; a late small turn fails early and substantial
    assert not _record(HEAD_ON, [0, -35, -40, -40, 0, 0], ranges, tcpas)["starboard"]
    late = _record(HEAD_ON, [0, 0, 0, 0, 12, 0], ranges, tcpas)
    assert late == {"early": False, "substantial": False, "starboard": True}
    # crossing give-way passing ahead of the target fails not_ahead
    assert not _record(GIVE_WAY, [0, 40, 40, 40, 40, 0], ranges, tcpas, ahead=True)["not_ahead"]
    # stand-on: course kept until the release range, then a starboard turn, passes; an early port turn fails
    assert _record(STAND_ON, [0, 2, 0, 0, 40, 0], ranges, tcpas) == {"stand_on": True, "no_port": True}
    assert _record(STAND_ON, [0, -20, -30, 0, 0, 0], ranges, tcpas) == {"stand_on": False, "no_port": False}
    assert _record(SAFE, [0, 90, 0, 0, 0, 0], ranges, tcpas) == {}


def test_route_follower_collides_and_the_episode_ends_as_a_collision():
    from vessel_gym.envs.tasks.colreg import route_pilot

    env = gym.make(ID)
    pilot = route_pilot(env)
    obs, _ = env.reset(seed=0, options={"scenario": "imazu:1"})
    while True:
        obs, r, te, tr, info = env.step(pilot(obs))
        if te or tr:
            break
    assert te and info["collision"] and info["outcome"] == "collision" and not info["success"]
    assert info["reward_terms"]["collision"] == -20.0
    assert info["min_separation_m"] < L  # the hulls touch: midships within a ship length
    assert info["colreg_passed"]["starboard"] == 0 and info["colreg_violations"] == 1
    assert info["reaction_delay_s"] == -1.0  # it never alters course


@pytest.mark.parametrize("case", [1, 2, 5, 13])
def test_velocity_obstacle_pilot_passes_imazu_cases_by_the_rules(case):
    from vessel_gym.envs.tasks.colreg import vo_pilot

    env = gym.make(ID)
    pilot = vo_pilot(env)
    obs, _ = env.reset(seed=case, options={"scenario": f"imazu:{case}"})
    pilot.reset()
    while True:
        obs, r, te, tr, info = env.step(pilot(obs))
        if te or tr:
            break
    assert info["success"] and not info["collision"]
    assert info["min_separation_L"] > 1.5
    p, a = info["colreg_passed"], info["colreg_applied"]
    assert p["starboard"] == a["starboard"] >= 1  # head-on and give-way: altered to starboard
    assert p["early"] == a["early"]
    assert 0.0 <= info["reaction_delay_s"] <= 60.0  # acts within a few steps of detection


def test_evaluation_reports_rates_and_colreg_scores():
    from agents.evaluation import evaluate

    out = evaluate(ID, "scripted", episodes=2, seed=0)["summary"]
    assert out["success_rate"] == 0.0 and out["collision_rate"] == 1.0
    assert 0.0 <= out["colreg_score_mean"] < 0.5 and out["colreg_violation_mean"] == 1.0
    good = evaluate(ID, "pid", episodes=2, seed=0)["summary"]
    assert good["success_rate"] == 1.0 and good["collision_rate"] == 0.0
    assert good["colreg_score_mean"] > out["colreg_score_mean"]


def test_evaluate_json_reports_success_and_collision_rates_and_colreg_scores(capsys):
    import json

    from agents.evaluate import main

    assert main(["--env", ID, "--agent", "scripted", "--episodes", "2", "--seed", "0", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["success_rate"] == 0.0 and out["collision_rate"] == 1.0
    for key in ("mean_colreg_score", "mean_colreg_violation", "mean_min_separation_L", "mean_path_ratio"):
        assert key in out, key
    assert "mean_starboard_ok" in out and "mean_rudder_reversals" in out


def _situation(tmp_path, **over):
    """A head-on traffic situation in the maritime-schema format: the target 5 NM north, 0.2 NM to the east,
    on the reciprocal course; both at 12 kn; the own ship's goal 10 NM north."""
    lat0, lon0 = 58.7, 10.5
    dlat = 1.0 / 60.0  # deg per NM of latitude
    dlon = 1.0 / (60.0 * math.cos(math.radians(lat0)))  # deg per NM of longitude there
    data = {
        "version": "0.8.1",
        "title": "HO test",
        "ownShip": {
            "initial": {"position": {"lat": lat0, "lon": lon0}, "sog": 12.0, "cog": 0.0, "heading": 0.0},
            "waypoints": [
                {"position": {"lat": lat0, "lon": lon0}},
                {"position": {"lat": lat0 + 10 * dlat, "lon": lon0}},
            ],
            "static": {"id": 1, "dimensions": {"length": 122.0, "width": 20.0}},
        },
        "targetShips": [
            {
                "initial": {
                    "position": {"lat": lat0 + 5 * dlat, "lon": lon0 + 0.2 * dlon},
                    "sog": 12.0,
                    "cog": 180.0,
                    "heading": 180.0,
                },
            }
        ],
    }
    data.update(over)
    path = tmp_path / "ho.json"
    path.write_text(__import__("json").dumps(data))
    return path


def test_a_maritime_schema_traffic_situation_runs_as_an_encounter(tmp_path):
    from vessel_gym.envs.tasks.colreg_situation import read_situation

    nm, kn = 1852.0, 1852.0 / 3600.0  # positions within 1 %: one minute of arc is not 1852 m at 58.7 deg N
    enc = read_situation(_situation(tmp_path))
    (t,), ((d, tc),) = enc.targets, enc.planned_cpa
    assert t.situation == HEAD_ON and enc.speed == pytest.approx(12 * kn)
    assert d == pytest.approx(0.2 * nm, rel=1e-2) and tc == pytest.approx(5 * nm / (24 * kn), rel=1e-2)
    assert enc.goal[0] == pytest.approx(10 * nm, rel=1e-2) and abs(enc.goal[1]) < 1.0
    env = gym.make(ID, observation_type="physical", tcpa_L=40.0)  # the goal distance's scale: 80 L = 25.6 km
    lay = env.unwrapped.observation_layout
    obs, info = env.reset(seed=0, options={"scenario": f"file:{_situation(tmp_path)}", "heading_deg": 45.0})
    assert info["scenario"] == "file:HO test" and info["planned_dcpa_m"] == pytest.approx(0.2 * nm, rel=1e-2)
    assert lay.value(obs, "u") == pytest.approx(12 * kn, rel=1e-3)
    assert lay.value(obs, "goal_distance") == pytest.approx(10 * nm, rel=1e-2)
    assert lay.value(obs, "t0_head_on") == 1.0 and lay.value(obs, "t0_range") == pytest.approx(
        5 * nm, rel=1e-2
    )


def test_a_malformed_traffic_situation_is_named(tmp_path):
    from vessel_gym.envs.tasks.colreg_situation import read_situation

    with pytest.raises(ValueError, match=r"targetShips: expected a list"):
        read_situation(_situation(tmp_path, targetShips=[]))
    with pytest.raises(ValueError, match=r"ownShip.initial.sog: expected a number"):
        read_situation({"ownShip": {"initial": {"position": {"lat": 1.0, "lon": 2.0}, "sog": "fast"}}})
    with pytest.raises(ValueError, match="not a readable traffic-situation file"):
        read_situation(tmp_path / "missing.json")


@pytest.mark.parametrize("react", [False, True])
def test_reacting_targets_give_way_to_a_stand_on_own_ship(react):
    """A target crossing from port on a collision course must give way (rule 15). Constant-velocity, it hits
    the own ship that stands on; keeping the rules (targets_react), it turns to starboard and passes astern,
    and the own ship's standing on passes its checks."""
    env = gym.make(ID, targets_react=react, generated_dcpa_L=[0.0, 0.0], generated_tcpa_fraction=[1.0, 1.0])
    _obs, info = env.reset(seed=4, options={"scenario": "generated:stand_on", "heading_deg": 0.0})
    while True:
        _obs, _r, te, tr, info = env.step(np.zeros(1, dtype=np.float32))
        if te or tr:
            break
    if not react:
        assert info["collision"]
        return
    assert info["success"] and not info["collision"] and info["min_separation_L"] > 1.0
    assert info["colreg_passed"] == info["colreg_applied"] and info["colreg_applied"]["stand_on"] == 1
