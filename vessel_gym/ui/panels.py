"""pygame panels of the JSON channel: a helm panel and a passive viewer.

Both reach a :class:`~vessel_gym.net.link.UdpLink` on this or another host through a
:class:`~vessel_gym.net.clients.ServerConnection` (UDP, ``hello`` every 0.5 s as keep-alive) and draw a
readout panel plus a north-up chart of the own track and the targets. The helm panel starts as a watcher
(registered as a viewer, sending no orders); after ``t`` it takes the helm and sends its full order (rudder,
telegraph) at 10-20 Hz:

=============  ===============================================
key            action
=============  ===============================================
t              take the helm
w              give the helm back and watch (released at once)
left / right   rudder order 5 deg to port / starboard
0              rudder midships
up / down      telegraph one step ahead / astern
z / x          first thruster or tug a quarter more to port / starboard (a ship that has them: Berthing)
c / v          second thruster or tug; ``,`` / ``.`` the third
b              every thruster and tug to zero
Esc, q         quit (sends ``bye``, releasing the helm)
=============  ===============================================

On ``t`` the panel takes its orders from the next state it receives, so taking the helm does not jerk the
rudder or the engine. Both clients join with the cookie handshake of ``docs/protocol.md`` and accept datagrams
only from the server they joined. pygame is imported only inside the functions that draw (extra ``render``).
"""

from __future__ import annotations

import math
import os
import time
from collections import deque
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field

import numpy as np

from vessel_gym.net.clients import Address, ServerConnection
from vessel_gym.net.protocol import MAX_ASSIST
from vessel_gym.physics.bridge import Telegraph
from vessel_gym.ui.chart import fender_colour

RUDDER_STEP_DEG = 5.0
ASSIST_STEP = 0.25  # a thruster's or tug's order per key press (fraction of its range)
#: key pairs (to port, to starboard) of the first, second and third thruster or tug
ASSIST_KEYS = (("z", "x"), ("c", "v"), (",", "."))
TRACK_POINTS = 4000
_RANGES_M = (250.0, 500.0, 1000.0, 2000.0, 5000.0, 10000.0, 20000.0, 50000.0, 100000.0)

# Colours (RGB)
_BG = (12, 22, 40)
_PANEL = (22, 34, 58)
_SEA = (16, 40, 70)
_RING = (40, 70, 110)
_TEXT = (225, 232, 240)
_DIM = (140, 155, 175)
_OWN = (250, 200, 60)
_TRACK = (250, 200, 60)
_TARGET = (120, 220, 160)
_ORDER = (90, 170, 255)
_PORT = (230, 70, 70)
_STBD = (70, 210, 110)
_WARN = (255, 120, 60)


