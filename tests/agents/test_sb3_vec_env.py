"""vessel_gym.sb3: the SB3 VecEnv over the native vector environments steps exactly as SB3's DummyVecEnv over
the single environments seeded the same way: observations, rewards, dones, terminal observations, time-limit
flags, info and episode statistics, through several automatic resets."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode
from stable_baselines3.common.vec_env import DummyVecEnv, VecMonitor

from vessel_gym.sb3 import VectorEnvAdapter, make_vec_env

# (env id, env kwargs with a short time limit to force resets, number of ships, steps, rudder bias per ship)
CASES = [
    ("vessel_gym/ZigZag-v1", {"schedule": "random", "max_episode_steps": 37}, 3, 200, 0.0),
    # ("mode": "reverse"): ships 0 and 2 turn hard over and reach 180 deg, ship 1 meanders into the time limit
    ("vessel_gym/TurningCircle-v0", {"mode": "reverse", "max_episode_steps": 300}, 3, 420, (0.9, 0.0, 0.9)),
    ("vessel_gym/HarbourApproach-v2", {"max_episode_steps": 40}, 2, 150, 0.0),
]


def _dummy(env_id: str, n: int, seed: int, kwargs: dict) -> VecMonitor:
    venv = DummyVecEnv([lambda: gym.make(env_id, **kwargs) for _ in range(n)])
    venv.seed(seed)
    return VecMonitor(venv)


def _actions(venv, steps: int, bias, seed: int = 7) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    shape = (venv.num_envs, *venv.action_space.shape)
    b = np.reshape(np.broadcast_to(bias, venv.num_envs), (-1, 1))
    return [np.clip(b + 0.6 * rng.standard_normal(shape), -1, 1).astype(np.float32) for _ in range(steps)]


def _rollout(venv, actions: list[np.ndarray]) -> list[tuple]:
    out = [(venv.reset(), None, None, None)]
    for a in actions:
        venv.step_async(a)
        out.append(venv.step_wait())
    venv.close()
    return out


def _same_info(a: dict, b: dict, where: str) -> None:
    assert set(a) == set(b), where
    for key in a:
        x, y = a[key], b[key]
        if key == "episode":
            assert (x["r"], x["l"]) == pytest.approx((y["r"], y["l"]), rel=1e-6), where
        elif isinstance(x, dict):
            _same_info(x, y, f"{where}[{key}]")
        elif isinstance(x, np.ndarray):
            np.testing.assert_array_equal(x, y, err_msg=f"{where}[{key}]")
        elif isinstance(x, float) or isinstance(y, float):
            assert type(x) is type(y), f"{where}[{key}]: {type(x)} != {type(y)}"
            assert x == pytest.approx(y, rel=1e-12, abs=1e-12), f"{where}[{key}]: {x} != {y}"
        else:
            assert x == y, f"{where}[{key}]: {x!r} != {y!r}"


def _compare(ref: list[tuple], got: list[tuple]) -> tuple[int, int]:
    np.testing.assert_array_equal(got[0][0], ref[0][0])
    terminations = truncations = 0
    for t, ((o1, r1, d1, i1), (o2, r2, d2, i2)) in enumerate(zip(ref[1:], got[1:]), start=1):
        np.testing.assert_array_equal(o2, o1, err_msg=f"obs, step {t}")
        assert o2.dtype == o1.dtype and r2.dtype == r1.dtype == np.float32
        np.testing.assert_array_equal(r2, r1, err_msg=f"rewards, step {t}")
        np.testing.assert_array_equal(d2, d1, err_msg=f"dones, step {t}")
        for k, (a, b) in enumerate(zip(i1, i2)):
            _same_info(a, b, f"step {t} env {k}")
            if d1[k]:
                terminations += not a["TimeLimit.truncated"]
                truncations += a["TimeLimit.truncated"]
    return terminations, truncations


@pytest.mark.parametrize(("env_id", "kwargs", "n", "steps", "bias"), CASES, ids=lambda c: str(c)[:24])
def test_adapter_steps_exactly_as_dummy_vec_env(env_id, kwargs, n, steps, bias) -> None:
    seed = 11
    ref_env = _dummy(env_id, n, seed, kwargs)
    actions = _actions(ref_env, steps, bias)
    ref = _rollout(ref_env, actions)
    got = _rollout(make_vec_env(env_id, n, seed=seed, **kwargs), actions)
    terminations, truncations = _compare(ref, got)
    assert terminations + truncations >= n and truncations >= 1  # several automatic resets were compared
    if "TurningCircle" in env_id:
        assert terminations >= 2


def test_disabled_autoreset_and_gymnasium_sync_vector_env_translate_alike() -> None:
    """The adapter also takes a vector environment with autoreset disabled (it resets the finished ships
    itself) and Gymnasium's SyncVectorEnv in same-step mode (batched final_info)."""
    env_id, kwargs, n, steps = "vessel_gym/ZigZag-v1", {"schedule": "random", "max_episode_steps": 23}, 2, 60
    ref_env = _dummy(env_id, n, 3, kwargs)
    actions = _actions(ref_env, steps, 0.0)
    ref = _rollout(ref_env, actions)
    disabled = gym.make_vec(
        env_id, n, vectorization_mode="vector_entry_point", autoreset_mode=AutoresetMode.DISABLED, **kwargs
    )
    sync = gym.make_vec(
        env_id,
        n,
        vectorization_mode="sync",
        vector_kwargs={"autoreset_mode": AutoresetMode.SAME_STEP},
        **kwargs,
    )
    for venv in (disabled, sync):
        adapter = VectorEnvAdapter(venv)
        adapter.seed(3)
        assert _compare(ref, _rollout(VecMonitor(adapter), actions))[1] >= n


