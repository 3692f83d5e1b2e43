"""The JSON state/command channel, schema version 1.

One UTF-8 JSON object per UDP datagram, always with ``"v": 1`` and a ``"type"``. Units are in the field names
(``_deg``, ``_kn``, ``_dpm`` = deg/min, ``_m``, ``_s``, ``_hz``). Angles are true, clockwise from north; rudder
and rate of turn are positive to starboard; x is north and y east of the scenario's reference point.

Client to server: ``hello``, ``helm``, ``bye``, ``stats_request``. Server to client: ``welcome``, ``state``,
``stats``. The full schema with ranges is in ``docs/protocol.md``. Joining takes two hellos: the first is
answered by a short ``welcome`` with a ``cookie`` (:func:`encode_challenge`), the second echoes it and is answered
by the full ``welcome`` with a ``session`` that ``helm`` and ``bye`` then carry.

Incoming datagrams are parsed by :func:`parse_datagram`, which either returns a typed message or raises
:class:`ProtocolError` carrying a short reason code for the caller's drop counters. Out-of-range numbers are
clamped to their limits; ill-typed or non-finite ones are rejected. Outgoing messages are encoded with
``allow_nan=False``; a non-finite value in the simulation state is sent as ``null`` (not available).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from vessel_gym.physics.bridge import BridgeReading

PROTOCOL_VERSION = 1
MAX_DATAGRAM_BYTES = 2048  # larger client datagrams are rejected unread
MAX_SERVER_DATAGRAM_BYTES = 65536  # larger server datagrams are rejected unread by the clients' parsers
MAX_STATE_DATAGRAM_BYTES = 1400  # server datagrams stay below a LAN MTU (no IP fragmentation)
MIN_RATE_HZ = 1.0
MAX_RATE_HZ = 50.0
MAX_SEQ = 2**53 - 1  # largest integer every JSON implementation (JavaScript, C# double) holds exactly
MAX_NAME_CHARS = 32
MAX_TOKEN_CHARS = 128
MAX_COOKIE_CHARS = 64
MAX_SESSION_CHARS = 32
# A hello that carries no valid cookie is answered only if the answer is no larger than the hello (no
# amplification towards an address that has not shown it receives); clients pad such hellos to this size, which
# leaves room for the challenge (about 80 bytes).
MIN_HELLO_BYTES = 128
TELEGRAPH_MIN = -4
TELEGRAPH_MAX = 4

CLIENT_TYPES = ("hello", "helm", "bye", "stats_request")
SERVER_TYPES = ("welcome", "state", "stats")
ROLES = ("viewer", "helm")

# Reason codes of ProtocolError, in the order the checks are made.
REASONS = (
    "oversize",
    "too_complex",
    "bad_utf8",
    "bad_json",
    "non_finite",
    "not_object",
    "bad_version",
    "bad_type",
    "bad_field",
)
# Client messages are flat objects. Capping the number of '[' and '{' bounds the objects one datagram can make
# the parser allocate: 2 kB of nested brackets would otherwise create ~1000 lists and can trigger a full
# garbage collection of the host process (tens of ms) inside the caller's step.
MAX_CONTAINERS = 32


class ProtocolError(ValueError):
    """A datagram that is not a valid v1 message. ``reason`` is one of :data:`REASONS`."""

    def __init__(self, reason: str, detail: str = "") -> None:
        super().__init__(f"{reason}: {detail}" if detail else reason)
        self.reason = reason


class _NonFinite(ValueError):
    pass


def _reject_constant(name: str) -> float:
    raise _NonFinite(name)


def _finite_float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):  # 1e309 overflows to inf
        raise _NonFinite(text)
    return value


_DECODER = json.JSONDecoder(parse_float=_finite_float, parse_constant=_reject_constant)


@dataclass(frozen=True)
class Limits:
    """Physical limits used to clamp helm orders: rudder order to +-``max_rudder_deg`` (deg), rpm order to
    +-``max_rpm`` (rev/min)."""

    max_rudder_deg: float = 35.0
    max_rpm: float = 200.0

    def __post_init__(self) -> None:
        for name in ("max_rudder_deg", "max_rpm"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0.0 < value < 1e6:
                raise ValueError(f"Limits.{name} must be a positive number, not {value!r}")


DEFAULT_LIMITS = Limits()


@dataclass(frozen=True)
class Hello:
    """Registration and keep-alive. ``rate_hz`` is the wanted state rate, already clamped to 1-50 Hz."""

    role: str  # "viewer" | "helm"
    rate_hz: float
    name: str = ""
    token: str | None = None
    cookie: str | None = None  # echoed from the last welcome: proof that the sender receives at its address
    session: str | None = None  # the session the client holds (from its last full welcome)
    proto: int = 1  # 2: the client also wants the v2 messages (scenario, particulars, event, helm_owner)


@dataclass(frozen=True)
class HelmCommand:
    """A full helm order (never a delta). Exactly one of ``telegraph`` and ``rpm_order`` is set.

    ``seq`` increases per panel; ``rudder_order_deg`` is clamped to the rudder limit (deg, + = starboard);
    ``telegraph`` is a Telegraph step -4..4; ``rpm_order`` is in rev/min (negative astern).
    """

    seq: int
    rudder_order_deg: float
    telegraph: int | None = None
    rpm_order: float | None = None
    session: str | None = None  # the sender's session (from its welcome); seq counts within it


@dataclass(frozen=True)
class Bye:
    """The client leaves (releases the helm if it held it); ``session`` as in :class:`HelmCommand`."""

    session: str | None = None


@dataclass(frozen=True)
class StatsRequest:
    """Ask for one ``stats`` message now."""


ClientMessage = Hello | HelmCommand | Bye | StatsRequest

_MISSING = object()


def _get_number(obj: Mapping, key: str, required: bool) -> int | float | None:
    value = obj.get(key, _MISSING)
    if value is _MISSING or (value is None and not required):
        if required:
            raise ProtocolError("bad_field", f"missing {key}")
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ProtocolError("bad_field", f"{key} must be a number")
    return value


def _clamp(value: int | float, low: float, high: float) -> float:
    # Compare before converting: int -> float would overflow for integers beyond 1e308.
    if value < low:
        return float(low)
    if value > high:
        return float(high)
    return float(value)


def _get_int(obj: Mapping, key: str, required: bool) -> int | None:
    value = obj.get(key, _MISSING)
    if value is _MISSING or (value is None and not required):
        if required:
            raise ProtocolError("bad_field", f"missing {key}")
        return None
    if isinstance(value, bool) or not isinstance(value, int):
        raise ProtocolError("bad_field", f"{key} must be an integer")
    return value


def _get_str(obj: Mapping, key: str, max_chars: int, truncate: bool = True) -> str | None:
    value = obj.get(key)
    if value is None:
        return None
    if not isinstance(value, str):
        raise ProtocolError("bad_field", f"{key} must be a string")
    if (
        len(value) > max_chars and not truncate
    ):  # a secret is never truncated: a long one would match its prefix
        raise ProtocolError("bad_field", f"{key} longer than {max_chars} characters")
    return value[:max_chars]


def _get_seq(obj: Mapping, required: bool) -> int | None:
    seq = _get_int(obj, "seq", required)
    if seq is not None and not 0 <= seq <= MAX_SEQ:
        raise ProtocolError("bad_field", "seq must be 0..2^53-1")
    return seq


def _decode_object(data: bytes, max_bytes: int, max_containers: int | None = None) -> dict:
    """The JSON object a datagram carries, or :class:`ProtocolError`: the size, nesting (``max_containers``
    ``[``/``{`` in total, when given), UTF-8, JSON and finiteness checks every parser makes before it looks at
    the version, the type and the fields."""
    if len(data) > max_bytes:
        raise ProtocolError("oversize", f"{len(data)} bytes")
    if max_containers is not None and data.count(b"[") + data.count(b"{") > max_containers:
        raise ProtocolError("too_complex")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise ProtocolError("bad_utf8") from None
    try:
        obj = _DECODER.decode(text)
    except _NonFinite:
        raise ProtocolError("non_finite") from None
    except (ValueError, RecursionError):  # JSONDecodeError, int digit limit, deep nesting
        raise ProtocolError("bad_json") from None
    if not isinstance(obj, dict):
        raise ProtocolError("not_object")
    return obj


def parse_datagram(
    data: bytes, limits: Limits = DEFAULT_LIMITS, default_rate_hz: float = 20.0
) -> ClientMessage:
    """Validate one client datagram and return its typed message, or raise :class:`ProtocolError`.

    Rejected: more than 2048 bytes, more than 32 ``[``/``{`` in total (``too_complex``), bad UTF-8, bad JSON (including nesting too deep to parse), NaN/Infinity or
    numbers that overflow a double, anything but an object, ``v`` other than 1, an unknown ``type``, and missing
    or ill-typed fields (booleans are not numbers). Clamped: ``rate_hz`` to 1-50, ``rudder_order_deg`` and
    ``rpm_order`` to ``limits``, ``telegraph`` to -4..4. Unknown keys are ignored (forward compatibility).
    """
    obj = _decode_object(data, MAX_DATAGRAM_BYTES, MAX_CONTAINERS)
    version = obj.get("v")
    if isinstance(version, bool) or version != PROTOCOL_VERSION:
        raise ProtocolError("bad_version")
    kind = obj.get("type")
    if kind == "helm":
        seq = _get_seq(obj, required=True)
        rudder = _get_number(obj, "rudder_order_deg", required=True)
        telegraph = _get_int(obj, "telegraph", required=False)
        rpm_order = _get_number(obj, "rpm_order", required=False)
        if (telegraph is None) == (rpm_order is None):
            raise ProtocolError("bad_field", "exactly one of telegraph and rpm_order")
        return HelmCommand(
            seq=seq,
            rudder_order_deg=_clamp(rudder, -limits.max_rudder_deg, limits.max_rudder_deg),
            telegraph=None if telegraph is None else int(_clamp(telegraph, TELEGRAPH_MIN, TELEGRAPH_MAX)),
            rpm_order=None if rpm_order is None else _clamp(rpm_order, -limits.max_rpm, limits.max_rpm),
            session=_get_str(obj, "session", MAX_SESSION_CHARS, truncate=False),
        )
    if kind == "hello":
        _get_seq(obj, required=False)
        role = obj.get("role")
        if role not in ROLES:
            raise ProtocolError("bad_field", "role must be 'viewer' or 'helm'")
        rate = _get_number(obj, "rate_hz", required=False)
        return Hello(
            role=role,
            rate_hz=_clamp(default_rate_hz if rate is None else rate, MIN_RATE_HZ, MAX_RATE_HZ),
            name=_get_str(obj, "name", MAX_NAME_CHARS) or "",
            token=_get_str(obj, "token", MAX_TOKEN_CHARS, truncate=False),
            cookie=_get_str(obj, "cookie", MAX_COOKIE_CHARS, truncate=False),
            session=_get_str(obj, "session", MAX_SESSION_CHARS, truncate=False),
            proto=2 if (_get_int(obj, "proto", required=False) or 1) >= 2 else 1,
        )
    if kind == "bye":
        _get_seq(obj, required=False)
        return Bye(session=_get_str(obj, "session", MAX_SESSION_CHARS, truncate=False))
    if kind == "stats_request":
        _get_seq(obj, required=False)
        return StatsRequest()
    raise ProtocolError("bad_type")


# ---------------------------------------------------------------------------------------------------------------
# Server -> client


@dataclass(frozen=True)
class Target:
    """Another ship in the scene, as sent in ``state.targets`` and (with an MMSI) as AIS.

    ``reading`` supplies position and motion; the rest is static data (m). ``mmsi`` None means the ship sends
    no AIS. ``ship_type`` is the AIS code (70 = cargo); ``nav_status`` the AIS navigational status (0 = under
    way using engine).
    """

    id: int
    name: str
    reading: BridgeReading
    length_m: float
    beam_m: float
    mmsi: int | None = None
    call_sign: str = ""
    imo: int = 0
    ship_type: int = 70
    draught_m: float = 0.0
    destination: str = ""
    nav_status: int = 0

    def __post_init__(self) -> None:
        if self.mmsi is not None and not 0 < self.mmsi < 10**9:
            raise ValueError(f"Target {self.id}: MMSI must be 1..999999999, not {self.mmsi!r}")


def _num(value: float | None, decimals: int) -> float | None:
    """Rounded number for JSON, None (null) when unknown or non-finite."""
    if value is None or not math.isfinite(value):
        return None
    return round(float(value), decimals)


def _dumps(obj: Mapping) -> str:
    return json.dumps(obj, allow_nan=False, separators=(",", ":"))


def own_state_fields(own: BridgeReading) -> dict[str, float | int | None]:
    """The own-ship part of a ``state`` message (edge units, rounded to what a viewer can use)."""
    return {
        "t_s": _num(own.t_s, 3),
        "lat_deg": _num(own.lat_deg, 7),
        "lon_deg": _num(own.lon_deg, 7),
        "x_m": _num(own.x_m, 2),
        "y_m": _num(own.y_m, 2),
        "hdg_deg": _num(own.hdg_deg, 2),
        "cog_deg": _num(own.cog_deg, 2),
        "sog_kn": _num(own.sog_kn, 3),
        "stw_kn": _num(own.stw_kn, 3),
        "rot_dpm": _num(own.rot_dpm, 2),
        "rudder_deg": _num(own.rudder_deg, 2),
        "rudder_order_deg": _num(own.rudder_order_deg, 2),
        "rpm": _num(own.rpm, 1),
        "telegraph": int(own.telegraph),
    }


def target_fields(target: Target) -> dict[str, float | int | str | None]:
    """One entry of ``state.targets``."""
    r = target.reading
    return {
        "id": int(target.id),
        "name": target.name,
        "lat_deg": _num(r.lat_deg, 7),
        "lon_deg": _num(r.lon_deg, 7),
        "x_m": _num(r.x_m, 2),
        "y_m": _num(r.y_m, 2),
        "hdg_deg": _num(r.hdg_deg, 2),
        "cog_deg": _num(r.cog_deg, 2),
        "sog_kn": _num(r.sog_kn, 3),
        "length_m": _num(target.length_m, 2),
        "beam_m": _num(target.beam_m, 2),
    }


def encode_state(
    seq: int,
    own: BridgeReading,
    helm_ok: bool,
    targets: Sequence[Target] = (),
    max_bytes: int = MAX_STATE_DATAGRAM_BYTES,
) -> list[bytes]:
    """Encode a ``state`` message as one or more datagrams of at most ``max_bytes`` bytes.

    Usually one datagram (``"part":0,"parts":1``). With many targets the target list is split over ``parts``
    datagrams that repeat the own-ship fields and share ``seq``; a client merges the parts of one ``seq``.
    """
    head = {"v": PROTOCOL_VERSION, "type": "state", "seq": int(seq)}
    head.update(own_state_fields(own))
    head["helm_ok"] = bool(helm_ok)
    fields = [target_fields(t) for t in targets]
    whole = _dumps({**head, "targets": fields, "part": 0, "parts": 1}).encode()
    if len(whole) <= max_bytes:
        return [whole]
    prefix = _dumps(head)[:-1] + ',"targets":['
    items = [_dumps(f) for f in fields]
    tail_room = len('],"part":99,"parts":99}')
    room = max_bytes - len(prefix.encode()) - tail_room
    for item in items:
        n = len(item.encode()) + 1
        if n > room:
            raise ValueError(f"target entry of {n} bytes does not fit a {max_bytes}-byte state datagram")
    return _in_parts(prefix, items, room)


def _in_parts(prefix: str, items: Sequence[str], room: int) -> list[bytes]:
    """The datagrams ``prefix`` + comma-separated items + ``],"part":i,"parts":n}``, filled in order with as
    many items as fit ``room`` bytes each (an item larger than ``room`` travels alone: the caller refuses or
    splits those)."""
    chunks: list[list[str]] = [[]]
    size = 0
    for item in items:
        n = len(item.encode()) + 1
        if size + n > room and chunks[-1]:
            chunks.append([])
            size = 0
        chunks[-1].append(item)
        size += n
    parts = len(chunks)
    return [
        f'{prefix}{",".join(chunk)}],"part":{i},"parts":{parts}}}'.encode() for i, chunk in enumerate(chunks)
    ]


def encode_welcome(
    seq: int,
    role: str,
    rate_hz: float,
    helm: bool,
    limits: Limits,
    watchdog_s: float,
    timeout_s: float,
    failsafe: str,
    cookie: str | None = None,
    session: str | None = None,
) -> bytes:
    """Reply to a ``hello`` with a valid cookie: the granted rate, whether this client owns the helm, the link
    rules, the client's ``session`` and a fresh ``cookie`` for its next hellos."""
    msg: dict[str, object] = {
        "v": PROTOCOL_VERSION,
        "type": "welcome",
        "seq": int(seq),
        "role": role,
        "rate_hz": rate_hz,
        "helm": bool(helm),
        "max_rudder_deg": limits.max_rudder_deg,
        "max_rpm": limits.max_rpm,
        "watchdog_s": watchdog_s,
        "timeout_s": timeout_s,
        "failsafe": failsafe,
    }
    if cookie is not None:
        msg["cookie"] = cookie
    if session is not None:
        msg["session"] = session
    return _dumps(msg).encode()


def encode_challenge(seq: int, cookie: str) -> bytes:
    """The short ``welcome`` to a hello without a valid cookie: only the cookie to echo (no session yet)."""
    return _dumps({"v": PROTOCOL_VERSION, "type": "welcome", "seq": int(seq), "cookie": cookie}).encode()


def encode_stats(seq: int, t_s: float, counters: Mapping[str, int], clients: int) -> bytes:
    """A ``stats`` message: link counters (datagrams received, sent, dropped per reason) and live clients."""
    return _dumps(
        {
            "v": PROTOCOL_VERSION,
            "type": "stats",
            "seq": int(seq),
            "t_s": _num(t_s, 3),
            "clients": int(clients),
            "counters": {str(k): int(v) for k, v in counters.items()},
        }
    ).encode()


# ---------------------------------------------------------------------------------------------------------------
# Client side


def encode_hello(
    role: str,
    rate_hz: float | None = None,
    name: str = "",
    token: str | None = None,
    cookie: str | None = None,
    session: str | None = None,
    pad_to: int = MIN_HELLO_BYTES,
    proto: int = 1,
) -> bytes:
    """A client's ``hello`` (send on start and at least once a second as keep-alive).

    ``cookie`` and ``session`` are echoed from the last ``welcome``. The datagram is padded with a ``pad``
    field to ``pad_to`` bytes, so that a server that does not (or no longer) knows the sender may answer it.
    ``proto=2`` asks for the v2 messages too.
    """
    if role not in ROLES:
        raise ValueError(f"role must be one of {ROLES}, not {role!r}")
    msg: dict[str, object] = {"v": PROTOCOL_VERSION, "type": "hello", "role": role}
    if rate_hz is not None:
        msg["rate_hz"] = float(rate_hz)
    if name:
        msg["name"] = name[:MAX_NAME_CHARS]
    if token is not None:
        msg["token"] = token
    if cookie is not None:
        msg["cookie"] = cookie
    if session is not None:
        msg["session"] = session
    if proto != 1:
        msg["proto"] = int(proto)
    data = _dumps(msg).encode()
    short = pad_to - len(data) - len(',"pad":""')
    if short > 0:
        msg["pad"] = "." * short
        data = _dumps(msg).encode()
    return data


def encode_helm(
    seq: int,
    rudder_order_deg: float,
    telegraph: int | None = None,
    rpm_order: float | None = None,
    session: str | None = None,
) -> bytes:
    """A full ``helm`` command; exactly one of ``telegraph`` (-4..4) and ``rpm_order`` (rev/min); ``session``
    from the sender's welcome."""
    if (telegraph is None) == (rpm_order is None):
        raise ValueError("give exactly one of telegraph and rpm_order")
    msg: dict[str, object] = {
        "v": PROTOCOL_VERSION,
        "type": "helm",
        "seq": int(seq),
        "rudder_order_deg": float(rudder_order_deg),
    }
    if telegraph is not None:
        msg["telegraph"] = int(telegraph)
    else:
        msg["rpm_order"] = float(rpm_order)
    if session is not None:
        msg["session"] = session
    return _dumps(msg).encode()


def encode_bye(session: str | None = None) -> bytes:
    """A client's ``bye`` (with the session of its welcome)."""
    if session is None:
        return b'{"v":1,"type":"bye"}'
    return _dumps({"v": PROTOCOL_VERSION, "type": "bye", "session": session}).encode()


def encode_stats_request() -> bytes:
    """Ask the server for a ``stats`` message."""
    return b'{"v":1,"type":"stats_request"}'


def parse_server_datagram(data: bytes) -> dict:
    """Decode a server datagram (``welcome``/``state``/``stats``) into a dict, or raise :class:`ProtocolError`.

    The same size, UTF-8, JSON, finiteness, version and type checks as :func:`parse_datagram` (``state``
    datagrams may be up to 64 KiB); the fields themselves are returned as sent (``null`` = not available).
    """
    obj = _decode_object(data, MAX_SERVER_DATAGRAM_BYTES)
    if obj.get("v") != PROTOCOL_VERSION or isinstance(obj.get("v"), bool):
        raise ProtocolError("bad_version")
    if obj.get("type") not in SERVER_TYPES:
        raise ProtocolError("bad_type")
    return obj


# ---------------------------------------------------------------------------------------------------------------
# Protocol v2: what a viewer needs to draw the scene (server -> client, only to clients that said "proto": 2)
#
# v2 adds four server message types and changes none of v1: ``state``, ``welcome`` and ``stats`` keep
# ``"v": 1``, the new messages carry ``"v": 2`` (a v1 reader never gets them, and would drop them as
# ``bad_version`` if it did). Every datagram stays within MAX_STATE_DATAGRAM_BYTES.

PROTOCOL_V2 = 2
V2_TYPES = ("scenario", "particulars", "event", "helm_owner")
SCENE_KINDS = ("land", "breakwater", "quay", "depth", "start", "goal")  # "kind" of a scenario feature
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
    data = _dumps(
        {
            "v": PROTOCOL_V2,
            "type": "particulars",
            "seq": int(seq),
            "id": int(ship.id),
            "own": ship.id == 0,
            "name": str(ship.name)[:MAX_NAME_CHARS],
            "length_m": _num(ship.length_m, 2),
            "beam_m": _num(ship.beam_m, 2),
            "draught_m": _num(ship.draught_m, 2),
            "outline_m": [[_num(x, 2), _num(y, 2)] for x, y in outline],
        }
    ).encode()
    if len(data) > MAX_STATE_DATAGRAM_BYTES:
        raise ValueError(f"ship {ship.id} outline of {len(outline)} points does not fit one datagram")
    return data


def _points(points: Sequence[Sequence[float]]) -> list[list[float | None]]:
    return [[_num(p[0], 2), _num(p[1], 2)] for p in points]


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
                "depth_m": _num(area.depth_m, 2),
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
            "heading_deg": _num(goal.heading_deg % 360.0, 2),
            "heading_tolerance_deg": _num(goal.heading_tolerance_deg, 2),
            "max_speed_kn": _num(goal.max_speed_m_s / KNOT_M_S, 2),
        }
    )
    return out