@dataclass
class HelmPanel:
    """Orders on the helm panel: rudder order (deg, + = starboard), telegraph step (-4..4) and, for a ship with
    thrusters or tugs (the welcome's ``assist``), one order per unit in [-1, 1] (+ towards starboard)."""

    max_rudder_deg: float = 35.0
    rudder_order_deg: float = 0.0
    telegraph: int = 0
    assist: list[float] = field(default_factory=list)
    ready: bool = False  # orders initialised from the ship's state (only then are they sent)
    active: bool = False  # the panel has asked for the helm (key t); a watcher sends no orders

    def take(self) -> None:
        """Ask for the helm: orders are synced from the next state, then sent."""
        if not self.active:
            self.active = True
            self.ready = False

    def watch(self) -> None:
        """Give the helm back and only watch."""
        self.active = False

    def sync(self, state: Mapping) -> None:
        """Take the current orders from a state message, once (bumpless takeover)."""
        if self.ready:
            return
        rudder, telegraph = state.get("rudder_order_deg"), state.get("telegraph")
        if isinstance(rudder, (int, float)) and not isinstance(rudder, bool):
            self.rudder_order_deg = max(-self.max_rudder_deg, min(self.max_rudder_deg, float(rudder)))
        if isinstance(telegraph, int) and not isinstance(telegraph, bool):
            self.telegraph = max(-4, min(4, telegraph))
        echoed = state.get("assist")
        if isinstance(echoed, list) and len(echoed) == len(self.assist):
            for j, a in enumerate(echoed):
                o = a.get("order") if isinstance(a, Mapping) else None
                if isinstance(o, (int, float)) and not isinstance(o, bool) and math.isfinite(o):
                    self.assist[j] = max(-1.0, min(1.0, float(o)))
        self.ready = True

    def set_units(self, n: int) -> None:
        """The ship has ``n`` thrusters and tugs (from the welcome): their orders start at 0."""
        if n != len(self.assist):
            self.assist = [0.0] * n

    def handle_key(self, key: str) -> None:
        """Apply one key: ``t`` (take), ``w`` (watch), and while holding the helm ``left``, ``right``, ``0``,
        ``up``, ``down``, and the thruster and tug keys (:data:`ASSIST_KEYS`, ``b``) (others are ignored)."""
        if key == "t":
            self.take()
        elif key == "w":
            self.watch()
        elif not self.active:
            return
        elif key == "left":
            self.rudder_order_deg = max(-self.max_rudder_deg, self.rudder_order_deg - RUDDER_STEP_DEG)
        elif key == "right":
            self.rudder_order_deg = min(self.max_rudder_deg, self.rudder_order_deg + RUDDER_STEP_DEG)
        elif key == "0":
            self.rudder_order_deg = 0.0
        elif key == "up":
            self.telegraph = min(4, self.telegraph + 1)
        elif key == "down":
            self.telegraph = max(-4, self.telegraph - 1)
        elif key == "b":
            self.assist = [0.0] * len(self.assist)
        else:
            for j, pair in enumerate(ASSIST_KEYS[: len(self.assist)]):
                if key in pair:
                    step = ASSIST_STEP if key == pair[1] else -ASSIST_STEP
                    self.assist[j] = max(-1.0, min(1.0, self.assist[j] + step))


# ---------------------------------------------------------------------------------------------------------------
# Drawing (pygame imported lazily)


def _pygame():
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame

    if not pygame.font.get_init():
        pygame.font.init()
        _FONTS.clear()  # fonts do not survive a font module restart
    return pygame


_FONTS: dict[int, object] = {}


def _font(pygame, size: int):
    font = _FONTS.get(size)
    if font is None:
        font = _FONTS[size] = pygame.font.Font(None, size)
    return font


def _fmt(value: object, fmt: str, unit: str = "") -> str:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return "---"
    return f"{value:{fmt}}{unit}"


def _telegraph_name(step: object) -> str:
    try:
        return Telegraph(int(step)).name.replace("_", " ")
    except (TypeError, ValueError):
        return "---"


def _pick_range(extent_m: float) -> float:
    for r in _RANGES_M:
        if extent_m <= r:
            return r
    return _RANGES_M[-1]


def _hull(cx: float, cy: float, hdg_deg: float, length_px: float, beam_px: float) -> list:
    """Screen polygon of a pointed hull centred at (cx, cy), heading clockwise from screen-up."""
    h = math.radians(hdg_deg)
    fwd = (math.sin(h), -math.cos(h))  # screen vector of the bow direction
    stb = (math.cos(h), math.sin(h))  # screen vector to starboard
    hl, hb = length_px / 2.0, beam_px / 2.0
    local = [(hl, 0.0), (hl * 0.45, hb), (-hl, hb), (-hl, -hb), (hl * 0.45, -hb)]
    return [(cx + a * fwd[0] + b * stb[0], cy + a * fwd[1] + b * stb[1]) for a, b in local]


_CHART = {"land": (74, 66, 48), "breakwater": (96, 96, 102), "quay": (118, 118, 126)}
_SHOAL = (92, 84, 52)
_GOAL = (70, 190, 90)


