"""vessel-gym view3d: geometry, the sea surface, the link client, the page's gate (Host, Origin, the helm key,
malformed messages), the command line, and a real headless browser (Debian's chromium) loading the page fed
by a running ``serve``."""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np
import pytest

from vessel_gym import cli
from vessel_gym.net import protocol as P
from vessel_gym.scenarios.geometry import signed_area
from vessel_gym.ui import view3d as V
from vessel_gym.ui import view3d_gate as G
from vessel_gym.ui import view3d_scene as S

from .chromium import Chromium, chromium_path
from .helpers import make_reading

ROOT = Path(__file__).resolve().parents[2]


def _area(poly, tris):
    return sum(abs(signed_area([poly[a], poly[b], poly[c]])) for a, b, c in tris)


@pytest.mark.parametrize("reverse", [False, True])
def test_triangulate_concave_polygon_covers_its_area(reverse):
    # an L-shaped quay (concave), either orientation
    poly = [(0, 0), (40, 0), (40, 10), (10, 10), (10, 30), (0, 30)]
    poly = poly[::-1] if reverse else poly
    tris = S.triangulate(poly)
    assert len(tris) == len(poly) - 2
    assert _area(poly, tris) == pytest.approx(abs(signed_area(poly)))  # 40*10 + 10*20 = 600 m^2
    assert abs(signed_area(poly)) == pytest.approx(600.0)


def test_prism_has_top_bottom_and_walls():
    v, f = S.prism([(0, 0), (2, 0), (2, 1), (0, 1)], -1.0, 0.5)
    assert v.shape == (8, 3) and f.shape == (2 * 2 + 2 * 4, 3)
    assert set(v[:4, 2]) == {0.5} and set(v[4:, 2]) == {-1.0}


def test_heading_quaternion_turns_the_bow_clockwise_from_north():
    for hdg, expected in ((0.0, (0.0, 1.0)), (90.0, (1.0, 0.0)), (225.0, (-math.sqrt(0.5), -math.sqrt(0.5)))):
        w, _, _, z = S.heading_wxyz(hdg)
        # rotate the ship frame's forward axis (scene +y) about +z by the quaternion
        angle = 2.0 * math.atan2(z, w)
        fwd = (-math.sin(angle), math.cos(angle))
        assert fwd == pytest.approx(expected, abs=1e-12)


def _rotate(q, v):
    """Vector v rotated by the unit quaternion q = (w, x, y, z)."""
    w, x, y, z = q
    u = np.array([x, y, z])
    v = np.asarray(v, dtype=float)
    return v + 2.0 * np.cross(u, np.cross(u, v) + w * v)


def test_attitude_quaternion_heels_the_starboard_side_down_and_keeps_the_heading():
    """Ship frame: x starboard, y forward, z up. A heel of +10 deg (starboard side down) on heading 90 deg:
    the bow still points east, the starboard side (ship +x, pointing south) dips by sin 10 deg, the mast
    leans to starboard; zero heel is the heading quaternion."""
    for hdg in (0.0, 33.0, 90.0, 225.0):
        assert S.attitude_wxyz(hdg, 0.0) == pytest.approx(S.heading_wxyz(hdg), abs=1e-15)
    q = S.attitude_wxyz(90.0, 10.0)
    assert sum(c * c for c in q) == pytest.approx(1.0)
    s10, c10 = math.sin(math.radians(10.0)), math.cos(math.radians(10.0))
    assert _rotate(q, (0, 1, 0)) == pytest.approx((1.0, 0.0, 0.0), abs=1e-12)  # bow east
    assert _rotate(q, (1, 0, 0)) == pytest.approx((0.0, -c10, -s10), abs=1e-12)  # starboard side south, down
    assert _rotate(q, (0, 0, 1)) == pytest.approx((0.0, -s10, c10), abs=1e-12)  # mast leans to starboard
    # heel to port lifts the starboard side
    assert _rotate(S.attitude_wxyz(0.0, -5.0), (1, 0, 0))[2] == pytest.approx(math.sin(math.radians(5.0)))


def test_viewer_places_the_own_ship_heeled_by_the_state_roll():
    """The ship node takes the state's heading and roll_deg; a state without roll (3-DOF ship) is upright."""
    from types import SimpleNamespace

    from vessel_gym.ui.view3d import Viewer3D

    viewer = Viewer3D.__new__(Viewer3D)  # the placement only needs the ship nodes
    frame = SimpleNamespace(position=None, wxyz=None)
    viewer._ships = {0: frame}
    viewer._place(0, {"x_m": 10.0, "y_m": 20.0, "hdg_deg": 45.0, "roll_deg": -7.89})
    assert frame.position == (20.0, 10.0, 0.0)
    assert frame.wxyz == pytest.approx(S.attitude_wxyz(45.0, -7.89))
    viewer._place(0, {"x_m": 10.0, "y_m": 20.0, "hdg_deg": 45.0})
    assert frame.wxyz == pytest.approx(S.heading_wxyz(45.0))
    assert "| Heel | -7.9°" in viewer._hud_text.__func__(
        SimpleNamespace(link=SimpleNamespace(owner=None, helm=False, scene=None, events=[])),
        {"roll_deg": -7.89, "hdg_deg": 45.0},
    )


