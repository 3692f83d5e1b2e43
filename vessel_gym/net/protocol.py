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

This module holds the v1 messages. The wire format they share with v2 (limits, reason codes, checked decoding,
compact encoding) is :mod:`~vessel_gym.net.wire`; the v2 scene, particulars, event and helm-owner messages are
:mod:`~vessel_gym.net.protocol_v2`. Every name of both is importable from here too.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from vessel_gym.net.protocol_v2 import (  # noqa: F401  (re-exported: v1 and v2 names import from here)
    EVENTS,
    HELM_OWNER_REASONS,
    KNOT_M_S,
    PROTOCOL_V2,
    SCENE_KINDS,
    V2_TYPES,
    SceneAssembler,
    ShipParticulars,
    encode_event,
    encode_helm_owner,
    encode_particulars,
    encode_scenario,
    environment_fields,
    parse_server_datagram_v2,
    scenario_features,
)
from vessel_gym.net.wire import (  # noqa: F401
    CLIENT_TYPES,
    MAX_CONTAINERS,
    MAX_COOKIE_CHARS,
    MAX_DATAGRAM_BYTES,
    MAX_NAME_CHARS,
    MAX_RATE_HZ,
    MAX_SEQ,
    MAX_SERVER_DATAGRAM_BYTES,
    MAX_SESSION_CHARS,
    MAX_STATE_DATAGRAM_BYTES,
    MAX_TOKEN_CHARS,
    MIN_HELLO_BYTES,
    MIN_RATE_HZ,
    PROTOCOL_VERSION,
    REASONS,
    ROLES,
    SERVER_TYPES,
    TELEGRAPH_MAX,
    TELEGRAPH_MIN,
    ProtocolError,
    clamp,
    decode_object,
    dumps,
    get_int,
    get_number,
    get_seq,
    get_str,
    in_parts,
    num,
)
from vessel_gym.physics.bridge import BridgeReading

#: most thrusters and tugs one ship's helm orders (each a number of ``helm.assist``)
MAX_ASSIST = 8
ASSIST_KINDS = ("thruster", "tug")


@dataclass(frozen=True)
class AssistUnit:
    """A thruster or tug the helm orders besides rudder and engine: its ``name`` (the ship file's or the
    berth's) and ``kind`` (:data:`ASSIST_KINDS`). Its order is a fraction in [-1, 1], + towards starboard: a
    thruster's of its rated rpm, a tug's of its bollard pull along its line."""

    name: str
    kind: str

    def __post_init__(self) -> None:
        if self.kind not in ASSIST_KINDS:
            raise ValueError(
                f"AssistUnit {self.name!r}: kind must be one of {ASSIST_KINDS}, not {self.kind!r}"
            )


