"""Many ships learning together: ``vessel_gym.parallel_env`` as a PettingZoo ParallelEnv with one reward,
termination and info per own ship, on the same task code as the Gymnasium environments."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pettingzoo")

from pettingzoo.test import parallel_api_test, parallel_seed_test  # noqa: E402

import vessel_gym  # noqa: E402

ID = "vessel_gym/CollisionAvoidance-v0"


def test_parallel_api_test_passes():
    parallel_api_test(vessel_gym.parallel_env(ID, agents=3), num_cycles=400)


def test_parallel_seed_test_passes():
    parallel_seed_test(lambda: vessel_gym.parallel_env(ID, agents=2), num_cycles=100)


def test_any_task_runs_as_independent_ships():
    parallel_api_test(vessel_gym.parallel_env("vessel_gym/ZigZag-v1", agents=2), num_cycles=50)


def test_own_ships_share_one_encounter_and_see_each_other():
    """Two own ships in Imazu case 1 meet head-on: each sees the other dead ahead, classified head-on; both
    steering straight, they collide and both episodes end as a collision, each with its own reward."""
    env = vessel_gym.parallel_env(ID, agents=2, observation_type="physical")
    lay = env.task.layout
    obs, infos = env.reset(seed=0, options={"scenario": "imazu:1", "heading_deg": 0.0})
    assert env.task.sim.n == 2 + 3  # two own ships and the encounter's target slots, one batch
    for a in env.possible_agents:
        assert lay.value(obs[a], "t0_head_on") == 1.0 and lay.value(obs[a], "t0_bearing_cos") > 0.99
        assert lay.value(obs[a], "t1_valid") == 0.0  # case 1 has one target: the other own ship
        assert infos[a]["scenario"] == "imazu:1"
    assert env.state().shape == env.state_space.shape == (2 * len(lay),)
    straight = {a: np.zeros(1, dtype=np.float32) for a in env.agents}
    steps = 0
    while env.agents:
        obs, rewards, terms, truncs, infos = env.step({a: straight[a] for a in env.agents})
        steps += 1
        assert set(rewards) == set(terms) == set(infos) and all(
            isinstance(r, float) for r in rewards.values()
        )
    assert all(terms.values()) and all(i["collision"] for i in infos.values())
    assert steps < 150


def test_rewards_are_per_ship_not_aggregated():
    """One ship turns hard to port, the other holds course: their rewards differ at the first step."""
    env = vessel_gym.parallel_env(ID, agents=2)
    env.reset(seed=1, options={"scenario": "imazu:1"})
    _o, rewards, _t, _tr, infos = env.step({"ship_0": np.array([-1.0]), "ship_1": np.array([0.0])})
    assert rewards["ship_0"] != rewards["ship_1"]
    assert infos["ship_0"]["reward_terms"]["rudder"] < 0.0 == infos["ship_1"]["reward_terms"]["rudder"]


def test_velocity_obstacle_pilots_on_every_ship_pass_each_other():
    """Every own ship steered by its own velocity-obstacle pilot (the same policy on each agent's
    observation): in Imazu case 13 (three ships and a scripted one) all arrive without contact."""
    import gymnasium as gym

    from vessel_gym.envs.tasks.colreg import vo_pilot

    env = vessel_gym.parallel_env(ID, agents=3)
    pilots = {a: vo_pilot(gym.make(ID)) for a in env.possible_agents}
    obs, _ = env.reset(seed=4, options={"scenario": "imazu:13"})
    while env.agents:
        obs, _r, _t, _tr, infos = env.step({a: pilots[a](obs[a]) for a in env.agents})
        for a, info in infos.items():
            assert not info["collision"], a
    assert all(i["success"] for i in infos.values())


def test_one_shared_policy_trains_with_sb3_on_every_ship():
    """SB3's PPO learns on the ships of one parallel environment through SharedPolicyVectorEnv and the
    project's VecEnv adapter: every ship's steps are in its rollout, episodes end with their final infos."""
    pytest.importorskip("stable_baselines3")
    from stable_baselines3 import PPO

    from vessel_gym.multiagent import SharedPolicyVectorEnv
    from vessel_gym.sb3 import VectorEnvAdapter

    venv = VectorEnvAdapter(SharedPolicyVectorEnv(vessel_gym.parallel_env(ID, agents=2)))
    venv.seed(0)
    obs = venv.reset()
    assert obs.shape == (2, venv.observation_space.shape[0])
    ends = []
    for _ in range(120):
        obs, rewards, dones, infos = venv.step(np.zeros((2, 1), dtype=np.float32))
        ends += [i for d, i in zip(dones, infos) if d]
    assert ends and all("terminal_observation" in i and "collision" in i for i in ends)
    model = PPO("MlpPolicy", venv, n_steps=32, batch_size=32, n_epochs=1, seed=0, device="cpu")
    model.learn(64)
    assert model.num_timesteps == 64


# --- a mix: learning agents, policy-driven ships, rule-following scripted targets, AIS contacts ---------------

MIX = {"targets_react": True, "targets_observed": "ais", "ais_dropout": 0.2}


def _mixed(**kw):
    """Three own ships in one encounter: ship_0 and ship_1 agents, ship_2 steered by its velocity-obstacle
    pilot; the encounter's other targets scripted keeping the rules; every ship seen over AIS."""
    import gymnasium as gym

    from vessel_gym.envs.tasks.colreg_pilots import VelocityObstaclePilot

    pilot = VelocityObstaclePilot(gym.make(ID, **MIX, **kw))
    return vessel_gym.parallel_env(ID, agents=3, driven={"ship_2": pilot}, **MIX, **kw)


