"""The ship-file reference documents every key the loader accepts (no silently undocumented keys)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from vessel_gym.physics import shipfile as sf

DOC = Path(__file__).resolve().parents[2] / "docs" / "ship-file.md"


def test_every_ship_file_key_is_documented():
    text = DOC.read_text()
    for cls in (
        sf.Source,
        sf.Particulars,
        sf.AbkowitzHull,
        sf.MMGHull,
        sf.Propeller,
        sf.Rudder,
        sf.SteeringGear,
        sf.Engine,
        sf.Transmission,
        sf.Windage,
        sf.WaveDrift,
    ):
        for f in dataclasses.fields(cls):
            assert f"`{f.name}" in text, f"{cls.__name__}.{f.name} missing from docs/ship-file.md"