def test_wave_number_limits_of_linear_theory():
    omega = 2.0 * math.pi / 8.0
    # deep water: wavelength g T^2 / (2 pi) = 99.89 m for T = 8 s
    assert 2.0 * math.pi / S.wave_number(omega, 1e4) == pytest.approx(99.89, abs=0.01)
    # shallow water: celerity omega / k -> sqrt(g h) (h = 0.5 m: 2.21 m/s), within 1 % at kh ~ 0.18
    k = S.wave_number(omega, 0.5)
    assert omega / k == pytest.approx(math.sqrt(9.80665 * 0.5), rel=0.01)
    h = 10.0
    assert omega**2 == pytest.approx(
        9.80665 * S.wave_number(omega, h) * math.tanh(S.wave_number(omega, h) * h)
    )


def test_sea_surface_has_the_significant_wave_height():
    x, y = np.meshgrid(np.linspace(0, 2000, 400), np.linspace(0, 2000, 400))
    z = S.sea_elevation(x.ravel(), y.ravel(), 3.0, 2.0, 8.0, 45.0, 50.0)
    assert 4.0 * np.std(z) == pytest.approx(2.0, rel=0.05)  # Hs = 4 sigma
    assert not np.any(S.sea_elevation(x.ravel(), y.ravel(), 3.0, 0.0, 8.0, 45.0, 50.0))  # calm: flat
    later = S.sea_elevation(x.ravel(), y.ravel(), 4.0, 2.0, 8.0, 45.0, 50.0)
    assert np.max(np.abs(later - z)) > 0.5  # it moves


def test_link_client_merges_parts_ignores_strangers_and_takes_the_helm_from_orders_in_force():
    server = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    server.bind(("127.0.0.1", 0))
    stranger = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    link = V.LinkClient(server.getsockname(), 20.0, "t", None)
    try:
        link.poll(0.0)
        hello, addr = server.recvfrom(4096)
        assert P.parse_datagram(hello).proto == 2 and P.parse_datagram(hello).role == "viewer"
        targets = [P.Target(i, f"T{i}", make_reading(x_m=10.0 * i), 100.0, 20.0) for i in range(1, 30)]
        parts = P.encode_state(5, make_reading(), False, targets)
        assert len(parts) > 1
        for d in parts:
            server.sendto(d, addr)
        stranger.sendto(P.encode_state(99, make_reading(hdg_deg=1.0), True)[0], addr)
        for d in P.encode_scenario(3, None, None):
            server.sendto(d, addr)
        time.sleep(0.01)
        link.poll(0.1)
        assert link.state["seq"] == 5 and len(link.state["targets"]) == 29
        assert link.dropped == 1 and link.scene is not None
        link.take_helm()
        assert link.helm and link.rudder_order_deg == -15.0 and link.telegraph == 3
        link.poll(1.0)
        msgs = []
        server.settimeout(1.0)
        for _ in range(3):
            msgs.append(json.loads(server.recv(4096)))
            if msgs[-1]["type"] == "helm":
                break
        assert msgs[0]["role"] == "helm"
        helm = [m for m in msgs if m["type"] == "helm"][0]
        assert helm["rudder_order_deg"] == -15.0 and helm["telegraph"] == 3
    finally:
        link.close()
        server.close()
        stranger.close()


