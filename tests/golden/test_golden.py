"""Replays the golden rollouts of ``rollouts.py`` (recorded before the task-layer and physics refactors) and
compares: environments (observations, rewards, terminated, truncated, every numeric info entry recorded)
exactly in their integers and booleans and within 1e-12 in their floats, physics within 1e-12 relative (the
bound the physics refactor promises). On the machine that recorded them both replay bitwise; on another CPU
the same code can differ in the last bit, because numpy and numba pick their SIMD kernels by CPU (one
reward of ZigZag-v1 with weather, 1.2e-16 relative, on an AMD EPYC with AVX2 only).

An intended change re-records the file (``python -m tests.golden.rollouts``) and names itself in the docs.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from . import rollouts as R

INDEX = R.load(R.DATA / "index.pkl.gz")

# info entries recorded in the goldens that a later version no longer reports, each with the reason
DROPPED_INFO: dict[str, str] = {}

# relative bound of the physics comparison (per state component, scaled by the largest magnitude of that
# component over the rollout so that a state crossing zero is not judged by its tiny values)
PHYSICS_RTOL = 1e-12


# bound of the environments' float comparison, relative and absolute (observations and rewards are O(1)):
# a last-bit difference of another CPU's SIMD kernels is ~1e-16; any change of a model or rule is far larger
ENV_TOL = 1e-12


def _same(g, w) -> bool:
    g, w = np.asarray(g), np.asarray(w)
    if g.shape != w.shape:
        return False
    if np.issubdtype(w.dtype, np.floating) or np.issubdtype(g.dtype, np.floating):
        return bool(np.allclose(g, w, rtol=ENV_TOL, atol=ENV_TOL, equal_nan=True))
    return bool(np.array_equal(g, w))


def _compare_step(i, got, want):
    names = ("observation", "reward", "terminated", "truncated")
    for name, g, w in zip(names, got[:4], want[:4]):
        assert _same(g, w), f"step {i}: {name} differs"
    ginfo, winfo = got[4], want[4]
    for k, w in winfo.items():
        if k in DROPPED_INFO:
            continue
        assert k in ginfo, f"step {i}: info[{k!r}] missing"
        assert _same(ginfo[k], w), f"step {i}: info[{k!r}] differs"


@pytest.mark.parametrize("vector", [False, True], ids=["single", "vector"])
@pytest.mark.parametrize("env_id", INDEX["ids"])
def test_env_rollout_unchanged(env_id, vector):
    want = R.load(R.path("vector" if vector else "single", env_id))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        got = R.env_rollout(env_id, vector)
    assert len(got) == len(want)
    for i, (g, w) in enumerate(zip(got, want)):
        _compare_step(i, g, w)


@pytest.mark.parametrize("j", range(len(INDEX["variants"])))
def test_env_variant_unchanged(j):
    env_id, kw = INDEX["variants"][j]
    want = R.load(R.path("variant", f"{j:02d}"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        got = R.env_rollout(env_id, False, kw)
    assert len(got) == len(want)
    for i, (g, w) in enumerate(zip(got, want)):
        _compare_step(i, g, w)


@pytest.mark.parametrize("weather", [False, True], ids=["calm", "weather"])
@pytest.mark.parametrize("ship", INDEX["ships"])
def test_physics_rollout_unchanged(ship, weather):
    want = R.load(R.path("weather" if weather else "calm", ship))
    got = R.physics_rollout(ship, weather)
    assert got.shape == want.shape
    scale = np.maximum(np.abs(want).max(axis=0), 1e-300)
    err = np.abs(got - want) / scale
    assert np.all(np.isfinite(got) == np.isfinite(want))
    assert np.nanmax(err) <= PHYSICS_RTOL, f"largest relative difference {np.nanmax(err):.3g}"
