"""UdpLink over real loopback sockets, with injected time: registration, rates, helm rules, NMEA and AIS."""

from __future__ import annotations

import time
from datetime import datetime, timezone

import pyais
import pynmea2
import pytest

from vessel_gym.net import nmea
from vessel_gym.net import protocol as P
from vessel_gym.net.link import HelmState, LinkConfig, UdpLink

from .helpers import make_reading, moved

SETTLE_S = 0.003  # loopback delivery is immediate; this only absorbs scheduling noise
EPOCH = datetime(2021, 6, 1, 12, 0, 0, tzinfo=timezone.utc)


def _link(**kw) -> UdpLink:
    kw.setdefault("json_bind", ("127.0.0.1", 0))
    kw.setdefault("nmea_destinations", ())
    return UdpLink(LinkConfig(**kw))


def _hello(peer, link, role="viewer", rate=None, **extra):
    """Register like a real client: the first time the whole handshake (serviced at the link's last time, so
    rate counts keep their timeline), later a keep-alive hello echoing the cookie and session."""
    if peer.session is None:
        now = link._last_now if link._last_now is not None else 0.0
        peer.join(link.json_address, lambda: link.service(now, make_reading()), role, rate, **extra)
    else:
        peer.hello(link.json_address, role, rate, **extra)
    time.sleep(SETTLE_S)


def _helm(peer, link, seq, rudder, telegraph=None, rpm=None):
    peer.helm(link.json_address, seq, rudder, telegraph=telegraph, rpm=rpm)
    time.sleep(SETTLE_S)


def _run(link, t0, t1, dt=0.02, reading=None, targets=()):
    """Call service() every dt from t0 (inclusive) to t1 (exclusive); return the last helm state."""
    reading = reading or make_reading()
    state = None
    n = round((t1 - t0) / dt)
    for k in range(n):
        state = link.service(t0 + k * dt, reading, targets)
    return state


# -- configuration --------------------------------------------------------------------------------------------


def test_config_is_strict():
    with pytest.raises(ValueError, match="nmea_rte_hz"):
        LinkConfig.from_dict({"nmea_rte_hz": 5})
    with pytest.raises(ValueError, match="nmea_rate_hz"):
        LinkConfig(nmea_rate_hz=20)
    with pytest.raises(ValueError, match="failsafe"):
        LinkConfig(failsafe="stop")
    with pytest.raises(ValueError, match="json_bind"):
        LinkConfig(json_bind=("127.0.0.1", 70000))
    with pytest.raises(ValueError, match="nmea_destinations"):
        LinkConfig(nmea_destinations=[("127.0.0.1",)])
    with pytest.raises(ValueError, match="allow_remote"):
        LinkConfig(allow_remote="yes")
    with pytest.raises(ValueError, match="max_clients"):
        LinkConfig(max_clients=0)
    cfg = LinkConfig.from_dict(
        {
            "nmea_destinations": [["127.0.0.1", 10110], ["localhost", 10112]],
            "talkers": {"heading": "HE"},
            "limits": {"max_rudder_deg": 30.0},
            "failsafe": "midships_stop",
        }
    )
    assert cfg.nmea_destinations == (("127.0.0.1", 10110), ("localhost", 10112))
    assert cfg.talkers.heading == "HE" and cfg.talkers.gnss == "GP" and cfg.limits.max_rudder_deg == 30.0
    assert LinkConfig().json_bind == ("127.0.0.1", 10120)
    assert LinkConfig().nmea_destinations == (("127.0.0.1", 10110),)


def test_non_loopback_bind_needs_allow_remote():
    with pytest.raises(ValueError, match="allow_remote"):
        UdpLink(LinkConfig(json_bind=("0.0.0.0", 0), nmea_destinations=()))
    with UdpLink(LinkConfig(json_bind=("0.0.0.0", 0), nmea_destinations=(), allow_remote=True)) as link:
        assert link.json_address[1] > 0


def test_close_is_idempotent_and_service_after_close_is_a_no_op():
    link = _link()
    link.service(0.0, make_reading())
    link.close()
    link.close()
    assert link.service(1.0, make_reading()) == HelmState()
    with _link() as other:
        addr = other.json_address
    with pytest.raises(ValueError):
        _ = other.json_address
    with _link(json_bind=addr) as again:  # the port was released
        assert again.json_address == addr


