"""``vessel-gym view3d``: a 3D bridge view in the browser, fed by the JSON link (protocol v2).

The viewer joins a running link (``vessel-gym serve``) as a v2 client, builds the harbour from the ``scenario``
message (land, breakwaters and quays extruded above the water, depth areas as steps of the sea bed, the goal),
the ships from their ``particulars`` (hull outline to scale) and draws them, with the track, the sea surface,
wind and current arrows and a HUD, in a web page served on loopback by `viser <https://viser.studio>`_ (its
three.js client is bundled in the package: no internet access at run time). Every request and message of the
page passes :mod:`~vessel_gym.ui.view3d_gate` (the page's Host and Origin, the helm key of the run).

The page opened from the ``/helm/KEY`` URL printed at start is a watcher until someone presses ``H`` (or the
"Take the helm" button): it then says ``hello`` as a helm panel and sends full orders at 10 Hz, starting from
the orders in force; the page at ``/`` only watches. Keys: left/right arrows rudder
5 deg to port/starboard, ``M`` midships, up/down arrows telegraph one step ahead/astern, ``H`` take and ``R``
release the helm, ``C`` next camera (chase, bridge, top-down, harbour, free). A ship with thrusters or tugs
(Berthing) gets their controls, a berth its fenders coloured by load, a CollisionAvoidance run its route and
target ships (:mod:`~vessel_gym.ui.view3d_tasks`).

Scene frame: x east, y north, z up, m, origin at the scenario's reference point (the link's ``y_m``, ``x_m``).
What is drawn but not in the protocol is stated where it is chosen (freeboard, superstructure, heights of
land above the water).

Its jobs beside it: the scene's geometry and the sea (:mod:`~vessel_gym.ui.view3d_scene`), the link client
(:mod:`~vessel_gym.ui.view3d_link`) and the gate (:mod:`~vessel_gym.ui.view3d_gate`); this module is the page
(viser scene, GUI, cameras, HUD) and its entry point.
"""

from __future__ import annotations

import contextlib
import io
import math
import socket
import sys
import time
from typing import Any, TextIO

import numpy as np

from vessel_gym.ui.panels import RUDDER_STEP_DEG
from vessel_gym.ui.view3d_gate import (
    PageGate,
    bind_page_socket,
    current_role,
    gated_viser_server,
    resolve_page_address,
)
from vessel_gym.ui.view3d_link import Address, LinkClient
from vessel_gym.ui.view3d_scene import (
    CAMERAS,
    CHASE_ABOVE_L,
    CHASE_AHEAD_L,
    CHASE_ASTERN_L,
    COLOURS,
    FREEBOARD_T,
    TELEGRAPH_NAMES,
    attitude_wxyz,
    harbour_geometry,
    heading_wxyz,
    sea_elevation,
    sea_grid,
    ship_meshes,
)
from vessel_gym.ui.view3d_tasks import AssistControls, TaskScene, hud_rows, outcome_figures

TRACK_POINTS = 2000  # own-ship track kept, one point per TRACK_SPACING_S
TRACK_SPACING_S = 1.0  # s of simulation time between track points
FRAME_PERIOD_S = 1.0 / 30.0  # scene updates, s
TRACK_REDRAW_S = 0.5  # the track is re-sent to the page at most this often, s (wall clock)
SEA_PERIOD_S = 1.0 / 8.0  # sea-surface vertex updates, s
HUD_PERIOD_S = 0.25


# ---------------------------------------------------------------------------------------------------------------
# The page


