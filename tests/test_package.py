"""The package face: ``import vessel_gym`` is cheap and registers the ids; its ``__all__`` is the documented public
API, each name loaded from its one home on first use."""

from __future__ import annotations

import json
import subprocess
import sys

import vessel_gym


def test_import_loads_no_physics_link_or_plots():
    code = (
        "import json, sys, vessel_gym\n"
        "heavy = ('numba', 'pygame', 'matplotlib', 'vessel_gym.physics', 'vessel_gym.net', 'vessel_gym.manoeuvres')\n"
        "print(json.dumps(sorted({m for m in sys.modules for h in heavy if m == h or m.startswith(h + '.')})))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert json.loads(out) == []


def test_every_public_name_is_documented_and_comes_from_its_home():
    doc = vessel_gym.__doc__
    homes = vessel_gym._HOMES
    assert set(vessel_gym.__all__) == {"__version__", "env_ids", *homes}
    for name in vessel_gym.__all__:
        value = getattr(vessel_gym, name)
        if name == "__version__":
            continue
        assert f"`{name}`" in doc, f"{name} is not in vessel_gym's docstring"
        if name in homes:
            assert value.__module__ == homes[name], (
                f"{name} is defined in {value.__module__}, not {homes[name]}"
            )
            assert value is getattr(sys.modules[homes[name]], name)
    assert set(dir(vessel_gym)) >= set(vessel_gym.__all__)


def test_env_ids_are_the_registered_ones():
    import gymnasium

    ids = vessel_gym.env_ids()
    assert ids and all(i.startswith("vessel_gym/") for i in ids)
    assert set(ids) == {i for i in gymnasium.registry if i.startswith("vessel_gym/")}
    assert "vessel_gym/HarbourApproach-v2" in ids


def test_unknown_names_raise_attribute_error():
    import pytest

    with pytest.raises(AttributeError, match="no_such_name"):
        vessel_gym.no_such_name  # noqa: B018


def test_docs_do_not_count_the_ids_by_hand():
    """The number of ids changes with the tasks: the docs point at env_ids() instead of stating a count."""
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "envs.md").read_text()
    counted = re.findall(r"registers (?:one|two|three|four|five|six|seven|eight|nine|ten|\d+) ", text)
    assert not counted and "env_ids()" in text