# -- viewers --------------------------------------------------------------------------------------------------


def test_viewer_gets_welcome_and_state_at_its_rate(peers):
    with _link() as link:
        v = peers()
        _hello(v, link, rate=10)
        _run(link, 0.0, 2.0)
        msgs = v.messages()
        welcome = [m for m in msgs if m["type"] == "welcome"]
        states = [m for m in msgs if m["type"] == "state"]
        assert len(welcome) == 1 and welcome[0]["rate_hz"] == 10.0 and welcome[0]["helm"] is False
        assert len(states) == 20  # 10 Hz for 2 s of a 50 Hz loop
        assert [s["seq"] for s in states] == sorted({s["seq"] for s in states})
        assert states[0]["hdg_deg"] == 123.4 and states[0]["helm_ok"] is False
        assert link.stats()["tx_state"] == 20 and link.stats()["clients_joined"] == 1


@pytest.mark.parametrize(("rate", "expected"), [(50, 100), (20, 40), (7, 14), (1000, 100)])
def test_rates_are_exact_on_average(peers, rate, expected):
    with _link() as link:
        v = peers()
        _hello(v, link, rate=rate, name="v")
        # keep-alive every second so the client stays registered for the whole 2 s
        for k in range(2):
            _hello(v, link, rate=rate)
            _run(link, k * 1.0, (k + 1) * 1.0)
        assert len(v.messages("state")) == expected


def test_viewer_dropped_after_3_s_silence(peers):
    with _link() as link:
        v = peers()
        _hello(v, link)
        _run(link, 0.0, 2.9)
        assert len(link.clients) == 1
        _run(link, 2.9, 3.2)
        assert link.clients == []
        assert link.stats()["clients_timed_out"] == 1
        sent = link.stats()["tx_state"]
        _run(link, 3.2, 4.0)
        assert link.stats()["tx_state"] == sent


def test_keepalive_keeps_a_viewer(peers):
    with _link() as link:
        v = peers()
        for k in range(5):
            _hello(v, link)
            _run(link, k * 2.0, (k + 1) * 2.0)
        assert len(link.clients) == 1
        assert link.stats()["clients_timed_out"] == 0


def test_static_destinations_get_state_without_hello(peers):
    listener = peers()
    with _link(json_static_destinations=[listener.address], static_rate_hz=5) as link:
        _run(link, 0.0, 2.0)
        states = listener.messages("state")
        assert len(states) == 10
        assert link.clients == []


def test_bye_unregisters(peers):
    with _link() as link:
        v = peers()
        _hello(v, link)
        _run(link, 0.0, 0.1)
        v.bye(link.json_address)
        time.sleep(SETTLE_S)
        _run(link, 0.1, 0.2)
        assert link.clients == [] and link.stats()["clients_left"] == 1


def test_max_clients_and_token(peers):
    with _link(max_clients=2, token="s3cret") as link:
        a, b, c = peers(), peers(), peers()
        a.send(link.json_address, P.encode_hello("viewer"))  # no token
        b.send(link.json_address, P.encode_hello("viewer", token="wrong"))
        time.sleep(SETTLE_S)
        _run(link, 0.0, 0.04)
        assert link.clients == [] and link.stats()["drop_bad_token"] == 2
        assert a.messages() == [] and b.messages() == []  # a bad token gets no answer at all
        for p in (a, b):
            _hello(p, link, token="s3cret")
        with pytest.raises(AssertionError, match="no session"):
            c.join(link.json_address, lambda: link.service(0.04, make_reading()), tries=2, token="s3cret")
        _run(link, 0.04, 0.08)
        assert len(link.clients) == 2 and link.stats()["drop_too_many_clients"] == 1


def test_stats_on_request_and_periodically(peers):
    with _link(stats_interval_s=1.0) as link:
        v = peers()
        _hello(v, link)
        v.send(link.json_address, b"not json")
        v.send(link.json_address, P.encode_stats_request(v.session))
        time.sleep(SETTLE_S)
        _run(link, 0.0, 0.02)
        stats = v.messages("stats")
        assert len(stats) == 1
        counters = stats[0]["counters"]
        # two hellos of the handshake, the junk and the request
        assert counters["drop_bad_json"] == 1 and counters["rx_datagrams"] == 4 and stats[0]["clients"] == 1
        _hello(v, link)
        _run(link, 0.02, 2.5)
        assert len(v.messages("stats")) == 2  # at 1 s and 2 s
        outsider = peers()
        outsider.send(link.json_address, P.encode_stats_request())
        time.sleep(SETTLE_S)
        _run(link, 2.5, 2.52)
        assert outsider.messages() == [] and link.stats()["drop_unregistered"] == 1


