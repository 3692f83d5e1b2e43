"""The link and the protocol are split by job; the names their users import from them are the same
objects (one home per rule)."""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

NET = Path(__file__).resolve().parents[2] / "vessel_gym" / "net"
# the names the link's users import from it, defined in one of these modules
LINK_NAMES = {
    "access": ("Address",),
    "helm_owner": ("HelmChange", "HelmState"),
    "link_config": ("LinkConfig",),
}
SPLIT = ("link", "access", "helm_owner", "link_config", "nmea_feed", "protocol", "wire", "protocol_v2")


@pytest.mark.parametrize("name", SPLIT)
def test_each_module_is_short_and_says_its_job(name):
    text = (NET / f"{name}.py").read_text()
    assert len(text.splitlines()) <= 600
    assert ast.get_docstring(ast.parse(text)), f"vessel_gym/net/{name}.py has no module docstring"


def test_link_reexports_the_same_objects():
    link = importlib.import_module("vessel_gym.net.link")
    for home_name, names in LINK_NAMES.items():
        home = importlib.import_module(f"vessel_gym.net.{home_name}")
        for attr in names:
            assert getattr(link, attr) is getattr(home, attr), attr


@pytest.mark.parametrize("home_name", ["wire", "protocol_v2"])
def test_protocol_reexports_every_public_name_of_wire_and_v2(home_name):
    protocol = importlib.import_module("vessel_gym.net.protocol")
    home = importlib.import_module(f"vessel_gym.net.{home_name}")
    for attr, value in vars(home).items():
        if attr.startswith("_") or isinstance(value, type(importlib)):
            continue
        if callable(value) and getattr(value, "__module__", None) != home.__name__:
            continue  # a class or function imported from elsewhere
        assert getattr(protocol, attr, None) is value, (
            f"vessel_gym.net.protocol.{attr} is not {home_name}.{attr}"
        )
