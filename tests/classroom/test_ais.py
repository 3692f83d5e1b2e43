"""A student sees the other ships as its own ship's AIS receiver has them (``envs.tasks.colreg_ais``: the
reporting intervals of ITU-R M.1371-5 Annex 1 Table 1, SOG and COG rounded to the report's resolution, dead
reckoning between reports); the instructor sees the truth."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from vessel_gym.classroom.harbour import ClassHarbour
from vessel_gym.envs.task import start
from vessel_gym.physics.units import KNOT_M_S

from .conftest import recv_type


def _truth_cog_deg(h: ClassHarbour, k: int) -> float:
    vn, ve = h.sim.ground_velocity()
    return math.degrees(math.atan2(float(ve[k]), float(vn[k]))) % 360.0


def test_the_other_ship_is_its_last_report_dead_reckoned_and_stale_between_reports():
    """Ship 2 turns hard to starboard at about 2 kn beside ship 1: a Class A station under 14 kn changing
    course reports every 3 1/3 s (Table 1). Between two reports ship 1's picture of it keeps the report's SOG
    and COG and moves along them, while the true course swings on."""
    h = ClassHarbour("harbour", 2, seed=3)
    start(h.task, 0, 1.0, 0.0, x_m=-100.0, y_m=0.0)
    start(h.task, 1, 1.0, 0.0, x_m=-100.0, y_m=30.0)
    first = {a["name"]: a for a in h.ais_picture(0)}["Ship 2"]
    assert (first["n"], first["e"], first["age_s"]) == (pytest.approx(-100.0), pytest.approx(30.0), 0.0)
    h.order(1, 35.0, 2)
    rows = []
    for _ in range(60):  # 15 s
        h.step()
        a = {x["name"]: x for x in h.ais_picture(0)}["Ship 2"]
        rows.append((h.t_s, a, _truth_cog_deg(h, 1), float(h.sim.north[1]), float(h.sim.east[1])))
    report_t = sorted({round(t - a["age_s"], 2) for t, a, *_ in rows})
    turning = abs(math.degrees(float(h.sim.r[1])) * 60.0) > 5.0
    assert turning and len(report_t) >= 4
    # reports 3 1/3 s apart once the turn is established (the first interval was drawn at random within it)
    assert np.diff(report_t[1:]) == pytest.approx(10.0 / 3.0, abs=0.02)
    for _t, a, *_ in rows:
        assert a["age_s"] <= 10.0 / 3.0 + 1e-6
        sog_kn = math.hypot(a["vn"], a["ve"]) / KNOT_M_S
        assert sog_kn == pytest.approx(round(sog_kn, 1), abs=1e-6)  # the report's 0.1 kn resolution
    # the last stretch between two reports: the picture holds the report's COG and SOG, moves along them by its
    # age, and falls behind the truth, which turns on
    t_r = report_t[-2]
    span = [
        r for r in rows if t_r <= r[0] - r[1]["age_s"] + 1e-6 and r[0] - r[1]["age_s"] < report_t[-1] - 1e-6
    ]
    assert len(span) >= 12
    (t0, a0, cog0, *_), (t1, a1, cog1, n1, e1) = span[0], span[-1]
    assert a1["cog"] == a0["cog"] and a1["sog"] == a0["sog"]
    assert cog1 - cog0 > 3.0  # the true course changed meanwhile
    c = math.radians(a0["cog"])
    assert a1["n"] - a0["n"] == pytest.approx(a0["sog"] * math.cos(c) * (t1 - t0), abs=2e-3)
    assert a1["e"] - a0["e"] == pytest.approx(a0["sog"] * math.sin(c) * (t1 - t0), abs=2e-3)
    stale = math.hypot(a1["n"] - n1, a1["e"] - e1)
    fresh = min(math.hypot(a["n"] - n, a["e"] - e) for _t, a, _c, n, e in rows if a["age_s"] < 0.25)
    assert stale > 0.05 and fresh < 0.02 and stale > 3 * fresh
    # the targets list reads the same picture: the report's age, the dead-reckoned range
    _t, last, _c, n_now, e_now = rows[-1]
    radar = {t["name"]: t for t in h.targets_for(0)}["Ship 2"]
    assert radar["age_s"] == last["age_s"]
    own = (float(h.sim.north[0]), float(h.sim.east[0]))
    assert radar["range_m"] == pytest.approx(math.hypot(last["n"] - own[0], last["e"] - own[1]), abs=0.06)
    # the instructor's list is the truth
    truth = h.ships()[1]
    assert (truth["n"], truth["e"]) == (pytest.approx(n_now, abs=1e-3), pytest.approx(e_now, abs=1e-3))


def test_a_student_page_gets_the_others_over_ais_and_the_instructor_the_truth(room):
    r = room(ships=2, time_factor=4.0)
    ws, welcome = r.join(r.codes.helm[0], "Ann")
    assert welcome["type"] == "welcome"
    teacher, _ = r.join(r.codes.instructor)
    for _ in range(8):
        st = recv_type(ws, ("state",))
    assert [s["k"] for s in st["ships"]] == [0] and "targets" not in st  # no truth of the others
    names = {a["name"] for a in st["ais"]}
    assert {"Ship 2", "KVLCC2 LOOP", "KVLCC2 PIER"} <= names
    for a in st["ais"]:
        assert a["age_s"] >= 0.0 and {"n", "e", "sog", "cog", "L", "B"} <= set(a)
    assert all("age_s" in t for t in st["radar"])
    # the picture sent is the receiver's at that time (the state goes out after the step it describes)
    got = r.srv.call(lambda: (r.harbour.t_s, r.harbour.ais_picture(0)))
    if got[0] == st["t_s"]:
        sent = {a["name"]: (a["n"], a["e"]) for a in st["ais"]}
        assert sent == {a["name"]: (a["n"], a["e"]) for a in json.loads(json.dumps(got[1]))}
    st_t = recv_type(teacher, ("state",))
    assert [s["k"] for s in st_t["ships"]] == [0, 1] and "ais" not in st_t
    assert {t["name"] for t in st_t["targets"]} == {"KVLCC2 LOOP", "KVLCC2 PIER"}
