"""Full-astern stopping (crash stop) of the full-scale KVLCC2 with its direct-reversing diesel.

Reference: IMO MSC/Circ.1053 (2002), Explanatory notes to the Standards for ship manoeuvrability, Appendix 3
"Stopping ability of very large ships": on a straight track, with hull resistance proportional to the square
of the speed, R = R_0 (u / V_0)^2, and a constant astern thrust T_a equal to the thrust when the ship is
finally dead in the water, the stopping distance is

    S = m (1 + k) V_0^2 / (2 R_0) ln(1 + R_0 / T_a),

m (1 + k) the mass with surge added mass. App. 3 takes the propeller as reversed at once; the model's engine
takes its reversal sequence, during which the ship keeps nearly its approach speed.
"""

from __future__ import annotations

import math

import pytest

from vessel_gym.manoeuvres import stopping
from vessel_gym.manoeuvres.imo import STOPPING_LIMIT_L, stopping_criteria
from vessel_gym.physics import layout as lo
from vessel_gym.physics.hull import hull_forces
from vessel_gym.physics.propulsion import propeller_thrust_torque
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.vessel import pack

#: the reversing sequence of the KVLCC2 engine ends within this time (tests/physics/test_reversal.py), s
REVERSAL_BOUND_S = 60.0


def _app3_inputs(ship) -> tuple[float, float, float, float]:
    """(m (1 + k) V_0^2 / (2 R_0) m, R_0 N, T_a N, J_max): App. 3's inputs from the model's own mass, resistance
    and dead-in-water astern thrust at the full-astern telegraph rpm; J_max the propeller's advance ratio
    u_a / (|n| D) at the approach speed and that rpm."""
    P = pack(ship)
    V0 = ship.test_speed_m_s
    R0 = -hull_forces(P, V0, 0.0, 0.0, 0.0)[0]
    n_astern = ship.engine.telegraph_rpm[0] / 60.0
    T, _Q = propeller_thrust_torque(P, 0.0, n_astern)
    T_a = -(1.0 - P[lo.P_TP]) * T
    J_max = V0 * (1.0 - P[lo.P_WP0]) / (abs(n_astern) * P[lo.P_DP])
    return P[lo.P_M11] * V0**2 / (2.0 * R0), R0, T_a, J_max


def test_kvlcc2_crash_stop_against_msc_circ_1053_appendix_3():
    """Head reach between the App. 3 estimate with the ahead-inflow thrust gain of the model's four-quadrant
    propeller (lower bound: the astern thrust with headway is up to 1 + astern_inflow_slope J times the
    dead-in-water thrust, which App. 3 ignores) and the App. 3 estimate plus the approach speed over the
    reversal (upper bound: App. 3 calls the straight track the longest stop). Rudder midships and no
    single-screw side force in the model: the track stays straight (lateral deviation < 0.01 L)."""
    ship = load_ship("kvlcc2")
    scale, R0, T_a, J_max = _app3_inputs(ship)
    S = scale * math.log(1.0 + R0 / T_a)
    gain = 1.0 + ship.propeller.astern_inflow_slope * J_max
    S_low = scale * math.log(1.0 + R0 / (gain * T_a))
    S_high = S + ship.test_speed_m_s * REVERSAL_BOUND_S
    st = stopping("kvlcc2")
    assert S_low <= st.head_reach_m <= S_high, (S_low / st.L_m, st.head_reach_m / st.L_m, S_high / st.L_m)
    assert abs(st.lateral_deviation_m) < 0.01 * st.L_m
    assert st.track_reach_m == pytest.approx(st.head_reach_m, rel=1e-3)
    (crit,) = stopping_criteria(st)  # the MSC.137(76) 15 L criterion is still evaluated
    assert crit.limit == STOPPING_LIMIT_L
    assert crit.value == pytest.approx(st.track_reach_m / st.L_m)
