"""The network side of the helm and viewer panels: a UDP client of a link's JSON channel.

:class:`ServerConnection` talks plain UDP to a :class:`~vessel_gym.net.link.UdpLink` on this or another host,
registers with ``hello`` (repeated every 0.5 s as keep-alive), joins with the cookie handshake of
``docs/protocol.md``, accepts datagrams only from the server it joined and keeps the newest complete state,
scenario and particulars. It draws nothing: the pygame panels that use it are in :mod:`vessel_gym.ui.panels`.
"""

from __future__ import annotations

import math
import socket
from collections.abc import Sequence

from vessel_gym.net import protocol
from vessel_gym.net.protocol import ProtocolError

Address = tuple[str, int]

HELLO_INTERVAL_S = 0.5  # keep-alive period, well inside the server's 3 s client timeout


class ServerConnection:
    """Non-blocking UDP connection to a link's JSON channel.

    ``poll()`` reads everything waiting and keeps the newest complete ``state`` (parts of one ``seq`` merged),
    the last ``welcome`` and ``stats``; datagrams from any other address than ``server`` are dropped (counted
    in ``foreign``). ``keepalive(now_s)`` sends ``hello`` every 0.5 s, echoing the cookie and session of the
    last ``welcome``. With ``listen`` set the socket binds there and never sends anything (a listen-only viewer
    fed by ``json_static_destinations``).
    """

    def __init__(
        self,
        server: Address = ("127.0.0.1", 10120),
        role: str = "viewer",
        rate_hz: float = 20.0,
        name: str = "",
        token: str | None = None,
        listen: Address | None = None,
    ) -> None:
        if role not in protocol.ROLES:
            raise ValueError(f"role must be one of {protocol.ROLES}, not {role!r}")
        self.server = (socket.gethostbyname(server[0]), int(server[1]))
        self.role = role
        self.listen_only = listen is not None
        self._rate_hz, self._name, self._token = rate_hz, name, token
        self.cookie: str | None = None  # from the last welcome
        self.session: str | None = None  # from the last full welcome: this client is registered
        self.foreign = 0  # datagrams from other addresses than the server, dropped
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.setblocking(False)
        self.sock.bind(listen if listen is not None else ("", 0))
        self.state: dict | None = None  # newest complete state message
        self.welcome: dict | None = None
        self.stats: dict | None = None
        self.scene: dict | None = None  # the last complete v2 scenario message
        self.particulars: dict[int, dict] = {}  # v2 particulars by ship id (0 = own ship)
        self._scene_parts = protocol.SceneAssembler()
        self.states_received = 0
        self.dropped = 0
        self.helm_sent = 0
        self._seq = 0
        self._last_hello = -math.inf
        self._parts_seq = -1
        self._parts: dict[int, dict] = {}
        self._last_rx_s = -math.inf

    @property
    def owns_helm(self) -> bool:
        """True if the last welcome said this client owns the helm and the state says the helm is ok."""
        return bool(self.welcome and self.welcome.get("helm") and self.state and self.state.get("helm_ok"))

    def seconds_since_data(self, now_s: float) -> float:
        """Seconds since the last datagram from the server (inf before the first)."""
        return now_s - self._last_rx_s

    def _sendto(self, data: bytes) -> None:
        if self.listen_only:
            return
        try:
            self.sock.sendto(data, self.server)
        except OSError:
            pass  # unreachable server: the keep-alive retries

    def hello(self) -> None:
        """Send a ``hello`` now (padded; with the cookie and session held)."""
        self._sendto(
            protocol.encode_hello(
                self.role,
                self._rate_hz,
                self._name,
                self._token,
                cookie=self.cookie,
                session=self.session,
                proto=2,  # v2: the chart as well
            )
        )

    def keepalive(self, now_s: float) -> None:
        """Send ``hello`` if the last one is 0.5 s old (clock of ``now_s``: any monotonic seconds)."""
        if now_s - self._last_hello >= HELLO_INTERVAL_S:
            self._last_hello = now_s
            self.hello()

    def set_role(self, role: str) -> None:
        """Re-register as ``"helm"`` or ``"viewer"`` (a helm owner becoming a viewer releases the helm)."""
        if role not in protocol.ROLES:
            raise ValueError(f"role must be one of {protocol.ROLES}, not {role!r}")
        if role != self.role:
            self.role = role
            self.hello()

    def send_helm(
        self,
        rudder_order_deg: float,
        telegraph: int | None = None,
        rpm_order: float | None = None,
        assist: Sequence[float] | None = None,
    ) -> None:
        """Send one full helm command with the next ``seq`` (nothing before the server gave a session);
        ``assist``: one order per thruster or tug the welcome named."""
        if self.session is None:
            return
        self._seq += 1
        data = protocol.encode_helm(self._seq, rudder_order_deg, telegraph, rpm_order, self.session, assist)
        self._sendto(data)
        self.helm_sent += 1

    def poll(self, now_s: float = 0.0) -> int:
        """Read every waiting datagram; return how many were valid."""
        n = 0
        while True:
            try:
                data, source = self.sock.recvfrom(65536)
            except (BlockingIOError, InterruptedError):
                return n
            except OSError:  # an error reported on the socket: try again next frame
                return n
            if source[:2] != self.server:  # only the server joined may feed the display
                self.foreign += 1
                continue
            try:
                msg = protocol.parse_server_datagram_v2(data)
            except ProtocolError:
                self.dropped += 1
                continue
            n += 1
            self._last_rx_s = now_s
            kind = msg["type"]
            if kind == "state":
                self._on_state(msg)
            elif kind == "welcome":
                self._on_welcome(msg)
            elif kind == "scenario":
                self.scene = self._scene_parts.add(msg) or self.scene
            elif kind == "particulars":
                if isinstance(msg.get("id"), int):
                    self.particulars[msg["id"]] = msg
            elif kind == "stats":
                self.stats = msg

    def _on_welcome(self, msg: dict) -> None:
        cookie, session = msg.get("cookie"), msg.get("session")
        if isinstance(cookie, str):
            self.cookie = cookie
        if not isinstance(session, str):
            self.hello()  # a challenge: echo its cookie at once (one hello per challenge, never a loop)
            return
        if session != self.session:  # a new registration (e.g. the server restarted): seqs start again
            self.session = session
            self._seq = 0
            self.state = None
            self._parts_seq, self._parts = -1, {}
        self.welcome = msg

    def _on_state(self, msg: dict) -> None:
        seq, part, parts = msg.get("seq"), msg.get("part", 0), msg.get("parts", 1)
        if not all(isinstance(v, int) and not isinstance(v, bool) for v in (seq, part, parts)):
            self.dropped += 1
            return
        if self.state is not None and seq <= self.state.get("seq", -1):
            return  # older than what is shown
        if parts <= 1:
            self.state = msg
            self.states_received += 1
            return
        if seq != self._parts_seq:
            self._parts_seq, self._parts = seq, {}
        self._parts[part] = msg
        if len(self._parts) == parts:
            merged = dict(self._parts[0])
            merged["targets"] = [t for i in range(parts) for t in self._parts.get(i, {}).get("targets", [])]
            self.state = merged
            self.states_received += 1
            self._parts = {}

    def close(self, bye: bool = True) -> None:
        """Send ``bye`` (unless listen-only or ``bye`` is false) and close the socket."""
        if bye and self.session is not None:
            self._sendto(protocol.encode_bye(self.session))
        self.sock.close()
