"""NMEA 0183 framing and the own-ship sentences, checked against pynmea2 as an independent parser."""

from __future__ import annotations

import math
from datetime import datetime, timezone

import numpy as np
import pynmea2
import pytest

from vessel_gym.net import nmea

from .helpers import make_reading

UTC = datetime(2026, 3, 14, 12, 34, 56, 780000, tzinfo=timezone.utc)


# -- framing -------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "line",
    [
        # The classic public examples (NMEA FAQ / gpsd "NMEA Revealed").
        "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47",
        "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A",
        "$IIHDT,123.4,T*26",
    ],
)
def test_checksum_of_public_examples(line):
    body, expected = line[1:].split("*")
    assert nmea.checksum(body) == expected
    assert nmea.verify(line)
    assert nmea.verify(line + "\r\n")
    assert not nmea.verify(line[:-1] + ("0" if line[-1] != "0" else "1"))


def test_sentence_rebuilds_the_public_gga():
    fields = "123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,".split(",")
    assert nmea.sentence("GP", "GGA", fields) == (
        "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n"
    )


def test_checksum_is_upper_case_hex():
    # 0x5E-ish checksums must print as upper-case hex digits.
    for body in ("IIROT,-12.0,A", "GPVTG,124.9,T,,M,12.30,N,22.78,K,A", "AAA"):
        cs = nmea.checksum(body)
        assert len(cs) == 2 and cs == cs.upper()
        assert int(cs, 16) == np.bitwise_xor.reduce(np.frombuffer(body.encode(), np.uint8))


def test_sentence_over_82_characters_raises():
    with pytest.raises(nmea.NmeaError, match="82"):
        nmea.sentence("II", "TXT", ["X" * 80])
    longest = nmea.sentence("II", "TXT", ["X" * (82 - len("$IITXT,*hh\r\n"))])
    assert len(longest) == 82


@pytest.mark.parametrize("bad", ["a,b", "x*y", "$", "!", "\r", "tab\t", "caf\u00e9"])
def test_sentence_rejects_reserved_characters(bad):
    with pytest.raises(nmea.NmeaError):
        nmea.sentence("II", "HDT", [bad])


@pytest.mark.parametrize(("talker", "formatter"), [("I", "HDT"), ("ii", "HDT"), ("II", "HD"), ("II", "hdt")])
def test_sentence_rejects_bad_ids(talker, formatter):
    with pytest.raises(nmea.NmeaError):
        nmea.sentence(talker, formatter, ["1"])


# -- field formatting ----------------------------------------------------------------------------------------


def test_lat_lon_format_and_hemispheres():
    assert nmea.fmt_lat(53.5412) == ("5332.4720", "N")
    assert nmea.fmt_lon(9.9876) == ("00959.2560", "E")
    assert nmea.fmt_lat(-33.8568) == ("3351.4080", "S")
    assert nmea.fmt_lon(-151.2153) == ("15112.9180", "W")
    assert nmea.fmt_lon(190.0) == ("17000.0000", "W")  # wrapped to -170
    assert nmea.fmt_lat(91.0) == ("", "")
    assert nmea.fmt_lat(math.nan) == ("", "")


def test_minutes_never_round_to_sixty():
    # 10.9999999 deg = 10 deg 59.999994 min: must carry to 11 deg 00.0000 min, not print "1060.0000".
    assert nmea.fmt_lat(10.9999999) == ("1100.0000", "N")
    assert nmea.fmt_lon(-0.99999999) == ("00100.0000", "W")


def test_numbers_fixed_decimals_no_negative_zero_and_empty_when_unknown():
    assert nmea.fmt_num(12.3, 2) == "12.30"
    assert nmea.fmt_num(-0.04, 1) == "0.0"
    assert nmea.fmt_num(None, 1) == ""
    assert nmea.fmt_num(math.inf, 1) == ""
    assert nmea.fmt_angle(359.96) == "0.0"
    assert nmea.fmt_angle(-10.0) == "350.0"
    assert nmea.fmt_angle(720.25, 2) == "0.25"