class Viewer3D:
    """The viser scene and GUI for one :class:`LinkClient`."""

    def __init__(self, link: LinkClient, gate: PageGate, sock: socket.socket, camera: str) -> None:
        self.link = link
        self.gate = gate
        self.server = gated_viser_server(gate, sock, label="vessel-gym view3d")
        self.server.scene.set_up_direction("+z")
        self.server.gui.configure_theme(control_layout="floating", show_share_button=False, dark_mode=False)
        self.server.gui.main_panel.dock_right()  # the HUD and the helm buttons right of the 3D view
        sc = self.server.scene
        # Daylight: sky and sea-bed tones from a hemisphere light, a sun from the south-west at 50 deg elevation.
        self._fog = (1e4, 2e4)
        sc.configure_environment_map(hdri=None)
        self.server.on_client_connect(self._joined)
        self.server.on_client_connect(self._tell_watchers)
        self.camera = camera
        self._scene_version = -1
        self._particulars_version = -1
        self._ships: dict[int, Any] = {}
        self._labels: dict[int, Any] = {}
        self._track: list[tuple[float, float]] = []
        self._track_t = -math.inf
        self._track_drawn = 0.0
        self._sea: Any = None
        self._sea_xy: tuple[np.ndarray, np.ndarray] | None = None
        self._sea_due = 0.0
        self._hud_due = 0.0
        self._arrow_handles: list[Any] = []
        self._arrows_for = -1  # scene version the wind and current arrows were drawn for
        self._L = 7.0
        self._T = 0.5
        self._extent = (-100.0, 100.0, -100.0, 100.0)  # scene x min, x max, y min, y max
        self._depth = 10.0
        self._build_gui()
        self.assist_controls = AssistControls(self.server.gui, link)  # built when the welcome names units
        self.task_scene = TaskScene()

    def _joined(self, client: Any) -> None:
        client.scene.configure_fog(*self._fog, color=(205, 218, 232))

    async def _tell_watchers(self, client: Any) -> None:
        """A page opened without the helm key says so (async: it runs in the connection's context)."""
        if current_role() == "watch":
            client.gui.add_markdown(
                "*Watching only*: the helm is taken from the URL that `vessel-gym view3d` printed."
            )

    # -- GUI ----------------------------------------------------------------------------------------------------

    def _build_gui(self) -> None:
        gui = self.server.gui
        self.commands: dict[str, Any] = {}
        self.hud = gui.add_markdown("waiting for the link ...")
        self.cam_box = gui.add_dropdown("Camera", CAMERAS, initial_value=self.camera)
        self.cam_box.on_update(lambda _e: self._camera_chosen())
        self.helm_button = gui.add_button("Take the helm (H)")
        self.helm_button.on_click(lambda _e: self.toggle_helm())
        gui.add_markdown(
            "Keys: **H** take the helm, **R** release it; **←/→** rudder 5° port/starboard; **M** midships; "
            "**↑/↓** telegraph ahead/astern; **C** next camera."
        )
        for label, key, action in (
            ("Take the helm", "H", lambda: self.set_helm(True)),
            ("Release the helm", "R", lambda: self.set_helm(False)),
            ("Rudder 5 deg to port", "arrowleft", lambda: self.rudder(-RUDDER_STEP_DEG)),
            ("Rudder 5 deg to starboard", "arrowright", lambda: self.rudder(RUDDER_STEP_DEG)),
            ("Midships", "M", lambda: self.rudder(None)),
            ("Telegraph one step ahead", "arrowup", lambda: self.telegraph(1)),
            ("Telegraph one step astern", "arrowdown", lambda: self.telegraph(-1)),
            ("Next camera", "C", self.next_camera),
        ):
            cmd = gui.add_command(label, hotkey=key)
            cmd.on_trigger(lambda _e, f=action: f())
            self.commands[label] = cmd

    def _camera_chosen(self) -> None:
        if self.cam_box.value in CAMERAS:
            self.camera = self.cam_box.value
        else:  # viser casts whatever a page sends to str
            self.cam_box.value = self.camera

    def toggle_helm(self) -> None:
        self.set_helm(not self.link.helm)

    def set_helm(self, take: bool) -> None:
        """Take (True) or release the helm; separate keys, so that a repeated key press cannot undo itself."""
        if take and not self.link.helm:
            self.link.take_helm()
        elif not take and self.link.helm:
            self.link.release_helm()
        self.helm_button.label = "Release the helm (R)" if self.link.helm else "Take the helm (H)"

    def rudder(self, step: float | None) -> None:
        if not self.link.helm:
            return  # orders only after the helm was taken on purpose
        limit, _ = self.link.limits()
        value = 0.0 if step is None else self.link.rudder_order_deg + step
        self.link.rudder_order_deg = max(-limit, min(limit, value))

    def telegraph(self, step: int) -> None:
        if self.link.helm:
            self.link.telegraph = max(-4, min(4, self.link.telegraph + step))

    def next_camera(self) -> None:
        self.camera = CAMERAS[(CAMERAS.index(self.camera) + 1) % len(CAMERAS)]
        self.cam_box.value = self.camera

    # -- scene -------------------------------------------------------------------------------------------------

    def _build_scene(self, scene: dict) -> None:
        sc = self.server.scene
        own = self.link.particulars.get(0)
        if own is not None:
            self._L, self._T = float(own["length_m"] or 7.0), float(own["draught_m"] or 0.5)
        geo = harbour_geometry(scene, self._L, self._T)
        self._extent, self._depth = geo.extent, geo.depth_m
        x0, x1, y0, y1 = self._extent
        span = max(x1 - x0, y1 - y0)
        self._fog = (2.0 * span, 6.0 * span)  # haze well beyond the harbour
        for client in self.server.get_clients().values():
            self._joined(client)
        for m in geo.meshes:
            sc.add_mesh_simple(
                m.name, m.vertices, m.faces, color=m.colour, opacity=m.opacity if m.opacity < 1.0 else None,
                flat_shading=True, side="double", cast_shadow=False,
            )  # fmt: skip
        for name, segs, colour in geo.rings:
            sc.add_line_segments(name, segs, colour, thickness=0.04 * self._L)
        if geo.goal_arrow is not None:
            L = self._L
            sc.add_arrows("/chart/goal_heading", geo.goal_arrow[None], COLOURS["goal"], shaft_radius=0.03 * L,
                          head_radius=0.08 * L, head_length=0.15 * L)  # fmt: skip
        self.task_scene.build(sc, scene["features"], self._T, self._L)
        x, y, faces = sea_grid(self._extent)
        self._sea_xy = (x, y)
        self._sea = sc.add_mesh_simple(
            "/sea",
            np.column_stack([x, y, np.zeros(len(x))]).astype(np.float32),
            faces,
            color=COLOURS["sea"],
            opacity=0.55,
            side="double",
            cast_shadow=False,
            receive_shadow=0.3,
        )

    def _build_ships(self) -> None:
        sc = self.server.scene
        for pid, p in self.link.particulars.items():
            L, B, T = (float(p.get(k) or 0.0) for k in ("length_m", "beam_m", "draught_m"))
            if not (L > 0.0 and B > 0.0):
                continue
            frame = sc.add_frame(f"/ship_{pid}", show_axes=False)
            colour = COLOURS["own"] if pid == 0 else COLOURS["traffic"]
            for m in ship_meshes(pid, p.get("outline_m"), L, B, T, colour):
                sc.add_mesh_simple(m.name, m.vertices, m.faces, color=m.colour, flat_shading=True,
                                   side="double", cast_shadow=False)  # fmt: skip
            self._ships[pid] = frame
            if pid != 0:
                self._labels[pid] = sc.add_label(
                    f"/ship_{pid}/label", str(p.get("name", "")), position=(0.0, 0.0, 2.0 * T + 0.2 * L)
                )
        if 0 in self.link.particulars:
            own = self.link.particulars[0]
            self._L, self._T = float(own["length_m"] or 7.0), float(own["draught_m"] or 0.5)

    # -- per frame ----------------------------------------------------------------------------------------------

    def update(self, now: float) -> None:
        link = self.link
        self.assist_controls.sync()
        if link.particulars_version != self._particulars_version and link.particulars:
            self._particulars_version = link.particulars_version
            self._build_ships()
        if link.scene_version != self._scene_version and link.scene is not None:
            self._scene_version = link.scene_version
            self._track.clear()
            self._build_scene(link.scene)
        st = link.state
        if st is None:
            return
        with self.server.atomic():
            self._place(0, st)
            for t in st.get("targets") or []:
                if isinstance(t, dict) and isinstance(t.get("id"), int):
                    self._place(t["id"], t)
            self._track_update(st)
            self._arrows(st)
            self.task_scene.update(st)
        if now >= self._sea_due and self._sea is not None and link.scene is not None:
            self._sea_due = now + SEA_PERIOD_S
            sea = link.scene.get("sea") or {}
            x, y = self._sea_xy
            z = sea_elevation(
                x,
                y,
                float(st.get("t_s") or 0.0),
                float(sea.get("hs_m") or 0.0),
                float(sea.get("tp_s") or 8.0),
                float(sea.get("wave_from_deg") or 0.0),
                self._depth,
            )
            self._sea.vertices = np.column_stack([x, y, z]).astype(np.float32)
        self._cameras(st)
        if now >= self._hud_due:
            self._hud_due = now + HUD_PERIOD_S
            self.hud.content = self._hud_text(st)

    def _place(self, pid: int, s: dict) -> None:
        frame = self._ships.get(pid)
        x, y, h = s.get("y_m"), s.get("x_m"), s.get("hdg_deg")
        if frame is None:
            if (
                pid != 0
                and isinstance(s.get("length_m"), (int, float))
                and isinstance(s.get("beam_m"), (int, float))
            ):
                L, B = float(s["length_m"]), float(s["beam_m"])
                self.link.particulars.setdefault(
                    pid,
                    {
                        "id": pid,
                        "name": s.get("name", ""),
                        "length_m": L,
                        "beam_m": B,
                        "draught_m": 0.06 * L,
                        "outline_m": None,
                    },
                )
                self.link.particulars_version += 1
            return
        if all(isinstance(v, (int, float)) for v in (x, y, h)):
            frame.position = (x, y, 0.0)
            # the heel of a ship with roll (state roll_deg); a 3-DOF ship's state has none: upright
            phi = s.get("roll_deg")
            frame.wxyz = attitude_wxyz(h, phi) if isinstance(phi, (int, float)) else heading_wxyz(h)

    def _track_update(self, st: dict) -> None:
        t, x, y = st.get("t_s"), st.get("y_m"), st.get("x_m")
        if not all(isinstance(v, (int, float)) for v in (t, x, y)):
            return
        if t < self._track_t:  # a new episode (time went back)
            self._track.clear()
        if t - self._track_t >= TRACK_SPACING_S or t < self._track_t:
            self._track_t = t
            self._track.append((x, y))
            del self._track[:-TRACK_POINTS]
            if len(self._track) >= 2 and time.monotonic() - self._track_drawn >= TRACK_REDRAW_S:
                self._track_drawn = time.monotonic()
                p = np.array([(a, b, 0.03 * self._T) for a, b in self._track])
                segs = np.stack([p[:-1], p[1:]], axis=1)
                self.server.scene.add_line_segments(
                    "/track", segs, COLOURS["track"], thickness=0.03 * self._L
                )

    def _arrows(self, st: dict) -> None:
        sea = (self.link.scene or {}).get("sea") or {}
        x, y = st.get("y_m"), st.get("x_m")
        if not (isinstance(x, (int, float)) and isinstance(y, (int, float))):
            return
        L = self._L
        z = FREEBOARD_T * self._T + 0.5 * L
        if self._arrows_for == self._scene_version:  # same sea: move the arrows with the ship
            for handle in self._arrow_handles:
                handle.position = (x, y, 0.0)
                handle.visible = self.camera != "bridge"  # they would stand in front of the bridge windows
            return
        self._arrows_for = self._scene_version
        for handle in self._arrow_handles:
            handle.remove()
        self._arrow_handles = []
        for key, speed_key, dir_key, towards, scale in (
            ("wind", "wind_speed_kn", "wind_from_deg", False, 0.1),
            ("current", "current_speed_kn", "current_to_deg", True, 1.0),
        ):
            speed, d = sea.get(speed_key), sea.get(dir_key)
            if not (isinstance(speed, (int, float)) and isinstance(d, (int, float))) or speed <= 0.0:
                continue
            to = math.radians(d if towards else d + 180.0)
            length = L * min(2.0, 0.4 + scale * speed)  # ship lengths, grows with speed (kn), capped
            start = np.array([0.0, 0.0, z if key == "wind" else 0.1 * self._T])
            end = start + length * np.array([math.sin(to), math.cos(to), 0.0])
            handle = self.server.scene.add_arrows(
                f"/{key}",
                np.array([[start, end]]),
                COLOURS[key],
                shaft_radius=0.03 * L,
                head_radius=0.09 * L,
                head_length=0.2 * L,
                position=(x, y, 0.0),
            )
            self._arrow_handles.append(handle)

    def _cameras(self, st: dict) -> None:
        # Clip planes for the scene's size: viser's 1000 m far plane hides an open-sea encounter's targets
        # kilometres off; the near plane grows with it to keep the depth buffer's precision (1e5 : 1).
        x0, x1, y0, y1 = self._extent
        far = max(1000.0, 4.0 * max(x1 - x0, y1 - y0))
        for client in self.server.get_clients().values():
            try:
                client.camera.far, client.camera.near = far, max(0.01, 1e-5 * far)
            except (AssertionError, ValueError):  # camera not reported by the browser yet
                continue
        x, y, h = st.get("y_m"), st.get("x_m"), st.get("hdg_deg")
        if self.camera == "free" or not all(isinstance(v, (int, float)) for v in (x, y, h)):
            return
        L, T = self._L, self._T
        fwd = np.array([math.sin(math.radians(h)), math.cos(math.radians(h)), 0.0])
        ship = np.array([x, y, 0.0])
        if self.camera == "chase":
            pos = ship - CHASE_ASTERN_L * L * fwd + np.array([0, 0, CHASE_ABOVE_L * L])
            look, up = ship + CHASE_AHEAD_L * L * fwd, (0, 0, 1)
        elif self.camera == "bridge":
            eye = ship - 0.38 * L * fwd + np.array([0, 0, FREEBOARD_T * T + 0.1 * L])
            pos, look, up = eye, eye + 3.0 * L * fwd - np.array([0, 0, 0.1 * L]), (0, 0, 1)
        elif self.camera == "top-down":
            pos, look, up = ship + np.array([0, 0, 8.0 * L]), ship, tuple(fwd)
        else:  # harbour overview, north up
            x0, x1, y0, y1 = self._extent
            c = np.array([0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.0])
            span = max(x1 - x0, y1 - y0)
            pos, look, up = c + np.array([0.0, -0.35 * span, 0.85 * span]), c, (0, 0, 1)
        for client in self.server.get_clients().values():
            cam = client.camera
            try:
                with client.atomic():
                    cam.up_direction = up
                    cam.position = pos
                    cam.look_at = look
            except (AssertionError, ValueError):  # camera not reported by the browser yet
                continue

    def _hud_text(self, st: dict) -> str:
        def f(key: str, fmt: str) -> str:
            v = st.get(key)
            return format(v, fmt) if isinstance(v, (int, float)) else "–"

        tg = st.get("telegraph")
        link = self.link
        owner = link.owner
        if link.helm and (owner is None or owner.get("you")):
            helm = f"**YOU** (order {link.rudder_order_deg:+.0f}°, {TELEGRAPH_NAMES[link.telegraph]})"
        elif owner is not None and owner.get("owner"):
            helm = f"{owner['owner']}"
        else:
            helm = "autopilot" if not st.get("helm_ok") else "a panel"
        sea = (link.scene or {}).get("sea") or {}
        lines = [
            f"**{(link.scene or {}).get('name') or 'vessel-gym'}**  t = {f('t_s', '.1f')} s",
            "",
            "| | |",
            "|---|---|",
            f"| Heading | {f('hdg_deg', '05.1f')}° |",
            f"| SOG | {f('sog_kn', '.2f')} kn |",
            f"| ROT | {f('rot_dpm', '+.1f')} °/min |",
            *([f"| Heel | {f('roll_deg', '+.1f')}° (+ starboard down) |"] if "roll_deg" in st else []),
            f"| Rudder order / actual | {f('rudder_order_deg', '+.1f')}° / {f('rudder_deg', '+.1f')}° |",
            f"| Shaft | {f('rpm', '.0f')} rpm |",
            f"| Telegraph | {TELEGRAPH_NAMES.get(tg, '–') if isinstance(tg, int) else '–'} |",
            f"| Helm | {helm} |",
            *hud_rows(st, link),
        ]
        if sea:
            lines.append(
                f"| Wind / current | {sea.get('wind_speed_kn', 0):.1f} kn from {sea.get('wind_from_deg', 0):03.0f}° / "
                f"{sea.get('current_speed_kn', 0):.2f} kn to {sea.get('current_to_deg', 0):03.0f}° |"
            )
            lines.append(f"| Waves | Hs {sea.get('hs_m', 0):.2f} m, Tp {sea.get('tp_s', 0):.1f} s |")
        if link.events:
            e = link.events[-1]
            what = e.get("outcome") or e.get("what") or ""
            lines.append(f"| Episode {e.get('episode')} | {e.get('event')} {what}{outcome_figures(e)} |")
        return "\n".join(lines)

    def close(self) -> None:
        with contextlib.redirect_stdout(io.StringIO()):
            self.server.stop()


