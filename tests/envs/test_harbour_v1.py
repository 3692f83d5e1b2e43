"""HarbourApproach-v1: time scale defaults, time limit in seconds, difficulty levels and the curriculum hook,
disturbances drawn from the scenario with wind force, scenarios and procedural layouts, and a reward under
which the harbour pilot out-scores loitering helms."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.envs.policies import HarbourPilot
from vessel_gym.envs.tasks.harbour import DIFFICULTIES
from vessel_gym.envs.tasks.harbour_env import HarbourApproachEnv
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.schema import SpecError
from vessel_gym.scenarios import builtin_scenarios, load_scenario
from vessel_gym.scenarios.geometry import point_in_polygon

ID = "vessel_gym/HarbourApproach-v1"


def test_defaults_from_the_ship_time_scale():
    """kvlcc2_l7: L / U_T = 7 m / 1.179 m/s = 5.94 s; control interval L / U_T / 6 = 0.99 s (2 digits), time
    limit 100 L / U_T = 590 s (2 digits) = 596 steps."""
    env = gym.make(ID)
    u = env.unwrapped
    assert u.config.control_interval_s == pytest.approx(0.99)
    assert u.config.time_limit_s == pytest.approx(590.0)
    assert u.task.max_steps == math.ceil(590.0 / 0.99)
    assert env.spec.max_episode_steps is None  # the environment truncates by time, not a step wrapper
    full = gym.make(ID, ship="kvlcc2")  # full scale: 320 m / 7.97 m/s = 40.1 s -> 6.7 s
    assert full.unwrapped.config.control_interval_s == pytest.approx(6.7)


def test_truncation_after_the_time_limit_in_seconds():
    env = gym.make(ID, time_limit_s=5.0, control_interval_s=1.0)
    env.reset(seed=0)
    flags = [env.step(np.zeros(2, dtype=np.float32))[3] for _ in range(5)]
    assert flags == [False] * 4 + [True]
    venv = gym.make_vec(ID, num_envs=2, time_limit_s=5.0, control_interval_s=1.0)
    venv.reset(seed=0)
    tr = [venv.step(np.zeros((2, 2), dtype=np.float32))[3] for _ in range(5)]
    assert not np.any(tr[:4]) and np.all(tr[4])


def _start_distance(env, seed: int) -> float:
    return env.reset(seed=seed)[1]["distance_to_goal_m"]


def test_raised_difficulty_changes_the_start_region_on_the_next_reset():
    env = gym.make(ID, difficulty=0)
    sc = env.unwrapped.task.scenario
    near = [_start_distance(env, s) for s in range(5)]
    env.unwrapped.set_difficulty(3)  # what a curriculum callback does
    assert env.unwrapped.difficulty == 3
    far = [_start_distance(env, s) for s in range(5)]
    assert max(near) < min(far)
    start = [(p[0], p[1]) for p in sc.start.points]
    for s in range(3):
        env.reset(seed=s)
        assert point_in_polygon((float(env.unwrapped.sim.north[0]), float(env.unwrapped.sim.east[0])), start)
    # levels 0..2 start ever further out along the track; level 0 is inside the entrance (north > 0)
    means = []
    for k in range(3):
        env.unwrapped.set_difficulty(DIFFICULTIES[k])
        means.append(np.mean([_start_distance(env, s) for s in range(4)]))
        if k == 0:
            assert env.unwrapped.sim.north[0] > 1.5
    assert means[0] < means[1] < means[2] < min(far)
    with pytest.raises(ValueError, match="difficulty"):
        env.unwrapped.set_difficulty(4)


def test_vector_env_curriculum_hook_through_call():
    venv = gym.make_vec(ID, num_envs=3, difficulty=0)
    d0 = venv.reset(seed=0)[1]["distance_to_goal_m"]
    assert venv.call("set_difficulty", 2) == (None, None, None)
    assert venv.call("difficulty") == (2, 2, 2)
    d2 = venv.reset(seed=0)[1]["distance_to_goal_m"]
    assert np.all(d2 > d0 + 20.0)


def test_difficulty_key_is_checked():
    with pytest.raises(SpecError, match="difficulty"):
        gym.make(ID, difficulty=5)


def test_disturbances_drawn_from_the_scenario_by_the_reset_seed():
    env = gym.make(ID)
    w = env.unwrapped.task.scenario.weather
    draws = []
    for seed in (0, 1, 0):
        env.reset(seed=seed)
        e = env.unwrapped.sim.environments[0]
        assert w.wind_speed_m_s[0] <= e.wind_speed_m_s <= w.wind_speed_m_s[1]
        assert w.current_speed_m_s[0] <= e.current_speed_m_s <= w.current_speed_m_s[1]
        draws.append((e.wind_speed_m_s, e.wind_from_deg, e.current_speed_m_s, e.current_to_deg))
    assert draws[0] == draws[2] and draws[0] != draws[1]


def test_wind_exerts_force_on_the_harbour_ship():
    """A 1.5 m/s beam wind (10 m/s full scale, Froude-scaled) from starboard on the model with the helm
    amidships: leeway (sway through the water to port), and the bow turns up into the wind because the
    windage's lateral centre is aft of midship (s_L < 0: the stern is blown to leeward). In calm air
    neither happens."""
    start = {"north_m": -100.0, "east_m": 0.0, "heading_deg": 0.0, "speed_m_s": 0.6}
    got = {}
    for name, wind in (("calm", 0.0), ("windy", 1.5)):
        env = gym.make(ID, engine_control=False, observation_type="physical")
        opts = dict(start, environment=Environment(wind_speed_m_s=wind, wind_from_deg=90.0))
        env.reset(seed=0, options=opts)
        for _ in range(30):
            obs = env.step(np.zeros(1, dtype=np.float32))[0]
        v = float(env.unwrapped.observation_layout.value(obs, "v"))
        got[name] = (v, math.degrees(float(env.unwrapped.sim.heading[0])))
    assert got["calm"] == (0.0, 0.0)
    v, heading = got["windy"]
    assert v < -0.005 and heading > 1.0


@pytest.mark.parametrize("name", ["harbour", "harbour_east", "harbour_channel"])
def test_builtin_scenarios_run(name):
    assert name in builtin_scenarios()
    env = gym.make(ID, scenario=name)
    obs, info = env.reset(seed=3)
    assert env.observation_space.contains(obs) and info["outcome"] == "running"
    sc = load_scenario(name)
    assert env.unwrapped.task.scenario == sc


def test_procedural_layouts_train_and_eval_differ():
    tr = gym.make(ID, layout="procedural", layout_split="train", layout_index=1).unwrapped.task.scenario
    ev = gym.make(ID, layout="procedural", layout_split="eval", layout_index=1).unwrapped.task.scenario
    assert tr.name == "procedural-1" and ev.name == "procedural-1000001"
    assert tr.breakwater != ev.breakwater


def _episode_return(env, seed: int, helm) -> tuple[float, bool]:
    obs, _ = env.reset(seed=seed)
    total = 0.0
    while True:
        obs, r, te, tr, info = env.step(helm(obs))
        total += r
        if te or tr:
            return total, bool(info["is_success"])


@pytest.mark.slow
def test_pilot_outscores_loitering_at_the_default_difficulty():
    """Arrival is worth more than loitering: over 3 seeds at the default difficulty the harbour pilot arrives
    every time and its every return beats every return of full astern, circling and a stopped engine."""
    env = gym.make(ID)
    assert isinstance(env.unwrapped, HarbourApproachEnv) and env.unwrapped.difficulty == 3
    pilot = HarbourPilot(env)

    def pilot_helm(obs):
        return pilot(obs)

    loiter = {
        "astern": np.array([0.0, -1.0], np.float32),
        "circling": np.array([1.0, 0.3], np.float32),
        "stopped": np.array([0.0, 0.0], np.float32),
    }
    seeds = (0, 1, 2)
    got = []
    for s in seeds:
        pilot.reset()
        got.append(_episode_return(env, s, pilot_helm))
    assert all(ok for _r, ok in got)
    worst_pilot = min(r for r, _ok in got)
    for name, a in loiter.items():
        for s in seeds:
            r, ok = _episode_return(env, s, lambda _obs, a=a: a)
            assert not ok and r < worst_pilot, (name, s, r, worst_pilot)
