"""The ``curriculum`` hyperparameter key: its checks, and the callback's promotions by success, by schedule,
and without counting the episodes begun at the level before."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from agents.config import UsageError, _curriculum
from agents.training import curriculum_callback

SPEC = {"levels": [0, 1, 3], "promote_at": 0.5, "window": 4, "final_by": 0.5}


class FakeVecEnv:
    def __init__(self) -> None:
        self.calls: list[tuple[str, object]] = []

    def env_method(self, name: str, *args: object) -> list[None]:
        self.calls.append((name, *args))
        return [None]


def make(n_timesteps: int = 1000, n_envs: int = 2):
    env = FakeVecEnv()
    model = SimpleNamespace(
        num_timesteps=0, get_env=lambda: env, logger=SimpleNamespace(record=lambda *a, **k: None)
    )
    cb = curriculum_callback(_curriculum(SPEC), n_timesteps, n_envs)
    cb.init_callback(model)
    return cb, model, env


def step(cb, model, t: int, dones: list[bool], successes: list[bool]) -> None:
    model.num_timesteps = t
    cb.update_locals({"dones": dones, "infos": [{"success": s} for s in successes]})
    cb.on_step()


def test_promotes_on_success_and_ignores_the_episodes_begun_before():
    cb, model, env = make()
    for t in (2, 4):
        step(cb, model, t, [True, True], [True, False])  # 2 of 4: rate 0.5 reaches promote_at
    assert env.calls == [("set_difficulty", 1)]
    assert cb.history[-1]["level"] == 1 and cb.history[-1]["timesteps"] == 4
    assert cb.history[-1]["why"].startswith("success 0.50")
    # the first episode of each copy to end after the change began at level 0: not counted
    step(cb, model, 6, [True, True], [True, True])
    assert len(cb.recent) == 0
    step(cb, model, 8, [True, True], [True, True])
    assert list(cb.recent) == [True, True]
    step(cb, model, 10, [True, True], [False, False])  # 2 of 4 again
    assert env.calls[-1] == ("set_difficulty", 3) and cb.index == 2


def test_a_level_not_mastered_is_left_on_schedule():
    cb, model, env = make(n_timesteps=1000)
    # deadlines: level 1 by 1/2 x 0.5 x 1000 = 250 steps, level 3 by 500
    step(cb, model, 249, [True, True], [False, False])
    assert env.calls == []
    step(cb, model, 250, [False, False], [False, False])
    assert env.calls == [("set_difficulty", 1)] and cb.history[-1]["why"] == "schedule"
    step(cb, model, 500, [False, False], [False, False])
    assert env.calls[-1] == ("set_difficulty", 3)
    step(cb, model, 900, [True, True], [True, True])  # the last level stays
    assert len(env.calls) == 2


@pytest.mark.parametrize(
    ("block", "what"),
    [
        ([0, 3], "expected a mapping"),
        ({"levels": [3]}, "curriculum.levels"),
        ({"levels": [0, 3], "promote_at": 0}, "curriculum.promote_at"),
        ({"levels": [0, 3], "final_by": 1.5}, "curriculum.final_by"),
        ({"levels": [0, 3], "window": 0}, "curriculum.window"),
        ({"levels": [0, 3], "stages": 2}, "unknown key(s) stages"),
    ],
)
def test_bad_blocks_are_refused_naming_the_key(block, what):
    with pytest.raises(UsageError, match=what.replace("(", r"\(").replace(")", r"\)")):
        _curriculum(block)


def test_defaults():
    assert _curriculum({"levels": ["basin", "open"]}) == {
        "levels": ["basin", "open"], "promote_at": 0.8, "final_by": 0.5, "window": 100,
    }  # fmt: skip
