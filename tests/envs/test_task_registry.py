"""A task defined in this module alone gets everything from its declaration: Gymnasium registration, the
checker, the single and native vector environments, evaluation by ``agents`` with its declared pilot, a row in
the generated docs tables and training defaults. docs/tasks.md shows the task below as its worked example (a test
checks that the page carries this code)."""

from __future__ import annotations

# --- the worked example of docs/tasks.md: begin ----------------------------------------------------------------
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.envs.config import OpenWaterConfig
from vessel_gym.envs.declare import FeatureSpec, Info, Term, columns, degrees
from vessel_gym.envs.registration import register_task
from vessel_gym.envs.tasks.common import (
    DIVERGED,
    OpenWaterTask,
    clear_row,
    encode_row,
    finish,
    motion,
    motion_features,
    motion_observed,
    reset_options,
    task_spec,
)
from vessel_gym.physics.schema import param
from vessel_gym.physics.units import DEG

# 1. the declaration: reward terms, features and info entries by name (columns, weights class, docs follow)
SPEC = task_spec(
    "CourseKeeping",
    terms=(
        Term("heading_error", 1.0, "-|course - heading| / pi"),
        Term("rudder", 0.1, "-|rudder order| / rudder limit"),
    ),
    features=(FeatureSpec("heading_error", "rad", (1.0, "pi"), "commanded course - heading, wrapped"),),
    info=(
        Info("heading_error_deg", lambda v: degrees(v.feat[FEAT.heading_error]), "course - heading, deg"),
        DIVERGED,
    ),
)
TERM, FEAT = SPEC.TERM, SPEC.FEAT
S = columns("psi0", "U0", "prev_order", "course")  # per-vessel task state
CourseKeepingReward = SPEC.weights_class("CourseKeepingReward", __name__, "CourseKeeping reward weights.")


# 2. the configuration: the shared keys, the open-water start, the task's own keys and its reward weights
@dataclass(frozen=True, kw_only=True)
class CourseKeepingConfig(OpenWaterConfig):
    course_change_deg: tuple[float, ...] = param(
        (10.0, 30.0), unit="deg", lo=0.0, hi=180.0, doc="[min, max] course change ordered at the start"
    )
    reward: CourseKeepingReward = param(CourseKeepingReward(), doc="reward weights")


# 3. the step of every vessel in ``phase`` (1: stepped, 2: just reset); numba's @njit makes it fast.
# ``v``: the vessels' arrays by name (v.terms, v.feat, ...), ``t``: the task's own (t.ts, t.p)
def course_keeping_update(phase, v, t):
    for k in range(len(phase)):
        if phase[k] == 0:
            continue
        u, vv, r, psi, _n, _e, rudder, order, rev, _rev_order = motion(v, k)
        s = t.ts[k]
        clear_row(v.terms, k)
        error = (s[S.course] - psi + math.pi) % (2.0 * math.pi) - math.pi
        if phase[k] == 1:
            v.terms[k, TERM.heading_error] = -abs(error) / math.pi
            v.terms[k, TERM.rudder] = -abs(order) / t.p[0]
        v.done[k] = not v.alive[k]
        finish(v, k)  # weights the terms, sums the reward
        s[S.prev_order] = order
        motion_features(v.feat[k], u, vv, r, rudder, order, rev)
        v.feat[k, FEAT.heading_error] = error
        encode_row(v, k)


# 4. the capabilities: a classical pilot and the episode metrics the agents report
def pid_pilot(env: Any) -> Any:
    from vessel_gym.envs.policies import PIDHeadingAutopilot

    return PIDHeadingAutopilot(env)


def episode_metrics(infos: list, terminated: bool) -> dict[str, Any]:
    return {"heading_error_deg": float(np.mean([abs(i["heading_error_deg"]) for i in infos]))}


# 5. the task: ids as presets of the config, time limit, capabilities, training defaults
@register_task(
    presets={"CourseKeeping-v0": {}, "CourseKeepingLarge-v0": {"course_change_deg": [60.0, 90.0]}},
    max_episode_steps=240,
    pilots={"pid": pid_pilot},
    metrics=episode_metrics,
    train={"common": {"n_timesteps": 100_000, "n_envs": 8}},
    namespace="example",
)
class CourseKeepingTask(OpenWaterTask):
    """Course keeping: turn onto a commanded course and hold it with little rudder."""

    Config = CourseKeepingConfig
    spec = SPEC
    S = S
    kernel = staticmethod(course_keeping_update)  # its record t: OpenWaterTask's (ts, p)

    def __init__(self, config: CourseKeepingConfig, n: int) -> None:
        super().__init__(config, n)
        self.ts = np.zeros((n, len(S)))
        self.p = np.array([self.rudder_scale()])

    def observed(self) -> tuple[str, ...]:
        return motion_observed(rev=self.config.engine_control) + ("heading_error",)

    def reset_vessel(self, k: int, rng: np.random.Generator, options: Any) -> None:
        heading, speed, _ = reset_options(self.config, options, rng, self.U_T)
        change = rng.uniform(*self.config.course_change_deg) * rng.choice([-1.0, 1.0])
        self.start_vessel(k, rng, heading, speed)
        self.ts[k, S.course] = (heading + change) * DEG


