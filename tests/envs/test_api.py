"""API tests over every registered vessel-gym id (and config variants): Gymnasium and SB3 checkers with
warnings as errors, determinism, spaces, pickling, vector = N singles, reward terms, rendering."""

from __future__ import annotations

import pickle
import subprocess
import sys
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from vessel_gym.envs.registration import builtin_declarations, register_envs, registered

from .helpers import ENV_IDS, VARIANTS, rollout, same

ALL = [(i, {}) for i in ENV_IDS] + VARIANTS


def _id(p):
    return p if isinstance(p, str) else ",".join(f"{k}={v}" for k, v in p.items()) or "default"


def test_ids_registered_with_vector_entry_points():
    decls = registered()
    assert ENV_IDS == sorted(decls) and ENV_IDS
    assert set(ENV_IDS) == {i for i in gym.registry if i.startswith("vessel_gym/")}
    for env_id in ENV_IDS:
        spec = gym.spec(env_id)
        assert isinstance(spec.entry_point, str) and isinstance(spec.vector_entry_point, str)
        assert spec.max_episode_steps == decls[env_id].max_episode_steps
        if spec.max_episode_steps is None:  # the task truncates itself (a time limit in seconds, not steps)
            env = gym.make(env_id)
            assert env.unwrapped._max_steps > 0
            env.close()


def test_builtin_declarations_read_from_source_match_the_imported_ones():
    decls = registered()
    for src in builtin_declarations():
        for env_id in src.ids:
            imported = decls[env_id]
            assert (imported.module, imported.name) == (src.module, src.name)
            assert imported.presets == src.presets and imported.max_episode_steps == src.max_episode_steps


@pytest.mark.parametrize("old", ["ZigZag-v0", "HarbourApproach-v0"])
def test_removed_versions_raise_deprecated_naming_the_current_id(old):
    name = old.split("-")[0]
    current = max((i for i in ENV_IDS if i.split("/")[1].split("-")[0] == name), key=lambda i: i[-1])
    with pytest.raises(gym.error.DeprecatedEnv, match=current):
        gym.make(f"vessel_gym/{old}")


def test_registration_idempotent_without_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert register_envs() == register_envs()


