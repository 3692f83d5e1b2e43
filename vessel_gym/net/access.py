"""Who may talk to the UDP link: the registry of clients, the stateless hello cookie, the shared token, the
rate budgets, and whether the link's address is open to the network.

:class:`Access` decides admission only; the link (:mod:`vessel_gym.net.link`) counts the outcome and answers.
The rules are those of ``docs/protocol.md`` section 4:

- A cookie is an HMAC of the sender's address and the time under a secret of this link, so the link keeps no
  state for an address until it echoes a valid cookie.
- **Rates by session, not by address.** A datagram that carries the session of the client registered at its
  source address spends that client's own bucket (``max_rate_per_client_hz``); anything else is *unverified*
  and spends the bucket of its source host (``unverified_rate_per_host_hz``) and one bucket shared by all
  unverified traffic (``unverified_rate_total_hz``). A sender that cannot read the client's traffic does not
  know its session, so forged datagrams with a client's address spend only the unverified budgets and the
  client keeps its whole allowance.
- Every lookup is O(1): hosts' buckets live in an LRU hash map of at most ``MAX_RATE_HOSTS`` entries (the least
  recently heard host is forgotten first; the shared bucket still caps what forgotten hosts can send).
- One host may hold ``max_clients_per_host`` of the ``max_clients`` slots. When every slot is taken, a newcomer
  gets the slot of a client silent for ``IDLE_EVICT_S``, or else of the host holding more than its fair share
  (``max_clients`` / hosts, the newcomer's included); the helm owner is never evicted.
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
from collections import OrderedDict
from dataclasses import dataclass, field

Address = tuple[str, int]

# A cookie is valid this long after it was issued (s of the link's monotonic clock). Every full welcome carries a
# fresh one, and clients renew their hello at least once a second, so a live client never holds an old cookie.
COOKIE_LIFETIME_S = 10.0
# Unverified per-host buckets are kept for at most this many hosts (LRU). 4096 hosts cover a /20 of LAN clients;
# a flood from more (spoofed) addresses only recycles entries and is capped by the shared unverified bucket.
MAX_RATE_HOSTS = 4096
# A registered client that has sent nothing for this long (s) may lose its slot to a newcomer when all slots are
# taken: the bundled clients renew their hello every 0.5 s, so 1.5 s is three missed renewals (a dead or stalled
# client), well inside client_timeout_s (3 s by default) after which it is dropped anyway.
IDLE_EVICT_S = 1.5


class TokenBucket:
    """``rate`` tokens per second, holding at most one second's worth (bursts of 1 s)."""

    __slots__ = ("tokens", "t")

    def __init__(self, rate: float, now_s: float) -> None:
        self.tokens = rate
        self.t = now_s

    def take(self, rate: float, now_s: float) -> bool:
        """Spend one token at ``now_s`` if there is one; a clock that went back adds nothing."""
        tokens = min(rate, self.tokens + max(now_s - self.t, 0.0) * rate)
        self.t = now_s
        if tokens < 1.0:
            self.tokens = tokens
            return False
        self.tokens = tokens - 1.0
        return True


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
    bucket: TokenBucket | None = field(default=None, repr=False)  # the session's datagram allowance


class Access:
    """Admission of one link: the client registry (``clients``), cookies, the token and the rate budgets."""

    def __init__(
        self,
        token: str | None,
        max_rate_per_client_hz: float,
        max_clients: int,
        max_clients_per_host: int,
        unverified_rate_per_host_hz: float = 100.0,
        unverified_rate_total_hz: float = 1000.0,
    ) -> None:
        self.clients: dict[Address, Client] = {}
        self._secret = os.urandom(32)  # cookie key; a new link invalidates every cookie of an old one
        self._cookie_clock = time.monotonic  # cookies age in real time whatever clock service() gets
        self._token = None if token is None else token_bytes(token)
        self._client_rate = max_rate_per_client_hz
        self._host_rate = unverified_rate_per_host_hz
        self._total_rate = unverified_rate_total_hz
        self._max_clients = max_clients
        self._max_per_host = max_clients_per_host
        self._hosts: OrderedDict[str, TokenBucket] = OrderedDict()  # unverified buckets, least recent first
        self._total: TokenBucket | None = None  # the bucket all unverified traffic shares

    def admit(self, addr: Address, data: bytes, now_s: float) -> bool:
        """True if the datagram ``data`` from ``addr`` fits its budget (checked before it is parsed).

        It spends its client's bucket if it carries the session of the client registered at ``addr`` (a plain
        byte search: whoever includes the session knows it; the link still checks the parsed field), else the
        unverified budgets of its host and of everyone.
        """
        client = self.clients.get(addr)
        if client is not None and client.session and client.session.encode("ascii") in data:
            if client.bucket is None:
                client.bucket = TokenBucket(self._client_rate, now_s)
            return client.bucket.take(self._client_rate, now_s)
        return self.admit_unverified(addr[0], now_s)

    def admit_unverified(self, host: str, now_s: float) -> bool:
        """Spend a token of ``host``'s bucket and one of the shared bucket (both, or neither is charged)."""
        hosts = self._hosts
        bucket = hosts.get(host)
        if bucket is None:
            if len(hosts) >= MAX_RATE_HOSTS:
                hosts.popitem(last=False)
            bucket = hosts[host] = TokenBucket(self._host_rate, now_s)
        else:
            hosts.move_to_end(host)
        if not bucket.take(self._host_rate, now_s):
            return False
        total = self._total
        if total is None:
            total = self._total = TokenBucket(self._total_rate, now_s)
        if not total.take(self._total_rate, now_s):
            bucket.tokens += 1.0  # refused by the shared budget: the host's own token is not spent
            return False
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

    def make_room(self, host: str, now_s: float, owner: Address | None) -> Address | None | bool:
        """Find a slot for a new client from ``host``: True if one is free, the address of the client to evict
        for it (never ``owner``), or False if ``host`` has its share or every other host is within its share."""
        clients = self.clients
        per_host: dict[str, int] = {}
        for a in clients:
            per_host[a[0]] = per_host.get(a[0], 0) + 1
        if per_host.get(host, 0) >= self._max_per_host:
            return False
        if len(clients) < self._max_clients:
            return True
        candidates = [(c.last_seen, a) for a, c in clients.items() if a != owner]
        idle = [(t, a) for t, a in candidates if now_s - t > IDLE_EVICT_S]
        if idle:
            return min(idle)[1]
        fair = self._max_clients // (len(per_host) + (host not in per_host))
        # the most crowded host over its share gives up its longest-silent client, if that narrows the gap
        share = max(fair, per_host.get(host, 0) + 1)
        greedy = [(-per_host[a[0]], t, a) for t, a in candidates if per_host[a[0]] > share]
        return min(greedy)[2] if greedy else False

    def rebase(self, delta: float) -> None:
        """The caller's clock jumped by ``delta``: shift the clients' stored times so intervals are kept."""
        for c in self.clients.values():
            c.last_seen += delta
            c.last_stats += delta
            c.next_due += delta
