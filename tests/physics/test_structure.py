"""The physics package's shape: modules short enough to read, numba's private API in one module."""

from __future__ import annotations

import re
from pathlib import Path

PHYSICS = Path(__file__).resolve().parents[2] / "vessel_gym" / "physics"
MAX_LINES = 650  # any physics module
MAX_SIMULATION_LINES = 600  # simulation.py: the Simulation class and its set-up, nothing beside it
# numba's private API: its core package, dispatcher internals (compiled overloads, their entry points)
PRIVATE_NUMBA = re.compile(r"numba\.core|\._dispatcher|\.overloads\b|\.entry_point\b|numba\.misc")


def test_no_physics_module_is_too_long_to_read():
    counts = {
        p.relative_to(PHYSICS).as_posix(): len(p.read_text().splitlines()) for p in PHYSICS.rglob("*.py")
    }
    assert {k: v for k, v in counts.items() if v > MAX_LINES} == {}
    assert counts["simulation.py"] <= MAX_SIMULATION_LINES


def test_numba_private_api_is_used_in_jitcache_only():
    users = sorted(
        p.relative_to(PHYSICS).as_posix()
        for p in PHYSICS.rglob("*.py")
        if PRIVATE_NUMBA.search(p.read_text())
    )
    assert users == ["jitcache.py"]


def test_every_name_has_one_home():
    # a name imported only to be imported from here again would need a noqa for the unused import (ruff F401)
    reexporting = sorted(
        p.relative_to(PHYSICS).as_posix() for p in PHYSICS.rglob("*.py") if "noqa: F401" in p.read_text()
    )
    assert reexporting == []