def environment_fields(environment: object | None) -> dict[str, float | None]:
    """Wind, current and sea state of the episode (``scenario.sea``): speeds in kn, directions true."""
    if environment is None:
        return {}
    e = environment
    return {
        "wind_speed_kn": _num(e.wind_speed_m_s / KNOT_M_S, 2),
        "wind_from_deg": _num(e.wind_from_deg % 360.0, 1),
        "current_speed_kn": _num(e.current_speed_m_s / KNOT_M_S, 2),
        "current_to_deg": _num(e.current_to_deg % 360.0, 1),
        "hs_m": _num(e.Hs_m, 2),
        "tp_s": _num(e.Tp_s, 2),
        "wave_from_deg": _num(e.wave_from_deg % 360.0, 1),
    }


def encode_scenario(
    seq: int,
    scenario: object | None,
    environment: object | None = None,
    max_bytes: int = MAX_STATE_DATAGRAM_BYTES,
) -> list[bytes]:
    """The ``scenario`` message as ``parts`` datagrams of at most ``max_bytes`` bytes that share ``seq``.

    Every part repeats the head (name, geodetic reference, bounds, open-water depth, ``sea``) and carries some
    of the ``features``; a polygon too long for one datagram is split into pieces with the same ``id`` whose
    ``points`` are concatenated in part order. ``scenario`` None (open water) sends the head with no features.
    """
    head: dict[str, object] = {"v": PROTOCOL_V2, "type": "scenario", "seq": int(seq)}
    if scenario is not None:
        head["name"] = str(scenario.name)[:64]
        lat, lon = scenario.reference_latlon_deg
        head["ref_lat_deg"] = _num(lat, 7)
        head["ref_lon_deg"] = _num(lon, 7)
        head["bounds_m"] = [_num(b, 2) for b in scenario.bounds_m]  # north min, north max, east min, east max
        head["water_depth_m"] = _num(scenario.water_depth_m, 2)
        features = scenario_features(scenario)
    else:
        head["name"] = ""
        features = []
    head["sea"] = environment_fields(environment)
    prefix = _dumps(head)[:-1] + ',"features":['
    tail_room = len('],"part":9999,"parts":9999}')
    room = max_bytes - len(prefix.encode()) - tail_room
    if room < 200:
        raise ValueError(f"a {max_bytes}-byte datagram leaves no room for scenario features")
    items: list[str] = []
    for i, f in enumerate(features):
        f = {"id": i, **f}
        text = _dumps(f)
        if len(text.encode()) + 1 <= room:
            items.append(text)
            continue
        pts = f.pop("points")
        base = _dumps({**f, "points": []})
        per_point = max(len(_dumps(p)) + 1 for p in pts)
        n = max(1, (room - len(base.encode()) - 1) // per_point)
        items += [_dumps({**f, "points": pts[j : j + n]}) for j in range(0, len(pts), n)]
    return _in_parts(prefix, items, room)


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
        "t_s": _num(t_s, 3),
        "episode": int(episode),
    }
    for key, value in fields.items():
        if isinstance(value, str):
            msg[key] = value[:64]
        elif isinstance(value, (bool, int)) and not isinstance(value, float):
            msg[key] = value
        else:
            msg[key] = _num(float(value), 2)  # type: ignore[arg-type]
    return _dumps(msg).encode()


def encode_helm_owner(seq: int, owner: str | None, you: bool, reason: str) -> bytes:
    """A ``helm_owner`` change: ``owner`` is the new owner's name (or ``host:port`` when it gave none), None
    when the helm is free; ``you`` is true for the client that owns it; ``reason`` one of
    :data:`HELM_OWNER_REASONS`."""
    if reason not in HELM_OWNER_REASONS:
        raise ValueError(f"reason must be one of {HELM_OWNER_REASONS}, not {reason!r}")
    return _dumps(
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
    obj = _decode_object(data, MAX_SERVER_DATAGRAM_BYTES)
    version, kind = obj.get("v"), obj.get("type")
    if isinstance(version, bool) or version not in (PROTOCOL_VERSION, PROTOCOL_V2):
        raise ProtocolError("bad_version")
    if kind not in (SERVER_TYPES if version == PROTOCOL_VERSION else V2_TYPES):
        raise ProtocolError("bad_type")
    if kind == "scenario":
        part, parts = _get_int(obj, "part", True), _get_int(obj, "parts", True)
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
