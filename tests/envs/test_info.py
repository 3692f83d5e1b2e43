"""The one-ship environment's ``info`` is built when first read (envs/info.py): it must equal the dict built at
the step, keep its step's values however late it is read, and behave as a dict for every user and wrapper."""

from __future__ import annotations

import copy
import json
import pickle

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.envs.info import LazyInfo

from .helpers import ENV_IDS


def _built() -> dict:
    return {"a": 1.0, "b": {"x": 2.0}, "c": True}


def _lazy() -> LazyInfo:
    info = LazyInfo(dict.fromkeys(_built()))
    info._src = (dict, _built())
    return info


def test_lazy_info_reads_as_the_dict_it_builds():
    plain = _built()
    info = _lazy()
    assert isinstance(info, dict)
    assert info == plain and plain == info and not (info != plain)
    assert _lazy() == _lazy()
    assert list(info) == list(plain) and len(info) == 3 and "a" in info and "z" not in info
    assert info["b"] == {"x": 2.0} and info.get("z", 5) == 5
    assert list(_lazy().items()) == list(plain.items())
    assert list(_lazy().values()) == list(plain.values())
    assert list(reversed(_lazy())) == list(reversed(plain))
    assert dict(_lazy()) == plain and {**_lazy()} == plain
    assert (lambda **kw: kw)(**_lazy()) == plain
    assert repr(_lazy()) == repr(plain)
    assert _lazy() | {"d": 1} == plain | {"d": 1} and {"d": 1} | _lazy() == {"d": 1} | plain
    # the C encoder asks a dict for its size directly: the keys are there from the start
    assert json.dumps(_lazy()) == json.dumps(plain)
    assert json.dumps(_lazy(), indent=1) == json.dumps(plain, indent=1)


def test_lazy_info_writes_keep_the_built_order():
    info = _lazy()
    info["episode"] = {"r": 1.0}  # what RecordEpisodeStatistics and SB3's Monitor add at an episode's end
    assert list(info) == ["a", "b", "c", "episode"] and info["a"] == 1.0
    info = _lazy()
    info.update(c=False)
    assert info == {**_built(), "c": False}
    info = _lazy()
    del info["a"]
    assert list(info) == ["b", "c"]
    info = _lazy()
    assert info.pop("a") == 1.0 and info.setdefault("z", 3) == 3 and info.popitem() == ("z", 3)
    info = _lazy()
    info |= {"z": 0}
    assert list(info) == ["a", "b", "c", "z"]
    info = _lazy()
    info.clear()
    assert info == {} and len(info) == 0


def test_copies_and_pickles_of_lazy_info_are_plain_dicts():
    for twin in (
        copy.copy(_lazy()),
        copy.deepcopy(_lazy()),
        pickle.loads(pickle.dumps(_lazy())),
        _lazy().copy(),
    ):
        assert type(twin) is dict and twin == _built()
    deep = copy.deepcopy(_lazy())
    assert deep["b"] == {"x": 2.0}


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_info_read_late_holds_its_steps_values(env_id):
    """An info kept and read after later steps (and a reset) equals the dict built at its own step."""
    env = gym.make(env_id)
    env.action_space.seed(1)
    _o, first = env.reset(seed=1)
    eager = [env.unwrapped.task.info(0)]
    kept = [first]
    for _ in range(30):
        _o, _r, _te, _tr, info = env.step(env.action_space.sample())
        kept.append(info)
        eager.append(env.unwrapped.task.info(0))
    env.reset(seed=2)
    for lazy, built in zip(kept, eager):
        assert type(lazy) is LazyInfo
        assert list(lazy.keys()) == list(built.keys())
        for key in built:
            assert type(lazy[key]) is type(built[key]), key
        assert lazy == built
    env.close()


def _assert_same_batch_info(lazy: dict, built: dict) -> None:
    assert list(lazy.keys()) == list(built.keys())
    for key, want in built.items():
        got = lazy[key]
        assert type(got) is type(want), key
        if isinstance(want, dict):
            assert list(got) == list(want), key
            for t in want:
                assert got[t].dtype == want[t].dtype and got[t].tobytes() == want[t].tobytes(), (key, t)
        else:
            assert got.dtype == want.dtype and got.shape == want.shape, key
            np.testing.assert_array_equal(got, want, err_msg=key)


@pytest.mark.parametrize("env_id", ENV_IDS)
@pytest.mark.parametrize("autoreset", ["NextStep", "SameStep"])
def test_vector_info_read_late_holds_its_steps_values(env_id, autoreset):
    """The vector environment's batched info, built when first read (or before the next step changes what it
    is built from), equals ``batch_info()`` built at its own step: kept over steps with autoresets, read late."""
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
    eager = [task.batch_info()]
    kept = [first]
    for i in range(12):
        _o, _r, _te, _tr, info = venv.step(venv.action_space.sample())
        if i % 5 == 0:  # read at once sometimes: a built info must not be built again
            assert "time_s" in info
        eager.append(task.batch_info() if "final_obs" not in info else None)
        kept.append(info)
    assert (eager.count(None) > 0) == (autoreset == "SameStep")  # episodes ended (max_episode_steps)
    venv.reset(seed=2)
    for lazy, built in zip(kept, eager):
        if built is None:  # same-step autoreset: the info holds the final step's, read at once by the env
            continue
        _assert_same_batch_info(lazy, built)
    dropped = venv.step(venv.action_space.sample())[-1]
    del dropped  # dropped unread: nothing to build at the next step
    _o, _r, _te, _tr, info = venv.step(venv.action_space.sample())
    want = task.batch_info()
    assert pickle.loads(pickle.dumps(info)).keys() == want.keys()
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


def test_gymnasiums_sync_vector_env_batches_lazy_infos():
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
