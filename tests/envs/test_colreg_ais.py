"""CollisionAvoidance with targets as received over AIS (targets_observed="ais"): the ITU-R M.1371-5 reporting
intervals, dead reckoning between reports (the picture lags a turn and steps at a report), dropouts, noise,
seeding, and the truth when the option is off."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.envs.tasks.colreg_ais import AisReceiver, reporting_interval
from vessel_gym.physics.units import KNOT_M_S

ID = "vessel_gym/CollisionAvoidance-v0"
EXACT = {"ais_position_sigma_m": 0.0, "ais_sog_sigma_kn": 0.0, "ais_cog_sigma_deg": 0.0}


def test_reporting_intervals_are_those_of_itu_r_m1371_tables_1_and_2():
    assert reporting_interval(10.0, False) == 10.0
    assert reporting_interval(10.0, True) == pytest.approx(10.0 / 3.0)
    assert reporting_interval(15.5, False) == 6.0 and reporting_interval(15.5, True) == 2.0
    assert reporting_interval(25.0, False) == 2.0
    assert reporting_interval(15.5, False, "B") == 30.0 and reporting_interval(1.0, False, "B") == 180.0


def _receiver(cls: str = "B", dropout: float = 0.0, sigma: float = 0.0) -> AisReceiver:
    ais = AisReceiver(1, 2, cls, dropout, sigma, 0.0, 0.0, turning_deg_min=1e6)
    ais.reset(0, np.random.default_rng(3))
    return ais


def _circle(t: float, U: float = 8.0, R: float = 1000.0):
    """A ship on a circle of radius R (m) at U m/s, starting at the origin heading north: (n, e, vn, ve, r)."""
    a = U * t / R
    return R * math.sin(a), R * (1.0 - math.cos(a)), U * math.cos(a), U * math.sin(a), U / R


def test_the_picture_dead_reckons_the_last_report_lags_a_turn_and_steps_at_a_report():
    """A Class B target (30 s at 15.5 kn) turning on a circle, watched every 10 s: between reports the picture
    moves along the last reported velocity (straight: its error from the truth grows), and when a report
    arrives it steps back onto the truth (exact reports: no noise)."""
    ais = _receiver("B")
    dt, errors, heard = 10.0, [], []
    for i in range(31):
        t = i * dt
        n, e, vn, ve, r = _circle(t)
        on, oe, ovn, ove = ais.observe(0, 1, t, n, e, vn, ve, r)
        rep = ais.rep[0, 1].copy()
        rep_t = rep[4]
        if not heard or rep_t != heard[-1]:  # a report arrived in this step: the velocity of now (0.1 kn)
            assert rep[2:4] == pytest.approx((vn, ve), abs=0.06)
        heard.append(rep_t)
        # dead reckoning of the last report: the picture is on the straight line of the report's velocity
        assert (ovn, ove) == (rep[2], rep[3])
        assert (on, oe) == pytest.approx((rep[0] + rep[2] * (t - rep_t), rep[1] + rep[3] * (t - rep_t)))
        errors.append(math.hypot(on - n, oe - e))
    reports = sorted(set(heard))
    gaps = np.diff(reports)
    assert 0.0 < gaps[0] <= 30.0  # the reset report, then the first transmission at a random phase
    np.testing.assert_allclose(gaps[1:], 30.0)  # Table 2, Class B above 2 kn
    # the error grows between reports: a picture 20 s old on a 1 km circle at 8 m/s is U^2 t^2 / 2R = 12.8 m
    # off the arc (the observations every 10 s see ages of up to 20-29 s)
    assert max(errors) > 10.0
    steps = [i for i in range(1, 31) if heard[i] != heard[i - 1]]
    assert steps and all(errors[i] < errors[i - 1] for i in steps if errors[i - 1] > 1.0)


def test_dropouts_lengthen_the_gaps_and_noise_scatters_the_reports():
    ais = _receiver("A", dropout=0.5, sigma=10.0)
    seen, dev = [], []
    for i in range(600):
        t = i * 10.0
        n, e, vn, ve = 100.0 + 8.0 * t, 0.0, 8.0, 0.0  # straight north at 8 m/s (15.6 kn: 6 s interval)
        ais.observe(0, 1, t, n, e, vn, ve, 0.0)
        seen.append(ais.rep[0, 1, 4])
        rep = ais.rep[0, 1]
        dev.append(rep[1])  # east error of the last report (truth: 0)
    reports = np.unique(seen)
    # every 6 s sent, half received: about 1 in 12 s over 6000 s
    assert 350 < len(reports) < 650
    assert np.max(np.diff(reports)) >= 24.0  # several lost in a row
    assert 5.0 < np.std(np.unique(dev)) < 15.0


def _run(seed: int, steps: int, **kw) -> list[np.ndarray]:
    env = gym.make(ID, observation_type="physical", **kw)
    obs, _ = env.reset(seed=seed, options={"scenario": "imazu:12"})
    out = [obs]
    for _ in range(steps):
        obs, *_ = env.step(np.zeros(1, dtype=np.float32))
        out.append(obs)
    return out


def test_off_is_the_truth_and_exact_reports_of_steady_targets_agree_with_it():
    """Without noise and dropouts, a target keeping course and speed is dead-reckoned exactly: the AIS picture
    equals the truth (to the reports' 0.1 kn / 0.1 deg rounding); the default is the truth itself."""
    truth = _run(5, 20)
    default = _run(5, 20, targets_observed="true")
    np.testing.assert_array_equal(np.array(truth), np.array(default))
    ais = _run(5, 20, targets_observed="ais", **EXACT)
    env = gym.make(ID, observation_type="physical")
    lay = env.unwrapped.observation_layout
    for a, b in zip(truth, ais):
        for j in range(3):
            assert lay.value(b, f"t{j}_range") == pytest.approx(lay.value(a, f"t{j}_range"), abs=15.0)
            assert lay.value(b, f"t{j}_rel_u") == pytest.approx(lay.value(a, f"t{j}_rel_u"), abs=0.06)


def test_ais_picture_is_seeded_and_noisy():
    kw = {"targets_observed": "ais", "ais_dropout": 0.3, "ais_position_sigma_m": 30.0, "ais_class": "B"}
    a, b = _run(9, 12, **kw), _run(9, 12, **kw)
    np.testing.assert_array_equal(np.array(a), np.array(b))
    truth = _run(9, 12)
    env = gym.make(ID, observation_type="physical")
    lay = env.unwrapped.observation_layout
    diff = [abs(lay.value(x, "t0_range") - lay.value(y, "t0_range")) for x, y in zip(a, truth)]
    assert max(diff) > 5.0


def test_sog_above_the_first_bound_uses_the_faster_rate():
    assert reporting_interval(14.0 - 1e-9, False) == 10.0 and reporting_interval(14.0, False) == 6.0
    assert reporting_interval(8.0 / KNOT_M_S, False) == 6.0  # 8 m/s is 15.6 kn
