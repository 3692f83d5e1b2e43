"""The propeller's four-quadrant open-water model (vessel_gym/physics/propeller4q.py, propulsion.py).

References: Roddy, Hess & Faller (2006), NSWCCD-50-TR-2006/004 (the B4-70 four-quadrant Fourier series);
Oosterveld & van Oossanen (1975), "Further computer-analyzed data of the Wageningen B-screw series", Int.
Shipbuilding Progress 22(251), Table 1 (the K_T, K_Q polynomials at Rn = 2e6, transcribed below as the
independent first-quadrant reference); IMO MSC/Circ.1053 Appendix 3 (the straight-track stopping estimate).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from vessel_gym.manoeuvres import stopping
from vessel_gym.physics.hull import hull_forces
from vessel_gym.physics.params import BODY, PROPELLER
from vessel_gym.physics.propeller4q import BOLLARD_FACTOR, TABLE_NAMES, ct_cq_star
from vessel_gym.physics.propulsion import propeller_thrust_torque
from vessel_gym.physics.schema import read_toml
from vessel_gym.physics.shipchecks import ShipFileError
from vessel_gym.physics.shipfile import load_ship, parse_ship, resolve_ship_path
from vessel_gym.physics.vessel import pack

# Oosterveld & van Oossanen (1975) Table 1: K_T = sum C (J^s) (P/D)^t (A_E/A_0)^u Z^v, rows (C, s, t, u, v)
OOSTERVELD_KT = (
    (0.00880496, 0, 0, 0, 0), (-0.204554, 1, 0, 0, 0), (0.166351, 0, 1, 0, 0),
    (0.158114, 0, 2, 0, 0), (-0.147581, 2, 0, 1, 0), (-0.481497, 1, 1, 1, 0),
    (0.415437, 0, 2, 1, 0), (0.0144043, 0, 0, 0, 1), (-0.0530054, 2, 0, 0, 1),
    (0.0143481, 0, 1, 0, 1), (0.0606826, 1, 1, 0, 1), (-0.0125894, 0, 0, 1, 1),
    (0.0109689, 1, 0, 1, 1), (-0.133698, 0, 3, 0, 0), (0.00638407, 0, 6, 0, 0),
    (-0.00132718, 2, 6, 0, 0), (0.168496, 3, 0, 1, 0), (-0.0507214, 0, 0, 2, 0),
    (0.0854559, 2, 0, 2, 0), (-0.0504475, 3, 0, 2, 0), (0.010465, 1, 6, 2, 0),
    (-0.00648272, 2, 6, 2, 0), (-0.00841728, 0, 3, 0, 1), (0.0168424, 1, 3, 0, 1),
    (-0.00102296, 3, 3, 0, 1), (-0.0317791, 0, 3, 1, 1), (0.018604, 1, 0, 2, 1),
    (-0.00410798, 0, 2, 2, 1), (-0.000606848, 0, 0, 0, 2), (-0.0049819, 1, 0, 0, 2),
    (0.0025983, 2, 0, 0, 2), (-0.000560528, 3, 0, 0, 2), (-0.00163652, 1, 2, 0, 2),
    (-0.000328787, 1, 6, 0, 2), (0.000116502, 2, 6, 0, 2), (0.000690904, 0, 0, 1, 2),
    (0.00421749, 0, 3, 1, 2), (5.65229e-05, 3, 6, 1, 2), (-0.00146564, 0, 3, 2, 2),
)
OOSTERVELD_KQ = (
    (0.00379368, 0, 0, 0, 0), (0.00886523, 2, 0, 0, 0), (-0.032241, 1, 1, 0, 0),
    (0.00344778, 0, 2, 0, 0), (-0.0408811, 0, 1, 1, 0), (-0.108009, 1, 1, 1, 0),
    (-0.0885381, 2, 1, 1, 0), (0.188561, 0, 2, 1, 0), (-0.00370871, 1, 0, 0, 1),
    (0.00513696, 0, 1, 0, 1), (0.0209449, 1, 1, 0, 1), (0.00474319, 2, 1, 0, 1),
    (-0.00723408, 2, 0, 1, 1), (0.00438388, 1, 1, 1, 1), (-0.0269403, 0, 2, 1, 1),
    (0.0558082, 3, 0, 1, 0), (0.0161886, 0, 3, 1, 0), (0.00318086, 1, 3, 1, 0),
    (0.015896, 0, 0, 2, 0), (0.0471729, 1, 0, 2, 0), (0.0196283, 3, 0, 2, 0),
    (-0.0502782, 0, 1, 2, 0), (-0.030055, 3, 1, 2, 0), (0.0417122, 2, 2, 2, 0),
    (-0.0397722, 0, 3, 2, 0), (-0.00350024, 0, 6, 2, 0), (-0.0106854, 3, 0, 0, 1),
    (0.00110903, 3, 3, 0, 1), (-0.000313912, 0, 6, 0, 1), (0.0035985, 3, 0, 1, 1),
    (-0.00142121, 0, 6, 1, 1), (-0.00383637, 1, 0, 2, 1), (0.0126803, 0, 2, 2, 1),
    (-0.00318278, 2, 3, 2, 1), (0.00334268, 0, 6, 2, 1), (-0.00183491, 1, 1, 0, 2),
    (0.000112451, 3, 2, 0, 2), (-2.97228e-05, 3, 6, 0, 2), (0.000269551, 1, 0, 1, 2),
    (0.00083265, 2, 0, 1, 2), (0.00155334, 0, 2, 1, 2), (0.000302683, 0, 6, 1, 2),
    (-0.0001843, 0, 0, 2, 2), (-0.000425399, 0, 3, 2, 2), (8.69243e-05, 3, 3, 2, 2),
    (-0.0004659, 0, 6, 2, 2), (5.54194e-05, 1, 6, 2, 2),
)
#: pitch ratio of each four-quadrant table (all are B4-70: Z = 4, A_E/A_0 = 0.70)
PITCH = {"B4-70 P/D=0.8": 0.8, "B4-70 P/D=1.0": 1.0}


def _wageningen(rows, J, PD, AEA0=0.70, Z=4):
    return sum(c * J**s * PD**t * AEA0**u * Z**v for c, s, t, u, v in rows)


def _with_4q(name="B4-70 P/D=0.8", ship="kvlcc2"):
    s = load_ship(ship)
    return dataclasses.replace(s, propeller=dataclasses.replace(s.propeller, four_quadrant=name))


@pytest.mark.parametrize("name", TABLE_NAMES)
def test_first_quadrant_of_the_series_against_the_wageningen_polynomials(name):
    """Quadrant 1 of the published series against the B-series regression polynomials, J = 0..0.8 (the
    working range of these pitch ratios): K_T = C_T* (pi/8) (J^2 + (0.7 pi)^2), K_Q likewise. The two are
    independent fits of different test sets (the four-quadrant tests of van Lammeren et al. 1969 and the
    1975 regression over the whole series), so they agree only to within their fitting scatter, each a few
    per cent (the truncated 31-term series ripples by about that much in quadrant 1): tolerance 5 % of the
    bollard K_T and 8 % of the bollard K_Q (largest differences found on J = 0..0.8: K_T 3.2 % at P/D 0.8,
    K_Q 5.4 % at P/D 1.0)."""
    PD = PITCH[name]
    code = TABLE_NAMES.index(name) + 1
    kt0 = _wageningen(OOSTERVELD_KT, 0.0, PD)
    kq0 = _wageningen(OOSTERVELD_KQ, 0.0, PD)
    for J in np.linspace(0.0, 0.8, 17):
        ct, cq = ct_cq_star(code, math.atan2(J, 0.7 * math.pi))
        scale = math.pi / 8.0 * (J * J + (0.7 * math.pi) ** 2)
        assert ct * scale == pytest.approx(_wageningen(OOSTERVELD_KT, J, PD), abs=0.05 * kt0), J
        assert cq * scale == pytest.approx(_wageningen(OOSTERVELD_KQ, J, PD), abs=0.08 * kq0), J


@pytest.mark.parametrize("name", TABLE_NAMES)
def test_series_shape_in_the_other_quadrants(name):
    """The published curves' signs: a locked propeller (n = 0) is a drag against the flow and its torque turns
    it as a turbine; bollard astern gives thrust and torque astern, at 0.74 (P/D 0.8) to 0.76 (P/D 1.0) of the
    bollard-ahead thrust (the astern thrust ratio the built-in ships' astern_kt_ratio = 0.74 was taken from)."""
    code = TABLE_NAMES.index(name) + 1
    ct0, cq0 = ct_cq_star(code, 0.0)
    ct90, cq90 = ct_cq_star(code, 0.5 * math.pi)
    ctm90, cqm90 = ct_cq_star(code, -0.5 * math.pi)
    ct180, cq180 = ct_cq_star(code, math.pi)
    assert ct0 > 0 and cq0 > 0
    assert ct90 < 0 and cq90 < 0  # ship ahead, propeller locked: drag astern, torque driving the shaft astern
    assert ctm90 > 0 and cqm90 > 0
    assert ct180 < 0 and cq180 < 0
    assert -ct180 / ct0 == pytest.approx(0.745, abs=0.015)
    assert ct_cq_star(code, -math.pi) == pytest.approx((ct180, cq180), abs=1e-12)


def test_continuous_through_n_zero_and_va_zero():
    """T and Q of the KVLCC2 with the four-quadrant curves are continuous where a quadrant changes: n = 0 with
    the ship ahead and astern, V_A = 0 with the propeller ahead and astern (the four points tried from all
    four sides, 1e-7 apart), and vanish at rest."""
    P = pack(_with_4q())
    eps = 1e-7
    for ua, n in ((4.0, 0.0), (-4.0, 0.0), (0.0, 1.5), (0.0, -1.5)):
        ref = propeller_thrust_torque(P, ua, n)
        scale_T, scale_Q = abs(ref[0]), abs(ref[1])
        for du in (eps, -eps):
            for dn in (eps, -eps):
                T, Q = propeller_thrust_torque(P, ua + du, n + dn)
                assert T == pytest.approx(ref[0], abs=1e-5 * scale_T), (ua, n, du, dn)
                assert Q == pytest.approx(ref[1], abs=1e-5 * scale_Q), (ua, n, du, dn)
    assert propeller_thrust_torque(P, 0.0, 0.0) == (0.0, 0.0)
    T, Q = propeller_thrust_torque(P, -1e-9, -1e-9)
    assert abs(T) < 1e-6 and abs(Q) < 1e-6


def test_first_quadrant_keeps_the_ships_own_curves_and_the_option_is_off_by_default():
    """Quadrant 1 is the ship's published K_T / K_Q (the ahead-speed validation is untouched). The option is
    off by default: the environment ships (kvlcc2_l7, kvlcc2_l7_windage) leave it off, so their parameter
    row has code 0 and the astern_* approximation; the other built-in ships, whose first quadrant is a B4
    propeller (docs/physics.md), name the B4-70 P/D 0.8 table."""
    ship = _with_4q(name="")
    P0, P4 = pack(ship), pack(_with_4q())
    assert P0[PROPELLER.four_quadrant] == 0.0 and P4[PROPELLER.four_quadrant] == 1.0
    for ua, n in ((0.0, 1.75), (4.8, 1.75), (6.0, 0.5), (4.0, 0.0)):
        assert propeller_thrust_torque(P4, ua, n) == propeller_thrust_torque(P0, ua, n)
    for name in ("kvlcc2_l7", "kvlcc2_l7_windage"):
        assert pack(load_ship(name))[PROPELLER.four_quadrant] == 0.0
    for name in ("kvlcc2", "mariner", "dtc", "supply"):
        assert pack(load_ship(name))[PROPELLER.four_quadrant] == 1.0
    # bollard ahead: the ship's own k_0; bollard astern: the series' astern/ahead ratio times the ship's k_0
    n = 1.5
    T_ahead = propeller_thrust_torque(P4, 0.0, n)[0]
    T_astern = propeller_thrust_torque(P4, 0.0, -n)[0]
    ct0, _ = ct_cq_star(1, 0.0)
    ct180, _ = ct_cq_star(1, math.pi)
    assert T_ahead == pytest.approx(P4[BODY.rho_kg_m3] * n * n * P4[PROPELLER.D_m] ** 4 * P4[PROPELLER.k_0], rel=1e-12)
    assert T_astern / T_ahead == pytest.approx(ct180 / ct0, rel=1e-9)
    assert BOLLARD_FACTOR == pytest.approx(math.pi / 8.0 * (0.7 * math.pi) ** 2, rel=1e-15)


def test_unknown_table_is_a_one_line_error_naming_the_key():
    path = resolve_ship_path("kvlcc2")
    data = read_toml(path)
    data["propeller"]["four_quadrant"] = "B5-75 P/D=1.0"
    with pytest.raises(ShipFileError) as exc:
        parse_ship(data, str(path))
    msg = str(exc.value)
    assert "four_quadrant" in msg and "B4-70 P/D=0.8" in msg and "\n" not in msg


def test_kvlcc2_crash_stop_with_the_four_quadrant_propeller():
    """Full astern from 15.5 kn with the B4-70 P/D 0.8 curves: the ship stops on a straight track, and its
    head reach lies within the MSC/Circ.1053 App. 3 bracket built from the model's own resistance R_0 and
    astern thrust (no target): at least S with the dead-in-water thrust T_a and the propeller reversed at
    once (the largest astern thrust this propeller gives at full astern rpm), at most S with the smaller
    thrust at the approach speed plus the approach speed over the reversal sequence (<= 60 s,
    tests/physics/test_reversal.py). The figure is reported in docs/physics.md."""
    ship = _with_4q()
    P = pack(ship)
    V0 = ship.test_speed_m_s
    R0 = -hull_forces(P, V0, 0.0, 0.0, 0.0)[0]
    scale = P[BODY.m11] * V0**2 / (2.0 * R0)
    n_astern = ship.engine.telegraph_rpm[0] / 60.0
    T_dead = -(1.0 - P[PROPELLER.t_P]) * propeller_thrust_torque(P, 0.0, n_astern)[0]
    T_way = -(1.0 - P[PROPELLER.t_P]) * propeller_thrust_torque(P, V0 * (1.0 - P[PROPELLER.w_P0]), n_astern)[0]
    assert 0.0 < T_way < T_dead  # with headway the reversed propeller gives less thrust (quadrant 2)
    S_low = scale * math.log(1.0 + R0 / T_dead)
    S_high = scale * math.log(1.0 + R0 / T_way) + V0 * 60.0
    st = stopping(ship)
    assert S_low <= st.head_reach_m <= S_high, (S_low / st.L_m, st.head_reach_m / st.L_m, S_high / st.L_m)
    assert abs(st.lateral_deviation_m) < 0.01 * st.L_m
