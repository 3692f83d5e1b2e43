"""The CI script's lanes: lint and types, then the fast tests stopping at their first failure, then the slow ones;
pytest's "no tests selected" (exit code 5) is not a failure, any other failure is."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = (ROOT / ".ci" / "run").read_text()


def test_fast_lane_first_and_stops_at_the_first_failure_then_the_slow_lane():
    lanes = re.findall(r"^lane (.*)$", SCRIPT, re.M)
    assert len(lanes) == 2, lanes
    fast, slow = lanes
    assert '-m "not slow"' in fast and " -x" in fast
    assert "-m slow" in slow and "-x" not in slow and "--durations" in slow
    assert SCRIPT.index("ruff check") < SCRIPT.index("python -m mypy") < SCRIPT.index("lane -q")


def test_mypy_is_in_the_dev_extra_and_checks_the_public_api_and_the_task_layer():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert any(r.startswith("mypy") for r in project["project"]["optional-dependencies"]["dev"])
    mypy = project["tool"]["mypy"]
    assert {"vessel_gym/__init__.py", "vessel_gym/envs"} <= set(mypy["files"])
    assert mypy["ignore_missing_imports"] is True
    overrides = mypy.get("overrides", [])
    assert not any(o.get("ignore_errors") for o in overrides) and not mypy.get("ignore_errors")


def _lane(*args: str) -> int:
    function = re.search(r"^lane\(\) \{.*?^\}", SCRIPT, re.M | re.S).group(0)
    script = f"set -euo pipefail\n{function}\nlane {' '.join(args)}\n"
    return subprocess.run(["bash", "-c", script], cwd=ROOT, capture_output=True, text=True).returncode


def test_lane_passes_when_no_test_is_selected_and_fails_on_a_failure(tmp_path):
    (tmp_path / "test_fails.py").write_text("def test_fails():\n    assert 1 == 2\n")
    (tmp_path / "test_none.py").write_text("def helper():\n    pass\n")
    assert _lane("-q", "-p", "no:cacheprovider", str(tmp_path / "test_none.py")) == 0
    assert _lane("-q", "-p", "no:cacheprovider", str(tmp_path / "test_fails.py")) == 1


def test_the_cpu_only_torch_route_is_documented_and_used():
    index = "https://download.pytorch.org/whl/cpu"
    assert index in SCRIPT and "constraints.txt" in SCRIPT
    agents_doc = (ROOT / "docs" / "agents.md").read_text()
    assert f"pip install torch==2.13.0 --index-url {index}" in agents_doc
    assert "CPU build)" not in agents_doc  # the pin alone does not choose the build
    assert index in (ROOT / "README.md").read_text()


def test_readme_says_what_the_ci_command_costs_and_gives_the_fast_lane():
    readme = (ROOT / "README.md").read_text()
    (extras,) = re.findall(r'pip install -e "\.\[([\w,]+)\]" && python -m pytest -m "not slow"', readme)
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    assert set(extras.split(",")) <= set(declared) and "dev" in extras.split(",")
    ci = readme[readme.index("bash .ci/run") :]
    for fact in ("virtual environment", "OpenFOAM", "gpsd", "Chromium", "minutes", "GB"):
        assert fact in ci[:1200], fact
    installed = re.search(r'-e "\.\[([\w,]+)\]"', SCRIPT).group(1).split(",")
    assert set(installed) <= set(declared)
