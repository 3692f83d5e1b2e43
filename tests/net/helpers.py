"""Helpers for the UDP link tests: readings, free ports and a loopback peer."""

from __future__ import annotations

import dataclasses
import json
import socket
import time
from collections.abc import Callable

from vessel_gym.net import protocol as P
from vessel_gym.physics.bridge import BridgeReading


def make_reading(**overrides: float) -> BridgeReading:
    """A ship at 53.5412 N 9.9876 E on 123.4 deg, 12.3 kn, turning to port with port rudder."""
    values = {
        "t_s": 10.0,
        "x_m": 1234.5,
        "y_m": -789.0,
        "lat_deg": 53.54120,
        "lon_deg": 9.98760,
        "hdg_deg": 123.4,
        "cog_deg": 124.9,
        "sog_kn": 12.3,
        "stw_kn": 12.0,
        "stw_transverse_kn": -0.2,
        "rot_dpm": -12.0,
        "rudder_deg": -10.0,
        "rudder_order_deg": -15.0,
        "rpm": 85.0,
        "telegraph": 3,
        "wind_rel_angle_deg": 40.0,
        "wind_rel_speed_kn": 15.0,
        "wind_true_dir_deg": 163.4,
        "wind_true_speed_kn": 11.0,
    }
    values.update(overrides)
    return BridgeReading(**values)


def moved(reading: BridgeReading, **changes: float) -> BridgeReading:
    return dataclasses.replace(reading, **changes)


def drain(link, n: int, t0: float, calls: int = 100) -> dict:
    """Service ``link`` from link time ``t0`` until it has read ``n`` datagrams in all (at most ``calls``
    calls, 1 ms of link time apart): one call stops at its receive budget (``max_receive_ms``), which a loaded
    machine reaches before a burst is read; the rest waits for the next calls. Returns the link's stats."""
    for k in range(calls):
        if link.stats()["rx_datagrams"] >= n:
            break
        link.service(t0 + 0.001 * k, make_reading())
    return link.stats()


def free_udp_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def free_tcp_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Peer:
    """A UDP socket on 127.0.0.1 playing a client (or a listen-only receiver)."""

    def __init__(self, host: str = "127.0.0.1") -> None:
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind((host, 0))
        self.sock.setblocking(False)
        self.address = self.sock.getsockname()
        self.cookie: str | None = None  # from the last welcome
        self.session: str | None = None  # from the last full welcome
        self._pending: list[dict] = []  # messages read while joining, returned by the next messages()

    def send(self, to: tuple[str, int], msg: dict | bytes) -> None:
        data = msg if isinstance(msg, bytes) else json.dumps(msg).encode()
        self.sock.sendto(data, to)

    def raw(self, wait_s: float = 0.0) -> list[bytes]:
        """Every datagram waiting now (after an optional settle time)."""
        if wait_s:
            time.sleep(wait_s)
        out = []
        while True:
            try:
                out.append(self.sock.recv(65536))
            except BlockingIOError:
                return out

    def _read(self) -> None:
        """Read what waits; keep the cookie and session of welcomes, keep all but challenges for messages()."""
        for d in self.raw():
            m = json.loads(d)
            if m.get("type") == "welcome":
                self.cookie = m.get("cookie", self.cookie)
                if "session" not in m:
                    continue  # a challenge: only its cookie matters
                self.session = m["session"]
            self._pending.append(m)

    def messages(self, kind: str | None = None) -> list[dict]:
        self._read()
        msgs, self._pending = self._pending, []
        return [m for m in msgs if kind is None or m.get("type") == kind]

    def hello(
        self, to: tuple[str, int], role: str = "viewer", rate: float | None = None, name: str = "", token=None
    ) -> None:
        """Send a hello echoing the cookie and session held (padded, as the bundled clients do)."""
        self._read()
        self.send(to, P.encode_hello(role, rate, name, token, cookie=self.cookie, session=self.session))

    def helm(self, to: tuple[str, int], seq: int, rudder: float, telegraph=None, rpm=None) -> None:
        """Send a helm command in this peer's session."""
        self.send(to, P.encode_helm(seq, rudder, telegraph=telegraph, rpm_order=rpm, session=self.session))

    def bye(self, to: tuple[str, int]) -> None:
        self.send(to, P.encode_bye(self.session))

    def join(
        self,
        to: tuple[str, int],
        pump: Callable[[], object],
        role: str = "viewer",
        rate: float | None = None,
        tries: int = 50,
        **extra,
    ) -> None:
        """The full handshake: hello, read the cookie, hello with it, read the session. ``pump`` lets the server
        run once (service the link, step an environment, or just wait for a server thread)."""
        self.cookie = self.session = None
        for _ in range(tries):
            self.hello(to, role, rate, **extra)
            time.sleep(0.003)
            pump()
            time.sleep(0.003)
            self._read()
            if self.session is not None:
                return
        raise AssertionError(f"no session from {to} after {tries} hellos")

    def close(self) -> None:
        self.sock.close()