def _draw_chart(
    pygame, surface, scene: Mapping, to_screen: Callable, draught_m: float, fender_load: object = None
) -> None:
    """The v2 scenario under the ships: depth areas shallower than the own draught (shoals), land,
    breakwaters and quays filled, the goal outlined (same geometry as the simulation's chart), a berth's
    fenders coloured by ``fender_load`` (the state's, in fender order; the chart's colours)."""
    features = [f for f in scene.get("features") or [] if isinstance(f, Mapping)]

    def poly(f: Mapping) -> list | None:
        pts = f.get("points")
        if not isinstance(pts, list) or len(pts) < 3:
            return None
        try:
            return [to_screen(float(p[0]), float(p[1])) for p in pts]
        except (TypeError, ValueError, IndexError):
            return None

    for f in features:
        depth = f.get("depth_m")
        if f.get("kind") == "depth" and isinstance(depth, (int, float)) and depth < draught_m:
            pts = poly(f)
            if pts:
                pygame.draw.polygon(surface, _SHOAL, pts)
    for f in features:
        colour = _CHART.get(str(f.get("kind")))
        pts = poly(f) if colour else None
        if pts:
            pygame.draw.polygon(surface, colour, pts)
    for f in features:
        if f.get("kind") == "goal":
            pts = poly(f)
            if pts:
                pygame.draw.polygon(surface, _GOAL, pts, 2)
    loads = fender_load if isinstance(fender_load, list) else []
    for j, f in enumerate(f for f in features if f.get("kind") == "fender"):
        pts = poly(f)
        load = loads[j] if j < len(loads) and isinstance(loads[j], (int, float)) else 0.0
        if pts:
            pygame.draw.polygon(surface, fender_colour(float(load)), pts)


