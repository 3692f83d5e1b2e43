"""Access to the classroom from the network: the Host and Origin gate, codes, sessions, helm theft, floods,
oversized frames, and who may send what (docs/classroom.md, "Access")."""

from __future__ import annotations

import http.client
import json
import logging
import time

import pytest
from websockets.exceptions import ConnectionClosed, InvalidStatus

from vessel_gym.classroom import server as S
from vessel_gym.classroom.codes import ClassCodes

from .conftest import recv_ack, recv_type


def _get(port: int, path: str, host: str | None = None) -> tuple[int, dict, bytes]:
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    c.putrequest("GET", path, skip_host=True)
    c.putheader("Host", host if host is not None else f"127.0.0.1:{port}")
    c.endheaders()
    r = c.getresponse()
    body = r.read()
    c.close()
    return r.status, dict(r.getheaders()), body


def _closed_code(ws) -> int:
    with pytest.raises(ConnectionClosed) as exc:
        for _ in range(1000):
            ws.recv(timeout=10)
    closed = exc.value.rcvd or exc.value.sent
    return closed.code if closed is not None else 1006  # 1006: the connection dropped without a close frame


def test_codes_are_long_random_and_each_admits_its_role():
    codes = ClassCodes(16)
    every = [codes.instructor, codes.spectator, *codes.helm]
    assert len(set(every)) == 18 and all(len(c) >= 22 for c in every)  # 128 bits each
    assert codes.role(codes.instructor).kind == "instructor"
    assert codes.role(codes.spectator).kind == "spectator"
    assert codes.role(codes.helm[7]).ship == 7
    for bad in (None, 42, "", codes.helm[7][:-1], codes.helm[7] + "x", "x" * 65, "\udcff"):
        assert codes.role(bad) is None
    old = codes.helm[7]
    assert codes.revoke(7) != old and codes.role(old) is None


def test_page_is_served_only_to_this_servers_names(room):
    r = room()
    status, headers, body = _get(r.port, "/")
    assert status == 200 and b"Join the class" in body
    assert "script-src 'self'" in headers["Content-Security-Policy"] and headers["X-Frame-Options"] == "DENY"
    assert _get(r.port, "/page.js")[0] == 200
    assert _get(r.port, "/", host=f"localhost:{r.port}")[0] == 200
    # a DNS-rebinding page reaches this address under its own name: refused, as is a wrong port
    assert _get(r.port, "/", host=f"attacker.example:{r.port}")[0] == 421
    assert _get(r.port, "/", host=f"127.0.0.1:{r.port + 1}")[0] == 421
    assert _get(r.port, "/", host="")[0] == 421
    assert _get(r.port, "/../etc/passwd")[0] == 404
    assert _get(r.port, "/helm/anything")[0] == 404
    assert r.srv.stats["bad_host"] == 3


def test_cross_origin_and_originless_sockets_are_refused(room):
    r = room()
    for origin in ("http://evil.example", f"http://localhost:{r.port}", f"https://127.0.0.1:{r.port}", None):
        with pytest.raises(InvalidStatus) as exc:
            r.connect(origin=origin)
        assert exc.value.response.status_code == 403
    assert r.srv.stats["bad_origin"] == 4
    # even with a valid code a page of another origin cannot open the socket
    with pytest.raises(InvalidStatus):
        r.connect(origin="http://evil.example")


def test_absent_and_wrong_codes_get_nothing_and_three_close_the_connection(room):
    r = room()
    ws = r.connect()
    ws.send(json.dumps({"type": "join"}))
    assert recv_type(ws, ("refused",))["error"] == "unknown code"
    ws.send(json.dumps({"type": "join", "code": r.codes.helm[0][:-2] + "xx"}))
    assert recv_type(ws, ("refused",))["error"] == "unknown code"
    ws.send(json.dumps({"type": "join", "code": "0" * 22}))
    recv_type(ws, ("refused",))
    assert _closed_code(ws) == 1008
    assert r.srv.stats["bad_code"] == 3 and r.srv.stats["joins"] == 0
    # a connection that has not joined gets no state and may not order
    ws = r.connect()
    ws.send(json.dumps({"type": "order", "rudder": 35, "telegraph": 4, "seq": 1, "session": "x"}))
    assert recv_type(ws, ("error",))["error"] == "join first"
    assert _closed_code(ws) == 1008
    assert r.harbour.rudder_i.tolist() == [7, 7]  # midships still


