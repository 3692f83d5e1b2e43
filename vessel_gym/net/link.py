"""The UDP link: NMEA 0183 + AIS out to chartplotters, JSON state out to viewers, helm commands in.

One :class:`UdpLink` serves one own ship. The caller's loop calls :meth:`UdpLink.service` once per step with the
current time and readings; the call drains the JSON socket without blocking, applies helm commands, sends what is
due, and returns the :class:`HelmState` in force. Nothing a peer sends can raise out of it: every rejected
datagram is counted by reason in :meth:`UdpLink.stats`, and socket errors are counted too.

Handshake and limits (``docs/protocol.md`` has the full text):

- A ``hello`` without a valid ``cookie`` gets only a short ``welcome`` carrying a cookie (an HMAC of the sender's
  address and the time under a secret of this link, so the link keeps no state for it), and only if that answer
  is no larger than the hello: an address that has not shown that it receives gets no more bytes than it sent.
- A ``hello`` that echoes a valid cookie registers the client (role ``viewer`` or ``helm``) with a fresh random
  ``session``, sent in the full ``welcome``; ``helm`` and ``bye`` must carry that session. A client stays
  registered while it renews its hello (or, as helm owner, commands) at least every ``client_timeout_s`` (3 s).
- Datagrams are rate-limited before parsing, by session or else by unverified budgets (:mod:`access`), and one
  ``service()`` call reads at most ``max_datagrams_per_call`` datagrams for at most ``max_receive_ms``.
- Slots: ``max_clients``, ``max_clients_per_host``; a full registry evicts an idle or over-share client.
- Tokens are compared as UTF-8 bytes in constant time.

Helm rules:

- Only registered ``helm`` clients may command, within their session. The first command while nobody owns the
  helm takes ownership; commands from other panels are dropped (``not_owner``) while an owner exists.
- Per session, only a command with a higher ``seq`` than the last one is applied (``stale_seq`` otherwise).
- If the owner sends no command for ``watchdog_s`` (1 s), or says ``bye``, ownership is released,
  ``helm_ok`` becomes false and the failsafe policy applies to the orders: ``hold`` keeps the last order,
  ``midships_stop`` orders rudder 0 and telegraph STOP (or 0 rpm). Another helm panel may then take over.

Time is whatever clock the caller passes as ``now_s`` (wall clock in live mode, simulation time otherwise); all
rates, the watchdog and the timeouts are measured in it.

This module is the link's loop (receive, dispatch, send on schedule). Admission (cookies, token, rate limits,
client registry) is :mod:`~vessel_gym.net.access`, helm ownership :mod:`~vessel_gym.net.helm_owner`, the
configuration :mod:`~vessel_gym.net.link_config` and the NMEA/AIS sentences :mod:`~vessel_gym.net.nmea_feed`.
"""

from __future__ import annotations

import math
import select
import socket
import time
from collections.abc import Callable, Sequence
from datetime import datetime

from vessel_gym.net import nmea
from vessel_gym.net.access import Access, Address, Client, is_loopback, new_session, resolve_host
from vessel_gym.net.helm_owner import HelmChange, HelmOwner, HelmState
from vessel_gym.net.link_config import LinkConfig  # noqa: F401
from vessel_gym.net.nmea_feed import NmeaFeed
from vessel_gym.net.protocol import (
    MAX_DATAGRAM_BYTES,
    NO_EXTRAS,
    REASONS,
    Bye,
    Hello,
    HelmCommand,
    ProtocolError,
    ShipParticulars,
    StateExtras,
    StatsRequest,
    Target,
    encode_challenge,
    encode_event,
    encode_helm_owner,
    encode_particulars,
    encode_scenario,
    encode_state,
    encode_stats,
    encode_welcome,
    parse_datagram,
)
from vessel_gym.physics.bridge import BridgeReading

