"""Code named by a ship file runs only with the user's consent, and never escapes the one-line errors
(docs/components.md, "Code from ship files needs your consent")."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from vessel_gym.cli import main
from vessel_gym.physics import components
from vessel_gym.physics.shipchecks import ShipFileError
from vessel_gym.physics.shipfile import load_ship

SHIPS = Path(__file__).resolve().parents[2] / "vessel_gym" / "physics" / "data" / "ships"

LOUD = """import sys
print("the module ran at import")
sys.exit(3)
"""


@pytest.fixture
def no_consent(monkeypatch):
    monkeypatch.delenv(components.ALLOW_CODE_ENV, raising=False)
    monkeypatch.setattr(components, "_code_allowed", False)


def _ship_naming(tmp_path: Path, model: str) -> Path:
    text = (SHIPS / "kvlcc2_l7.toml").read_text()
    start = text.index("[hull]")
    end = text.index("\n[", start + 1)
    path = tmp_path / "coded.toml"
    path.write_text(text[:start] + f'[hull]\nmodel = "{model}"\n' + text[end:])
    return path


def test_a_foreign_module_is_not_imported_without_consent(tmp_path, no_consent, monkeypatch, capsys):
    (tmp_path / "loud_hull.py").write_text(LOUD)
    monkeypatch.syspath_prepend(str(tmp_path))
    ship = _ship_naming(tmp_path, "loud_hull:Hull")
    with pytest.raises(
        ShipFileError, match=r"coded.toml \[hull\] model: 'loud_hull:Hull' would run the code"
    ):
        load_ship(str(ship))
    assert "loud_hull" not in sys.modules
    assert main(["imo", str(ship)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and "--allow-code" in err


def test_the_attack_module_stays_inside_the_error_handling(tmp_path, no_consent, capsys):
    """unittest.__main__ runs unittest's main at import: it prints and raises SystemExit."""
    ship = _ship_naming(tmp_path, "unittest.__main__:Foo")
    assert main(["imo", str(ship)]) == 2  # refused: no consent
    assert "would run the code of module 'unittest.__main__'" in capsys.readouterr().err
    assert main(["imo", str(ship), "--allow-code"]) == 2  # consent given: its exit is one line, exit 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.count("\n") == 1 and "importing 'unittest.__main__' failed (SystemExit" in err
    sys.modules.pop("unittest.__main__", None)


def test_a_module_that_exits_at_import_in_a_real_process(tmp_path):
    (tmp_path / "loud_hull.py").write_text(LOUD)
    ship = _ship_naming(tmp_path, "loud_hull:Hull")
    proc = subprocess.run(
        [sys.executable, "-m", "vessel_gym.cli", "ships", "check", str(ship), "--allow-code"],
        capture_output=True, text=True, cwd=tmp_path, timeout=120,
        env={**__import__("os").environ, "PYTHONPATH": str(tmp_path)},
    )  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert proc.stdout == "" and "the module ran" not in proc.stderr
    assert proc.stderr.count("\n") == 1 and "SystemExit: 3" in proc.stderr


def test_own_components_need_no_consent(no_consent):
    """supply.toml names vessel-gym's reversing gearbox: always allowed."""
    ship = load_ship("supply")
    assert any("gearbox" in c.model for c in ship.components)


def test_consent_by_environment(tmp_path, monkeypatch):
    monkeypatch.setattr(components, "_code_allowed", False)
    monkeypatch.setenv(components.ALLOW_CODE_ENV, "1")
    assert components.code_allowed()
    monkeypatch.setenv(components.ALLOW_CODE_ENV, "0")
    assert not components.code_allowed()