# --- the worked example of docs/tasks.md: end ------------------------------------------------------------------

import warnings  # noqa: E402  (the test's own imports)
from pathlib import Path  # noqa: E402

import gymnasium as gym  # noqa: E402
import pytest  # noqa: E402
from gymnasium.utils.env_checker import check_env  # noqa: E402

ID = "example/CourseKeeping-v0"
ROOT = Path(__file__).resolve().parents[2]


def test_registered_from_its_declaration():
    from vessel_gym.envs.registration import declaration, registered

    assert {"example/CourseKeeping-v0", "example/CourseKeepingLarge-v0"} <= set(registered(None))
    assert "example/CourseKeeping-v0" not in registered()  # not a vessel_gym id
    spec = gym.spec(ID)
    assert spec.max_episode_steps == 240 and spec.kwargs == {"preset": "CourseKeeping-v0"}
    assert spec.entry_point == f"{__name__}:CourseKeepingEnv"
    assert declaration(ID).pilots["pid"] is pid_pilot
    large = gym.make("example/CourseKeepingLarge-v0").unwrapped.config
    assert large.course_change_deg == (60.0, 90.0)


def test_passes_gymnasiums_checker():
    env = gym.make(ID, disable_env_checker=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)
    env.close()


def test_single_and_native_vector_env_agree():
    single = gym.make(ID)
    venv = gym.make_vec(ID, num_envs=2, vectorization_mode="vector_entry_point")
    assert type(venv).__name__ == "CourseKeepingVectorEnv"
    vobs, _ = venv.reset(seed=5)
    obs, _ = single.reset(seed=6)  # vessel k of a vector env seeded s follows a single env seeded s + k
    np.testing.assert_array_equal(vobs[1], obs)
    for _ in range(20):
        a = np.array([0.3], dtype=np.float32)
        vobs, vr, *_ = venv.step(np.stack([a, a]))
        obs, r, *_ = single.step(a)
    np.testing.assert_array_equal(vobs[1], obs)
    assert vr[1] == r and r < 0.0
    venv.close()
    single.close()


def test_pilot_evaluated_by_the_agents():
    from agents.evaluation import evaluate

    out = evaluate(ID, "pid", episodes=1, seed=0)
    summary = out["summary"]
    assert summary["episodes"] == 1 and out["episodes"][0]["length"] == 240
    # the pilot holds the ordered course: its mean heading error is well below the 10-30 deg ordered
    assert 0.0 < summary["heading_error_deg_mean"] < 10.0


def test_generated_docs_row_and_tables():
    from vessel_gym.envs.registration import registered
    from vessel_gym.envs.tasks import docs_block, ids_table

    decls = registered("example")
    table = ids_table(decls)
    assert "| `example/CourseKeeping-v0` | `CourseKeepingTask` | the defaults | 240 steps | `pid` |" in table
    assert "`course_change_deg=[60, 90]`" in table
    block = docs_block(decls)
    assert "#### CourseKeeping (`CourseKeepingTask`, `CourseKeepingConfig`)" in block
    assert "| `course_change_deg` |" in block and "| `heading_error` | 1 |" in block
    assert "| `heading_error_deg` | course - heading, deg |" in block  # the declared info entries


def test_training_defaults_from_the_declaration():
    from agents.config import load_hyperparams

    hp = load_hyperparams("ppo", ID)
    assert hp["n_timesteps"] == 100_000 and hp["n_envs"] == 8


def test_docs_tasks_md_shows_this_example():
    """docs/tasks.md carries the example above, line for line, in <= 150 lines."""
    src = Path(__file__).read_text()
    code = src.split("# --- the worked example of docs/tasks.md: begin")[1].split("\n", 1)[1]
    code = code.split("# --- the worked example of docs/tasks.md: end")[0].rstrip() + "\n"
    assert len(code.splitlines()) <= 150
    doc = (ROOT / "docs" / "tasks.md").read_text()
    assert code in doc


@pytest.mark.parametrize("old", ["CourseKeeping-v1"])
def test_unknown_version_is_gymnasiums_error(old):
    with pytest.raises(gym.error.VersionNotFound):
        gym.make(f"example/{old}")