# -- helm -----------------------------------------------------------------------------------------------------


def test_no_helm_by_default(peers):
    with _link() as link:
        h = _run(link, 0.0, 0.5)
        assert h == HelmState() and not h.has_orders and h.owner is None and not h.helm_ok


def test_helm_takes_ownership_and_orders_apply(peers):
    with _link() as link:
        a = peers()
        _hello(a, link, role="helm")
        _helm(a, link, 1, -10.0, telegraph=2)
        h = _run(link, 0.0, 0.1)
        assert h.has_orders and h.helm_ok and not h.failsafe
        assert (h.rudder_order_deg, h.telegraph, h.rpm_order, h.seq) == (-10.0, 2, None, 1)
        assert h.owner == a.address
        assert link.helm == h
        states = a.messages("state")
        assert states[-1]["helm_ok"] is True
        _hello(a, link, role="helm")
        _run(link, 0.1, 0.12)
        assert a.messages("welcome")[-1]["helm"] is True


def test_newest_seq_wins_per_client(peers):
    with _link() as link:
        a = peers()
        _hello(a, link, role="helm")
        for seq, rudder in [(5, 5.0), (3, 3.0), (5, 55.0), (4, 4.0)]:  # out of order and duplicate
            a.helm(link.json_address, seq, rudder, telegraph=1)
        time.sleep(SETTLE_S)
        h = link.service(0.0, make_reading())
        assert h.rudder_order_deg == 5.0 and h.seq == 5
        assert link.stats()["drop_stale_seq"] == 3
        _helm(a, link, 6, 6.0, telegraph=1)
        assert link.service(0.02, make_reading()).rudder_order_deg == 6.0


def test_only_one_owner_and_unregistered_or_viewer_cannot_steer(peers):
    with _link() as link:
        a, b, v, x = peers(), peers(), peers(), peers()
        _hello(a, link, role="helm")
        _hello(b, link, role="helm")
        _hello(v, link, role="viewer")
        _helm(a, link, 1, 10.0, telegraph=1)
        _helm(b, link, 100, -20.0, telegraph=-1)
        _helm(v, link, 1, 30.0, telegraph=4)
        _helm(x, link, 1, 30.0, telegraph=4)
        h = link.service(0.0, make_reading())
        assert h.owner == a.address and h.rudder_order_deg == 10.0 and h.telegraph == 1
        s = link.stats()
        assert (s["drop_not_owner"], s["drop_not_helm"], s["drop_unregistered"]) == (1, 1, 1)


def test_watchdog_hold_then_takeover_by_another_panel(peers):
    with _link() as link:
        a, b = peers(), peers()
        _hello(a, link, role="helm")
        _hello(b, link, role="helm")
        _helm(a, link, 1, -10.0, telegraph=3)
        _helm(b, link, 1, 25.0, telegraph=1)  # dropped: a owns the helm
        assert link.service(0.0, make_reading()).owner == a.address
        h = _run(link, 0.02, 0.98)  # a is silent
        assert h.helm_ok and h.owner == a.address
        h = _run(link, 0.98, 1.08)
        assert not h.helm_ok and h.owner is None and h.failsafe
        assert (h.rudder_order_deg, h.telegraph) == (-10.0, 3)  # "hold" keeps the last order
        assert link.stats()["helm_watchdog"] == 1
        states = b.messages("state")
        assert states[-1]["helm_ok"] is False
        _helm(b, link, 2, 25.0, telegraph=1)
        h = link.service(1.1, make_reading())
        assert h.helm_ok and h.owner == b.address and not h.failsafe
        assert (h.rudder_order_deg, h.telegraph) == (25.0, 1)
        assert link.stats()["helm_takeovers"] == 2
        _helm(a, link, 2, 0.0, telegraph=0)  # the old owner is back: b owns the helm now
        assert link.service(1.12, make_reading()).rudder_order_deg == 25.0


