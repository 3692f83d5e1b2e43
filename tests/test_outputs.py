"""Output files: --force replaces the named file itself, never what a symbolic link points at."""

from __future__ import annotations

import os

import pytest

from vessel_gym.outputs import OutputExistsError, check_free, safe_name, write_new


def test_force_refuses_a_symlink_and_keeps_its_target(tmp_path):
    precious = tmp_path / "precious.txt"
    precious.write_text("keep me")
    link = tmp_path / "p.png"
    link.symlink_to(precious)
    for force in (False, True):
        with pytest.raises(OutputExistsError, match="symbolic link"):
            check_free([link], force, "--plot")
        with pytest.raises(OutputExistsError, match="symbolic link"):
            write_new(link, b"plot", force)
    assert precious.read_text() == "keep me" and link.is_symlink()


def test_a_dangling_symlink_is_not_followed_either(tmp_path):
    link = tmp_path / "p.png"
    link.symlink_to(tmp_path / "elsewhere.png")
    with pytest.raises(OutputExistsError, match="symbolic link"):
        write_new(link, b"plot", True)
    assert not (tmp_path / "elsewhere.png").exists()


def test_force_replaces_a_regular_file_and_new_files_are_created(tmp_path):
    f = tmp_path / "plot.png"
    write_new(f, b"one", False)
    with pytest.raises(OutputExistsError, match="--force"):
        write_new(f, b"two", False)
    write_new(f, b"three", True)
    assert f.read_bytes() == b"three" and not f.is_symlink()


@pytest.mark.parametrize(
    "name",
    ["../../../../ESCAPED", "/etc/passwd", "a/b", "..", "", "ok-name_1.2", "x" * 300, "é" * 200, "a\0b"],
)
def test_safe_name_is_one_path_segment(name, tmp_path):
    s = safe_name(name)
    assert s and os.sep not in s and s not in (".", "..") and not s.startswith(".")
    # a file of that name (with the longest prefix and suffix the commands add) can be made in the folder
    assert write_new(tmp_path / f"debrief_{s}_initial_turning.png", b"x", False).parent == tmp_path


def test_the_cli_refuses_a_plot_symlink_with_force(tmp_path, capsys):
    from vessel_gym.cli import main

    precious = tmp_path / "precious.txt"
    precious.write_text("keep me")
    (tmp_path / "p.png").symlink_to(precious)
    code = main(["manoeuvre", "zigzag", "kvlcc2", "--plot", str(tmp_path / "p.png"), "--force"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "symbolic link" in err[0]
    assert precious.read_text() == "keep me"
