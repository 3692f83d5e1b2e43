"""The v1 JSON schema: round trips, clamping, and rejection reasons."""

from __future__ import annotations

import json
import math

import pytest

from vessel_gym.net import protocol as P

from .helpers import make_reading

STATE_KEYS = [
    "v",
    "type",
    "seq",
    "t_s",
    "lat_deg",
    "lon_deg",
    "x_m",
    "y_m",
    "hdg_deg",
    "cog_deg",
    "sog_kn",
    "stw_kn",
    "rot_dpm",
    "rudder_deg",
    "rudder_order_deg",
    "rpm",
    "telegraph",
    "helm_ok",
    "targets",
    "part",
    "parts",
]
TARGET_KEYS = [
    "id",
    "name",
    "lat_deg",
    "lon_deg",
    "x_m",
    "y_m",
    "hdg_deg",
    "cog_deg",
    "sog_kn",
    "length_m",
    "beam_m",
]


def _reason(data: bytes | str | dict) -> str:
    if isinstance(data, dict):
        data = json.dumps(data)
    if isinstance(data, str):
        data = data.encode()
    with pytest.raises(P.ProtocolError) as info:
        P.parse_datagram(data)
    assert info.value.reason in P.REASONS
    return info.value.reason


# -- client -> server round trips -----------------------------------------------------------------------------


def test_hello_round_trip():
    msg = P.parse_datagram(P.encode_hello("viewer", 30.0, "unity-1"))
    assert msg == P.Hello(role="viewer", rate_hz=30.0, name="unity-1", token=None)
    helm = P.parse_datagram(P.encode_hello("helm", name="panel-A", token="s3cret"))
    assert helm == P.Hello(role="helm", rate_hz=20.0, name="panel-A", token="s3cret")


def test_helm_round_trip_telegraph_and_rpm():
    assert P.parse_datagram(P.encode_helm(1234, -10.0, telegraph=3)) == P.HelmCommand(1234, -10.0, 3, None)
    assert P.parse_datagram(P.encode_helm(7, 12.5, rpm_order=-60.0)) == P.HelmCommand(7, 12.5, None, -60.0)


def test_bye_and_stats_request():
    assert P.parse_datagram(P.encode_bye()) == P.Bye()
    assert P.parse_datagram(P.encode_stats_request()) == P.StatsRequest()
    assert P.parse_datagram(b'{"v":1,"type":"bye","seq":5}') == P.Bye()


def test_unknown_keys_are_ignored():
    data = {"v": 1, "type": "helm", "seq": 1, "rudder_order_deg": 5, "telegraph": 1, "future": [1, {"x": 2}]}
    assert P.parse_datagram(json.dumps(data).encode()) == P.HelmCommand(1, 5.0, 1, None)


# -- clamping -------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("rate", "expected"), [(0, 1.0), (-5, 1.0), (0.5, 1.0), (10, 10.0), (500, 50.0), (1e308, 50.0)]
)
def test_rate_is_clamped(rate, expected):
    msg = P.parse_datagram(json.dumps({"v": 1, "type": "hello", "role": "viewer", "rate_hz": rate}).encode())
    assert msg.rate_hz == expected


@pytest.mark.parametrize(
    ("rudder", "expected"),
    [(90, 35.0), (-90.5, -35.0), (1e308, 35.0), (-1e308, -35.0), (10**400, 35.0), (3.5, 3.5)],
)
def test_rudder_is_clamped(rudder, expected):
    data = f'{{"v":1,"type":"helm","seq":1,"rudder_order_deg":{rudder},"telegraph":0}}'.encode()
    assert P.parse_datagram(data).rudder_order_deg == expected


