"""Who may talk to the UDP link: the registry of clients, the stateless hello cookie, the shared token, the
per-source rate limit, and whether the link's address is open to the network.

:class:`Access` decides admission only; the link (:mod:`vessel_gym.net.link`) counts the outcome and answers.
The rules are those of ``docs/protocol.md``:

- A cookie is an HMAC of the sender's address and the time under a secret of this link, so the link keeps no
  state for an address until it echoes a valid cookie.
- Each source address may send ``max_rate_per_source_hz`` datagrams per second (token bucket, bursts of 1 s of
  it); one host may hold ``max_clients_per_host`` of the ``max_clients`` slots.
- Tokens and cookies are compared as UTF-8 bytes in constant time.
"""

from __future__ import annotations

import base64
import hashlib
import hmac
import ipaddress
import math
import os
import secrets
import socket
import time
from dataclasses import dataclass

Address = tuple[str, int]

# A cookie is valid this long after it was issued (s of the link's monotonic clock). Every full welcome carries a
# fresh one, and clients renew their hello at least once a second, so a live client never holds an old cookie.
COOKIE_LIFETIME_S = 10.0
# Per-source rate limits are kept for at most this many source addresses; beyond it, unknown sources share one
# bucket (a flood from many spoofed addresses then limits itself, not the registered clients).
MAX_RATE_SOURCES = 4096


def token_bytes(text: str) -> bytes:
    """UTF-8 bytes of any str, lone surrogates included (JSON may carry them as escapes), for compare_digest."""
    return text.encode("utf-8", "surrogatepass")


def resolve_host(host: str) -> str:
    """IPv4 address of a host name ("" = every interface), resolved once when a link opens."""
    return socket.gethostbyname(host) if host else "0.0.0.0"


def is_loopback(ip: str) -> bool:
    """True for a loopback address: only a link bound there is closed to the network without ``allow_remote``."""
    try:
        return ipaddress.ip_address(ip).is_loopback
    except ValueError:
        return False


def new_session() -> str:
    """A fresh random session id for a registered client."""
    return secrets.token_hex(8)


@dataclass
class Client:
    """A registered client: its hello (role, rate, name), session, and the link times it was last heard from
    and is next due a state message (s of the caller's clock)."""

    role: str
    rate_hz: float
    name: str
    last_seen: float
    next_due: float
    session: str = ""
    last_seq: int = -1
    last_stats: float = -math.inf  # link time of the last stats reply on request
    proto: int = 1  # 2: also gets the v2 scene, event and helm_owner messages


class Access:
    """Admission of one link: the client registry (``clients``), cookies, the token and the rate limits."""

    def __init__(
        self,
        token: str | None,
        max_rate_per_source_hz: float,
        max_clients: int,
        max_clients_per_host: int,
    ) -> None:
        self.clients: dict[Address, Client] = {}
        self._secret = os.urandom(32)  # cookie key; a new link invalidates every cookie of an old one
        self._cookie_clock = time.monotonic  # cookies age in real time whatever clock service() gets
        self._token = None if token is None else token_bytes(token)
        self._rate = max_rate_per_source_hz
        self._max_clients = max_clients
        self._max_per_host = max_clients_per_host
        self._buckets: dict[Address | None, list[float]] = {}  # source -> [datagrams allowed, last time]

    def admit(self, addr: Address, now_s: float) -> bool:
        """Token bucket per source address: ``max_rate_per_source_hz`` datagrams/s, bursts of 1 s of it."""
        rate = self._rate
        buckets = self._buckets
        key: Address | None = addr
        bucket = buckets.get(addr)
        if bucket is None:
            if len(buckets) >= MAX_RATE_SOURCES:
                # forget sources that have been quiet long enough to have a full bucket again
                for k in [k for k, b in buckets.items() if k is not None and now_s - b[1] >= 1.0]:
                    del buckets[k]
            if len(buckets) >= MAX_RATE_SOURCES:
                key = None
                bucket = buckets.get(None)
            if bucket is None:
                bucket = buckets[key] = [rate, now_s]
        allowed = min(rate, bucket[0] + max(now_s - bucket[1], 0.0) * rate)
        bucket[1] = now_s
        if allowed < 1.0:
            bucket[0] = allowed
            return False
        bucket[0] = allowed - 1.0
        return True

    def token_ok(self, token: str | None) -> bool:
        """True if the link needs no token or ``token`` is it (constant-time comparison)."""
        expected = self._token
        return expected is None or (token is not None and hmac.compare_digest(token_bytes(token), expected))

    def _cookie(self, addr: Address, issued: int) -> str:
        mac = hmac.new(self._secret, f"{addr[0]}|{addr[1]}|{issued}".encode(), hashlib.sha256).digest()
        return f"{issued:x}." + base64.urlsafe_b64encode(mac[:16]).rstrip(b"=").decode("ascii")

    def new_cookie(self, addr: Address) -> str:
        """A cookie for ``addr``, stamped now."""
        return self._cookie(addr, int(self._cookie_clock()))

    def cookie_ok(self, addr: Address, cookie: str | None) -> bool:
        """True if ``cookie`` was issued by this link to ``addr`` less than COOKIE_LIFETIME_S ago."""
        if cookie is None:
            return False
        head, dot, _ = cookie.partition(".")
        if not dot or not 0 < len(head) <= 12 or not all(c in "0123456789abcdef" for c in head):
            return False
        issued = int(head, 16)
        if not 0.0 <= self._cookie_clock() - issued <= COOKIE_LIFETIME_S + 1.0:  # +1: whole-second stamps
            return False
        return hmac.compare_digest(self._cookie(addr, issued).encode("ascii"), token_bytes(cookie))

    def has_room(self, host: str) -> bool:
        """True if a new client from ``host`` fits in ``max_clients`` and ``max_clients_per_host``."""
        clients = self.clients
        return len(clients) < self._max_clients and (
            sum(1 for a in clients if a[0] == host) < self._max_per_host
        )

    def rebase(self, delta: float) -> None:
        """The caller's clock jumped by ``delta``: shift the clients' stored times so intervals are kept."""
        for c in self.clients.values():
            c.last_seen += delta
            c.last_stats += delta
            c.next_due += delta
