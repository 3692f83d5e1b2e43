"""Protocol v2 of the JSON channel: what a viewer needs to draw the scene, sent only to clients that said
``"proto": 2`` — the ``scenario`` (polygons, sea state, in parts), ship ``particulars``, ``event`` and
``helm_owner`` messages, the v2 client's parser and the reassembly of scenario parts.

v2 adds four server message types and changes none of v1 (:mod:`vessel_gym.net.protocol`): ``state``,
``welcome`` and ``stats`` keep ``"v": 1``, the new messages carry ``"v": 2`` (a v1 reader never gets them, and
would drop them as ``bad_version`` if it did). Every datagram stays within MAX_STATE_DATAGRAM_BYTES.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from vessel_gym.net.wire import (
    MAX_NAME_CHARS,
    MAX_SERVER_DATAGRAM_BYTES,
    MAX_STATE_DATAGRAM_BYTES,
    PROTOCOL_VERSION,
    SERVER_TYPES,
    ProtocolError,
    decode_object,
    dumps,
    get_int,
    in_parts,
    num,
)

PROTOCOL_V2 = 2
V2_TYPES = ("scenario", "particulars", "event", "helm_owner")
# "kind" of a scenario feature; "fender" (a berth's fender, from the quay to its face) and "route" (the own
# ship's planned leg, start to goal) come from the task, not the scenario file
SCENE_KINDS = ("land", "breakwater", "quay", "depth", "start", "goal", "fender", "route")
EVENTS = ("reset", "outcome", "contact")
HELM_OWNER_REASONS = ("takeover", "watchdog", "released")
KNOT_M_S = 1852.0 / 3600.0  # m/s per knot (international nautical mile per hour)


@dataclass(frozen=True)
class ShipParticulars:
    """Static data of one ship for the ``particulars`` message: ``id`` 0 is the own ship, others are the ids of
    ``state.targets``. Lengths in m; ``outline`` is the waterline outline in body axes (x forward, y starboard,
    m), by default the project's hull outline from L and B."""

    id: int
    name: str
    length_m: float
    beam_m: float
    draught_m: float
    outline: tuple[tuple[float, float], ...] | None = None


def encode_particulars(seq: int, ship: ShipParticulars) -> bytes:
    """A ``particulars`` message (one ship). The outline is rounded to 0.01 m."""
    from vessel_gym.scenarios.geometry import hull_outline

    outline = ship.outline if ship.outline is not None else hull_outline(ship.length_m, ship.beam_m)
    data = dumps(
        {
            "v": PROTOCOL_V2,
            "type": "particulars",
            "seq": int(seq),
            "id": int(ship.id),
            "own": ship.id == 0,
            "name": str(ship.name)[:MAX_NAME_CHARS],
            "length_m": num(ship.length_m, 2),
            "beam_m": num(ship.beam_m, 2),
            "draught_m": num(ship.draught_m, 2),
            "outline_m": [[num(x, 2), num(y, 2)] for x, y in outline],
        }
    ).encode()
    if len(data) > MAX_STATE_DATAGRAM_BYTES:
        raise ValueError(f"ship {ship.id} outline of {len(outline)} points does not fit one datagram")
    return data


def _points(points: Sequence[Sequence[float]]) -> list[list[float | None]]:
    return [[num(p[0], 2), num(p[1], 2)] for p in points]


def scenario_features(scenario: object) -> list[dict]:
    """The scenario's polygons as ``scenario.features`` entries (before splitting): land, breakwaters, quays,
    depth areas (with ``depth_m``), the start region and the goal (with ``heading_deg``, its tolerance, the
    goal point and the speed limit). ``scenario`` is a :class:`~vessel_gym.scenarios.Scenario`."""
    out: list[dict] = []
    for kind in ("land", "breakwater", "quay"):
        for area in getattr(scenario, kind):
            out.append({"kind": kind, "name": area.name, "points": _points(area.points)})
    for area in scenario.depth_area:
        out.append(
            {
                "kind": "depth",
                "name": area.name,
                "depth_m": num(area.depth_m, 2),
                "points": _points(area.points),
            }
        )
    out.append({"kind": "start", "name": "start", "points": _points(scenario.start.points)})
    goal = scenario.goal
    out.append(
        {
            "kind": "goal",
            "name": "goal",
            "points": _points(goal.points),
            "point_m": _points([scenario.goal_point])[0],
            "heading_deg": num(goal.heading_deg % 360.0, 2),
            "heading_tolerance_deg": num(goal.heading_tolerance_deg, 2),
            "max_speed_kn": num(goal.max_speed_m_s / KNOT_M_S, 2),
        }
    )
    return out