@dataclass(frozen=True)
class Limits:
    """What helm orders may say: rudder order clamped to +-``max_rudder_deg`` (deg), rpm order to +-``max_rpm``
    (rev/min); ``assist`` the ship's thrusters and tugs, in the order of ``helm.assist`` (none: a helm order
    carrying ``assist`` orders is refused)."""

    max_rudder_deg: float = 35.0
    max_rpm: float = 200.0
    assist: tuple[AssistUnit, ...] = ()

    def __post_init__(self) -> None:
        for name in ("max_rudder_deg", "max_rpm"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0.0 < value < 1e6:
                raise ValueError(f"Limits.{name} must be a positive number, not {value!r}")
        if len(self.assist) > MAX_ASSIST:
            raise ValueError(f"Limits.assist: {len(self.assist)} units, at most {MAX_ASSIST}")


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
    ``telegraph`` is a Telegraph step -4..4; ``rpm_order`` is in rev/min (negative astern); ``assist`` one
    order in [-1, 1] per thruster or tug of the ship (:class:`Limits` ``assist``; all 0 when the command
    carries none).
    """

    seq: int
    rudder_order_deg: float
    telegraph: int | None = None
    rpm_order: float | None = None
    session: str | None = None  # the sender's session (from its welcome); seq counts within it
    assist: tuple[float, ...] = ()


@dataclass(frozen=True)
class Bye:
    """The client leaves (releases the helm if it held it); ``session`` as in :class:`HelmCommand`."""

    session: str | None = None


@dataclass(frozen=True)
class StatsRequest:
    """Ask for one ``stats`` message now; only the client's own ``session`` gets an answer."""

    session: str | None = None


ClientMessage = Hello | HelmCommand | Bye | StatsRequest


def parse_datagram(
    data: bytes, limits: Limits = DEFAULT_LIMITS, default_rate_hz: float = 20.0
) -> ClientMessage:
    """Validate one client datagram and return its typed message, or raise :class:`ProtocolError`.

    Rejected: more than 2048 bytes, more than 32 ``[``/``{`` in total (``too_complex``), bad UTF-8, bad JSON (including nesting too deep to parse), NaN/Infinity or
    numbers that overflow a double, anything but an object, ``v`` other than 1, an unknown ``type``, and missing
    or ill-typed fields (booleans are not numbers). Clamped: ``rate_hz`` to 1-50, ``rudder_order_deg`` and
    ``rpm_order`` to ``limits``, ``telegraph`` to -4..4. ``assist`` (thruster and tug orders) is checked, not
    clamped: a list of exactly as many numbers in [-1, 1] as ``limits.assist`` has units. Unknown keys are
    ignored (forward compatibility).
    """
    obj = decode_object(data, MAX_DATAGRAM_BYTES, MAX_CONTAINERS)
    version = obj.get("v")
    if isinstance(version, bool) or version != PROTOCOL_VERSION:
        raise ProtocolError("bad_version")
    kind = obj.get("type")
    if kind == "helm":
        seq = get_seq(obj, required=True)
        rudder = get_number(obj, "rudder_order_deg", required=True)
        telegraph = get_int(obj, "telegraph", required=False)
        rpm_order = get_number(obj, "rpm_order", required=False)
        if (telegraph is None) == (rpm_order is None):
            raise ProtocolError("bad_field", "exactly one of telegraph and rpm_order")
        return HelmCommand(
            seq=seq,
            rudder_order_deg=clamp(rudder, -limits.max_rudder_deg, limits.max_rudder_deg),
            telegraph=None if telegraph is None else int(clamp(telegraph, TELEGRAPH_MIN, TELEGRAPH_MAX)),
            rpm_order=None if rpm_order is None else clamp(rpm_order, -limits.max_rpm, limits.max_rpm),
            session=get_str(obj, "session", MAX_SESSION_CHARS, truncate=False),
            assist=_assist_orders(obj, len(limits.assist)),
        )
    if kind == "hello":
        get_seq(obj, required=False)
        role = obj.get("role")
        if role not in ROLES:
            raise ProtocolError("bad_field", "role must be 'viewer' or 'helm'")
        rate = get_number(obj, "rate_hz", required=False)
        return Hello(
            role=role,
            rate_hz=clamp(default_rate_hz if rate is None else rate, MIN_RATE_HZ, MAX_RATE_HZ),
            name=get_str(obj, "name", MAX_NAME_CHARS) or "",
            token=get_str(obj, "token", MAX_TOKEN_CHARS, truncate=False),
            cookie=get_str(obj, "cookie", MAX_COOKIE_CHARS, truncate=False),
            session=get_str(obj, "session", MAX_SESSION_CHARS, truncate=False),
            proto=2 if (get_int(obj, "proto", required=False) or 1) >= 2 else 1,
        )
    if kind == "bye":
        get_seq(obj, required=False)
        return Bye(session=get_str(obj, "session", MAX_SESSION_CHARS, truncate=False))
    if kind == "stats_request":
        get_seq(obj, required=False)
        return StatsRequest(session=get_str(obj, "session", MAX_SESSION_CHARS, truncate=False))
    raise ProtocolError("bad_type")


def _assist_orders(obj: dict, units: int) -> tuple[float, ...]:
    """A helm command's thruster and tug orders: ``units`` zeros when it carries none, else its ``assist``
    list, which must hold one number in [-1, 1] per unit (a full order, never a delta)."""
    value = obj.get("assist")
    if value is None:
        return (0.0,) * units
    if not isinstance(value, list):
        raise ProtocolError("bad_field", "assist must be a list of numbers")
    if len(value) != units:
        raise ProtocolError(
            "bad_field", f"assist has {len(value)} orders; the ship has {units} thrusters/tugs"
        )
    out = []
    for j, o in enumerate(value):
        if isinstance(o, bool) or not isinstance(o, (int, float)):
            raise ProtocolError("bad_field", f"assist[{j}] must be a number")
        if not -1.0 <= o <= 1.0:
            raise ProtocolError("bad_field", f"assist[{j}] = {o!r} is outside -1..1")
        out.append(float(o))
    return tuple(out)


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


@dataclass(frozen=True)
class AssistReading:
    """A thruster's or tug's order and what it delivers now (thrust, or pull along its line, as a fraction of
    its maximum; both in [-1, 1], + towards starboard), for ``state.assist``."""

    name: str
    kind: str
    order: float
    delivered: float


@dataclass(frozen=True)
class StateExtras:
    """What a task adds to the own ship's ``state``: its thrusters and tugs (``assist``) and the load of each
    fender of its berth (``fender_load``: the larger of absorbed energy and compression, each over its rating;
    1 = rated). Empty fields are left out of the message."""

    assist: tuple[AssistReading, ...] = ()
    fender_load: tuple[float, ...] = ()


NO_EXTRAS = StateExtras()


def extras_fields(extras: StateExtras) -> dict[str, object]:
    """The ``assist`` and ``fender_load`` fields of a ``state`` message (none when empty)."""
    out: dict[str, object] = {}
    if extras.assist:
        out["assist"] = [
            {
                "name": a.name[:MAX_NAME_CHARS],
                "kind": a.kind,
                "order": num(a.order, 3),
                "delivered": num(a.delivered, 3),
            }
            for a in extras.assist
        ]
    if extras.fender_load:
        out["fender_load"] = [num(x, 3) for x in extras.fender_load]
    return out


def own_state_fields(own: BridgeReading) -> dict[str, float | int | None]:
    """The own-ship part of a ``state`` message (edge units, rounded to what a viewer can use); a ship with
    roll adds ``roll_deg`` and ``roll_rate_dps`` (a 3-DOF ship, which has no roll, leaves them out)."""
    roll = {}
    if own.roll_deg is not None:
        roll = {"roll_deg": num(own.roll_deg, 2), "roll_rate_dps": num(own.roll_rate_dps, 3)}
    return {
        "t_s": num(own.t_s, 3),
        "lat_deg": num(own.lat_deg, 7),
        "lon_deg": num(own.lon_deg, 7),
        "x_m": num(own.x_m, 2),
        "y_m": num(own.y_m, 2),
        "hdg_deg": num(own.hdg_deg, 2),
        "cog_deg": num(own.cog_deg, 2),
        "sog_kn": num(own.sog_kn, 3),
        "stw_kn": num(own.stw_kn, 3),
        "rot_dpm": num(own.rot_dpm, 2),
        "rudder_deg": num(own.rudder_deg, 2),
        "rudder_order_deg": num(own.rudder_order_deg, 2),
        "rpm": num(own.rpm, 1),
        "telegraph": int(own.telegraph),
        **roll,
    }


def target_fields(target: Target) -> dict[str, float | int | str | None]:
    """One entry of ``state.targets``."""
    r = target.reading
    return {
        "id": int(target.id),
        "name": target.name,
        "lat_deg": num(r.lat_deg, 7),
        "lon_deg": num(r.lon_deg, 7),
        "x_m": num(r.x_m, 2),
        "y_m": num(r.y_m, 2),
        "hdg_deg": num(r.hdg_deg, 2),
        "cog_deg": num(r.cog_deg, 2),
        "sog_kn": num(r.sog_kn, 3),
        "length_m": num(target.length_m, 2),
        "beam_m": num(target.beam_m, 2),
    }


def encode_state(
    seq: int,
    own: BridgeReading,
    helm_ok: bool,
    targets: Sequence[Target] = (),
    max_bytes: int = MAX_STATE_DATAGRAM_BYTES,
    extras: StateExtras = NO_EXTRAS,
) -> list[bytes]:
    """Encode a ``state`` message as one or more datagrams of at most ``max_bytes`` bytes; ``extras`` adds the
    thrusters, tugs and fenders of a berthing ship (:class:`StateExtras`).

    Usually one datagram (``"part":0,"parts":1``). With many targets the target list is split over ``parts``
    datagrams that repeat the own-ship fields and share ``seq``; a client merges the parts of one ``seq``.
    """
    head = {"v": PROTOCOL_VERSION, "type": "state", "seq": int(seq)}
    head.update(own_state_fields(own))
    head["helm_ok"] = bool(helm_ok)
    head.update(extras_fields(extras))
    fields = [target_fields(t) for t in targets]
    whole = dumps({**head, "targets": fields, "part": 0, "parts": 1}).encode()
    if len(whole) <= max_bytes:
        return [whole]
    prefix = dumps(head)[:-1] + ',"targets":['
    items = [dumps(f) for f in fields]
    tail_room = len('],"part":99,"parts":99}')
    room = max_bytes - len(prefix.encode()) - tail_room
    for item in items:
        n = len(item.encode()) + 1
        if n > room:
            raise ValueError(f"target entry of {n} bytes does not fit a {max_bytes}-byte state datagram")
    return in_parts(prefix, items, room)


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
    rules (with the ship's thrusters and tugs, ``assist``, where it has any), the client's ``session`` and a
    fresh ``cookie`` for its next hellos."""
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
    if limits.assist:
        msg["assist"] = [{"name": a.name[:MAX_NAME_CHARS], "kind": a.kind} for a in limits.assist]
    if cookie is not None:
        msg["cookie"] = cookie
    if session is not None:
        msg["session"] = session
    return dumps(msg).encode()


def encode_challenge(seq: int, cookie: str) -> bytes:
    """The short ``welcome`` to a hello without a valid cookie: only the cookie to echo (no session yet)."""
    return dumps({"v": PROTOCOL_VERSION, "type": "welcome", "seq": int(seq), "cookie": cookie}).encode()


def encode_stats(seq: int, t_s: float, counters: Mapping[str, int], clients: int) -> bytes:
    """A ``stats`` message: link counters (datagrams received, sent, dropped per reason) and live clients."""
    return dumps(
        {
            "v": PROTOCOL_VERSION,
            "type": "stats",
            "seq": int(seq),
            "t_s": num(t_s, 3),
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
    data = dumps(msg).encode()
    short = pad_to - len(data) - len(',"pad":""')
    if short > 0:
        msg["pad"] = "." * short
        data = dumps(msg).encode()
    return data


def encode_helm(
    seq: int,
    rudder_order_deg: float,
    telegraph: int | None = None,
    rpm_order: float | None = None,
    session: str | None = None,
    assist: Sequence[float] | None = None,
) -> bytes:
    """A full ``helm`` command; exactly one of ``telegraph`` (-4..4) and ``rpm_order`` (rev/min); ``session``
    from the sender's welcome; ``assist`` one order in [-1, 1] per thruster or tug the welcome named."""
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
    if assist is not None:
        msg["assist"] = [round(float(o), 4) for o in assist]
    return dumps(msg).encode()


def encode_bye(session: str | None = None) -> bytes:
    """A client's ``bye`` (with the session of its welcome)."""
    if session is None:
        return b'{"v":1,"type":"bye"}'
    return dumps({"v": PROTOCOL_VERSION, "type": "bye", "session": session}).encode()


def encode_stats_request(session: str | None = None) -> bytes:
    """Ask the server for a ``stats`` message (answered only with the session of the client's welcome)."""
    if session is None:
        return b'{"v":1,"type":"stats_request"}'
    return dumps({"v": PROTOCOL_VERSION, "type": "stats_request", "session": session}).encode()


def parse_server_datagram(data: bytes) -> dict:
    """Decode a server datagram (``welcome``/``state``/``stats``) into a dict, or raise :class:`ProtocolError`.

    The same size, UTF-8, JSON, finiteness, version and type checks as :func:`parse_datagram` (``state``
    datagrams may be up to 64 KiB); the fields themselves are returned as sent (``null`` = not available).
    """
    obj = decode_object(data, MAX_SERVER_DATAGRAM_BYTES)
    if obj.get("v") != PROTOCOL_VERSION or isinstance(obj.get("v"), bool):
        raise ProtocolError("bad_version")
    if obj.get("type") not in SERVER_TYPES:
        raise ProtocolError("bad_type")
    return obj
