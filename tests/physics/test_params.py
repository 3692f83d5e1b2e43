"""The parameter records of the compiled model (physics/params.py): one per component kind, fields with units,
laid out without overlap, written and read by name; the number keys of a ship-file table are fields of its
record without a second declaration (their unit and doc are the table's), copied by name."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import pytest

from vessel_gym.physics import params, sections
from vessel_gym.physics.components.registry import BUILTINS
from vessel_gym.physics.schema import param
from vessel_gym.physics.shipfile import builtin_ships, load_ship
from vessel_gym.physics.vessel import pack


def test_every_field_has_a_unit_and_the_records_tile_the_row():
    seen = np.zeros(params.NP, dtype=int)
    for rec in params.RECORDS.values():
        assert rec.doc
        for f in rec.fields:
            assert f.unit, f"{rec.kind}.{f.name} has no unit"
            i = getattr(rec.at, f.name)
            seen[i : i + f.size] += 1
    assert (seen == 1).all()  # every float of the row belongs to exactly one field
    assert len(params.PARAM_NAMES) == params.NP


def test_every_builtin_component_names_its_record():
    for spec in BUILTINS:
        assert spec.record == "" or spec.record in params.RECORDS, spec.name
    assert {s.record for s in BUILTINS} - {""} >= {"mmg_hull", "propeller", "engine", "rudder", "windage"}


def test_put_refuses_an_unknown_field_and_a_long_table():
    P = np.zeros(params.NP)
    with pytest.raises(ValueError, match="record 'propeller' has no field 'k_9'"):
        params.put(P, params.PROPELLER, k_9=1.0)
    with pytest.raises(ValueError, match="engine.map_speed: 9 values for a table of 8"):
        params.put(P, params.ENGINE, map_speed=np.arange(9.0))
    params.put(P, params.PROPELLER, D_m=9.86)
    assert params.get(P, params.PROPELLER)["D_m"] == P[params.PROPELLER.D_m] == 9.86


@pytest.mark.parametrize("name", builtin_ships())
def test_records_hold_the_ship_file_values_by_name(name):
    ship = load_ship(name)
    P = pack(ship)
    body = params.get(P, params.BODY)
    assert (body["L_m"], body["B_m"], body["T_m"], body["m"]) == (
        ship.particulars.L_m,
        ship.particulars.B_m,
        ship.particulars.T_m,
        ship.mass_kg,
    )
    if ship.propeller is not None:
        prop = params.get(P, params.PROPELLER)
        assert (prop["D_m"], prop["k_0"], prop["w_P0"], prop["t_P"]) == (
            ship.propeller.D_m,
            ship.propeller.k_0,
            ship.propeller.w_P0,
            ship.propeller.t_P,
        )
    sg = params.get(P, params.STEERING_GEAR)
    assert sg["delta_max"] == pytest.approx(np.radians(ship.steering_gear.max_angle_deg), rel=1e-15)


def _number_keys(section: type) -> list[dataclasses.Field]:
    return [f for f in dataclasses.fields(section) if f.type in ("float", float)]


def test_every_number_key_of_a_table_is_a_field_of_its_record_declared_once():
    """The record of a component kind built from a ship-file table holds every number key of the table under the
    key's name, with the unit and doc of the key's ``param`` (one declaration, in sections.py); no field declared
    in params.py repeats a number key."""
    built = {rec.section for rec in params.RECORDS.values() if rec.section is not None}
    assert built >= {
        sections.Particulars,
        sections.MMGHull,
        sections.AbkowitzHull,
        sections.Propeller,
        sections.Engine,
        sections.Transmission,
        sections.Rudder,
        sections.SteeringGear,
        sections.Windage,
        sections.WaveDrift,
        sections.LargeDrift,
        sections.Roll,
    }
    for rec in params.RECORDS.values():
        if rec.section is None:
            assert not any(f.key for f in rec.fields), rec.kind
            continue
        keys = _number_keys(rec.section)
        fields = {f.name: f for f in rec.fields}
        assert keys, rec.kind
        for k in keys:
            f = fields[k.name]
            assert f.key and (f.unit, f.doc, f.size) == (k.metadata["unit"], k.metadata["doc"], 1), (rec.kind, k.name)
        # a derived field is a code of a string key (``four_quadrant``), a conversion or a flag: never a number
        # key declared a second time
        for f in rec.fields:
            if not f.key:
                assert f.name not in {k.name for k in keys}, f"{rec.kind}.{f.name} declared again beside its key"
    # a registry entry's parameter dataclass is the table its record is built from
    for spec in BUILTINS:
        if spec.record and params.RECORDS[spec.record].section is not None and spec.name != "derivative_rudder":
            assert params.RECORDS[spec.record].section is spec.params, spec.name


@pytest.mark.parametrize("name", builtin_ships())
def test_pack_copies_every_number_key_of_every_table_by_name(name):
    ship = load_ship(name)
    P = pack(ship)
    tables = [getattr(ship, f.name) for f in dataclasses.fields(ship)]
    copied = 0
    for rec in params.RECORDS.values():
        for table in (t for t in tables if rec.section is not None and isinstance(t, rec.section)):
            for f in rec.fields:
                if f.key:
                    assert P[getattr(rec.at, f.name)] == getattr(table, f.name), (name, rec.kind, f.name)
                    copied += 1
    assert copied >= len(_number_keys(sections.Particulars)) + len(_number_keys(sections.Rudder))


def test_a_new_key_in_a_table_is_a_field_of_its_record(monkeypatch):
    """Adding a parameter: a key written once in a table's dataclass (here a table declared in this module
    alone) is a field of the record with its unit and doc, and is copied into the row by name; a string key
    (a model choice) becomes a field only where a code for it is declared."""
    monkeypatch.setattr(params, "RECORDS", dict(params.RECORDS))
    monkeypatch.setattr(params, "_row", list(params._row))

    @dataclass(frozen=True, kw_only=True)
    class TunnelThruster:
        model: str = param("fixed_pitch", choices=("fixed_pitch",), doc="thruster type")
        max_thrust_N: float = param(unit="N", lo=0.0, hi=1e7, doc="bollard thrust at full order")
        x_m: float = param(0.0, unit="m", lo=-500.0, hi=500.0, doc="position forward of midship")

    at = params.record(
        "tunnel_thruster", "a tunnel thruster", params.Field("on", "-", "1 with the table"), section=TunnelThruster
    )
    assert at._fields == ("max_thrust_N", "x_m", "on")
    rec = params.RECORDS["tunnel_thruster"]
    assert [(f.name, f.unit, f.doc) for f in rec.fields if f.key] == [
        ("max_thrust_N", "N", "bollard thrust at full order"),
        ("x_m", "m", "position forward of midship"),
    ]
    assert params._row[at.max_thrust_N] == "tunnel_thruster.max_thrust_N"
    P = np.zeros(len(params._row))
    params.put_keys(P, at, TunnelThruster(max_thrust_N=1.5e5, x_m=140.0))
    params.put(P, at, on=1.0)
    assert params.get(P, at) == {"max_thrust_N": 1.5e5, "x_m": 140.0, "on": 1.0}
    with pytest.raises(ValueError, match="record 'tunnel_thruster_2': field 'x_m' declared twice"):
        params.record("tunnel_thruster_2", "again", params.Field("x_m", "m", "a second x_m"), section=TunnelThruster)


def test_put_keys_refuses_another_table():
    P = np.zeros(params.NP)
    with pytest.raises(TypeError, match="record 'propeller' is built from Propeller, not Rudder"):
        params.put_keys(P, params.PROPELLER, load_ship("kvlcc2").rudder)
    with pytest.raises(TypeError, match="record 'hull' is built from no ship-file table"):
        params.put_keys(P, params.HULL, load_ship("kvlcc2").hull)
