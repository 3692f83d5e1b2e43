"""The 3D page for the served tasks: the thruster and tug controls of the link client and the page (unit level,
then the real page in headless chromium on a served Berthing-v0), the fenders coloured by load, the route."""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
import signal
import socket
import subprocess
import sys
import time
import urllib.request

import pytest

from vessel_gym.net import protocol as P
from vessel_gym.ui import view3d as V
from vessel_gym.ui.chart import fender_colour
from vessel_gym.ui.view3d_tasks import AssistControls, TaskScene, hud_rows, outcome_figures

from .chromium import Chromium, chromium_path
from .helpers import make_reading
from .test_view3d import ROOT, _free_port

UNITS = (P.AssistUnit("bow_thruster", "thruster"), P.AssistUnit("stern_tug", "tug"))


def _welcome(addr, server):
    limits = P.Limits(assist=UNITS)
    server.sendto(P.encode_welcome(1, "helm", 20.0, False, limits, 1.0, 3.0, "hold", "c", "s1"), addr)


def test_link_client_orders_the_units_the_welcome_names_from_the_orders_in_force():
    server = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    server.bind(("127.0.0.1", 0))
    link = V.LinkClient(server.getsockname(), 20.0, "t", None)
    try:
        link.poll(0.0)
        _hello, addr = server.recvfrom(4096)
        _welcome(addr, server)
        extras = P.StateExtras(
            (
                P.AssistReading("bow_thruster", "thruster", 0.5, 0.4),
                P.AssistReading("stern_tug", "tug", -0.25, 0.0),
            )
        )
        server.sendto(P.encode_state(4, make_reading(), False, extras=extras)[0], addr)
        time.sleep(0.02)
        link.poll(0.1)
        assert link.assist_units() == [("bow_thruster", "thruster"), ("stern_tug", "tug")]
        link.set_assist(0, 1.0)
        assert link.assist == [0.0, 0.0]  # no orders before the helm is taken
        link.take_helm()
        assert link.assist == [0.5, -0.25]  # from the orders in force
        link.set_assist(1, -7.0)
        link.set_assist(0, float("nan"))
        assert link.assist == [0.5, -1.0]
        server.settimeout(1.0)
        link.poll(1.0)
        helm = None
        for _ in range(4):
            m = json.loads(server.recv(4096))
            if m["type"] == "helm":
                helm = m
                break
        assert helm is not None and helm["assist"] == [0.5, -1.0]
        # what the server makes of it: a valid full order for a ship with these units
        assert P.parse_datagram(json.dumps(helm).encode(), P.Limits(assist=UNITS)).assist == (0.5, -1.0)
    finally:
        link.close()
        server.close()


class _Handle:
    def __init__(self, label=""):
        self.label = label
        self.removed = False
        self.color = None
        self.cb = None

    def on_click(self, f):
        self.cb = f

    on_trigger = on_click

    def remove(self):
        self.removed = True


class _Gui:
    def __init__(self):
        self.made: list[_Handle] = []

    def _add(self, label, **_kw):
        self.made.append(_Handle(label))
        return self.made[-1]

    add_button = add_command = add_markdown = _add


class _Link:
    def __init__(self, units):
        self.units = units
        self.helm = False
        self.assist = [0.0] * len(units)

    def assist_units(self):
        return self.units

    def set_assist(self, j, o):
        self.assist[j] = max(-1.0, min(1.0, o))


def test_controls_step_the_orders_only_with_the_helm_and_follow_the_units():
    gui, link = _Gui(), _Link([("bow_thruster", "thruster"), ("stern_thruster", "thruster")])
    c = AssistControls(gui, link)
    c.sync()
    starboard = c.buttons["bow_thruster to starboard"]
    starboard.cb(None)
    assert link.assist == [0.0, 0.0]  # a watcher's click moves nothing
    link.helm = True
    for _ in range(5):
        starboard.cb(None)
    c.buttons["stern_thruster to port"].cb(None)
    assert link.assist == [1.0, -0.25]
    c.buttons["zero"].cb(None)
    assert link.assist == [0.0, 0.0]
    made = list(gui.made)
    link.units = [("tug_1", "tug")]
    c.sync()
    assert all(h.removed for h in made) and "tug_1 to starboard" in c.buttons
    st = {
        "assist": [{"name": "tug_1", "kind": "tug", "order": 0.5, "delivered": 0.25}],
        "fender_load": [0.1, 0.7],
    }
    link.assist = [0.5]
    rows = hud_rows(st, link)
    assert rows == [
        "| tug_1 | order +0.50 (you +0.50), delivers +0.25 |",
        "| Fenders | fender 2 at 70 % of rated |",
    ]


