"""Low speed, sternway and rest: continuity and symmetry of the forces, rest stays rest, a dead ship drifts
to leeward, and runaway states are flagged (docs/physics.md, "Sternway and rest")."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.runaway import RUNAWAY_RATE, RUNAWAY_SPEED, runaway_limits
from vessel_gym.physics.shipfile import builtin_ships, load_ship
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.vessel import N_OUT, forces

SHIPS = Path(__file__).resolve().parents[2] / "vessel_gym" / "physics" / "data" / "ships"
I_YR, I_NR = 5, 6  # Y_R, N_R in the output of vessel.forces


def _forces(sim, u, v, r=0.0, delta=0.0, n=0.0):
    x = sim.state[0].copy()
    x[lo.X_U], x[lo.X_V], x[lo.X_R], x[lo.X_DELTA], x[lo.X_REV] = u, v, r, delta, n
    return forces(sim.Ps[0], x, sim.inputs[0], sim.env[0], np.zeros(N_OUT)).copy()


@pytest.fixture(scope="module")
def kvlcc2():
    sim = Simulation("kvlcc2", dt=0.1)
    sim.reset(speed_m_s=0.0)
    return sim


def test_sternway_rudder_moment_vanishes_with_the_sway(kvlcc2):
    # straight astern at 2 m/s, rudder amidships: a sway of 1e-9 m/s of either sign once gave -596 / +233 MN m
    a = _forces(kvlcc2, -2.0, -1e-9)
    b = _forces(kvlcc2, -2.0, +1e-9)
    for f in (a, b):
        assert abs(f[I_NR]) < 1.0  # N m
        assert abs(f[I_YR]) < 1e-2  # N
    assert a[I_NR] == pytest.approx(-b[I_NR], rel=1e-9, abs=1e-12)


def test_rudder_forces_continuous_over_every_drift_angle(kvlcc2):
    """At U = 2 m/s, r = 0 and a rudder angle of 10 deg the rudder forces change smoothly with the drift
    angle all the way round, through u = 0 (+-90 deg) and v = 0 (0 and 180 deg); engine stopped."""
    delta = math.radians(10.0)
    betas = np.radians(np.arange(-180.0, 180.0 + 1e-9, 0.05))
    F = np.array([_forces(kvlcc2, 2.0 * math.cos(b), -2.0 * math.sin(b), delta=delta) for b in betas])
    scale = np.abs(F[:, I_NR]).max()
    # a 0.05 deg step moves the force by a small fraction of its range (a jump would be of order 1)
    assert np.abs(np.diff(F[:, I_NR])).max() < 0.01 * scale
    assert np.abs(np.diff(F[:, I_YR])).max() < 0.01 * np.abs(F[:, I_YR]).max()


def test_rudder_lift_reverses_in_sternway(kvlcc2):
    """With the flow from astern the rudder's angle of attack reverses: starboard rudder gives a yaw moment to
    port when the ship moves straight astern (as ships steer in sternway), to starboard when ahead."""
    delta = math.radians(20.0)
    ahead = _forces(kvlcc2, 2.0, 0.0, delta=delta)
    astern = _forces(kvlcc2, -2.0, 0.0, delta=delta)
    assert ahead[I_NR] > 0.0 > astern[I_NR]


def test_rudder_sees_rotation_at_zero_speed(kvlcc2):
    """A ship turning on the spot still has cross flow at its rudder: the rudder damps the rotation."""
    f = _forces(kvlcc2, 0.0, 0.0, r=0.01)
    assert f[I_NR] < 0.0


@pytest.mark.parametrize("name", builtin_ships())
def test_rest_stays_rest(name):
    sim = Simulation(name, dt=0.1)
    sim.reset(speed_m_s=0.0)
    sim.set_helm(rudder_order_rad=0.0, rev_order=0.0)
    sim.advance(600.0)
    assert sim.alive[0]
    assert abs(sim.u[0]) < 0.01 and abs(sim.v[0]) < 0.01


def _run_from(u0, v0, seconds=600.0, rudder_deg=0.0, ship="kvlcc2"):
    sim = Simulation(ship, dt=0.1)
    sim.reset(speed_m_s=0.0)
    sim.state[0, lo.X_U] = u0
    sim.state[0, lo.X_V] = v0
    sim.set_helm(rudder_order_rad=math.radians(rudder_deg), rev_order=0.0)
    north, east, psi = [], [], []
    for _ in range(int(seconds / 10.0)):
        sim.advance(10.0)
        north.append(sim.north[0])
        east.append(sim.east[0])
        psi.append(sim.heading[0])
    assert sim.alive[0]
    return np.array(north), np.array(east), np.array(psi)


@pytest.mark.parametrize("v0", [1e-6, 0.05])
def test_sternway_tiny_sway_gives_mirrored_tracks(v0):
    """KVLCC2 going astern at 2 m/s, rudder amidships, engine stopped: a sway of either sign gives mirror
    tracks, and a tiny one leaves the ship going straight (no turn from nothing). The only asymmetry is the
    published gamma_R- != gamma_R+ of the ship file, which fades out in sternway but not
    completely at 1.4 deg of drift: 1e-3 of the reach."""
    n1, e1, p1 = _run_from(-2.0, v0)
    n2, e2, p2 = _run_from(-2.0, -v0)
    reach = np.abs(n1).max()
    tol = 1e-6 if v0 < 1e-3 else 1e-3
    assert n1 == pytest.approx(n2, abs=tol * reach)
    assert e1 == pytest.approx(-e2, abs=tol * reach + 1e-9)
    assert p1 == pytest.approx(-p2, abs=tol + 1e-9)
    if v0 < 1e-3:
        assert np.abs(p1).max() < math.radians(0.01)
        assert np.abs(e1).max() < 0.01  # m


def test_port_starboard_mirror_symmetry_ahead():
    """KVLCC2 (a symmetric MMG model apart from gamma_R+-, which mirror into each other) turning from 2 m/s
    with 20 deg rudder either side: the tracks mirror within the asymmetry the published gamma_R+- give."""
    n1, e1, p1 = _run_from(2.0, 0.0, 300.0, 20.0)
    n2, e2, p2 = _run_from(2.0, 0.0, 300.0, -20.0)
    assert e1[-1] > 0.0 > e2[-1]
    assert p1[-1] > 0.0 > p2[-1]
    assert n1 == pytest.approx(n2, rel=0.05, abs=5.0)
    assert e1 == pytest.approx(-e2, rel=0.05, abs=5.0)
    assert p1 == pytest.approx(-p2, rel=0.05, abs=0.01)


@pytest.mark.parametrize("name", ["kvlcc2", "mariner", "dtc"])
def test_dead_ship_in_beam_wind_drifts_to_leeward(name):
    """Engine stopped, rudder amidships, 20 m/s wind on the port beam (from the west, ship heading north):
    the ship drifts to starboard (leeward) and gains no headway. Headway is the speed along the original course
    (north): a bow that swings a degree or two while the ship drifts puts that share of the leeward drift into
    the body-axis u (0.8 m/s x sin 1.5 deg = 0.02 m/s for the Mariner) without any motion ahead."""
    sim = Simulation(name, dt=0.1, environment=Environment(wind_speed_m_s=20.0, wind_from_deg=270.0))
    sim.reset(speed_m_s=0.0)
    sim.set_helm(rudder_order_rad=0.0, rev_order=0.0)
    ahead = []
    for _ in range(60):
        sim.advance(10.0)
        psi = sim.heading[0]
        ahead.append(sim.u[0] * math.cos(psi) - sim.v[0] * math.sin(psi))
    assert sim.alive[0]
    assert sim.v[0] > 0.05 and sim.east[0] > 10.0
    assert max(ahead) < 0.01  # m/s


def _broken_mariner(tmp_path: Path) -> Path:
    """Mariner with X_vv of the wrong sign and 100 x its size: a drift angle now drives the ship ahead, so
    any turn accelerates without bound while every number stays finite."""
    text = (SHIPS / "mariner.toml").read_text()
    assert "X_vv = -8.990000e-03" in text
    p = tmp_path / "broken_mariner.toml"
    p.write_text(text.replace("X_vv = -8.990000e-03", "X_vv = 8.990000e-01"))
    return p


def test_runaway_is_flagged_with_its_reason(tmp_path):
    ship = load_ship(str(_broken_mariner(tmp_path)))
    sim = Simulation(ship, dt=0.1)
    sim.reset()
    sim.set_helm(rudder_order_rad=math.radians(35.0))
    U_max = runaway_limits(ship)[0]
    alive = 1
    for _ in range(6000):
        alive = sim.step(1)
        if alive == 0:
            break
    assert alive == 0 and not sim.alive[0]
    assert sim.why_dead[0] == RUNAWAY_SPEED
    assert math.isfinite(sim.u[0]) and math.hypot(sim.u[0], sim.v[0]) > U_max
    assert "exceeds" in sim.divergence(0) and "kn" in sim.divergence(0)
    # a new run starts clean
    sim.reset()
    assert sim.alive[0] and sim.divergence(0) is None


def test_runaway_rate_of_turn_bound():
    sim = Simulation("kvlcc2", dt=0.1)
    sim.reset()
    r_max = runaway_limits(sim.ship())[1]
    sim.state[0, lo.X_R] = 1.5 * r_max
    assert sim.step(1) == 0
    assert sim.why_dead[0] == RUNAWAY_RATE
    assert "rate of turn" in sim.divergence(0)


@pytest.mark.parametrize("name", builtin_ships())
def test_runaway_bounds_leave_the_ship_room(name):
    """The bounds sit well above what the ship does at full power: 3 x the speed, r' = 2, 1.5 x rated rpm."""
    ship = load_ship(name)
    U_max, r_max, n_max = runaway_limits(ship)
    assert U_max > 3.0 * ship.test_speed_m_s
    assert r_max * ship.particulars.L_m / ship.test_speed_m_s > 2.0
    if ship.engine is not None:
        assert n_max * 60.0 > ship.engine.rated_rpm / (
            ship.transmission.gear_ratio if ship.transmission else 1
        )
