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


def parse_datagram(
    data: bytes, limits: Limits = DEFAULT_LIMITS, default_rate_hz: float = 20.0
) -> ClientMessage:
    """Validate one client datagram and return its typed message, or raise :class:`ProtocolError`.

    Rejected: more than 2048 bytes, more than 32 ``[``/``{`` in total (``too_complex``), bad UTF-8, bad JSON (including nesting too deep to parse), NaN/Infinity or
    numbers that overflow a double, anything but an object, ``v`` other than 1, an unknown ``type``, and missing
    or ill-typed fields (booleans are not numbers). Clamped: ``rate_hz`` to 1-50, ``rudder_order_deg`` and
    ``rpm_order`` to ``limits``, ``telegraph`` to -4..4. Unknown keys are ignored (forward compatibility).
    """
    if len(data) > MAX_DATAGRAM_BYTES:
        raise ProtocolError("oversize", f"{len(data)} bytes")
    if data.count(b"[") + data.count(b"{") > MAX_CONTAINERS:
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
    chunks: list[list[str]] = [[]]
    size = 0
    for item in items:
        n = len(item.encode()) + 1
        if n > room:
            raise ValueError(f"target entry of {n} bytes does not fit a {max_bytes}-byte state datagram")
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
) -> bytes:
    """A client's ``hello`` (send on start and at least once a second as keep-alive).

    ``cookie`` and ``session`` are echoed from the last ``welcome``. The datagram is padded with a ``pad``
    field to ``pad_to`` bytes, so that a server that does not (or no longer) knows the sender may answer it.
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
    if len(data) > 65536:
        raise ProtocolError("oversize", f"{len(data)} bytes")
    try:
        obj = _DECODER.decode(data.decode("utf-8"))
    except UnicodeDecodeError:
        raise ProtocolError("bad_utf8") from None
    except _NonFinite:
        raise ProtocolError("non_finite") from None
    except (ValueError, RecursionError):
        raise ProtocolError("bad_json") from None
    if not isinstance(obj, dict):
        raise ProtocolError("not_object")
    if obj.get("v") != PROTOCOL_VERSION or isinstance(obj.get("v"), bool):
        raise ProtocolError("bad_version")
    if obj.get("type") not in SERVER_TYPES:
        raise ProtocolError("bad_type")
    return obj
