"""The 3D viewer's gate: who may load the page, open its websocket and take the helm (docs/protocol.md, "What
the page checks").

Any web page the user visits can make the browser open ``ws://127.0.0.1:PORT/`` or fetch from it, and a DNS
rebinding name can point at loopback, so every HTTP request and websocket upgrade is checked here before viser
sees it:

- ``Host`` must be one of the names the page is served under (the name given to ``--http`` and the address it
  resolved to, with the port); anything else (a rebinding name) gets 403.
- ``Origin``, when sent, must be the page's own (``http://`` + one of those hosts); ``null`` or a foreign one gets
  403. A websocket upgrade without ``Origin`` gets 403 too: a browser always sends one, and the page's own
  websocket is same-origin.
- The page is served at ``/`` (watch only) and at ``/helm/KEY``, where KEY is a random secret of this run printed
  on the command line. viser's client opens its websocket at the page's path, so only a page loaded from the
  ``/helm/KEY`` URL has a websocket that may send GUI actions (the helm keys and buttons); a websocket at any
  other path may only report its camera. A wrong key gets 403.
- Every message from a page is decoded and checked against the type and fields viser declares for it before
  viser handles it; a message that is not a binary frame, does not decode, is of a type the connection may not
  send, or has fields of the wrong type or non-finite numbers is dropped and counted, as are frames over
  :data:`MAX_MESSAGE_BYTES` (the connection is closed) and messages over :data:`MESSAGE_RATE_HZ`. websockets'
  own error log and a failed message handler of viser go to a counter, never to stderr.
- At most :data:`MAX_CONNECTIONS` websockets are open at once (each is sent the whole scene); more get 503. A
  websocket that did not agree on viser's subprotocol of this version (``viser-vX.Y.Z``) is closed (1002) and
  counted, before viser would print a banner for it.

viser (1.1) gives no hook for any of this: :func:`gated_viser_server` wraps the one call viser makes to
``websockets.asyncio.server.serve`` while the server starts (see there), which is why pyproject pins viser's
minor version.
"""

from __future__ import annotations

import contextlib
import contextvars
import hmac
import io
import ipaddress
import logging
import math
import secrets
import socket
import threading
import time
import weakref
from collections import Counter
from collections.abc import Iterable, Iterator
from typing import Any

RESOLVE_TIMEOUT_S = 5.0  # s allowed for the name given to --http to resolve
MAX_MESSAGE_BYTES = 1 << 20  # largest websocket message from a page, bytes (its camera reports are ~200 B)
MESSAGE_RATE_HZ = 200.0  # messages per second a page may send (the page reports its camera at most ~60 Hz)
MESSAGE_BURST = 400  # messages a page may send at once above that rate
MAX_CONNECTIONS = 16  # open websockets at once (each gets the whole scene on connecting); more get 503
HELM_PATH = "/helm/"

# The only messages a page needs to send: its camera (any page) and GUI actions (a page holding the key).
WATCH_MESSAGES = ("ViewerCameraMessage",)
HELM_MESSAGES = WATCH_MESSAGES + ("GuiUpdateMessage", "CommandTriggerMessage")

_ROLE: contextvars.ContextVar[str | None] = contextvars.ContextVar("view3d_role", default=None)


class PageAddress:
    """Where the page is served: the name as given, the address it resolved to (``sockaddr``) and its family."""

    def __init__(self, name: str, family: int, sockaddr: tuple) -> None:
        self.name = name
        self.family = family
        self.sockaddr = sockaddr

    @property
    def address(self) -> str:
        return str(self.sockaddr[0])

    def url_host(self, port: int) -> str:
        a = self.address
        return f"[{a}]:{port}" if self.family == socket.AF_INET6 else f"{a}:{port}"