def test_telegraph_and_rpm_are_clamped_to_limits():
    limits = P.Limits(max_rudder_deg=25.0, max_rpm=120.0)
    cmd = P.parse_datagram(b'{"v":1,"type":"helm","seq":1,"rudder_order_deg":30,"telegraph":9}', limits)
    assert cmd.rudder_order_deg == 25.0 and cmd.telegraph == 4
    cmd = P.parse_datagram(b'{"v":1,"type":"helm","seq":1,"rudder_order_deg":-30,"telegraph":-99}', limits)
    assert cmd.rudder_order_deg == -25.0 and cmd.telegraph == -4
    cmd = P.parse_datagram(b'{"v":1,"type":"helm","seq":1,"rudder_order_deg":0,"rpm_order":-1e300}', limits)
    assert cmd.rpm_order == -120.0


def test_limits_are_validated():
    with pytest.raises(ValueError, match="max_rudder_deg"):
        P.Limits(max_rudder_deg=0.0)
    with pytest.raises(ValueError, match="max_rpm"):
        P.Limits(max_rpm=math.nan)


# -- rejection reasons ----------------------------------------------------------------------------------------


def test_oversize_bad_utf8_bad_json():
    assert _reason(b" " * 2049) == "oversize"
    assert _reason(b"[" * 60000) == "oversize"
    assert _reason(b'{"v":1,"type":"bye","name":"\xff\xfe"}') == "bad_utf8"
    assert _reason(b"\xc3\x28") == "bad_utf8"
    assert _reason(b"") == "bad_json"
    assert _reason(b"{") == "bad_json"
    assert _reason(b'{"v":1,"type":"bye"} trailing') == "bad_json"
    assert _reason(b"[" * 2048) == "too_complex"
    assert _reason(b'{"a":' * 300 + b"1" + b"}" * 300) == "too_complex"
    assert P.parse_datagram(b'{"v":1,"type":"bye","x":' + b"[" * 31 + b"]" * 31 + b"}") == P.Bye()  # 32: fine
    assert _reason(b'{"v":1,"type":"helm","seq":' + b"9" * 5000 + b"}") == "oversize"


@pytest.mark.parametrize("token", ["NaN", "Infinity", "-Infinity", "1e309", "-1e400"])
def test_non_finite_numbers_are_rejected(token):
    data = f'{{"v":1,"type":"helm","seq":1,"rudder_order_deg":{token},"telegraph":0}}'
    assert _reason(data) == "non_finite"
    assert _reason(f'{{"v":1,"type":"bye","junk":[{token}]}}') == "non_finite"


@pytest.mark.parametrize("doc", ["[]", "null", "3", '"hello"', "true", '[{"v":1,"type":"bye"}]'])
def test_non_objects_are_rejected(doc):
    assert _reason(doc) == "not_object"


@pytest.mark.parametrize("v", [None, 0, 2, "1", True, [1]])
def test_wrong_version_is_rejected(v):
    doc = {"type": "bye"} if v is None else {"v": v, "type": "bye"}
    assert _reason(doc) == "bad_version"


@pytest.mark.parametrize("kind", [None, "state", "welcome", "HELLO", 1, "ping"])
def test_unknown_type_is_rejected(kind):
    assert _reason({"v": 1, "type": kind}) == "bad_type"


