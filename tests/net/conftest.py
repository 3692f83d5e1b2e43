"""Fixtures for the UDP link tests."""

from __future__ import annotations

import pytest

from .helpers import Peer


@pytest.fixture
def peers():
    made: list[Peer] = []

    def make() -> Peer:
        made.append(Peer())
        return made[-1]

    yield make
    for p in made:
        p.close()