def resolve_page_address(
    host: str, port: int, *, lan: bool = False, timeout_s: float | None = None
) -> PageAddress:
    """Resolve ``host`` once (getaddrinfo, at most ``timeout_s``, default :data:`RESOLVE_TIMEOUT_S`) to the
    address the page will be bound to: the first one returned. Raises ``ValueError`` (one line) if the name does
    not resolve in time, if the address is not loopback and ``lan`` is False, or if it is a wildcard address
    (the page checks the ``Host`` header against the names it is served under, so it must have one)."""
    timeout_s = RESOLVE_TIMEOUT_S if timeout_s is None else timeout_s
    result: list = []
    bare = host[1:-1] if host.startswith("[") and host.endswith("]") else host  # [::1] as in a URL

    def lookup() -> None:
        try:
            result.append(socket.getaddrinfo(bare, port, type=socket.SOCK_STREAM))
        except (OSError, UnicodeError) as exc:
            result.append(exc)

    # A daemon thread, not an executor: a lookup that never returns must not keep the process alive.
    t = threading.Thread(target=lookup, name="view3d-resolve", daemon=True)
    t.start()
    t.join(timeout_s)
    if not result:
        raise ValueError(f"--http {host}: the name did not resolve within {timeout_s:g} s")
    got = result[0]
    if isinstance(got, BaseException):
        reason = getattr(got, "strerror", None) or str(got)
        raise ValueError(f"--http {host}: cannot resolve the name ({reason})")
    usable = [g for g in got if g[0] in (socket.AF_INET, socket.AF_INET6)]
    if not usable:
        raise ValueError(f"--http {host}: the name has no IPv4 or IPv6 address")
    family, _, _, _, sockaddr = usable[0]
    ip = ipaddress.ip_address(str(sockaddr[0]).split("%")[0])
    if not ip.is_loopback and not lan:
        raise ValueError(
            f"--http {host}: {ip} is not a loopback address; the page can take the helm, so it is served on "
            "loopback unless --lan is given"
        )
    if ip.is_unspecified:
        raise ValueError(
            f"--http {host}: give the address or name the page is opened with, not a wildcard "
            "(requests are checked against it)"
        )
    return PageAddress(bare, family, sockaddr)


def bind_page_socket(addr: PageAddress) -> socket.socket:
    """A TCP socket bound to exactly the resolved address and listening (viser serves on it; it never binds a
    name, and never moves to another port)."""
    sock = socket.socket(addr.family, socket.SOCK_STREAM)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        if addr.family == socket.AF_INET6:
            sock.setsockopt(socket.IPPROTO_IPV6, socket.IPV6_V6ONLY, 1)
        sock.bind(addr.sockaddr)
        sock.listen(64)
    except OSError as exc:
        sock.close()
        port = addr.sockaddr[1]
        raise ValueError(f"cannot serve the page on {addr.url_host(port)}: {exc.strerror or exc}") from None
    return sock


