"""Scripted traffic: [[traffic]] entries in scenario files, route following, targets, lazy simulation."""

from __future__ import annotations

import numpy as np
import pytest

from vessel_gym.net.protocol import Target
from vessel_gym.physics.units import KNOT_M_S
from vessel_gym.scenarios import ScenarioError, load_scenario
from vessel_gym.scenarios.scenario import SCENARIO_DIR, TrafficShip
from vessel_gym.scenarios.traffic import Traffic

HARBOUR = (SCENARIO_DIR / "harbour.toml").read_text()


def _ship(**kw) -> TrafficShip:
    kw.setdefault("name", "TEST SHIP")
    kw.setdefault("start_m", (0.0, 0.0))
    kw.setdefault("speed_kn", 1.5)
    return TrafficShip(**kw)


def test_harbour_has_traffic_with_ais_identities():
    sc = load_scenario("harbour")
    assert [t.name for t in sc.traffic] == ["KVLCC2 LOOP", "KVLCC2 PIER"]
    tr = Traffic.from_scenario(sc)
    targets = tr.targets()
    assert [t.id for t in targets] == [1, 2]
    assert all(isinstance(t, Target) and t.mmsi for t in targets)
    loop, pier = targets
    assert loop.length_m == pytest.approx(7.0) and loop.beam_m == pytest.approx(1.27)
    assert loop.reading.sog_kn == pytest.approx(1.5, abs=0.05)
    assert (loop.reading.x_m, loop.reading.y_m) == pytest.approx((-20.0, 0.0))
    assert pier.reading.sog_kn == pytest.approx(0.0, abs=1e-6) and pier.nav_status == 5  # moored
    # lat/lon about the scenario's reference point
    assert loop.reading.lat_deg == pytest.approx(54.33 - 20.0 / 111_200.0, abs=2e-6)


def test_scenario_without_traffic_gives_none(tmp_path):
    text = HARBOUR[: HARBOUR.index("# Other ships")]
    p = tmp_path / "quiet.toml"
    p.write_text(text)
    assert Traffic.from_scenario(load_scenario(p)) is None


def test_route_followed_with_small_heading_error_after_settling():
    # north, a dog-leg to the north-east, north again: the ship settles on each leg
    tr = Traffic([_ship(route_m=((60.0, 0.0), (160.0, 60.0), (400.0, 60.0)), at_end="stop")])
    legs: dict[int, list[tuple[float, float]]] = {0: [], 1: [], 2: []}
    for _ in range(int(400 / 0.25)):
        tr.step()
        legs[int(tr.wp[0])].append((float(tr.heading_error_deg()[0]), float(tr.cross_track[0])))
    assert not tr.stopped[0] and len(legs[2]) > 600  # more than 150 s on the last leg
    settled = np.array(legs[2][160:])  # from 40 s after the turn
    assert np.max(np.abs(settled[:, 0])) < 3.0  # heading within 3 deg of the line of sight
    assert np.max(np.abs(settled[80:, 1])) < 1.0  # from 60 s: within 1 m of the track
    r = tr.targets()[0].reading
    assert min(r.cog_deg, 360.0 - r.cog_deg) < 3.0  # course over ground along the leg (north)
    assert r.sog_kn == pytest.approx(1.5, rel=0.1)


def test_stop_at_end_stops_engine_and_loop_wraps_around():
    tr = Traffic(
        [
            _ship(name="STOPPER", route_m=((40.0, 0.0),), at_end="stop"),
            _ship(name="LOOPER", start_m=(0.0, 100.0), route_m=((40.0, 100.0), (40.0, 160.0)), at_end="loop"),
        ]
    )
    seen = set()
    for _ in range(int(400 / 0.25)):
        tr.step()
        seen.add(int(tr.wp[1]))
    assert tr.stopped[0] and tr.sim.rev_order[0] == 0.0 and tr.sim.rudder_order[0] == 0.0
    assert tr.targets()[0].reading.telegraph == 0
    assert tr.targets()[0].reading.sog_kn < 0.3  # coasting to a stop
    assert seen == {0, 1} and not tr.stopped[1]


