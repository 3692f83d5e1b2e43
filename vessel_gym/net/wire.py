"""The wire format every message of the JSON channel shares (v1 and v2): versions, size and field limits,
message types, the reason codes of :class:`ProtocolError`, the checked decoding of a datagram into a JSON object
and its field readers, and the compact JSON encoding with its splitting into datagram parts."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence

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
    """A datagram that is not a valid message. ``reason`` is one of :data:`REASONS`."""

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


_MISSING = object()


def get_number(obj: Mapping, key: str, required: bool) -> int | float | None:
    value = obj.get(key, _MISSING)
    if value is _MISSING or (value is None and not required):
        if required:
            raise ProtocolError("bad_field", f"missing {key}")
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ProtocolError("bad_field", f"{key} must be a number")
    return value


def clamp(value: int | float, low: float, high: float) -> float:
    # Compare before converting: int -> float would overflow for integers beyond 1e308.
    if value < low:
        return float(low)
    if value > high:
        return float(high)
    return float(value)


def get_int(obj: Mapping, key: str, required: bool) -> int | None:
    value = obj.get(key, _MISSING)
    if value is _MISSING or (value is None and not required):
        if required:
            raise ProtocolError("bad_field", f"missing {key}")
        return None
    if isinstance(value, bool) or not isinstance(value, int):
        raise ProtocolError("bad_field", f"{key} must be an integer")
    return value


def get_str(obj: Mapping, key: str, max_chars: int, truncate: bool = True) -> str | None:
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


def get_seq(obj: Mapping, required: bool) -> int | None:
    seq = get_int(obj, "seq", required)
    if seq is not None and not 0 <= seq <= MAX_SEQ:
        raise ProtocolError("bad_field", "seq must be 0..2^53-1")
    return seq


def decode_object(data: bytes, max_bytes: int, max_containers: int | None = None) -> dict:
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


def num(value: float | None, decimals: int) -> float | None:
    """Rounded number for JSON, None (null) when unknown or non-finite."""
    if value is None or not math.isfinite(value):
        return None
    return round(float(value), decimals)


def dumps(obj: Mapping) -> str:
    return json.dumps(obj, allow_nan=False, separators=(",", ":"))


def in_parts(prefix: str, items: Sequence[str], room: int) -> list[bytes]:
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
