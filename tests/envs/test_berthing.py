"""Berthing-v0 (vessel_gym.envs.tasks.berthing): the berth from the scenario, the start, the orders reaching
the thrusters, the outcomes (success by the scripted pilot, touching too fast, fender overload, contact
elsewhere) and the metrics. docs/berthing.md."""

import math

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym  # noqa: F401  (registers the ids)
from vessel_gym.envs.tasks.berthing import BerthingTask
from vessel_gym.envs.tasks.berthing_pilot import BerthingPilot
from vessel_gym.physics.schema import SpecError
from vessel_gym.physics.units import DEG
from vessel_gym.scenarios.scenario import ScenarioError, load_scenario

ID = "vessel_gym/Berthing-v0"


def _env(**kw):
    return gym.make(ID, **kw)


def test_the_berth_comes_from_the_scenario_and_a_wrong_one_is_one_line():
    sc = load_scenario("supply_base")
    b = sc.find_berth(None)
    assert b.name == "supply quay 1" and b.side == "port" and b.heading_deg == pytest.approx(90.0)
    assert b.to_water() == pytest.approx((-1.0, 0.0))  # the quay face looks south into the basin
    with pytest.raises(ScenarioError, match="no \\[\\[berth\\]\\] 'nowhere' \\(berths: 'supply quay 1'\\)"):
        sc.find_berth("nowhere")
    with pytest.raises(SpecError, match="has no \\[\\[berth\\]\\]"):
        _env(scenario="harbour")


def test_start_lies_3_to_6_lengths_off_the_approach_point_in_clear_water():
    env = _env()
    task = env.unwrapped.task
    approach = task.berthed + task.config.approach_offset_L * task.L * task.to_water
    for seed in range(8):
        env.reset(seed=seed)
        sim = task.sim
        d = math.hypot(sim.north[0] - approach[0], sim.east[0] - approach[1]) / task.L
        assert 3.0 <= d <= 6.0
        assert task._clear(float(sim.north[0]), float(sim.east[0]), float(sim.heading[0]))
        bearing = math.atan2(approach[1] - sim.east[0], approach[0] - sim.north[0])
        noise = (sim.heading[0] - bearing + math.pi) % (2.0 * math.pi) - math.pi
        assert abs(noise) <= 15.0 * DEG + 1e-9  # heading for the approach point within the noise
    env.close()


def test_actions_order_the_rudder_engine_and_each_thruster():
    env = _env()
    assert env.action_space.shape == (4,)  # rudder, engine, bow thruster, stern thruster
    env.reset(seed=0)
    task = env.unwrapped.task
    env.step(np.array([0.0, 0.0, 1.0, -0.5], dtype=np.float32))
    bow, stern = task.assist
    assert (bow.name, stern.name) == ("bow_thruster", "stern_thruster")
    assert bow.orders(1)[0] == 1.0 and stern.orders(1)[0] == -0.5
    for _ in range(5):
        _obs, _r, _term, _trunc, info = env.step(np.array([0.0, 0.0, 1.0, -0.5], dtype=np.float32))
    assert info["assist_effort"] == pytest.approx((1.0 + 0.25) / 2.0)
    obs_assist = task.feat[0, -2:]  # the actual thrusts lag the orders (3 s) and follow them as o |o|
    assert 0.9 < obs_assist[0] <= 1.0 and -0.25 <= obs_assist[1] < -0.2
    env.close()


@pytest.mark.parametrize("seed", [0, 3])
def test_the_scripted_pilot_berths_within_the_pianc_limits(seed):
    env = _env()
    pilot = BerthingPilot(env)
    obs, _info = env.reset(seed=seed)
    pilot.reset()
    for _ in range(900):
        obs, _r, term, trunc, info = env.step(pilot(obs))
        if term or trunc:
            break
    assert info["outcome"] == "success"
    assert 0.0 < info["contact_speed_m_s"] < info["contact_speed_limit_m_s"]
    assert info["contact_speed_limit_m_s"] == pytest.approx(0.110, abs=0.001)  # PIANC (a) at 6000 t
    assert 0.0 < info["max_fender_energy_fraction"] < 1.0
    assert abs(info["heading_error_deg"]) <= 3.0 and abs(info["along_error_m"]) <= 5.0
    assert info["off_error_m"] <= 0.1 and info["held_s"] >= 30.0
    env.close()