def test_outcome_events_show_the_tasks_figures():
    colreg = {"event": "outcome", "outcome": "success", "colreg_score": 0.88, "colreg_violations": 1}
    assert outcome_figures(colreg) == ": COLREG score 0.88, 1 in violation"
    berth = {"event": "outcome", "contact_speed_m_s": 0.07, "max_fender_energy_fraction": 0.42}
    assert outcome_figures(berth) == ": contact 0.07 m/s, fender max 42 % of rated"
    assert outcome_figures({"event": "outcome", "path_m": 3.0, "colreg_score": "x"}) == ""


def test_fenders_are_drawn_and_recoloured_by_load_and_the_route_as_a_line():
    class Scene:
        def __init__(self):
            self.meshes, self.lines = [], []

        def add_mesh_simple(self, name, v, f, **kw):
            self.meshes.append((name, v, kw))
            return _Handle(name)

        def add_line_segments(self, name, segs, colour, **kw):
            self.lines.append((name, segs))

    quad = [[100.0, 10.0], [100.0, 12.0], [102.0, 12.0], [102.0, 10.0]]
    feats = [{"kind": "fender", "points": quad}, {"kind": "fender", "points": quad}]
    feats.append({"kind": "route", "points": [[0.0, 0.0], [1000.0, 0.0]]})
    sc, ts = Scene(), TaskScene()
    ts.build(sc, feats, T=5.0, L=76.0)
    assert len(sc.meshes) == 2 and len(sc.lines) == 1
    name, v, kw = sc.meshes[0]
    assert kw["color"] == fender_colour(0.0) and v[:, 2].min() < 0.0 < v[:, 2].max()
    assert sorted(set(v[:, 0].round(3))) == [10.0, 12.0]  # scene x is the chart's east
    ts.update({"fender_load": [0.01, 1.3]})  # the first changed by less than FENDER_RECOLOUR
    assert ts.fenders[0].color is None and ts.fenders[1].color == fender_colour(1.3) != fender_colour(1.0)


