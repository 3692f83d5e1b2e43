"""Protocol v2: scene, particulars, event and helm_owner messages; v1 clients unaffected."""

from __future__ import annotations

import time

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401
from vessel_gym.net import protocol as P
from vessel_gym.net.link import LinkConfig, UdpLink
from vessel_gym.net.wrapper import UdpLinkWrapper
from vessel_gym.physics.environment import Environment
from vessel_gym.scenarios import load_scenario
from vessel_gym.scenarios.geometry import hull_outline

from .helpers import make_reading

SETTLE_S = 0.003
ENV = Environment(
    wind_speed_m_s=10.0, wind_from_deg=270.0, current_speed_m_s=0.5, current_to_deg=90.0, Hs_m=1.2
)


def _parse_all(datagrams):
    return [P.parse_server_datagram_v2(d) for d in datagrams]


@pytest.mark.parametrize("max_bytes", [P.MAX_STATE_DATAGRAM_BYTES, 560])
def test_scenario_round_trip_through_parts(max_bytes):
    sc = load_scenario("harbour")
    datagrams = P.encode_scenario(7, sc, ENV, max_bytes=max_bytes)
    assert all(len(d) <= max_bytes for d in datagrams)
    if max_bytes == 560:
        assert len(datagrams) > 3  # split, polygons included
    msgs = _parse_all(datagrams)
    assert [m["part"] for m in msgs] == list(range(len(msgs)))
    assert {m["parts"] for m in msgs} == {len(msgs)} and {m["seq"] for m in msgs} == {7}
    asm = P.SceneAssembler()
    out = [asm.add(m) for m in reversed(msgs)]  # arrival order does not matter
    scene = out[-1]
    assert all(o is None for o in out[:-1]) and scene is not None
    expected = P.scenario_features(sc)
    got = sorted(scene["features"], key=lambda f: f["id"])
    assert [{k: v for k, v in f.items() if k != "id"} for f in got] == expected
    kinds = [f["kind"] for f in got]
    assert kinds.count("land") == len(sc.land) and kinds.count("breakwater") == len(sc.breakwater)
    assert kinds.count("quay") == len(sc.quay) and kinds.count("depth") == len(sc.depth_area)
    assert kinds.count("goal") == 1
    land = next(f for f in got if f["kind"] == "land")
    assert land["points"] == [[round(x, 2), round(y, 2)] for x, y in sc.land[0].points]
    assert scene["ref_lat_deg"] == pytest.approx(sc.reference_latlon_deg[0])
    assert scene["bounds_m"] == [pytest.approx(b) for b in sc.bounds_m]
    sea = scene["sea"]
    assert sea["wind_speed_kn"] == pytest.approx(10.0 / 0.514444, abs=0.01)  # 1 kn = 1852/3600 m/s
    assert sea["wind_from_deg"] == 270.0 and sea["hs_m"] == 1.2 and sea["current_to_deg"] == 90.0


def test_long_polygon_is_split_and_joined_again():
    sc = load_scenario("harbour")
    ring = [(1000.0 * np.cos(a), 1000.0 * np.sin(a)) for a in np.linspace(0, 2 * np.pi, 400, endpoint=False)]
    big = type(sc.land[0])(name="island", points=tuple(ring))
    sc2 = type(sc).__new__(type(sc))
    sc2.__dict__.update(sc.__dict__)
    object.__setattr__(sc2, "land", (big,))
    datagrams = P.encode_scenario(1, sc2, None)
    assert len(datagrams) >= 4 and all(len(d) <= P.MAX_STATE_DATAGRAM_BYTES for d in datagrams)
    asm = P.SceneAssembler()
    scene = [asm.add(m) for m in _parse_all(datagrams)][-1]
    island = next(f for f in scene["features"] if f["kind"] == "land")
    assert island["points"] == [[round(x, 2), round(y, 2)] for x, y in ring]


def test_open_water_scene_has_no_features():
    (d,) = P.encode_scenario(3, None, ENV)
    m = P.parse_server_datagram_v2(d)
    assert (
        m["features"] == []
        and m["parts"] == 1
        and m["sea"]["current_speed_kn"] == pytest.approx(0.97, abs=0.01)
    )


def test_particulars_event_and_helm_owner_round_trip():
    d = P.encode_particulars(5, P.ShipParticulars(0, "KVLCC2", 320.0, 58.0, 20.8))
    m = P.parse_server_datagram_v2(d)
    assert len(d) <= P.MAX_STATE_DATAGRAM_BYTES
    assert m["own"] is True and m["length_m"] == 320.0 and m["beam_m"] == 58.0 and m["draught_m"] == 20.8
    assert m["outline_m"] == [list(p) for p in hull_outline(320.0, 58.0)]
    with pytest.raises(ValueError, match="does not fit"):
        P.encode_particulars(5, P.ShipParticulars(1, "X", 10, 2, 1, tuple((i, i) for i in range(200))))
    e = P.parse_server_datagram_v2(
        P.encode_event(9, "outcome", 123.456, 2, outcome="success", path_m=812.345)
    )
    assert (e["event"], e["t_s"], e["episode"], e["outcome"], e["path_m"]) == (
        "outcome",
        123.456,
        2,
        "success",
        812.35,
    )
    with pytest.raises(ValueError):
        P.encode_event(9, "explosion", 0.0, 1)
    h = P.parse_server_datagram_v2(P.encode_helm_owner(10, "panel-A", True, "takeover"))
    assert (h["owner"], h["you"], h["reason"]) == ("panel-A", True, "takeover")


