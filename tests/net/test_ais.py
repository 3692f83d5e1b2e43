"""AIS type 1 and type 5 encoding, decoded with pyais as an independent oracle."""

from __future__ import annotations

import math

import numpy as np
import pyais
import pytest

from vessel_gym.net import ais, nmea


def _decode(lines: list[str]) -> dict:
    return pyais.decode(*[line.rstrip("\r\n") for line in lines]).asdict()


def _check_framing(lines: list[str]) -> None:
    for line in lines:
        assert line.startswith("!AIVD") and line.endswith("\r\n")
        assert len(line) <= 82
        assert nmea.verify(line)


def test_type1_decodes_to_the_same_fields():
    lines = ais.position_report(211000002, 53.55, 9.99, 8.0, 300.0, 299.4, -16.0, 29, channel="B")
    assert len(lines) == 1
    _check_framing(lines)
    assert lines[0].startswith("!AIVDM,1,1,,B,")
    d = _decode(lines)
    assert d["msg_type"] == 1 and d["mmsi"] == 211000002 and d["status"] == 0
    assert d["lat"] == pytest.approx(53.55, abs=1e-6) and d["lon"] == pytest.approx(9.99, abs=1e-6)
    assert d["speed"] == 8.0 and d["course"] == 300.0 and d["heading"] == 299 and d["second"] == 29
    assert d["turn"] == pytest.approx(-16.0, abs=1.0) and d["turn"] < 0  # port: negative


def test_type1_south_west_starboard_and_vdo():
    lines = ais.position_report(
        366123456, -33.8568, -151.2153, 12.34, 45.67, 46.0, 30.0, 5, nav_status=3, own=True, accuracy=True
    )
    _check_framing(lines)
    assert lines[0].startswith("!AIVDO,")
    d = _decode(lines)
    assert d["lat"] == pytest.approx(-33.8568, abs=1.0 / 600000) and d["lon"] == pytest.approx(
        -151.2153, abs=2e-6
    )
    assert d["speed"] == pytest.approx(12.3) and d["course"] == pytest.approx(45.7) and d["heading"] == 46
    assert d["status"] == 3 and d["accuracy"] is True
    assert d["turn"] == pytest.approx(30.0, abs=2.0) and d["turn"] > 0


def test_type1_not_available_values():
    lines = ais.position_report(211000003, None, math.nan, None, math.inf, None, None, None)
    d = _decode(lines)
    assert d["lat"] == 91.0 and d["lon"] == 181.0
    assert d["speed"] == pytest.approx(102.3) and d["course"] == 360.0
    assert d["heading"] == 511 and d["second"] == 60
    assert d["turn"] == ais.ROT_NOT_AVAILABLE == -128


@pytest.mark.parametrize(
    ("rot_dpm", "code"),
    [(0.0, 0), (1.0, 5), (-1.0, -5), (-16.0, -19), (100.0, 47), (708.0, 126), (5000.0, 126), (-5000.0, -126)],
)
def test_rot_code(rot_dpm, code):
    # ROT_AIS = 4.733 sqrt(ROT_sensor), ITU-R M.1371-5 Annex 8 Table 48
    assert ais.encode_rot(rot_dpm) == code
    if abs(code) < 126:
        assert ais.decode_rot(code) == pytest.approx(rot_dpm, rel=0.25, abs=0.1)


def test_rot_not_available():
    assert ais.encode_rot(None) == -128
    assert ais.encode_rot(math.nan) == -128
    assert ais.decode_rot(-128) is None


def test_type5_two_fragments_fill_bits_and_fields():
    lines = ais.static_voyage(
        211000002,
        imo=9123456,
        call_sign="dabc",
        name="KVLCC2 sim",
        ship_type=80,
        to_bow_m=160,
        to_stern_m=160,
        to_port_m=29,
        to_starboard_m=29,
        draught_m=20.8,
        destination="Hamburg",
        eta=(6, 1, 12, 30),
        seq_id=3,
        channel="B",
    )
    _check_framing(lines)
    assert len(lines) == 2
    f1, f2 = (line.split(",") for line in lines)
    assert f1[1:4] == ["2", "1", "3"] and f2[1:4] == ["2", "2", "3"]
    assert f1[6].startswith("0*") and f2[6].startswith("2*")  # 424 bits = 70 chars + 4 bits: 2 fill bits
    assert len(f1[5]) + len(f2[5]) == 71
    d = _decode(lines)
    assert d["msg_type"] == 5 and d["mmsi"] == 211000002 and d["imo"] == 9123456
    assert d["callsign"] == "DABC" and d["shipname"] == "KVLCC2 SIM" and d["destination"] == "HAMBURG"
    assert d["ship_type"] == 80 and d["epfd"] == 1
    assert (d["to_bow"], d["to_stern"], d["to_port"], d["to_starboard"]) == (160, 160, 29, 29)
    assert d["draught"] == pytest.approx(20.8)
    assert (d["month"], d["day"], d["hour"], d["minute"]) == (6, 1, 12, 30)


