"""The ship-file reference documents every key the loader accepts (no silently undocumented keys)."""

from __future__ import annotations

import dataclasses
import re
import sys
from pathlib import Path

import numpy as np

from vessel_gym.physics import components, sections
from vessel_gym.physics import shipfile as sf

DOC = Path(__file__).resolve().parents[2] / "docs" / "ship-file.md"


def test_every_ship_file_key_is_documented():
    text = DOC.read_text()
    for cls in (
        sf.Source,
        sections.Particulars,
        sections.AbkowitzHull,
        sections.MMGHull,
        sections.Propeller,
        sections.Rudder,
        sections.SteeringGear,
        sections.Engine,
        sections.Transmission,
        sections.Windage,
        sections.WaveDrift,
        sections.LargeDrift,
        sections.Roll,
    ):
        for f in dataclasses.fields(cls):
            assert f"`{f.name}" in text, f"{cls.__name__}.{f.name} missing from docs/ship-file.md"


COMPONENTS_DOC = DOC.parent / "components.md"
_FENCE = re.compile(r"(?:<!-- (?P<marker>[^>]*) -->\n)?```(?P<lang>\w+)\n(?P<body>.*?)\n```", re.S)
_HEADER = re.compile(r"^\[\[?([A-Za-z_]+)")


def _ship_file(block: str, builtin: str) -> str:
    """The built-in ship file with its tables named in ``block`` (and their sub-tables) replaced by ``block``."""
    ours = {m.group(1) for m in map(_HEADER.match, block.splitlines()) if m}
    kept, keep = [], True
    for line in sf.resolve_ship_path(builtin).read_text().splitlines():
        m = _HEADER.match(line)
        if m:
            keep = m.group(1) not in ours
        if keep:
            kept.append(line)
    return "\n".join(kept) + "\n\n" + block + "\n"


def test_components_doc_examples_run(tmp_path, monkeypatch):
    """Every code block of docs/components.md runs: modules and ship files it shows are written to a
    directory, the other Python blocks run there in order, in one namespace."""
    text = COMPONENTS_DOC.read_text()
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(components, "_code_allowed", False)  # the page calls allow_code(); undone after
    namespace: dict = {}
    modules = []
    ran = 0
    for m in _FENCE.finditer(text):
        marker, lang, body = m.group("marker") or "", m.group("lang"), m.group("body")
        if marker.startswith("file: "):
            name = marker.removeprefix("file: ").strip()
            (tmp_path / name).write_text(body + "\n")
            modules.append(Path(name).stem)
        elif marker.startswith("ship file: "):
            name, _, builtin = marker.removeprefix("ship file: ").partition(", other tables from ")
            (tmp_path / name.strip()).write_text(_ship_file(body, builtin.strip()))
        elif lang == "python":
            exec(compile(body, f"{COMPONENTS_DOC.name} block at offset {m.start()}", "exec"), namespace)
            ran += 1
    for name in modules:
        sys.modules.pop(name, None)
    assert ran >= 7 and len(modules) == 5
    assert np.all(np.isfinite(namespace["sim"].state))  # the last example ran its turn
