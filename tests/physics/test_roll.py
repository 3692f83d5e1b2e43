"""Roll, the optional fourth degree of freedom (vessel_gym/physics/roll.py).

Free roll of the ``container`` ship (Son & Nomoto 1982) at rest, where its speed-dependent hull terms vanish:
the period from the published inertias and GM, the decay from added linear and quadratic damping, both
against closed-form results. A 3-DOF ship never leaves phi = p = 0. Bad roll tables are refused by key.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics import params
from vessel_gym.physics.shipchecks import ShipFileError
from vessel_gym.physics.shipfile import load_ship, resolve_ship_path
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.vessel import pack

DEG = math.pi / 180.0
G = 9.80665  # m/s^2
DT = 0.05  # s, 1/600 of the roll period


def _effective_roll_inertia() -> float:
    """Roll inertia of the free ship at rest, kg m^2, from container.m's prime masses (Son & Nomoto 1982):
    with no sway force at rest, the sway-roll added mass m_y l_y lowers the roll inertia to
    det(M) / (m22 m44 - m42^2), M over (v, p, r) as in container.m."""
    m, my, ly, alphay = 0.00792, 0.007049, 0.0313, 0.05
    Ix, Jx, Iz, Jz = 0.0000176, 0.0000034, 0.000456, 0.000419
    m22, m32, m42, m33, m44 = m + my, -my * ly, my * alphay, Ix + Jx, Iz + Jz
    det = m22 * m33 * m44 - m32**2 * m44 - m42**2 * m33
    return det / (m22 * m44 - m42**2) * 0.5 * 1025.0 * 175.0**5


def _free_roll(ship, phi0: float, duration_s: float) -> tuple[np.ndarray, np.ndarray]:
    """Time and roll angle of the ship released at rest with heel ``phi0`` (rad), engine stopped."""
    sim = Simulation(ship, dt=DT)
    sim.reset(speed_m_s=0.0)
    sim.set_helm(rudder_order_rad=0.0, rev_order=0.0)
    sim.state[0, :] = 0.0
    sim.state[0, lo.X_PHI] = phi0
    t, phi = [0.0], [phi0]
    for _ in range(int(round(duration_s / DT))):
        assert sim.step(1) == 1
        t.append(sim.t)
        phi.append(sim.state[0, lo.X_PHI])
    return np.asarray(t), np.asarray(phi)


def _peaks(phi: np.ndarray) -> np.ndarray:
    """Indices of the positive maxima of phi (parabola-free: the step is 1/600 of the period)."""
    i = np.nonzero((phi[1:-1] > phi[:-2]) & (phi[1:-1] >= phi[2:]) & (phi[1:-1] > 0.0))[0] + 1
    return np.concatenate(([0], i))


@pytest.fixture(scope="module")
def container():
    return load_ship("container")


def test_free_roll_period_from_gm_and_inertia(container):
    """T_phi = 2 pi sqrt(I_eff / (rho g nabla GM)): 30.3 s for GM = 0.3 m. A 2 deg release (GM sin(phi)
    lengthens the period by phi^2/16 = 8e-5); tolerance 0.5 % for the peak times on a 0.05 s grid."""
    T_expected = 2.0 * math.pi * math.sqrt(_effective_roll_inertia() / (container.mass_kg * G * 0.3))
    t, phi = _free_roll(container, 2.0 * DEG, 3.2 * T_expected)
    p = _peaks(phi)
    assert len(p) >= 4
    T = (t[p[3]] - t[p[0]]) / 3.0
    assert T == pytest.approx(T_expected, rel=0.005)
    assert phi[p[3]] == pytest.approx(2.0 * DEG, rel=0.01)  # undamped at rest: K_p p' vanishes with U


def test_a_gz_curve_replaces_gm_sin_phi(container):
    """With a righting-lever curve GZ = 0.6 m x phi (rad) up to 40 deg the restoring is that of GM = 0.6 m:
    the free-roll period is 2 pi sqrt(I_eff / (rho g nabla 0.6 m)), 21.4 s (tolerance 0.5 %)."""
    gz = tuple(0.6 * math.radians(h) for h in (0.0, 10.0, 20.0, 40.0))
    roll = dataclasses.replace(container.roll, GZ_heel_deg=(0.0, 10.0, 20.0, 40.0), GZ_m=gz)
    ship = dataclasses.replace(container, roll=roll)
    T_expected = 2.0 * math.pi * math.sqrt(_effective_roll_inertia() / (container.mass_kg * G * 0.6))
    t, phi = _free_roll(ship, 5.0 * DEG, 3.2 * T_expected)
    p = _peaks(phi)
    assert (t[p[3]] - t[p[0]]) / 3.0 == pytest.approx(T_expected, rel=0.005)


def test_linear_roll_damping_gives_the_logarithmic_decrement(container):
    """Damping ratio zeta = c / (2 sqrt(k I)) = 0.05: successive maxima in the ratio
    exp(-2 pi zeta / sqrt(1 - zeta^2)) = 0.730 (tolerance 1 %)."""
    k = container.mass_kg * G * 0.3
    I_eff = _effective_roll_inertia()
    zeta = 0.05
    c = 2.0 * zeta * math.sqrt(k * I_eff)
    ship = dataclasses.replace(container, roll=dataclasses.replace(container.roll, damping_linear_Nms=c))
    t, phi = _free_roll(ship, 2.0 * DEG, 75.0)
    p = _peaks(phi)
    ratio = phi[p[2]] / phi[p[1]]
    assert ratio == pytest.approx(math.exp(-2.0 * math.pi * zeta / math.sqrt(1.0 - zeta**2)), rel=0.01)


def test_quadratic_roll_damping_gives_the_energy_decrement(container):
    """For K = -c p|p| the energy lost over a cycle of amplitude a is (8/3) c a^3 omega^2, so the amplitude
    falls by (8/3) (c / I) a^2 per cycle (small damping). c is chosen for a 5 % fall per cycle from 10 deg;
    the first-order formula holds to ~0.2 % of the amplitude, tolerance 10 % of the fall."""
    a = 10.0 * DEG
    I_eff = _effective_roll_inertia()
    c = 0.05 * a * I_eff / (8.0 / 3.0 * a * a)
    ship = dataclasses.replace(container, roll=dataclasses.replace(container.roll, damping_quadratic_Nms2=c))
    t, phi = _free_roll(ship, a, 40.0)
    p = _peaks(phi)
    fall = phi[p[0]] - phi[p[1]]
    # amplitude at mid-cycle (the mean over the cycle) for the a^2 factor
    a_mid = 0.5 * (phi[p[0]] + phi[p[1]])
    assert fall == pytest.approx(8.0 / 3.0 * c / I_eff * a_mid**2, rel=0.1)


def test_shaft_torque_reaction_heels_a_right_handed_ship_to_port(container):
    """With a right-handed propeller the hull takes -Q_P about x: in straight running the ship heels to port by
    phi = -asin(Q_P / (rho g nabla GM)), 0.41 deg at 13.6 kn. The heel makes the ship drift and yaw a little, and
    the hull's roll terms and the rudder's moment from that flow add 1.7 % of the moment: tolerance 3 %.
    Without the option (container.m has no such term) the ship stays upright."""
    from vessel_gym.physics.vessel import N_OUT, forces

    roll = dataclasses.replace(container.roll, propeller_torque_reaction="right_handed")
    for ship, heeled in ((dataclasses.replace(container, roll=roll), True), (container, False)):
        sim = Simulation(ship, dt=0.1)
        sim.reset()
        sim.set_helm(rudder_order_rad=0.0)
        sim.advance(800.0)  # 27 roll periods; the hull's K_p damps the roll in ~120 s at this speed
        Q = forces(sim.Ps[0], sim.state[0], sim.inputs[0], sim.env[0], np.zeros(N_OUT))[14]
        phi = sim.state[0, lo.X_PHI]
        if heeled:
            assert Q > 0.0 and phi == pytest.approx(-math.asin(Q / (ship.mass_kg * G * 0.3)), rel=0.03)
        else:
            assert phi == 0.0


def test_a_three_dof_ship_never_rolls():
    """Without [roll] the roll fields are all 0 and phi, p stay exactly 0 in a hard turn."""
    ship = load_ship("kvlcc2")
    P = pack(ship)
    assert all(np.all(np.asarray(v) == 0.0) for v in params.get(P, params.ROLL).values())
    sim = Simulation(ship, dt=0.5)
    sim.reset()
    sim.set_helm(rudder_order_rad=35.0 * DEG)
    sim.step(400)
    assert sim.state[0, lo.X_R] > 0.0
    assert sim.state[0, lo.X_PHI] == 0.0 and sim.state[0, lo.X_P] == 0.0


def _with_roll_lines(tmp_path: Path, old: str, new: str) -> Path:
    text = resolve_ship_path("container").read_text()
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1))
    return path


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("K_v = 0.0003026", "K_v = 0.0003026\nY_vv = 0.1", "[roll.derivatives] Y_vv: not a roll derivative"),
        ("K_v = 0.0003026", "K_q = 0.1", "[roll.derivatives] K_q: not a roll derivative"),
        ("K_v = 0.0003026", "K_vvvvv = 0.1", "[roll.derivatives] K_vvvvv: powers above 4"),
        ("GM_m = 0.3", "GM_m = -0.3", "[roll] GM_m"),
        ("GM_m = 0.3", "GM_m = 0.3\nKG_m = 9.0", "[roll]: unknown key 'KG_m'"),
        ("GM_m = 0.3", "GM_m = 0.3\nGZ_heel_deg = [0, 20, 30]\nGZ_m = [0, 0.1, 0.15]", "must reach 40 deg"),
        ("GM_m = 0.3", "GM_m = 0.3\nGZ_heel_deg = [0, 20, 40]\nGZ_m = [0, 0.1]", "[roll] GZ_m: 2 values"),
        ("GM_m = 0.3", "GM_m = 0.3\nGZ_heel_deg = [0, 40, 20]\nGZ_m = [0, 0.1, 0.2]", "increase strictly"),
    ],
)
def test_bad_roll_tables_are_refused_by_key(tmp_path, old, new, message):
    with pytest.raises(ShipFileError) as exc:
        load_ship(_with_roll_lines(tmp_path, old, new))
    assert message in str(exc.value) and "\n" not in str(exc.value)
