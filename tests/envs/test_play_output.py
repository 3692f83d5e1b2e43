"""`play --out DIR` never replaces an earlier debrief plot unless --force is given."""

from __future__ import annotations

from pathlib import Path

import pytest

from vessel_gym.cli import main
from vessel_gym.outputs import OutputExistsError
from vessel_gym.ui.play import play


def test_play_refuses_to_replace_a_debrief(tmp_path, capsys):
    pytest.importorskip("pygame")
    earlier = tmp_path / "debrief_harbour.png"
    earlier.write_bytes(b"an earlier debrief")
    with pytest.raises(OutputExistsError, match="--force"):
        play("harbour", seed=1, realtime=False, max_steps=2, out_dir=tmp_path)
    assert earlier.read_bytes() == b"an earlier debrief"
    # the command line says so in one line, exit 2, before a window opens
    code = main(["play", "harbour", "--max-steps", "2", "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "debrief_harbour.png" in err
    assert earlier.read_bytes() == b"an earlier debrief"
    d = play("harbour", seed=1, realtime=False, max_steps=2, out_dir=tmp_path, force=True)
    assert d.track_png == str(earlier) and earlier.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_scenario_name_cannot_move_the_debrief_out_of_out_dir(tmp_path):
    """A scenario file's ``name`` becomes one path segment of the debrief's file name, never a path."""
    pytest.importorskip("pygame")
    from importlib.resources import files

    text = (files("vessel_gym.scenarios") / "harbour.toml").read_text()
    hostile = tmp_path / "hostile.toml"
    hostile.write_text(text.replace('name = "harbour"', 'name = "../../../../ESCAPED"', 1))
    out = tmp_path / "a" / "b"
    d = play(str(hostile), seed=1, realtime=False, max_steps=2, out_dir=out)
    written = Path(d.track_png)
    assert written.parent == out and written.is_file()
    assert [p.parent for p in tmp_path.rglob("*ESCAPED*.png")] == [out]