def test_v1_reader_rejects_v2_messages_and_v2_reader_reads_v1():
    for d in (P.encode_helm_owner(1, None, False, "watchdog"), P.encode_scenario(1, None)[0]):
        with pytest.raises(P.ProtocolError) as err:
            P.parse_server_datagram(d)
        assert err.value.reason == "bad_version"
    (state,) = P.encode_state(4, make_reading(), True)
    assert P.parse_server_datagram_v2(state)["type"] == "state"
    for bad in (
        b'{"v":2,"type":"state"}',
        b'{"v":1,"type":"scenario"}',
        b'{"v":2,"type":"scenario","part":2,"parts":1,"features":[]}',
    ):
        with pytest.raises(P.ProtocolError):
            P.parse_server_datagram_v2(bad)


def test_hello_proto_field():
    assert P.parse_datagram(P.encode_hello("viewer", 10, proto=2)).proto == 2
    assert P.parse_datagram(P.encode_hello("viewer", 10)).proto == 1
    assert b"proto" not in P.encode_hello("viewer", 10)  # a v1 hello is byte-for-byte what it was
    assert P.parse_datagram(b'{"v":1,"type":"hello","role":"viewer","proto":7}').proto == 2


def _hello2(peer, to, role="viewer", rate=None):
    """A v2 hello echoing the peer's cookie and session."""
    peer._read()
    peer.send(to, P.encode_hello(role, rate, cookie=peer.cookie, session=peer.session, proto=2))


def _join2(peer, to, pump, role="viewer", rate=None):
    """The link's handshake (hello, cookie, hello with it, session) as a v2 client."""
    peer.cookie = peer.session = None
    for _ in range(50):
        _hello2(peer, to, role, rate)
        time.sleep(SETTLE_S)
        pump()
        time.sleep(SETTLE_S)
        peer._read()
        if peer.session is not None:
            return
    raise AssertionError("no session")


def _types(peer):
    time.sleep(SETTLE_S)
    return [m["type"] for m in peer.messages()]


def test_link_sends_scene_only_to_v2_clients(peers):
    link = UdpLink(LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=()))
    try:
        sc = load_scenario("harbour")
        link.set_scene(sc, [P.ShipParticulars(0, "OWN", 7.0, 1.2, 0.4)], ENV)
        v1, v2 = peers(), peers()
        to = link.json_address
        v1.join(to, lambda: link.service(0.0, make_reading()), "helm", 2.0)
        _join2(v2, to, lambda: link.service(0.0, make_reading()), "viewer", 2.0)
        t1, t2 = _types(v1), _types(v2)
        assert "welcome" in t1 and not set(t1) & set(P.V2_TYPES)
        assert "welcome" in t2 and t2.count("particulars") == 1 and t2.count("scenario") >= 1
        assert t2.index("particulars") > t2.index("welcome")  # after the full welcome
        # keep-alive hellos do not resend the scene; a new set_scene (reset) does
        _hello2(v2, to, "viewer", 2.0)
        time.sleep(SETTLE_S)
        link.service(0.1, make_reading())
        assert _types(v2) == ["welcome"]
        link.set_scene(None, [P.ShipParticulars(0, "OWN", 7.0, 1.2, 0.4)], None)
        link.publish_event("reset", 0.0, 2)
        assert _types(v2) == ["scenario", "particulars", "event"] and _types(v1) == []
        # helm ownership changes reach v2 clients only
        v1.helm(to, 1, 5.0, telegraph=2)
        time.sleep(SETTLE_S)
        link.service(0.2, make_reading())
        time.sleep(SETTLE_S)
        owner = [m for m in v2.messages() if m["type"] == "helm_owner"]
        assert len(owner) == 1 and owner[0]["reason"] == "takeover" and owner[0]["you"] is False
        assert owner[0]["owner"] == f"{v1.address[0]}:{v1.address[1]}"
        assert "helm_owner" not in _types(v1)
        link.service(1.5, make_reading())  # watchdog
        time.sleep(SETTLE_S)
        msgs = v2.messages()
        assert [(m["owner"], m["reason"]) for m in msgs if m["type"] == "helm_owner"] == [(None, "watchdog")]
        assert link.stats()["tx_v2"] > 0
    finally:
        link.close()


def _pump(env):
    return lambda: env.link.service(env._clock(), env._own_reading)


