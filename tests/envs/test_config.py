"""Strict, typed configuration of the environments."""

from __future__ import annotations

import gymnasium as gym
import pytest

import vessel_gym.envs  # noqa: F401
from vessel_gym.envs.tasks.zigzag import ZigZagConfig
from vessel_gym.physics.schema import SpecError


def test_unknown_key_raises_naming_it():
    with pytest.raises(SpecError, match="unknown key 'zig_heading'"):
        gym.make("vessel_gym/ZigZag-v1", zig_heading=20)
    with pytest.raises(SpecError, match="unknown key 'overshot'"):
        gym.make("vessel_gym/ZigZag-v1", reward={"overshot": 2.0})


def test_out_of_range_and_wrong_type_raise():
    with pytest.raises(SpecError, match="zigzag_heading_deg"):
        gym.make("vessel_gym/ZigZag-v1", zigzag_heading_deg=500.0)
    with pytest.raises(SpecError, match="expected a string"):
        gym.make("vessel_gym/ZigZag-v1", schedule=3)
    with pytest.raises(SpecError, match="not one of"):
        gym.make("vessel_gym/TurningCircle-v0", mode="spiral")


def test_control_interval_must_be_whole_multiple_of_dt():
    with pytest.raises(SpecError, match="whole multiple"):
        gym.make("vessel_gym/ZigZag-v1", control_interval_s=0.23, dt_s=0.05)
    env = gym.make("vessel_gym/ZigZag-v1", control_interval_s=0.5, dt_s=0.05)
    assert env.unwrapped.task.nsub == 10


def test_nested_reward_override_merges_and_config_file(tmp_path):
    env = gym.make("vessel_gym/ZigZag-v1", reward={"overshoot": 3.0})
    r = env.unwrapped.config.reward
    assert r.overshoot == 3.0 and r.heading_error == 1.0
    f = tmp_path / "zz.toml"
    f.write_text('schedule = "random"\n[reward]\nspeed_loss = 0.0\n')
    env = gym.make("vessel_gym/ZigZag-v1", config=str(f), reward={"overshoot": 2.0})
    c = env.unwrapped.config
    assert c.schedule == "random" and c.reward.speed_loss == 0.0 and c.reward.overshoot == 2.0
    f.write_text("colour = 1\n")
    with pytest.raises(SpecError, match=r"zz\.toml.*unknown key 'colour'"):
        gym.make("vessel_gym/ZigZag-v1", config=str(f))


def test_config_instances_are_not_shared():
    a = gym.make("vessel_gym/ZigZag-v1", zigzag_heading_deg=20.0).unwrapped.config
    b = gym.make("vessel_gym/ZigZag-v1").unwrapped.config
    assert a.zigzag_heading_deg == 20.0 and b.zigzag_heading_deg == 10.0
    assert isinstance(b, ZigZagConfig)


def test_unknown_reset_option_raises():
    env = gym.make("vessel_gym/ZigZag-v1")
    with pytest.raises(ValueError, match="unknown reset option"):
        env.reset(options={"colour": 1})


def test_docs_list_every_config_key():
    """docs/envs.md carries every config and reward key of every registered task (its tables are generated from
    the declarations and the config dataclasses)."""
    import dataclasses
    from pathlib import Path

    from vessel_gym.envs.registration import registered, task_class

    doc = (Path(__file__).parents[2] / "docs" / "envs.md").read_text()
    for env_id in registered():
        task = task_class(env_id)
        for cls in (task.Config, type(task.Config().reward)):
            for f in dataclasses.fields(cls):
                assert f"`{f.name}`" in doc, (cls.__name__, f.name)


def test_scenario_name_with_a_nul_is_a_one_line_error_naming_it():
    from vessel_gym.physics.schema import SpecError

    with pytest.raises(SpecError) as err:
        gym.make("vessel_gym/HarbourApproach-v2", scenario="my_har\x00bour.toml")
    msg = str(err.value)
    assert "'my_har\\x00bour.toml'" in msg and "U+0000" in msg
    assert "\x00" not in msg and "\n" not in msg