@pytest.mark.parametrize(
    "doc",
    [
        {"v": 1, "type": "helm", "rudder_order_deg": 1, "telegraph": 0},  # no seq
        {"v": 1, "type": "helm", "seq": True, "rudder_order_deg": 1, "telegraph": 0},
        {"v": 1, "type": "helm", "seq": -1, "rudder_order_deg": 1, "telegraph": 0},
        {"v": 1, "type": "helm", "seq": 2**53, "rudder_order_deg": 1, "telegraph": 0},
        {"v": 1, "type": "helm", "seq": 1.5, "rudder_order_deg": 1, "telegraph": 0},
        {"v": 1, "type": "helm", "seq": 1, "telegraph": 0},  # no rudder
        {"v": 1, "type": "helm", "seq": 1, "rudder_order_deg": "10", "telegraph": 0},
        {"v": 1, "type": "helm", "seq": 1, "rudder_order_deg": None, "telegraph": 0},
        {"v": 1, "type": "helm", "seq": 1, "rudder_order_deg": False, "telegraph": 0},
        {"v": 1, "type": "helm", "seq": 1, "rudder_order_deg": 1},  # neither
        {"v": 1, "type": "helm", "seq": 1, "rudder_order_deg": 1, "telegraph": 0, "rpm_order": 5},  # both
        {"v": 1, "type": "helm", "seq": 1, "rudder_order_deg": 1, "telegraph": 2.0},
        {"v": 1, "type": "helm", "seq": 1, "rudder_order_deg": 1, "telegraph": "HALF_AHEAD"},
        {"v": 1, "type": "helm", "seq": 1, "rudder_order_deg": 1, "rpm_order": [60]},
        {"v": 1, "type": "hello", "role": "admin"},
        {"v": 1, "type": "hello"},
        {"v": 1, "type": "hello", "role": "viewer", "rate_hz": "fast"},
        {"v": 1, "type": "hello", "role": "viewer", "name": 5},
        {"v": 1, "type": "hello", "role": "viewer", "token": {"x": 1}},
        {"v": 1, "type": "bye", "seq": "1"},
    ],
)
def test_missing_or_ill_typed_fields_are_rejected(doc):
    assert _reason(doc) == "bad_field"


def test_long_names_are_truncated():
    msg = P.parse_datagram(P.encode_hello("viewer", name="x" * 31) + b"")
    assert msg.name == "x" * 31
    doc = json.dumps({"v": 1, "type": "hello", "role": "viewer", "name": "n" * 500}).encode()
    assert P.parse_datagram(doc).name == "n" * P.MAX_NAME_CHARS


# -- server -> client -----------------------------------------------------------------------------------------


def _target(i: int, **kw) -> P.Target:
    r = make_reading(lat_deg=53.5 + i * 1e-3, lon_deg=9.9, x_m=100.0 * i, y_m=-50.0 * i, hdg_deg=10.0 * i)
    return P.Target(id=i, name=f"SHIP {i}", reading=r, length_m=180.0 + i, beam_m=30.0, **kw)


def test_state_keys_values_and_round_trip():
    (data,) = P.encode_state(42, make_reading(), True, [_target(1), _target(2)])
    msg = P.parse_server_datagram(data)
    assert list(msg) == STATE_KEYS
    assert msg["seq"] == 42 and msg["helm_ok"] is True and msg["part"] == 0 and msg["parts"] == 1
    assert msg["lat_deg"] == 53.5412 and msg["lon_deg"] == 9.9876
    assert msg["x_m"] == 1234.5 and msg["y_m"] == -789.0
    assert (
        msg["hdg_deg"] == 123.4
        and msg["cog_deg"] == 124.9
        and msg["sog_kn"] == 12.3
        and msg["stw_kn"] == 12.0
    )
    assert msg["rot_dpm"] == -12.0 and msg["rudder_deg"] == -10.0 and msg["rudder_order_deg"] == -15.0
    assert msg["rpm"] == 85.0 and msg["telegraph"] == 3 and msg["t_s"] == 10.0
    assert [list(t) for t in msg["targets"]] == [TARGET_KEYS, TARGET_KEYS]
    t2 = msg["targets"][1]
    assert t2["id"] == 2 and t2["name"] == "SHIP 2" and t2["x_m"] == 200.0 and t2["hdg_deg"] == 20.0
    assert t2["length_m"] == 182.0 and t2["beam_m"] == 30.0
    assert len(data) < 1400


def test_state_with_non_finite_values_sends_null():
    r = make_reading(rot_dpm=math.nan, sog_kn=math.inf, lat_deg=-math.inf)
    (data,) = P.encode_state(1, r, False)
    assert b"NaN" not in data and b"Infinity" not in data
    msg = json.loads(data)
    assert msg["rot_dpm"] is None and msg["sog_kn"] is None and msg["lat_deg"] is None


