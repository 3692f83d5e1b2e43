"""Wind, current and waves for ZigZag-v1, ZigZagRandom-v1 and TurningCircle-v0: drawn per episode from the
configured ranges by the reset seed, set as the vessel's Environment in the simulation (no copy in the task),
refused on a ship that could not feel them."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.physics.environment import CALM
from vessel_gym.physics.schema import SpecError

IDS = ["vessel_gym/ZigZag-v1", "vessel_gym/ZigZagRandom-v1", "vessel_gym/TurningCircle-v0"]


@pytest.mark.parametrize("env_id", IDS)
@pytest.mark.parametrize(("key", "table"), [("wind_speed_m_s", "windage"), ("Hs_m", "wave_drift")])
def test_wind_or_waves_on_a_ship_without_the_table_raise(env_id, key, table):
    """kvlcc2_l7 (the tank model) has no windage and no wave-drift table: a clear error, not a silent calm."""
    with pytest.raises(SpecError, match=rf"{key}: ship 'kvlcc2_l7' has no \[{table}\] table"):
        gym.make(env_id, **{key: [1.0, 2.0]})


@pytest.mark.parametrize("env_id", IDS)
def test_bad_range_and_unknown_keys_raise(env_id):
    with pytest.raises(SpecError, match=r"current_speed_m_s: expected \[min, max\]"):
        gym.make(env_id, current_speed_m_s=[0.5, 0.1])
    with pytest.raises(SpecError, match="wind_speed_m_s"):
        gym.make(env_id, ship="mariner", wind_speed_m_s=[5.0, 80.0])  # above the 60 m/s bound


@pytest.mark.parametrize("env_id", IDS)
def test_draws_per_episode_set_in_the_simulation(env_id):
    """Each reset draws from the ranges with the reset seed; directions relative to the original course."""
    kw = {
        "ship": "mariner",
        "initial_heading_deg": [30.0, 30.0],
        "wind_speed_m_s": [8.0, 12.0],
        "wind_from_rel_deg": [90.0, 90.0],
        "current_speed_m_s": [0.5, 0.5],
        "current_to_rel_deg": [-45.0, -45.0],
        "Hs_m": [1.0, 2.0],
        "Tp_s": [7.0, 9.0],
        "wave_from_rel_deg": [350.0, 350.0],
    }
    env = gym.make(env_id, **kw)
    sim = env.unwrapped.sim
    seen = []
    for seed in (0, 1, 0):
        env.reset(seed=seed)
        e = sim.environments[0]
        assert 8.0 <= e.wind_speed_m_s <= 12.0 and e.wind_from_deg == pytest.approx(120.0)
        assert e.current_speed_m_s == 0.5 and e.current_to_deg == pytest.approx(345.0)
        assert 1.0 <= e.Hs_m <= 2.0 and 7.0 <= e.Tp_s <= 9.0 and e.wave_from_deg == pytest.approx(20.0)
        seen.append((e.wind_speed_m_s, e.Hs_m, e.Tp_s))
        # the simulation's environment row is this environment's
        np.testing.assert_array_equal(
            sim.env[0], e.row(sim.ship(0).particulars.L_m, sim.ship(0).particulars.T_m)
        )
    assert seen[0] == seen[2] and seen[0] != seen[1]
    # the vector environment's vessel k has the single environment's draw for seed + k
    venv = gym.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point", **kw)
    venv.reset(seed=0)
    env.reset(seed=1)
    assert venv.unwrapped.sim.environments[1] == sim.environments[0]
    venv.close()


@pytest.mark.parametrize("env_id", IDS)
def test_calm_defaults_leave_the_water_calm(env_id):
    env = gym.make(env_id)
    env.reset(seed=3)
    assert env.unwrapped.sim.environments[0] is CALM


def test_a_uniform_current_carries_the_ship_and_nothing_else():
    """A uniform current changes nothing in the motion through the water and adds V_c t to the track over
    the ground (the relative-velocity formulation, Fossen 2011 §10.3): a 0.1 m/s current setting to
    starboard of a ship on course 0 moves her 0.1 m/s x t east."""
    kw = {"initial_heading_deg": [0.0, 0.0], "first_change_s": [0.0, 0.0], "first_side": "starboard"}
    calm = gym.make("vessel_gym/ZigZag-v1", **kw)
    set_ = gym.make(
        "vessel_gym/ZigZag-v1", current_speed_m_s=[0.1, 0.1], current_to_rel_deg=[90.0, 90.0], **kw
    )
    calm.reset(seed=0)
    set_.reset(seed=0)
    rudder = np.array([0.5], dtype=np.float32)
    for _ in range(160):  # 40 s, turning
        oc = calm.step(rudder)[0]
        os_ = set_.step(rudder)[0]
    np.testing.assert_allclose(os_, oc, atol=1e-9)  # u, v, r, rudder, heading errors: through the water
    a, b = calm.unwrapped.sim, set_.unwrapped.sim
    assert b.east[0] - a.east[0] == pytest.approx(0.1 * 40.0, rel=1e-9)
    assert b.north[0] - a.north[0] == pytest.approx(0.0, abs=1e-9)


def test_beam_wind_sets_the_ship_to_leeward():
    """Wind on the windage: with the helm amidships a 20 m/s wind from starboard sets a mariner to port
    (leeway: sway velocity through the water to port, track to port of the calm-water one)."""
    kw = {"ship": "mariner", "initial_heading_deg": [0.0, 0.0], "first_change_s": [1e4, 1e4]}
    calm = gym.make("vessel_gym/ZigZag-v1", **kw)
    windy = gym.make(
        "vessel_gym/ZigZag-v1", wind_speed_m_s=[20.0, 20.0], wind_from_rel_deg=[90.0, 90.0], **kw
    )
    v = {}
    for name, env in (("calm", calm), ("windy", windy)):
        env.reset(seed=0)
        for _ in range(120):  # 30 s
            obs = env.step(np.zeros(1, np.float32))[0]
        v[name] = env.unwrapped.observation_layout.value(obs, "v")
    assert v["windy"] < v["calm"] - 0.02  # m/s, to port
    assert windy.unwrapped.sim.east[0] < calm.unwrapped.sim.east[0] - 2.0  # m
