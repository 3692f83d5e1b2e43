"""vessel-gym view3d: geometry, the sea surface, the link client, the command line, and a real headless
browser (Debian's chromium) loading the page fed by a running ``serve``."""

from __future__ import annotations

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
from vessel_gym.net import view3d as V
from vessel_gym.scenarios.geometry import signed_area

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
    tris = V.triangulate(poly)
    assert len(tris) == len(poly) - 2
    assert _area(poly, tris) == pytest.approx(abs(signed_area(poly)))  # 40*10 + 10*20 = 600 m^2
    assert abs(signed_area(poly)) == pytest.approx(600.0)


def test_prism_has_top_bottom_and_walls():
    v, f = V.prism([(0, 0), (2, 0), (2, 1), (0, 1)], -1.0, 0.5)
    assert v.shape == (8, 3) and f.shape == (2 * 2 + 2 * 4, 3)
    assert set(v[:4, 2]) == {0.5} and set(v[4:, 2]) == {-1.0}


def test_heading_quaternion_turns_the_bow_clockwise_from_north():
    for hdg, expected in ((0.0, (0.0, 1.0)), (90.0, (1.0, 0.0)), (225.0, (-math.sqrt(0.5), -math.sqrt(0.5)))):
        w, _, _, z = V.heading_wxyz(hdg)
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
        assert V.attitude_wxyz(hdg, 0.0) == pytest.approx(V.heading_wxyz(hdg), abs=1e-15)
    q = V.attitude_wxyz(90.0, 10.0)
    assert sum(c * c for c in q) == pytest.approx(1.0)
    s10, c10 = math.sin(math.radians(10.0)), math.cos(math.radians(10.0))
    assert _rotate(q, (0, 1, 0)) == pytest.approx((1.0, 0.0, 0.0), abs=1e-12)  # bow east
    assert _rotate(q, (1, 0, 0)) == pytest.approx((0.0, -c10, -s10), abs=1e-12)  # starboard side south, down
    assert _rotate(q, (0, 0, 1)) == pytest.approx((0.0, -s10, c10), abs=1e-12)  # mast leans to starboard
    # heel to port lifts the starboard side
    assert _rotate(V.attitude_wxyz(0.0, -5.0), (1, 0, 0))[2] == pytest.approx(math.sin(math.radians(5.0)))


def test_viewer_places_the_own_ship_heeled_by_the_state_roll():
    """The ship node takes the state's heading and roll_deg; a state without roll (3-DOF ship) is upright."""
    from types import SimpleNamespace

    from vessel_gym.ui.view3d import Viewer3D

    viewer = Viewer3D.__new__(Viewer3D)  # the placement only needs the ship nodes
    frame = SimpleNamespace(position=None, wxyz=None)
    viewer._ships = {0: frame}
    viewer._place(0, {"x_m": 10.0, "y_m": 20.0, "hdg_deg": 45.0, "roll_deg": -7.89})
    assert frame.position == (20.0, 10.0, 0.0)
    assert frame.wxyz == pytest.approx(V.attitude_wxyz(45.0, -7.89))
    viewer._place(0, {"x_m": 10.0, "y_m": 20.0, "hdg_deg": 45.0})
    assert frame.wxyz == pytest.approx(V.heading_wxyz(45.0))
    assert "| Heel | -7.9°" in viewer._hud_text.__func__(
        SimpleNamespace(link=SimpleNamespace(owner=None, helm=False, scene=None, events=[])),
        {"roll_deg": -7.89, "hdg_deg": 45.0},
    )


def test_wave_number_limits_of_linear_theory():
    omega = 2.0 * math.pi / 8.0
    # deep water: wavelength g T^2 / (2 pi) = 99.89 m for T = 8 s
    assert 2.0 * math.pi / V.wave_number(omega, 1e4) == pytest.approx(99.89, abs=0.01)
    # shallow water: celerity omega / k -> sqrt(g h) (h = 0.5 m: 2.21 m/s), within 1 % at kh ~ 0.18
    k = V.wave_number(omega, 0.5)
    assert omega / k == pytest.approx(math.sqrt(9.80665 * 0.5), rel=0.01)
    h = 10.0
    assert omega**2 == pytest.approx(
        9.80665 * V.wave_number(omega, h) * math.tanh(V.wave_number(omega, h) * h)
    )


def test_sea_surface_has_the_significant_wave_height():
    x, y = np.meshgrid(np.linspace(0, 2000, 400), np.linspace(0, 2000, 400))
    z = V.sea_elevation(x.ravel(), y.ravel(), 3.0, 2.0, 8.0, 45.0, 50.0)
    assert 4.0 * np.std(z) == pytest.approx(2.0, rel=0.05)  # Hs = 4 sigma
    assert not np.any(V.sea_elevation(x.ravel(), y.ravel(), 3.0, 0.0, 8.0, 45.0, 50.0))  # calm: flat
    later = V.sea_elevation(x.ravel(), y.ravel(), 4.0, 2.0, 8.0, 45.0, 50.0)
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
    assert "loopback" in capsys.readouterr().err


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


@pytest.mark.slow
def test_page_in_headless_chromium_draws_the_ship_moving(tmp_path):
    if chromium_path() is None:
        pytest.skip("chromium is not installed (Debian package chromium)")
    pytest.importorskip("viser")
    pytest.importorskip("websockets")
    pytest.importorskip("PIL")
    env = {**os.environ, "PYTHONPATH": f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    udp, http = _free_port(socket.SOCK_DGRAM), _free_port()
    py = [sys.executable, "-m", "vessel_gym.cli"]
    procs = []
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
                    "120",
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
                    "110",
                ],
                env=env,
                stdout=open(tmp_path / "view3d.log", "w"),
                stderr=subprocess.STDOUT,
            )
        )
        url = f"http://127.0.0.1:{http}/"
        deadline = time.monotonic() + 90
        while True:
            try:
                with urllib.request.urlopen(url, timeout=2) as r:
                    assert r.status == 200
                if f"open {url}" in (tmp_path / "view3d.log").read_text():  # the URL is printed
                    break
                raise ConnectionError("not printed yet")
            except OSError:
                assert all(p.poll() is None for p in procs), (tmp_path / "view3d.log").read_text()
                assert time.monotonic() < deadline, "the page was not served within 90 s"
                time.sleep(0.5)
        with Chromium() as browser:
            browser.call("Page.navigate", url=url)
            first = None
            for i in range(30):  # the scene and the first states arrive within seconds
                browser.pump(1.0)
                shot = browser.screenshot(str(tmp_path / f"wait{i}.png"))
                n, c = _ship_pixels(shot)
                if n >= 12:
                    first = (n, c)
                    break
            assert first is not None, f"no ship drawn; screenshots in {tmp_path}"
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
        totals = (tmp_path / "serve.log").read_text()
        assert "helm takeovers 1;" in totals, totals
        assert errors == []
        assert n2 >= 12
        moved_px = math.hypot(c2[0] - first[1][0], c2[1] - first[1][1])
        assert moved_px > 3.0, f"ship did not move between screenshots ({moved_px:.1f} px); see {tmp_path}"
    finally:
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
    assert frame.wxyz == pytest.approx(V.attitude_wxyz(st["hdg_deg"], st["roll_deg"]))
    # the starboard side (ship node +x) is up: heeled to port
    assert _rotate(frame.wxyz, (1, 0, 0))[2] == pytest.approx(math.sin(math.radians(-st["roll_deg"])), abs=1e-9)
