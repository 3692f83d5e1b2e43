"""Azimuth thrusters (vessel_gym.physics.components.azimuth) against their source: the open-water curve of the
Ka 4-70 ducted propeller in nozzle 19A (Oosterveld 1970, NSMB Publ. 345; Kuiper 1992), the rated rpm and
bollard thrust from power, the loss of thrust with forward speed, the slewing-rate limit, the rpm lag, thrust
deduction; the ship-file keys and the Berthing task driving the unit. docs/berthing.md."""

import math

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components.azimuth import KA470_KQ, KA470_KT, AzimuthThruster, series
from vessel_gym.physics.shipfile import SHIP_DIR, load_ship
from vessel_gym.physics.simulation import Simulation

RHO = 1025.0  # kg/m^3, the ship files' sea water


def _unit(dt=0.1):
    sim = Simulation("supply_dp", dt=dt)
    sim.reset(speed_m_s=0.0)
    return sim, next(c for c in sim.components if c.name == "azimuth_thruster")


def _kt_table(J, pd):
    """K_T of the Ka 4-70 / 19A regression written out term by term from the published table (c, x, y):
    c (P/D)^x J^y, summed here independently of the component's own evaluation."""
    return sum(c * pd**x * J**y for c, x, y in KA470_KT)


def test_the_series_has_the_published_open_water_character_at_pd_1():
    """Ka 4-70, P/D 1.0: K_T(0) = 0.5257 and K_Q(0) = 0.04424 (the sums of the table's J^0 terms), K_T falling
    to zero near J = 0.83, open-water efficiency J K_T / (2 pi K_Q) peaking near 0.58 at J about 0.57."""
    assert float(series(KA470_KT, 0.0, 1.0)) == pytest.approx(0.030550 + 0.667657 - 0.172529, abs=1e-12)
    assert float(series(KA470_KQ, 0.0, 1.0)) == pytest.approx(
        0.006735 + 0.046605 - 0.007366 - 0.001730, abs=1e-12
    )
    J = np.linspace(0.0, 0.83, 167)
    kt, kq = series(KA470_KT, J, 1.0), series(KA470_KQ, J, 1.0)
    assert np.all(np.diff(kt) < 0.0) and np.all(kq > 0.0)
    eta = J * kt / (2.0 * math.pi * kq)
    assert 0.52 < eta.max() < 0.62 and 0.45 < J[eta.argmax()] < 0.7
    _sim, az = _unit()
    assert 0.80 < az.J_max < 0.86 and float(series(KA470_KT, az.J_max, 1.0)) == pytest.approx(0.0, abs=1e-9)


def test_rated_rpm_and_bollard_thrust_follow_from_power():
    """The rated rpm absorbs the delivered power at bollard (eta P = 2 pi rho n^3 D^5 K_Q(0)); the bollard
    thrust rho n^2 D^4 K_T(0) lies between the ideal open disc's (2 rho A P^2)^(1/3) (a 19A nozzle beats an open
    propeller of the same diameter at bollard) and the ideal ducted disc's (4 rho A P^2)^(1/3)."""
    _sim, az = _unit()
    p = az.params
    P = p.transmission_efficiency * p.power_kW * 1e3  # W at the propeller
    D = p.diameter_m
    assert 2.0 * math.pi * RHO * az.n_rated**3 * D**5 * az.KQ0 == pytest.approx(P, rel=1e-12)
    assert az.T_max == pytest.approx(RHO * az.n_rated**2 * D**4 * az.KT0, rel=1e-12)
    A = math.pi * D**2 / 4.0
    open_ideal, ducted_ideal = (2.0 * RHO * A * P**2) ** (1 / 3), (4.0 * RHO * A * P**2) ** (1 / 3)
    assert open_ideal < az.T_max < ducted_ideal
    assert 0.80 < az.T_max / ducted_ideal < 0.88
    # 18.2 kgf/kW of rated power and 355 rpm for the supply_dp's unit (880 kW, 1.7 m)
    assert az.T_max / 9.80665 / p.power_kW == pytest.approx(18.2, abs=0.1)
    assert az.n_rated * 60.0 == pytest.approx(355.0, abs=1.0)


@pytest.mark.parametrize("J", [0.0, 0.2, 0.4, 0.6, 0.8])
def test_thrust_at_speed_is_the_published_curve(J):
    """Unit pointing ahead at rated rpm, the ship making way so that the advance coefficient is J: the hull force
    is (1 - t) rho n^2 D^4 K_T(J); pointing athwartships with the same inflow across it, the same on Y, with the
    moment x Y."""
    sim, az = _unit()
    p = az.params
    n, D = az.n_rated, p.diameter_m
    x = np.zeros((1, lo.NX))
    x[0, lo.X_U] = J * n * D / (1.0 - p.wake_fraction)
    F = az.forces(sim, x, np.array([[1.0, 0.0]]))
    want = (1.0 - p.thrust_deduction) * RHO * n**2 * D**4 * _kt_table(J, p.pitch_ratio)
    assert F[0, 0] == pytest.approx(want, rel=1e-9)
    assert abs(F[0, 1]) < 1e-6 * want
    x = np.zeros((1, lo.NX))
    x[0, lo.X_V] = J * n * D  # sway through the water along the unit's axis (azimuth 90 deg)
    F = az.forces(sim, x, np.array([[1.0, math.pi / 2.0]]))
    assert F[0, 1] == pytest.approx(want, rel=1e-9)
    assert F[0, 2] == pytest.approx(p.x_m * want, rel=1e-9)


