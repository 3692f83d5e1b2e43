"""RealTimePacer: drift-free deadlines, skip-ahead, statistics (fake clock) and one real-clock run."""

from __future__ import annotations

import math
import time

import pytest

from vessel_gym.net.pacing import RealTimePacer


class FakeClock:
    """A clock whose sleep overshoots by a fixed amount, and a loop body of settable duration."""

    def __init__(self, overshoot_s: float = 0.0) -> None:
        self.t = 1000.0
        self.overshoot_s = overshoot_s

    def __call__(self) -> float:
        return self.t

    def sleep(self, dt: float) -> None:
        self.t += dt + self.overshoot_s

    def work(self, dt: float) -> None:
        self.t += dt


def test_deadlines_do_not_drift_with_sleep_overshoot():
    clock = FakeClock(overshoot_s=0.002)
    pacer = RealTimePacer(20.0, clock=clock, sleep=clock.sleep)
    start = clock.t
    lateness = []
    for _ in range(72000):  # one hour at 20 Hz
        clock.work(0.01)
        lateness.append(pacer.wait())
    assert min(lateness) == pytest.approx(0.002, abs=1e-9) and max(lateness) == pytest.approx(0.002, abs=1e-9)
    # Each wake-up is 2 ms late, but the schedule is anchored: 72000 ticks end one hour (+2 ms) after start.
    assert clock.t - start == pytest.approx(3600.0 + 0.002, abs=1e-6)
    assert pacer.ticks == 72000 and pacer.skipped == 0
    assert pacer.sim_time_s == pytest.approx(3600.0)


def test_time_factor_shortens_the_wall_period():
    clock = FakeClock()
    pacer = RealTimePacer(10.0, time_factor=4.0, clock=clock, sleep=clock.sleep)
    assert pacer.period_s == pytest.approx(0.025)
    start = clock.t
    for _ in range(40):
        pacer.wait()
    assert clock.t - start == pytest.approx(1.0)
    assert pacer.sim_time_s == pytest.approx(4.0)


def test_short_overruns_are_caught_up():
    clock = FakeClock()
    pacer = RealTimePacer(10.0, max_lag_s=0.25, clock=clock, sleep=clock.sleep)
    start = clock.t
    clock.work(0.25)  # one slow step: 2.5 periods
    assert pacer.wait() == pytest.approx(0.15)
    assert pacer.wait() == pytest.approx(0.05)  # back to back
    assert pacer.wait() == 0.0  # caught up: sleeps again
    assert clock.t - start == pytest.approx(0.3)
    assert pacer.skipped == 0


def test_long_stall_skips_ahead_instead_of_bursting():
    clock = FakeClock()
    pacer = RealTimePacer(10.0, max_lag_s=0.25, clock=clock, sleep=clock.sleep)
    start = clock.t
    clock.work(1.05)  # stalled for 10.5 periods
    late = pacer.wait()
    assert late == pytest.approx(0.95)
    assert pacer.skipped == 9
    assert pacer.next_deadline > clock.t
    assert pacer.wait() == 0.0  # no burst: the next tick sleeps
    assert clock.t - start == pytest.approx(1.1)


def test_percentiles_and_stats():
    clock = FakeClock()
    pacer = RealTimePacer(50.0, clock=clock, sleep=clock.sleep)
    assert all(math.isnan(v) for v in pacer.lateness_percentiles(50, 99))
    for k in range(100):
        clock.overshoot_s = 0.001 if k < 98 else 0.010
        pacer.wait()
    p50, p99 = pacer.lateness_percentiles(50, 99)
    assert p50 == pytest.approx(0.001) and 0.001 < p99 <= 0.010
    stats = pacer.stats()
    assert stats["ticks"] == 100 and stats["late_max_ms"] == pytest.approx(10.0)
    pacer.reset()
    assert pacer.ticks == 0 and math.isnan(pacer.lateness_percentiles(50)[0])


@pytest.mark.parametrize(
    "kwargs",
    [{"rate_hz": 0.0}, {"rate_hz": math.inf}, {"time_factor": -1.0}, {"max_lag_s": -0.1}, {"history": 0}],
)
def test_invalid_arguments(kwargs):
    args = {"rate_hz": 20.0, **kwargs}
    with pytest.raises(ValueError):
        RealTimePacer(**args)


def test_real_clock_20hz():
    pacer = RealTimePacer(20.0)
    start = time.perf_counter()
    for _ in range(10):
        pacer.wait()
    elapsed = time.perf_counter() - start
    assert elapsed == pytest.approx(0.5, abs=0.05)
    assert pacer.lateness_percentiles(50)[0] < 0.01
