"""The classroom's server: one port serves the page and its websocket (``/ws``), and one loop runs the harbour.

Built on the ``websockets`` library (already a dependency of the 3D view): its asyncio server answers plain
HTTP requests through ``process_request`` (the page, its script) and upgrades ``/ws``; one event loop holds
the simulation, every connection and the pacing, so no lock is needed anywhere.

Access, in the order a request meets it (``docs/classroom.md``):

1. **Host**: the ``Host`` header must name this server: the bound address, ``localhost`` on loopback, a name
   given with ``--host-name``, or (bound to every interface) any IP literal, with this port. A DNS-rebinding
   page carries its own domain name and is refused.
2. **Origin** (``/ws`` only): exactly ``http(s)://`` + that Host: a page of any other origin cannot open the
   socket, whatever code it holds.
3. **Connections**: at most :data:`MAX_CONNECTIONS`, :data:`MAX_CONNECTIONS_PER_HOST` from one address.
4. **Frames**: at most :data:`MAX_FRAME_BYTES` (the library closes the connection with 1009 beyond it), text
   JSON objects only; every message spends a token of its connection's bucket (:data:`MESSAGE_RATE_HZ`,
   :class:`~vessel_gym.net.access.TokenBucket`); a connection that keeps flooding is closed.
5. **Join**: the first message must be a ``join`` with a code, within :data:`JOIN_TIMEOUT_S`; join attempts
   spend the budgets of the sender's address and of everyone (:class:`~vessel_gym.net.access.Access`), and a
   connection is closed after :data:`MAX_BAD_CODES` wrong codes. A helm code gives one ship to one connection
   at a time: a second page with the same code is refused while the first is open (no helm theft).
6. **Session**: the welcome carries a fresh random session; every later message of that connection must carry
   it (constant-time comparison). A session is worth nothing on another connection or after its own closed.

Codes travel only inside websocket messages (never in a URL), so no access log could hold one; the server
logs counts, never a message's content.
"""

from __future__ import annotations

import asyncio
import contextlib
import hmac
import ipaddress
import json
import logging
import math
import secrets
import ssl
import threading
import time
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from vessel_gym.classroom.codes import ClassCodes, Role
from vessel_gym.classroom.harbour import ClassHarbour
from vessel_gym.net.access import Access, TokenBucket, is_loopback, token_bytes

#: the largest frame a page may send (B): a join or an order is under 200 B; a weather order under 300 B
MAX_FRAME_BYTES = 1024
#: messages per second a connection may send (bursts of one second): a held key sends at most 20 orders/s
MESSAGE_RATE_HZ = 30.0
#: a connection that has had this many messages refused for rate is closed (a page that floods on purpose)
FLOOD_CLOSE_AFTER = 100
#: join attempts per second from one address (a class behind one NAT joins within a few seconds), and from all
#: addresses together; the codes' 128 bits make guessing hopeless at any rate: this caps the work a flood costs
JOIN_RATE_PER_HOST_HZ = 5.0
JOIN_RATE_TOTAL_HZ = 30.0
#: wrong codes, bad sessions or malformed messages a connection may send before it is closed
MAX_BAD_CODES = 3
MAX_BAD_MESSAGES = 10
#: a connection must join within this time (s) or it is closed
JOIN_TIMEOUT_S = 10.0
MAX_CONNECTIONS = 64
MAX_CONNECTIONS_PER_HOST = 16
#: a connection whose unsent data exceeds this (B) skips state messages until it has caught up
SLOW_CLIENT_BYTES = 256 * 1024
#: the longest student name kept (characters)
MAX_NAME_CHARS = 32

log = logging.getLogger("vessel_gym.classroom")


class _NoFrames(logging.LoggerAdapter):
    """The websocket library's logger without its debug level: at debug it logs every frame's text, and a join
    frame holds a code. Its warnings and errors (a handler's failure) pass."""

    def isEnabledFor(self, level: int) -> bool:  # noqa: N802 (logging's name)
        return level > logging.DEBUG and self.logger.isEnabledFor(level)