def test_join_attempts_are_rate_limited_per_address(room):
    r = room()
    refused = 0
    t0 = time.monotonic()
    for _ in range(6):  # up to 3 codes per connection
        ws = r.connect()
        for _ in range(3):
            ws.send(json.dumps({"type": "join", "code": "guess" * 5}))
            m = recv_type(ws, ("refused",))
            refused += "too many join attempts" in m["error"]
    took = time.monotonic() - t0
    # what got through: a burst of one second's budget and its refill while the tries lasted
    assert 18 - refused <= S.JOIN_RATE_PER_HOST_HZ * (1.0 + took) + 1
    assert refused > 0 and r.srv.stats["join_rate"] == refused
    assert r.srv.stats["bad_code"] == 18 - refused


def test_a_helm_code_in_use_cannot_take_the_ship(room):
    r = room()
    ws_a, w_a = r.join(r.codes.helm[0], "Ann")
    assert (w_a["type"], w_a["role"], w_a["ship"]) == ("welcome", "helm", 0)
    _ws_b, w_b = r.join(r.codes.helm[0], "Thief")
    assert w_b["type"] == "refused" and "already has a helmsman" in w_b["error"]
    assert r.srv.stats["taken"] == 1
    ws_a.close()
    time.sleep(0.3)
    _ws_c, w_c = r.join(r.codes.helm[0], "Ann again")  # after the page is closed the code works again
    assert w_c["type"] == "welcome" and w_c["session"] != w_a["session"]


def test_replayed_sessions_are_refused(room):
    r = room()
    ws_a, w_a = r.join(r.codes.helm[0], "Ann")
    ws_b, w_b = r.join(r.codes.helm[1], "Bob")
    # Bob's connection sends an order with Ann's session: refused, and neither ship's orders change
    ws_b.send(
        json.dumps({"type": "order", "session": w_a["session"], "seq": 1, "rudder": 35, "telegraph": 4})
    )
    assert recv_type(ws_b, ("error",))["error"] == "not this connection's session"
    assert r.harbour.rudder_i.tolist() == [7, 7]
    # Ann's own order with her session works
    ws_a.send(
        json.dumps({"type": "order", "session": w_a["session"], "seq": 5, "rudder": -10, "telegraph": 2})
    )
    assert recv_ack(ws_a, 5)["own"]["rudder_order_deg"] == -10.0
    # after Ann's page closed, her session is worth nothing on a new connection
    ws_a.close()
    time.sleep(0.3)
    ws_c, w_c = r.join(r.codes.spectator)
    ws_c.send(
        json.dumps({"type": "order", "session": w_a["session"], "seq": 6, "rudder": 35, "telegraph": 4})
    )
    assert recv_type(ws_c, ("error",))["error"] == "not this connection's session"
    assert r.srv.stats["bad_session"] == 2 and r.srv.stats["orders"] == 1


