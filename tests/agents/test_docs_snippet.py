"""The SB3 example of docs/agents.md runs as printed (with a smaller budget) and shows its progress."""

from __future__ import annotations

import re
from pathlib import Path

DOC = Path(__file__).resolve().parents[2] / "docs" / "agents.md"


def _snippet() -> str:
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), re.S)
    (code,) = [b for b in blocks if "vessel_gym.sb3 import make_vec_env" in b and ".learn(" in b]
    return code


def test_sb3_snippet_is_short_shows_progress_and_runs():
    code = _snippet()
    assert len(code.strip().splitlines()) <= 8
    assert "progress_bar=True" in code
    budget = re.search(r"\.learn\(([\d_]+)", code).group(1)
    small = code.replace(f".learn({budget}", ".learn(2048")  # one rollout of 16 ships x 128 steps
    scope: dict = {}
    exec(compile(small, str(DOC), "exec"), scope)
    assert scope["model"].num_timesteps == 2048