def _drift_onto_the_berth(env, v0, seed=0):
    """Reset, then put the ship parallel 0.5 m off the fenders drifting onto them at ``v0``; step with the
    helm amidships and stopped until the episode ends."""
    env.reset(seed=seed)
    task = env.unwrapped.task
    sim = task.sim
    n0, e0 = task.berthed + 0.5 * task.to_water
    sim.set_environments(np.array([0]), wind_speed_m_s=0.0, current_speed_m_s=0.0)
    sim.reset(speed_m_s=0.0, heading_deg=task.berth.heading_deg, x_m=float(n0), y_m=float(e0), k=0)
    sim.state[0, 0:3] = 0.0
    sim.state[0, 1] = -v0  # port side to: sway to port is towards the quay
    for _ in range(300):
        _obs, _r, term, trunc, info = env.step(np.zeros(4, dtype=np.float32))
        if term or trunc:
            return info
    return info


def test_touching_faster_than_the_pianc_velocity_ends_the_episode():
    env = _env(weather=False)
    info = _drift_onto_the_berth(env, 0.3)
    assert info["outcome"] == "contact_speed" and not info["success"]
    # the first touch, before the fender acts: 0.3 m/s less what the hull's damping took over the last 0.5 m
    assert 0.27 < info["contact_speed_m_s"] < 0.3
    env.close()


def test_a_blow_beyond_the_fenders_rated_energy_is_an_overload():
    """At 0.55 m/s (under PIANC's 0.64 m/s of condition e) the ship brings 1/2 (m - Y_vdot) v^2 = 1.7 MJ, more
    than its five fenders' 5 x 188 kJ."""
    env = _env(weather=False, pianc_condition="e")
    info = _drift_onto_the_berth(env, 0.55)
    assert info["outcome"] == "fender_overload"
    assert info["max_fender_energy_fraction"] > 1.0
    assert max(info["fender_energy_kJ"]) > info["fender_rated_energy_kJ"] == pytest.approx(187.6, abs=0.1)
    env.close()


def test_the_hull_on_another_quay_is_contact():
    env = _env(weather=False)
    env.reset(seed=0)
    sim = env.unwrapped.task.sim
    # heading east with the bow into the east pier (north 250-290, east 440-620)
    sim.reset(speed_m_s=0.5, heading_deg=90.0, x_m=270.0, y_m=420.0, k=0)
    _obs, _r, term, _trunc, info = env.step(np.zeros(4, dtype=np.float32))
    assert term and info["outcome"] == "contact"
    env.close()


def test_vector_env_and_metrics():
    from agents.evaluation import evaluate

    out = evaluate(ID, "scripted", episodes=1, seed=5)
    ep = out["episodes"][0]
    for key in (
        "success",
        "outcome",
        "time_s",
        "contact_speed_m_s",
        "max_fender_energy_fraction",
        "assist_effort",
    ):
        assert key in ep
    assert ep["success"] and ep["time_s"] < 1800.0
    venv = gym.make_vec(ID, num_envs=2, vectorization_mode="vector_entry_point")
    venv.reset(seed=0)
    _o, _r, _t, _tr, info = venv.step(np.zeros((2, 4), dtype=np.float32))
    # a per-vessel row stays a row in the batch info, vessels first as in every vector info entry
    assert info["fender_energy_kJ"].shape == (2, 5) and info["outcome"].shape == (2,)
    venv.close()
    assert BerthingTask.declaration.max_episode_steps == 900


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('side = "port"', 'side = "starboard"', "water side of the face is on quay 'supply quay'"),
        (
            "fenders_m = [58.0, 69.0, 80.0, 91.0, 102.0]",
            "fenders_m = [58.0, 200.0]",
            "within the face's 160 m",
        ),
        ("fenders_m = [58.0, 69.0, 80.0, 91.0, 102.0]", "fenders_m = [58.0]", "at least 2 fenders"),
        (
            "quay_m = [[560.0, -330.0], [560.0, -170.0]]",
            "quay_m = [[560.0, -330.0]]",
            "expected [[north, east]",
        ),
        ("height_m = 0.8", "height_m = -0.8", "height_m"),
    ],
)
def test_a_bad_berth_is_a_one_line_error_naming_file_and_key(tmp_path, old, new, message):
    from vessel_gym.scenarios.scenario import SCENARIO_DIR

    text = (SCENARIO_DIR / "supply_base.toml").read_text()
    assert text.count(old) == 1
    path = tmp_path / "bad_berth.toml"
    path.write_text(text.replace(old, new))
    with pytest.raises(ScenarioError) as err:
        load_scenario(path)
    assert str(path) in str(err.value) and message in str(err.value) and "\n" not in str(err.value)


