"""Fixtures shared by every test package."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import pytest

from vessel_gym.physics.shipfile import SHIP_DIR

# Tests never open windows: pygame's dummy drivers (also on a desktop, and where there is no display at all).
os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("SDL_AUDIODRIVER", "dummy")


@pytest.fixture
def ship_file(tmp_path: Path) -> Callable[..., Path]:
    """Write a variant of a built-in ship file: ``ship_file("kvlcc2", edit)`` -> path of the new file.

    ``edit`` takes the built-in's TOML text and returns the text to write (default: unchanged).
    """

    def make(name: str, edit: Callable[[str], str] = lambda text: text, filename: str | None = None) -> Path:
        text = (SHIP_DIR / f"{name}.toml").read_text()
        path = tmp_path / (filename or f"{name}_variant.toml")
        path.write_text(edit(text))
        return path

    return make
