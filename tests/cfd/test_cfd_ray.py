"""`vessel-cfd run --ray`: the cases of ``ray_cases.py`` run in a pytest of their own.

They start a local Ray instance in the test process and send it Ctrl-C. A Ray driver whose raylet stops
answering (a loaded machine, a cancelled task's worker) ends its process at once, which would end the whole
test session without a report; in a child process such an end is one failed test with its output."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("ray")

HERE = Path(__file__).resolve().parent


def test_ray_cases_pass_in_a_process_of_their_own():
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(HERE.parents[1]), os.environ.get("PYTHONPATH", "")]))
    res = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", str(HERE / "ray_cases.py")],
        cwd=HERE.parents[1],
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
        check=False,
    )
    assert res.returncode == 0, f"ray_cases.py exited {res.returncode}:\n{res.stdout[-4000:]}\n{res.stderr[-2000:]}"
    assert " passed" in res.stdout
