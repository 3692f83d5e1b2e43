"""The choice between the serial and the threaded batch driver (physics.drivers.threaded): by the size of the
call and numba's thread count only, so the same call takes the same driver on every run, whatever the load;
and both drivers give the same bits, so the choice changes timing only."""

from __future__ import annotations

import numpy as np
import pytest
from numba import config

from vessel_gym.physics import drivers
from vessel_gym.physics.drivers import THREADED_MIN_BATCH, THREADED_MIN_WORK, threaded
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.units import DEG

WIND = Environment(wind_speed_m_s=12.0, wind_from_deg=30.0)


@pytest.fixture
def two_threads(monkeypatch):
    monkeypatch.setattr(config, "NUMBA_NUM_THREADS", 2)


def test_small_calls_are_serial_large_ones_threaded(two_threads):
    assert not threaded(1, 10_000)  # one ship: never worth waking threads
    assert not threaded(THREADED_MIN_BATCH - 1, 10_000)
    assert not threaded(THREADED_MIN_BATCH, THREADED_MIN_WORK // THREADED_MIN_BATCH - 1)
    assert threaded(THREADED_MIN_BATCH, THREADED_MIN_WORK // THREADED_MIN_BATCH)
    assert threaded(16384, 1)


def test_one_numba_thread_makes_every_call_serial(monkeypatch):
    monkeypatch.setattr(config, "NUMBA_NUM_THREADS", 1)
    assert not threaded(16384, 100)


def _turning(n: int) -> Simulation:
    sim = Simulation("kvlcc2", n=n, environment=WIND)
    sim.reset(heading_deg=np.linspace(0.0, 360.0, n))
    sim.set_helm(rudder_order_rad=10 * DEG)
    return sim


def test_the_same_call_takes_the_same_driver_every_time(two_threads):
    sim = _turning(THREADED_MIN_BATCH)
    sim.step(0)  # the first step checks the drivers' kind against the rows (Simulation.step)
    serial, parallel = sim._kernels
    calls = []
    sim._kernels = (lambda *a: calls.append(0) or serial(*a), lambda *a: calls.append(1) or parallel(*a))
    small = THREADED_MIN_WORK // THREADED_MIN_BATCH - 1
    for _ in range(5):
        sim.step(small)
        sim.step(small + 1)
    assert calls == [0, 1] * 5


def test_results_do_not_depend_on_the_driver(monkeypatch, two_threads):
    a, b = _turning(128), _turning(128)
    for _ in range(10):
        a.step(10)  # 1280 vessel-steps: threaded
    assert threaded(128, 10)
    monkeypatch.setattr(drivers, "THREADED_MIN_BATCH", 10**9)
    assert not threaded(128, 10)
    for _ in range(10):
        b.step(10)  # the same calls serially
    assert np.array_equal(a.state, b.state) and np.array_equal(a.alive, b.alive)
