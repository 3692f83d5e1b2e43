"""An environment's ``info`` is a plain dict built at its step from the task's state, weighted reward terms and
features: equal to the entries the task declares (``vessel_info`` / ``batch_info`` of the task), holding its step's values however late it is read
(no entry is a view of an array the next step changes), and usable by every wrapper."""

from __future__ import annotations

import copy
import json

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.envs.task import batch_info, vessel_info

from .helpers import ENV_IDS


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_info_is_a_plain_dict_that_keeps_its_steps_values(env_id):
    """Infos kept and read after later steps (and a reset) equal deep copies taken at their own step."""
    env = gym.make(env_id)
    env.action_space.seed(1)
    _o, first = env.reset(seed=1)
    kept, at_step = [first], [copy.deepcopy(first)]
    assert first == vessel_info(env.unwrapped.task, 0)
    for _ in range(30):
        _o, _r, _te, _tr, info = env.step(env.action_space.sample())
        assert type(info) is dict and info == vessel_info(env.unwrapped.task, 0)
        kept.append(info)
        at_step.append(copy.deepcopy(info))
    env.reset(seed=2)
    for late, then in zip(kept, at_step):
        assert list(late) == list(then)
        for key in then:
            assert type(late[key]) is type(then[key]), key
        assert late == then
    env.close()


def _assert_same_batch_info(got_info: dict, want_info: dict) -> None:
    assert list(got_info.keys()) == list(want_info.keys())
    for key, want in want_info.items():
        got = got_info[key]
        assert type(got) is type(want), key
        if isinstance(want, dict):
            assert list(got) == list(want), key
            for t in want:
                assert got[t].dtype == want[t].dtype and got[t].tobytes() == want[t].tobytes(), (key, t)
        elif isinstance(want, np.ndarray) and want.dtype != object:
            assert got.dtype == want.dtype and got.shape == want.shape, key
            np.testing.assert_array_equal(got, want, err_msg=key)


@pytest.mark.parametrize("env_id", ENV_IDS)
@pytest.mark.parametrize("autoreset", ["NextStep", "SameStep"])
def test_vector_info_keeps_its_steps_values(env_id, autoreset):
    """The vector environment's batched info equals ``batch_info(task)`` at its step and, kept over steps with
    autoresets and read late, deep copies taken at its step."""
    venv = gym.make_vec(
        env_id,
        num_envs=3,
        vectorization_mode="vector_entry_point",
        max_episode_steps=4,
        autoreset_mode=autoreset,
    )
    venv.action_space.seed(1)
    _o, first = venv.reset(seed=1)
    task = venv.unwrapped.task
    _assert_same_batch_info(first, batch_info(task))
    kept, at_step = [first], [copy.deepcopy(first)]
    ended = 0
    for _ in range(12):
        _o, _r, _te, _tr, info = venv.step(venv.action_space.sample())
        assert type(info) is dict
        if "final_obs" in info:  # same-step autoreset: the final step's info, the task already reset
            ended += 1
        else:
            _assert_same_batch_info(info, batch_info(task))
        kept.append(info)
        at_step.append(copy.deepcopy(info))
    assert (ended > 0) == (autoreset == "SameStep")  # episodes ended (max_episode_steps)
    venv.reset(seed=2)
    for late, then in zip(kept, at_step):
        _assert_same_batch_info(late, then)
    venv.close()


def test_wrappers_that_add_to_or_copy_infos():
    from stable_baselines3.common.monitor import Monitor
    from stable_baselines3.common.vec_env import DummyVecEnv

    env = gym.wrappers.RecordEpisodeStatistics(
        gym.make("vessel_gym/TurningCircle-v0", mode="reverse", max_episode_steps=5)
    )
    env.reset(seed=0)
    for _ in range(5):
        _o, _r, te, tr, info = env.step(np.array([1.0], dtype=np.float32))
    assert (te or tr) and "episode" in info and "is_success" in info
    assert list(info)[-1] == "episode"

    def make():
        return Monitor(
            gym.make("vessel_gym/HarbourApproach-v2", max_episode_steps=3), info_keywords=("is_success",)
        )

    venv = DummyVecEnv([make])
    venv.seed(0)
    venv.reset()
    for _ in range(3):
        _o, _r, dones, infos = venv.step(np.zeros((1, 2), dtype=np.float32))
    assert dones[0] and type(infos[0]) is dict
    assert infos[0]["episode"]["is_success"] is False and infos[0]["TimeLimit.truncated"] is True
    json.dumps({k: v for k, v in infos[0].items() if k != "terminal_observation"})
    venv.close()


