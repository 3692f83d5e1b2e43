"""The full-scale `supply_base` harbour for the 76.2 m supply vessel: real-scale dimensions and an episode of
HarbourApproach-v1 with the ship and the scenario given as keyword arguments.

Dimensions are checked against the rules the scenario file states, from PIANC (2014) Report 121, "Harbour
approach channels design guidelines": channel, entrance and basin depth above 1.3 T in the fairway, a one-way
channel wider than 5 B, an entrance of about 2 L, a turning basin of more than 2 L diameter.
"""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym  # noqa: F401  (registers the environments)
from vessel_gym.envs.policies import HarbourPilot
from vessel_gym.physics.environment import Environment
from vessel_gym.scenarios import builtin_scenarios, load_scenario

ID = "vessel_gym/HarbourApproach-v1"


@pytest.fixture(scope="module")
def scenario():
    return load_scenario("supply_base")


def _depth(sc, name: str) -> float:
    return next(d.depth_m for d in sc.depth_area if d.name == name)


def test_real_scale_dimensions(scenario):
    sc = scenario
    assert "supply_base" in builtin_scenarios()
    ship = sc.load_ship()
    L, B, T = ship.particulars.L_m, ship.particulars.B_m, ship.particulars.T_m
    assert ship.name == "supply" and L == pytest.approx(76.2)
    # fairway depths above 1.3 T; the banks and the shallows are grounding areas for this draught
    for name in ("approach channel", "harbour basin"):
        assert _depth(sc, name) >= 1.3 * T, name
    assert {n for n, _ in sc.shoals(T)} == {"west bank", "east bank", "south-west shallows"}
    # entrance between the breakwater heads (the vertices nearest the centre line): about 2 L
    heads = [min(abs(p[1]) for p in b.points) for b in sc.breakwater]
    entrance = sum(heads)
    assert 1.8 * L <= entrance <= 2.2 * L
    # channel narrowest where it meets the breakwaters: wider than 5 B
    channel = next(d for d in sc.depth_area if d.name == "approach channel")
    east = [p[1] for p in channel.points if p[0] == max(q[0] for q in channel.points)]
    assert max(east) - min(east) > 5.0 * B
    # the goal, a turning basin in front of the quay, is at least 2 L across
    g = np.array(sc.goal.points)
    assert np.ptp(g[:, 1]) >= 2.0 * L * 0.99 and sc.goal.heading_deg == 0.0


def test_episode_runs_with_ship_and_scenario_keywords():
    """gym.make(ID, ship=..., scenario=...): an episode of fixed helm runs to its end with every observation
    finite and inside the observation space."""
    env = gym.make(ID, ship="supply", scenario="supply_base")
    assert env.unwrapped.task.ship.name == "supply"
    obs, info = env.reset(seed=0)
    assert info["outcome"] == "running"
    action = np.array([0.0, 0.5], dtype=np.float32)
    for _ in range(2000):
        assert env.observation_space.contains(obs) and np.all(np.isfinite(obs))
        obs, reward, terminated, truncated, info = env.step(action)
        assert math.isfinite(reward)
        if terminated or truncated:
            break
    assert terminated or truncated
    assert info["outcome"] != "running"
    env.close()


def test_pilot_arrives_in_calm_weather():
    """The harbour is navigable at this scale: the HarbourPilot baseline, started on the leading line in calm
    weather, reaches the goal in front of the quay."""
    env = gym.make(ID, ship="supply", scenario="supply_base")
    pilot = HarbourPilot(env)
    pilot.reset()
    obs, _ = env.reset(
        seed=0,
        options={
            "north_m": -1300.0,
            "east_m": 0.0,
            "heading_deg": 0.0,
            "speed_m_s": 2.5,
            "environment": Environment(),
        },
    )
    while True:
        obs, _, terminated, truncated, info = env.step(pilot(obs))
        if terminated or truncated:
            break
    assert info["is_success"], info["outcome"]
    env.close()
