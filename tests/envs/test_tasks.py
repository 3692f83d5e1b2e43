"""Task semantics: IMO overshoot and turning figures against an independent reading of the same run,
contact / grounding / success in the harbour, reference policies."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401
from vessel_gym.envs.policies import HarbourPilot, PIDHeadingAutopilot, TurningRule, ZigZagRule


def _run(env, policy, steps, seed=0, options=None):
    obs, info = env.reset(seed=seed, options=options)
    u = env.unwrapped
    hist = [(float(u.sim.heading[0]), float(u.sim.r[0]), float(u.sim.north[0]), float(u.sim.east[0]))]
    infos = [info]
    for _ in range(steps):
        obs, _r, te, tr, info = env.step(policy(obs))
        hist.append((float(u.sim.heading[0]), float(u.sim.r[0]), float(u.sim.north[0]), float(u.sim.east[0])))
        infos.append(info)
        if te or tr:
            break
    return np.array(hist), infos


def test_zigzag_rule_overshoots_match_the_heading_history():
    """IMO MSC.137(76): overshoot = additional heading deviation past psi after the 2nd / 3rd execute.
    Read independently from the recorded heading: the extreme deviation between successive rate sign
    changes beyond +-psi."""
    env = gym.make("vessel_gym/ZigZag-v1", first_change_s=[0.0, 0.0], first_side="starboard")
    hist, infos = _run(env, ZigZagRule(env), 480)
    dev = np.degrees(hist[:, 0] - hist[0, 0])
    info = infos[-1]
    assert info["course_changes"] >= 4 and info["overshoot_2_deg"] > 0.0
    # swings: extremes of the deviation between sign changes of the rate of turn
    turn = np.sign(hist[:, 1])
    cuts = np.flatnonzero(np.diff(turn) != 0) + 1
    extremes = [dev[a:b][np.argmax(np.abs(dev[a:b]))] for a, b in zip(cuts[:-1], cuts[1:])]
    swings = [abs(x) - 10.0 for x in extremes if abs(x) > 10.0]
    assert info["overshoot_1_deg"] == pytest.approx(swings[0], abs=0.05)
    assert info["overshoot_2_deg"] == pytest.approx(swings[1], abs=0.05)
    assert 0.0 < info["overshoot_1_deg"] < info["overshoot_2_deg"]


def test_pid_autopilot_beats_the_zigzag_rule_on_reward():
    def total(policy_cls):
        env = gym.make("vessel_gym/ZigZag-v1")
        obs, _ = env.reset(seed=0)
        pol = policy_cls(env)
        s = 0.0
        for _ in range(480):
            obs, r, te, tr, _ = env.step(pol(obs))
            s += r
            if te or tr:
                break
        return s

    assert total(PIDHeadingAutopilot) > total(ZigZagRule) + 50.0


def test_turning_circle_figures_match_the_track():
    """Advance / transfer at 90 deg and tactical diameter at 180 deg heading change (MSC.137(76) 4.2),
    interpolated from the recorded track, and the IMO criteria (advance <= 4.5 L, TD <= 5 L)."""
    env = gym.make("vessel_gym/TurningCircle-v0", mode="reverse")
    hist, infos = _run(env, TurningRule(env, rudder_deg=35.0, side=1.0), 480)
    info = infos[-1]
    assert info["success"] and info["reached_180"]
    turned = np.abs(hist[:, 0] - hist[0, 0])
    adv = hist[:, 2] - hist[0, 2]  # original course north
    trf = hist[:, 3] - hist[0, 3]
    assert info["advance_m"] == pytest.approx(np.interp(math.pi / 2, turned, adv), rel=1e-9)
    assert info["transfer_m"] == pytest.approx(np.interp(math.pi / 2, turned, trf), rel=1e-9)
    assert info["tactical_diameter_m"] == pytest.approx(np.interp(math.pi, turned, trf), rel=1e-9)
    L = env.unwrapped.task.L
    assert 2.0 * L < info["advance_m"] <= 4.5 * L
    assert 2.0 * L < info["tactical_diameter_m"] <= 5.0 * L


def test_turning_rate_mode_tracks_with_a_constant_rudder_side():
    env = gym.make("vessel_gym/TurningCircle-v0", side="port")
    obs, info = env.reset(seed=0)
    assert info["commanded_rate_deg_s"] < 0.0
    pol = TurningRule(env, rudder_deg=15.0)
    for _ in range(200):
        obs, r, *_ = env.step(pol(obs))
    assert env.unwrapped.sim.r[0] < 0.0


def test_harbour_pilot_arrives():
    env = gym.make("vessel_gym/HarbourApproach-v2")
    for seed in (0, 1):
        obs, info = env.reset(seed=seed)
        pilot = HarbourPilot(env)
        for _ in range(1600):
            obs, r, te, tr, info = env.step(pilot(obs))
            if te or tr:
                break
        assert info["outcome"] == "success", (seed, info)
        assert info["reward_terms"]["success"] == env.unwrapped.config.reward.success
        assert info["min_clearance_m"] > 1.0


@pytest.mark.parametrize(
    "pose,outcome",
    [
        ({"north_m": -3.0, "east_m": -12.0, "heading_deg": 0.0}, "contact"),  # into the west breakwater
        ({"north_m": 38.0, "east_m": 42.0, "heading_deg": 90.0}, "grounding"),  # onto the east shoal
        ({"north_m": -136.0, "east_m": 0.0, "heading_deg": 180.0}, "out_of_bounds"),
    ],
)
def test_harbour_failures_terminate_with_flag(pose, outcome):
    env = gym.make("vessel_gym/HarbourApproach-v2")
    env.reset(seed=0, options={**pose, "speed_m_s": 1.0})
    for _ in range(200):
        _o, r, te, tr, info = env.step(np.array([0.0, 0.5], dtype=np.float32))
        if te:
            break
    assert te and info["outcome"] == outcome and info[outcome]
    key = "out_of_bounds" if outcome == "out_of_bounds" else "collision"
    assert info["reward_terms"][key] == -env.unwrapped.config.reward.__getattribute__(key)


def test_policies_accept_vector_observations():
    venv = gym.make_vec("vessel_gym/HarbourApproach-v2", num_envs=3, vectorization_mode="vector_entry_point")
    obs, _ = venv.reset(seed=0)
    pilot = HarbourPilot(venv)
    for _ in range(5):
        a = pilot(obs)
        assert a.shape == (3, 2)
        obs, *_ = venv.step(a)
    venv = gym.make_vec(
        "vessel_gym/ZigZag-v1", num_envs=2, vectorization_mode="vector_entry_point", action_type="discrete"
    )
    obs, _ = venv.reset(seed=0)
    a = ZigZagRule(venv)(obs)
    assert a.shape == (2,) and venv.action_space.contains(a)