def test_gymnasiums_sync_vector_env_batches_the_infos():
    sync = gym.make_vec("vessel_gym/ZigZag-v1", num_envs=2, vectorization_mode="sync")
    native = gym.make_vec("vessel_gym/ZigZag-v1", num_envs=2, vectorization_mode="vector_entry_point")
    _o, a = sync.reset(seed=3)
    _o, b = native.reset(seed=3)
    acts = np.array([[0.5], [-0.5]], dtype=np.float32)
    for _ in range(3):
        *_x, a = sync.step(acts)
        *_y, b = native.step(acts)
    for key in ("time_s", "heading_error_deg", "course_changes", "is_success"):
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)
    np.testing.assert_array_equal(a["reward_terms"]["heading_error"], b["reward_terms"]["heading_error"])
    sync.close()
    native.close()


def test_declared_entries_follow_the_config():
    """TurningCircle declares its commanded rate for the rate mode (0 otherwise), its commanded radius for the
    radius mode and is_success (the same as success) for the reverse mode only: single and vector alike."""
    for mode, rate, radius in (("rate", True, False), ("radius", False, True), ("reverse", False, False)):
        env = gym.make("vessel_gym/TurningCircle-v0", mode=mode)
        _o, info = env.reset(seed=0)
        _o, _r, _te, _tr, info = env.step(np.array([0.5], dtype=np.float32))
        assert (info["commanded_rate_deg_s"] != 0.0) == rate and (info["commanded_radius_m"] != 0.0) == radius
        assert type(info["commanded_rate_deg_s"]) is float and type(info["success"]) is bool
        assert ("is_success" in info) == (mode == "reverse")
        venv = gym.make_vec(
            "vessel_gym/TurningCircle-v0", num_envs=2, vectorization_mode="vector_entry_point", mode=mode
        )
        _o, binfo = venv.reset(seed=0)
        assert binfo["commanded_rate_deg_s"].dtype == np.float64 and binfo["commanded_rate_deg_s"].shape == (2,)
        assert (binfo["commanded_radius_m"] != 0.0).all() == radius
        assert ("is_success" in binfo) == (mode == "reverse")
        if mode == "reverse":
            assert binfo["is_success"] is not binfo["success"]  # a copy: the two arrays share nothing
        venv.close()
        env.close()


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_batch_info_from_the_columns_read_equals_the_whole_copy(env_id, monkeypatch):
    """The vector env copies only the columns its entries read where that saves (many ships) and the whole
    transposed array otherwise: both give the same info, bit for bit."""
    import vessel_gym.envs.task as T

    venv = gym.make_vec(env_id, num_envs=3, vectorization_mode="vector_entry_point")
    venv.action_space.seed(0)
    venv.reset(seed=0)
    for _ in range(5):
        venv.step(venv.action_space.sample())
    task = venv.unwrapped.task
    infos, copies = [], []
    for saves in (0, 10**9):  # 0: the columns read, always; 10**9: the whole copy, always
        monkeypatch.setattr(T, "COPY_SAVES", saves)
        task._infos = None
        infos.append(batch_info(task))
        plan = T.info_plan(task)
        copies.append([cols is None for name, _a, cols in plan.columns])
        # an array whose every column an entry reads (whole_rows) is copied whole
        whole = [len(plan.read[name]) == a.shape[1] for name, a, _c in plan.columns]
    assert copies[0] == whole and all(copies[1])  # (no such array where the kernel writes the entries)
    _assert_same_batch_info(infos[0], infos[1])
    for key, want in infos[1].items():
        if isinstance(want, np.ndarray) and want.dtype != object:
            assert infos[0][key].tobytes() == want.tobytes(), key
    venv.close()