class PageGate:
    """The checks of every request and message of the page, and their counts.

    ``hosts`` are the names the page is served under (without port); ``port`` the port it listens on; ``key``
    the helm secret (a new random one by default). Counts are in :meth:`stats`.
    """

    def __init__(self, hosts: Iterable[str], port: int, key: str | None = None) -> None:
        import msgspec
        import viser
        from viser import _messages

        self.key = key or secrets.token_urlsafe(18)
        names = {h.lower().strip("[]") for h in hosts}
        self.hosts: set[str] = set()
        for n in names:
            shown = f"[{n}]" if ":" in n else n  # an IPv6 literal in a Host header is bracketed
            self.hosts.add(f"{shown}:{port}")
            if port == 80:
                self.hosts.add(shown)  # a browser leaves out the default port
        self.origins = {f"http://{h}" for h in self.hosts}
        self._lock = threading.Lock()
        self._counts: Counter[str] = Counter()
        # connection -> "helm" or "watch", from its upgrade request (weak: a failed handshake leaves nothing)
        self._roles: weakref.WeakKeyDictionary[Any, str] = weakref.WeakKeyDictionary()
        self._open = 0  # websockets open now (touched on viser's event loop thread only)
        self._decode = msgspec.msgpack.decode
        self._convert = msgspec.convert
        # RecursionError: msgspec's answer to deeply nested data (a 100 kB message can nest 100 000 deep)
        self._invalid = (msgspec.DecodeError, msgspec.ValidationError, TypeError, ValueError, RecursionError)
        self._classes = {name: getattr(_messages, name) for name in HELM_MESSAGES}
        # the page's client offers this websocket subprotocol (viser picks the first "viser-v..." offered)
        self._subprotocol = f"viser-v{viser.__version__}"

    @property
    def helm_path(self) -> str:
        return HELM_PATH + self.key

    # -- counts ------------------------------------------------------------------------------------------------

    def count(self, what: str, n: int = 1) -> None:
        with self._lock:
            self._counts[what] += n

    def stats(self) -> dict[str, int]:
        """Counts so far: ``refused ...`` (HTTP requests and upgrades answered 403), ``dropped ...`` (websocket
        messages), ``accepted helm``/``accepted watch`` (websocket connections), ``server errors``."""
        with self._lock:
            return dict(self._counts)

    # -- requests ----------------------------------------------------------------------------------------------

    def check_request(self, path: str, headers: Any) -> tuple[int, str, str | None]:
        """(status, reason, role) for one HTTP request or websocket upgrade: status 0 lets it through to viser
        with ``role`` ("helm" or "watch"), 403 refuses it with ``reason``. ``headers`` is websockets' Headers
        (``get_all``)."""
        upgrade = any(v.lower() == "websocket" for v in headers.get_all("Upgrade"))
        host = headers.get_all("Host")
        if len(host) != 1 or host[0].lower() not in self.hosts:
            return 403, "host", None
        origin = headers.get_all("Origin")
        if len(origin) > 1 or (origin and origin[0].lower() not in self.origins):
            return 403, "origin", None  # a foreign page, a sandboxed or file page ("null")
        if upgrade and not origin:
            return 403, "origin", None  # a browser always sends Origin with a websocket upgrade
        route = path.partition("?")[0]
        if route.startswith(HELM_PATH):
            given = route[len(HELM_PATH) :].rstrip("/")
            if not hmac.compare_digest(given.encode("utf-8", "replace"), self.key.encode()):
                return 403, "key", None
            return 0, "", "helm"
        return 0, "", "watch"

    # -- messages ----------------------------------------------------------------------------------------------

    def admit(self, raw: object, role: str) -> bool:
        """Whether one websocket message from a page (of ``role``) may reach viser; counts what it drops."""
        if not isinstance(raw, bytes):
            self.count("dropped text frame")
            return False
        try:
            mapping = self._decode(raw)
        except self._invalid:
            self.count("dropped undecodable")
            return False
        kind = mapping.get("type") if isinstance(mapping, dict) else None
        allowed = HELM_MESSAGES if role == "helm" else WATCH_MESSAGES
        if not isinstance(kind, str) or kind not in allowed:
            self.count("dropped not allowed" if kind in HELM_MESSAGES else "dropped unknown type")
            return False
        fields = {k: v for k, v in mapping.items() if k != "type"}
        try:
            self._convert(fields, self._classes[kind])
        except self._invalid:
            self.count("dropped bad fields")
            return False
        if kind == "GuiUpdateMessage" and not _value_update(fields["updates"]):
            # a page only ever sends a new value; viser would set any property a message names
            self.count("dropped bad fields")
            return False
        if not _finite(fields):
            self.count("dropped bad fields")
            return False
        return True

    # -- the hooks into websockets' server (run on viser's event loop thread) ----------------------------------

    def process_request(self, viser_process_request: Any, connection: Any, request: Any) -> Any:
        try:
            status, reason, role = self.check_request(request.path, request.headers)
        except Exception:  # noqa: BLE001 - a request the checks cannot read is refused, never a traceback
            status, reason, role = 403, "malformed", None
        if status:
            self.count(f"refused {reason}")
            return connection.respond(status, f"403 Forbidden: {_REFUSALS[reason]}\n")
        if any(v.lower() == "websocket" for v in request.headers.get_all("Upgrade")):
            if self._open >= MAX_CONNECTIONS:
                self.count("refused busy")
                return connection.respond(503, "503 Service Unavailable: too many open pages\n")
            self._roles[connection] = role  # taken by handle() as soon as the upgrade completes
            return None
        if role == "helm":
            from websockets.http11 import Request

            request = Request("/", request.headers)  # the same page (viser serves one index.html)
        try:
            response = viser_process_request(connection, request) if viser_process_request else None
        except Exception:  # noqa: BLE001 - counted, answered 500
            self.count("server errors")
            return connection.respond(500, "500 Internal Server Error\n")
        if response is None:  # an upgrade the checks above did not see as one: never let it through
            self.count("refused malformed")
            return connection.respond(403, f"403 Forbidden: {_REFUSALS['malformed']}\n")
        # The page's URL may carry the key: no caching, no referrer, no framing by another page.
        response.headers["Cache-Control"] = "no-store"
        response.headers["Referrer-Policy"] = "no-referrer"
        response.headers["X-Frame-Options"] = "DENY"
        response.headers["Content-Security-Policy"] = "frame-ancestors 'none'"
        response.headers["X-Content-Type-Options"] = "nosniff"
        return response

    async def handle(self, viser_handler: Any, connection: Any) -> None:
        import asyncio

        # viser handles each message in a task of its own: one that fails is counted, not printed at exit
        asyncio.get_running_loop().set_exception_handler(lambda _loop, _ctx: self.count("server errors"))
        role = self._roles.pop(connection, None) or "watch"
        if connection.subprotocol != self._subprotocol:
            # viser would refuse it too, but print a banner on stdout for each such connection
            self.count("refused version")
            await connection.close(1002, "not a viser client of this version")
            return
        self.count(f"accepted {role}")
        self._open += 1
        _ROLE.set(role)  # this task's context: viser's tasks for the connection inherit it
        inner = connection.recv
        gate = self
        bucket = [float(MESSAGE_BURST), time.monotonic()]

        async def recv(*args: Any, **kwargs: Any) -> Any:
            from websockets.exceptions import ConnectionClosedError

            while True:
                try:
                    raw = await inner(*args, **kwargs)
                except ConnectionClosedError as exc:
                    code = exc.sent.code if exc.sent is not None else None
                    if code == 1009:  # message too big
                        gate.count("dropped oversized")
                    elif code in (1002, 1007):  # not a websocket frame (protocol error), text not UTF-8
                        gate.count("dropped bad frame")
                    raise
                now = time.monotonic()
                bucket[0] = min(float(MESSAGE_BURST), bucket[0] + (now - bucket[1]) * MESSAGE_RATE_HZ)
                bucket[1] = now
                if bucket[0] < 1.0:
                    gate.count("dropped over rate")
                    continue
                bucket[0] -= 1.0
                if gate.admit(raw, role):
                    return raw

        connection.recv = recv
        try:
            await viser_handler(connection)
        except Exception:  # noqa: BLE001 - counted; the connection is closed by websockets
            self.count("server errors")
        finally:
            self._open -= 1