def render(
    surface,
    state: Mapping | None,
    track: Iterable[tuple[float, float]] = (),
    panel: HelmPanel | None = None,
    status: str = "",
    title: str = "vessel-gym",
    scene: Mapping | None = None,
    own_draught_m: float = 0.0,
) -> None:
    """Draw one frame on a pygame ``surface``: readouts on the left, a north-up chart on the right.

    ``state`` is a state message (None: waiting for data); ``track`` the own (x_m, y_m) history; ``panel`` the
    helm orders to show next to the ship's (helm panel only); ``status`` a one-line link status; ``scene`` a v2
    scenario message drawn under the ships (shoals are depth areas shallower than ``own_draught_m``).
    """
    pygame = _pygame()
    w, h = surface.get_size()
    surface.fill(_BG)
    font, big, small = _font(pygame, 22), _font(pygame, 34), _font(pygame, 18)
    left_w = min(320, w // 2)
    pygame.draw.rect(surface, _PANEL, (0, 0, left_w, h))

    def text(s: str, x: int, y: int, colour=_TEXT, f=font) -> None:
        surface.blit(f.render(s, True, colour), (x, y))

    text(title, 12, 10, _TEXT, big)
    text(status, 12, 42, _WARN if "!" in status else _DIM, font)
    s = state or {}
    rows = [
        ("HDG", _fmt(s.get("hdg_deg"), "05.1f", " deg")),
        ("COG", _fmt(s.get("cog_deg"), "05.1f", " deg")),
        ("SOG", _fmt(s.get("sog_kn"), ".1f", " kn")),
        ("STW", _fmt(s.get("stw_kn"), ".1f", " kn")),
        ("ROT", _fmt(s.get("rot_dpm"), "+.1f", " deg/min")),
        ("RPM", _fmt(s.get("rpm"), ".0f", " rev/min")),
        ("ENGINE", _telegraph_name(s.get("telegraph"))),
        ("TIME", _fmt(s.get("t_s"), ".1f", " s")),
    ]
    y = 74
    for label, value in rows:
        text(label, 12, y, _DIM)
        text(value, 100, y, _TEXT)
        y += 26

    # Rudder indicator: actual (bar) against order (tick), +-max from the panel or 35 deg.
    max_rudder = panel.max_rudder_deg if panel else 35.0
    text("RUDDER", 12, y + 4, _DIM)
    gx, gy, gw, gh = 12, y + 28, left_w - 24, 18
    pygame.draw.rect(surface, _SEA, (gx, gy, gw, gh))
    mid = gx + gw / 2

    def gauge_x(deg: object) -> float | None:
        if isinstance(deg, bool) or not isinstance(deg, (int, float)) or not math.isfinite(deg):
            return None
        return mid + max(-1.0, min(1.0, deg / max_rudder)) * gw / 2

    actual = gauge_x(s.get("rudder_deg"))
    if actual is not None:
        colour = _STBD if actual >= mid else _PORT
        pygame.draw.rect(surface, colour, (min(mid, actual), gy + 3, abs(actual - mid) + 1, gh - 6))
    order = gauge_x(s.get("rudder_order_deg"))
    if order is not None:
        pygame.draw.line(surface, _ORDER, (order, gy - 4), (order, gy + gh + 4), 3)
    pygame.draw.line(surface, _DIM, (mid, gy), (mid, gy + gh), 1)
    text(
        f"actual {_fmt(s.get('rudder_deg'), '+.1f')}   order {_fmt(s.get('rudder_order_deg'), '+.1f')}",
        12,
        gy + gh + 8,
        _TEXT,
        small,
    )
    y = gy + gh + 34
    if panel is not None:
        text("PANEL ORDER", 12, y, _DIM)
        text(f"rudder {panel.rudder_order_deg:+.0f} deg", 12, y + 24, _ORDER)
        text(_telegraph_name(panel.telegraph), 12, y + 48, _ORDER)
        echoed = [a for a in s.get("assist") or [] if isinstance(a, Mapping)]
        for j, o in enumerate(panel.assist):
            name = str(echoed[j].get("name", ""))[:14] if j < len(echoed) else f"unit {j + 1}"
            now = _fmt(echoed[j].get("delivered"), "+.2f") if j < len(echoed) else "-"
            keys = "/".join(ASSIST_KEYS[j]) if j < len(ASSIST_KEYS) else "-"
            text(f"{name} {keys} {o:+.2f} ({now})", 12, y + 72 + 22 * j, _ORDER, small)
        keys = "w watch  <- -> rudder  0 midships  up/down engine" if panel.active else "t take the helm"
        text(f"{keys}  q quit", 12, h - 24, _DIM, small)
    helm_ok = s.get("helm_ok")
    text("HELM OK" if helm_ok else "NO HELM", left_w - 90, 16, _STBD if helm_ok else _WARN, font)

    # Chart, north up, centred on own ship.
    cx0, cw = left_w, w - left_w
    ccx, ccy = cx0 + cw / 2, h / 2
    pygame.draw.rect(surface, _SEA, (cx0, 0, cw, h))
    ox, oy = s.get("x_m"), s.get("y_m")
    if not all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in (ox, oy)
    ):
        text("waiting for state ...", int(ccx) - 70, int(ccy), _DIM)
        return
    targets = [t for t in s.get("targets") or [] if isinstance(t, Mapping)]
    pts = list(track)
    extent = 200.0
    for t in targets:
        tx, ty = t.get("x_m"), t.get("y_m")
        if isinstance(tx, (int, float)) and isinstance(ty, (int, float)):
            extent = max(extent, abs(tx - ox) * 1.15, abs(ty - oy) * 1.15)
    if pts:
        far = max(max(abs(px - ox), abs(py - oy)) for px, py in pts[:: max(1, len(pts) // 200)])
        extent = max(extent, min(far, 5000.0))
    rng = _pick_range(extent)
    scale = (min(cw, h) / 2 - 20) / rng  # px per m

    def to_screen(x_m: float, y_m: float) -> tuple[float, float]:
        return ccx + (y_m - oy) * scale, ccy - (x_m - ox) * scale

    if scene is not None:
        _draw_chart(pygame, surface, scene, to_screen, own_draught_m, s.get("fender_load"))
    for k in (0.5, 1.0):
        pygame.draw.circle(surface, _RING, (int(ccx), int(ccy)), int(rng * k * scale), 1)
    text(f"range {rng:.0f} m", int(cx0 + 10), 10, _DIM, small)
    text("N", int(ccx) - 5, 4, _DIM, font)
    if len(pts) >= 2:
        screen = [to_screen(px, py) for px, py in pts]
        pygame.draw.lines(surface, _TRACK, False, screen, 1)
    for t in targets:
        tx, ty, th = t.get("x_m"), t.get("y_m"), t.get("hdg_deg")
        if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (tx, ty, th)):
            continue
        sx, sy = to_screen(tx, ty)
        length = max(float(t.get("length_m") or 0.0) * scale, 12.0)
        beam = max(float(t.get("beam_m") or 0.0) * scale, 5.0)
        pygame.draw.polygon(surface, _TARGET, _hull(sx, sy, th, length, beam))
        text(str(t.get("name", ""))[:20], int(sx) + 10, int(sy) + 8, _TARGET, small)
    hdg = s.get("hdg_deg") if isinstance(s.get("hdg_deg"), (int, float)) else 0.0
    pygame.draw.polygon(surface, _OWN, _hull(ccx, ccy, hdg, 18.0, 7.0))
    cog, sog = s.get("cog_deg"), s.get("sog_kn")
    if isinstance(cog, (int, float)) and isinstance(sog, (int, float)) and sog > 0.1:
        # Course vector: where the ship will be in 1 minute at the present SOG.
        d = sog * 1852.0 / 60.0 * scale
        c = math.radians(cog)
        pygame.draw.line(surface, _OWN, (ccx, ccy), (ccx + d * math.sin(c), ccy - d * math.cos(c)), 1)


def render_frame_array(
    state: Mapping | None,
    track: Iterable[tuple[float, float]] = (),
    panel: HelmPanel | None = None,
    status: str = "",
    size: tuple[int, int] = (900, 560),
    title: str = "vessel-gym",
    scene: Mapping | None = None,
    own_draught_m: float = 0.0,
) -> np.ndarray:
    """Render one frame off-screen and return it as a (height, width, 3) uint8 RGB array (no display needed)."""
    pygame = _pygame()
    surface = pygame.Surface(size)
    render(surface, state, track, panel, status, title, scene, own_draught_m)
    return np.ascontiguousarray(pygame.surfarray.array3d(surface).transpose(1, 0, 2))


# ---------------------------------------------------------------------------------------------------------------
# Run loops


@dataclass
class ClientResult:
    """What a client run did: frames drawn, complete states received, helm commands sent, the last state and,
    with ``capture=True``, the last frame as a (height, width, 3) uint8 array."""

    frames: int = 0
    states_received: int = 0
    helm_sent: int = 0
    owned_helm: bool = False
    last_state: dict | None = None
    last_frame: np.ndarray | None = None
    panel: HelmPanel | None = None
    track: list[tuple[float, float]] = field(default_factory=list)


_KEYS = {"K_LEFT": "left", "K_RIGHT": "right", "K_UP": "up", "K_DOWN": "down", "K_0": "0", "K_KP0": "0"}
_KEYS.update({"K_t": "t", "K_w": "w", "K_b": "b", "K_COMMA": ",", "K_PERIOD": "."})
_KEYS.update({f"K_{k}": k for k in "zxcv"})


def _run(
    conn: ServerConnection,
    panel: HelmPanel | None,
    helm_rate_hz: float,
    title: str,
    max_frames: int | None,
    duration_s: float | None,
    headless: bool,
    size: tuple[int, int],
    fps: float,
    capture: bool,
    on_frame: Callable[[int, HelmPanel | None, ServerConnection], None] | None,
) -> ClientResult:
    if headless:
        os.environ["SDL_VIDEODRIVER"] = "dummy"
    pygame = _pygame()
    pygame.display.init()
    result = ClientResult(panel=panel)
    track: deque[tuple[float, float]] = deque(maxlen=TRACK_POINTS)
    try:
        screen = pygame.display.set_mode(size)
        pygame.display.set_caption(title)
        clock = pygame.time.Clock()
        keymap = {getattr(pygame, k): v for k, v in _KEYS.items()}
        quit_keys = {pygame.K_ESCAPE, pygame.K_q}
        start = time.monotonic()
        next_helm = start
        frame = 0
        running = True
        while running:
            now = time.monotonic()
            if max_frames is not None and frame >= max_frames:
                break
            if duration_s is not None and now - start >= duration_s:
                break
            for event in pygame.event.get():
                if event.type == pygame.QUIT or (event.type == pygame.KEYDOWN and event.key in quit_keys):
                    running = False
                elif event.type == pygame.KEYDOWN and panel is not None and event.key in keymap:
                    panel.handle_key(keymap[event.key])
            conn.keepalive(now)
            conn.poll(now)
            state = conn.state
            if state is not None:
                x, y = state.get("x_m"), state.get("y_m")
                if isinstance(x, (int, float)) and isinstance(y, (int, float)):
                    if not track or abs(track[-1][0] - x) + abs(track[-1][1] - y) > 1.0:
                        track.append((float(x), float(y)))
            if panel is not None:
                if conn.welcome is not None:
                    limit = conn.welcome.get("max_rudder_deg")
                    if isinstance(limit, (int, float)) and 0 < limit < 90:
                        panel.max_rudder_deg = float(limit)
                    units = conn.welcome.get("assist")
                    panel.set_units(min(len(units), MAX_ASSIST) if isinstance(units, list) else 0)
            if on_frame is not None:
                on_frame(frame, panel, conn)
            if panel is not None:
                conn.set_role("helm" if panel.active else "viewer")
                if panel.active and state is not None:
                    panel.sync(state)
            if panel is not None and panel.active and panel.ready and now >= next_helm:
                conn.send_helm(panel.rudder_order_deg, panel.telegraph, assist=panel.assist or None)
                next_helm = max(next_helm + 1.0 / helm_rate_hz, now)
            result.owned_helm |= conn.owns_helm
            age = conn.seconds_since_data(now)
            if age > 2.0:
                status = "! no data from server"
            elif panel is not None and not panel.active:
                status = "watching (t takes the helm)"
            elif panel is not None:
                status = "you have the helm" if conn.owns_helm else "helm: other panel or none"
            else:
                status = f"viewer, {len(track)} track points"
            own = conn.particulars.get(0) or {}
            draught = own.get("draught_m") if isinstance(own.get("draught_m"), (int, float)) else 0.0
            render(screen, state, track, panel, status, title, conn.scene, draught)
            pygame.display.flip()
            frame += 1
            if capture:
                result.last_frame = np.ascontiguousarray(pygame.surfarray.array3d(screen).transpose(1, 0, 2))
            clock.tick(fps)
    finally:
        conn.close(bye=not conn.listen_only)
        pygame.display.quit()
    result.frames = frame
    result.states_received = conn.states_received
    result.helm_sent = conn.helm_sent
    result.last_state = conn.state
    result.track = list(track)
    return result


def run_helm(
    server: Address = ("127.0.0.1", 10120),
    *,
    name: str = "helm",
    rate_hz: float = 20.0,
    state_rate_hz: float = 20.0,
    token: str | None = None,
    max_frames: int | None = None,
    duration_s: float | None = None,
    headless: bool = False,
    size: tuple[int, int] = (900, 560),
    fps: float = 30.0,
    capture: bool = False,
    on_frame: Callable[[int, HelmPanel | None, ServerConnection], None] | None = None,
    take: bool = False,
) -> ClientResult:
    """Run the helm panel against the link at ``server`` until closed or ``max_frames``/``duration_s`` (s).

    Starts as a watcher; after the ``t`` key (or ``take=True``) sends full helm commands at ``rate_hz`` (10-20
    Hz), synced from the state at that moment; asks for state at ``state_rate_hz``. ``headless`` uses SDL's dummy video driver; ``capture`` keeps the last frame in the
    result; ``on_frame(frame, panel, connection)`` is called every frame before sending (scripted input).
    """
    if not 1.0 <= rate_hz <= 50.0:
        raise ValueError(f"helm rate_hz must be 1-50, not {rate_hz}")
    conn = ServerConnection(server, "viewer", state_rate_hz, name, token)
    title = f"vessel-gym helm - {name}"
    panel = HelmPanel()
    if take:
        panel.take()
    return _run(conn, panel, rate_hz, title, max_frames, duration_s, headless, size, fps, capture, on_frame)


def run_viewer(
    server: Address = ("127.0.0.1", 10120),
    *,
    name: str = "viewer",
    rate_hz: float = 20.0,
    token: str | None = None,
    listen: Address | None = None,
    max_frames: int | None = None,
    duration_s: float | None = None,
    headless: bool = False,
    size: tuple[int, int] = (900, 560),
    fps: float = 30.0,
    capture: bool = False,
    on_frame: Callable[[int, HelmPanel | None, ServerConnection], None] | None = None,
) -> ClientResult:
    """Run the passive viewer: like :func:`run_helm` without helm input. With ``listen`` it binds there and
    waits for state from a link whose ``json_static_destinations`` point at it (no ``hello`` is sent)."""
    conn = ServerConnection(server, "viewer", rate_hz, name, token, listen=listen)
    title = f"vessel-gym view - {name}"
    return _run(conn, None, 20.0, title, max_frames, duration_s, headless, size, fps, capture, on_frame)
