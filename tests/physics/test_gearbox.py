"""The reversing-gear plant (physics/components/gearbox.py): a non-reversible diesel, a reversing reduction gear
with a friction clutch per direction, a fixed-pitch propeller; the supply vessel's plant.

The clutch's physics is checked against its own defining relations (capacity, stick, engagement time,
interlock); the supply vessel's crash stop against MSC/Circ.1053 Appendix 3 is in
tests/manoeuvres/test_stopping.py.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from vessel_gym.physics.components import compose as cp
from vessel_gym.physics.components.gearbox import (
    C_CAP,
    C_ENGAGE_REV,
    C_ENGAGE_T,
    C_I_E,
    C_IDLE_REV,
    C_LOCK_T,
    C_SHIFT_REV,
    CLUTCH_SET,
    PHASE_ENGAGING,
    PHASE_LOCKED,
    PHASE_SLIPPING,
    PHASE_WAITING,
    ReversingGearbox,
    ReversingGearboxParams,
    gearbox_drive,
)
from vessel_gym.physics.params import ENGINE, TRANSMISSION
from vessel_gym.physics.schema import read_toml
from vessel_gym.physics.shipchecks import ShipFileError
from vessel_gym.physics.shipfile import SHIP_DIR, load_ship
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.vessel import pack

SHIP = load_ship("supply")
(ENTRY,) = [e for e in SHIP.components if e.slot == "engine"]  # the plant (the thrusters are extras)
PLANT = ENTRY.build(SHIP)
C = PLANT.constants
P = cp.compose(SHIP, pack(SHIP), [PLANT], ["engine"])
I_G, ETA, I_S = P[TRANSMISSION.gear_ratio], P[TRANSMISSION.efficiency], P[TRANSMISSION.I_shaft]
Q_RATED = P[ENGINE.Q_e_rated]  # engine side, N m
N_PROP_RATED = P[ENGINE.n_e_rated] / I_G  # rev/s
ASTERN = SHIP.engine.telegraph_rpm[0] / 60.0  # full astern order, rev/s
AHEAD = SHIP.engine.telegraph_rpm[-1] / 60.0


def _slip_rate(n, n_E, c, Q_load, gov=0.5, order=AHEAD):
    q, dn_E, *_rest = gearbox_drive(P, C, n, n_E, gov, c, order, Q_load)
    s = math.copysign(1.0, c)
    dn = (q - Q_load) / (2.0 * math.pi * I_S)  # the kernel's shaft equation (propulsion.shaft_rate)
    return dn_E - s * I_G * dn


def test_supply_chooses_the_plant_in_its_ship_file_and_no_other_ship_does():
    assert ENTRY.slot == "engine" and ENTRY.replace and ENTRY.cls is ReversingGearbox
    for name in ("kvlcc2", "kvlcc2_l7", "kvlcc2_l7_windage", "mariner", "dtc", "container"):
        assert not any(e.cls is ReversingGearbox for e in load_ship(name).components)
    sim = Simulation("supply", dt=0.1)
    assert sim.component_state_names == (
        "ReversingGearbox.engine_speed",
        "ReversingGearbox.governor",
        "ReversingGearbox.clutch",
        "bow_thruster.thrust",  # the tunnel thrusters of the ship file, idle (docs/berthing.md)
        "stern_thruster.thrust",
    )
    assert sim.Ps[0][ENGINE.by_component] == 1.0  # the built-in engine, governor and instant clutch are out
    # the engine's inertia is behind the clutch, in the plant's own equation: the shaft keeps its own
    assert sim.Ps[0][TRANSMISSION.I_shaft] == SHIP.transmission.shaft_inertia_kgm2


def test_clutch_torque_never_exceeds_its_capacity():
    """A clutch slips at |Q_c| = |c| k_cap Q_rated and no more, whatever the slip: propeller windmilling ahead
    while the astern clutch fills, and the astern clutch applied with the engine at idle."""
    for c in (-0.2, -0.6, -1.0):
        for n in (0.1 * N_PROP_RATED, 0.3 * N_PROP_RATED):
            q, _dn_E, _dg, _dc, _f, _QE, Q_c, slip, phase = gearbox_drive(
                P, C, n, C[C_IDLE_REV], 0.3, c, ASTERN, 5e4
            )
            assert slip > 0.0  # engine forwards, astern train: the shaft is dragged back
            assert abs(Q_c) == pytest.approx(abs(c) * C[C_CAP] * Q_RATED, rel=1e-12)
            assert q == pytest.approx(-ETA * I_G * Q_c, rel=1e-12)  # astern drive at the propeller shaft
            assert q < 0.0 and phase in (PHASE_ENGAGING, PHASE_SLIPPING)


def test_a_holding_clutch_keeps_engine_and_shaft_together():
    """Within the capacity, at zero slip the clutch transmits exactly the torque that keeps the engine speed
    i times the shaft speed (slip rate 0 to round-off), and a residual slip decays with lock_time_s."""
    n = 0.6 * N_PROP_RATED
    for Q_load in (0.0, 1.0e5, 2.5e5):
        *_, phase = gearbox_drive(P, C, n, I_G * n, 0.6, 1.0, AHEAD, Q_load)
        assert phase == PHASE_LOCKED
        assert abs(_slip_rate(n, I_G * n, 1.0, Q_load, gov=0.6)) < 1e-9 * I_G * n
        w = 1e-3  # rev/s of slip, engine side
        rate = _slip_rate(n, I_G * n + w, 1.0, Q_load, gov=0.6)
        assert rate == pytest.approx(-w / C[C_LOCK_T], rel=1e-6)


def test_a_clutch_fills_in_its_engagement_time():
    """From released, the astern clutch (interlock satisfied) is applied to within 5 % of full pressure in
    0.9 T + 0.1 T ln 2 = 0.969 T: a fill at 1/T, then the exponential approach of the last tenth."""
    c, t, dt = 0.0, 0.0, 1e-4
    while c > -0.95:
        dc = gearbox_drive(P, C, 0.0, C[C_IDLE_REV], 0.3, c, ASTERN, 0.0)[3]
        c += dc * dt
        t += dt
    T = C[C_ENGAGE_T]
    assert t == pytest.approx((0.9 + 0.1 * math.log(2.0)) * T, rel=2e-3)


@pytest.mark.parametrize(
    ("n_frac", "engine_frac", "applies"),
    [(0.9, 0.2, False), (0.5, 0.3, False), (0.2, 0.8, False), (0.2, 0.3, True), (-0.5, 0.3, True)],
)
def test_interlock_waits_for_the_propeller_and_the_engine(n_frac, engine_frac, applies):
    """Astern ordered, clutches released: the astern clutch is applied only while the propeller turns ahead
    slower than engage_rpm_fraction of rated and the engine runs no faster than shift_rpm_fraction."""
    n = n_frac * N_PROP_RATED
    n_E = engine_frac * P[ENGINE.n_e_rated]
    assert (n <= C[C_ENGAGE_REV] and n_E <= C[C_SHIFT_REV]) == applies
    q, _dn_E, _dg, dc, *_, phase = gearbox_drive(P, C, n, n_E, 0.3, 0.0, ASTERN, 1e5)
    assert q == 0.0  # released: no drive
    if applies:
        assert dc < 0.0 and phase == PHASE_ENGAGING
    else:
        assert dc == 0.0 and phase == PHASE_WAITING


def test_reversal_releases_the_old_clutch_and_idles_the_engine():
    """Full astern ordered while driving ahead: the ahead clutch is released at 1/release_time_s and the
    governor's set point drops to idle (speed error negative at full ahead: fuel falls)."""
    n = 0.7 * N_PROP_RATED
    _q, _dn_E, dgov, dc, fuel, *_ = gearbox_drive(P, C, n, I_G * n, 0.8, 1.0, ASTERN, 2e5)
    assert dc == pytest.approx(-1.0 / SHIP.components[0].params.release_time_s)
    assert dgov <= 0.0 and fuel < 0.8
    # with the order ahead the same state is held (steady running, locked)
    _q, _dn_E, dgov, dc, *_rest, phase = gearbox_drive(P, C, n, I_G * n, 0.8, 1.0, n, 2e5)
    assert dc == 0.0 and dgov == 0.0 and phase == PHASE_LOCKED


