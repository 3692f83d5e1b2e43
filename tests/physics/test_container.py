"""The built-in ``container`` ship (Son & Nomoto 1982, 4 DOF) against an independent transcription of Fossen's
MSS ``container.m`` (tests/physics/container_reference.py): turning circle, 20/20 zig-zag and heel in a turn.

Both models start from the same state: our ship at its test speed with the shaft speed the steady approach
found, the transcription at that speed and shaft speed. They then differ only where the ship file maps
container.m onto this project's components (documented in the file's notes and docs/physics.md):
the engine holds the ordered rpm through a governor (container.m: a first-order lag, which holds it
exactly), the restoring moment is GM sin(phi) (container.m: GM phi, 0.3 % less at 8 deg), g = 9.80665 m/s^2
and the mass m' 1/2 rho L^3 (container.m: 9.81 and rho nabla, together 4e-4), the rudder angle is the steering
gear's exact solution at each stage (container.m: integrated by the same RK4). Each of these moves a
distance of the turn by well under 0.5 %, hence the tolerances: 1 % on distances, 2 % and 0.1 deg on heel,
0.3 deg on overshoots (the transcription's heading is checked every 0.05 s, at up to 1 deg/s of yaw).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from container_reference import container_rhs, rk4

from vessel_gym.manoeuvres.trials import turning_circle, zigzag
from vessel_gym.physics import layout as lo

DEG = math.pi / 180.0
RUDDER_LIMIT_DEG = 35.0  # the ship file's steering gear; container.m's own 10 deg is its autopilot demo's
DT_REF = 0.05  # s, the trials' step for this ship (trial_dt: L/V/400 rounded down)


def _reference_start(track_rows: np.ndarray) -> tuple[np.ndarray, float]:
    """container.m's state at our trial's first row: same u, shaft speed in rpm; the rest 0."""
    u0 = track_rows[0, lo.X_U]
    n_rpm = track_rows[0, lo.X_REV] * 60.0
    return np.array([u0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, n_rpm]), n_rpm


def _reference_turn(x0: np.ndarray, n_rpm: float, rudder_deg: float, until_rad: float):
    """RK4 of the transcription with the rudder order held until the heading has changed ``until_rad``.
    Returns (advance, tactical diameter, max |phi|, phi at the end, first phi extremum), m and rad."""
    x = x0.copy()
    advance = tactical = None
    phi_max = 0.0
    first_peak = None
    prev = 0.0
    while abs(x[5]) < until_rad:
        x_new = rk4(x, [rudder_deg * DEG, n_rpm], DT_REF, RUDDER_LIMIT_DEG)
        if advance is None and abs(x_new[5]) >= math.pi / 2:
            f = (math.pi / 2 - abs(x[5])) / (abs(x_new[5]) - abs(x[5]))
            advance = x[3] + f * (x_new[3] - x[3])
        if tactical is None and abs(x_new[5]) >= math.pi:
            f = (math.pi - abs(x[5])) / (abs(x_new[5]) - abs(x[5]))
            tactical = abs(x[4] + f * (x_new[4] - x[4]))
        if first_peak is None and abs(x_new[7]) < abs(x[7]) and abs(x[7]) > 1e-4 and prev * x[6] >= 0:
            first_peak = x[7]
        prev = x[6]
        phi_max = max(phi_max, abs(x_new[7]))
        x = x_new
    return advance, tactical, phi_max, x[7], first_peak


@pytest.fixture(scope="module")
def turn35():
    return turning_circle("container", 35.0)


def test_straight_running_matches_the_transcription(turn35):
    """At our test speed and shaft speed container.m is in equilibrium too: hull resistance, thrust, wake and
    thrust deduction are mapped one to one."""
    x0, n_rpm = _reference_start(np.asarray(turn35.track._rows))
    xdot, U = container_rhs(x0, [0.0, n_rpm])
    assert U == pytest.approx(7.0, rel=1e-3)  # 13.6 kn, the ship file's test speed
    assert abs(xdot[0]) < 1e-4  # m/s^2: a 1e-4 imbalance would change the speed 0.6 % in a minute
    assert np.all(xdot[[1, 2, 4, 5, 6, 7, 8]] == 0.0) and abs(xdot[9]) < 1e-9  # xdot[3] = u, the x-position rate


def test_turning_circle_and_heel_match_the_transcription(turn35):
    rows = np.asarray(turn35.track._rows)
    x0, n_rpm = _reference_start(rows)
    adv, tac, phi_max, phi_end, first = _reference_turn(x0, n_rpm, 35.0, 4.0 * math.pi)
    # 575 m and 731 m (3.29 L, 4.18 L) in both; MSC.137(76) limits 4.5 L and 5 L
    assert turn35.advance_m == pytest.approx(adv, rel=0.01)
    assert turn35.tactical_diameter_m == pytest.approx(tac, rel=0.01)
    phi = rows[:, lo.X_PHI]
    # maximum heel (7.9 deg, outward, in the first half-turn) and the steady heel after 720 deg (2.1 deg)
    assert np.abs(phi).max() == pytest.approx(phi_max, rel=0.02, abs=0.1 * DEG)
    assert phi[-1] == pytest.approx(phi_end, rel=0.02, abs=0.1 * DEG)
    # Son & Nomoto's coupled steering and rolling: the rudder's sway force below G first heels the ship
    # into the turn (starboard, phi > 0), then the turn heels it outward (port)
    assert first > 0.0 and phi[np.argmax(np.abs(phi) > 0.05 * DEG)] > 0.0
    assert phi[-1] < 0.0 and phi_end < 0.0


def test_turning_circle_reports_heel(turn35):
    """--json keys of a 4-DOF ship: the heel at its largest magnitude, signed as phi (outward, to port, in a
    starboard turn), and the mean heel of the steady turn."""
    d = turn35.to_dict()
    phi = np.degrees(np.asarray(turn35.track._rows)[:, lo.X_PHI])
    assert d["max_heel_deg"] == pytest.approx(phi[np.argmax(np.abs(phi))]) and d["max_heel_deg"] < -7.0
    assert 0.0 < d["max_heel_time_s"] < turn35.time_to_180_s
    assert -2.5 < d["steady_heel_deg"] < -1.5  # 2.1 deg at the end of the turn


def test_a_three_dof_result_has_no_heel_keys():
    d = turning_circle("mariner", 35.0, until_deg=180.0).to_dict()
    assert not [k for k in d if "heel" in k]


def _reference_zigzag(x0: np.ndarray, n_rpm: float, angle_deg: float, n_overshoots: int) -> list[float]:
    """A zig-zag of the transcription, first execute to starboard: overshoot angles in degrees."""
    x = x0.copy()
    side = 1.0
    overshoots: list[float] = []
    extreme = None
    while len(overshoots) < n_overshoots:
        x = rk4(x, [side * angle_deg * DEG, n_rpm], DT_REF, RUDDER_LIMIT_DEG)
        psi = x[5] / DEG
        if side > 0 and psi >= angle_deg or side < 0 and psi <= -angle_deg:
            side = -side
            extreme = -side  # the swing continues to the side the rudder just left
        if extreme is not None and x[2] * extreme <= 0.0:
            overshoots.append(abs(psi) - angle_deg)
            extreme = None
    return overshoots


def test_zigzag_20_20_overshoots_match_the_transcription():
    zz = zigzag("container", 20.0)
    x0, n_rpm = _reference_start(np.asarray(zz.track._rows))
    ref = _reference_zigzag(x0, n_rpm, 20.0, 2)
    assert zz.overshoot_deg[:2] == pytest.approx(ref, abs=0.3)
    # the largest heel of the zig-zag (7.4 deg to port at 55 s, just after the second execute), signed as phi
    phi = np.degrees(np.asarray(zz.track._rows)[:, lo.X_PHI])
    d = zz.to_dict()
    assert d["max_heel_deg"] == pytest.approx(phi[np.argmax(np.abs(phi))])
    assert 5.0 < abs(d["max_heel_deg"]) < 10.0


def test_hard_turn_at_26_kn_leaves_the_roll_model_in_both():
    """GM is 0.3 m: at 26 kn a 35 deg turn heels the ship past 40 deg, where the roll model ends
    (runaway.RUNAWAY_HEEL_DEG); the trial stops there and says so. The transcription, started from the same
    state, heels past 40 deg too, within the same half-minute."""
    from vessel_gym.manoeuvres.trials import ManoeuvreDiverged
    from vessel_gym.physics.simulation import Simulation

    with pytest.raises(ManoeuvreDiverged, match="heel .* exceeds 40 deg") as exc:
        turning_circle("container", 35.0, speed_kn=26.0)
    assert 20.0 < exc.value.t_s < 35.0
    sim = Simulation("container", dt=DT_REF)
    sim.reset(speed_m_s=26.0 * 1852.0 / 3600.0)
    x, n_rpm = _reference_start(sim.state[:1].copy())
    for _ in range(int(35.0 / DT_REF)):
        x = rk4(x, [35.0 * DEG, n_rpm], DT_REF, RUDDER_LIMIT_DEG)
        if abs(x[7]) > 40.0 * DEG:
            break
    assert abs(x[7]) > 40.0 * DEG