LINK_DROP_REASONS = (
    "unregistered",
    "not_helm",
    "not_owner",
    "stale_seq",
    "too_many_clients",
    "bad_token",
    "short_hello",
    "bad_session",
    "rate_limited",
)
STATS_REQUEST_INTERVAL_S = 1.0  # a client gets at most one stats reply on request per this many s
NMEA_MAX_DATAGRAM_BYTES = 1400
RECEIVE_BUFFER_BYTES = 1 << 20
# A periodic send is made up to this fraction of its period early, so that rounding of a simulated clock
# (k * dt against a sum of periods) never skips a send. Jitter of a wall clock needs no slack: a deadline that is
# missed by a call stays behind the clock and is served by the next call, and deadlines advance by whole periods.
_SLACK = 1e-3


# ---------------------------------------------------------------------------------------------------------------
# The link


class UdpLink:
    """Non-blocking UDP link of one own ship (see the module docstring for the rules).

    ``UdpLink(config)`` binds the JSON socket at once (``json_address`` gives the bound port) and raises
    ``ValueError`` if the bind address is not loopback and ``config.allow_remote`` is false, or ``OSError`` if
    the port is taken. Use as a context manager or call :meth:`close`.
    """

    def __init__(self, config: LinkConfig | None = None) -> None:
        self.config = config = config if config is not None else LinkConfig()
        self._json_sock: socket.socket | None = None
        self._nmea_sock: socket.socket | None = None
        self._closed = False

        bind_host = resolve_host(config.json_bind[0])
        if not is_loopback(bind_host) and not config.allow_remote:
            raise ValueError(
                f"binding the JSON channel to {bind_host} accepts helm commands from the network: "
                "set allow_remote to do so"
            )
        self._nmea_dest = [(resolve_host(h), p) for h, p in config.nmea_destinations]
        self._static_dest = [(resolve_host(h), p) for h, p in config.json_static_destinations]

        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        try:
            sock.setblocking(False)
            # Room for bursts between two service() calls (the kernel caps this at net.core.rmem_max).
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, RECEIVE_BUFFER_BYTES)
            sock.bind((bind_host, config.json_bind[1]))
            if any(ip.endswith(".255") for ip, _ in self._static_dest):
                sock.setsockopt(socket.SOL_SOCKET, socket.SO_BROADCAST, 1)
        except OSError:
            sock.close()
            raise
        self._json_sock = sock
        # A zero-timeout poll costs ~0.5 us where a recvfrom that raises BlockingIOError costs ~2 us: it keeps
        # service() cheap when nobody is connected.
        if hasattr(select, "poll"):
            self._poller = select.poll()
            self._poller.register(sock, select.POLLIN)
        else:  # Windows
            self._poller = None
        if self._nmea_dest:
            nsock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            nsock.setblocking(False)
            if any(ip.endswith(".255") for ip, _ in self._nmea_dest):
                nsock.setsockopt(socket.SOL_SOCKET, socket.SO_BROADCAST, 1)
            self._nmea_sock = nsock

        self._access = Access(
            config.token,
            config.max_rate_per_client_hz,
            config.max_clients,
            config.max_clients_per_host,
            config.unverified_rate_per_host_hz,
            config.unverified_rate_total_hz,
        )
        self._clients = self._access.clients  # the registry, shared: Access admits, the link serves
        self._helm = HelmOwner(config.failsafe)
        self._state_seq = 0
        self._msg_seq = 0
        self._last_now: float | None = None
        self._nmea_due = -math.inf
        self._nmea_slack = _SLACK / config.nmea_rate_hz
        self._static_slack = _SLACK / config.static_rate_hz
        self._static_due = -math.inf
        self._stats_due = math.inf
        self._nmea_feed = NmeaFeed(config, self._encode_failed)
        self._scene_source: tuple = (None, (), None, ())  # what set_scene was given
        self._scene: list[bytes] | None = []  # its v2 datagrams, encoded on first need (None: not yet)
        self.last_error: str | None = None  # text of the last counted encoding/socket error
        #: what the owner adds to each state (thrusters, tugs, fenders), asked only when a state is encoded
        self.state_extras: Callable[[], StateExtras] | None = None
        counters = """rx_datagrams rx_accepted tx_state tx_welcome tx_challenge tx_stats tx_nmea_datagrams
            tx_nmea_sentences tx_ais_sentences tx_error rx_error encode_error clients_joined clients_left
            clients_timed_out clients_evicted rx_budget_spent helm_takeovers helm_watchdog helm_released tx_v2 """
        counters += " ".join(f"drop_{r}" for r in REASONS + LINK_DROP_REASONS)
        self._counters: dict[str, int] = dict.fromkeys(counters.split(), 0)

    # -- properties -------------------------------------------------------------------------------------------

    @property
    def json_address(self) -> Address:
        """The bound (host, port) of the JSON channel."""
        if self._json_sock is None:
            raise ValueError("the link is closed")
        return self._json_sock.getsockname()

    @property
    def helm(self) -> HelmState:
        """The helm state as of the last :meth:`service` call."""
        return self._helm.state

    @property
    def clients(self) -> list[dict[str, object]]:
        """Snapshot of the registered clients: address, role, rate_hz, name, last_seen_s, helm owner flag."""
        owner = self._helm.owner
        keys = ("address", "role", "rate_hz", "name", "last_seen_s", "owner")
        rows = [(a, c.role, c.rate_hz, c.name, c.last_seen, a == owner) for a, c in self._clients.items()]
        return [dict(zip(keys, row)) for row in rows]

    def pop_helm_changes(self) -> list[HelmChange]:
        """The helm ownership changes since the last call, oldest first (kept until popped, at most 1000)."""
        return self._helm.pop_changes()

    def stats(self) -> dict[str, int]:
        """Copy of the counters (the key set is fixed).

        Every received datagram is counted once in ``rx_datagrams`` and then exactly once more, in
        ``rx_accepted`` or in one ``drop_<reason>``. ``tx_*`` count sent datagrams (``tx_nmea_sentences`` and
        ``tx_ais_sentences`` sentences), ``clients_*`` and ``helm_*`` events, ``*_error`` counted failures.
        """
        return dict(self._counters)

    # -- main entry -------------------------------------------------------------------------------------------

    def service(
        self,
        now_s: float,
        own: BridgeReading | Callable[[], BridgeReading],
        targets: Sequence[Target] = (),
        utc: datetime | None = None,
    ) -> HelmState:
        """Receive, apply helm commands, send what is due at time ``now_s`` (s), return the helm state.

        ``own`` is the own ship's readings, or a function returning them that is called at most once, and
        only when a state message or NMEA is due (so a link with nobody due costs no readings); ``targets``
        the other ships (state targets and AIS). ``utc`` is the time stamped on NMEA/AIS; by default
        ``utc_epoch + own.t_s``. Never blocks; never raises because of
        peer input or socket errors (they are counted). After :meth:`close` it only returns the last state.
        """
        if self._closed:
            return self._helm.state
        last = self._last_now
        if last is not None and now_s < last:
            self._rebase(now_s - last)
        self._last_now = now_s
        if self._readable():
            self._receive(now_s)
        helm = self._helm
        if helm.owner is not None and now_s - helm.last_command_s > self.config.watchdog_s:
            self._release(now_s, "helm_watchdog", "watchdog")
        serve = bool(self._clients) or bool(
            self._static_dest and now_s + self._static_slack >= self._static_due
        )
        nmea = self._nmea_sock is not None and now_s + self._nmea_slack >= self._nmea_due
        if serve or nmea:
            readings: list[BridgeReading] = []

            def reading() -> BridgeReading:  # computed on first use: registered clients may not be due
                if not readings:
                    readings.append(own() if callable(own) else own)
                return readings[0]

            if serve:
                self._serve_clients(now_s, reading, targets)
            if nmea:
                self._send_nmea(now_s, reading(), targets, utc)
        return self._helm.state

    # -- receive ----------------------------------------------------------------------------------------------

    def _readable(self) -> bool:
        if self._poller is not None:
            return bool(self._poller.poll(0))
        return bool(select.select([self._json_sock], [], [], 0.0)[0])

    def _receive(self, now_s: float) -> None:
        sock = self._json_sock
        counters = self._counters
        access = self._access
        clock = time.perf_counter
        deadline = clock() + self.config.max_receive_ms * 1e-3
        for _ in range(self.config.max_datagrams_per_call):
            try:
                data, addr = sock.recvfrom(MAX_DATAGRAM_BYTES + 1)
            except (BlockingIOError, InterruptedError):
                return
            except OSError as exc:  # e.g. an ICMP error reported on the socket
                counters["rx_error"] += 1
                self.last_error = f"recv: {exc}"
                continue
            counters["rx_datagrams"] += 1
            if not access.admit(addr, data, now_s):
                counters["drop_rate_limited"] += 1
            else:
                try:
                    msg = parse_datagram(data, self.config.limits, self.config.default_rate_hz)
                except ProtocolError as exc:
                    counters["drop_" + exc.reason] += 1
                else:
                    self._handle(now_s, addr, msg, len(data))
            if clock() > deadline:
                break
        counters["rx_budget_spent"] += 1  # the rest waits for the next call (or the kernel drops it)

    def _drop(self, reason: str) -> None:
        self._counters["drop_" + reason] += 1

    def _handle(self, now_s: float, addr: Address, msg: object, size: int) -> None:
        client = self._clients.get(addr)
        if isinstance(msg, Hello):
            access = self._access
            if not access.token_ok(msg.token):
                self._drop("bad_token")
                return
            if not access.cookie_ok(addr, msg.cookie):
                data = encode_challenge(self._msg_seq + 1, access.new_cookie(addr))
                if len(data) > size:  # never more bytes than came in to an address not shown to receive
                    self._drop("short_hello")
                    return
                self._msg_seq += 1
                self._counters["rx_accepted"] += 1
                self._send(addr, data, "tx_challenge")
                return
            if client is None:
                room = access.make_room(addr[0], now_s, self._helm.owner)
                if room is False:
                    self._drop("too_many_clients")
                    return
                if room is not True:
                    del self._clients[room]
                    self._counters["clients_evicted"] += 1
                client = Client(msg.role, msg.rate_hz, msg.name, now_s, now_s, session=new_session())
                self._clients[addr] = client
                self._counters["clients_joined"] += 1
            else:
                if msg.session != client.session:  # a restarted client: its commands count from a new seq
                    if addr == self._helm.owner:
                        self._release(now_s, "helm_released", "new_session")
                    client.session = new_session()
                    client.last_seq = -1
                if client.role == "helm" and msg.role != "helm" and addr == self._helm.owner:
                    self._release(now_s, "helm_released", "viewer")
                if msg.rate_hz != client.rate_hz:
                    client.next_due = min(client.next_due, now_s + 1.0 / msg.rate_hz)
                client.role, client.rate_hz, client.name = msg.role, msg.rate_hz, msg.name
            client.last_seen = now_s
            self._counters["rx_accepted"] += 1
            self._send_welcome(addr, client)
            if msg.proto >= 2 and client.proto < 2:  # joined (or upgraded) as v2: send the scene once
                for data in self._scene_datagrams():
                    self._send(addr, data, "tx_v2")
            client.proto = msg.proto
            return
        if client is None:
            self._drop("unregistered")
            return
        if isinstance(msg, (HelmCommand, Bye, StatsRequest)) and msg.session != client.session:
            # a forged or stale command: it neither steers nor keeps the client, nor gets the stats
            self._drop("bad_session")
            return
        if isinstance(msg, HelmCommand):
            client.last_seen = now_s
            self._command(now_s, addr, client, msg)
            return
        if isinstance(msg, StatsRequest) and now_s - client.last_stats < STATS_REQUEST_INTERVAL_S:
            # even the client itself gets one ~1 kB reply per second, however many ~80-byte requests it sends
            self._drop("rate_limited")
            return
        self._counters["rx_accepted"] += 1
        if isinstance(msg, Bye):
            if addr == self._helm.owner:
                self._release(now_s, "helm_released", "bye")
            del self._clients[addr]
            self._counters["clients_left"] += 1
        elif isinstance(msg, StatsRequest):
            client.last_stats = now_s
            self._send(addr, self._stats_message(now_s), "tx_stats")

    def _command(self, now_s: float, addr: Address, client: Client, cmd: HelmCommand) -> None:
        if client.role != "helm":
            self._drop("not_helm")
            return
        if cmd.seq <= client.last_seq:
            self._drop("stale_seq")
            return
        client.last_seq = cmd.seq
        outcome = self._helm.command(now_s, addr, client.name, cmd)
        if outcome == "not_owner":
            self._drop("not_owner")
            return
        if outcome == "takeover":
            self._counters["helm_takeovers"] += 1
            self._owner_changed("takeover")
        self._counters["rx_accepted"] += 1

    def _release(self, now_s: float, counter: str, reason: str) -> None:
        """Owner lost (watchdog, bye, role change or timeout): free the helm (failsafe orders), tell v2 clients."""
        self._counters[counter] += 1
        self._helm.release(now_s, reason)
        self._owner_changed("watchdog" if counter == "helm_watchdog" else "released")

    # -- protocol v2 ------------------------------------------------------------------------------------------

    def set_scene(
        self,
        scenario: object | None,
        ships: Sequence[ShipParticulars],
        environment: object | None = None,
        features: Sequence[dict] = (),
    ) -> None:
        """Publish the scene (protocol v2): the scenario's polygons (and the task's ``features``: fenders, the
        route) and sea state and the ships' particulars.

        Sent now to every client that said ``"proto": 2`` and later to each one when it joins; call it again at
        each reset (the sea state is drawn per episode). The datagrams are encoded only when a v2 client needs
        them (a training loop without viewers pays nothing); encoding errors are counted (``encode_error``).
        """
        if self._closed:
            return
        self._scene_source = (scenario, tuple(ships), environment, tuple(features))
        self._scene = None
        for addr, c in self._clients.items():
            if c.proto >= 2:
                for data in self._scene_datagrams():
                    self._send(addr, data, "tx_v2")

    def _scene_datagrams(self) -> list[bytes]:
        if self._scene is None:
            scenario, ships, environment, features = self._scene_source
            seq = self._next_seq()
            try:
                scene = encode_scenario(seq, scenario, environment, extra_features=features)
                scene += [encode_particulars(seq, ship) for ship in ships]
            except (ValueError, TypeError, OverflowError) as exc:
                self._counters["encode_error"] += 1
                self.last_error = f"scene: {exc}"
                scene = []
            self._scene = scene
        return self._scene

    def publish_event(self, event: str, t_s: float, episode: int, **fields: object) -> None:
        """Send an ``event`` (``reset``, ``outcome``, ``contact``; protocol v2) to every v2 client."""
        if self._closed or not self._clients:
            return
        data = encode_event(self._next_seq(), event, t_s, episode, **fields)
        for addr, c in self._clients.items():
            if c.proto >= 2:
                self._send(addr, data, "tx_v2")

    def _owner_changed(self, reason: str) -> None:
        owner = self._helm.owner
        name = None
        if owner is not None:
            client = self._clients.get(owner)
            name = (client.name if client is not None else "") or f"{owner[0]}:{owner[1]}"
        seq = self._next_seq()
        for addr, c in self._clients.items():
            if c.proto >= 2:
                self._send(addr, encode_helm_owner(seq, name, addr == owner, reason), "tx_v2")

    def _rebase(self, delta: float) -> None:
        """The caller's clock jumped back by -delta: shift every stored time so intervals are kept."""
        self._helm.rebase(delta)
        self._access.rebase(delta)
        self._nmea_due += delta
        self._static_due += delta
        self._stats_due += delta
        self._nmea_feed.rebase(delta)

    # -- send -------------------------------------------------------------------------------------------------

    def _send(self, addr: Address, data: bytes, counter: str, sock: socket.socket | None = None) -> bool:
        try:
            (sock or self._json_sock).sendto(data, addr)
        except OSError as exc:  # buffer full, unreachable network, ...
            self._counters["tx_error"] += 1
            self.last_error = f"send to {addr}: {exc}"
            return False
        self._counters[counter] += 1
        return True

    def _encode_failed(self, text: str) -> None:
        self._counters["encode_error"] += 1
        self.last_error = text

    def _next_seq(self) -> int:
        self._msg_seq += 1
        return self._msg_seq

    def _send_welcome(self, addr: Address, client: Client) -> None:
        cfg = self.config
        data = encode_welcome(
            self._next_seq(),
            client.role,
            client.rate_hz,
            addr == self._helm.owner,
            cfg.limits,
            cfg.watchdog_s,
            cfg.client_timeout_s,
            cfg.failsafe,
            cookie=self._access.new_cookie(addr),
            session=client.session,
        )
        self._send(addr, data, "tx_welcome")

    def _stats_message(self, now_s: float) -> bytes:
        return encode_stats(self._next_seq(), now_s, self._counters, len(self._clients))

    def _serve_clients(
        self, now_s: float, own: Callable[[], BridgeReading], targets: Sequence[Target]
    ) -> None:
        timeout = self.config.client_timeout_s
        parts: list[bytes] | None = None
        expired = []
        for addr, c in self._clients.items():
            if now_s - c.last_seen > timeout:
                expired.append(addr)
                continue
            if now_s + _SLACK / c.rate_hz < c.next_due:
                continue
            if parts is None:
                parts = self._encode_state(own(), targets)
            for data in parts:
                self._send(addr, data, "tx_state")
            c.next_due = _advance(c.next_due, 1.0 / c.rate_hz, now_s)
        for addr in expired:
            del self._clients[addr]
            self._counters["clients_timed_out"] += 1
            if addr == self._helm.owner:
                self._release(now_s, "helm_watchdog", "timeout")
        if self._static_dest and now_s + self._static_slack >= self._static_due:
            if parts is None:
                parts = self._encode_state(own(), targets)
            for addr in self._static_dest:
                for data in parts:
                    self._send(addr, data, "tx_state")
            self._static_due = _advance(self._static_due, 1.0 / self.config.static_rate_hz, now_s)
        if self._clients:
            if self._stats_due == math.inf:
                self._stats_due = now_s + self.config.stats_interval_s
            elif now_s >= self._stats_due:
                data = self._stats_message(now_s)
                for addr in self._clients:
                    self._send(addr, data, "tx_stats")
                self._stats_due = _advance(self._stats_due, self.config.stats_interval_s, now_s)
        else:
            self._stats_due = math.inf

    def _encode_state(self, own: BridgeReading, targets: Sequence[Target]) -> list[bytes]:
        self._state_seq += 1
        try:
            extras = self.state_extras() if self.state_extras is not None else NO_EXTRAS
            return encode_state(self._state_seq, own, self._helm.state.helm_ok, targets, extras=extras)
        except (ValueError, TypeError, OverflowError) as exc:
            self._counters["encode_error"] += 1
            self.last_error = f"state: {exc}"
            return []

    def _send_nmea(
        self, now_s: float, own: BridgeReading, targets: Sequence[Target], utc: datetime | None
    ) -> None:
        self._nmea_due = _advance(self._nmea_due, 1.0 / self.config.nmea_rate_hz, now_s)
        sentences, n_own = self._nmea_feed.cycle(now_s, own, targets, utc)
        if not sentences:
            return
        datagrams = nmea.pack_datagrams(sentences, NMEA_MAX_DATAGRAM_BYTES)
        sent_any = False
        for addr in self._nmea_dest:
            for data in datagrams:
                sent_any |= self._send(addr, data, "tx_nmea_datagrams", self._nmea_sock)
        if sent_any:
            self._counters["tx_nmea_sentences"] += n_own
            self._counters["tx_ais_sentences"] += len(sentences) - n_own

    # -- lifecycle --------------------------------------------------------------------------------------------

    def close(self) -> None:
        """Close the sockets (idempotent). Later :meth:`service` calls do nothing."""
        self._closed = True
        for sock in (self._json_sock, self._nmea_sock):
            if sock is not None:
                sock.close()
        self._json_sock = None
        self._nmea_sock = None

    def __enter__(self) -> UdpLink:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def __del__(self) -> None:
        if not getattr(self, "_closed", True):
            self.close()


def _advance(due: float, period: float, now_s: float) -> float:
    """Next deadline one period after ``due``; after a stall of more than a period, one period from now.

    Deadlines advance by whole periods, so the average rate is exact whatever the caller's rate; the stall rule
    keeps a late loop from sending a burst to catch up.
    """
    nxt = due + period
    if not nxt > now_s - period:  # also catches the initial -inf
        nxt = now_s + period
    return nxt