def test_time_and_date():
    assert nmea.fmt_time(UTC) == "123456.78"
    assert nmea.fmt_date(UTC) == "140326"
    naive = datetime(2021, 6, 1, 0, 0, 5, 999999)
    assert nmea.fmt_time(naive) == "000005.99"  # truncated, never rounds up to 6 s


# -- own-ship sentences --------------------------------------------------------------------------------------


def _by_type(lines: list[str]) -> dict[str, pynmea2.NMEASentence]:
    out = {}
    for line in lines:
        msg = pynmea2.parse(line.rstrip("\r\n"), check=True)
        out[msg.sentence_type] = msg
    return out


def test_default_cycle_types_talkers_and_framing():
    lines = nmea.own_ship_sentences(make_reading(), UTC)
    heads = [line[1:6] for line in lines]
    assert heads == ["GPRMC", "GPGGA", "GPVTG", "IIHDT", "IIROT", "IIRSA", "IIRPM", "IIVHW", "IIMWV"]
    for line in lines:
        assert line.endswith("\r\n") and line.count("\r\n") == 1
        assert len(line) <= 82
        assert nmea.verify(line)


def test_sentences_match_the_documented_examples():
    lines = nmea.own_ship_sentences(make_reading(), UTC)
    assert lines[0] == "$GPRMC,123456.78,A,5332.4720,N,00959.2560,E,12.30,124.9,140326,,,S*4A\r\n"
    assert lines[1] == "$GPGGA,123456.78,5332.4720,N,00959.2560,E,1,08,1.0,0.0,M,0.0,M,,*5F\r\n"
    assert lines[3:] == [
        "$IIHDT,123.4,T*26\r\n",
        "$IIROT,-12.0,A*38\r\n",
        "$IIRSA,-10.0,A,,V*65\r\n",
        "$IIRPM,S,0,85.0,,A*52\r\n",
        "$IIVHW,123.4,T,,M,12.00,N,22.22,K*7C\r\n",
        "$IIMWV,40.0,R,15.0,N,A*3D\r\n",
    ]


def test_values_round_trip_through_pynmea2():
    r = make_reading()
    m = _by_type(nmea.own_ship_sentences(r, UTC, gll_sentence=True, zda_sentence=True))
    assert m["RMC"].status == "A" and m["RMC"].mode_indicator == "S"
    assert m["RMC"].latitude == pytest.approx(r.lat_deg, abs=2e-6)
    assert m["RMC"].longitude == pytest.approx(r.lon_deg, abs=2e-6)
    assert float(m["RMC"].spd_over_grnd) == pytest.approx(r.sog_kn)
    assert float(m["RMC"].true_course) == pytest.approx(r.cog_deg)
    assert m["RMC"].datetime == UTC
    assert m["GGA"].gps_qual == 1
    assert m["GGA"].latitude == pytest.approx(r.lat_deg, abs=2e-6)
    assert m["GLL"].longitude == pytest.approx(r.lon_deg, abs=2e-6)
    assert float(m["VTG"].spd_over_grnd_kts) == pytest.approx(r.sog_kn)
    assert float(m["VTG"].spd_over_grnd_kmph) == pytest.approx(r.sog_kn * 1.852, abs=0.006)
    assert float(m["VTG"].true_track) == pytest.approx(r.cog_deg)
    assert float(m["HDT"].heading) == pytest.approx(r.hdg_deg)
    assert float(m["ROT"].rate_of_turn) == pytest.approx(-12.0)  # to port: negative
    assert float(m["RSA"].rsa_starboard) == pytest.approx(-10.0)  # rudder to port: negative
    assert m["RPM"].source == "S" and m["RPM"].engine_no == 0 and float(m["RPM"].speed) == 85.0
    assert float(m["VHW"].water_speed_knots) == pytest.approx(r.stw_kn)
    assert float(m["VHW"].heading_true) == pytest.approx(r.hdg_deg)
    assert float(m["MWV"].wind_angle) == 40.0 and m["MWV"].reference == "R"
    assert float(m["MWV"].wind_speed) == 15.0 and m["MWV"].wind_speed_units == "N"
    assert (m["ZDA"].day, m["ZDA"].month, m["ZDA"].year) == (14, 3, 2026)


