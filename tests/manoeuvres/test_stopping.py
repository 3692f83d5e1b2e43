"""Full-astern stopping (crash stop) of every built-in ship except the environment ships (kvlcc2_l7,
kvlcc2_l7_windage), each against the published reference that applies to a ship of its kind (``container``, a
4-DOF roll model, is not among them).

References:
- IMO Res. MSC.137(76) (2002) §5.3.4: track reach of the full-astern stopping test <= 15 L; an Administration
  may accept more for ships of large displacement, never more than 20 L. It applies to ships of 100 m and over.
- IMO MSC/Circ.1053 (2002), Explanatory notes to the Standards for ship manoeuvrability, Appendix 3 "Stopping
  ability of very large ships": (1) the discretion beyond 15 L "is only likely to be required in the case of
  large tankers"; (2) the longest stop is on a straight track; (3) with hull resistance proportional to the
  square of the speed, R = R_0 (u / V_0)^2, a constant astern thrust T_a and the propeller reversed as rapidly
  as possible, the straight-track stopping distance is

      S = m (1 + k) V_0^2 / (2 R_0) ln(1 + R_0 / T_a),

  m (1 + k) the mass with surge added mass (App. 3 takes T_a as the thrust when the ship is dead in the
  water), plus a term for the time taken to achieve the astern thrust at the initial speed.
- Tani, H. (1968), "The reverse stopping ability of supertankers", Journal of Navigation 21 (Royal Institute of
  Navigation): the head reach of a 100,000 dwt supertanker from service speed, engines full astern and helm
  midships, "may range from 10 L to 15 L"; a larger tanker stops in more lengths (its mass grows as L^3,
  its resistance as L^2).

Each test builds App. 3's bracket from the model's own mass, resistance and propeller (never from a trial
result of the model) and checks the head reach lies inside it, and the MSC.137(76) criterion where it applies.
The figures are reported in docs/physics.md ("Crash stop of the built-in ships").
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from vessel_gym.manoeuvres import stopping
from vessel_gym.manoeuvres.imo import STOPPING_LARGE_SHIP_LIMIT_L, STOPPING_LIMIT_L, stopping_criteria
from vessel_gym.physics.hull import hull_forces
from vessel_gym.physics.params import BODY, PROPELLER
from vessel_gym.physics.propulsion import propeller_thrust_torque
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.vessel import pack

#: the reversing sequence ends (engine or clutch driving astern) within this time of the full-astern order
#: (direct-reversing engine: tests/physics/test_reversal.py; clutch plants: the shaft's run-down), s
REVERSAL_BOUND_S = 60.0

#: Tani (1968): head reach of a 100,000 dwt supertanker from service speed, L
TANI_1968_SUPERTANKER_L = (10.0, 15.0)


def _app3_bracket(name: str, speeds: int = 2) -> tuple[float, float]:
    """(lower, upper) head reach in metres from MSC/Circ.1053 App. 3 with the model's own quantities.

    The astern thrust T_a at full-astern telegraph rpm (after thrust deduction) is evaluated both dead in the
    water and at the approach speed: the larger of the two, with the propeller reversed at once, gives the
    shortest straight stop (lower bound); the smaller, with the approach speed kept over the reversal
    (REVERSAL_BOUND_S), the longest (upper bound). App. 3 calls the straight track the longest stop, so the
    head reach of any track is below the upper bound. ``speeds`` > 2 evaluates T_a at that many speeds from
    dead in the water to the approach speed instead of the two ends: needed where the reversed propeller's
    thrust has its minimum between them (quadrant 2 of the B-series at a light loading, ``kvlcc2_full``).
    """
    ship = load_ship(name)
    P = pack(ship)
    V0 = ship.test_speed_m_s
    R0 = -hull_forces(P, V0, 0.0, 0.0, 0.0)[0]
    scale = P[BODY.m11] * V0**2 / (2.0 * R0)
    n_astern = ship.engine.telegraph_rpm[0] / 60.0
    thrust = [
        -(1.0 - P[PROPELLER.t_P]) * propeller_thrust_torque(P, u_a, n_astern)[0]
        for u_a in np.linspace(0.0, V0 * (1.0 - P[PROPELLER.w_P0]), speeds)
    ]
    assert min(thrust) > 0.0
    low = scale * math.log(1.0 + R0 / max(thrust))
    high = scale * math.log(1.0 + R0 / min(thrust)) + V0 * REVERSAL_BOUND_S
    return low, high


def _check(name: str, speeds: int = 2):
    st = stopping(name)
    low, high = _app3_bracket(name, speeds)
    assert low <= st.head_reach_m <= high, (low / st.L_m, st.head_reach_m / st.L_m, high / st.L_m)
    assert st.track_reach_m >= st.head_reach_m - 1e-6
    return st


def test_kvlcc2_crash_stop_against_msc_circ_1053_appendix_3():
    """VLCC, direct-reversing two-stroke diesel, Wageningen B4-70 four-quadrant propeller. Head reach within
    the App. 3 bracket; no single-screw side force is modelled, so with the rudder midships the track stays
    straight (lateral deviation < 0.01 L). The MSC.137(76) criterion is evaluated; a large tanker may need
    the 20 L an Administration may accept, never more."""
    st = _check("kvlcc2")
    assert abs(st.lateral_deviation_m) < 0.01 * st.L_m
    assert st.track_reach_m == pytest.approx(st.head_reach_m, rel=1e-3)
    (crit,) = stopping_criteria(st)
    assert crit.limit == STOPPING_LIMIT_L
    assert crit.value == pytest.approx(st.track_reach_m / st.L_m)
    assert crit.value <= STOPPING_LARGE_SHIP_LIMIT_L


@pytest.mark.xfail(
    strict=True,
    reason="known gap (docs/physics.md, 'Engine reversal'): the published MMG set's resistance R'_0 = 0.022 "
    "is the model-scale value, about twice a full-scale estimate, so the full-scale KVLCC2 stops in about "
    "half the lengths a real VLCC needs; kvlcc2_full, with a full-scale resistance, does not",
)
def test_kvlcc2_head_reach_where_published_supertanker_stops_lie():
    """Tani (1968): 10-15 L for a 100,000 dwt supertanker; the ~300,000 dwt KVLCC2 should need at least the
    lower figure (a larger tanker stops in more lengths), and MSC/Circ.1053 App. 3 names large tankers as the
    ships that may exceed 15 L. Strict: when the gap is closed this test passes and must lose its mark.
    This is about the `kvlcc2` file, which keeps the published model-scale resistance for the MMG
    validation; the gap is closed in the separate full-scale file `kvlcc2_full`
    (test_kvlcc2_full_head_reach_where_published_supertanker_stops_lie below)."""
    st = stopping("kvlcc2")
    assert st.head_reach_m / st.L_m >= TANI_1968_SUPERTANKER_L[0]


def test_kvlcc2_full_crash_stop_against_msc_circ_1053_appendix_3():
    """The KVLCC2 with a full-scale resistance and an engine sized to it (R_0 1.63 MN, 29 MW, full astern
    -62 rpm; the file's notes). Head reach within the App. 3 bracket, with T_a taken over the whole speed
    range (its minimum lies between dead in the water and the approach speed); straight track, as for
    kvlcc2."""
    st = _check("kvlcc2_full", speeds=81)
    assert abs(st.lateral_deviation_m) < 0.01 * st.L_m
    assert st.track_reach_m == pytest.approx(st.head_reach_m, rel=1e-3)


def test_kvlcc2_full_head_reach_where_published_supertanker_stops_lie():
    """Tani (1968): 10-15 L for a 100,000 dwt supertanker, more lengths for a larger one, so the ~300,000 dwt
    KVLCC2 should need at least the lower figure (the test `kvlcc2` fails). MSC/Circ.1053 App. 3 names large
    tankers as the ships that may need more than the 15 L of MSC.137(76): this one does."""
    st = stopping("kvlcc2_full")
    assert st.head_reach_m / st.L_m >= TANI_1968_SUPERTANKER_L[0]


def test_kvlcc2_full_track_reach_in_the_large_tanker_band():
    """The band a VLCC's crash stop belongs in, from published practice, not from this model: no shorter than
    Tani's (1968) 10 L for a 100,000 dwt supertanker (a larger tanker stops in more lengths), no longer than
    the 20 L an Administration may accept for a ship of large displacement (MSC.137(76) §5.3.4; MSC/Circ.1053
    App. 3: the discretion beyond 15 L is for large tankers). The IMO report evaluates the 15 L criterion and
    names the 20 L discretion. The figure rests on the full-astern revolutions (the file's notes: 79 % of
    rated rpm, from published pilot cards of ships with the same kind of engine); at kvlcc2's 70 % it was
    21.5 L."""
    st = stopping("kvlcc2_full")
    (crit,) = stopping_criteria(st)
    assert crit.value == pytest.approx(st.track_reach_m / st.L_m)
    assert TANI_1968_SUPERTANKER_L[0] <= crit.value <= STOPPING_LARGE_SHIP_LIMIT_L
    assert crit.limit == STOPPING_LIMIT_L and not crit.passed
    assert "20 L" in crit.note


def test_mariner_crash_stop_against_msc_137_and_appendix_3():
    """Mariner-class cargo liner (L 161 m, 15 kn; geared steam turbine with an astern turbine, modelled as the
    clutch plant with astern torque 0.4 of ahead). Not a large tanker, so App. 3 expects the 15 L of
    MSC.137(76) to be met; head reach within the App. 3 bracket. The published Abkowitz set carries the
    trial ship's asymmetry (bias terms Y_0, N_0), so the track veers to one side: the lateral deviation is
    nonzero but stays below the head reach."""
    st = _check("mariner")
    (crit,) = stopping_criteria(st)
    assert crit.value <= STOPPING_LIMIT_L
    assert 0.0 < abs(st.lateral_deviation_m) < st.head_reach_m


def test_dtc_crash_stop_against_msc_137_and_appendix_3():
    """DTC 14,000 TEU container ship at 25 kn (its propulsion plant is not published; the file keeps the
    instant clutch reversal, docs/physics.md). Not a large tanker: App. 3 expects the 15 L of MSC.137(76)
    to be met; head reach within the App. 3 bracket; symmetric model, straight track."""
    st = _check("dtc")
    (crit,) = stopping_criteria(st)
    assert crit.value <= STOPPING_LIMIT_L
    assert abs(st.lateral_deviation_m) < 0.01 * st.L_m


def test_supply_crash_stop_against_appendix_3():
    """76 m offshore supply vessel at its 6 kn test speed: non-reversible medium-speed diesels reversing
    through a reversing reduction gear with friction clutches (physics/components/gearbox.py: the ahead clutch
    released, the engine to idle, the astern clutch applied over its engagement time once the interlock
    allows, slipping until it holds). MSC.137(76) applies to ships of 100 m and over only, and no published
    stopping trial of a supply vessel was found, so the reference is MSC/Circ.1053 App. 3's bracket. The
    published linear surge damping makes the resistance far from App. 3's quadratic law at low speed
    (docs/physics.md), so the bracket uses the resistance at the test speed, which overstates R below it: the
    lower bound holds all the more, and the upper bound carries the reversal allowance. The model is
    symmetric (twin screws as one on the centreline), so the track is straight (App. 3's longest stop):
    lateral deviation below 0.01 L and track reach equal to head reach."""
    st = _check("supply")
    assert abs(st.lateral_deviation_m) < 0.01 * st.L_m
    assert st.track_reach_m == pytest.approx(st.head_reach_m, rel=1e-3)
