"""Agent tests: skip when the ``rl`` extra (stable-baselines3, torch, PyYAML) is missing; make the
repository root importable (``agents`` is a top-level package of the repository, not of the wheel)."""

import sys
from pathlib import Path

import pytest

ROOT = str(Path(__file__).resolve().parents[2])
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)

pytest.importorskip("stable_baselines3")
pytest.importorskip("yaml")