def test_starboard_turn_is_positive_and_hemispheres_follow_sign():
    r = make_reading(rot_dpm=30.5, rudder_deg=20.0, lat_deg=-33.8568, lon_deg=-151.2153, rpm=-40.0)
    m = _by_type(nmea.own_ship_sentences(r, UTC))
    assert float(m["ROT"].rate_of_turn) == 30.5
    assert float(m["RSA"].rsa_starboard) == 20.0
    assert float(m["RPM"].speed) == -40.0
    assert m["RMC"].lat_dir == "S" and m["RMC"].lon_dir == "W"
    assert m["RMC"].latitude == pytest.approx(-33.8568, abs=2e-6)
    assert m["GGA"].longitude == pytest.approx(-151.2153, abs=2e-6)


def test_unknown_values_are_empty_fields_with_status_v():
    r = make_reading(rot_dpm=math.nan, rudder_deg=math.inf, wind_rel_speed_kn=math.nan, rpm=math.nan)
    lines = nmea.own_ship_sentences(r, UTC)
    assert "$IIROT,,V*" in "".join(lines)
    assert "$IIRSA,,V,,V*" in "".join(lines)
    assert "$IIRPM,S,0,,,V*" in "".join(lines)
    assert "$IIMWV,40.0,R,,N,V*" in "".join(lines)
    no_fix = nmea.own_ship_sentences(make_reading(lat_deg=math.nan), UTC)
    rmc = pynmea2.parse(no_fix[0].strip())
    assert rmc.status == "V" and rmc.lat == ""
    assert pynmea2.parse(no_fix[1].strip()).gps_qual == 0


def test_talkers_are_configurable_and_validated():
    talkers = nmea.Talkers(gnss="GN", heading="HE", log="VW", steering="AG", engine="ER", wind="WI")
    heads = [line[1:6] for line in nmea.own_ship_sentences(make_reading(), UTC, talkers)]
    assert heads == ["GNRMC", "GNGGA", "GNVTG", "HEHDT", "HEROT", "AGRSA", "ERRPM", "VWVHW", "WIMWV"]
    with pytest.raises(ValueError, match="heading"):
        nmea.Talkers(heading="H")
    with pytest.raises(ValueError, match="gnss"):
        nmea.Talkers(gnss="gp")


def test_random_readings_always_frame_and_parse():
    rng = np.random.default_rng(7)
    for _ in range(400):
        r = make_reading(
            lat_deg=float(rng.uniform(-89.99, 89.99)),
            lon_deg=float(rng.uniform(-180.0, 180.0)),
            hdg_deg=float(rng.uniform(0.0, 360.0)),
            cog_deg=float(rng.uniform(0.0, 360.0)),
            sog_kn=float(rng.uniform(0.0, 40.0)),
            stw_kn=float(rng.uniform(-10.0, 40.0)),
            rot_dpm=float(rng.uniform(-700.0, 700.0)),
            rudder_deg=float(rng.uniform(-45.0, 45.0)),
            rpm=float(rng.uniform(-300.0, 300.0)),
            wind_rel_angle_deg=float(rng.uniform(0.0, 360.0)),
            wind_rel_speed_kn=float(rng.uniform(0.0, 80.0)),
        )
        lines = nmea.own_ship_sentences(r, UTC, gll_sentence=True, zda_sentence=True)
        m = _by_type(lines)
        assert all(len(line) <= 82 and nmea.verify(line) for line in lines)
        assert m["RMC"].latitude == pytest.approx(r.lat_deg, abs=1e-6)
        lon = m["RMC"].longitude
        assert lon == pytest.approx(r.lon_deg, abs=1e-6) or abs(abs(lon) - 180.0) < 1e-6
        assert float(m["RMC"].spd_over_grnd) == pytest.approx(r.sog_kn, abs=0.005)
        assert (float(m["HDT"].heading) - r.hdg_deg + 180.0) % 360.0 - 180.0 == pytest.approx(0.0, abs=0.05)
        assert float(m["ROT"].rate_of_turn) == pytest.approx(r.rot_dpm, abs=0.05)
        assert float(m["RSA"].rsa_starboard) == pytest.approx(r.rudder_deg, abs=0.05)


