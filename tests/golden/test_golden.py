"""Replays the golden rollouts of ``rollouts.py`` (recorded before the task-layer and physics refactors) and
compares: environments bitwise (observations, rewards, terminated, truncated, every numeric info entry
recorded), physics within 1e-12 relative (the bound the physics refactor promises; bitwise is expected).

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


def _compare_step(i, got, want):
    names = ("observation", "reward", "terminated", "truncated")
    for name, g, w in zip(names, got[:4], want[:4]):
        g, w = np.asarray(g), np.asarray(w)
        assert g.shape == w.shape and np.array_equal(g, w, equal_nan=True), f"step {i}: {name} differs"
    ginfo, winfo = got[4], want[4]
    for k, w in winfo.items():
        if k in DROPPED_INFO:
            continue
        assert k in ginfo, f"step {i}: info[{k!r}] missing"
        g = np.asarray(ginfo[k])
        assert g.shape == np.shape(w) and np.array_equal(g, w, equal_nan=True), f"step {i}: info[{k!r}] differs"


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