def test_view3d_without_viser_names_the_extra(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "viser", None)  # import viser -> ImportError
    assert cli.main(["view3d", "--server", "127.0.0.1:10120"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "view3d" in err and "pip install" in err


def test_view3d_refuses_a_page_off_loopback(capsys):
    pytest.importorskip("viser")
    assert cli.main(["view3d", "--http", "0.0.0.0:8080"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "0.0.0.0 is not a loopback address" in err and "--lan" in err
    # with --lan a wildcard is still refused: requests are checked against the name the page is served under
    assert cli.main(["view3d", "--http", "0.0.0.0:8080", "--lan"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "wildcard" in err


# -- the page in a real browser ---------------------------------------------------------------------------


def _free_port(kind=socket.SOCK_STREAM) -> int:
    with socket.socket(socket.AF_INET, kind) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _ship_pixels(png: bytes):
    """Pixels of the own ship's red hull in the 3D view (HUD panel, the software-WebGL notice and the axes
    gizmo excluded): their count and centroid (px)."""
    from PIL import Image

    im = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
    view = im[:, :940]
    r, g, b = view[..., 0], view[..., 1], view[..., 2]
    red = (r > 110) & (r > 2.5 * g) & (r > 2.5 * b)
    red[:200, :330] = False  # the notice
    red[-90:, :90] = False  # the orientation gizmo (its x axis is red)
    ys, xs = np.nonzero(red)
    return len(xs), (xs.mean() if len(xs) else math.nan, ys.mean() if len(ys) else math.nan)


EVIL_PAGE = """<!doctype html><html><body><p>a page from another origin</p><script>
window.results = {};
function tryWs(name, url) {
  results[name] = "pending";
  const ws = new WebSocket(url, ["viser-v%(version)s"]);
  ws.onopen = () => { results[name] = "open"; };
  ws.onclose = (e) => { if (results[name] !== "open") results[name] = "refused " + e.code; };
}
tryWs("watch", "ws://127.0.0.1:%(port)d/");
tryWs("helm", "ws://127.0.0.1:%(port)d%(helm)s");  // even with the key (leaked), the Origin is wrong
fetch("http://127.0.0.1:%(port)d/").then(r => { results.fetch = "status " + r.status; })
  .catch(() => { results.fetch = "blocked"; });
</script></body></html>"""


def _serve_evil_page(html: str):
    """A web page from another origin (another port of loopback), as any site the user visits."""
    import http.server
    import threading

    class Handler(http.server.BaseHTTPRequestHandler):
        def do_GET(self):
            body = html.encode()
            self.send_response(200)
            self.send_header("Content-Type", "text/html")
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, *args):
            pass

    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    threading.Thread(target=httpd.serve_forever, daemon=True).start()
    return httpd


@pytest.mark.slow
def test_page_in_headless_chromium_only_its_helm_url_takes_the_helm(tmp_path):
    """The real page in a real browser: a page of another origin cannot open its websocket (not even with the
    helm key); the page at / draws the scene and says it only watches (H does nothing); the page at the printed
    helm URL draws the ship moving and takes the helm with H; serve counts one takeover."""
    if chromium_path() is None:
        pytest.skip("chromium is not installed (Debian package chromium)")
    pytest.importorskip("viser")
    pytest.importorskip("websockets")
    pytest.importorskip("PIL")
    import re

    env = {**os.environ, "PYTHONPATH": f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    udp, http = _free_port(socket.SOCK_DGRAM), _free_port()
    py = [sys.executable, "-m", "vessel_gym.cli"]
    procs = []
    evil = None
    try:
        procs.append(
            subprocess.Popen(
                py
                + [
                    "serve",
                    "--json",
                    f"127.0.0.1:{udp}",
                    "--nmea",
                    "off",
                    "--time-factor",
                    "10",
                    "--duration",
                    "400",
                    "--seed",
                    "1",
                ],
                env=env,
                stdout=open(tmp_path / "serve.log", "w"),
                stderr=subprocess.STDOUT,
            )
        )
        procs.append(
            subprocess.Popen(
                py
                + [
                    "view3d",
                    "--server",
                    f"127.0.0.1:{udp}",
                    "--http",
                    f"127.0.0.1:{http}",
                    "--camera",
                    "harbour",
                    "--duration",
                    "390",
                ],
                env=env,
                stdout=open(tmp_path / "view3d.log", "w"),
                stderr=open(tmp_path / "view3d.err", "w"),
            )
        )
        url = f"http://127.0.0.1:{http}/"
        deadline = time.monotonic() + 90
        while True:
            found = re.search(
                rf"open ({re.escape(url)}helm/[A-Za-z0-9_-]+) ", (tmp_path / "view3d.log").read_text()
            )
            if found:
                helm_url = found.group(1)
                with urllib.request.urlopen(helm_url, timeout=5) as r:
                    assert r.status == 200
                break
            assert all(p.poll() is None for p in procs), (tmp_path / "view3d.err").read_text()
            assert time.monotonic() < deadline, "the page was not served within 90 s"
            time.sleep(0.5)
        helm_path = helm_url[len(url) - 1 :]
        evil = _serve_evil_page(EVIL_PAGE % {"port": http, "helm": helm_path, "version": _viser_version()})
        with Chromium() as browser:
            # 1. a page of another origin
            browser.call("Page.navigate", url=f"http://127.0.0.1:{evil.server_address[1]}/")
            for _ in range(20):
                browser.pump(0.5)
                got = browser.call(
                    "Runtime.evaluate", expression="JSON.stringify(window.results)", returnByValue=True
                )
                results = json.loads(got.get("result", {}).get("value") or "{}")
                if results and "pending" not in results.values() and "fetch" in results:
                    break
            assert results.get("watch", "").startswith("refused") and results.get("helm", "").startswith(
                "refused"
            ), results
            assert results["fetch"] == "blocked", results  # 403 without CORS headers: the page reads nothing
            # 2. the page without the key: it watches, H does not take the helm
            browser.events.clear()
            browser.call("Page.navigate", url=url)
            for _ in range(360):  # serve's first start compiles its kernels (minutes on a loaded machine)
                browser.pump(0.5)
                if "Watching only" in browser.text() and "Heading" in browser.text():
                    break
            text = browser.text()
            assert "Watching only" in text and "Heading" in text, (text, (tmp_path / "serve.log").read_text())
            browser.press("h", "KeyH", 72)
            browser.pump(2.0)
            assert "YOU" not in browser.text()
            # 3. the page at the helm URL
            browser.events.clear()
            browser.call("Page.navigate", url=helm_url)
            first = None
            for i in range(30):  # the scene and the first states arrive within seconds
                browser.pump(1.0)
                shot = browser.screenshot(str(tmp_path / f"wait{i}.png"))
                n, c = _ship_pixels(shot)
                if n >= 12:
                    first = (n, c)
                    break
            assert first is not None, f"no ship drawn; screenshots in {tmp_path}"
            assert "Watching only" not in browser.text()
            browser.pump(4.0)
            shot2 = browser.screenshot(str(tmp_path / "second.png"))
            n2, c2 = _ship_pixels(shot2)
            # the page only watches: a rudder key does nothing until H takes the helm
            assert "autopilot" in browser.text()
            browser.press("ArrowRight", "ArrowRight", 39)
            browser.pump(1.5)
            assert "YOU" not in browser.text()
            browser.press("h", "KeyH", 72)
            for _ in range(10):
                browser.pump(0.5)
                text = browser.text()
                if "YOU" in text:
                    break
            assert "YOU" in text, text
            browser.press("ArrowRight", "ArrowRight", 39)
            browser.pump(1.5)
            assert "YOU (order" in browser.text()
            errors = browser.errors()
        procs[0].send_signal(signal.SIGINT)  # serve prints its totals on Ctrl-C
        procs[0].wait(30)
        procs[1].send_signal(signal.SIGINT)  # and view3d what its gate refused and dropped
        procs[1].wait(30)
        totals = (tmp_path / "serve.log").read_text()
        assert "helm takeovers 1;" in totals, totals
        assert errors == []
        # still drawn: by now the pilot may have brought the ship into the basin heading north, seen end-on
        # from the harbour camera in the south (11 hull pixels in one run against 12+ beam-on)
        assert n2 >= 6
        moved_px = math.hypot(c2[0] - first[1][0], c2[1] - first[1][1])
        assert moved_px > 3.0, f"ship did not move between screenshots ({moved_px:.1f} px); see {tmp_path}"
        log = (tmp_path / "view3d.log").read_text()
        stopped = [line for line in log.splitlines() if "view3d: stopped" in line][-1]
        assert re.search(r"refused \d+ requests \(origin [3-9]\)", stopped), log  # 2 upgrades and the fetch
        assert "not allowed 1" in stopped, log  # the watcher's H
        assert "unknown type" not in stopped and "bad fields" not in stopped, (
            log
        )  # the real page's messages pass
        assert (tmp_path / "view3d.err").read_text() == ""
    finally:
        if evil is not None:
            evil.shutdown()
        for p in procs:
            p.terminate()
        for p in procs:
            try:
                p.wait(15)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def test_link_client_answers_the_handshake_and_commands_in_its_session():
    server = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    server.bind(("127.0.0.1", 0))
    server.settimeout(1.0)
    link = V.LinkClient(server.getsockname(), 20.0, "t", None)
    try:
        link.poll(0.0)
        first, addr = server.recvfrom(4096)
        assert len(first) >= P.MIN_HELLO_BYTES and P.parse_datagram(first).cookie is None
        server.sendto(P.encode_challenge(1, "c0ffee"), addr)
        time.sleep(0.01)
        link.poll(0.1)  # a challenge is answered at once, with its cookie
        again = P.parse_datagram(server.recv(4096))
        assert again.cookie == "c0ffee" and again.proto == 2 and again.session is None
        full = P.encode_welcome(2, "viewer", 20.0, False, P.Limits(), 1.0, 3.0, "hold", "c0ffee2", "s1")
        server.sendto(full, addr)
        time.sleep(0.01)
        link.poll(0.2)
        assert link.session == "s1" and link.welcome is not None
        link.take_helm()
        hello = P.parse_datagram(server.recv(4096))
        assert (hello.role, hello.cookie, hello.session) == ("helm", "c0ffee2", "s1")
        link.poll(1.0)
        while True:
            msg = P.parse_datagram(server.recv(4096))
            if isinstance(msg, P.HelmCommand):
                break
        assert msg.session == "s1"
    finally:
        link.close()
        server.close()


def test_viewer_heels_the_container_ship_from_a_real_link():
    """End to end without a browser: the 4-DOF container ship 30 s into a 35 deg starboard turn, its bridge
    reading served by a real UdpLink; the viewer's link client receives roll_deg (the simulation's heel,
    outward in the turn, to port) and the viewer places the ship node heeled by it."""
    from types import SimpleNamespace

    from vessel_gym.net.link import LinkConfig, UdpLink
    from vessel_gym.physics.simulation import Simulation
    from vessel_gym.ui.view3d import Viewer3D

    sim = Simulation("container", dt=0.1)
    sim.reset(speed_m_s=sim.ship(0).test_speed_m_s)
    sim.set_helm(rudder_order_rad=math.radians(35.0))
    sim.advance(30.0)
    own = sim.bridge(0)
    assert own.roll_deg < -3.0  # the outward heel of the turn (docs/manoeuvres.md: -7.9 deg at 28.9 s)
    with UdpLink(LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=())) as link:
        client = V.LinkClient(link.json_address, 20.0, "t", None)
        try:
            deadline = time.monotonic() + 5.0
            while time.monotonic() < deadline:
                client.poll(time.monotonic())
                link.service(sim.t, own)
                client.poll(time.monotonic())
                if client.state and "roll_deg" in client.state:
                    break
                time.sleep(0.02)
            st = client.state
        finally:
            client.close()
    assert st["roll_deg"] == pytest.approx(own.roll_deg, abs=0.005)
    assert st["roll_rate_dps"] == pytest.approx(own.roll_rate_dps, abs=5e-4)
    viewer = Viewer3D.__new__(Viewer3D)
    frame = SimpleNamespace(position=None, wxyz=None)
    viewer._ships = {0: frame}
    viewer._place(0, st)
    assert frame.wxyz == pytest.approx(S.attitude_wxyz(st["hdg_deg"], st["roll_deg"]))
    # the starboard side (ship node +x) is up: heeled to port
    assert _rotate(frame.wxyz, (1, 0, 0))[2] == pytest.approx(
        math.sin(math.radians(-st["roll_deg"])), abs=1e-9
    )


# -- the page's gate: Host, Origin, the helm key, malformed messages (issue: a foreign page took the helm) ----


def _raw_request(port: int, path: str, headers, upgrade: bool) -> tuple[int, bytes]:
    """One HTTP request with exactly ``headers`` (a dict or (name, value) pairs; no Host or Origin added), as
    a hostile page or client would send it; returns the status code and the response's first bytes."""
    with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
        s.sendall(_request_bytes(path, headers, upgrade))
        data = s.recv(4096)
    return int(data.split(b" ", 2)[1]), data


def _request_bytes(path: str, headers, upgrade: bool) -> bytes:
    pairs = headers.items() if isinstance(headers, dict) else headers
    lines = [f"GET {path} HTTP/1.1"] + [f"{k}: {v}" for k, v in pairs]
    if upgrade:
        lines += [
            "Upgrade: websocket",
            "Connection: Upgrade",
            "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==",
            "Sec-WebSocket-Version: 13",
            f"Sec-WebSocket-Protocol: viser-v{_viser_version()}",
        ]
    return ("\r\n".join(lines) + "\r\n\r\n").encode()


def _viser_version() -> str:
    import viser

    return viser.__version__


class _Page:
    """A running gated page (the real Viewer3D, its link client pointed at a silent UDP socket)."""

    def __init__(self, host: str = "127.0.0.1") -> None:
        pytest.importorskip("viser")
        self.udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.udp.bind(("127.0.0.1", 0))
        addr = G.resolve_page_address(host, 0)
        self.sock = G.bind_page_socket(addr)
        self.port = self.sock.getsockname()[1]
        self.gate = G.PageGate((addr.name, addr.address), self.port)
        self.link = V.LinkClient(self.udp.getsockname(), 20.0, "t", None)
        self.viewer = V.Viewer3D(self.link, self.gate, self.sock, "chase")

    def url(self, path: str = "/") -> str:
        return f"ws://127.0.0.1:{self.port}{path}"

    def connect(self, path: str = "/", origin: str | None = "own"):
        from websockets.sync.client import connect

        origin = f"http://127.0.0.1:{self.port}" if origin == "own" else origin
        return connect(
            self.url(path), subprotocols=[f"viser-v{_viser_version()}"], origin=origin, open_timeout=5
        )

    def close(self) -> None:
        self.viewer.close()
        self.link.close()
        self.udp.close()
        self.sock.close()


@pytest.fixture
def page():
    p = _Page()
    try:
        yield p
    finally:
        p.close()


def _msg(kind: str, **fields) -> bytes:
    import msgspec

    return msgspec.msgpack.encode({"type": kind, **fields})


CAMERA = dict(
    wxyz=[1.0, 0.0, 0.0, 0.0],
    position=[0.0, -10.0, 5.0],
    fov=1.0,
    near=0.01,
    far=1000.0,
    image_height=800,
    image_width=1280,
    look_at=[0.0, 0.0, 0.0],
    up_direction=[0.0, 0.0, 1.0],
)


def test_page_http_requests_need_the_pages_host_and_origin(page):
    port = page.port
    own = {"Host": f"127.0.0.1:{port}"}
    status, data = _raw_request(port, "/", own, upgrade=False)
    assert status == 200 and b"X-Frame-Options: DENY" in data and b"Cache-Control: no-store" in data
    assert (
        _raw_request(port, "/", {"Host": f"localhost:{port}"}, upgrade=False)[0] == 403
    )  # not the bound name
    assert _raw_request(port, page.gate.helm_path, own, upgrade=False)[0] == 200  # the page with the key
    assert _raw_request(port, "/helm/" + "x" * 24, own, upgrade=False)[0] == 403
    for origin in (
        "http://evil.example",
        "null",
        f"http://127.0.0.1:{port + 1}",
        f"https://127.0.0.1:{port}",
    ):
        assert _raw_request(port, "/", {**own, "Origin": origin}, upgrade=False)[0] == 403, origin
    # DNS rebinding: evil.example resolved to 127.0.0.1, the browser sends its own name as Host
    for host in (f"evil.example:{port}", "evil.example", f"127.0.0.1:{port + 1}", ""):
        assert _raw_request(port, "/", {"Host": host}, upgrade=False)[0] == 403, host
    assert _raw_request(port, "/", {}, upgrade=False)[0] == 403  # no Host at all
    two = [("Host", f"127.0.0.1:{port}"), ("Host", "evil.example")]
    assert _raw_request(port, "/", two, upgrade=False)[0] == 403  # which one would a proxy have used?
    two = [*own.items(), ("Origin", f"http://127.0.0.1:{port}"), ("Origin", "http://evil.example")]
    assert _raw_request(port, "/", two, upgrade=True)[0] == 403
    # an upgrade to websocket and something else: never upgraded
    odd = [*own.items(), ("Origin", f"http://127.0.0.1:{port}"), ("Upgrade", "h2c")]
    assert _raw_request(port, "/", odd, upgrade=True)[0] not in (101, 200)
    stats = page.gate.stats()
    assert stats["refused origin"] == 5 and stats["refused host"] == 7 and stats["refused key"] == 1


@pytest.mark.parametrize(
    "origin, host, expected",
    [
        ("http://127.0.0.1:{port}", "127.0.0.1:{port}", 101),
        ("http://evil.example", "127.0.0.1:{port}", 403),  # a foreign page
        ("null", "127.0.0.1:{port}", 403),  # a sandboxed iframe, a file:// page
        (None, "127.0.0.1:{port}", 403),  # no Origin: a browser always sends one with an upgrade
        ("http://evil.example:{port}", "evil.example:{port}", 403),  # DNS rebinding
        ("http://127.0.0.1:{port}", "evil.example:{port}", 403),
    ],
)
def test_page_websocket_upgrade_needs_the_pages_host_and_origin(page, origin, host, expected):
    headers = {"Host": host.format(port=page.port)}
    if origin is not None:
        headers["Origin"] = origin.format(port=page.port)
    for path in ("/", page.gate.helm_path):
        status, _ = _raw_request(page.port, path, headers, upgrade=True)
        assert status == expected, (path, headers)


def _wait_for(cond, timeout_s: float = 5.0) -> bool:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if cond():
            return True
        time.sleep(0.02)
    return cond()


def test_page_without_the_helm_key_watches_but_cannot_command(page):
    """A websocket client with the page's Origin but without the key gets the scene and may report its
    camera, but its helm command and button press are dropped; the same messages from the key's path take the
    helm. (An attacker reads the command ids from the scene it receives; the test takes them from the page.)"""
    take = page.viewer.commands["Take the helm"]._impl.uuid
    button = page.viewer.helm_button._impl.uuid
    commands = [
        _msg("CommandTriggerMessage", uuid=take),
        _msg("GuiUpdateMessage", uuid=button, updates={"value": True}),
    ]
    with page.connect("/") as ws:
        assert len(ws.recv(timeout=5)) > 16  # the scene is sent: it may watch
        ws.send(_msg("ViewerCameraMessage", **CAMERA))
        assert _wait_for(lambda: len(page.viewer.server.get_clients()) == 1)  # connected (camera accepted)
        for m in commands:
            ws.send(m)
        assert _wait_for(lambda: page.gate.stats().get("dropped not allowed") == 2)
        time.sleep(0.3)
        assert not page.link.helm
    from websockets.exceptions import InvalidStatus

    with pytest.raises(InvalidStatus) as refused:  # a wrong key is refused at the upgrade
        page.connect("/helm/" + "A" * len(page.gate.key)).close()
    assert refused.value.response.status_code == 403
    with page.connect(page.gate.helm_path) as ws:
        ws.send(_msg("ViewerCameraMessage", **CAMERA))
        assert _wait_for(lambda: len(page.viewer.server.get_clients()) == 1)
        ws.send(commands[0])
        assert _wait_for(lambda: page.link.helm), page.gate.stats()
    stats = page.gate.stats()
    assert stats["accepted watch"] == 1 and stats["accepted helm"] == 1 and stats["refused key"] == 1


def test_page_drops_and_counts_malformed_messages_without_a_traceback(page, capfd):
    """Garbage from a page (the 211 tracebacks of the report): each message dropped and counted, the
    connection kept (except for an oversized frame, which closes it), nothing on stderr, and the page still
    serves the next client."""
    rng = np.random.default_rng(25)
    take = page.viewer.commands["Take the helm"]._impl.uuid
    garbage: list[tuple[bytes | str, str]] = [(rng.bytes(int(n)), "") for n in rng.integers(1, 400, 150)]
    garbage += [(f"text frame {i}", "dropped text frame") for i in range(20)]
    garbage += [
        (_msg("Nope"), "dropped unknown type"),
        (_msg("RunJavascriptMessage", source="alert(1)"), "dropped unknown type"),
        (_msg("ShareUrlRequest"), "dropped unknown type"),
        (_msg("FileTransferStartUpload", source_component_uuid="x"), "dropped unknown type"),
        (b"\x93\x01\x02\x03", "dropped unknown type"),  # a msgpack list, not a message
        (b"\x91" * 100_000 + b"\x00", "dropped undecodable"),  # nested 100 000 deep
        (_msg("ViewerCameraMessage", **{**CAMERA, "wxyz": "a"}), "dropped bad fields"),
        (_msg("ViewerCameraMessage", **{**CAMERA, "fov": float("nan")}), "dropped bad fields"),
        (_msg("ViewerCameraMessage", **{**CAMERA, "position": [0.0, 1.0]}), "dropped bad fields"),
        (_msg("ViewerCameraMessage", wxyz=[1, 0, 0, 0]), "dropped bad fields"),
        (_msg("CommandTriggerMessage", uuid=take), "dropped not allowed"),  # a watcher
    ]
    with page.connect("/") as ws:
        ws.recv(timeout=5)
        for data, _ in garbage:
            ws.send(data)
        ws.send(_msg("ViewerCameraMessage", **CAMERA))  # still heard after all that
        assert _wait_for(lambda: len(page.viewer.server.get_clients()) == 1)
    with page.connect(page.gate.helm_path) as ws:  # the key holder's malformed GUI messages
        ws.recv(timeout=5)
        for m in (
            _msg("GuiUpdateMessage", uuid=take, updates={"label": "pwned"}),  # viser would set any property
            _msg("GuiUpdateMessage", uuid=take, updates={"value": [1, 2]}),
            _msg("GuiUpdateMessage", uuid=5, updates={"value": True}),
            _msg("CommandTriggerMessage", uuid=None),
        ):
            ws.send(m)
        ws.send(b"\x00" * (G.MAX_MESSAGE_BYTES + 1))  # oversized: websockets closes the connection (1009)
        from websockets.exceptions import ConnectionClosedError

        with pytest.raises(ConnectionClosedError) as closed:
            for _ in range(100):
                ws.recv(timeout=5)
        assert closed.value.sent.code == 1009  # message too big
    with socket.create_connection(("127.0.0.1", page.port), timeout=5) as raw:  # not even HTTP
        raw.sendall(b"\x16\x03\x01\x02\x00garbage\r\n\r\n")
        raw.recv(100)
    own = {"Host": f"127.0.0.1:{page.port}", "Origin": f"http://127.0.0.1:{page.port}"}
    for frames in (rng.bytes(300), b"\x81\x05hello", b"\x81\x82abcd\xff\xfe"):  # random, unmasked, bad UTF-8
        with socket.create_connection(("127.0.0.1", page.port), timeout=5) as raw:
            raw.sendall(_request_bytes("/", own, upgrade=True))
            assert raw.recv(4096).startswith(b"HTTP/1.1 101")
            raw.sendall(frames)
            with contextlib.suppress(OSError):
                while raw.recv(65536):  # until websockets closes the connection
                    pass
    expected = {k for _, k in garbage if k}
    assert _wait_for(lambda: page.gate.stats().get("dropped oversized") == 1)
    assert _wait_for(lambda: page.gate.stats().get("refused malformed") == 1)
    assert _wait_for(lambda: page.gate.stats().get("dropped bad frame") == 3), page.gate.stats()
    stats = page.gate.stats()
    frame_level = ("dropped oversized", "dropped bad frame")
    dropped = sum(n for k, n in stats.items() if k.startswith("dropped ") and k not in frame_level)
    assert dropped == len(garbage) + 4, stats
    assert (
        expected <= set(stats) and stats["dropped bad fields"] == 4 + 4 and stats["dropped text frame"] == 20
    )
    assert stats.get("server errors", 0) == 0
    with page.connect("/") as ws:  # still serving
        assert len(ws.recv(timeout=5)) > 16
    err = capfd.readouterr().err
    assert "Traceback" not in err and "Error" not in err, err[-2000:]
    assert "dropped" in V._gate_line(stats) and "refused 1 request (malformed 1)" in V._gate_line(stats)


def test_page_counts_a_failing_message_handler_instead_of_printing_it(page, capfd):
    """A message that passes the checks but makes one of viser's handlers fail (here a number for a 2-vector
    input, which viser iterates) is counted as a server error; nothing reaches stderr."""
    vec = page.viewer.server.gui.add_vector2("v", (0.0, 0.0))
    with page.connect(page.gate.helm_path) as ws:
        ws.send(_msg("ViewerCameraMessage", **CAMERA))
        assert _wait_for(lambda: len(page.viewer.server.get_clients()) == 1)
        ws.send(_msg("GuiUpdateMessage", uuid=vec._impl.uuid, updates={"value": 5}))
        assert _wait_for(lambda: page.gate.stats().get("server errors") == 1), page.gate.stats()
    assert "Traceback" not in capfd.readouterr().err


def test_page_refuses_websockets_beyond_its_limit(page):
    with contextlib.ExitStack() as stack:
        for _ in range(G.MAX_CONNECTIONS):
            stack.enter_context(page.connect("/")).recv(timeout=5)
        from websockets.exceptions import InvalidStatus

        with pytest.raises(InvalidStatus) as busy:
            page.connect("/").close()
        assert busy.value.response.status_code == 503
    assert _wait_for(lambda: page.gate._open == 0)
    with page.connect("/") as ws:  # room again
        assert len(ws.recv(timeout=5)) > 16
    assert page.gate.stats()["refused busy"] == 1


def test_page_closes_a_websocket_of_another_client_without_printing(page, capfd):
    """A websocket from the page's own origin that did not offer viser's subprotocol of this version (a
    script, another viser) is closed and counted; viser would have printed a banner on stdout for each one."""
    from websockets.exceptions import ConnectionClosed
    from websockets.sync.client import connect

    for protocols in (None, ["viser-v0.0.1"], ["chat"]):
        with connect(page.url("/"), origin=f"http://127.0.0.1:{page.port}", subprotocols=protocols) as ws:
            with pytest.raises(ConnectionClosed) as closed:
                ws.recv(timeout=5)
            assert closed.value.rcvd.code == 1002
    assert page.gate.stats()["refused version"] == 3 and "accepted watch" not in page.gate.stats()
    assert page.viewer.server.get_clients() == {}
    out, err = capfd.readouterr()
    assert "viser" not in out and err == "", (out, err)
    with page.connect("/") as ws:  # the page's own client is served
        assert len(ws.recv(timeout=5)) > 16


def test_page_drops_a_flood_of_messages_over_its_rate(page):
    with page.connect("/") as ws:
        ws.recv(timeout=5)
        for _ in range(G.MESSAGE_BURST + 600):
            ws.send(_msg("ViewerCameraMessage", **CAMERA))
        assert _wait_for(lambda: page.gate.stats().get("dropped over rate", 0) >= 300)


def test_view3d_logs_what_its_gate_refused_and_dropped(monkeypatch):
    """The counts reach the log: a line while it runs (monkeypatched to every 0.5 s) and the stop line."""
    pytest.importorskip("viser")
    monkeypatch.setattr(V, "STATS_PERIOD_S", 0.5)
    udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    udp.bind(("127.0.0.1", 0))
    out = io.StringIO()
    import threading

    t = threading.Thread(
        target=V.view3d, args=(udp.getsockname(), ("127.0.0.1", 0)), kwargs={"duration_s": 3.0, "out": out}
    )
    t.start()
    try:
        assert _wait_for(lambda: "open http://" in out.getvalue())
        first = out.getvalue().splitlines()[0]
        helm_url = first.split("open ", 1)[1].split(" ", 1)[0]
        host, _, key = helm_url.removeprefix("http://").partition("/helm/")
        assert len(key) >= 24 and host.startswith("127.0.0.1:")  # the bound address, a fresh key
        port = int(host.split(":")[1])
        assert (
            _raw_request(port, "/", {"Host": host, "Origin": "http://evil.example"}, upgrade=True)[0] == 403
        )
        assert _raw_request(port, f"/helm/{key}", {"Host": host}, upgrade=False)[0] == 200
        assert _wait_for(lambda: "refused 1 request (origin 1)" in out.getvalue(), 3.0), out.getvalue()
    finally:
        t.join(10)
        udp.close()
    assert out.getvalue().splitlines()[-1] == "vessel-gym view3d: stopped; refused 1 request (origin 1)"


def _fake_getaddrinfo(answer):
    real = socket.getaddrinfo

    def fake(host, port, *args, **kwargs):
        if host in answer:
            a = answer[host]
            if isinstance(a, BaseException):
                raise a
            if a == "hang":
                time.sleep(30)
            return [(socket.AF_INET, socket.SOCK_STREAM, 6, "", (a, port))]
        return real(host, port, *args, **kwargs)

    return fake


def test_view3d_http_name_is_resolved_once_and_must_be_loopback(monkeypatch, capsys):
    """--http resolves its name (getaddrinfo, 5 s at most) and checks the address, not the text: a name that
    starts with "127." but resolves elsewhere is refused, one that does not resolve or hangs ends with one
    line and exit 2."""
    pytest.importorskip("viser")
    monkeypatch.setattr(
        socket,
        "getaddrinfo",
        _fake_getaddrinfo(
            {
                "127.0.0.1.example": "93.184.216.34",
                "nowhere.invalid": socket.gaierror(socket.EAI_NONAME, "Name or service not known"),
                "slow.example": "hang",
                "boat.lan": "192.168.7.7",
            }
        ),
    )
    monkeypatch.setattr(G, "RESOLVE_TIMEOUT_S", 0.3)
    cases = [
        ("127.0.0.1.example:8080", [], "93.184.216.34 is not a loopback address"),
        ("nowhere.invalid:8080", [], "cannot resolve the name (Name or service not known)"),
        ("slow.example:8080", [], "did not resolve within 0.3 s"),
        ("boat.lan:8080", [], "192.168.7.7 is not a loopback address"),
        ("boat.lan:8080", ["--lan"], "cannot serve the page on 192.168.7.7:8080"),  # not this machine's
        ("[::1]x:8080", [], "cannot resolve"),
    ]
    for http, extra, message in cases:
        t0 = time.monotonic()
        assert cli.main(["view3d", "--http", http, *extra]) == 2, http
        err = capsys.readouterr().err.strip()
        assert err.count("\n") == 0 and message in err, (http, err)
        assert time.monotonic() - t0 < 2.0


def test_view3d_refuses_a_port_in_use_with_one_line(capsys):
    pytest.importorskip("viser")
    with socket.socket() as holder:
        holder.bind(("127.0.0.1", 0))
        holder.listen()
        port = holder.getsockname()[1]
        assert cli.main(["view3d", "--http", f"127.0.0.1:{port}"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and f"cannot serve the page on 127.0.0.1:{port}" in err


def test_page_on_ipv6_loopback_checks_the_bracketed_host():
    if not socket.has_ipv6:
        pytest.skip("no IPv6")
    try:
        p = _Page("[::1]")
    except ValueError as exc:
        pytest.skip(f"no IPv6 loopback here ({exc})")
    try:
        host = f"[::1]:{p.port}"
        with socket.create_connection(("::1", p.port), timeout=5) as s:
            s.sendall(f"GET / HTTP/1.1\r\nHost: {host}\r\n\r\n".encode())
            assert s.recv(100).startswith(b"HTTP/1.1 200")
        with socket.create_connection(("::1", p.port), timeout=5) as s:
            s.sendall(f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{p.port}\r\n\r\n".encode())
            assert s.recv(100).startswith(b"HTTP/1.1 403")
        from websockets.sync.client import connect

        url = f"ws://{host}/"
        with connect(url, subprotocols=[f"viser-v{_viser_version()}"], origin=f"http://{host}") as ws:
            assert len(ws.recv(timeout=5)) > 16
    finally:
        p.close()


def test_page_address_keeps_the_name_and_the_resolved_address():
    a = G.resolve_page_address("localhost", 0)
    assert a.name == "localhost" and a.address in ("127.0.0.1", "::1")
    gate = G.PageGate((a.name, a.address), 8080)
    assert {"localhost:8080", "127.0.0.1:8080"} <= gate.hosts or "[::1]:8080" in gate.hosts
    assert len(gate.key) == 24 and gate.key != G.PageGate((a.name,), 8080).key  # 18 random bytes, each run
    six = G.PageGate(("::1",), 80)
    assert six.hosts == {"[::1]:80", "[::1]"} and "http://[::1]" in six.origins


@pytest.mark.slow
def test_view3d_with_a_name_that_does_not_resolve_exits_2_with_one_line(tmp_path):
    """The real resolver, in a subprocess: .invalid never resolves (RFC 6761); exit 2 within the 5 s bound."""
    pytest.importorskip("viser")
    env = {**os.environ, "PYTHONPATH": f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    t0 = time.monotonic()
    r = subprocess.run(
        [sys.executable, "-m", "vessel_gym.cli", "view3d", "--http", "127.0.0.1.vessel-gym.invalid:8080"],
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.count("\n") == 1 and "--http 127.0.0.1.vessel-gym.invalid" in r.stderr, r.stderr
    assert time.monotonic() - t0 < G.RESOLVE_TIMEOUT_S + 15.0  # interpreter start and imports included


def test_link_client_binds_loopback_for_a_loopback_server_by_its_address():
    """The link client's own socket is reachable from the network only when the server is not on loopback,
    decided from the resolved address (ipaddress), not from its text."""
    for server, bound in (
        (("127.0.0.1", 9), "127.0.0.1"),
        (("127.3.2.1", 9), "127.0.0.1"),
        (("192.0.2.1", 9), "0.0.0.0"),
    ):
        link = V.LinkClient(server, 20.0, "t", None)
        try:
            assert link.sock.getsockname()[0] == bound, server
        finally:
            link.close()