def test_steady_approach_is_held():
    """After the reset the plant holds the test speed: no drift of speed, shaft or engine over 60 s."""
    sim = Simulation("supply", dt=0.1)
    sim.reset()
    u0, n0 = sim.u[0], sim.rev[0]
    z0 = sim.component_states[0].copy()
    assert z0[2] == 1.0 and z0[0] == pytest.approx(I_G * n0, rel=1e-12)  # ahead clutch applied, locked
    sim.advance(60.0)
    assert sim.u[0] == pytest.approx(u0, abs=1e-4)
    assert sim.rev[0] == pytest.approx(n0, abs=1e-5)
    assert sim.component_states[0] == pytest.approx(z0, abs=1e-5)


@pytest.mark.parametrize("dt", [0.1, 0.82])  # 0.82 s: the HarbourApproach env's step for this ship
def test_crash_stop_sequence(dt):
    """Full astern from the steady approach: the engine never stalls or reverses, the astern clutch is applied
    within a few seconds (release, run-down below the interlock speeds, engagement time), and the shaft then
    turns astern near the full-astern order (limited by the engine's torque with the ship's headway). The same
    at the longest step the environments take for this ship: the released clutch does not overshoot into the
    other train before the interlock allows it."""
    sim = Simulation("supply", dt=dt)
    sim.reset()
    sim.set_helm(rev_order=ASTERN)
    t_applied = None
    n_E_min = np.inf
    allowed = False  # the interlock has been satisfied (at the end of a step)
    for step in range(int(30.0 / dt)):
        sim.advance(dt)
        n_E, _gov, c = sim.component_states[0, :3]  # the plant's states (then the thrusters')
        n_E_min = min(n_E_min, n_E)
        # speeds fall monotonically until the clutch is applied: allowed at the step's end if within it
        allowed = allowed or (sim.rev[0] <= C[C_ENGAGE_REV] and n_E <= C[C_SHIFT_REV])
        if not allowed:
            assert c > -CLUTCH_SET  # no astern clutch before the interlock allows it
        if t_applied is None and c <= -0.95:
            t_applied = (step + 1) * dt
    params = SHIP.components[0].params
    assert n_E_min > 0.5 * C[C_IDLE_REV]  # no stall
    assert t_applied is not None
    assert params.engagement_time_s <= t_applied <= params.release_time_s + params.engagement_time_s + 10.0
    assert sim.rev[0] < 0.75 * ASTERN  # astern, at least three quarters of the order
    assert sim.rev[0] > 1.05 * ASTERN


