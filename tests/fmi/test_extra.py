"""Without the 'fmi' extra the FMI commands say which extra to install, in one line, exit 2."""

from __future__ import annotations

import sys

from vessel_gym.cli import main


def test_fmu_command_without_the_extra_names_it(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(sys.modules, "pythonfmu", None)  # import pythonfmu raises ImportError
    assert main(["fmu", "kvlcc2", "--out", str(tmp_path / "k.fmu")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "vessel-gym[fmi]" in err and "pythonfmu" in err
    assert not list(tmp_path.iterdir())
