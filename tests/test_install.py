"""What the README's install command brings: everything its examples import (rendering included)."""

from __future__ import annotations

import re
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]


def _names(requirements: list[str]) -> set[str]:
    return {re.split(r"[<>=!~;\[ ]", r, maxsplit=1)[0].lower() for r in requirements}


def test_readme_install_brings_rendering_and_plots():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    readme = (ROOT / "README.md").read_text()
    (extras,) = re.findall(r'pip install -e "\.\[(\w+)\]" && vessel-gym imo', readme)
    brought = _names(project["dependencies"]) | _names(project["optional-dependencies"][extras])
    # the chart view, play, helm and view need pygame; the plots need matplotlib; envs and physics the rest
    assert {"numpy", "numba", "gymnasium", "pygame", "matplotlib"} <= brought
    for picture in re.findall(r"!\[[^\]]*\]\(([^)]+)\)", readme):
        assert (ROOT / picture).is_file(), picture


def test_readme_lists_every_built_in_ship():
    from vessel_gym.physics.shipfile import builtin_ships

    readme = (ROOT / "README.md").read_text()
    item = next(line for line in readme.split("\n- ") if line.startswith("**Ships**"))
    named = set(re.findall(r"`(\w+)`", item))
    assert set(builtin_ships()) <= named, sorted(set(builtin_ships()) - named)


def test_the_agents_are_installed_with_the_package():
    setuptools = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    assert {"vessel_gym*", "cfd*", "agents*"} <= set(setuptools["packages"]["find"]["include"])
    data = setuptools["package-data"]["agents"]
    assert "hyperparams/*.yml" in data and any(d.startswith("trained/") for d in data)
