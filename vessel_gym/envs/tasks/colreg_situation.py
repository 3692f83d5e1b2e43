"""A reader of traffic situations in the open maritime-schema "Traffic Situation" JSON format (DNV's
ship-traffic-generator writes its baseline situations in it; dnv-opensource.github.io/maritime-schema):
``reset(options={"scenario": "file:situation.json"})`` runs such a file as a CollisionAvoidance encounter.

Read: the own ship's ``initial`` (``position`` lat/lon in deg, ``sog`` in kn, ``heading`` in deg; where a
file of schema 0.2 leaves ``position`` and ``sog`` out of it, the first waypoint's ``position`` and
``leg.sog``) and its last ``waypoints`` entry (the goal; the route is the straight leg from the start to it), and every target ship's
``initial``. The targets keep course and speed. Positions are turned into the task's frame: the own ship at
the origin heading north (a flat earth about its start, ``vessel_gym.physics.geodesy``; the reset then turns
the whole situation by the own ship's drawn heading). Not read: ``static`` (the simulated ships are the
task's ``ship``, whatever length the file gives), the targets' waypoints, ``navStatus``. A file that is not
of this shape raises ValueError naming the file and the key.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
from typing import Any

from vessel_gym.envs.tasks.colreg_encounters import Encounter, Target, planned_cpa
from vessel_gym.envs.tasks.colreg_geometry import classify
from vessel_gym.physics.geodesy import latlon_to_local
from vessel_gym.physics.units import KNOT_M_S

MAX_BYTES = 1 << 20  # a traffic situation is a few kB


def _number(node: Any, key: str, where: str) -> float:
    value = node.get(key) if isinstance(node, dict) else None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"{where}.{key}: expected a number, got {value!r}")
    return float(value)


def _initial(ship: Any, where: str) -> tuple[float, float, float, float]:
    """(lat deg, lon deg, speed m/s, heading deg) of a ship's ``initial`` block. Schema 0.2 (the generator's
    files since its version 0.8) leaves the position and speed out of ``initial``: then they are the first
    waypoint's ``position`` and its ``leg.sog``."""
    init = ship.get("initial") if isinstance(ship, dict) else None
    if not isinstance(init, dict):
        raise ValueError(f"{where}.initial: missing")
    pos, at = init.get("position"), f"{where}.initial.position"
    sog_node: Any = init
    sog_at = f"{where}.initial"
    if pos is None or "sog" not in init:
        waypoints = ship.get("waypoints")
        first = waypoints[0] if isinstance(waypoints, list) and waypoints else None
        if not isinstance(first, dict):
            raise ValueError(f"{where}.initial.position: missing, and no waypoints to take it from")
        if pos is None:
            pos, at = first.get("position"), f"{where}.waypoints[0].position"
        if "sog" not in init:
            sog_node, sog_at = first.get("leg"), f"{where}.waypoints[0].leg"
    lat = _number(pos, "lat", at)
    lon = _number(pos, "lon", at)
    sog = _number(sog_node, "sog", sog_at)
    key = (
        "heading" if "heading" in init else "cog"
    )  # the generator writes both; cog if the heading is left out
    return lat, lon, sog * KNOT_M_S, _number(init, key, f"{where}.initial")


def read_situation(source: str | Path | dict) -> Encounter:
    """The encounter of a traffic-situation file (a path, or its parsed JSON), with the own ship's goal in the
    encounter's frame (north, east, m; None without waypoints)."""
    where = "situation"
    if isinstance(source, dict):
        data = source
    else:
        path = Path(source)
        where = str(path)
        try:
            if path.stat().st_size > MAX_BYTES:
                raise ValueError(f"{path}: larger than {MAX_BYTES} bytes, not a traffic situation")
            data = json.loads(path.read_text())
        except (OSError, json.JSONDecodeError) as exc:
            raise ValueError(f"{path}: not a readable traffic-situation file ({exc})") from None
    if not isinstance(data, dict):
        raise ValueError(f"{where}: expected a JSON object")
    own = data.get("ownShip")
    lat0, lon0, speed, heading = _initial(own, f"{where}.ownShip")
    h = math.radians(heading)
    ch, sh = math.cos(h), math.sin(h)

    def frame(lat: float, lon: float) -> tuple[float, float]:
        n, e = latlon_to_local(lat, lon, lat0, lon0)
        return n * ch + e * sh, -n * sh + e * ch  # turned so that the own ship heads north

    goal = None
    waypoints = own.get("waypoints") if isinstance(own, dict) else None
    if waypoints:
        last = waypoints[-1].get("position") if isinstance(waypoints[-1], dict) else None
        at = f"{where}.ownShip.waypoints[-1].position"
        goal = frame(_number(last, "lat", at), _number(last, "lon", at))
    ships = data.get("targetShips")
    if not isinstance(ships, list) or not ships:
        raise ValueError(f"{where}.targetShips: expected a list of at least one ship")
    targets, planned = [], []
    for i, ship in enumerate(ships):
        lat, lon, sp, hd = _initial(ship, f"{where}.targetShips[{i}]")
        n, e = frame(lat, lon)
        psi = math.radians(hd - heading)
        targets.append(Target(n, e, psi, sp, classify(n, e, 0.0, psi, True)))
        planned.append(planned_cpa(n, e, psi, sp, speed))
    title = data.get("title") or (Path(source).stem if not isinstance(source, dict) else "situation")
    return Encounter(f"file:{title}", speed, tuple(targets), tuple(planned), goal)


#: DNV's 55 baseline traffic situations (ship-traffic-generator, ``data/baseline_situations_generated``, MIT
#: licence; vessel_gym/scenarios/dnv/README.md), as that generator wrote them
DNV_DIR = Path(__file__).resolve().parents[2] / "scenarios" / "dnv"
DNV_COUNT = 55


def dnv_situation(number: int) -> Encounter:
    """DNV baseline situation ``number`` (1..55), read from its file unchanged, named ``dnv:<number>``."""
    if not 1 <= number <= DNV_COUNT:
        raise ValueError(f"DNV baseline situation {number} does not exist (1..{DNV_COUNT})")
    enc = read_situation(DNV_DIR / f"traffic_situation_{number:02d}.json")
    return Encounter(f"dnv:{number}", enc.speed, enc.targets, enc.planned_cpa, enc.goal)


def within_speed(enc: Encounter, top: float) -> Encounter:
    """``enc`` with every ship's speed scaled by ``top`` / its fastest ship's speed (m/s) when that ship is
    faster than ``top``: the same straight paths, met in the same geometry (the same DCPA), the TCPA longer by
    the inverse factor. A simulated ship cannot start faster than its engine holds; the task's ``ship`` is
    driven by the one engine for own ship and targets alike."""
    fastest = max([enc.speed] + [t.speed for t in enc.targets])
    if fastest <= top:
        return enc
    f = top / fastest
    targets = tuple(dataclasses.replace(t, speed=t.speed * f) for t in enc.targets)
    planned = tuple((d, tc / f) for d, tc in enc.planned_cpa)
    return dataclasses.replace(enc, speed=enc.speed * f, targets=targets, planned_cpa=planned)