def test_each_role_sends_only_its_own_messages(room):
    r = room()
    ws_s, w_s = r.join(r.codes.spectator)
    ws_s.send(
        json.dumps({"type": "order", "session": w_s["session"], "seq": 1, "rudder": 35, "telegraph": 4})
    )
    assert "not a message a spectator may send" in recv_type(ws_s, ("error",))["error"]
    ws_h, w_h = r.join(r.codes.helm[1])
    ws_h.send(json.dumps({"type": "pause", "session": w_h["session"]}))
    assert "not a message a helm may send" in recv_type(ws_h, ("error",))["error"]
    assert not r.srv.paused
    assert "own" not in recv_type(ws_s, ("state",)) and "class" not in recv_type(ws_s, ("state",))
    state_h = recv_type(ws_h, ("state",))
    assert "class" not in state_h and "spectator_code" not in json.dumps(state_h)
    for bad in (
        {"rudder": 12.5, "telegraph": 1, "seq": 2},  # not a 5 deg step
        {"rudder": 5, "telegraph": 1.5, "seq": 3},
        {"rudder": True, "telegraph": 1, "seq": 4},
        {"rudder": 5, "telegraph": 1, "seq": -1},
        {"rudder": 5, "telegraph": 9, "seq": 5},
    ):
        ws_h.send(json.dumps({"type": "order", "session": w_h["session"], **bad}))
        recv_type(ws_h, ("error",))
    ws_h.send("not json")
    recv_type(ws_h, ("error",))
    ws_h.send(b"\x00binary")
    recv_type(ws_h, ("error",))
    assert r.harbour.rudder_i.tolist() == [7, 7]


def test_floods_are_cut_and_the_connection_closed(room):
    r = room()
    ws, w = r.join(r.codes.helm[0])
    t0 = time.monotonic()
    seq = 0
    while time.monotonic() - t0 < 30.0:  # until the server closes it (the bucket refills as it reads)
        seq += 1
        try:
            ws.send(
                json.dumps(
                    {"type": "order", "session": w["session"], "seq": seq, "rudder": 5, "telegraph": 1}
                )
            )
        except ConnectionClosed:
            break
        if seq % 200 == 0 and ws.protocol.close_rcvd is not None:
            break
    # 1008 (policy), or 1006 when the close frame waited behind echoes this client never read, until the
    # server gave up on a clean close and dropped the connection
    assert _closed_code(ws) in (1008, 1006)
    took = time.monotonic() - t0
    stats = r.srv.stats
    assert stats["flood_closed"] == 1 and stats["rate"] == S.FLOOD_CLOSE_AFTER
    # what got through: the bucket's one-second burst and its refill while the flood lasted
    assert stats["orders"] <= S.MESSAGE_RATE_HZ * (1.0 + took) + 1
    # the others are unaffected
    _ws2, w2 = r.join(r.codes.helm[1])
    assert w2["type"] == "welcome"


def test_oversized_frames_close_the_connection(room):
    r = room()
    ws, w = r.join(r.codes.helm[0])
    ws.send(json.dumps({"type": "order", "session": w["session"], "seq": 1, "rudder": 5, "telegraph": 1,
                        "pad": "x" * S.MAX_FRAME_BYTES}))  # fmt: skip
    assert _closed_code(ws) == 1009
    time.sleep(0.2)
    assert r.srv.stats["oversize"] == 1 and r.srv.stats["orders"] == 0
    # before joining too
    ws = r.connect()
    ws.send("x" * 5000)
    assert _closed_code(ws) == 1009


def test_a_connection_that_does_not_join_is_closed(room, monkeypatch):
    monkeypatch.setattr(S, "JOIN_TIMEOUT_S", 0.5)
    r = room()
    ws = r.connect()
    assert _closed_code(ws) == 1008
    # one wrong code and then silence: the join's time counts from the connection, not the last try
    ws = r.connect()
    t0 = time.monotonic()
    ws.send(json.dumps({"type": "join", "code": "wrong" * 5}))
    assert _closed_code(ws) == 1008 and time.monotonic() - t0 < 5.0


def test_connections_per_address_are_capped(room, monkeypatch):
    monkeypatch.setattr(S, "MAX_CONNECTIONS_PER_HOST", 3)
    r = room()
    for _ in range(3):
        r.connect()
    time.sleep(0.2)
    with pytest.raises(InvalidStatus) as exc:
        r.connect()
    assert exc.value.response.status_code == 503


