"""Command lines: bad arguments exit with code 2 and one line on stderr."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from agents import evaluate, results, train, tune_ray

REPO = Path(__file__).resolve().parents[2]

BAD = [
    (train, ["--algo", "ppo"]),  # --env missing
    (train, ["--env", "ZigZag-v1", "--algo", "dqn"]),
    (train, ["--env", "CartPole-v1", "--algo", "ppo"]),
    (train, ["--env", "ZigZag-v1", "--algo", "ppo", "--seed", "-1"]),
    (train, ["--env", "ZigZag-v1", "--algo", "ppo", "--timesteps", "0"]),
    (train, ["--env", "ZigZag-v1", "--algo", "ppo", "--vec", "ray"]),
    (train, ["--env", "ZigZag-v1", "--algo", "ppo", "--time-budget", "nan"]),
    (train, ["--env", "ZigZag-v1", "--algo", "ppo", "--hyperparams", "n_step=64"]),
    (train, ["--env", "ZigZag-v1", "--algo", "ppo", "--hyperparams", "gamma"]),
    (train, ["--env", "ZigZag-v1", "--algo", "ppo", "--hyperparams", "env_kwargs.schedule=sometimes"]),
    (train, ["--env", "ZigZag-v1", "--algo", "ppo", "--hyperparams-file", "/nonexistent.yml"]),
    # a curriculum: a bad block, a task without difficulty levels, a level out of the task's range
    (train, ["--env", "HarbourApproach-v3", "--algo", "ppo", "--hyperparams", "curriculum={levels: [3]}"]),
    (train, ["--env", "ZigZag-v1", "--algo", "ppo", "--hyperparams", "curriculum={levels: [0, 3]}"]),
    (train, ["--env", "HarbourApproach-v3", "--algo", "ppo", "--hyperparams", "curriculum={levels: [0, 7]}"]),
    (evaluate, ["--env", "ZigZag-v1"]),  # --agent missing
    (evaluate, ["--env", "ZigZag-v1", "--agent", "pid", "--episodes", "0"]),
    (evaluate, ["--env", "ZigZag-v1", "--agent", "pid", "--episodes", "two"]),
    (evaluate, ["--env", "Nope-v0", "--agent", "pid"]),
    (evaluate, ["--env", "ZigZag-v1", "--agent", "lqr"]),
    (evaluate, ["--env", "ZigZag-v1", "--agent", "/nonexistent/ppo_x.zip"]),
    (evaluate, ["--env", "ZigZag-v1", "--agent", "pid", "--env-kwargs", "speed=3"]),
    (evaluate, ["--env", "ZigZag-v1", "--agent", "pid", "--video", "out.avi"]),
    (evaluate, ["--env", "ZigZag-v1", "--agent", "pid", "--plot", "out.svg"]),
    (evaluate, ["--env", "ZigZag-v1", "--agent", "pid", "--frame-every", "0"]),
    (results, ["--seeds", "0"]),
    (results, ["--budget", "0"]),
    (results, ["--algos", "dqn"]),
    (results, ["--jobs", "0"]),
    (results, ["--time-budget", "nan"]),
    (results, ["--envs", "Nope-v0", "--skip-train"]),
    (tune_ray, ["--env", "ZigZag-v1", "--algo", "ppo", "--samples", "0"]),
    (tune_ray, ["--env", "ZigZag-v1"]),
]


@pytest.mark.parametrize(
    "module, argv", BAD, ids=[f"{m.__name__.split('.')[-1]}:{' '.join(a)}" for m, a in BAD]
)
def test_bad_arguments_exit_2_with_one_line(module, argv, capsys, tmp_path: Path) -> None:
    if module is results:
        argv = [*argv, "--out", str(tmp_path / "out"), "--doc", str(tmp_path / "results.md")]
    with pytest.raises(SystemExit) as exc:
        code = module.main(argv)
        raise SystemExit(code)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1, err
    assert "error" in err


@pytest.mark.parametrize("script", ["train.py", "evaluate.py", "results.py", "tune_ray.py"])
def test_scripts_run_as_scripts(script: str) -> None:
    """``python agents/<script>`` from any directory: --help works, a bad option exits 2 in one line."""
    path = REPO / "agents" / script
    ok = subprocess.run([sys.executable, str(path), "--help"], capture_output=True, text=True, cwd="/")
    assert ok.returncode == 0 and "usage" in ok.stdout
    bad = subprocess.run([sys.executable, str(path), "--bogus"], capture_output=True, text=True, cwd="/")
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1, bad.stderr


def test_evaluate_json_baseline(capsys) -> None:
    import json

    assert evaluate.main(["--env", "ZigZag-v1", "--agent", "pid", "--episodes", "1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["agent"] == "pid" and out["episodes"] == 1 and out["summary"]["episodes"] == 1
    assert out["mean_heading_error_deg"] > 0.0 and out["mean_overshoot_deg"] >= 0.0
    for key in ("mean_return", "mean_rudder_deg", "mean_rudder_rate_deg_s"):
        assert isinstance(out[key], float)


def test_vessel_gym_evaluate_and_the_script_print_the_same_json(tmp_path: Path) -> None:
    """``vessel-gym evaluate`` is the command; ``python agents/evaluate.py`` from another directory is its alias:
    the same JSON, byte for byte (the episodes are seeded)."""
    import json

    argv = ["--env", "ZigZag-v1", "--agent", "pid", "--episodes", "1", "--json"]
    script = subprocess.run(
        [sys.executable, str(REPO / "agents" / "evaluate.py"), *argv],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    command = subprocess.run(
        [sys.executable, "-m", "vessel_gym.cli", "evaluate", *argv],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert script.returncode == 0 and command.returncode == 0, script.stderr + command.stderr
    assert script.stdout == command.stdout
    assert json.loads(command.stdout)["env_id"] == "vessel_gym/ZigZag-v1"


def test_vessel_gym_train_and_evaluate_errors_name_the_command(capsys) -> None:
    from vessel_gym.cli import main

    assert main(["train", "--env", "ZigZag-v1", "--algo", "dqn"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("vessel-gym train: error: ") and "dqn" in err and len(err.splitlines()) == 1
    assert main(["evaluate", "--env", "Nope-v0", "--agent", "pid"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("vessel-gym evaluate: error: ") and "Nope-v0" in err and len(err.splitlines()) == 1