def test_many_targets_are_split_into_parts_sharing_seq():
    targets = [_target(i) for i in range(40)]
    parts = P.encode_state(9, make_reading(), False, targets)
    assert len(parts) > 1
    msgs = [P.parse_server_datagram(p) for p in parts]
    assert all(len(p) <= P.MAX_STATE_DATAGRAM_BYTES for p in parts)
    assert {m["seq"] for m in msgs} == {9}
    assert [m["part"] for m in msgs] == list(range(len(parts)))
    assert {m["parts"] for m in msgs} == {len(parts)}
    assert [t["id"] for m in msgs for t in m["targets"]] == list(range(40))
    assert all(m["hdg_deg"] == 123.4 for m in msgs)


def test_welcome_and_stats():
    w = P.parse_server_datagram(
        P.encode_welcome(3, "helm", 20.0, True, P.Limits(30.0, 150.0), 1.0, 3.0, "hold")
    )
    assert (
        w["type"] == "welcome"
        and w["helm"] is True
        and w["max_rudder_deg"] == 30.0
        and w["failsafe"] == "hold"
    )
    s = P.parse_server_datagram(P.encode_stats(4, 12.5, {"rx_datagrams": 7, "drop_bad_json": 2}, 3))
    assert s["counters"] == {"rx_datagrams": 7, "drop_bad_json": 2} and s["clients"] == 3 and s["t_s"] == 12.5


def test_server_parser_rejects_hostile_input():
    for data, reason in [
        (b"\xff", "bad_utf8"),
        (b"{", "bad_json"),
        (b"[]", "not_object"),
        (b'{"v":2,"type":"state"}', "bad_version"),
        (b'{"v":1,"type":"helm"}', "bad_type"),
        (b'{"v":1,"type":"state","x":NaN}', "non_finite"),
    ]:
        with pytest.raises(P.ProtocolError) as info:
            P.parse_server_datagram(data)
        assert info.value.reason == reason


def test_client_encoders_validate():
    with pytest.raises(ValueError):
        P.encode_helm(1, 0.0)
    with pytest.raises(ValueError):
        P.encode_helm(1, 0.0, telegraph=1, rpm_order=10.0)
    with pytest.raises(ValueError):
        P.encode_hello("pilot")
    with pytest.raises(ValueError):  # non-finite never leaves a client either
        P.encode_helm(1, math.nan, telegraph=0)


def test_state_carries_roll_only_for_a_ship_with_roll():
    """The bridge of a ship with roll gives the heel and roll rate (deg, deg/s, + = starboard side down), and
    the state sends them as roll_deg and roll_rate_dps after the other own-ship fields; a 3-DOF ship sends
    neither (a viewer draws it upright)."""
    from vessel_gym.physics import layout as lo
    from vessel_gym.physics.simulation import Simulation

    sim = Simulation("container", 1, dt=0.1)
    sim.state[0, lo.X_PHI] = math.radians(-3.5)
    sim.state[0, lo.X_P] = math.radians(0.25)
    own = sim.bridge(0)
    assert own.roll_deg == pytest.approx(-3.5) and own.roll_rate_dps == pytest.approx(0.25)
    (data,) = P.encode_state(7, own, True)
    msg = P.parse_server_datagram(data)
    assert list(msg) == STATE_KEYS[: STATE_KEYS.index("helm_ok")] + ["roll_deg", "roll_rate_dps"] + STATE_KEYS[
        STATE_KEYS.index("helm_ok") :
    ]
    assert msg["roll_deg"] == -3.5 and msg["roll_rate_dps"] == 0.25
    flat = Simulation("kvlcc2", 1, dt=0.1).bridge(0)
    assert flat.roll_deg is None and flat.roll_rate_dps is None
    (data,) = P.encode_state(8, flat, True)
    assert list(P.parse_server_datagram(data)) == STATE_KEYS