def test_a_mix_of_agents_driven_ships_and_scripted_targets_passes_the_api_and_seed_tests():
    parallel_api_test(_mixed(), num_cycles=400)
    parallel_seed_test(_mixed, num_cycles=100)


def test_in_the_mix_the_driven_ship_acts_on_its_own_and_only_agents_are_reported():
    """Imazu case 13 (three targets): ship_2 (the first case target's role after ship_1) is steered by its pilot
    and is no agent; the third target is scripted and keeps the rules; the agents see everything over AIS."""
    env = _mixed(observation_type="physical")
    assert env.possible_agents == ["ship_0", "ship_1"]
    obs, infos = env.reset(seed=2, options={"scenario": "imazu:13"})
    assert set(obs) == set(infos) == {"ship_0", "ship_1"}
    task = env.task
    assert task.sim.n == 3 + 3 and task.world.active[:3].all() and task.world.active[3]  # + 1 scripted
    lay = task.layout
    assert all(sum(lay.value(obs[a], f"t{j}_valid") for j in range(3)) == 3.0 for a in obs)  # 3 others each
    turned = False
    for _ in range(150):
        obs, rewards, terms, truncs, infos = env.step({a: np.zeros(1, dtype=np.float32) for a in env.agents})
        assert set(rewards) <= {"ship_0", "ship_1"}
        turned = turned or abs(float(task.sim.rudder_order[2])) > 0.01  # its pilot's orders, not ours
        if not env.agents:
            break
    assert turned and all(float(task.sim.rudder_order[k]) == 0.0 for k in (0, 1) if task.world.active[k])
    with pytest.raises(ValueError, match="no own ship ship_7"):
        vessel_gym.parallel_env(ID, agents=2, driven={"ship_7": None})
    with pytest.raises(ValueError, match="at least one must be an agent"):
        vessel_gym.parallel_env(ID, agents=1, driven={"ship_0": None})


def test_one_shared_policy_trains_beside_a_driven_ship():
    pytest.importorskip("stable_baselines3")
    from vessel_gym.multiagent import SharedPolicyVectorEnv

    venv = SharedPolicyVectorEnv(_mixed())
    obs, _ = venv.reset(seed=0)
    assert venv.num_envs == 2 and obs.shape == (2, venv.single_observation_space.shape[0])
    for _ in range(5):
        obs, r, te, tr, _info = venv.step(np.zeros((2, 1), dtype=np.float32))
    assert r.shape == (2,)
