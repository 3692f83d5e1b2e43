"""The classroom's harbour: several own ships in one batch, spaced starts, contacts between them, one weather,
a ship reset alone, and the debrief scored as play scores a run."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vessel_gym.classroom.debrief import class_debrief_html, student_debrief
from vessel_gym.classroom.harbour import START_SPACING_L, ClassHarbour, hull_gaps
from vessel_gym.envs.task import start
from vessel_gym.ui.play import score


@pytest.fixture(scope="module")
def harbour16():
    return ClassHarbour("harbour", 16, seed=5)


def test_sixteen_ships_start_in_the_start_region_apart(harbour16):
    h = harbour16
    n, e = h.sim.north, h.sim.east
    d = np.hypot(n[:, None] - n[None, :], e[:, None] - e[None, :]) + np.eye(16) * 1e9
    assert d.min() >= START_SPACING_L * h.L - 1e-9  # 8.4 m for the 7 m model
    pts = np.array(h.scenario.start.points)
    assert (n >= pts[:, 0].min()).all() and (n <= pts[:, 0].max()).all()
    assert (e >= pts[:, 1].min()).all() and (e <= pts[:, 1].max()).all()
    assert h.live.all() and {r.outcome for r in h.records} == {"running"}


def test_hull_gaps_of_two_squares():
    sq = np.array([(0, 0), (1, 0), (1, 1), (0, 1), (0, 0.5)], dtype=float)
    gaps = hull_gaps(np.stack([sq, sq + (3.0, 0.0), sq + (3.0, 4.0)]))
    assert gaps[0, 1] == pytest.approx(2.0) and gaps[1, 0] == pytest.approx(2.0)
    assert gaps[0, 2] == pytest.approx(math.hypot(2.0, 3.0))
    assert gaps[1, 2] == pytest.approx(3.0)


def test_two_ships_bow_to_bow_meet_and_both_runs_end_in_contact():
    """Ships 1 and 2 head for each other at 1 m/s on one line, centres 12 m apart: the bows (L/2 = 3.5 m ahead
    of each centre) are 5 m apart and close at about 2 m/s, so contact comes after about 2.5 s; ship 3 sails on."""
    h = ClassHarbour("harbour", 3, seed=2)
    start(h.task, 0, 1.0, 0.0, x_m=-100.0, y_m=0.0)  # north
    start(h.task, 1, 1.0, 180.0, x_m=-88.0, y_m=0.0)  # south, 12 m ahead of ship 1
    start(h.task, 2, 1.0, 0.0, x_m=-100.0, y_m=25.0)
    # as targets: ship 2 dead ahead of ship 1 at 12 m, closing at 2 m/s: CPA 0 m in 6 s
    radar = {t["name"]: t for t in h.targets_for(0)}
    assert radar["Ship 2"]["range_m"] == pytest.approx(12.0, abs=0.05)
    assert radar["Ship 2"]["bearing_deg"] % 360.0 == pytest.approx(0.0, abs=0.5)
    assert radar["Ship 2"]["dcpa_m"] == pytest.approx(0.0, abs=0.3)
    assert radar["Ship 2"]["tcpa_s"] == pytest.approx(6.0, abs=0.3)
    assert radar["Ship 3"]["bearing_deg"] == pytest.approx(90.0, abs=0.5)  # abeam to starboard, 25 m
    assert radar["Ship 3"]["tcpa_s"] <= 0.1  # same course and speed: not closing
    assert {"KVLCC2 LOOP", "KVLCC2 PIER"} <= set(radar)  # the scenario's traffic too
    assert [t["range_m"] for t in h.targets_for(0)] == sorted(t["range_m"] for t in h.targets_for(0))
    ended: list[int] = []
    while not ended and h.t_s < 10.0:
        ended = h.step()
    assert sorted(ended) == [0, 1]
    assert 1.5 <= h.t_s <= 4.0
    r0, r1 = h.records[0], h.records[1]
    assert (r0.outcome, r0.contact_with, r0.contacts) == ("contact", "Ship 2", 1)
    assert (r1.outcome, r1.contact_with) == ("contact", "Ship 1")
    assert r0.min_ship_distance_m == 0.0 and h.live.tolist() == [False, False, True]
    assert h.records[2].min_ship_distance_m == pytest.approx(25.0 - 1.27, abs=1.5)  # beam 1.27 m apart
    # an ended ship gets midships and stop, whatever its helm asks
    h.order(0, 35.0, 4)
    h.step()
    assert float(h.sim.rudder_order[0]) == 0.0 and float(h.sim.rev_order[0]) == 0.0
    # the instructor's reset gives it a new run; ship 3 keeps its
    t3 = h.records[2].start_t_s
    h.reset_ship(0)
    assert h.live[0] and h.records[0].outcome == "running" and h.records[2].start_t_s == t3
    d = np.hypot(h.sim.north - h.sim.north[0], h.sim.east - h.sim.east[0])
    assert np.delete(d, 0).min() >= START_SPACING_L * h.L


def test_orders_and_weather_reach_the_physics():
    h = ClassHarbour("harbour", 2, seed=3)
    h.order(1, -20.0, 4)
    h.step()
    assert math.degrees(float(h.sim.rudder_order[1])) == pytest.approx(-20.0)
    assert float(h.sim.rev_order[1]) == pytest.approx(float(h.task.helm.rev_table[1][8]))  # full ahead
    assert h.conning(1)["telegraph"] == 4 and h.conning(1)["rudder_order_deg"] == -20.0
    assert h.records[1].rudder_effort_deg == 20.0 and h.records[1].engine_changes == 1
    for bad in ((-20.5, 0), (40.0, 0), (0.0, 5), (0.0, -5)):
        with pytest.raises(ValueError):
            h.order(0, *bad)
    h.set_weather(wind_speed_m_s=8.0, wind_from_deg=270.0, current_speed_m_s=0.2)
    for k in range(2):
        e = h.sim.environments[k]
        assert (e.wind_speed_m_s, e.wind_from_deg, e.current_speed_m_s) == (8.0, 270.0, 0.2)
    with pytest.raises(ValueError, match="wind_speed_m_s"):
        h.set_weather(wind_speed_m_s=99.0)
    assert h.sim.environments[0].wind_speed_m_s == 8.0  # a refused weather changes nothing
    h.reset_ship(0)  # a new run keeps the class weather
    assert h.sim.environments[0].wind_speed_m_s == 8.0
    # the conning display: depth under the keel is the chart's depth less the draught
    c = h.conning(0)
    assert c["ukc_m"] == pytest.approx(float(h.task.depth_m[0]) - h.T, abs=1e-3)
    assert c["heading_deg"] == pytest.approx(math.degrees(float(h.sim.heading[0])) % 360.0, abs=1e-3)


def test_debrief_scores_each_student_as_play_does(harbour16):
    h = harbour16
    for _ in range(40):
        h.step()
    d = student_debrief(h, 3)
    rec = h.records[3]
    clearance = min(rec.info["min_clearance_m"], rec.min_ship_distance_m)
    outcome = rec.outcome if rec.outcome != "running" else "time_limit"
    expected = score(
        outcome,
        rec.info["time_s"],
        clearance,
        rec.start_distance_m,
        rec.info["distance_to_goal_m"],
        h.L,
        h.task.U_T,
    )
    assert d.score == pytest.approx(expected) and 0.0 <= d.score <= 100.0
    assert d.time_s == pytest.approx(10.0)  # 40 steps of 0.25 s
    page = class_debrief_html(h)
    assert page.count("<svg") == 17  # the class chart and one per student
    assert page.count("<polyline") == 32  # every track twice
    for k in range(16):
        assert h.names[k] in page
    assert f"{d.score:.0f}</b>" in page


def test_pilot_ships_are_steered_by_the_harbour_pilot():
    """Two of three ships under the task's scripted pilot: it gives its own orders (the rudder moves over
    several steps) and closes on the goal; the student's ship keeps the orders it was given."""
    h = ClassHarbour("harbour", 3, seed=1, pilots=2)
    assert h.names == ["Ship 1", "Pilot 2", "Pilot 3"] and h.pilot_ships.tolist() == [1, 2]
    start = [h.conning(k)["goal_m"] for k in range(3)]
    orders = set()
    for _ in range(400):  # 100 s
        h.step()
        orders.add(h.conning(2)["rudder_order_deg"])
    assert len(orders) >= 3
    for k in (1, 2):
        assert h.records[k].outcome == "running"
        assert h.conning(k)["goal_m"] < start[k] - 40.0  # made good towards the goal
    assert h.conning(0)["rudder_order_deg"] == 0.0  # nobody steered ship 1
    with pytest.raises(ValueError, match="pilots"):
        ClassHarbour("harbour", 2, pilots=3)


def test_a_start_region_too_small_for_the_class_is_refused():
    """supply_base's start region is 180 m x 120 m and its supply ship 76.2 m long: 16 ships cannot start
    1.2 ship lengths apart; 2 can (this also resets part of a batch of a ship with thrusters)."""
    with pytest.raises(ValueError, match="give fewer ships"):
        ClassHarbour("supply_base", 16, seed=1)
    h = ClassHarbour("supply_base", 2, seed=1)
    assert math.hypot(h.sim.north[0] - h.sim.north[1], h.sim.east[0] - h.sim.east[1]) >= START_SPACING_L * h.L