def test_type5_payload_equals_pyais_encoder():
    fields = {
        "imo": 9123456,
        "callsign": "DABC",
        "shipname": "KVLCC2 SIM",
        "ship_type": 80,
        "to_bow": 160,
        "to_stern": 160,
        "to_port": 29,
        "to_starboard": 29,
        "draught": 20.8,
        "destination": "HAMBURG",
    }
    ref = pyais.encode_dict(
        {"type": 5, "mmsi": 211000002, "epfd": 1, "month": 0, "day": 0, "hour": 24, "minute": 60, **fields},
        talker_id="AI",
        sentence_type="VDM",
        radio_channel="B",
        seq_id=1,
    )
    ours = ais.static_voyage(
        211000002,
        imo=9123456,
        call_sign="DABC",
        name="KVLCC2 SIM",
        ship_type=80,
        to_bow_m=160,
        to_stern_m=160,
        to_port_m=29,
        to_starboard_m=29,
        draught_m=20.8,
        destination="HAMBURG",
        seq_id=1,
        channel="B",
    )

    def payload(lines):
        return "".join(line.split(",")[5] for line in lines), lines[-1].split(",")[6][0]

    assert payload(ours) == payload(ref)


def test_text_is_truncated_and_mapped_to_the_ais_charset():
    lines = ais.static_voyage(
        1, name="a very long ship name indeed", destination="Kiel~Canal", call_sign="abc"
    )
    d = _decode(lines)
    assert d["shipname"] == "A VERY LONG SHIP NAM"
    assert d["destination"] == "KIEL?CANAL"
    assert ais.sixbit_text("ab", 4) == "AB@@"


def test_random_position_reports_decode_exactly():
    rng = np.random.default_rng(11)
    for _ in range(300):
        mmsi = int(rng.integers(1, 10**9))
        lat, lon = float(rng.uniform(-90, 90)), float(rng.uniform(-180, 180))
        sog, cog, hdg = float(rng.uniform(0, 102)), float(rng.uniform(0, 360)), float(rng.uniform(0, 360))
        rot = float(rng.uniform(-720, 720))
        lines = ais.position_report(mmsi, lat, lon, sog, cog, hdg, rot, int(rng.integers(0, 60)))
        _check_framing(lines)
        d = _decode(lines)
        assert d["mmsi"] == mmsi
        # 1/10000 min = 1.7e-6 deg resolution, and pyais rounds to 6 decimals
        assert d["lat"] == pytest.approx(lat, abs=1.4e-6) and d["lon"] == pytest.approx(lon, abs=1.4e-6)
        assert d["speed"] == pytest.approx(round(sog, 1), abs=0.051)
        assert d["course"] == pytest.approx(round(cog, 1) % 360.0, abs=0.051)
        assert d["heading"] == round(hdg) % 360
        if rot != 0.0 and abs(ais.encode_rot(rot)) >= 1:
            assert math.copysign(1.0, d["turn"]) == math.copysign(1.0, rot)


@pytest.mark.parametrize(
    "kwargs",
    [{"mmsi": 1 << 30}, {"mmsi": -1}, {"channel": "C"}, {"nav_status": 16}],
)
def test_type1_rejects_out_of_range_ids(kwargs):
    args = {"mmsi": 1, "channel": "A", "nav_status": 0}
    args.update(kwargs)
    with pytest.raises(ValueError):
        ais.position_report(
            args["mmsi"], 0, 0, 0, 0, 0, 0, 0, channel=args["channel"], nav_status=args["nav_status"]
        )


def test_type5_rejects_bad_sequence_id():
    with pytest.raises(ValueError):
        ais.static_voyage(1, seq_id=10)