def environment_fields(environment: object | None) -> dict[str, float | None]:
    """Wind, current and sea state of the episode (``scenario.sea``): speeds in kn, directions true."""
    if environment is None:
        return {}
    e = environment
    return {
        "wind_speed_kn": num(e.wind_speed_m_s / KNOT_M_S, 2),
        "wind_from_deg": num(e.wind_from_deg % 360.0, 1),
        "current_speed_kn": num(e.current_speed_m_s / KNOT_M_S, 2),
        "current_to_deg": num(e.current_to_deg % 360.0, 1),
        "hs_m": num(e.Hs_m, 2),
        "tp_s": num(e.Tp_s, 2),
        "wave_from_deg": num(e.wave_from_deg % 360.0, 1),
    }


def encode_scenario(
    seq: int,
    scenario: object | None,
    environment: object | None = None,
    max_bytes: int = MAX_STATE_DATAGRAM_BYTES,
    extra_features: Sequence[Mapping] = (),
) -> list[bytes]:
    """The ``scenario`` message as ``parts`` datagrams of at most ``max_bytes`` bytes that share ``seq``;
    ``extra_features`` (the task's fenders or route) follow the scenario's own.

    Every part repeats the head (name, geodetic reference, bounds, open-water depth, ``sea``) and carries some
    of the ``features``; a polygon too long for one datagram is split into pieces with the same ``id`` whose
    ``points`` are concatenated in part order. ``scenario`` None (open water) sends the head with no features.
    """
    head: dict[str, object] = {"v": PROTOCOL_V2, "type": "scenario", "seq": int(seq)}
    if scenario is not None:
        head["name"] = str(scenario.name)[:64]
        lat, lon = scenario.reference_latlon_deg
        head["ref_lat_deg"] = num(lat, 7)
        head["ref_lon_deg"] = num(lon, 7)
        head["bounds_m"] = [num(b, 2) for b in scenario.bounds_m]  # north min, north max, east min, east max
        head["water_depth_m"] = num(scenario.water_depth_m, 2)
        features = scenario_features(scenario)
    else:
        head["name"] = ""
        features = []
    features = features + [
        {"kind": f["kind"], "name": str(f.get("name", ""))[:MAX_NAME_CHARS], "points": _points(f["points"])}
        for f in extra_features
    ]
    head["sea"] = environment_fields(environment)
    prefix = dumps(head)[:-1] + ',"features":['
    tail_room = len('],"part":9999,"parts":9999}')
    room = max_bytes - len(prefix.encode()) - tail_room
    if room < 200:
        raise ValueError(f"a {max_bytes}-byte datagram leaves no room for scenario features")
    items: list[str] = []
    for i, f in enumerate(features):
        f = {"id": i, **f}
        text = dumps(f)
        if len(text.encode()) + 1 <= room:
            items.append(text)
            continue
        pts = f.pop("points")
        base = dumps({**f, "points": []})
        per_point = max(len(dumps(p)) + 1 for p in pts)
        n = max(1, (room - len(base.encode()) - 1) // per_point)
        items += [dumps({**f, "points": pts[j : j + n]}) for j in range(0, len(pts), n)]
    return in_parts(prefix, items, room)


def encode_event(seq: int, event: str, t_s: float, episode: int, **fields: object) -> bytes:
    """An ``event``: ``reset`` (an episode starts), ``outcome`` (it ended: ``outcome`` and figures) or
    ``contact`` (the hull touched land, a breakwater or a quay, or grounded: ``what``). Extra ``fields`` are
    numbers (rounded to 0.01) or strings."""
    if event not in EVENTS:
        raise ValueError(f"event must be one of {EVENTS}, not {event!r}")
    msg: dict[str, object] = {
        "v": PROTOCOL_V2,
        "type": "event",
        "seq": int(seq),
        "event": event,
        "t_s": num(t_s, 3),
        "episode": int(episode),
    }
    for key, value in fields.items():
        if isinstance(value, str):
            msg[key] = value[:64]
        elif isinstance(value, (bool, int)) and not isinstance(value, float):
            msg[key] = value
        else:
            msg[key] = num(float(value), 2)  # type: ignore[arg-type]
    return dumps(msg).encode()


def encode_helm_owner(seq: int, owner: str | None, you: bool, reason: str) -> bytes:
    """A ``helm_owner`` change: ``owner`` is the new owner's name (or ``host:port`` when it gave none), None
    when the helm is free; ``you`` is true for the client that owns it; ``reason`` one of
    :data:`HELM_OWNER_REASONS`."""
    if reason not in HELM_OWNER_REASONS:
        raise ValueError(f"reason must be one of {HELM_OWNER_REASONS}, not {reason!r}")
    return dumps(
        {
            "v": PROTOCOL_V2,
            "type": "helm_owner",
            "seq": int(seq),
            "owner": owner,
            "you": bool(you),
            "reason": reason,
        }
    ).encode()


def parse_server_datagram_v2(data: bytes) -> dict:
    """Decode any server datagram a v2 client receives: the v1 types with ``"v": 1`` and the v2 types with
    ``"v": 2``. Same checks as :func:`parse_server_datagram`; a ``scenario`` part must carry a ``features``
    list and integer ``part`` < ``parts``, a ``particulars`` an ``outline_m`` list of [x, y] pairs."""
    obj = decode_object(data, MAX_SERVER_DATAGRAM_BYTES)
    version, kind = obj.get("v"), obj.get("type")
    if isinstance(version, bool) or version not in (PROTOCOL_VERSION, PROTOCOL_V2):
        raise ProtocolError("bad_version")
    if kind not in (SERVER_TYPES if version == PROTOCOL_VERSION else V2_TYPES):
        raise ProtocolError("bad_type")
    if kind == "scenario":
        part, parts = get_int(obj, "part", True), get_int(obj, "parts", True)
        if not 0 <= part < parts or not isinstance(obj.get("features"), list):
            raise ProtocolError("bad_field", "scenario part/parts/features")
    elif kind == "particulars":
        outline = obj.get("outline_m")
        if not isinstance(outline, list) or not all(isinstance(p, list) and len(p) == 2 for p in outline):
            raise ProtocolError("bad_field", "particulars outline_m")
    return obj


class SceneAssembler:
    """Collects the parts of ``scenario`` messages and returns the whole scene once all parts of one ``seq``
    are in: ``add(msg)`` gives the merged message (``features`` with split polygons joined again) or None."""

    def __init__(self) -> None:
        self._seq: int | None = None
        self._parts: dict[int, dict] = {}

    def add(self, msg: Mapping) -> dict | None:
        seq = msg.get("seq")
        if seq != self._seq:
            if self._seq is not None and isinstance(seq, int) and seq < self._seq:
                return None  # a late part of an older scene
            self._seq, self._parts = seq, {}
        self._parts[int(msg["part"])] = dict(msg)
        parts = int(msg["parts"])
        if len(self._parts) < parts:
            return None
        merged: dict[int, dict] = {}
        for i in range(parts):
            for f in self._parts[i]["features"]:
                if not isinstance(f, dict):
                    continue
                fid = f.get("id")
                if fid in merged:
                    merged[fid]["points"] = merged[fid]["points"] + list(f.get("points", []))
                else:
                    merged[fid] = {**f, "points": list(f.get("points", []))}
        whole = {k: v for k, v in self._parts[0].items() if k not in ("part", "parts", "features")}
        whole["features"] = list(merged.values())
        self._parts = {}
        return whole