def test_steady_commands_keep_the_helm(peers):
    with _link() as link:
        a = peers()
        _hello(a, link, role="helm")
        for k in range(60):  # 20 Hz commands over a 3 s, 50 Hz loop; hello keep-alive each second
            if k % 20 == 0:
                _hello(a, link, role="helm")
            _helm(a, link, k + 1, float(k % 30), telegraph=2)
            h = _run(link, k * 0.05, (k + 1) * 0.05)
            assert h.helm_ok and h.owner == a.address
        assert link.stats()["helm_watchdog"] == 0


def test_midships_stop_failsafe(peers):
    with _link(failsafe="midships_stop") as link:
        a = peers()
        _hello(a, link, role="helm")
        _helm(a, link, 1, -20.0, telegraph=4)
        assert link.service(0.0, make_reading()).telegraph == 4
        h = _run(link, 0.02, 1.2)
        assert (
            h.failsafe and not h.helm_ok and (h.rudder_order_deg, h.telegraph, h.rpm_order) == (0.0, 0, None)
        )
    with _link(failsafe="midships_stop") as link:
        a = peers()
        _hello(a, link, role="helm")
        _helm(a, link, 1, 15.0, rpm=90.0)
        link.service(0.0, make_reading())
        h = _run(link, 0.02, 1.2)
        assert (h.rudder_order_deg, h.telegraph, h.rpm_order) == (0.0, None, 0.0)


def test_bye_from_owner_releases_with_failsafe(peers):
    with _link() as link:
        a, b = peers(), peers()
        _hello(a, link, role="helm")
        _hello(b, link, role="helm")
        _helm(a, link, 1, 5.0, telegraph=2)
        link.service(0.0, make_reading())
        a.bye(link.json_address)
        time.sleep(SETTLE_S)
        h = link.service(0.02, make_reading())
        assert h.owner is None and h.failsafe and h.rudder_order_deg == 5.0
        assert link.stats()["helm_released"] == 1
        _helm(b, link, 1, -5.0, telegraph=1)
        assert link.service(0.04, make_reading()).owner == b.address


def test_helm_switching_to_viewer_releases(peers):
    with _link() as link:
        a = peers()
        _hello(a, link, role="helm")
        _helm(a, link, 1, 5.0, telegraph=2)
        link.service(0.0, make_reading())
        _hello(a, link, role="viewer")
        assert link.service(0.02, make_reading()).owner is None


def test_clock_going_back_keeps_intervals(peers):
    with _link() as link:
        a = peers()
        _hello(a, link, role="helm")
        _helm(a, link, 1, 5.0, telegraph=2)
        link.service(100.0, make_reading())
        h = link.service(10.5, make_reading())  # episode reset: time jumps back
        assert h.helm_ok
        assert _run(link, 10.5, 11.0).helm_ok
        assert not _run(link, 11.0, 11.6).helm_ok


# -- NMEA and AIS ---------------------------------------------------------------------------------------------


def _target(i, mmsi, **kw):
    r = make_reading(
        lat_deg=53.55 + 0.001 * i, lon_deg=9.99, sog_kn=8.0, cog_deg=300.0, hdg_deg=299.0, rot_dpm=5.0
    )
    return P.Target(id=i, name=f"TARGET {i}", reading=r, length_m=200.0, beam_m=32.0, mmsi=mmsi, **kw)


def _lines(datagrams: list[bytes]) -> list[str]:
    out = []
    for d in datagrams:
        text = d.decode("ascii")
        assert text.endswith("\r\n")
        out += [line for line in text.split("\r\n") if line]
    return out


def test_nmea_cycles_at_rate_to_every_destination(peers):
    rx1, rx2 = peers(), peers()
    with _link(nmea_destinations=[rx1.address, rx2.address], nmea_rate_hz=5, utc_epoch=EPOCH) as link:
        r = make_reading(t_s=0.0)
        for k in range(100):  # 2 s at 50 Hz
            link.service(k * 0.02, moved(r, t_s=k * 0.02))
        for rx in (rx1, rx2):
            datagrams = rx.raw(SETTLE_S)
            assert len(datagrams) == 10  # one datagram per cycle
            lines = _lines(datagrams)
            assert len(lines) == 90
            assert all(len(line) + 2 <= 82 and nmea.verify(line) for line in lines)
            rmc = [pynmea2.parse(line) for line in lines if line.startswith("$GPRMC")]
            assert [m.timestamp.strftime("%H%M%S.%f")[:9] for m in rmc[:3]] == [
                "120000.00",
                "120000.20",
                "120000.40",
            ]
            assert rmc[0].datestamp.isoformat() == "2021-06-01"
        s = link.stats()
        assert s["tx_nmea_datagrams"] == 20 and s["tx_nmea_sentences"] == 90 and s["encode_error"] == 0