def test_next_step_autoreset_is_refused() -> None:
    venv = gym.make_vec("vessel_gym/ZigZag-v1", 2, vectorization_mode="vector_entry_point")
    with pytest.raises(ValueError, match="same-step or disabled autoreset"):
        VectorEnvAdapter(venv)
    venv.close()


def test_is_success_reaches_sb3_and_render_tiles() -> None:
    venv = make_vec_env(
        "vessel_gym/HarbourApproach-v2", 2, seed=0, max_episode_steps=3, render_mode="rgb_array"
    )
    venv.reset()
    for _ in range(3):
        _obs, _r, dones, infos = venv.step(np.zeros((2, 2), dtype=np.float32))
    assert dones.all() and all(i["is_success"] is False and "episode" in i for i in infos)
    assert venv.get_attr("render_mode") == ["rgb_array", "rgb_array"]
    frame = venv.render(mode="rgb_array")
    assert frame.ndim == 3 and frame.shape[2] == 3
    venv.close()


def test_training_wrapper_twin_matches_the_single_env_wrapper() -> None:
    """agents.common.make_vec_env: RudderEffortPenalty on single environments (dummy) and its vector twin on
    the native vector environment give the same rewards, reward terms and episode returns."""
    from agents import common

    kwargs = {"schedule": "random", "max_episode_steps": 29}
    wrapper = [{"RudderEffortPenalty": {"weight": 0.3}}]
    ref_env = common.make_vec_env("vessel_gym/ZigZag-v1", 3, 4, "dummy", kwargs, env_wrapper=wrapper)
    actions = _actions(ref_env, 70, 0.0)
    ref = _rollout(ref_env, actions)
    got = _rollout(
        common.make_vec_env("vessel_gym/ZigZag-v1", 3, 4, "native", kwargs, env_wrapper=wrapper), actions
    )
    assert _compare(ref, got)[1] >= 3
    assert "rudder_effort" in got[-1][3][0]["reward_terms"]


def test_a_wrapper_without_vector_twin_is_refused_on_native() -> None:
    from agents import common

    with pytest.raises(common.UsageError, match="wraps single environments only; train with --vec dummy"):
        common.make_vec_env(
            "vessel_gym/ZigZag-v1", 2, 0, "native", env_wrapper=["gymnasium.wrappers.RecordEpisodeStatistics"]
        )


def test_the_package_does_not_import_sb3() -> None:
    """Only vessel_gym.sb3 needs stable-baselines3: making and stepping environments never imports it."""
    import subprocess
    import sys

    code = (
        "import sys, gymnasium as gym, vessel_gym\n"
        "env = gym.make_vec('vessel_gym/ZigZag-v1', 2, vectorization_mode='vector_entry_point')\n"
        "env.reset(seed=0)\n"
        "assert 'stable_baselines3' not in sys.modules and 'torch' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=300)
