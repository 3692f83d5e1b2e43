"""Engine reversal: the direct-reversing two-stroke diesel's sequence (fuel off, reversing gear, starting air,
fuel astern) and the clutch plant that other ships keep."""

from __future__ import annotations

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.params import ENGINE, TRANSMISSION
from vessel_gym.physics.propulsion import (
    PHASE_AIR,
    PHASE_FUEL_OFF,
    PHASE_RUNNING,
    PHASE_SHIFTING,
    engine_drive,
    engine_torque,
    governor,
)
from vessel_gym.physics.schema import read_toml
from vessel_gym.physics.shipchecks import ShipFileError
from vessel_gym.physics.shipfile import SHIP_DIR, load_ship, parse_ship
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.vessel import pack

KV = load_ship("kvlcc2")
P_KV = pack(KV)
N_RATED = P_KV[ENGINE.n_e_rated]  # rev/s (gear ratio 1: engine and propeller speed alike)
ASTERN = -80.0 / 60.0  # full astern order, rev/s


def test_kvlcc2_declares_direct_reversing_engine_others_keep_the_clutch():
    assert KV.engine.reversing == "direct_air_start"
    assert P_KV[ENGINE.reversing] == lo.REVERSING_DIRECT_AIR
    for name in ("kvlcc2_l7", "kvlcc2_l7_windage", "mariner", "dtc", "supply"):
        assert load_ship(name).engine.reversing == "clutch"
        assert pack(load_ship(name))[ENGINE.reversing] == lo.REVERSING_CLUTCH


def test_fuel_is_cut_while_the_reversing_gear_shifts():
    """Gear still set ahead (cam between +1 and -1) and an astern order: no fuel, only the engine's drag."""
    for cam in (1.0, 0.3, -0.8):
        q, dcam, _di, fuel, _ne, Q_e, phase = engine_drive(P_KV, 1.5, cam, 0.8, ASTERN)
        assert fuel == 0.0 and phase == PHASE_SHIFTING
        assert dcam < 0.0  # moving towards astern
        assert Q_e < 0.0 and q < 0.0  # drag opposes the ahead rotation
        assert abs(Q_e) <= 0.3 * P_KV[ENGINE.Q_e_rated]


def test_starting_air_only_below_the_air_braking_speed():
    """Gear set astern, shaft windmilling ahead: no air above air_brake_rpm_fraction x rated, air torque
    against the rotation below it (the ship's way keeps the propeller turning ahead)."""
    f_air = KV.engine.air_brake_rpm_fraction
    above = (f_air + 0.05) * N_RATED
    below = (f_air - 0.05) * N_RATED
    *_, fuel, _ne, Q_e, phase = engine_drive(P_KV, above, -1.0, 0.0, ASTERN)
    assert phase == PHASE_FUEL_OFF and fuel == 0.0 and Q_e < 0.0
    assert abs(Q_e) < 0.2 * P_KV[ENGINE.Q_e_rated]  # drag only
    *_, fuel, _ne, Q_e, phase = engine_drive(P_KV, below, -1.0, 0.0, ASTERN)
    assert phase == PHASE_AIR and fuel == 0.0
    assert Q_e == pytest.approx(-KV.engine.starting_air_torque_fraction * P_KV[ENGINE.Q_e_rated])


def test_fuel_astern_only_above_the_firing_speed_and_with_limited_torque():
    f_fire = KV.engine.firing_rpm_fraction
    *_, fuel, _ne, _q, phase = engine_drive(P_KV, -(f_fire - 0.02) * N_RATED, -1.0, 0.0, ASTERN)
    assert phase == PHASE_AIR and fuel == 0.0
    n = -(f_fire + 0.3) * N_RATED
    *_, fuel, n_e, Q_e, phase = engine_drive(P_KV, n, -1.0, 0.5, ASTERN)
    assert phase == PHASE_RUNNING and fuel == 1.0  # far below the ordered speed: full fuel
    full_ahead = engine_torque(P_KV, abs(n_e), 1.0)
    assert Q_e == pytest.approx(-KV.engine.astern_torque_ratio * full_ahead)