def test_wrapper_publishes_harbour_scene_and_episode_events(peers):
    t = [100.0]
    env = gym.make("vessel_gym/HarbourApproach-v2", max_episode_steps=8, control_interval_s=0.25)
    cfg = {"json_bind": ("127.0.0.1", 0), "nmea_destinations": []}
    env = UdpLinkWrapper(env, cfg, clock=lambda: t[0])
    try:
        env.reset(seed=0)
        viewer = peers()
        _join2(viewer, env.link.json_address, _pump(env), "viewer", 4.0)
        truncated = False
        while not truncated:
            t[0] += 0.25
            _, _, terminated, truncated, _ = env.step(np.zeros(2, dtype=np.float32))
            assert not terminated
        env.reset()
        time.sleep(SETTLE_S)
        msgs = viewer.messages()
        asm = P.SceneAssembler()
        scenes = [s for s in (asm.add(m) for m in msgs if m["type"] == "scenario") if s is not None]
        assert len(scenes) == 2  # on joining, and at the second reset
        assert {f["kind"] for f in scenes[0]["features"]} >= {"land", "breakwater", "quay", "depth", "goal"}
        own = [m for m in msgs if m["type"] == "particulars" and m["own"]]
        assert own and own[0]["length_m"] == pytest.approx(env.unwrapped.task.ship.particulars.L_m, abs=0.01)
        names = {m["name"] for m in msgs if m["type"] == "particulars" and not m["own"]}
        assert names == {"KVLCC2 LOOP", "KVLCC2 PIER"}
        events = [(m["event"], m["episode"]) for m in msgs if m["type"] == "event"]
        assert events == [("outcome", 1), ("reset", 2)]
        outcome = next(m for m in msgs if m["type"] == "event")
        assert outcome["outcome"] == "time_limit" and outcome["t_s"] == pytest.approx(2.0)
    finally:
        env.close()


def test_wrapper_publishes_contact_before_the_outcome(peers):
    t = [100.0]
    env = UdpLinkWrapper(
        gym.make("vessel_gym/HarbourApproach-v2"),
        {"json_bind": ("127.0.0.1", 0), "nmea_destinations": []},
        clock=lambda: t[0],
    )
    try:
        # 10 m south of the west breakwater (north -1.5 .. 1.5 m), heading for it at 0.5 m/s
        env.reset(seed=0, options={"north_m": -10.0, "east_m": -40.0, "heading_deg": 0.0, "speed_m_s": 0.5})
        viewer = peers()
        _join2(viewer, env.link.json_address, _pump(env), "viewer", 1.0)
        for k in range(400):
            if k % 4 == 3:  # keep-alive every second of link time
                _hello2(viewer, env.link.json_address, "viewer", 1.0)
                time.sleep(SETTLE_S)
            t[0] += 0.25
            _, _, terminated, truncated, info = env.step(np.zeros(2, dtype=np.float32))
            if terminated or truncated:
                break
        assert info["outcome"] == "contact"
        time.sleep(SETTLE_S)
        msgs = viewer.messages()
        events = [m for m in msgs if m["type"] == "event"]
        assert [e["event"] for e in events] == ["contact", "outcome"]
        contact, outcome = events
        assert contact["what"] == "contact" and outcome["outcome"] == "contact"
        assert contact["x_m"] == pytest.approx(-10.0 + 0.5 * contact["t_s"], abs=1.5)  # the bow met the pier
        assert contact["x_m"] + 3.5 == pytest.approx(
            -1.5, abs=0.5
        )  # bow (L/2 = 3.5 m ahead) at its south face
    finally:
        env.close()


def test_panels_draw_the_chart_from_the_scenario_message(peers):
    pytest.importorskip("pygame")
    from vessel_gym.net import clients
    from vessel_gym.ui import panels

    link = UdpLink(LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=()))
    conn = clients.ServerConnection(link.json_address, "viewer", 10.0)
    try:
        sc = load_scenario("harbour")
        link.set_scene(sc, [P.ShipParticulars(0, "OWN", 7.0, 1.27, 0.46)], ENV)
        conn.keepalive(0.0)
        for k in range(20):  # the handshake: hello, challenge, hello with its cookie, welcome, scene, state
            time.sleep(SETTLE_S)
            link.service(0.01 * k, make_reading(x_m=-100.0, y_m=0.0, hdg_deg=0.0))
            time.sleep(SETTLE_S)
            conn.poll(0.01 * k)
            if conn.state is not None and conn.scene is not None:
                break
        assert conn.state is not None and conn.scene is not None and conn.particulars[0]["draught_m"] == 0.46
        assert len(conn.scene["features"]) == len(P.scenario_features(sc))
        land = np.array(panels._CHART["land"])
        shoal = np.array(panels._SHOAL)

        def count(frame, colour):
            return int(np.all(frame == colour, axis=-1).sum())

        plain = panels.render_frame_array(conn.state)
        charted = panels.render_frame_array(conn.state, scene=conn.scene, own_draught_m=0.46)
        assert count(plain, land) == 0 and count(charted, land) > 1000
        assert count(charted, shoal) > 100  # the outer bank (0.35 m) is shallower than the draught
        # the chart is north up and centred on the ship at (-100, 0): the west shore is left of centre
        h, w, _ = charted.shape
        cols = np.nonzero(np.all(charted == land, axis=-1))[1]
        left = min(320, w // 2)
        assert np.any(cols < left + (w - left) / 2 - 50) and np.any(cols > left + (w - left) / 2 + 50)
    finally:
        conn.close()
        link.close()