@dataclass(eq=False)  # one per connection, hashed by identity
class Client:
    """One open websocket: its peer address, role after a join, session, budgets and misdeeds."""

    conn: Any
    host: str
    role: Role | None = None
    session: str = ""
    name: str = ""
    bucket: TokenBucket = field(default_factory=lambda: TokenBucket(MESSAGE_RATE_HZ, time.monotonic()))
    rate_refused: int = 0
    bad_codes: int = 0
    bad: int = 0
    ack: int = -1  # the last order's sequence number, echoed in every state
    closing: bool = False


class ClassroomServer:
    """The classroom of ``harbour`` with ``codes`` on ``sock``'s address (module doc).

    ``host_names``: extra names the pages may be opened by (``Host``); ``tls``: an SSL context or None;
    ``time_factor``: simulation seconds per wall-clock second; ``debrief_path``: where the class debrief goes.
    """

    def __init__(
        self,
        harbour: ClassHarbour,
        codes: ClassCodes,
        bind: tuple[str, int],
        *,
        host_names: tuple[str, ...] = (),
        tls: ssl.SSLContext | None = None,
        time_factor: float = 1.0,
        debrief_path: Path | None = None,
    ) -> None:
        self.harbour = harbour
        self.codes = codes
        self.bind = bind
        self.host_names = tuple(h.lower() for h in host_names)
        self.tls = tls
        self.scheme = "https" if tls is not None else "http"
        self.time_factor = time_factor
        self.debrief_path = debrief_path
        self.paused = False
        self.clients: set[Client] = set()
        self.helms: dict[int, Client] = {}  # ship -> the connection at its helm
        self.stats: dict[str, int] = dict.fromkeys(
            (
                "pages",
                "bad_host",
                "bad_origin",
                "not_found",
                "too_many",
                "joins",
                "bad_code",
                "join_rate",
                "taken",
                "bad_session",
                "malformed",
                "rate",
                "flood_closed",
                "oversize",
                "orders",
            ),
            0,
        )
        self.port = 0
        self._access = Access(
            None,
            max_rate_per_client_hz=MESSAGE_RATE_HZ,
            max_clients=MAX_CONNECTIONS,
            max_clients_per_host=MAX_CONNECTIONS_PER_HOST,
            unverified_rate_per_host_hz=JOIN_RATE_PER_HOST_HZ,
            unverified_rate_total_hz=JOIN_RATE_TOTAL_HZ,
        )
        self._page = resources.files("vessel_gym.classroom").joinpath("page.html").read_bytes()
        self._script = resources.files("vessel_gym.classroom").joinpath("page.js").read_bytes()
        self._script3d = resources.files("vessel_gym.classroom").joinpath("scene3d.js").read_bytes()
        self._scene3d: dict[str, Any] | None = None  # built at the first student's join
        self._loop: asyncio.AbstractEventLoop | None = None
        self._stop: asyncio.Event | None = None
        self._thread: threading.Thread | None = None
        self._sending: set[asyncio.Future] = set()
        self.step_ms: list[float] = []  # wall time of each harbour step, ms (the last 1000)

    # --- the gate ---------------------------------------------------------------------------------------------

    def host_ok(self, host_header: str | None) -> bool:
        """The Host header names this server (module doc, 1)."""
        if not host_header or len(host_header) > 255:
            return False
        host, sep, port = host_header.rpartition(":")
        if not sep or port != str(self.port):
            return False
        host = host.lower()
        if host.startswith("[") and host.endswith("]"):
            host = host[1:-1]
        bound = self.bind[0]
        if host == bound or host in self.host_names:
            return True
        if host == "localhost":
            return is_loopback(bound)
        try:
            ip = ipaddress.ip_address(host)
        except ValueError:
            return False  # a name not given with --host-name (a rebinding page's own domain)
        if bound in ("", "0.0.0.0", "::"):
            return (
                True  # bound to every interface: any address of this machine (an IP literal is no rebinding)
            )
        return ip.is_loopback and is_loopback(bound)

    def _response(self, status: int, body: bytes, ctype: str) -> Any:
        from websockets.datastructures import Headers
        from websockets.http11 import Response

        reason = {
            200: "OK",
            204: "No Content",
            403: "Forbidden",
            404: "Not Found",
            421: "Misdirected Request",
            503: "Busy",
        }
        headers = Headers(
            [
                ("Content-Type", ctype),
                ("Content-Length", str(len(body))),
                ("Cache-Control", "no-store"),
                ("X-Content-Type-Options", "nosniff"),
                ("X-Frame-Options", "DENY"),
                ("Referrer-Policy", "no-referrer"),
                (
                    "Content-Security-Policy",
                    "default-src 'none'; script-src 'self'; style-src 'unsafe-inline'; connect-src 'self'; "
                    "img-src 'self' blob: data:; frame-ancestors 'none'; base-uri 'none'; form-action 'none'",
                ),
            ]
        )
        return Response(status, reason.get(status, "Error"), headers, body)

    def process_request(self, connection: Any, request: Any) -> Any:
        """Every HTTP request: the page and its script, or the websocket's upgrade if it passes the gate."""
        headers = request.headers
        host = headers.get("Host")
        if not self.host_ok(host):
            self.stats["bad_host"] += 1
            return self._response(421, b"this server is not reached by that name\n", "text/plain")
        path = request.path.split("?", 1)[0]
        if path == "/":
            self.stats["pages"] += 1
            return self._response(200, self._page, "text/html; charset=utf-8")
        if path == "/page.js":
            return self._response(200, self._script, "text/javascript; charset=utf-8")
        if path == "/scene3d.js":
            return self._response(200, self._script3d, "text/javascript; charset=utf-8")
        if path == "/favicon.ico":  # browsers ask for it: no icon, and no error in the page's console
            return self._response(204, b"", "image/x-icon")
        if path != "/ws":
            self.stats["not_found"] += 1
            return self._response(404, b"not found\n", "text/plain")
        origins = headers.get_all("Origin")
        if len(origins) != 1 or origins[0] != f"{self.scheme}://{host}":
            self.stats["bad_origin"] += 1
            return self._response(403, b"origin refused\n", "text/plain")
        peer = _peer_host(connection)
        same = sum(1 for c in self.clients if c.host == peer)
        if len(self.clients) >= MAX_CONNECTIONS or same >= MAX_CONNECTIONS_PER_HOST:
            self.stats["too_many"] += 1
            return self._response(503, b"too many connections\n", "text/plain")
        return None

    # --- one connection ---------------------------------------------------------------------------------------

    async def handler(self, conn: Any) -> None:
        from websockets.exceptions import ConnectionClosed

        client = Client(conn, _peer_host(conn))
        self.clients.add(client)
        try:
            deadline = time.monotonic() + JOIN_TIMEOUT_S  # the whole join, wrong codes included
            while client.role is None and not client.closing:
                try:
                    raw = await asyncio.wait_for(conn.recv(), max(deadline - time.monotonic(), 0.0))
                except TimeoutError:
                    await _close(client, "join within 10 s")
                    return
                await self._message(client, raw)
            async for raw in conn:
                await self._message(client, raw)
        except ConnectionClosed as exc:
            if exc.rcvd is None and exc.sent is not None and exc.sent.code == 1009:
                self.stats["oversize"] += 1
        finally:
            self.clients.discard(client)
            if (
                client.role is not None
                and client.role.kind == "helm"
                and self.helms.get(client.role.ship) is client
            ):
                del self.helms[client.role.ship]

    async def _message(self, client: Client, raw: Any) -> None:
        if client.closing:  # what it sent before our close frame reached it is not read
            return
        if client.role is not None and not client.bucket.take(MESSAGE_RATE_HZ, time.monotonic()):
            self.stats["rate"] += 1
            client.rate_refused += 1
            if client.rate_refused >= FLOOD_CLOSE_AFTER:
                self.stats["flood_closed"] += 1
                await _close(client, "too many messages")
            return
        try:
            msg = json.loads(raw) if isinstance(raw, str) else None
        except ValueError:
            msg = None
        if not isinstance(msg, dict) or not isinstance(msg.get("type"), str):
            await self._bad(client, "malformed", "a message is a JSON object with a type")
            return
        if client.role is None:
            await self._join(client, msg)
            return
        session = msg.get("session")
        if not isinstance(session, str) or not hmac.compare_digest(
            token_bytes(session), token_bytes(client.session)
        ):
            await self._bad(client, "bad_session", "not this connection's session")
            return
        kind, typ = client.role.kind, msg["type"]
        try:
            if kind == "helm" and typ == "order":
                await self._order(client, msg)
            elif kind == "instructor" and typ in INSTRUCTOR_COMMANDS:
                await self._command(client, typ, msg)
            else:
                raise ValueError(f"{typ!r} is not a message a {kind} may send")
        except ValueError as exc:
            await self._bad(client, "malformed", str(exc))

    async def _bad(self, client: Client, what: str, text: str) -> None:
        self.stats[what] += 1
        client.bad += 1
        await _send(client.conn, {"type": "error", "error": text})
        if client.bad >= MAX_BAD_MESSAGES:
            await _close(client, "too many bad messages")

    async def _join(self, client: Client, msg: dict) -> None:
        conn = client.conn
        if msg["type"] != "join":
            await self._bad(client, "malformed", "join first")
            if client.bad >= 1:
                await _close(client, "join first")
            return
        if not self._access.admit_unverified(client.host, time.monotonic()):
            self.stats["join_rate"] += 1
            client.bad += 1  # a connection that keeps trying is closed like one that sends garbage
            await _send(conn, {"type": "refused", "error": "too many join attempts: wait a second"})
            if client.bad >= MAX_BAD_MESSAGES:
                await _close(client, "too many join attempts")
            return
        role = self.codes.role(msg.get("code"))
        if role is None:
            self.stats["bad_code"] += 1
            client.bad_codes += 1
            await _send(conn, {"type": "refused", "error": "unknown code"})
            if client.bad_codes >= MAX_BAD_CODES:
                await _close(client, "too many wrong codes")
            return
        if role.kind == "helm":
            if role.ship in self.harbour.pilot_ships or role.ship in self.harbour.agent_ships:
                await _send(conn, {"type": "refused", "error": "this ship is steered by a pilot or an agent"})
                return
            if role.ship in self.helms:
                self.stats["taken"] += 1
                await _send(conn, {"type": "refused", "error": "this ship already has a helmsman"})
                return
            self.helms[role.ship] = client
        self.stats["joins"] += 1
        client.role = role
        client.session = secrets.token_urlsafe(16)
        client.name = _clean_name(msg.get("name"))
        client.bucket = TokenBucket(MESSAGE_RATE_HZ, time.monotonic())
        h = self.harbour
        if role.kind == "helm" and client.name:
            h.names[role.ship] = client.name
        welcome = {
            "type": "welcome",
            "role": role.kind,
            "ship": role.ship,
            "session": client.session,
            "chart": h.chart(),
            "rudder_step_deg": 5.0,
            "dt_s": h.dt,
        }
        if role.kind == "helm":  # the bridge's 3D view
            if self._scene3d is None:
                from vessel_gym.classroom.scene3d import class_scene

                self._scene3d = class_scene(h)
            welcome["scene3d"] = self._scene3d
        await _send(conn, welcome)
        await _send(conn, self._state_for(client, self._common()))

    async def _order(self, client: Client, msg: dict) -> None:
        rudder, tele, seq = msg.get("rudder"), msg.get("telegraph"), msg.get("seq")
        if not _number(rudder) or not _integer(tele) or not _integer(seq) or not 0 <= seq < 2**53:
            raise ValueError("order: rudder (deg), telegraph (integer) and seq (integer) expected")
        self.harbour.order(client.role.ship, float(rudder), int(tele))
        self.stats["orders"] += 1
        client.ack = int(seq)
        await _send(client.conn, self._state_for(client, self._common()))  # the echo, at once

    async def _command(self, client: Client, typ: str, msg: dict) -> None:
        h = self.harbour
        if typ == "pause":
            self.paused = True
        elif typ == "resume":
            self.paused = False
        elif typ == "reset":
            ship = msg.get("ship")
            if ship == "all":
                h.reset_all()
            elif _integer(ship) and 0 <= ship < h.n:
                h.reset_ship(int(ship))
            else:
                raise ValueError(f"reset: ship 0..{h.n - 1} or 'all' expected")
        elif typ == "weather":
            fields = {k: msg[k] for k in WEATHER_FIELDS if k in msg}
            if not fields or not all(_number(v) for v in fields.values()):
                raise ValueError(f"weather: numbers expected for some of {', '.join(WEATHER_FIELDS)}")
            try:
                h.set_weather(**fields)
            except ValueError as exc:  # SpecError is a ValueError: the field and its range
                raise ValueError(f"weather: {exc}") from None
        elif typ == "revoke":
            ship = msg.get("ship")
            if not _integer(ship) or not 0 <= ship < h.n:
                raise ValueError(f"revoke: ship 0..{h.n - 1} expected")
            self.codes.revoke(int(ship))
            holder = self.helms.pop(int(ship), None)
            if holder is not None:
                holder.role = None
                await _close(holder, "helm code revoked")
        elif typ == "debrief":
            html_text, path = self.write_debrief()
            await _send(
                client.conn, {"type": "debrief", "path": str(path) if path else None, "html": html_text}
            )
            return
        await _send(client.conn, {**self._state_for(client, self._common()), "done": typ})

    # --- state out --------------------------------------------------------------------------------------------

    def _common(self) -> dict[str, Any]:
        h = self.harbour
        return {
            "type": "state",
            "t_s": round(h.t_s, 2),
            "paused": self.paused,
            "ships": h.ships(),
            "targets": h.targets(),
            "weather": {k: round(v, 3) for k, v in h.weather.items()},
        }

    def _state_for(self, client: Client, common: dict[str, Any]) -> dict[str, Any]:
        role = client.role
        if role is None:
            return common
        if role.kind == "helm":
            # a student knows the truth of the own ship only: the others come as its AIS receiver has them
            h = self.harbour
            k = role.ship
            return {
                **{key: v for key, v in common.items() if key not in ("ships", "targets")},
                "ships": [common["ships"][k]],
                "ais": h.ais_picture(k),
                "own": h.conning(k),
                "radar": h.targets_for(k),
                "ack": client.ack,
            }
        if role.kind == "instructor":
            h = self.harbour
            return {
                **common,
                "class": [
                    {
                        "k": k,
                        "name": h.names[k],
                        "code": self.codes.helm[k],
                        "at_helm": k in self.helms,
                        "pilot": k in h.pilot_ships,
                        "agent": k in h.agent_ships,
                        **h.conning(k),
                    }
                    for k in range(h.n)
                ],
                "spectator_code": self.codes.spectator,
                "stats": dict(self.stats),
            }
        return common

    def broadcast(self) -> None:
        common = self._common()
        text = json.dumps(common, allow_nan=False)
        for c in list(self.clients):
            if c.role is None:
                continue
            transport = getattr(c.conn, "transport", None)
            if transport is not None and transport.get_write_buffer_size() > SLOW_CLIENT_BYTES:
                continue  # a slow page skips states rather than filling the server's memory
            data = (
                text
                if c.role.kind == "spectator"
                else json.dumps(self._state_for(c, common), allow_nan=False)
            )
            task = asyncio.ensure_future(_send_text(c.conn, data))
            self._sending.add(task)  # held until sent (the loop keeps only weak references)
            task.add_done_callback(self._sending.discard)

    async def _run_harbour(self) -> None:
        period = self.harbour.dt / self.time_factor
        due = time.monotonic()
        while True:
            due += period
            if not self.paused:
                t0 = time.perf_counter()
                self.harbour.step()
                self.step_ms = (self.step_ms + [(time.perf_counter() - t0) * 1e3])[-1000:]
            self.broadcast()
            delay = due - time.monotonic()
            if delay < -period:  # behind by more than a step (a loaded machine): do not race to catch up
                due = time.monotonic()
                delay = 0.0
            await asyncio.sleep(max(delay, 0.0))

    # --- debrief ----------------------------------------------------------------------------------------------

    def write_debrief(self) -> tuple[str, Path | None]:
        from vessel_gym.classroom.debrief import class_debrief_html

        html_text = class_debrief_html(self.harbour)
        if self.debrief_path is not None:
            self.debrief_path.parent.mkdir(parents=True, exist_ok=True)
            self.debrief_path.write_text(html_text, encoding="utf-8")
        return html_text, self.debrief_path

    # --- running ----------------------------------------------------------------------------------------------

    async def serve(
        self, sock: Any, ready: threading.Event | None = None, duration_s: float | None = None
    ) -> None:
        from websockets.asyncio.server import serve

        self._loop = asyncio.get_running_loop()
        self._stop = asyncio.Event()
        self.port = sock.getsockname()[1]
        async with serve(
            self.handler,
            sock=sock,
            process_request=self.process_request,
            max_size=MAX_FRAME_BYTES,
            max_queue=32,
            close_timeout=2.0,  # a page that does not answer our close within 2 s is dropped
            compression=None,  # no deflate: frames stay the size they say (no compression bombs)
            server_header=None,
            ssl=self.tls,
            logger=_NoFrames(log, {}),
        ):
            runner = asyncio.ensure_future(self._run_harbour())
            # a harbour that fails (a bug, not a ship's divergence: the task ends that ship's run) ends the class
            runner.add_done_callback(lambda _t: self._stop.set())
            if ready is not None:
                ready.set()
            try:
                if duration_s is None:
                    await self._stop.wait()
                else:
                    with contextlib.suppress(TimeoutError):
                        await asyncio.wait_for(self._stop.wait(), duration_s)
            finally:
                runner.cancel()
                with contextlib.suppress(asyncio.CancelledError):
                    await runner  # raises what stopped the harbour, if anything did

    def start_in_thread(self, sock: Any) -> None:
        """Serve from a background thread (tests, benchmarks); returns once the socket is served."""
        ready = threading.Event()
        self._thread = threading.Thread(target=lambda: asyncio.run(self.serve(sock, ready)), daemon=True)
        self._thread.start()
        if not ready.wait(60):
            raise RuntimeError("the classroom server did not start within 60 s")

    def stop(self) -> None:
        if self._loop is not None and self._stop is not None:
            self._loop.call_soon_threadsafe(self._stop.set)
        if self._thread is not None:
            self._thread.join(15)

    def call(self, fn: Any, *args: Any) -> Any:
        """Run ``fn(*args)`` in the server's loop and return its result (the harbour has one owner)."""
        assert self._loop is not None

        async def run() -> Any:
            return fn(*args)

        return asyncio.run_coroutine_threadsafe(run(), self._loop).result(30)


INSTRUCTOR_COMMANDS = ("pause", "resume", "reset", "weather", "revoke", "debrief")
WEATHER_FIELDS = ("wind_speed_m_s", "wind_from_deg", "current_speed_m_s", "current_to_deg")


async def _close(client: Client, reason: str) -> None:
    """Close ``client``'s connection for a policy violation (1008) and read nothing more of it."""
    client.closing = True
    await client.conn.close(1008, reason)


async def _send(conn: Any, msg: dict) -> None:
    await _send_text(conn, json.dumps(msg, allow_nan=False))


async def _send_text(conn: Any, text: str) -> None:
    from websockets.exceptions import ConnectionClosed

    with contextlib.suppress(ConnectionClosed):  # a connection closing now: its handler cleans up
        await conn.send(text)


def _peer_host(conn: Any) -> str:
    addr = getattr(conn, "remote_address", None)
    return str(addr[0]) if addr else "?"


def _number(v: object) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _integer(v: object) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


def _clean_name(v: object) -> str:
    """A student's name as shown to the instructor: printable characters only, at most MAX_NAME_CHARS."""
    if not isinstance(v, str):
        return ""
    return "".join(ch for ch in v if ch.isprintable()).strip()[:MAX_NAME_CHARS]