def test_clutch_plant_unchanged():
    """Ships that do not declare a reversing engine keep the instant clutch: the drive torque is the governed
    engine torque through the gearbox, signed by the order, as before the reversing engine existed."""
    P = pack(load_ship("kvlcc2_l7"))
    for n, order, g in ((10.0, 12.0, 0.3), (2.0, -12.0, 0.1), (-5.0, -12.0, 0.5), (3.0, 0.0, 0.4)):
        q, dcam, di, fuel, n_e, _qe, _ph = engine_drive(P, n, 0.0, g, order)
        f_ref, di_ref, s, ne_ref = governor(P, n, g, order)
        q_ref = 0.0
        if s != 0.0:
            q_ref = s * P[TRANSMISSION.efficiency] * P[TRANSMISSION.gear_ratio] * engine_torque(P, ne_ref, f_ref)
            q_ref *= P[ENGINE.astern_torque_ratio] if s < 0.0 else 1.0
        assert (q, dcam, di, fuel, n_e) == (q_ref, 0.0, di_ref, f_ref, ne_ref)


def test_crash_stop_sequence_in_time():
    """From the steady approach at 15.5 kn, full astern: the shaft does not turn astern before the reversing
    gear has shifted (about reversal_time_s), fuel stays off until then, and the engine fires astern
    within a minute (the ship's way is then still almost all there)."""
    sim = Simulation("kvlcc2", dt=0.1)
    sim.reset()
    assert sim.state[0, lo.X_CAM] == 1.0
    sim.set_helm(rudder_order_rad=0.0, rev_order=ASTERN)
    t_rev = KV.engine.reversal_time_s
    first_astern = first_fuel = u_fire = None
    while sim.t < 60.0:
        sim.step()
        n = sim.state[0, lo.X_REV]
        if first_astern is None and n < 0.0:
            first_astern = sim.t
        if first_fuel is None and sim.engine(0)["fuel_index"] > 0.0:
            first_fuel, u_fire = sim.t, sim.u[0]
    assert first_astern is not None and first_fuel is not None
    assert first_astern >= 0.9 * t_rev  # the gear's travel takes ~T_rev (exponential end, docs/physics.md)
    assert first_fuel > first_astern
    assert u_fire > 0.9 * KV.test_speed_m_s
    assert sim.state[0, lo.X_REV] < -0.8 * 80.0 / 60.0  # close to full astern rpm


def test_ship_file_rejects_firing_above_air_braking():
    data = read_toml(SHIP_DIR / "kvlcc2.toml")
    data["engine"]["firing_rpm_fraction"] = 0.4
    with pytest.raises(ShipFileError, match=r"\[engine\] firing_rpm_fraction"):
        parse_ship(data, "x.toml")
    data["engine"]["firing_rpm_fraction"] = 0.15
    data["engine"]["reversing"] = "steam"
    with pytest.raises(ShipFileError, match=r"reversing.*not one of"):
        parse_ship(data, "x.toml")


def test_reversing_gear_state_is_appended_after_the_3dof_states():
    """The reversing gear was appended after the governor (and roll after it), so the indices the kernels and
    saved data use stay where they were."""
    assert lo.X_CAM == lo.X_GOV + 1 == 9 and lo.STATE_NAMES[lo.X_CAM] == "reversing_gear"
    assert (lo.X_PHI, lo.X_P) == (lo.X_CAM + 1, lo.X_CAM + 2) and lo.NX == lo.X_P + 1
    assert np.all(np.array([lo.X_U, lo.X_V, lo.X_R, lo.X_N, lo.X_E, lo.X_PSI]) == np.arange(6))


def test_stop_order_keeps_the_gear_and_a_stopped_shaft_at_rest():
    """A stop order cuts the fuel and leaves the reversing gear where it is; a shaft at rest gets no torque
    (the fuel-off drag is made linear through n = 0), so a ship at rest with the engine stopped stays at rest."""
    for cam in (1.0, -1.0):
        q, dcam, _di, fuel, _ne, _qe, phase = engine_drive(P_KV, 0.0, cam, 0.0, 0.0)
        assert (q, dcam, fuel, phase) == (0.0, 0.0, 0.0, PHASE_FUEL_OFF)
    q_small, *_ = engine_drive(P_KV, 1e-6, 1.0, 0.0, 0.0)
    assert q_small < 0.0 and abs(q_small) < 1e-3 * P_KV[ENGINE.Q_e_rated]


def test_astern_then_ahead_again_reverses_the_gear_back():
    """Running astern, an ahead order shifts the gear back and the engine comes ahead through the same
    sequence (mirror of the crash stop)."""
    q, dcam, _di, fuel, _ne, _qe, phase = engine_drive(P_KV, -1.0, -1.0, 0.5, 1.0)
    assert phase == PHASE_SHIFTING and fuel == 0.0 and dcam > 0.0 and q > 0.0  # drag opposes astern rotation
    *_, Q_e, phase = engine_drive(P_KV, -0.1 * N_RATED, 1.0, 0.0, 1.0)
    assert phase == PHASE_AIR and Q_e > 0.0
