"""Without an optional extra, a command that needs it says so in one line naming the extra (exit code 2) before
any work, and a command that does not need it runs. The extras' modules are hidden in a subprocess
(``sys.modules[name] = None`` makes their import fail as if they were not installed)."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

RL = ("yaml", "stable_baselines3", "torch", "tqdm", "rich", "tensorboard")


def _run(hidden: tuple[str, ...], body: str, tmp_path) -> subprocess.CompletedProcess:
    code = "import sys\n" + "".join(f"sys.modules[{m!r}] = None\n" for m in hidden) + textwrap.dedent(body)
    return subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, timeout=600
    )


def _one_line(proc: subprocess.CompletedProcess, *needles: str) -> None:
    assert proc.returncode == 2, proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "Traceback" not in proc.stderr, proc.stderr
    for needle in needles:
        assert needle in proc.stderr, proc.stderr


def test_evaluate_a_baseline_needs_no_rl_packages(tmp_path):
    proc = _run(
        RL,
        """
        from agents.evaluate import main
        sys.exit(main(["--env", "ZigZag-v1", "--agent", "pid", "--episodes", "1", "--json",
                       "--env-kwargs", "schedule=imo"]))
        """,
        tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert out["agent"] == "pid" and out["episodes"] == 1 and out["env_kwargs"] == {"schedule": "imo"}


@pytest.mark.parametrize(
    "command, argv",
    [
        ("train", ["--env", "ZigZag-v1", "--algo", "ppo", "--timesteps", "64"]),
        ("evaluate", ["--env", "ZigZag-v1", "--agent", "runs/ppo_ZigZag-v1_s0.zip"]),
    ],
)
def test_training_and_saved_models_name_the_rl_extra(tmp_path, command, argv):
    body = f"from vessel_gym.cli import main\nsys.exit(main({[command, *argv]!r}))\n"
    _one_line(_run(RL, body, tmp_path), f"vessel-gym {command}: error:", "'rl' extra", "vessel-gym[rl]")


@pytest.mark.parametrize(
    "argv",
    [
        ["imo", "kvlcc2", "--plot", "plots"],
        ["imo", "kvlcc2", "--report", "report"],
        ["manoeuvre", "zigzag", "kvlcc2", "--plot", "plots"],
    ],
)
def test_plots_without_matplotlib_name_the_plot_extra_before_any_trial(tmp_path, argv):
    body = f"""
    from vessel_gym import cli
    from vessel_gym.manoeuvres import imo, trials

    def no_trial(*a, **kw):
        raise SystemExit("a trial ran before the check")

    imo.imo_report = trials.zigzag = no_trial
    sys.exit(cli.main({argv!r}))
    """
    proc = _run(("matplotlib",), body, tmp_path)
    _one_line(proc, f"vessel-gym {argv[0]}", argv[-2], "'plot' extra", "vessel-gym[plot]")
    assert not list(tmp_path.iterdir()), "nothing is written"


def test_evaluate_pictures_without_matplotlib_name_the_plot_extra(tmp_path):
    body = """
    from agents.evaluate import main
    sys.exit(main(["--env", "ZigZag-v1", "--agent", "pid", "--episodes", "1", "--plot", "t.png"]))
    """
    _one_line(_run(("matplotlib",), body, tmp_path), "evaluate.py: error: --plot", "'plot' extra")
    assert not list(tmp_path.iterdir())