TANKER = "vessel_gym/BerthingTanker-v0"


def test_the_tankers_physics_step_resolves_the_stiffest_fender_contact():
    """The step against the contact's stiffness: every fender bottoming out (BOTTOM_SLOPE x R_R / H each) on
    the ship's dry mass alone (no added mass: the highest frequency) stays well inside RK4's stability bound
    on the imaginary axis (omega dt < 2 sqrt 2), so the contact cannot make the integration diverge."""
    from vessel_gym.physics.components.fenders import BOTTOM_SLOPE

    env = gym.make(TANKER)
    task = env.unwrapped.task
    assert task.config.method == "rk4"
    f = task.berth.fender
    k = len(task.berth.fenders_m) * BOTTOM_SLOPE * f.rated_reaction_kN * 1e3 / f.height_m  # N/m
    omega = math.sqrt(k / task.ship.mass_kg)  # rad/s
    assert task.dt == pytest.approx(1.0)
    assert omega * task.dt < 1.0 < 2.0 * math.sqrt(2.0)
    env.close()


def test_the_tankers_tugs_are_observed_by_the_force_along_their_lines():
    """A square-on tug's force is all sway: the observation reads it along the line (its first state, the
    surge component, stays 0), following the order with the tug's lag."""
    env = gym.make(TANKER)
    env.reset(seed=0)
    task = env.unwrapped.task
    order = np.array([0.0, 0.0, 1.0, -1.0], dtype=np.float32)  # rudder, engine, the two tugs
    for _ in range(30):  # 30 control steps
        env.step(order)
    tugs = task.feat[0, -2:]
    t_s = task.sim.t
    T = task.assist[0].params.time_constant_s
    assert tugs[0] == pytest.approx(1.0 - math.exp(-t_s / T), rel=0.05) and tugs[1] == pytest.approx(-tugs[0])
    env.close()


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
def test_the_scripted_pilot_berths_the_tanker_on_two_tugs(seed):
    """The VLCC stops off the berth and comes in sideways on its tugs: touching under PIANC's 0.031 m/s for
    312,600 t (condition a), no faster than 0.1 m/s sideways in the last beam off, in place and parallel."""
    env = gym.make(TANKER)
    task = env.unwrapped.task
    pilot = BerthingPilot(env)
    assert pilot.stop_first and pilot.V_lat <= 0.1
    obs, _info = env.reset(seed=seed)
    pilot.reset()
    lateral = []
    for _ in range(900):
        obs, _r, term, trunc, info = env.step(pilot(obs))
        if 0.0 < info["off_error_m"] < task.ship.particulars.B_m:
            lateral.append(-float(task.berth_frame.frame()[4][0]))
        if term or trunc:
            break
    assert info["outcome"] == "success"
    assert info["contact_speed_limit_m_s"] == pytest.approx(0.0314, abs=0.0005)
    assert 0.0 < info["contact_speed_m_s"] < info["contact_speed_limit_m_s"]
    assert 0.0 < info["max_fender_energy_fraction"] < 0.1
    assert max(lateral) <= 0.11
    assert abs(info["heading_error_deg"]) <= 3.0 and abs(info["along_error_m"]) <= 5.0
    env.close()


def test_wind_and_current_can_be_stronger_than_the_scenarios_with_its_directions():
    """wind_m_s / current_m_s replace the scenario's speed ranges (the stronger-weather sweep of the tanker,
    benchmarks/bench_berthing_weather.py); directions stay the scenario's draw; a negative speed is refused."""
    env = gym.make("vessel_gym/BerthingTanker-v0", wind_m_s=[14.0, 14.0], current_m_s=[0.3, 0.3])
    sim = env.unwrapped.task.sim
    froms = set()
    for seed in range(3):
        env.reset(seed=seed)
        e = sim.environments[0]
        assert e.wind_speed_m_s == pytest.approx(14.0) and e.current_speed_m_s == pytest.approx(0.3)
        froms.add(round(e.wind_from_deg))
    assert len(froms) == 3
    env.close()
    env = gym.make("vessel_gym/BerthingTanker-v0")
    env.reset(seed=0)
    assert env.unwrapped.task.sim.environments[0].wind_speed_m_s <= 6.0  # the scenario's range
    env.close()
    with pytest.raises(SpecError, match="wind_m_s"):
        gym.make("vessel_gym/BerthingTanker-v0", wind_m_s=[-1.0, 2.0])
