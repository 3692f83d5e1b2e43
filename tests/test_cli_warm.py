"""``vessel-gym warm``: compiles an environment's kernels ahead of its first step, says so line by line."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from vessel_gym import cli
from vessel_gym.physics import jitcache

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["warm", "Nope-v9"], "'Nope-v9' is no registered environment id"),
        (["warm", "--imo", "nosuchship"], "nosuchship: unknown ship"),
        (["warm", "ZigZag-v1", "--imo"], "--imo: expected at least one argument"),
    ],
)
def test_bad_input_is_one_line_and_exit_2_before_anything_compiles(capsys, argv, needle):
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert needle in err and len(err.strip().splitlines()) == 1, err


def test_progress_line_per_id_and_a_total(capsys, monkeypatch):
    monkeypatch.setenv(jitcache.NOTICE_ENV, "1")  # the command turns the notice off: its own lines say it
    assert cli.main(["warm", "ZigZag-v1", "vessel_gym/TurningCircle-v0"]) == 0
    lines = capsys.readouterr().err.splitlines()
    assert [ln.split(" ...")[0] for ln in lines[:2]] == [
        "vessel-gym warm: [1/2] vessel_gym/ZigZag-v1",
        "vessel-gym warm: [2/2] vessel_gym/TurningCircle-v0",
    ]
    assert all(ln.endswith("s CPU)") for ln in lines[:2])
    assert lines[2].startswith("vessel-gym warm: 2 done in ") and len(lines) == 3


@pytest.mark.slow
def test_after_warm_the_first_step_of_a_fresh_process_compiles_nothing(tmp_path):
    """On an empty cache: ``warm ZigZag-v1`` compiles; a new process's first step then loads everything."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env.update(PYTHONPATH=str(ROOT), NUMBA_CACHE_DIR=str(tmp_path / "cache"), **{jitcache.NOTICE_ENV: "1"})
    warm = subprocess.run(
        [sys.executable, "-m", "vessel_gym.cli", "warm", "ZigZag-v1"],
        env=env,
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert warm.returncode == 0, warm.stderr
    assert "[1/1] vessel_gym/ZigZag-v1" in warm.stderr
    step = (
        "import gymnasium as gym, vessel_gym.envs; env = gym.make('vessel_gym/ZigZag-v1'); env.reset(seed=0); "
        "env.step(env.action_space.sample())"
    )
    first = subprocess.run(
        [sys.executable, "-c", step], env=env, cwd=ROOT, capture_output=True, text=True, timeout=900
    )
    assert first.returncode == 0, first.stderr
    assert jitcache.COMPILE_NOTICE not in first.stderr, first.stderr