def _ship_file_with(tmp_path, **params):
    text = (SHIP_DIR / "supply.toml").read_text()
    data = read_toml(SHIP_DIR / "supply.toml")
    table = dict(data["components"][0]["params"])
    table.update(params)
    line = "params = { " + ", ".join(f"{k} = {v!r}" for k, v in table.items()) + " }"
    old = [ln for ln in text.splitlines() if ln.startswith("params = {")]
    assert len(old) == 1
    path = tmp_path / "my_supply.toml"
    path.write_text(text.replace(old[0], line))
    return path


@pytest.mark.parametrize(
    ("key", "value", "allowed"),
    [("clutch_capacity_ratio", 0.5, "1"), ("engagement_time_s", 0.0, "0.2"), ("engage_rpm_fraction", 1.5, "1")],
)
def test_bad_plant_values_give_one_line_naming_file_key_and_range(tmp_path, capsys, key, value, allowed):
    path = _ship_file_with(tmp_path, **{key: value})
    with pytest.raises(ShipFileError) as exc:
        load_ship(str(path))
    msg = str(exc.value)
    assert "\n" not in msg and "my_supply.toml" in msg and key in msg and allowed in msg
    from vessel_gym.cli import main

    assert main(["imo", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and key in err and "Traceback" not in err


def test_idle_speed_below_the_declutch_threshold_is_refused():
    """An idle speed whose propeller speed is below [transmission] clutch_min_rpm would read as a stop order
    to the governor: refused when the simulation builds the plant, on one line naming the key."""
    params = ReversingGearboxParams()
    ship = dataclasses.replace(SHIP, transmission=dataclasses.replace(SHIP.transmission, clutch_min_rpm=40.0))
    low = ship.transmission.clutch_min_rpm * ship.transmission.gear_ratio / ship.engine.rated_rpm
    assert params.idle_rpm_fraction <= low
    with pytest.raises(ValueError, match="idle_rpm_fraction") as exc:
        ReversingGearbox(ship, params)
    assert "\n" not in str(exc.value)


def test_a_slipping_clutch_opposes_the_slip():
    """Friction dissipates: beyond the stick band (K |w| > Q_cap + |Q_lock|, K the stabilising stiffness) the
    clutch transmits its full capacity against the slip, Q_c w > 0, for either train, either sign of slip and
    any load."""
    rng = np.random.default_rng(3)
    a = 1.0 / C[C_I_E] + ETA * I_G**2 / I_S
    K = 2.0 * math.pi / (C[C_LOCK_T] * a)
    checked = 0
    for _ in range(400):
        c = rng.choice([-1.0, 1.0]) * rng.uniform(0.1, 1.0)
        s = math.copysign(1.0, c)
        n = rng.uniform(-1.0, 1.0) * N_PROP_RATED
        n_E = rng.uniform(0.25, 1.0) * P[ENGINE.n_e_rated]
        Q_load = rng.uniform(-3e5, 3e5)
        order = AHEAD if c > 0 else ASTERN
        *_, Q_E, Q_c, slip, _phase = gearbox_drive(P, C, n, n_E, rng.uniform(0, 1), c, order, Q_load)
        Q_cap = abs(c) * C[C_CAP] * Q_RATED
        Q_lock = (Q_E / C[C_I_E] + s * I_G * Q_load / I_S) / a
        if K * abs(slip) > Q_cap + abs(Q_lock):
            assert Q_c * slip > 0.0 and abs(Q_c) == pytest.approx(Q_cap, rel=1e-12)
            checked += 1
    assert checked >= 50


@pytest.mark.parametrize("dt", [0.1, 0.82])
def test_stop_order_releases_the_clutch(dt):
    """Stop ordered while driving astern: the clutch is released completely (no residue of a fixed step's
    oscillation) and the engine idles; the propeller is then turned by the water alone."""
    sim = Simulation("supply", dt=dt)
    sim.reset()
    sim.set_helm(rev_order=ASTERN)
    sim.advance(round(30.0 / dt) * dt)
    assert sim.component_states[0][2] < -0.95
    sim.set_helm(rev_order=0.0)
    sim.advance(round(20.0 / dt) * dt)
    n_E, _gov, c = sim.component_states[0, :3]  # the plant's states (then the thrusters')
    assert abs(c) < 1e-3
    assert n_E == pytest.approx(C[C_IDLE_REV], rel=0.02)


def test_drive_torque_is_continuous_through_neutral_and_the_stick_edge():
    """The drive torque has no jump where the engaged train changes (c through 0: the capacity vanishes on both
    sides) nor where the clutch passes from holding to slipping (the clip of a continuous torque)."""
    n, n_E = 0.2 * N_PROP_RATED, C[C_IDLE_REV]
    eps = 1e-9
    q_ahead = gearbox_drive(P, C, n, n_E, 0.3, eps, ASTERN, 1e5)[0]
    q_astern = gearbox_drive(P, C, n, n_E, 0.3, -eps, ASTERN, 1e5)[0]
    assert abs(q_ahead - q_astern) < 1e-6 * Q_RATED
    # along the slip, the clutch torque of a half-applied clutch has no jump: its steps stay within the stick's
    # slope K (plus the engine torque's own change with speed) from full slip one way to full slip the other
    a = 1.0 / C[C_I_E] + ETA * I_G**2 / I_S
    K = 2.0 * math.pi / (C[C_LOCK_T] * a)
    n = 0.5 * N_PROP_RATED
    slips = np.linspace(-6.0, 6.0, 12001)  # rev/s, engine side
    dw = slips[1] - slips[0]
    Q_c = [gearbox_drive(P, C, n, I_G * n + w, 0.3, 0.5, AHEAD, 1e5)[6] for w in slips]
    assert np.max(np.abs(np.diff(Q_c))) <= 1.1 * K * dw
    assert min(Q_c) == pytest.approx(-0.5 * C[C_CAP] * Q_RATED) and max(Q_c) == pytest.approx(0.5 * C[C_CAP] * Q_RATED)