def test_instructor_revokes_pauses_resets_and_sets_the_weather(room, caplog):
    caplog.set_level(logging.DEBUG)
    r = room(ships=2, time_factor=4.0)
    ws_i, w_i = r.join(r.codes.instructor)
    assert w_i["role"] == "instructor"
    st = recv_type(ws_i, ("state",))
    assert [s["code"] for s in st["class"]] == r.codes.helm and st["spectator_code"] == r.codes.spectator
    ws_h, _w = r.join(r.codes.helm[1], "Bob")
    old = r.codes.helm[1]

    def cmd(**m):
        ws_i.send(json.dumps({"session": w_i["session"], **m}))
        while True:  # the reply: states of the running class come in between
            got = recv_type(ws_i, ("state", "error", "debrief"))
            if got["type"] != "state" or got.get("done") == m["type"]:
                return got

    st = cmd(type="revoke", ship=1)
    assert _closed_code(ws_h) == 1008
    assert r.codes.role(old) is None and st["class"][1]["code"] == r.codes.helm[1] != old
    assert r.join(old)[1]["type"] == "refused"
    assert r.join(r.codes.helm[1])[1]["type"] == "welcome"
    assert cmd(type="pause")["paused"]
    t = r.harbour.t_s
    time.sleep(0.5)
    assert r.harbour.t_s == t
    cmd(type="resume")
    time.sleep(0.5)
    assert r.harbour.t_s > t
    st = cmd(type="weather", wind_speed_m_s=6.0, wind_from_deg=45.0)
    assert st["weather"]["wind_speed_m_s"] == 6.0
    assert r.srv.call(lambda: [r.harbour.sim.environments[k].wind_speed_m_s for k in range(2)]) == [6.0, 6.0]
    assert "wind_speed_m_s" in cmd(type="weather", wind_speed_m_s=100.0)["error"]
    assert "error" == cmd(type="weather", wind_speed_m_s="calm")["type"]
    assert "error" == cmd(type="reset", ship=7)["type"]
    st = cmd(type="reset", ship=0)
    assert st["class"][0]["timer_s"] < 0.5
    d = cmd(type="debrief")
    assert d["type"] == "debrief" and "<svg" in d["html"] and (r.srv.debrief_path.read_text() == d["html"])
    # no code in any log line, nor in the debrief
    every = [r.codes.instructor, r.codes.spectator, old, *r.codes.helm]
    server_logs = [rec.getMessage() for rec in caplog.records if not rec.name.startswith("websockets.client")]
    assert not any(c in line for line in server_logs for c in every)
    assert not any(c in d["html"] for c in every)


@pytest.mark.parametrize(
    ("bound", "host", "ok"),
    [
        ("0.0.0.0", "192.168.1.20:8090", True),  # any address of this machine when bound to all
        ("0.0.0.0", "10.0.0.5:8090", True),
        ("0.0.0.0", "127.0.0.1:8090", True),
        ("0.0.0.0", "classroom.school.example:8090", True),  # given with --host-name
        ("0.0.0.0", "CLASSROOM.school.example:8090", True),
        ("0.0.0.0", "attacker.example:8090", False),  # DNS rebinding
        ("0.0.0.0", "192.168.1.20:8091", False),
        ("0.0.0.0", "192.168.1.20", False),
        ("192.168.1.20", "192.168.1.20:8090", True),
        ("192.168.1.20", "10.0.0.5:8090", False),
        ("192.168.1.20", "localhost:8090", False),
        ("127.0.0.1", "localhost:8090", True),
        ("127.0.0.1", "[::1]:8090", True),
        ("127.0.0.1", "192.168.1.20:8090", False),
        ("127.0.0.1", "x" * 300, False),
    ],
)
def test_host_names_the_server_accepts(bound, host, ok):
    srv = S.ClassroomServer(None, ClassCodes(1), (bound, 8090), host_names=("classroom.school.example",))
    srv.port = 8090
    assert srv.host_ok(host) is ok


def test_a_pilot_ship_takes_no_student(room):
    r = room(ships=2, pilots=1)
    assert r.join(r.codes.helm[1])[1] == {
        "type": "refused",
        "error": "this ship is steered by a pilot or an agent",
    }
    ws, _w = r.join(r.codes.instructor)
    st = recv_type(ws, ("state",))
    assert [(s["name"], s["pilot"]) for s in st["class"]] == [("Ship 1", False), ("Pilot 2", True)]
