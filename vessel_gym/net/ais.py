"""AIS (ITU-R M.1371) message encoding with NMEA 0183 6-bit armouring (``!AIVDM`` / ``!AIVDO``).

Implemented messages:

- type 1, Class A position report (168 bits, one sentence);
- type 5, static and voyage related data (424 bits, two sentences sharing a sequential message id).

The bit layouts follow ITU-R M.1371-5 Annex 8 as tabulated in gpsd's "AIVDM/AIVDO protocol decoding". Payload
bits are packed into 6-bit groups, each written as one character (values 0-39 -> ``0``-``W``, 40-63 -> `````-
``w``); the last sentence of a message states how many fill bits pad its payload to a multiple of 6.
"""

from __future__ import annotations

import math

from vessel_gym.net.nmea import MAX_SENTENCE_CHARS, sentence

# "Not available" values of the type 1 fields.
ROT_NOT_AVAILABLE = -128
SOG_NOT_AVAILABLE = 1023  # 0.1 kn units
LON_NOT_AVAILABLE = 181 * 600000  # 1/10000 min units
LAT_NOT_AVAILABLE = 91 * 600000
COG_NOT_AVAILABLE = 3600  # 0.1 deg units
HEADING_NOT_AVAILABLE = 511
SECOND_NOT_AVAILABLE = 60

# Navigational status codes (type 1, 4 bits).
NAV_UNDER_WAY_ENGINE = 0
NAV_AT_ANCHOR = 1
NAV_NOT_UNDER_COMMAND = 2
NAV_RESTRICTED_MANOEUVRABILITY = 3
NAV_MOORED = 5
NAV_NOT_DEFINED = 15

_SIXBIT_CHARS = "@ABCDEFGHIJKLMNOPQRSTUVWXYZ[\\]^_ !\"#$%&'()*+,-./0123456789:;<=>?"
_SIXBIT_INDEX = {c: i for i, c in enumerate(_SIXBIT_CHARS)}
_ARMOUR = [chr(v + 48) if v < 40 else chr(v + 56) for v in range(64)]


class _Bits:
    """Big-endian bit accumulator."""

    __slots__ = ("value", "length")

    def __init__(self) -> None:
        self.value = 0
        self.length = 0

    def uint(self, value: int, width: int) -> None:
        if not 0 <= value < (1 << width):
            raise ValueError(f"{value} does not fit {width} unsigned bits")
        self.value = (self.value << width) | value
        self.length += width

    def sint(self, value: int, width: int) -> None:
        if not -(1 << (width - 1)) <= value < (1 << (width - 1)):
            raise ValueError(f"{value} does not fit {width} signed bits")
        self.uint(value & ((1 << width) - 1), width)

    def text(self, value: str, chars: int) -> None:
        for c in sixbit_text(value, chars):
            self.uint(_SIXBIT_INDEX[c], 6)


def sixbit_text(value: str, chars: int) -> str:
    """``value`` in the AIS 6-bit character set: upper-cased, unknown characters as ``?``, ``@``-padded."""
    text = "".join(c if c in _SIXBIT_INDEX else "?" for c in value.upper()[:chars])
    return text + "@" * (chars - len(text))


def armour(bits: int, length: int) -> tuple[str, int]:
    """The armoured payload of ``length`` bits and its number of fill bits (0-5)."""
    fill = -length % 6
    value = bits << fill
    n = (length + fill) // 6
    chars = [_ARMOUR[(value >> (6 * (n - 1 - i))) & 0x3F] for i in range(n)]
    return "".join(chars), fill


def encode_rot(rot_dpm: float | None) -> int:
    """AIS rate-of-turn code: ``round(4.733 * sqrt(|ROT|))`` with the sign of ROT, limited to +-126.

    ``rot_dpm`` is in deg/min, positive to starboard; None or non-finite gives -128 (not available).
    """
    if rot_dpm is None or not math.isfinite(rot_dpm):
        return ROT_NOT_AVAILABLE
    code = min(round(4.733 * math.sqrt(abs(rot_dpm))), 126)
    return -code if rot_dpm < 0.0 else code


def decode_rot(code: int) -> float | None:
    """Inverse of :func:`encode_rot` (deg/min); None for the special codes -128, -127 and 127."""
    if abs(code) >= 127:
        return None
    return math.copysign((code / 4.733) ** 2, code)


def _sog_code(sog_kn: float | None) -> int:
    if sog_kn is None or not math.isfinite(sog_kn):
        return SOG_NOT_AVAILABLE
    return min(max(round(sog_kn * 10.0), 0), 1022)


def _angle_code(value_deg: float | None, scale: float, modulo: int, missing: int) -> int:
    if value_deg is None or not math.isfinite(value_deg):
        return missing
    return round((value_deg % 360.0) * scale) % modulo


def _position_code(value_deg: float | None, limit: float, missing: int) -> int:
    if value_deg is None or not math.isfinite(value_deg) or abs(value_deg) > limit:
        return missing
    return round(value_deg * 600000.0)


def _sentences(
    payload: str, fill: int, channel: str, talker: str, formatter: str, seq_id: int | None
) -> list[str]:
    # The largest payload that keeps every fragment within 82 characters.
    header = len(f"!{talker}{formatter},9,9,{'' if seq_id is None else seq_id},{channel},")
    room = MAX_SENTENCE_CHARS - header - len(",0*hh\r\n")
    chunks = [payload[i : i + room] for i in range(0, len(payload), room)] or [""]
    if len(chunks) > 9:
        raise ValueError("AIS message needs more than 9 fragments")
    if len(chunks) > 1 and seq_id is None:
        raise ValueError("a multi-fragment AIS message needs a sequential message id")
    seq = "" if seq_id is None else str(seq_id)
    out = []
    for i, chunk in enumerate(chunks):
        last = i == len(chunks) - 1
        fields = [str(len(chunks)), str(i + 1), seq, channel, chunk, str(fill if last else 0)]
        out.append(sentence(talker, formatter, fields, start="!"))
    return out


