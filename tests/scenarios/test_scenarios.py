"""Scenario files: the built-in harbour, strict validation with one-line errors naming file and key."""

from __future__ import annotations

from pathlib import Path

import gymnasium as gym
import pytest

import vessel_gym.envs  # noqa: F401
from vessel_gym.scenarios import ScenarioError, builtin_scenarios, load_scenario
from vessel_gym.scenarios.geometry import point_in_polygon, polygons_overlap, self_intersection
from vessel_gym.scenarios.scenario import SCENARIO_DIR

HARBOUR = (SCENARIO_DIR / "harbour.toml").read_text()


def _write(tmp_path: Path, text: str, name: str = "port.toml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def test_builtin_harbour_loads():
    assert "harbour" in builtin_scenarios()
    sc = load_scenario("harbour")
    assert sc.name == "harbour" and sc.ship == "kvlcc2_l7"
    assert sc.goal_point == (65.0, 0.0)
    assert {k for k, _n, _p in sc.hard_obstacles()} == {"land", "breakwater", "quay"}
    assert [n for n, _p in sc.shoals(sc.load_ship().particulars.T_m)] == ["east shoal", "outer bank"]


def test_user_file_via_make(tmp_path):
    p = _write(tmp_path, HARBOUR.replace('name = "harbour"', 'name = "my port"'))
    env = gym.make("vessel_gym/HarbourApproach-v2", scenario=str(p))
    env.reset(seed=0)
    assert env.unwrapped.task.scenario.name == "my port"
    env = gym.make("vessel_gym/HarbourApproach-v2", scenario=load_scenario(p))
    assert env.unwrapped.task.scenario.path == str(p)


GOAL = "points = [[58.0, -10.0], [72.0, -10.0], [72.0, 10.0], [58.0, 10.0]]\npoint_m = [65.0, 0.0]"
START = "points = [[-120.0, -30.0], [-80.0, -30.0], [-80.0, 30.0], [-120.0, 30.0]]"
QUAY = 'name = "north quay"\npoints = [[80.0, -40.0], [84.0, -40.0], [84.0, 40.0], [80.0, 40.0]]'


@pytest.mark.parametrize(
    "old,new,message",
    [
        ("reference_latlon_deg", 'colour = "red"\nreference_latlon_deg', r"port\.toml: unknown key 'colour'"),
        (
            "heading_tolerance_deg = 30.0",
            "heading_tolerance_deg = 30.0\nradius_m = 3.0",
            r"port\.toml goal: unknown key 'radius_m'",
        ),
        ("max_speed_m_s = 0.12", "max_speed_m_s = -1.0", r"port\.toml goal max_speed_m_s: -1 m/s is outside"),
        (
            GOAL,
            "points = [[58.0, -10.0], [72.0, 10.0], [72.0, -10.0], [60.0, 12.0]]",
            r"port\.toml goal points: polygon is self-intersecting",
        ),
        (
            GOAL,
            "points = [[76.0, -10.0], [82.0, -10.0], [82.0, 10.0], [76.0, 10.0]]",
            r"port\.toml goal points: region overlaps quay 'north quay'",
        ),
        (
            GOAL,
            "points = [[30.0, 45.0], [40.0, 45.0], [40.0, 55.0], [30.0, 55.0]]",
            r"port\.toml goal points: region overlaps depth area 'east shoal', shallower than the draught",
        ),
        (
            GOAL,
            "points = [[58.0, -10.0], [72.0, -10.0], [72.0, 10.0], [58.0, 10.0]]\npoint_m = [0.0, 0.0]",
            r"port\.toml goal point_m: not inside the goal polygon",
        ),
        (
            START,
            "points = [[-160.0, -30.0], [-80.0, -30.0], [-80.0, 30.0], [-160.0, 30.0]]",
            r"port\.toml start points: region extends outside bounds_m",
        ),
        (
            "speed_m_s = [0.7, 1.18]",
            "speed_m_s = [1.18, 0.7]",
            r"port\.toml start speed_m_s: min 1.18 > max 0.7",
        ),
        (
            QUAY,
            'name = "north quay"\npoints = [[80.0, -40.0], [84.0, -40.0]]',
            r"port\.toml quay\[0\] 'north quay' points: a polygon needs at least 3 points",
        ),
        ('ship = "kvlcc2_l7"', 'ship = "titanic"', r"port\.toml ship: .*unknown ship"),
        ("route_m = [[-30.0, 0.0]", "route_m = [[-1.0, -30.0]", r"port\.toml route_m\[0\]: on breakwater"),
        ("[goal]", "[goal\n", r"port\.toml: TOML syntax error"),
    ],
)
def test_invalid_file_one_line_error_naming_file_and_key(tmp_path, old, new, message):
    assert old in HARBOUR
    p = _write(tmp_path, HARBOUR.replace(old, new, 1))
    with pytest.raises(ScenarioError, match=message) as exc:
        load_scenario(p)
    assert "\n" not in str(exc.value)


def test_unknown_name_lists_builtins():
    with pytest.raises(ScenarioError, match="unknown scenario.*harbour"):
        load_scenario("atlantis")


def test_geometry_helpers():
    sq = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    assert self_intersection(sq) is None
    assert self_intersection([(0.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)]) is not None
    assert point_in_polygon((0.5, 0.5), sq) and not point_in_polygon((1.5, 0.5), sq)
    assert polygons_overlap(sq, [(0.5, 0.5), (2.0, 0.5), (2.0, 2.0)])
    assert polygons_overlap(sq, [(0.2, 0.2), (0.4, 0.2), (0.4, 0.4)])  # contained
    assert not polygons_overlap(sq, [(2.0, 2.0), (3.0, 2.0), (3.0, 3.0)])


def test_docs_list_every_scenario_key():
    import dataclasses

    from vessel_gym.scenarios.scenario import Area, DepthArea, GoalRegion, Scenario, StartRegion, Weather

    doc = (Path(__file__).parents[2] / "docs" / "scenarios.md").read_text()
    for cls in (Scenario, Area, DepthArea, StartRegion, GoalRegion, Weather):
        for f in dataclasses.fields(cls):
            if f.init:
                assert f"`{f.name}`" in doc, (cls.__name__, f.name)