# -- datagrams -----------------------------------------------------------------------------------------------


def test_pack_datagrams_keeps_whole_sentences():
    lines = nmea.own_ship_sentences(make_reading(), UTC) * 20  # 180 sentences, ~6 kB
    datagrams = nmea.pack_datagrams(lines, max_bytes=1400)
    assert len(datagrams) > 1
    assert all(len(d) <= 1400 for d in datagrams)
    assert b"".join(datagrams).decode() == "".join(lines)
    for d in datagrams:
        assert d.endswith(b"\r\n")
        assert all(nmea.verify(s) for s in d.decode().split("\r\n") if s)
    assert nmea.pack_datagrams([]) == []
    assert nmea.pack_datagrams(lines[:3], max_bytes=82) == [s.encode() for s in lines[:3]]


def test_pack_datagrams_rejects_unterminated_or_oversized():
    with pytest.raises(ValueError, match="CRLF"):
        nmea.pack_datagrams(["$IIHDT,1.0,T*00"])
    with pytest.raises(ValueError, match="does not fit"):
        nmea.pack_datagrams(["$IIHDT,123.4,T*26\r\n"], max_bytes=10)


def test_heel_goes_out_as_xdr_roll_and_pashr_only_for_a_ship_with_roll():
    """A 3-DOF reading (roll None) keeps the nine-sentence cycle; with roll, PASHR and XDR (A, D, ROLL) join it,
    both read back by pynmea2 with the heel's sign (+ = starboard side down)."""
    assert len(nmea.own_ship_sentences(make_reading(), UTC)) == 9
    lines = nmea.own_ship_sentences(make_reading(roll_deg=-2.5, roll_rate_dps=0.4), UTC)
    heads = [line[1:6] for line in lines]
    # PASHR just before HDT (gpsd 3.22 reports the heel with HDT's ATT), XDR last
    assert heads == ["GPRMC", "GPGGA", "GPVTG", "PASHR", "IIHDT", "IIROT", "IIRSA", "IIRPM", "IIVHW", "IIMWV", "IIXDR"]
    assert lines[3] == "$PASHR,123456.78,123.40,T,-2.50,,,,,,1,*19\r\n"
    assert lines[10] == "$IIXDR,A,-2.50,D,ROLL*62\r\n"
    for line in lines:
        assert nmea.verify(line) and len(line) <= 82
    x = pynmea2.parse(lines[10].strip(), check=True)
    assert x.sentence_type == "XDR" and x.get_transducer(0) == ("A", "-2.50", "D", "ROLL")
    p = pynmea2.parse(lines[3].strip(), check=True)
    assert type(p).__name__ == "ASHRATT" and p.is_true_heading == "T"
    assert (p.true_heading, p.roll, p.pitch) == (123.4, -2.5, None)  # the model has no pitch: empty
    starboard_down = nmea.own_ship_sentences(make_reading(roll_deg=7.891, roll_rate_dps=0.0), UTC)
    assert starboard_down[10].startswith("$IIXDR,A,7.89,D,ROLL*")
