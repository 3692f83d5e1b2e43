"""NMEA 0183 output: sentence framing, checksums and the own-ship sentence set.

Every sentence is ``$`` (or ``!`` for encapsulated AIS) + talker (2 chars) + formatter (3 chars) + comma
separated fields + ``*`` + checksum (2 upper-case hex digits) + CRLF, at most 82 characters in total
(IEC 61162-1). Numbers are written with a fixed number of decimals; unknown values are empty fields, never ``0.0``.

Own-ship sentences (default talkers in brackets; gpsd 3.22 as shipped by Debian 12 drops the semantically correct
``HE``/``VW``/``ER``/``AG`` talkers, so instruments default to ``II``):

========  =====  =====================================================================
sentence  talker content
========  =====  =====================================================================
RMC       GP     UTC, status A, position, SOG (kn), COG (deg T), date, mode S (simulator)
GGA       GP     UTC, position, quality 1 (gpsd 3.22 reports no fix for 8 "simulation")
VTG       GP     COG (deg T), SOG (kn, km/h), mode S
HDT       II     true heading (deg)
ROT       II     rate of turn (deg/min, negative = bow turning to port)
RSA       II     rudder angle (deg, negative = rudder to port)
RPM       II     shaft 0 revolutions (rev/min, negative = astern)
VHW       II     heading (deg T), longitudinal speed through water (kn, km/h)
MWV       II     apparent wind angle from the bow (deg), apparent wind speed (kn)
GLL       GP     position, UTC (optional)
ZDA       GP     UTC date and time (optional)
PASHR     -      heading and heel as an attitude sentence (proprietary, no talker; before HDT); ships with roll only
XDR       II     heel: angular-displacement transducer ROLL (deg, + = starboard side down); ships with roll only
========  =====  =====================================================================

Heel goes out twice because no one sentence reaches every reader: XDR (type A, unit D, name ROLL) is the standard
transducer sentence that chartplotter dashboards and newer gpsd read, while gpsd 3.22 (Debian 12) ignores XDR but
turns ``$PASHR`` into an ATT report with ``roll``. A 3-DOF ship has no heel and sends neither.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from datetime import datetime, timezone
from typing import NamedTuple

from vessel_gym.physics.bridge import BridgeReading

MAX_SENTENCE_CHARS = 82  # IEC 61162-1: 80 visible characters + CR LF
KMH_PER_KN = 1.852  # km/h per knot (exact)

_TALKER_RE = re.compile(r"[A-Z][A-Z0-9]\Z")
_FORMATTER_RE = re.compile(r"[A-Z][A-Z0-9]{2}\Z")
# Characters a field may not hold: NMEA reserved characters (IEC 61162-1 Table 1) and anything not printable ASCII.
_BAD_FIELD_CHAR = re.compile(r"[^\x20-\x7e]|[$!*,\\^~]")


class NmeaError(ValueError):
    """A sentence cannot be framed (bad talker/formatter, reserved character, or longer than 82 chars)."""


def checksum(body: str) -> str:
    """XOR of the characters of ``body`` (the text strictly between ``$``/``!`` and ``*``), 2 upper-case hex."""
    # Fold the bytes as one integer, halving its width each round: the XOR of all bytes is preserved and the
    # loop runs log2(len) times instead of once per character.
    data = body.encode("ascii")
    value = int.from_bytes(data, "little")
    width = len(data)
    while width > 1:
        half = (width + 1) // 2
        value = (value & ((1 << (8 * half)) - 1)) ^ (value >> (8 * half))
        width = half
    return f"{value:02X}"


def sentence(talker: str, formatter: str, fields: Iterable[str], start: str = "$") -> str:
    """Frame one sentence: ``start`` + talker + formatter + ``,fields`` + ``*hh`` + CRLF.

    Raises :class:`NmeaError` if the talker or formatter is malformed, a field holds a reserved character
    (``$ ! * , \\ ^ ~`` or CR/LF) or a non-printable one, or the framed sentence exceeds 82 characters.
    """
    if start not in ("$", "!"):
        raise NmeaError(f"start must be '$' or '!', not {start!r}")
    if not _TALKER_RE.match(talker):
        raise NmeaError(f"talker id must be 2 upper-case characters, not {talker!r}")
    if not _FORMATTER_RE.match(formatter):
        raise NmeaError(f"sentence formatter must be 3 upper-case characters, not {formatter!r}")
    fields = list(fields)
    if _BAD_FIELD_CHAR.search("".join(fields)):
        bad = next(f for f in fields if _BAD_FIELD_CHAR.search(f))
        raise NmeaError(f"field {bad!r} holds a reserved or non-printable character")
    body = talker + formatter + "," + ",".join(fields)
    text = f"{start}{body}*{checksum(body)}\r\n"
    if len(text) > MAX_SENTENCE_CHARS:
        raise NmeaError(f"{talker}{formatter} sentence is {len(text)} characters (max {MAX_SENTENCE_CHARS})")
    return text


def verify(line: str) -> bool:
    """True if ``line`` is a framed sentence (``$``/``!``, ``*hh``, optional CRLF) whose checksum matches."""
    text = line.rstrip("\r\n")
    if len(text) < 4 or text[0] not in "$!" or text[-3] != "*":
        return False
    return checksum(text[1:-3]) == text[-2:].upper()


# ---------------------------------------------------------------------------------------------------------------
# Field formatting


def _finite(value: float | None) -> bool:
    return value is not None and math.isfinite(value)


def fmt_num(value: float | None, decimals: int) -> str:
    """Fixed-decimal number, ``""`` when unknown (None or non-finite); never ``-0.0``."""
    if not _finite(value):
        return ""
    return f"{round(value, decimals) + 0.0:.{decimals}f}"


def fmt_angle(value: float | None, decimals: int = 1) -> str:
    """Angle in [0, 360) with fixed decimals (``359.96`` -> ``"0.0"``), ``""`` when unknown."""
    if not _finite(value):
        return ""
    text = f"{round(value % 360.0, decimals) + 0.0:.{decimals}f}"
    return fmt_num(0.0, decimals) if float(text) >= 360.0 else text


def _fmt_dm(value_deg: float, deg_digits: int, decimals: int) -> str:
    # Work in integer units of 10^-decimals minutes so rounding can never print "60.0000" minutes.
    scale = 10**decimals
    units = round(abs(value_deg) * 60.0 * scale)
    degrees, rest = divmod(units, 60 * scale)
    minutes, frac = divmod(rest, scale)
    return f"{degrees:0{deg_digits}d}{minutes:02d}.{frac:0{decimals}d}"


def fmt_lat(lat_deg: float | None, decimals: int = 4) -> tuple[str, str]:
    """Latitude as (``ddmm.mmmm``, ``N``/``S``); ``("", "")`` when unknown or outside [-90, 90]."""
    if not _finite(lat_deg) or abs(lat_deg) > 90.0:
        return "", ""
    return _fmt_dm(lat_deg, 2, decimals), ("S" if lat_deg < 0.0 else "N")


def fmt_lon(lon_deg: float | None, decimals: int = 4) -> tuple[str, str]:
    """Longitude as (``dddmm.mmmm``, ``E``/``W``), wrapped to [-180, 180); ``("", "")`` when unknown."""
    if not _finite(lon_deg):
        return "", ""
    lon = (lon_deg + 180.0) % 360.0 - 180.0
    return _fmt_dm(lon, 3, decimals), ("W" if lon < 0.0 else "E")


def _as_utc(utc: datetime) -> datetime:
    # A naive datetime is taken to be UTC already.
    return utc.replace(tzinfo=timezone.utc) if utc.tzinfo is None else utc.astimezone(timezone.utc)


def fmt_time(utc: datetime) -> str:
    """UTC time of day as ``hhmmss.ss`` (truncated to 0.01 s)."""
    utc = _as_utc(utc)
    return f"{utc.hour:02d}{utc.minute:02d}{utc.second:02d}.{utc.microsecond // 10000:02d}"


def fmt_date(utc: datetime) -> str:
    """UTC date as ``ddmmyy``."""
    utc = _as_utc(utc)
    return f"{utc.day:02d}{utc.month:02d}{utc.year % 100:02d}"


# ---------------------------------------------------------------------------------------------------------------
# Own-ship sentence set


@dataclass(frozen=True)
class Talkers:
    """Talker ids per instrument group (2 upper-case characters each).

    The defaults are what gpsd 3.22 (Debian 12) and OpenCPN both accept. With gpsd >= 3.23.1 ``heading="HE"``
    is the semantically correct gyro talker.
    """

    gnss: str = "GP"  # RMC, GGA, VTG, GLL, ZDA
    heading: str = "II"  # HDT, ROT
    log: str = "II"  # VHW
    steering: str = "II"  # RSA
    engine: str = "II"  # RPM
    wind: str = "II"  # MWV

    def __post_init__(self) -> None:
        for name in ("gnss", "heading", "log", "steering", "engine", "wind"):
            value = getattr(self, name)
            if not isinstance(value, str) or not _TALKER_RE.match(value):
                raise ValueError(f"Talkers.{name} must be 2 upper-case characters, not {value!r}")


DEFAULT_TALKERS = Talkers()


class _Fix(NamedTuple):
    """Time and position fields shared by the sentences of one cycle (formatted once)."""

    time: str
    date: str
    lat: str
    ns: str
    lon: str
    ew: str

    @property
    def valid(self) -> bool:
        return bool(self.lat and self.lon)


def _fix(reading: BridgeReading, utc: datetime) -> _Fix:
    utc = _as_utc(utc)
    return _Fix(fmt_time(utc), fmt_date(utc), *fmt_lat(reading.lat_deg), *fmt_lon(reading.lon_deg))


def _rmc(reading: BridgeReading, f: _Fix, talker: str) -> str:
    status = "A" if f.valid else "V"
    fields = [
        f.time,
        status,
        f.lat,
        f.ns,
        f.lon,
        f.ew,
        fmt_num(reading.sog_kn, 2),
        fmt_angle(reading.cog_deg),
    ]
    fields += [f.date, "", "", "S" if f.valid else "N"]
    return sentence(talker, "RMC", fields)


def _gga(f: _Fix, talker: str) -> str:
    quality = "1" if f.valid else "0"
    fields = [f.time, f.lat, f.ns, f.lon, f.ew, quality, "08", "1.0", "0.0", "M", "0.0", "M", "", ""]
    return sentence(talker, "GGA", fields)


def _gll(f: _Fix, talker: str) -> str:
    fields = [f.lat, f.ns, f.lon, f.ew, f.time, "A" if f.valid else "V", "S" if f.valid else "N"]
    return sentence(talker, "GLL", fields)


def rmc(reading: BridgeReading, utc: datetime, talker: str = "GP") -> str:
    """RMC: UTC, status A, position, SOG (kn, 2 dp), COG (deg T, 1 dp), date, no magvar, mode S.

    Without a position the status is V and the mode N.
    """
    return _rmc(reading, _fix(reading, utc), talker)


def gga(reading: BridgeReading, utc: datetime, talker: str = "GP") -> str:
    """GGA: UTC, position, quality 1 (GPS), 8 satellites, HDOP 1.0, altitude 0.0 m, geoid separation 0.0 m.

    Without a position the quality is 0.
    """
    return _gga(_fix(reading, utc), talker)


def vtg(reading: BridgeReading, talker: str = "GP") -> str:
    """VTG: COG (deg T), no magnetic course, SOG in kn and km/h, mode S."""
    sog = reading.sog_kn
    kmh = sog * KMH_PER_KN if _finite(sog) else None
    fields = [fmt_angle(reading.cog_deg), "T", "", "M", fmt_num(sog, 2), "N", fmt_num(kmh, 2), "K", "S"]
    return sentence(talker, "VTG", fields)


def hdt(reading: BridgeReading, talker: str = "II") -> str:
    """HDT: true heading (deg, 1 dp)."""
    return sentence(talker, "HDT", [fmt_angle(reading.hdg_deg), "T"])


def rot(reading: BridgeReading, talker: str = "II") -> str:
    """ROT: rate of turn (deg/min, 1 dp, negative = bow turning to port), status A/V."""
    value = fmt_num(reading.rot_dpm, 1)
    return sentence(talker, "ROT", [value, "A" if value else "V"])


def rsa(reading: BridgeReading, talker: str = "II") -> str:
    """RSA: single (starboard) rudder angle (deg, 1 dp, negative = to port), port rudder field empty."""
    value = fmt_num(reading.rudder_deg, 1)
    return sentence(talker, "RSA", [value, "A" if value else "V", "", "V"])


def rpm(reading: BridgeReading, talker: str = "II", shaft: int = 0) -> str:
    """RPM: source S (shaft), shaft number (0 = single/centreline), rev/min (1 dp, negative = astern)."""
    value = fmt_num(reading.rpm, 1)
    return sentence(talker, "RPM", ["S", str(shaft), value, "", "A" if value else "V"])


def vhw(reading: BridgeReading, talker: str = "II") -> str:
    """VHW: heading (deg T), no magnetic heading, longitudinal speed through water in kn and km/h."""
    stw = reading.stw_kn
    kmh = stw * KMH_PER_KN if _finite(stw) else None
    fields = [fmt_angle(reading.hdg_deg), "T", "", "M", fmt_num(stw, 2), "N", fmt_num(kmh, 2), "K"]
    return sentence(talker, "VHW", fields)


def mwv(reading: BridgeReading, talker: str = "II") -> str:
    """MWV: apparent (relative, R) wind angle from the bow (deg) and speed (kn), status A/V."""
    angle = fmt_angle(reading.wind_rel_angle_deg)
    speed = fmt_num(reading.wind_rel_speed_kn, 1)
    return sentence(talker, "MWV", [angle, "R", speed, "N", "A" if angle and speed else "V"])


def xdr_roll(reading: BridgeReading, talker: str = "II") -> str:
    """XDR: one angular-displacement (A) transducer in degrees (D) named ROLL, the heel (2 dp, + = starboard
    side down, i.e. clockwise seen from astern, as XDR angles are signed)."""
    return sentence(talker, "XDR", ["A", fmt_num(reading.roll_deg, 2), "D", "ROLL"])


def pashr(reading: BridgeReading, utc: datetime) -> str:
    """PASHR attitude: UTC, true heading (2 dp) and T, roll (2 dp, + = port side up, i.e. starboard side down,
    as the heel), then pitch, heave and the three accuracies empty (the model has no pitch or heave), GNSS
    quality 1 as in GGA, alignment status empty."""
    fields = [fmt_time(utc), fmt_num(reading.hdg_deg, 2), "T", fmt_num(reading.roll_deg, 2)]
    # proprietary: P + manufacturer ASH + R; framed as talker "PA" and formatter "SHR", which gives the same text
    return sentence("PA", "SHR", fields + ["", "", "", "", "", "1", ""])


def gll(reading: BridgeReading, utc: datetime, talker: str = "GP") -> str:
    """GLL: position, UTC, status A, mode S."""
    return _gll(_fix(reading, utc), talker)


def zda(utc: datetime, talker: str = "GP") -> str:
    """ZDA: UTC time, day, month, 4-digit year, local zone 00:00."""
    u = _as_utc(utc)
    return sentence(
        talker, "ZDA", [fmt_time(u), f"{u.day:02d}", f"{u.month:02d}", f"{u.year:04d}", "00", "00"]
    )


def own_ship_sentences(
    reading: BridgeReading,
    utc: datetime,
    talkers: Talkers = DEFAULT_TALKERS,
    *,
    gll_sentence: bool = False,
    zda_sentence: bool = False,
) -> list[str]:
    """One full cycle of own-ship sentences for ``reading`` at time ``utc`` (CRLF-terminated strings).

    Order: RMC, GGA, [GLL], VTG, [ZDA], [PASHR], HDT, ROT, RSA, RPM, VHW, MWV, [XDR] (the bracketed PASHR and
    XDR only for a ship with roll). Position sentences come first so that a receiver that learns the cycle end
    from the first sentence type sees the full fix. PASHR goes just before HDT: gpsd 3.22 sends its ATT report
    on HDT, which then carries this cycle's heel (after HDT the heel waits a cycle and is cleared), and a timed
    PASHR at the end of the cycle would become gpsd's cycle ender and stop its TPV reports (probed).
    """
    f = _fix(reading, utc)
    out = [_rmc(reading, f, talkers.gnss), _gga(f, talkers.gnss)]
    if gll_sentence:
        out.append(_gll(f, talkers.gnss))
    out.append(vtg(reading, talkers.gnss))
    if zda_sentence:
        out.append(zda(utc, talkers.gnss))
    if reading.roll_deg is not None:
        out.append(pashr(reading, utc))
    out.append(hdt(reading, talkers.heading))
    out += [
        rot(reading, talkers.heading),
        rsa(reading, talkers.steering),
        rpm(reading, talkers.engine),
        vhw(reading, talkers.log),
        mwv(reading, talkers.wind),
    ]
    if reading.roll_deg is not None:
        out.append(xdr_roll(reading, talkers.heading))
    return out


def pack_datagrams(sentences: Sequence[str], max_bytes: int = 1400) -> list[bytes]:
    """Pack whole CRLF-terminated sentences into as few datagrams of at most ``max_bytes`` as possible.

    Order is preserved and a sentence is never split across datagrams. Raises ``ValueError`` if one sentence
    alone is longer than ``max_bytes`` or lacks its CRLF terminator.
    """
    datagrams: list[bytes] = []
    current = bytearray()
    for text in sentences:
        data = text.encode("ascii")
        if not data.endswith(b"\r\n"):
            raise ValueError(f"sentence {text!r} is not CRLF-terminated")
        if len(data) > max_bytes:
            raise ValueError(f"sentence of {len(data)} bytes does not fit a {max_bytes}-byte datagram")
        if len(current) + len(data) > max_bytes:
            datagrams.append(bytes(current))
            current = bytearray()
        current += data
    if current:
        datagrams.append(bytes(current))
    return datagrams