def current_role() -> str | None:
    """The role ("helm" or "watch") of the page connection whose callback runs now (async viser callbacks
    run in the connection's context), or None outside one."""
    return _ROLE.get()


_REFUSALS = {
    "host": "this page is not served under that host name",
    "origin": "requests from other pages are refused",
    "key": "wrong helm key",
    "malformed": "malformed request",
}


def _value_update(updates: dict) -> bool:
    return set(updates) == {"value"} and isinstance(updates["value"], (bool, int, float, str))


def _finite(obj: object) -> bool:
    if isinstance(obj, float):
        return math.isfinite(obj)
    if isinstance(obj, dict):
        return all(_finite(v) for v in obj.values())
    if isinstance(obj, (list, tuple)):
        return all(_finite(v) for v in obj)
    return True


class _CountingHandler(logging.Handler):
    """websockets' log (a failed handshake, a failed handler) counted instead of printed."""

    def __init__(self, gate: PageGate) -> None:
        super().__init__(logging.DEBUG)
        self.gate = gate

    def emit(self, record: logging.LogRecord) -> None:
        if record.levelno >= logging.ERROR:
            msg = record.getMessage()
            self.gate.count("refused malformed" if "handshake" in msg else "server errors")


_SERVE_LOCK = threading.Lock()


@contextlib.contextmanager
def _serve_through_gate(gate: PageGate, sock: socket.socket) -> Iterator[None]:
    """While viser starts its server, route its call to ``websockets.asyncio.server.serve`` through the gate.

    viser's ``WebsockServer`` calls that function once, from its own thread, with its websocket handler and its
    HTTP handler (``process_request``), before ``ViserServer()`` returns; nothing else lets a caller see or
    refuse a request. The replacement passes both through :class:`PageGate`, listens on ``sock`` (bound to the
    resolved address) instead of viser's host and port, caps the message size and sends websockets' log to a
    counter. Any other caller in the window gets the original function unchanged.
    """
    import websockets.asyncio.server as ws_server

    original = ws_server.serve
    used = []

    def serve(handler: Any, host: Any = None, port: Any = None, **kwargs: Any) -> Any:
        if not getattr(handler, "__module__", "").startswith("viser."):
            return original(handler, host, port, **kwargs)
        # viser's own call (again if the first raised OSError: viser then retries on the next port; every
        # try gets the gate and ``sock``, never viser's host and port)
        used.append(True)
        viser_pr = kwargs.pop("process_request", None)
        kwargs.update(
            sock=sock,
            max_size=MAX_MESSAGE_BYTES,
            logger=gate_logger(gate),
            process_request=lambda c, r: gate.process_request(viser_pr, c, r),
        )
        return original(lambda c: gate.handle(handler, c), **kwargs)

    with _SERVE_LOCK:
        ws_server.serve = serve
        try:
            yield
        finally:
            ws_server.serve = original
    if not used:
        raise RuntimeError("viser did not start its server through websockets.asyncio.server.serve")


def gate_logger(gate: PageGate) -> logging.Logger:
    """websockets' logger for the page's server: counts into ``gate``, prints nothing (not registered, so one
    per server and gone with it)."""
    log = logging.Logger("vessel_gym.view3d.websockets", logging.INFO)
    log.propagate = False
    log.addHandler(_CountingHandler(gate))
    return log


def gated_viser_server(gate: PageGate, sock: socket.socket, **viser_kwargs: Any) -> Any:
    """A ``viser.ViserServer`` listening on ``sock`` whose every request and message passes ``gate``."""
    import viser

    with _serve_through_gate(gate, sock), contextlib.redirect_stdout(io.StringIO()):
        # viser prints its own banner; ours names the URL. host/port are unused: viser listens on ``sock``.
        return viser.ViserServer(host="127.0.0.1", port=sock.getsockname()[1], verbose=False, **viser_kwargs)


__all__ = [
    "HELM_MESSAGES",
    "MAX_MESSAGE_BYTES",
    "MESSAGE_RATE_HZ",
    "PageAddress",
    "PageGate",
    "RESOLVE_TIMEOUT_S",
    "WATCH_MESSAGES",
    "bind_page_socket",
    "current_role",
    "gated_viser_server",
    "resolve_page_address",
]
