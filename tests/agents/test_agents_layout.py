"""The agent library is split by job (config, envs, training, evaluation, cli_util) and ``agents.common`` stays the
one import for all of it: the same objects, not copies."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import agents.common as common

AGENTS = Path(__file__).resolve().parents[2] / "agents"
MODULES = ("config", "envs", "training", "evaluation", "cli_util")


@pytest.mark.parametrize("name", MODULES)
def test_each_job_module_is_short_and_says_its_job(name):
    path = AGENTS / f"{name}.py"
    text = path.read_text()
    assert len(text.splitlines()) <= 600
    assert ast.get_docstring(ast.parse(text)), f"{path} has no module docstring"


def test_common_reexports_the_objects_of_their_home_modules():
    import importlib

    seen = {}
    for name in MODULES:
        mod = importlib.import_module(f"agents.{name}")
        for attr, value in vars(mod).items():
            if attr.startswith("_") or getattr(value, "__module__", mod.__name__) != mod.__name__:
                continue
            if callable(value):
                seen[attr] = value
    missing = sorted(a for a in seen if not hasattr(common, a))
    assert not missing, f"agents.common does not re-export {missing}"
    assert all(getattr(common, a) is v for a, v in seen.items())
    assert common.UsageError is importlib.import_module("agents.config").UsageError