def test_harbour_loop_stays_on_its_route():
    tr = Traffic.from_scenario(load_scenario("harbour"))
    cross = []
    n0, n1, e0, e1 = -140.0, 100.0, -100.0, 100.0
    for i in range(int(600 / 0.25)):  # more than a lap
        tr.step()
        if i > 400:
            cross.append(abs(float(tr.cross_track[0])))
        assert n0 < tr.sim.north[0] < n1 and e0 < tr.sim.east[0] < e1
    assert max(cross) < 7.0  # a sluggish tanker model on 25 m radius turns: within about a ship length
    assert (tr.sim.north[1], tr.sim.east[1]) == pytest.approx((45.0, -47.0), abs=1e-6)  # lies still


def test_lazy_targets_simulate_only_when_read_and_reset_restarts():
    tr = Traffic([_ship(route_m=((100.0, 0.0), (100.0, 50.0)))])
    lazy = tr.lazy_targets(40)
    assert len(lazy) == 1 and tr.steps == 0  # length needs no simulation
    first = list(lazy)[0]
    assert tr.steps == 40 and first.reading.t_s == pytest.approx(10.0)
    assert first.reading.x_m == pytest.approx(1.5 * KNOT_M_S * 10.0, rel=0.05)
    assert lazy[0] is first and tr.targets()[0] is first  # computed once per step
    tr.advance_to(10)  # never backwards
    assert tr.steps == 40
    tr.reset()
    assert tr.steps == 0 and tr.targets()[0].reading.x_m == pytest.approx(0.0)
    assert tr.wp[0] == 0


def test_traffic_speed_the_engine_cannot_make_is_a_one_line_error():
    with pytest.raises(ScenarioError, match=r"traffic\[0\] 'FAST' speed_kn: .*cannot") as exc:
        Traffic([_ship(name="FAST", speed_kn=39.0, route_m=((100.0, 0.0),), at_end="stop")])
    assert "\n" not in str(exc.value)


TRAFFIC0 = 'name = "KVLCC2 LOOP"\nmmsi = 211000101'


@pytest.mark.parametrize(
    "old,new,message",
    [
        (TRAFFIC0, TRAFFIC0 + "\ncolour = 1", r"port\.toml traffic\[0\]: unknown key 'colour'"),
        ("mmsi = 211000102", "mmsi = 211000101", r"traffic\[1\] 'KVLCC2 PIER' mmsi: 211000101 is also used"),
        ("mmsi = 211000101", "mmsi = 2110001010", r"port\.toml traffic\[0\] mmsi: .* outside"),
        ('at_end = "loop"', 'at_end = "circle"', r"traffic\[0\] at_end: 'circle' is not one of"),
        (
            "start_m = [-20.0, 0.0]",
            "start_m = [-20.0, -90.0]",
            r"traffic\[0\] 'KVLCC2 LOOP' start_m: on land",
        ),
        ("start_m = [-20.0, 0.0]", "start_m = [-200.0, 0.0]", r"'KVLCC2 LOOP' start_m: outside bounds_m"),
        ("start_m = [-20.0, 0.0]", "start_m = [-20.0]", r"'KVLCC2 LOOP' start_m: expected \[north, east\]"),
        ("[-20.0, 38.0], [-23.3", "[30.0, 45.0], [-23.3", r"route_m\[0\]: in depth area 'east shoal'"),
        (
            "[-70.0, 38.0], [-70.0",
            "[-70.0, 38.0], [-70.0, -60.0], [-70.0",
            r"route_m\[7\]: in depth area 'outer",
        ),
        (
            "[-23.3, -22.5], [-20.0, -10.0]]",
            "[-23.3, -22.5], [-20.0, -10.0], [20.0, -20.0]]",
            r"route_m\[14\]: the leg to it crosses breakwater 'west breakwater'",
        ),
        ("speed_kn = 1.5", "speed_kn = 0.0", r"'KVLCC2 LOOP' speed_kn: must be > 0 for a ship with a route"),
        (
            'name = "KVLCC2 PIER"\nmmsi',
            'name = "KVLCC2 PIER"\nship = "titanic"\nmmsi',
            r"'KVLCC2 PIER' ship: ",
        ),
        ('name = "KVLCC2 PIER"', 'name = " "', r"traffic\[1\] name: must not be empty"),
    ],
)
def test_bad_traffic_entry_is_one_line_error_naming_file_and_key(tmp_path, old, new, message):
    assert old in HARBOUR
    p = tmp_path / "port.toml"
    p.write_text(HARBOUR.replace(old, new, 1))
    with pytest.raises(ScenarioError, match=message) as exc:
        load_scenario(p)
    assert "\n" not in str(exc.value)
    assert "port.toml" in str(exc.value)
