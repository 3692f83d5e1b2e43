"""Code named by a ship file runs only with the user's consent, and never escapes the one-line errors
(docs/components.md, "Code from ship files needs your consent")."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from vessel_gym.cli import main
from vessel_gym.physics import components
from vessel_gym.physics.shipchecks import ShipFileError
from vessel_gym.physics.shipfile import load_ship

ROOT = Path(__file__).resolve().parents[2]  # this checkout, whichever vessel-gym is installed
SHIPS = ROOT / "vessel_gym" / "physics" / "data" / "ships"

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
        env={**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), str(ROOT)])},
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


RAW = """import os
print("printed at import")
os.write(1, b"written to fd 1 at import\\n")
os.write(2, b"written to fd 2 at import\\n")
{last}
"""


@pytest.mark.parametrize(
    "last, error",
    [
        ("raise KeyboardInterrupt", "importing 'raw_hull' failed (KeyboardInterrupt"),
        ("", "module 'raw_hull' has no 'Hull'"),  # imported, but names no component
    ],
)
def test_output_to_the_file_descriptors_and_an_interrupt_stay_inside_the_error(tmp_path, last, error):
    """A module that writes to fd 1 and 2 directly (os.write, a C library, a subprocess) or raises
    KeyboardInterrupt at import: still one line and exit 2, in a real process."""
    (tmp_path / "raw_hull.py").write_text(RAW.format(last=last))
    ship = _ship_naming(tmp_path, "raw_hull:Hull")
    proc = subprocess.run(
        [sys.executable, "-m", "vessel_gym.cli", "ships", "check", str(ship), "--allow-code"],
        capture_output=True, text=True, cwd=tmp_path, timeout=120,
        env={**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), str(ROOT)])},
    )  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert proc.stdout == "" and "at import" not in proc.stderr
    assert proc.stderr.count("\n") == 1 and error in proc.stderr, proc.stderr


def test_a_component_modules_output_is_shown_once_it_loads(tmp_path, monkeypatch, capfd):
    """A module that gives its component: what it wrote at import, to sys.stdout or fd 1, is shown on stderr."""
    (tmp_path / "raw_ok.py").write_text(
        RAW.format(last="from vessel_gym.physics.components.gearbox import ReversingGearbox as Gear")
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    components.allow_code()
    try:
        components.import_model("raw_ok:Gear", "test")
    finally:
        components.allow_code(False)
        sys.modules.pop("raw_ok", None)
    out, err = capfd.readouterr()
    assert out == ""
    assert "printed at import" in err and "written to fd 1 at import" in err and "fd 2" in err
