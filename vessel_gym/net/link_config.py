"""The strict, immutable configuration of a UDP link (:class:`LinkConfig`): addresses, rates, limits, token,
failsafe policy. Unknown keys and bad values raise ``ValueError`` naming the key and the allowed range."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from datetime import datetime

from vessel_gym.net import nmea
from vessel_gym.net.access import Address
from vessel_gym.net.helm_owner import FAILSAFE_POLICIES
from vessel_gym.net.protocol import MAX_RATE_HZ, MIN_RATE_HZ, Limits


def _check_number(name: str, value: object, low: float, high: float) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"LinkConfig.{name} must be a number, not {value!r}")
    if not low <= value <= high:
        raise ValueError(f"LinkConfig.{name} = {value} is outside [{low}, {high}]")
    return float(value)


def _check_address(name: str, value: object, port_zero_ok: bool) -> Address:
    if (
        not isinstance(value, (tuple, list))
        or len(value) != 2
        or not isinstance(value[0], str)
        or isinstance(value[1], bool)
        or not isinstance(value[1], int)
    ):
        raise ValueError(f"LinkConfig.{name} must be a (host, port) pair, not {value!r}")
    host, port = value
    if not (0 if port_zero_ok else 1) <= port <= 65535:
        raise ValueError(f"LinkConfig.{name}: port {port} is out of range")
    return (host, port)


@dataclass(frozen=True)
class LinkConfig:
    """Strict, immutable configuration of a :class:`~vessel_gym.net.link.UdpLink`. Unknown keys and bad values raise ``ValueError``.

    Build it with keyword arguments or from a mapping with :meth:`from_dict`. Addresses are ``(host, port)``;
    hosts are IPv4 addresses or names resolved once when the link opens.
    """

    nmea_destinations: tuple[Address, ...] = (("127.0.0.1", 10110),)  # NMEA/AIS receivers; () = no NMEA
    nmea_rate_hz: float = 2.0  # own-ship sentence cycles per second, 1-10
    talkers: nmea.Talkers = nmea.DEFAULT_TALKERS
    nmea_gll: bool = False  # add GLL to each cycle
    nmea_zda: bool = False  # add ZDA to each cycle
    ais_position_interval_s: float = 2.0  # type 1 reports of each target with an MMSI, s (0.1-180)
    ais_static_interval_s: float = 180.0  # type 5 static/voyage data of each target, s (10-3600)
    json_bind: Address = ("127.0.0.1", 10120)  # JSON channel socket; port 0 = any free port
    json_static_destinations: tuple[Address, ...] = ()  # listen-only viewers that get state without hello
    static_rate_hz: float = 20.0  # state rate to the static destinations, 1-50 Hz
    default_rate_hz: float = 20.0  # state rate for a hello without rate_hz, 1-50 Hz
    allow_remote: bool = False  # binding to a non-loopback address requires this
    token: str | None = None  # if set, a hello must carry this token
    max_rate_per_client_hz: float = 200.0  # datagrams/s in one client's session (burst: 1 s of it), 10-1e5
    unverified_rate_per_host_hz: float = 100.0  # datagrams/s without a session from one IP address, 10-1e5
    unverified_rate_total_hz: float = 1000.0  # datagrams/s without a session from everyone together, 10-1e6
    failsafe: str = "hold"  # "hold" | "midships_stop"
    watchdog_s: float = 1.0  # helm silence after which the owner loses the helm, s (0.1-10)
    client_timeout_s: float = 3.0  # silence after which a client is dropped, s (0.5-60)
    max_clients: int = 16
    max_clients_per_host: int = 8  # client slots one IP address may hold
    stats_interval_s: float = 5.0  # period of unsolicited stats messages to clients, s (0.5-3600)
    max_datagrams_per_call: int = 2048  # receive budget per service() call (datagrams)
    max_receive_ms: float = 2.0  # receive budget per service() call (ms of wall-clock time), 0.1-100
    limits: Limits = field(default_factory=Limits)
    utc_epoch: datetime | None = None  # UTC at simulation time 0; None = wall clock at the first service()

    def __post_init__(self) -> None:
        def put(name: str, value: object) -> None:
            object.__setattr__(self, name, value)

        if not isinstance(self.nmea_destinations, (tuple, list)):
            raise ValueError("LinkConfig.nmea_destinations must be a list of (host, port) pairs")
        put(
            "nmea_destinations",
            tuple(_check_address("nmea_destinations", a, False) for a in self.nmea_destinations),
        )
        if not isinstance(self.json_static_destinations, (tuple, list)):
            raise ValueError("LinkConfig.json_static_destinations must be a list of (host, port) pairs")
        put(
            "json_static_destinations",
            tuple(
                _check_address("json_static_destinations", a, False) for a in self.json_static_destinations
            ),
        )
        put("json_bind", _check_address("json_bind", self.json_bind, True))
        put("nmea_rate_hz", _check_number("nmea_rate_hz", self.nmea_rate_hz, 1.0, 10.0))
        put(
            "ais_position_interval_s",
            _check_number("ais_position_interval_s", self.ais_position_interval_s, 0.1, 180.0),
        )
        put(
            "ais_static_interval_s",
            _check_number("ais_static_interval_s", self.ais_static_interval_s, 10.0, 3600.0),
        )
        put("static_rate_hz", _check_number("static_rate_hz", self.static_rate_hz, MIN_RATE_HZ, MAX_RATE_HZ))
        put(
            "default_rate_hz",
            _check_number("default_rate_hz", self.default_rate_hz, MIN_RATE_HZ, MAX_RATE_HZ),
        )
        put("watchdog_s", _check_number("watchdog_s", self.watchdog_s, 0.1, 10.0))
        put("client_timeout_s", _check_number("client_timeout_s", self.client_timeout_s, 0.5, 60.0))
        put("stats_interval_s", _check_number("stats_interval_s", self.stats_interval_s, 0.5, 3600.0))
        for name, high in (
            ("max_rate_per_client_hz", 1e5),
            ("unverified_rate_per_host_hz", 1e5),
            ("unverified_rate_total_hz", 1e6),
        ):
            put(name, _check_number(name, getattr(self, name), 10.0, high))
        put("max_receive_ms", _check_number("max_receive_ms", self.max_receive_ms, 0.1, 100.0))
        for name, low, high in (
            ("max_clients", 1, 1024),
            ("max_clients_per_host", 1, 1024),
            ("max_datagrams_per_call", 1, 100000),
        ):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
                raise ValueError(f"LinkConfig.{name} must be an integer in [{low}, {high}], not {value!r}")
        for name in ("nmea_gll", "nmea_zda", "allow_remote"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"LinkConfig.{name} must be true or false")
        if self.failsafe not in FAILSAFE_POLICIES:
            raise ValueError(f"LinkConfig.failsafe must be one of {FAILSAFE_POLICIES}, not {self.failsafe!r}")
        if self.token is not None and (not isinstance(self.token, str) or not 1 <= len(self.token) <= 128):
            raise ValueError("LinkConfig.token must be a string of 1-128 characters or None")
        if isinstance(self.talkers, Mapping):
            put("talkers", nmea.Talkers(**self.talkers))
        if not isinstance(self.talkers, nmea.Talkers):
            raise ValueError("LinkConfig.talkers must be a Talkers")
        if isinstance(self.limits, Mapping):
            put("limits", Limits(**self.limits))
        if not isinstance(self.limits, Limits):
            raise ValueError("LinkConfig.limits must be a Limits")
        if self.utc_epoch is not None and not isinstance(self.utc_epoch, datetime):
            raise ValueError("LinkConfig.utc_epoch must be a datetime or None")

    @classmethod
    def from_dict(cls, data: Mapping[str, object]) -> LinkConfig:
        """Build from a mapping (e.g. a TOML table); an unknown key raises ``ValueError`` naming it."""
        known = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(data) - known)
        if unknown:
            raise ValueError(f"unknown LinkConfig key(s): {', '.join(unknown)}")
        return cls(**data)
