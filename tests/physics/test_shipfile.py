"""Ship files: every built-in loads and runs; every kind of mistake is a one-line ShipFileError naming the
file and the key."""

from __future__ import annotations

import re

import numpy as np
import pytest

from vessel_gym.physics import params
from vessel_gym.physics.shipchecks import ShipFileError
from vessel_gym.physics.shipfile import builtin_ships, load_ship
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.vessel import pack

BUILTINS = ("mariner", "kvlcc2", "kvlcc2_l7", "dtc")


def test_the_documented_ships_are_built_in():
    assert set(BUILTINS) <= set(builtin_ships())


@pytest.mark.parametrize("name", builtin_ships())
def test_builtin_ship_loads_packs_and_holds_its_test_speed(name):
    """Each built-in parses strictly, names its source, packs into a finite parameter row, and reaches a
    steady approach at its IMO test speed."""
    ship = load_ship(name)
    assert ship.name == name
    assert len(ship.source.citation) > 20
    P = pack(ship)
    assert P.shape == (params.NP,) and np.isfinite(P).all()
    sim = Simulation(ship)
    sim.reset()
    assert sim.u[0] == pytest.approx(ship.test_speed_m_s)
    assert sim.rev[0] > 0.0 or ship.propeller is None


def test_a_path_loads_like_the_name(ship_file):
    assert load_ship(ship_file("kvlcc2")).hull == load_ship("kvlcc2").hull


def test_unknown_ship_name_lists_the_built_ins():
    with pytest.raises(ShipFileError, match="unknown ship.*kvlcc2"):
        load_ship("titanic")


def _add_after(anchor: str, line: str):
    def edit(text: str) -> str:
        assert anchor in text
        return text.replace(anchor, f"{anchor}\n{line}", 1)

    return edit


def _replace(old: str, new: str):
    def edit(text: str) -> str:
        assert old in text, old
        return text.replace(old, new, 1)

    return edit


def _drop_table(header: str):
    """Remove a [table] and its keys (up to the next header)."""

    def edit(text: str) -> str:
        out = re.sub(rf"^\[{re.escape(header)}\]\n(?:(?!\[).*\n)*", "", text, count=1, flags=re.M)
        assert out != text
        return out

    return edit


# (case, built-in, edit, key the message must name, phrase it must contain)
BAD_FILES = [
    ("unknown key in a table", "kvlcc2", _add_after("m_x = 0.022", "m_z = 0.1"), "m_z", "unknown key"),
    ("misspelt key", "kvlcc2", _replace("A_F_m2 = 1200.0", "A_FW_m2 = 1200.0"), "A_FW_m2", "unknown key"),
    ("unknown table", "kvlcc2", _replace("[wave_drift]", "[wave_drfit]"), "wave_drfit", "unknown key"),
    (
        "unknown top-level key",
        "mariner",
        _add_after('name = "mariner"', 'colour = "grey"'),
        "colour",
        "unknown key",
    ),
    ("missing key", "kvlcc2", _replace("L_m = 320.0\n", ""), "L_m", "missing"),
    ("missing hull coefficient", "kvlcc2", _replace("N_rrr = -0.013\n", ""), "N_rrr", "missing"),
    ("missing table", "dtc", _drop_table("steering_gear"), "steering_gear", "missing"),
    ("NaN", "kvlcc2", _replace("B_m = 58.0", "B_m = nan"), "B_m", "finite"),
    ("infinity", "kvlcc2", _replace("T_m = 20.8", "T_m = inf"), "T_m", "finite"),
    ("NaN derivative", "mariner", _replace("Y_vvv = -8.078000e-02", "Y_vvv = nan"), "Y_vvv", "finite"),
    ("out of range", "kvlcc2", _replace("m_x = 0.022", "m_x = 5.0"), "m_x", "outside the allowed range"),
    (
        "negative diameter",
        "kvlcc2",
        _replace("D_m = 9.86", "D_m = -9.86"),
        "D_m",
        "outside the allowed range",
    ),
    (
        "implausible derivative",
        "mariner",
        _replace("N_vvr = -5.483000e-02", "N_vvr = -54.83"),
        "N_vvr",
        "not a plausible",
    ),
    (
        "bad derivative name",
        "mariner",
        _add_after("Y_vvv = -8.078000e-02", "Y_vq = 0.01"),
        "Y_vq",
        "not a derivative name",
    ),
    (
        "derivative power above 4",
        "mariner",
        _add_after("Y_vvv = -8.078000e-02", "Y_vvvvv = 0.01"),
        "Y_vvvvv",
        "powers above 4",
    ),
    ("string for a number", "kvlcc2", _replace("L_m = 320.0", 'L_m = "320"'), "L_m", "expected a number"),
    (
        "number for a table",
        "kvlcc2",
        lambda t: _drop_table("steering_gear")(t).replace(
            'name = "kvlcc2"', 'name = "kvlcc2"\nsteering_gear = 35.0'
        ),
        "steering_gear",
        "expected a table",
    ),
    (
        "array of tables for a table",
        "mariner",
        _replace("[hull.derivatives]", "[[hull.derivatives]]"),
        "derivatives",
        "expected a table",
    ),
    (
        "number for a list",
        "kvlcc2",
        _replace("torque_map_fuel = [0.0, 0.2, 0.4, 0.6, 0.8, 1.0]", "torque_map_fuel = 0.5"),
        "torque_map_fuel",
        "expected a list",
    ),
    (
        "short torque map row",
        "kvlcc2",
        _replace("[-0.060, 0.164, 0.388, 0.550, 0.550, 0.550],", "[-0.060, 0.164, 0.388, 0.550, 0.550],"),
        "torque_map",
        "rows",
    ),
    (
        "unknown hull model",
        "kvlcc2",
        _replace('model = "mmg"\nm_x', 'model = "mgm"\nm_x'),
        "model",
        "not one of",
    ),
    ("TOML syntax", "kvlcc2", _replace("R_0 = 0.022", "R_0 = 0.022 0.3"), "", "TOML syntax error"),
]


@pytest.mark.parametrize(("case", "name", "edit", "key", "phrase"), BAD_FILES, ids=[c[0] for c in BAD_FILES])
def test_bad_ship_file_names_file_and_key(ship_file, case, name, edit, key, phrase):
    """A user who mistypes anything gets ShipFileError with one line that names the file and the key."""
    path = ship_file(name, edit, filename="my_ship.toml")
    with pytest.raises(ShipFileError) as info:
        load_ship(path)
    msg = str(info.value)
    assert "\n" not in msg, case
    assert msg.startswith(str(path)), case
    assert key in msg, case
    assert phrase in msg, case