def test_make_in_fresh_subprocess():
    code = (
        "import gymnasium, vessel_gym.envs; e = gymnasium.make('vessel_gym/ZigZag-v1'); "
        "o, _ = e.reset(seed=0); print(o.shape)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "(8,)"


@pytest.mark.parametrize("env_id,kw", ALL, ids=_id)
def test_gymnasium_check_env_no_warnings(env_id, kw):
    env = gym.make(env_id, disable_env_checker=True, **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)
    env.close()


@pytest.mark.parametrize("env_id,kw", ALL, ids=_id)
def test_sb3_check_env_no_warnings(env_id, kw):
    sb3 = pytest.importorskip("stable_baselines3.common.env_checker")
    env = gym.make(env_id, **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sb3.check_env(env.unwrapped, warn=True)
    env.close()


@pytest.mark.parametrize("env_id,kw", ALL, ids=_id)
def test_same_seed_same_rollout(env_id, kw):
    a = rollout(gym.make(env_id, max_episode_steps=60, **kw), seed=7, steps=150)
    b = rollout(gym.make(env_id, max_episode_steps=60, **kw), seed=7, steps=150)
    assert same(a, b)
    c = rollout(gym.make(env_id, max_episode_steps=60, **kw), seed=8, steps=5)
    # the first observation of ZigZag and TurningCircle does not show what the seed draws (the original
    # course is not observed; v1's seeded start is tested in test_zigzag_v1.py)
    assert not np.array_equal(a[0][0], c[0][0]) or "ZigZag" in env_id or "TurningCircle" in env_id


@pytest.mark.parametrize("env_id,kw", ALL, ids=_id)
def test_observations_inside_space_and_finite(env_id, kw):
    env = gym.make(env_id, max_episode_steps=100, **kw)
    for obs, r, _te, _tr, info in rollout(env, seed=3, steps=300):
        assert obs in env.observation_space
        assert np.all(np.isfinite(obs))
        assert np.isfinite(r)
        assert sum(info["reward_terms"].values()) == pytest.approx(r, abs=1e-12)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_reward_is_sum_of_weighted_terms(env_id):
    env = gym.make(env_id)
    weights = env.unwrapped.config.reward
    env.reset(seed=1)
    env.action_space.seed(1)
    seen = set()
    for _ in range(200):
        _o, r, te, tr, info = env.step(env.action_space.sample())
        terms = info["reward_terms"]
        assert set(terms) == {f for f in weights.__dataclass_fields__}
        assert sum(terms.values()) == pytest.approx(r, abs=1e-12)
        seen |= {k for k, v in terms.items() if v != 0.0}
        if te or tr:
            env.reset()
    assert seen, "no reward term ever non-zero"


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_pickle_mid_episode_continues_identically(env_id):
    env = gym.make(env_id)
    env.reset(seed=2)
    env.action_space.seed(2)
    for _ in range(20):
        env.step(env.action_space.sample())
    twin = pickle.loads(pickle.dumps(env))
    acts = [env.action_space.sample() for _ in range(30)]
    a = [env.step(x) for x in acts]
    b = [twin.step(x) for x in acts]
    assert same(a, b)


@pytest.mark.parametrize("env_id,kw", ALL, ids=_id)
def test_vector_equals_n_single_envs(env_id, kw):
    n, steps, limit = 3, 70, 25  # the time limit forces autoresets inside the run
    venv = gym.make_vec(
        env_id, num_envs=n, vectorization_mode="vector_entry_point", max_episode_steps=limit, **kw
    )
    singles = [gym.make(env_id, max_episode_steps=limit, **kw) for _ in range(n)]
    vobs, _ = venv.reset(seed=11)
    sobs = [e.reset(seed=11 + k)[0] for k, e in enumerate(singles)]
    assert np.array_equal(vobs, np.stack(sobs))
    venv.action_space.seed(0)
    done = np.zeros(n, dtype=bool)
    for _ in range(steps):
        acts = venv.action_space.sample()
        vobs, vr, vte, vtr, vinfo = venv.step(acts)
        for k, e in enumerate(singles):
            if done[k]:  # next-step autoreset: the vector env resets this one now
                o, _i = e.reset()
                r, te, tr = 0.0, False, False
            else:
                o, r, te, tr, _i = e.step(acts[k])
            assert np.array_equal(vobs[k], o), (k, vobs[k], o)
            assert vr[k] == r and vte[k] == te and vtr[k] == tr
        done = vte | vtr
    assert venv.observation_space.contains(vobs)
    for name, arr in vinfo["reward_terms"].items():
        assert arr.shape == (n,), name
    venv.close()


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_vector_same_seed_same_rollout_and_same_step_autoreset(env_id):
    def run(mode):
        venv = gym.make_vec(
            env_id,
            num_envs=4,
            vectorization_mode="vector_entry_point",
            max_episode_steps=10,
            autoreset_mode=mode,
        )
        obs, _ = venv.reset(seed=5)
        venv.action_space.seed(5)
        out = [obs]
        infos = []
        for _ in range(25):
            o, r, te, tr, info = venv.step(venv.action_space.sample())
            out += [o, r, te, tr]
            infos.append(info)
        return out, infos

    a, _ = run("NextStep")
    b, _ = run("NextStep")
    assert same(a, b)
    c, infos = run("SameStep")
    finals = [i for i in infos if "final_obs" in i]
    assert finals and all(i["_final_obs"].any() for i in finals)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_rgb_array_frames(env_id):
    env = gym.make(env_id, render_mode="rgb_array")
    env.reset(seed=0)
    env.action_space.seed(0)
    for _ in range(10):
        env.step(env.action_space.sample())
    frame = env.render()
    assert frame.shape == (600, 800, 3) and frame.dtype == np.uint8
    assert frame.std() > 10.0 and len(np.unique(frame.reshape(-1, 3), axis=0)) > 20
    env.close()
    venv = gym.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point", render_mode="rgb_array")
    venv.reset(seed=0)
    frames = venv.render()
    assert len(frames) == 2 and all(f.shape == (600, 800, 3) for f in frames)
    venv.close()


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_nan_action_raises_and_out_of_range_is_clipped(env_id):
    env = gym.make(env_id)
    env.reset(seed=0)
    shape = env.action_space.shape
    with pytest.raises(ValueError, match="NaN"):
        env.step(np.full(shape, np.nan, dtype=np.float32))
    a = gym.make(env_id)
    b = gym.make(env_id)
    a.reset(seed=4)
    b.reset(seed=4)
    oa = a.step(np.full(shape, 7.0, dtype=np.float32))[0]
    ob = b.step(np.full(shape, 1.0, dtype=np.float32))[0]
    assert np.array_equal(oa, ob)
    venv = gym.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point")
    venv.reset(seed=0)
    with pytest.raises(ValueError, match="NaN"):
        venv.step(np.full((2, *shape), np.nan, dtype=np.float32))


def test_discrete_action_out_of_range_raises():
    env = gym.make("vessel_gym/HarbourApproach-v2", action_type="discrete")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="out of range"):
        env.step(np.array([99, 0]))
