"""The 3D viewer's link client: a v2 client of the JSON link keeping the latest state, scene, particulars and
helm owner, and sending the page's helm orders (docs/protocol.md)."""

from __future__ import annotations

import ipaddress
import math
import socket
import time

from vessel_gym.net.protocol import (
    ASSIST_KINDS,
    MAX_ASSIST,
    MAX_NAME_CHARS,
    ProtocolError,
    SceneAssembler,
    encode_bye,
    encode_hello,
    encode_helm,
    parse_server_datagram_v2,
)

Address = tuple[str, int]
HELLO_PERIOD_S = 0.5  # keep-alive (the link drops a client after 3 s of silence)
HELM_PERIOD_S = 0.1  # full orders at 10 Hz, as docs/protocol.md asks of a panel


class LinkClient:
    """A v2 client of the JSON link: keeps the latest state, the scene, the particulars and the helm owner.

    Datagrams from any address but the server's are ignored. ``helm`` is False until :meth:`take_helm`.
    """

    def __init__(self, server: Address, rate_hz: float, name: str, token: str | None) -> None:
        self.server = (socket.gethostbyname(server[0]), server[1])
        self.rate_hz = rate_hz
        self.name = name
        self.token = token
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        # A link on loopback is answered from loopback only: the socket is not reachable from the network.
        loopback = ipaddress.ip_address(self.server[0]).is_loopback
        self.sock.bind(("127.0.0.1" if loopback else "0.0.0.0", 0))
        self.sock.setblocking(False)
        self.state: dict | None = None
        self.welcome: dict | None = None  # the last full welcome (with a session)
        self.cookie: str | None = None  # from the last welcome, echoed in each hello
        self.session: str | None = None  # from the last full welcome, sent with helm orders and bye
        self.scene: dict | None = None
        self.scene_version = 0
        self.particulars: dict[int, dict] = {}
        self.particulars_version = 0
        self.owner: dict | None = None
        self.events: list[dict] = []
        self.helm = False
        self.rudder_order_deg = 0.0
        self.telegraph = 0
        self.assist: list[float] = []  # thruster and tug orders, one per unit the welcome named, in [-1, 1]
        self._assembler = SceneAssembler()
        self._parts: dict[int, list[dict]] = {}
        self._last_state_seq = -1
        self._hello_due = 0.0
        self._helm_due = 0.0
        self._helm_seq = int(time.time() * 1000.0)  # increases across restarts of the page's server
        self.dropped = 0

    def _send(self, data: bytes) -> None:
        try:
            self.sock.sendto(data, self.server)
        except OSError:
            self.dropped += 1

    def hello(self) -> None:
        """A padded ``hello`` with the cookie and session of the last welcome (the link's handshake)."""
        role = "helm" if self.helm else "viewer"
        self._send(
            encode_hello(
                role, self.rate_hz, self.name, self.token, cookie=self.cookie, session=self.session, proto=2
            )
        )

    def take_helm(self) -> None:
        """Become a helm panel, starting from the orders in force (taking the helm moves nothing)."""
        if self.state is not None:
            self.rudder_order_deg = float(self.state.get("rudder_order_deg") or 0.0)
            self.telegraph = int(self.state.get("telegraph") or 0)
        echoed = (self.state or {}).get("assist")
        units = self.assist_units()
        self.assist = [0.0] * len(units)
        if isinstance(echoed, list) and len(echoed) == len(units):
            for j, a in enumerate(echoed):
                o = a.get("order") if isinstance(a, dict) else None
                if isinstance(o, (int, float)) and not isinstance(o, bool):
                    self.assist[j] = max(-1.0, min(1.0, float(o)))
        self.helm = True
        self.hello()

    def release_helm(self) -> None:
        self.helm = False
        self.hello()  # re-registering as a viewer releases the helm at once

    def limits(self) -> tuple[float, int]:
        w = self.welcome or {}
        return float(w.get("max_rudder_deg") or 35.0), 4

    def assist_units(self) -> list[tuple[str, str]]:
        """(name, kind) of each thruster and tug the welcome named (the helm orders them after the engine)."""
        units = (self.welcome or {}).get("assist")
        if not isinstance(units, list):
            return []
        out = []
        for u in units[:MAX_ASSIST]:
            if isinstance(u, dict) and isinstance(u.get("name"), str) and u.get("kind") in ASSIST_KINDS:
                out.append((u["name"][:MAX_NAME_CHARS], u["kind"]))
        return out

    def set_assist(self, j: int, order: float) -> None:
        """Order unit j (clamped to [-1, 1]); nothing without the helm or for a unit the ship lacks."""
        units = len(self.assist_units())
        if len(self.assist) != units:
            self.assist = [0.0] * units
        if self.helm and 0 <= j < units and math.isfinite(order):
            self.assist[j] = max(-1.0, min(1.0, float(order)))

    def poll(self, now: float, budget: int = 512) -> None:
        """Send what is due (hello, helm orders) and read every waiting datagram (at most ``budget``)."""
        if now >= self._hello_due:
            self.hello()
            self._hello_due = now + HELLO_PERIOD_S
        if self.helm and now >= self._helm_due:
            self._helm_seq += 1
            units = len(self.assist_units())
            if len(self.assist) != units:
                self.assist = [0.0] * units
            self._send(
                encode_helm(
                    self._helm_seq,
                    self.rudder_order_deg,
                    telegraph=self.telegraph,
                    session=self.session,
                    assist=self.assist if units else None,
                )
            )
            self._helm_due = now + HELM_PERIOD_S
        for _ in range(budget):
            try:
                data, addr = self.sock.recvfrom(65536)
            except (BlockingIOError, InterruptedError):
                return
            except OSError:
                self.dropped += 1
                continue
            if addr != self.server:
                self.dropped += 1
                continue
            try:
                msg = parse_server_datagram_v2(data)
            except ProtocolError:
                self.dropped += 1
                continue
            self._take(msg)

    def _take(self, msg: dict) -> None:
        kind = msg["type"]
        if kind == "state":
            seq = msg.get("seq")
            if not isinstance(seq, int) or seq <= self._last_state_seq:
                return
            parts = msg.get("parts", 1)
            if isinstance(parts, int) and parts > 1:
                got = self._parts.setdefault(seq, [])
                got.append(msg)
                if len(got) < parts:
                    return
                got.sort(key=lambda m: m.get("part", 0))
                msg = {**got[0], "targets": [t for m in got for t in m.get("targets", [])]}
                self._parts = {}
            self._last_state_seq = seq
            self.state = msg
        elif kind == "welcome":
            if isinstance(msg.get("cookie"), str):
                self.cookie = msg["cookie"]
            if not isinstance(msg.get("session"), str):
                self.hello()  # a challenge: echo its cookie at once (one hello per challenge)
                return
            self.session = msg["session"]
            self.welcome = msg
        elif kind == "scenario":
            scene = self._assembler.add(msg)
            if scene is not None:
                self.scene = scene
                self.scene_version += 1
        elif kind == "particulars":
            if isinstance(msg.get("id"), int):
                self.particulars[msg["id"]] = msg
                self.particulars_version += 1
        elif kind == "helm_owner":
            self.owner = msg
            if self.helm and not msg.get("you") and msg.get("owner") is not None:
                self.helm = False  # another panel holds it: go back to watching
        elif kind == "event":
            self.events.append(msg)
            del self.events[:-5]

    def close(self) -> None:
        if self.helm:
            self.helm = False
        self._send(encode_bye(self.session))
        self.sock.close()