# ---------------------------------------------------------------------------------------------------------------
# Entry point


STATS_PERIOD_S = 10.0  # wall-clock s between log lines of refused requests and dropped messages


def _gate_line(stats: dict[str, int]) -> str:
    """'refused 3 requests (host 1, origin 2); dropped 211 page messages (text frame 11, undecodable 200)'."""
    parts = []
    for what, noun in (("refused", "request"), ("dropped", "page message")):
        items = sorted((k.split(" ", 1)[1], n) for k, n in stats.items() if k.startswith(what + " "))
        if items:
            detail = ", ".join(f"{k} {n}" for k, n in items)
            total = sum(n for _, n in items)
            parts.append(f"{what} {total} {noun}{'' if total == 1 else 's'} ({detail})")
    if stats.get("server errors"):
        parts.append(f"{stats['server errors']} server errors")
    return "; ".join(parts)


def view3d(
    server: Address,
    http: Address = ("127.0.0.1", 8080),
    *,
    lan: bool = False,
    camera: str = "chase",
    rate_hz: float = 20.0,
    name: str = "view3d",
    token: str | None = None,
    duration_s: float | None = None,
    out: TextIO | None = None,
) -> int:
    """Serve the 3D page on ``http`` for the link at ``server`` until Ctrl-C or ``duration_s``. Returns 0.

    ``http``'s name is resolved once (:func:`~vessel_gym.ui.view3d_gate.resolve_page_address`, 5 s at most) and
    the page bound to that address, which must be loopback unless ``lan``. Prints the page's two URLs: the
    one with the helm key (``/helm/KEY``, new each run) can take the helm, ``/`` only watches. Raises
    ``ValueError`` (one line) for a bad address or camera, ``ImportError`` without viser."""
    out = out if out is not None else sys.stdout
    if camera not in CAMERAS:
        raise ValueError(f"camera must be one of {', '.join(CAMERAS)}, not {camera!r}")
    import viser  # noqa: F401  (fail before binding anything)

    page = resolve_page_address(http[0], http[1], lan=lan)
    sock = bind_page_socket(page)
    port = sock.getsockname()[1]
    gate = PageGate((page.name, page.address), port)
    try:
        link = LinkClient(server, rate_hz, name, token)
    except OSError as exc:
        sock.close()
        raise ValueError(f"cannot reach {server[0]}:{server[1]}: {exc.strerror or exc}") from None
    viewer = None
    try:
        viewer = Viewer3D(link, gate, sock, camera)
        base = f"http://{page.url_host(port)}"
        print(
            f"vessel-gym view3d: link {server[0]}:{server[1]}; open {base}{gate.helm_path} to watch and take "
            f"the helm ({base}/ only watches); Ctrl-C to stop",
            file=out,
            flush=True,
        )
        if lan:
            print(
                "vessel-gym view3d: --lan: the page is reachable from the network, over plain HTTP "
                "(the helm key travels unencrypted: use a trusted network)",
                file=out,
                flush=True,
            )
        start = time.monotonic()
        warned_silent = warned_bad = False
        stats_due = start + STATS_PERIOD_S
        said: dict[str, int] = {}
        try:
            while duration_s is None or time.monotonic() - start < duration_s:
                now = time.monotonic()
                link.poll(now)
                try:
                    viewer.update(now)
                except (ValueError, TypeError, KeyError, IndexError) as exc:  # a malformed scene or state
                    if not warned_bad:
                        print(
                            f"vessel-gym view3d: ignoring a message it cannot draw: {exc}",
                            file=out,
                            flush=True,
                        )
                        warned_bad = True
                if link.state is None and not warned_silent and now - start > 5.0:
                    print(
                        f"vessel-gym view3d: no state from {server[0]}:{server[1]} yet (is 'vessel-gym serve' "
                        "running there?); still trying",
                        file=out,
                        flush=True,
                    )
                    warned_silent = True
                if now >= stats_due:
                    stats_due = now + STATS_PERIOD_S
                    stats = gate.stats()
                    line = _gate_line(stats)
                    if line and _gate_line(said) != line:
                        print(f"vessel-gym view3d: {line}", file=out, flush=True)
                        said = stats
                time.sleep(max(0.0, FRAME_PERIOD_S - (time.monotonic() - now)))
        except KeyboardInterrupt:
            pass
        line = _gate_line(gate.stats())
        print(f"vessel-gym view3d: stopped{'; ' + line if line else ''}", file=out, flush=True)
    finally:
        link.close()
        if viewer is not None:
            viewer.close()
        sock.close()
    return 0


__all__ = [
    "CAMERAS",
    "FRAME_PERIOD_S",
    "HUD_PERIOD_S",
    "LinkClient",
    "PageGate",
    "SEA_PERIOD_S",
    "STATS_PERIOD_S",
    "TRACK_POINTS",
    "TRACK_REDRAW_S",
    "TRACK_SPACING_S",
    "Viewer3D",
    "view3d",
]
