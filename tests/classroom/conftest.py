"""A classroom server on loopback in a background thread, and websocket clients for it."""

from __future__ import annotations

import json
import socket

import pytest

from vessel_gym.classroom.codes import ClassCodes
from vessel_gym.classroom.harbour import ClassHarbour
from vessel_gym.classroom.server import ClassroomServer


class Room:
    """A running server (``srv``) with its codes, port and a client factory."""

    def __init__(self, ships: int, time_factor: float, tmp_path, tls=None, pilots: int = 0) -> None:
        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(64)
        self.port = self.sock.getsockname()[1]
        self.origin = f"http://127.0.0.1:{self.port}"
        self.url = f"ws://127.0.0.1:{self.port}/ws"
        self.harbour = ClassHarbour("harbour", ships, seed=1, pilots=pilots)
        self.codes = ClassCodes(ships)
        self.srv = ClassroomServer(
            self.harbour,
            self.codes,
            ("127.0.0.1", self.port),
            time_factor=time_factor,
            tls=tls,
            debrief_path=tmp_path / "debrief.html",
        )
        self.srv.start_in_thread(self.sock)
        self.conns: list = []

    def connect(self, origin: str | None = "same", **kw):
        from websockets.sync.client import connect

        ws = connect(self.url, origin=self.origin if origin == "same" else origin, open_timeout=10, **kw)
        self.conns.append(ws)
        return ws

    def join(self, code: str, name: str = "", **kw):
        """A connection joined with ``code``: (connection, welcome)."""
        ws = self.connect(**kw)
        ws.send(json.dumps({"type": "join", "code": code, "name": name}))
        return ws, recv_type(ws, ("welcome", "refused"))

    def close(self) -> None:
        for ws in self.conns:
            ws.close()
        self.srv.stop()
        self.sock.close()


def recv_type(ws, types, timeout_s: float = 10.0) -> dict:
    """The next message of one of ``types`` (others skipped)."""
    while True:
        m = json.loads(ws.recv(timeout=timeout_s))
        if m["type"] in types:
            return m


def recv_ack(ws, seq: int, timeout_s: float = 10.0) -> dict:
    """The first state that echoes order ``seq``."""
    while True:
        m = recv_type(ws, ("state",), timeout_s)
        if m.get("ack") == seq:
            return m


@pytest.fixture
def room(tmp_path):
    made: list[Room] = []

    def make(ships: int = 2, time_factor: float = 1.0, tls=None, pilots: int = 0) -> Room:
        made.append(Room(ships, time_factor, tmp_path, tls, pilots))
        return made[-1]

    yield make
    for r in made:
        r.close()