def test_thrust_is_held_outside_the_series_range():
    """Pushing against the flow (J < 0) keeps the bollard value; beyond the zero of K_T there is no thrust."""
    sim, az = _unit()
    x = np.zeros((1, lo.NX))
    x[0, lo.X_U] = -2.0  # sternway, the unit pushing ahead
    F = az.forces(sim, x, np.array([[1.0, 0.0]]))
    assert F[0, 0] == pytest.approx((1.0 - az.params.thrust_deduction) * az.T_max, rel=1e-12)
    x[0, lo.X_U] = 1.2 * az.J_max * az.n_rated * az.params.diameter_m
    assert abs(az.forces(sim, x, np.array([[1.0, 0.0]]))[0, 0]) < 1e-9 * az.T_max


def test_a_unit_off_the_centre_line_turns_the_ship_with_its_surge_force():
    sim, az = _unit()
    x = np.zeros((1, lo.NX))
    F = az.forces(sim, x, np.array([[1.0, 0.0]]))
    assert F[0, 2] == pytest.approx(-az.params.y_m * F[0, 0])  # y_m = 0 on the supply_dp: no moment
    from dataclasses import replace

    off = AzimuthThruster(load_ship("supply_dp"), replace(az.params, y_m=5.0))
    F = off.forces(sim, x, np.array([[1.0, 0.0]]))
    assert F[0, 0] > 0.0 and F[0, 2] == pytest.approx(-5.0 * F[0, 0], rel=1e-12)


def test_the_azimuth_slews_at_most_at_its_rate_and_the_rpm_lags_the_order():
    """'side' order +1 then -1: the unit slews from +90 to -90 deg the short way at 12 deg/s (15 s for the
    half turn, the side force changing sign half way), the rpm reaching (1 - e^-1) of the order after one time
    constant."""
    sim, az = _unit(dt=0.05)
    assert sim.component_state("azimuth_thruster.azimuth")[0] == pytest.approx(math.pi / 2.0)
    az.set_order(1.0)
    sim.advance(az.params.time_constant_s)
    assert sim.component_state("azimuth_thruster.rpm")[0] == pytest.approx(1.0 - math.exp(-1.0), rel=2e-3)
    sim.advance(30.0)
    az.set_order(-1.0)
    rate = math.radians(az.params.slew_rate_deg_s)
    sim.advance(5.0)
    assert sim.component_state("azimuth_thruster.azimuth")[0] == pytest.approx(
        math.pi / 2.0 - 5.0 * rate, abs=1e-6
    )
    assert sim.named_forces()["azimuth_thruster"].Y[0] > 0.0
    sim.advance(5.0)  # 10 s: past 0 deg, pushing to port
    assert sim.component_state("azimuth_thruster.azimuth")[0] == pytest.approx(
        math.pi / 2.0 - 10.0 * rate, abs=1e-6
    )
    assert sim.named_forces()["azimuth_thruster"].Y[0] < 0.0
    sim.advance(10.0)
    assert sim.component_state("azimuth_thruster.azimuth")[0] == pytest.approx(-math.pi / 2.0, abs=1e-3)


def test_bad_azimuth_keys_in_a_ship_file_are_one_line_errors(tmp_path):
    from vessel_gym.physics.shipchecks import ShipFileError

    text = (SHIP_DIR / "supply_dp.toml").read_text()
    for old, new, word in [
        ("pitch_ratio = 1.0", "pitch_ratio = 2.0", "pitch_ratio"),
        ('berthing_order = "side"', 'berthing_order = "sideways"', "berthing_order"),
        ("slew_rate_deg_s = 12.0", "slew_rate_deg_s = -1.0", "slew_rate_deg_s"),
    ]:
        assert old in text
        path = tmp_path / "bad.toml"
        path.write_text(text.replace(old, new))
        with pytest.raises(ShipFileError) as exc:
            load_ship(path)
        msg = str(exc.value)
        assert word in msg and "\n" not in msg


def test_berthing_drives_the_azimuth_thruster_from_its_action():
    """Berthing-v0 with the supply_dp: five orders (rudder, engine, bow and stern thrusters, azimuth); the
    azimuth order alone turns the bow to starboard, and the observation shows what the unit delivers."""
    import gymnasium as gym

    import vessel_gym  # noqa: F401

    env = gym.make("vessel_gym/Berthing-v0", ship="supply_dp", weather=False)
    try:
        env.reset(seed=3)
        assert env.action_space.shape == (5,)
        task = env.unwrapped.task
        r0 = float(task.sim.r[0])
        for _ in range(10):
            env.step(np.array([0.0, 0.0, 0.0, 0.0, 1.0], dtype=np.float32))
        assert task.sim.named_forces()["azimuth_thruster"].Y[0] > 0.8 * 0.95 * task.assist[2].T_max * 0.9
        assert float(task.sim.r[0]) > r0
    finally:
        env.close()
