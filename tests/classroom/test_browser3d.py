"""The student's 3D view in headless Chromium (WebGL through SwiftShader, no GPU): the harbour, the own ship
and the sea are drawn from the scene the server built with the 3D viewer's scene code, the other ships where
their AIS reports put them, and the own ship turns in it when the student steers; the toggle chart / 3D and
the phone width."""

from __future__ import annotations

import io
import math
import time

import numpy as np
import pytest
from net.chromium import Chromium, chromium_path

from .test_browser import js, open_and_join, wait_for

pytestmark = pytest.mark.slow


def _canvas_pixels(b: Chromium, png: bytes, element: str) -> np.ndarray:
    """The screenshot's pixels (h, w, 3) inside ``element``'s box."""
    from PIL import Image

    box = js(b, f"(() => {{ const r = document.getElementById('{element}').getBoundingClientRect(); "
                "return [r.left, r.top, r.right, r.bottom]; })()")  # fmt: skip
    img = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.int16)
    x0, y0, x1, y1 = (int(round(v)) for v in box)
    return img[y0 + 1 : y1 - 1, x0 + 1 : x1 - 1]


def _red(px: np.ndarray) -> np.ndarray:
    """The own ship's hull (COLOURS["own"] = 200, 40, 30, lit from 55 % to full)."""
    r, g, b = px[..., 0], px[..., 1], px[..., 2]
    return (r > 100) & (r > 3 * g) & (r > 3 * b)


def test_the_3d_view_draws_the_harbour_and_the_own_ship_turns_in_it(room, tmp_path):
    if chromium_path() is None:
        pytest.skip("chromium is not installed (Debian package chromium)")
    pytest.importorskip("PIL")
    r = room(ships=2, time_factor=2.0)
    url = f"http://127.0.0.1:{r.port}/"
    h = r.harbour
    with Chromium(1200, 800) as ann, Chromium(390, 844) as bob:
        open_and_join(ann, url, r.codes.helm[0], "Ann")
        open_and_join(bob, url, r.codes.helm[1], "Bob")
        # a WebGL context, drawing: both views side by side on a wide screen
        assert js(ann, "vg.view") == "both"
        assert js(ann, "!!vg.view3d && !!vg.view3d.gl && vg.view3d.gl.getParameter(vg.view3d.gl.VERSION)")
        wait_for(ann, "vg.view3d.frames > 3 && vg.view3d.own !== null && vg.view3d.others.length >= 3")
        assert js(ann, "vg.view3d.scene.meshes.length") >= 5  # sea bed, land, breakwaters, quays, goal area
        chart_box = js(ann, "document.getElementById('chart').getBoundingClientRect().right")
        assert js(ann, "document.getElementById('view3d').getBoundingClientRect().left") >= chart_box
        ann.pump(0.5)
        png0 = ann.screenshot(str(tmp_path / "ann3d_0.png"))
        px0 = _canvas_pixels(ann, png0, "view3d")
        assert px0.shape[0] > 200 and px0.shape[1] > 300
        colours = len(np.unique(px0.reshape(-1, 3) // 8, axis=0))
        assert colours > 30, colours  # not a blank canvas: shaded hull, land, sea, sky
        red0 = _red(px0)
        assert red0.sum() > 300, red0.sum()  # the own ship seen from the chase camera, large
        # the own ship is drawn where the state puts it: its projected deck is red
        cx, cy = js(
            ann,
            "(() => { const o = vg.view3d.own; return vg.view3d.project(o.x, o.y, vg.view3d.scene.deck_z); })()",
        )
        assert red0[max(0, int(cy) - 3) : int(cy) + 4, max(0, int(cx) - 3) : int(cx) + 4].any()
        # the others are drawn at their AIS positions
        ais, drawn = js(ann, "[vg.state.ais.map(a => [a.e, a.n]), vg.view3d.others.map(o => [o.x, o.y])]")
        assert ais == drawn and len(drawn) >= 3  # read at one time: a state may come between two reads
        # steer: hard to starboard and ahead; the ship turns in the 3D view as in the physics
        hdg0 = js(ann, "vg.view3d.own.hdg")
        for _ in range(7):
            ann.press("ArrowRight", "ArrowRight", 39)
            ann.pump(0.06)
        ann.press("ArrowUp", "ArrowUp", 38)
        wait_for(ann, "vg.state.own.rudder_order_deg === 35")
        deadline = time.monotonic() + 40.0
        while time.monotonic() < deadline:
            ann.pump(0.5)
            turned = ((js(ann, "vg.view3d.own.hdg") - hdg0 + 180.0) % 360.0) - 180.0
            if turned > 20.0:
                break
        assert turned > 20.0, turned
        true_hdg = r.srv.call(lambda: math.degrees(float(h.sim.heading[0])) % 360.0)
        assert abs(((js(ann, "vg.view3d.own.hdg") - true_hdg + 180.0) % 360.0) - 180.0) < 10.0
        ann.pump(0.3)
        png1 = ann.screenshot(str(tmp_path / "ann3d_1.png"))
        px1 = _canvas_pixels(ann, png1, "view3d")
        assert _red(px1).sum() > 300  # the chase camera keeps the ship in view
        # the harbour swung round it: count the pixels that changed clearly (> 96 levels over R+G+B); a mean over
        # the canvas would mostly measure how much of it is uniform sky and sea (~3 levels here for a 20 deg turn)
        changed = (np.abs(px1 - px0).sum(axis=2) > 96).mean()
        assert changed > 0.01, changed  # 3.7 % measured after a 20 deg turn
        # the harbour camera: the whole harbour from above, the ship where the physics has it
        js(ann, "document.getElementById('cam3d').value = 'harbour'; "
                "document.getElementById('cam3d').dispatchEvent(new Event('change')); true")  # fmt: skip
        wait_for(ann, "vg.view3d.camera === 'harbour'")
        # the toggle: the 3D view alone, then the chart alone
        js(ann, "document.getElementById('b_view').click(); true")
        assert js(ann, "vg.view") == "chart"
        assert js(ann, "document.getElementById('view3d').classList.contains('hidden')")
        js(ann, "document.getElementById('b_view').click(); true")
        assert js(ann, "vg.view") == "3d"
        assert js(ann, "document.getElementById('chart').classList.contains('hidden')")
        # a phone: the chart first, the 3D view on the V key, nothing off the side
        assert js(bob, "vg.view") == "chart"
        bob.press("v", "KeyV", 86)
        wait_for(bob, "vg.view === '3d' && vg.view3d.frames > 2")
        bob.pump(0.5)
        assert js(bob, "document.documentElement.scrollWidth") <= 390
        pxb = _canvas_pixels(bob, bob.screenshot(str(tmp_path / "bob3d.png")), "view3d")
        assert _red(pxb).sum() > 50 and len(np.unique(pxb.reshape(-1, 3) // 8, axis=0)) > 20
        for b in (ann, bob):
            assert not b.errors(), b.errors()
            assert not js(b, "vg.errors"), js(b, "vg.errors")