def test_nmea_talkers_and_optional_sentences(peers):
    rx = peers()
    talkers = {"heading": "HE"}
    with _link(nmea_destinations=[rx.address], talkers=talkers, nmea_gll=True, nmea_zda=True) as link:
        link.service(0.0, make_reading())
        heads = [line[1:6] for line in _lines(rx.raw(SETTLE_S))]
        assert heads == [
            "GPRMC",
            "GPGGA",
            "GPGLL",
            "GPVTG",
            "GPZDA",
            "HEHDT",
            "HEROT",
            "IIRSA",
            "IIRPM",
            "IIVHW",
            "IIMWV",
        ]


def test_absurd_reading_is_counted_not_raised(peers):
    rx, v = peers(), peers()
    with _link(nmea_destinations=[rx.address]) as link:
        _hello(v, link)
        rx.raw(SETTLE_S)  # the NMEA of the handshake's service call
        h = link.service(1.0, make_reading(sog_kn=1e300, telegraph=float("nan")))
        assert h == HelmState()
        assert link.stats()["encode_error"] == 2 and link.last_error
        assert rx.raw(SETTLE_S) == []


def test_ais_for_targets_type1_and_type5(peers):
    rx = peers()
    targets = [_target(1, 211000001, call_sign="DA01"), _target(2, 211000002), _target(3, None)]
    with _link(
        nmea_destinations=[rx.address],
        nmea_rate_hz=2,
        ais_position_interval_s=1.0,
        ais_static_interval_s=10.0,
        utc_epoch=EPOCH,
    ) as link:
        _run(link, 0.0, 12.0, dt=0.1, reading=make_reading(t_s=0.0), targets=targets)
        lines = _lines(rx.raw(SETTLE_S))
    ais_lines = [line for line in lines if line.startswith("!AIVDM")]
    assert all(len(line) + 2 <= 82 and nmea.verify(line) for line in ais_lines)
    singles = [pyais.decode(line).asdict() for line in ais_lines if line.startswith("!AIVDM,1,1")]
    firsts = [i for i, line in enumerate(ais_lines) if line.startswith("!AIVDM,2,1")]
    statics = [pyais.decode(ais_lines[i], ais_lines[i + 1]).asdict() for i in firsts]
    by_mmsi = {}
    for d in singles:
        by_mmsi.setdefault(d["mmsi"], []).append(d)
    assert set(by_mmsi) == {211000001, 211000002}  # no AIS without an MMSI
    assert all(len(v) == 12 for v in by_mmsi.values())  # 1 s interval over 12 s
    d = by_mmsi[211000001][0]
    assert (
        d["msg_type"] == 1 and d["lat"] == pytest.approx(53.551, abs=2e-6) and d["lon"] == pytest.approx(9.99)
    )
    assert d["speed"] == 8.0 and d["course"] == 300.0 and d["heading"] == 299 and d["turn"] > 0
    # type 5 of each ship at 0 s and again at 10 s
    assert sorted(s["mmsi"] for s in statics) == [211000001] * 2 + [211000002] * 2
    s1 = next(s for s in statics if s["mmsi"] == 211000001)
    assert s1["shipname"] == "TARGET 1" and s1["callsign"] == "DA01"
    assert s1["to_bow"] + s1["to_stern"] == 200 and s1["to_port"] + s1["to_starboard"] == 32


def test_state_carries_targets_and_is_split_for_many(peers):
    v = peers()
    with _link() as link:
        _hello(v, link, rate=50)
        targets = [_target(i, 211000000 + i) for i in range(30)]
        v.messages()  # the state sent while joining
        link.service(0.02, make_reading(), targets)
        states = v.messages("state")
        assert len(states) > 1 and {s["parts"] for s in states} == {len(states)}
        assert sorted(t["id"] for s in states for t in s["targets"]) == list(range(30))
