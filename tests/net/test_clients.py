"""pygame helm panel and viewer: panel logic, off-screen rendering, and headless runs against a live link."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from vessel_gym.net import protocol as P
from vessel_gym.net.link import LinkConfig, UdpLink

from .helpers import Peer, make_reading, moved

pytest.importorskip("pygame")

from vessel_gym.ui import panels  # noqa: E402  (after the pygame check)


class ServedLink:
    """A UdpLink serviced at 50 Hz on wall-clock time in a background thread, the ship moving north-east."""

    def __init__(self, **config) -> None:
        config.setdefault("json_bind", ("127.0.0.1", 0))
        config.setdefault("nmea_destinations", ())
        self.link = UdpLink(LinkConfig(**config))
        self.helm_states: list = []
        self.targets = [
            P.Target(
                id=7,
                name="PILOT BOAT",
                reading=make_reading(x_m=600.0, y_m=-250.0),
                length_m=20.0,
                beam_m=6.0,
            )
        ]
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, daemon=True)

    def _loop(self) -> None:
        start = time.monotonic()
        base = make_reading(x_m=0.0, y_m=0.0, hdg_deg=45.0, cog_deg=45.0, sog_kn=10.0)
        while not self._stop.is_set():
            now = time.monotonic() - start
            d = now * 10.0 * 1852.0 / 3600.0 / 2**0.5
            helm = self.link.service(now, moved(base, t_s=now, x_m=d, y_m=d), self.targets)
            self.helm_states.append(helm)
            time.sleep(0.02)

    def __enter__(self) -> ServedLink:
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        self._thread.join(5.0)
        self.link.close()


def _non_blank(frame: np.ndarray) -> bool:
    return frame.ndim == 3 and frame.shape[2] == 3 and len(np.unique(frame.reshape(-1, 3), axis=0)) > 20


# -- panel logic ----------------------------------------------------------------------------------------------


def test_helm_panel_keys_and_limits():
    panel = panels.HelmPanel(max_rudder_deg=35.0)
    panel.handle_key("right")  # a watcher's keys change nothing
    assert (panel.active, panel.rudder_order_deg) == (False, 0.0)
    panel.handle_key("t")
    assert panel.active and not panel.ready  # orders sync from the next state before they are sent
    for _ in range(3):
        panel.handle_key("right")
    assert panel.rudder_order_deg == 15.0
    for _ in range(20):
        panel.handle_key("left")
    assert panel.rudder_order_deg == -35.0
    panel.handle_key("0")
    assert panel.rudder_order_deg == 0.0
    for _ in range(9):
        panel.handle_key("up")
    assert panel.telegraph == 4
    for _ in range(12):
        panel.handle_key("down")
    assert panel.telegraph == -4
    panel.handle_key("x")
    assert (panel.rudder_order_deg, panel.telegraph) == (0.0, -4)
    panel.handle_key("w")
    panel.handle_key("up")
    assert not panel.active and panel.telegraph == -4


def test_panel_syncs_once_from_state_for_a_bumpless_takeover():
    panel = panels.HelmPanel()
    panel.sync({"rudder_order_deg": -15.0, "telegraph": 3})
    assert panel.ready and (panel.rudder_order_deg, panel.telegraph) == (-15.0, 3)
    panel.sync({"rudder_order_deg": 5.0, "telegraph": 0})
    assert (panel.rudder_order_deg, panel.telegraph) == (-15.0, 3)


def test_render_frame_array_draws_state_and_waiting_screen():
    (data,) = P.encode_state(
        1, make_reading(), True, [P.Target(1, "TUG", make_reading(x_m=1500.0), 30.0, 10.0)]
    )
    state = P.parse_server_datagram(data)
    frame = panels.render_frame_array(state, track=[(1000.0, -900.0), (1234.5, -789.0)], size=(640, 400))
    assert frame.shape == (400, 640, 3) and frame.dtype == np.uint8
    assert _non_blank(frame)
    waiting = panels.render_frame_array(None, size=(640, 400))
    assert waiting.shape == (400, 640, 3)
    assert not np.array_equal(frame, waiting)


def test_render_survives_nulls_and_junk_values():
    state = {
        "type": "state",
        "x_m": None,
        "hdg_deg": "north",
        "targets": [None, {"x_m": 1.0}],
        "telegraph": 99,
    }
    assert panels.render_frame_array(state, size=(320, 200)).shape == (200, 320, 3)
    state = {"x_m": 0.0, "y_m": 0.0, "hdg_deg": None, "targets": [{"x_m": 1.0, "y_m": 2.0, "hdg_deg": 3.0}]}
    assert panels.render_frame_array(state, size=(320, 200)).shape == (200, 320, 3)


# -- headless runs against a live link ------------------------------------------------------------------------


def test_helm_panel_takes_the_helm_and_steers():
    pressed = []

    def press(frame, panel, conn):
        if frame == 10:
            assert served.helm_states[-1].owner is None  # the panel opened as a watcher
            assert not conn.helm_sent
            panel.handle_key("t")
        if panel.ready and not pressed:
            panel.handle_key("right")
            panel.handle_key("right")  # -15 (synced from the state) + 10
            panel.handle_key("up")  # telegraph 3 -> 4
            pressed.append(frame)

    with ServedLink() as served:
        result = panels.run_helm(
            served.link.json_address,
            name="test-helm",
            max_frames=45,
            fps=60.0,
            headless=True,
            size=(640, 400),
            capture=True,
            on_frame=press,
        )
        time.sleep(0.1)
        final = served.link.helm
    assert result.frames == 45
    assert result.states_received > 5 and result.helm_sent > 5
    assert result.panel.ready and pressed
    assert result.owned_helm
    assert result.last_state["type"] == "state" and result.last_state["targets"][0]["name"] == "PILOT BOAT"
    assert len(result.track) >= 2  # the ship moved
    assert _non_blank(result.last_frame)
    assert any(h.helm_ok and h.rudder_order_deg == -5.0 and h.telegraph == 4 for h in served.helm_states)
    # the panel said bye on exit: the helm was released with the "hold" failsafe
    assert final.owner is None and final.failsafe and final.rudder_order_deg == -5.0
    assert served.link.stats()["helm_released"] == 1


def test_viewer_runs_for_a_duration():
    with ServedLink() as served:
        result = panels.run_viewer(
            served.link.json_address, duration_s=0.6, fps=30.0, headless=True, size=(480, 320), capture=True
        )
        time.sleep(0.1)  # let the link read the bye
        stats = served.link.stats()
    assert 5 <= result.frames <= 20  # 30 fps for 0.6 s, fewer on a busy machine
    assert result.states_received >= 5 and result.helm_sent == 0
    assert _non_blank(result.last_frame)
    assert stats["clients_joined"] == 1 and stats["clients_left"] == 1
    assert stats["helm_takeovers"] == 0


def test_listen_only_viewer_fed_by_static_destination():
    listener = Peer()
    address = listener.address
    listener.close()
    with ServedLink(json_static_destinations=[address], static_rate_hz=20.0) as served:
        result = panels.run_viewer(
            served.link.json_address, listen=address, max_frames=20, fps=40.0, headless=True, size=(320, 240)
        )
        stats = served.link.stats()
    assert result.states_received >= 5
    assert stats["rx_datagrams"] == 0  # it never said anything