@contextlib.contextmanager
def _served_page(tmp_path, env_id: str, camera: str, time_factor: str):
    """serve --env ENV_ID and view3d on free ports; yields the page's helm URL and the two processes."""
    if chromium_path() is None:
        pytest.skip("chromium is not installed (Debian package chromium)")
    pytest.importorskip("viser")
    pytest.importorskip("websockets")
    env = {**os.environ, "PYTHONPATH": f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    udp, http = _free_port(socket.SOCK_DGRAM), _free_port()
    py = [sys.executable, "-m", "vessel_gym.cli"]
    procs = []
    try:
        serve = ["serve", "--env", env_id, "--json", f"127.0.0.1:{udp}", "--nmea", "off"]
        serve += ["--time-factor", time_factor, "--duration", "400", "--seed", "1"]
        log = open(tmp_path / "serve.log", "w")
        procs.append(subprocess.Popen(py + serve, env=env, stdout=log, stderr=subprocess.STDOUT))
        view = ["view3d", "--server", f"127.0.0.1:{udp}", "--http", f"127.0.0.1:{http}", "--camera", camera]
        out, err = open(tmp_path / "view3d.log", "w"), open(tmp_path / "view3d.err", "w")
        procs.append(subprocess.Popen(py + view + ["--duration", "390"], env=env, stdout=out, stderr=err))
        url = f"http://127.0.0.1:{http}/"
        deadline = time.monotonic() + 90
        while True:
            found = re.search(
                rf"open ({re.escape(url)}helm/[A-Za-z0-9_-]+) ", (tmp_path / "view3d.log").read_text()
            )
            if found:
                with urllib.request.urlopen(found.group(1), timeout=5) as r:
                    assert r.status == 200
                break
            assert all(p.poll() is None for p in procs), (tmp_path / "view3d.err").read_text()
            assert time.monotonic() < deadline, "the page was not served within 90 s"
            time.sleep(0.5)
        yield found.group(1), procs
    finally:
        for p in procs:
            p.terminate()
        for p in procs:
            try:
                p.wait(15)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def test_channel_page_in_headless_chromium_draws_the_target_ships(tmp_path):
    """A served CollisionAvoidanceChannel-v0 in the real page: the waters' name in the HUD and the target ships
    drawn in the traffic's orange (the harbour camera over the whole scheme, kilometres across: the clip planes
    follow the scene's size)."""
    Image = pytest.importorskip("PIL.Image")
    import numpy as np

    with _served_page(tmp_path, "vessel_gym/CollisionAvoidanceChannel-v0", "harbour", "20") as (
        helm_url,
        procs,
    ):
        with Chromium() as browser:
            browser.call("Page.navigate", url=helm_url)
            for _ in range(360):  # serve's first start compiles its kernels (minutes on a loaded machine)
                browser.pump(0.5)
                if "colreg_tss" in browser.text() and "Heading" in browser.text():
                    break
            assert "colreg_tss" in browser.text(), (tmp_path / "serve.log").read_text()
            orange = 0
            for i in range(10):
                browser.pump(1.0)
                shot = browser.screenshot(str(tmp_path / f"channel{i}.png"))
                im = np.asarray(Image.open(io.BytesIO(shot)).convert("RGB")).astype(int)[:, :940]
                r, g, b = im[..., 0], im[..., 1], im[..., 2]
                mask = (r > 170) & (g > 90) & (g < 190) & (b < 90)
                mask[:200, :330] = False  # the software-WebGL notice
                orange = int(mask.sum())
                if orange >= 4:
                    break
            assert orange >= 4, f"no target ship drawn; screenshots in {tmp_path}"
            assert browser.errors() == []
        assert (tmp_path / "view3d.err").read_text() == ""


def test_berthing_page_in_headless_chromium_orders_the_bow_thruster(tmp_path):
    """A served Berthing-v0 in the real page: the scene is drawn (screenshot not blank), the helm URL's page shows the thruster buttons; after H (taking the pilot's orders in force), 0
    (every unit to 0), two clicks on "bow_thruster to starboard" and the X key, the state echoes the bow
    thruster's order +0.75 from the server."""
    Image = pytest.importorskip("PIL.Image")
    import numpy as np

    with _served_page(tmp_path, "vessel_gym/Berthing-v0", "top-down", "2") as (helm_url, procs):
        with Chromium() as browser:
            browser.call("Page.navigate", url=helm_url)
            text = ""
            for _ in range(360):  # serve's first start compiles its kernels (minutes on a loaded machine)
                browser.pump(0.5)
                text = browser.text()
                if "bow_thruster to starboard" in text and "Heading" in text and "bow_thruster\t" in text:
                    break
            assert "bow_thruster to starboard" in text, (text, (tmp_path / "serve.log").read_text())
            browser.pump(2.0)
            shot = browser.screenshot(str(tmp_path / "berthing.png"))
            im = np.asarray(Image.open(io.BytesIO(shot)).convert("RGB"))
            assert im.shape[0] > 100 and len(np.unique(im[:, :900].reshape(-1, 3), axis=0)) > 50  # not blank
            browser.press("h", "KeyH", 72)
            for _ in range(20):
                browser.pump(0.5)
                if "YOU" in browser.text():
                    break
            assert "YOU" in browser.text()
            browser.press("0", "Digit0", 48)  # from the pilot's orders in force to 0
            browser.pump(0.3)
            click = (
                """[...document.querySelectorAll('button')].find(b => b.innerText.trim() === '%s').click()"""
            )
            for _ in range(2):
                browser.call("Runtime.evaluate", expression=click % "bow_thruster to starboard")
                browser.pump(0.3)
            browser.press("x", "KeyX", 88)
            echoed = ""
            for _ in range(30):
                browser.pump(0.5)
                m = re.search(
                    r"bow_thruster\s+order ([+-]\d\.\d\d) \(you ([+-]\d\.\d\d)\), delivers ([+-]\d\.\d\d)",
                    browser.text(),
                )
                if m and m.group(1) == "+0.75":
                    echoed = m.group(0)
                    break
            assert echoed, browser.text()
            errors = browser.errors()
        procs[0].send_signal(signal.SIGINT)
        procs[0].wait(30)
        log = (tmp_path / "serve.log").read_text()
        assert "thrusters/tugs on the helm: bow_thruster (thruster), stern_thruster (thruster)" in log
        assert "helm takeovers 1;" in log, log
        assert errors == []
        assert (tmp_path / "view3d.err").read_text() == ""