def _check_common(mmsi: int, channel: str, own: bool) -> str:
    if not 0 <= mmsi < (1 << 30):
        raise ValueError(f"MMSI {mmsi} does not fit 30 bits")
    if channel not in ("A", "B"):
        raise ValueError(f"AIS radio channel must be 'A' or 'B', not {channel!r}")
    return "VDO" if own else "VDM"


def position_report(
    mmsi: int,
    lat_deg: float | None,
    lon_deg: float | None,
    sog_kn: float | None,
    cog_deg: float | None,
    hdg_deg: float | None,
    rot_dpm: float | None,
    utc_second: int | None,
    *,
    nav_status: int = NAV_UNDER_WAY_ENGINE,
    accuracy: bool = False,
    channel: str = "A",
    own: bool = False,
    talker: str = "AI",
) -> list[str]:
    """Type 1 Class A position report as one ``!AIVDM`` (``!AIVDO`` if ``own``) sentence with CRLF.

    Units: lat/lon deg (sent in 1/10000 min), SOG kn (0.1 kn, 102.2 kn max), COG deg T (0.1 deg), heading deg T
    (rounded to whole degrees), ROT deg/min (AIS square-root code), ``utc_second`` 0-59 of the report time.
    None or non-finite values are sent as "not available".
    """
    formatter = _check_common(mmsi, channel, own)
    if not 0 <= nav_status <= 15:
        raise ValueError(f"navigational status {nav_status} is not 0-15")
    second = SECOND_NOT_AVAILABLE if utc_second is None else int(utc_second)
    if not 0 <= second <= 63:
        raise ValueError(f"timestamp second {utc_second} is not 0-63")
    b = _Bits()
    b.uint(1, 6)  # message type
    b.uint(0, 2)  # repeat indicator
    b.uint(mmsi, 30)
    b.uint(nav_status, 4)
    b.sint(encode_rot(rot_dpm), 8)
    b.uint(_sog_code(sog_kn), 10)
    b.uint(1 if accuracy else 0, 1)
    b.sint(_position_code(lon_deg, 180.0, LON_NOT_AVAILABLE), 28)
    b.sint(_position_code(lat_deg, 90.0, LAT_NOT_AVAILABLE), 27)
    b.uint(_angle_code(cog_deg, 10.0, 3600, COG_NOT_AVAILABLE), 12)
    b.uint(_angle_code(hdg_deg, 1.0, 360, HEADING_NOT_AVAILABLE), 9)
    b.uint(second, 6)
    b.uint(0, 2)  # manoeuvre indicator: not available
    b.uint(0, 3)  # spare
    b.uint(0, 1)  # RAIM
    b.uint(0, 19)  # radio status (SOTDMA sync state 0, no slot data)
    payload, fill = armour(b.value, b.length)
    return _sentences(payload, fill, channel, talker, formatter, None)


def static_voyage(
    mmsi: int,
    *,
    imo: int = 0,
    call_sign: str = "",
    name: str = "",
    ship_type: int = 0,
    to_bow_m: float = 0.0,
    to_stern_m: float = 0.0,
    to_port_m: float = 0.0,
    to_starboard_m: float = 0.0,
    draught_m: float = 0.0,
    destination: str = "",
    eta: tuple[int, int, int, int] | None = None,
    seq_id: int = 0,
    channel: str = "A",
    own: bool = False,
    talker: str = "AI",
) -> list[str]:
    """Type 5 static and voyage data as two ``!AIVDM`` sentences with sequential message id ``seq_id`` (0-9).

    Units: dimensions from the position reference to bow/stern/port/starboard in m (whole metres, 511/63 max),
    draught in m (0.1 m, 25.5 max), ``eta`` as (month, day, hour, minute) UTC or None (not available). Text is
    upper-cased into the AIS character set: call sign 7, name and destination 20 characters. EPFD is 1 (GPS).
    """
    formatter = _check_common(mmsi, channel, own)
    if not 0 <= seq_id <= 9:
        raise ValueError(f"sequential message id {seq_id} is not 0-9")
    if not 0 <= imo < (1 << 30):
        raise ValueError(f"IMO number {imo} does not fit 30 bits")
    if not 0 <= ship_type <= 255:
        raise ValueError(f"ship type {ship_type} is not 0-255")
    month, day, hour, minute = (0, 0, 24, 60) if eta is None else eta

    def dim(value: float, top: int) -> int:
        return min(max(round(value), 0), top) if math.isfinite(value) else 0

    b = _Bits()
    b.uint(5, 6)  # message type
    b.uint(0, 2)  # repeat indicator
    b.uint(mmsi, 30)
    b.uint(0, 2)  # AIS version: ITU-R M.1371-1
    b.uint(imo, 30)
    b.text(call_sign, 7)
    b.text(name, 20)
    b.uint(ship_type, 8)
    b.uint(dim(to_bow_m, 511), 9)
    b.uint(dim(to_stern_m, 511), 9)
    b.uint(dim(to_port_m, 63), 6)
    b.uint(dim(to_starboard_m, 63), 6)
    b.uint(1, 4)  # EPFD: GPS
    b.uint(month, 4)
    b.uint(day, 5)
    b.uint(hour, 5)
    b.uint(minute, 6)
    b.uint(dim(draught_m * 10.0, 255), 8)
    b.text(destination, 20)
    b.uint(0, 1)  # DTE: data terminal ready
    b.uint(0, 1)  # spare
    payload, fill = armour(b.value, b.length)
    return _sentences(payload, fill, channel, talker, formatter, seq_id)
