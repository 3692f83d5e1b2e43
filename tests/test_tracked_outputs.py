"""No documented command rewrites a file of the repository unless the user names it: the README's output
folders are ignored by git, and the tools that can rewrite committed files (the results table, the shipped
agents, the README's pictures) write elsewhere by default."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(
    shutil.which("git") is None or not (ROOT / ".git").exists(), reason="needs a git checkout"
)


def _ignored(path: str) -> bool:
    return subprocess.run(["git", "check-ignore", "-q", path], cwd=ROOT).returncode == 0


def _tracked(path: str) -> bool:
    return bool(
        subprocess.run(["git", "ls-files", path], cwd=ROOT, capture_output=True, text=True).stdout.strip()
    )


def test_the_readme_output_folders_are_ignored():
    readme = (ROOT / "README.md").read_text()
    folders = set(re.findall(r"--(?:plot|report|out) ([\w./-]+)", readme))
    assert {"imo_plots", "imo_report", "wigley_study"} <= folders
    for folder in folders:
        assert _ignored(f"{folder}/some_output.png"), (
            f"{folder}/ (written by a README command) is not ignored"
        )


def test_results_writes_the_committed_page_and_agents_only_when_named():
    pytest.importorskip("yaml")
    from agents import results

    parser = results.build_parser()
    args = parser.parse_args([])
    assert args.doc is None and args.ship_dir is None
    help_text = parser.format_help()
    assert "--doc FILE" in help_text and "<out>/results.md" in help_text and "docs/results.md" in help_text
    assert _ignored(f"{args.out}/results.md") and _tracked("docs/results.md")


def test_make_images_writes_to_an_ignored_folder_unless_named(monkeypatch, tmp_path):
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_images", ROOT / "docs" / "img" / "make_images.py")
    make_images = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(make_images)
    made = []
    monkeypatch.setattr(make_images, "chart", lambda out: made.append(out) or out / "chart.png")
    monkeypatch.setattr(make_images, "imo_plot", lambda out: made.append(out) or out / "imo.png")
    monkeypatch.chdir(tmp_path)
    assert make_images.main([]) == 0
    assert made == [Path("out/img")] * 2 and _ignored("out/img/chart_harbour.png")
    assert _tracked("docs/img/chart_harbour.png")
