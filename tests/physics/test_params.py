"""The parameter records of the compiled model (physics/params.py): one per component kind, fields with units,
laid out without overlap, written and read by name."""

from __future__ import annotations

import numpy as np
import pytest

from vessel_gym.physics import params
from vessel_gym.physics.components.registry import BUILTINS
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
    params.put(P, params.PROPELLER, D_P=9.86)
    assert params.get(P, params.PROPELLER)["D_P"] == P[params.PROPELLER.D_P] == 9.86


@pytest.mark.parametrize("name", builtin_ships())
def test_records_hold_the_ship_file_values_by_name(name):
    ship = load_ship(name)
    P = pack(ship)
    body = params.get(P, params.BODY)
    assert (body["L"], body["B"], body["T"], body["m"]) == (
        ship.particulars.L_m,
        ship.particulars.B_m,
        ship.particulars.T_m,
        ship.mass_kg,
    )
    if ship.propeller is not None:
        prop = params.get(P, params.PROPELLER)
        assert (prop["D_P"], prop["k_0"], prop["w_P0"], prop["t_P"]) == (
            ship.propeller.D_m,
            ship.propeller.k_0,
            ship.propeller.w_P0,
            ship.propeller.t_P,
        )
    sg = params.get(P, params.STEERING_GEAR)
    assert sg["delta_max"] == pytest.approx(np.radians(ship.steering_gear.max_angle_deg), rel=1e-15)
