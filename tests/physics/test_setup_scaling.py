"""Set-up of a large batch: construction, reset and the steady-state cache in numpy, memory per vessel, and the
per-call choice of the batch driver.

The reference for "results unchanged" is the per-vessel definition: :func:`steady_state` of each vessel at its
own heading, speed and environment, and each ship's ``telegraph_rpm`` table read directly.
"""

from __future__ import annotations

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics import simulation as simmod
from vessel_gym.physics.environment import CALM, Environment, EnvironmentList
from vessel_gym.physics.params import BODY
from vessel_gym.physics.schema import SpecError
from vessel_gym.physics.simulation import STEADY_CACHE_SIZE, Simulation
from vessel_gym.physics.steady import SimulationError, steady_state
from vessel_gym.physics.units import DEG

WIND = Environment(wind_speed_m_s=12.0, wind_from_deg=30.0)
CURRENT = Environment(current_speed_m_s=0.5, current_to_deg=100.0)


def per_vessel_reset(sim: Simulation, headings_deg: np.ndarray, speeds: np.ndarray) -> tuple[np.ndarray, ...]:
    """State and input rows of a reset solved vessel by vessel, each at its own heading."""
    X = np.zeros((sim.n, lo.NX))
    U = np.zeros((sim.n, lo.NU))
    for j in range(sim.n):
        si = sim.ship_index[j]
        X[j], U[j] = steady_state(
            sim.ships[si], sim.Ps[si], float(speeds[j]), env=sim.env[j], heading_rad=headings_deg[j] * DEG
        )
    return X, U


@pytest.mark.parametrize("environment", [CALM, WIND, CURRENT], ids=["calm", "wind", "current"])
def test_batch_reset_equals_per_vessel_solutions_bit_for_bit(environment):
    sim = Simulation(["kvlcc2", "mariner"], n=12, ship_index=[0, 1] * 6, environment=environment)
    headings = np.array([0.0, 0.0, 37.0, 37.0, 180.0, 181.0, -90.0, 359.0, 12.5, 12.5, 270.0, 5.0])
    speeds = np.array([s.test_speed_m_s for s in sim.ships])[sim.ship_index]
    speeds[4:8] = 5.0
    sim.reset(speed_m_s=np.where(np.arange(12) >= 4, speeds, np.nan), heading_deg=headings, x_m=3.0)
    X, U = per_vessel_reset(sim, headings, speeds)
    X[:, lo.X_N] = 3.0
    assert np.array_equal(sim.state, X)
    assert np.array_equal(sim.inputs, U)
    # one vessel at a time (the environments' path) gives the same rows
    one = Simulation(["kvlcc2", "mariner"], n=12, ship_index=[0, 1] * 6, environment=environment)
    for k in range(12):
        one.reset(speed_m_s=speeds[k], heading_deg=headings[k], x_m=3.0, k=k)
    assert np.array_equal(one.state, X)
    assert np.array_equal(one.inputs, U)


def random_weather(rng: np.random.Generator, m: int, waves: bool = True) -> dict[str, np.ndarray]:
    """Environment fields of m vessels drawn over their ranges (half of them with waves)."""
    return {
        "wind_speed_m_s": rng.uniform(0.0, 20.0, m),
        "wind_from_deg": rng.uniform(-360.0, 360.0, m),
        "current_speed_m_s": rng.uniform(0.0, 1.0, m),
        "current_to_deg": rng.uniform(0.0, 360.0, m),
        "Hs_m": np.where(rng.random(m) < 0.5, 0.0, rng.uniform(0.0, 3.0, m)) if waves else np.zeros(m),
        "Tp_s": rng.uniform(5.0, 12.0, m),
        "wave_from_deg": rng.uniform(0.0, 360.0, m),
    }


def test_environments_set_in_a_batch_equal_one_at_a_time():
    """set_environments computes the rows over arrays: each is Environment(...).row of that vessel, to the bit,
    and environments[k] is that Environment."""
    rng = np.random.default_rng(4)
    m = 40
    weather = random_weather(rng, m)
    batch = Simulation(["kvlcc2", "mariner"], n=2 * m, ship_index=[0, 1] * m)
    one = Simulation(["kvlcc2", "mariner"], n=2 * m, ship_index=[0, 1] * m)
    idx = rng.permutation(2 * m)[:m]
    batch.set_environments(idx, **weather)
    for j, k in enumerate(idx.tolist()):
        env = Environment(**{key: float(v[j]) for key, v in weather.items()})
        one.set_environment(env, k)
        assert batch.environments[k] == env
    assert np.array_equal(batch.env, one.env)
    with pytest.raises(SpecError, match="wind_speed_m_s"):
        batch.set_environments(idx, wind_speed_m_s=np.full(m, 70.0))  # beyond its range, as Environment says


@pytest.mark.parametrize("airs", [1, 3])
def test_environment_rows_in_a_batch_with_one_or_several_airs_equal_one_at_a_time(airs):
    rng = np.random.default_rng(8)
    m = 30
    weather = random_weather(rng, m)
    weather["air_temperature_k"] = np.array([253.15, 288.15, 308.15])[rng.integers(0, airs, m)]
    weather["air_pressure_pa"] = np.array([99000.0, 101325.0, 103000.0])[rng.integers(0, airs, m)]
    batch = Simulation("kvlcc2", n=m)
    one = Simulation("kvlcc2", n=m)
    batch.set_environments(np.arange(m), **weather)
    for k in range(m):
        one.set_environment(Environment(**{key: float(v[k]) for key, v in weather.items()}), k)
    assert np.array_equal(batch.env, one.env)


def test_many_distinct_approaches_solved_in_one_loop_equal_per_vessel_solutions():
    """Above STEADY_BATCH_MIN distinct approaches a reset solves them in one compiled loop (steady_rows):
    the rows equal steady_state of each vessel to the bit, two ships, random weather, speeds and headings."""
    rng = np.random.default_rng(5)
    n = 3 * simmod.STEADY_BATCH_MIN
    sim = Simulation(["kvlcc2", "mariner"], n=n, ship_index=rng.integers(0, 2, n))
    sim.set_environments(np.arange(n), **random_weather(rng, n, waves=False))
    test_speed = np.array([s.test_speed_m_s for s in sim.ships])[sim.ship_index]
    speeds, headings = test_speed * rng.uniform(0.5, 1.0, n), rng.uniform(0.0, 360.0, n)
    sim.reset(speed_m_s=speeds, heading_deg=headings)
    X, U = per_vessel_reset(sim, headings, speeds)
    assert np.array_equal(sim.state, X)
    assert np.array_equal(sim.inputs, U)


def test_approaches_solved_over_the_threads_equal_the_serial_loop(monkeypatch):
    """Many distinct approaches (STEADY_THREADED_MIN and more) are solved over the threads (steady_rows_threaded):
    each row equals the serial loop's and steady_state's to the bit, in deep and shallow water, and an approach
    the ship cannot make is reported as the serial loop reports it."""
    from vessel_gym.physics import steady

    monkeypatch.setattr(steady, "STEADY_THREADED_MIN", 8)
    monkeypatch.setattr(steady, "STEADY_THREADED_CHUNK", 5)  # several chunks per thread
    rng = np.random.default_rng(6)
    n = 3 * simmod.STEADY_BATCH_MIN
    sim = Simulation(["kvlcc2", "mariner"], n=n, ship_index=rng.integers(0, 2, n))
    sim.set_environments(np.arange(n), **random_weather(rng, n, waves=False))
    for k in np.flatnonzero(sim.ship_index == 0)[::5].tolist():  # some kvlcc2s in shallow water (its own kind)
        sim.set_environment(Environment(depth_m=float(rng.uniform(30.0, 60.0))), k)
    test_speed = np.array([s.test_speed_m_s for s in sim.ships])[sim.ship_index]
    speeds, headings = test_speed * rng.uniform(0.5, 1.0, n), rng.uniform(0.0, 360.0, n)
    sim.reset(speed_m_s=speeds, heading_deg=headings)
    X, U = per_vessel_reset(sim, headings, speeds)
    assert np.array_equal(sim.state, X)
    assert np.array_equal(sim.inputs, U)
    # an approach beyond the ship's power among many: the same error as the serial loop's
    speeds[n // 2] = 40.0
    errors = []
    for threshold in (8, 10**9):
        monkeypatch.setattr(steady, "STEADY_THREADED_MIN", threshold)
        with pytest.raises(SimulationError) as err:
            sim.reset(speed_m_s=speeds, heading_deg=headings + 1.0)
        errors.append(str(err.value))
    assert errors[0] == errors[1]


@pytest.mark.parametrize("collide", [False, True], ids=["hashed", "every-hash-colliding"])
def test_distinct_rows_found_by_hash_equal_numpys_unique(monkeypatch, collide):
    from vessel_gym.physics import steady

    if collide:  # every row the same hash: the rows are then sorted as bytes instead
        monkeypatch.setattr(steady, "_ROW_HASH_PRIME", np.uint64(0))
    rng = np.random.default_rng(7)
    base = rng.normal(size=(50, 18))
    keys = base[rng.integers(0, 50, 1000)]
    keys[::97, 2] = -0.0  # a negative zero is another row (compared byte for byte, as the rows are stored)
    first, inverse = steady.distinct_rows(keys)
    assert np.array_equal(keys[first][inverse], keys)
    _, first_np = np.unique(keys.view(np.dtype((np.void, 8 * 18))).reshape(-1), return_index=True)
    assert sorted(first.tolist()) == sorted(first_np.tolist())  # the first row of each, as numpy finds them


def test_heading_is_keyed_only_where_the_environment_has_a_direction():
    headings = np.linspace(0.0, 360.0, 64, endpoint=False)
    calm = Simulation("kvlcc2", n=64)
    calm.reset(heading_deg=headings)
    assert len(calm._steady_cache) == 1  # the heading cannot change a calm-water approach
    X, _ = per_vessel_reset(calm, headings, np.full(64, calm.ships[0].test_speed_m_s))
    assert np.array_equal(calm.state, X)  # ...and indeed does not, to the bit
    windy = Simulation("kvlcc2", n=64, environment=WIND)
    windy.reset(heading_deg=headings)
    assert len(windy._steady_cache) == 64  # in wind it does


def test_cache_stays_bounded_within_one_call(monkeypatch):
    monkeypatch.setattr(simmod, "STEADY_CACHE_SIZE", 16)
    sim = Simulation("kvlcc2", n=100, environment=WIND)
    sim.reset(heading_deg=np.arange(100.0))  # 100 distinct approaches in one call
    assert 0 < len(sim._steady_cache) <= 16
    X, _ = per_vessel_reset(sim, np.arange(100.0), np.full(100, sim.ships[0].test_speed_m_s))
    assert np.array_equal(sim.state, X)


def test_cache_entries_share_one_copy_of_the_parameters():
    sim = Simulation("kvlcc2", n=64, environment=WIND)
    sim.reset(heading_deg=np.arange(64.0))
    sim.reset(heading_deg=100.0 + np.arange(64.0))
    assert len({id(key[0]) for key in sim._steady_cache}) == 1
    sim.Ps[0, BODY.rho_kg_m3] *= 1.01  # changed parameters are a new key, not a stale hit
    sim.reset(heading_deg=0.0, k=0)
    assert len({key[0] for key in sim._steady_cache}) == 2


def nbytes_held(sim: Simulation) -> int:
    """Bytes of the arrays and lists a simulation holds (the cache's contents included)."""
    total = 0
    for value in vars(sim).values():
        if isinstance(value, np.ndarray):
            total += value.nbytes
        elif isinstance(value, list):
            total += 8 * len(value)  # one reference per element; the elements are shared objects
        elif isinstance(value, EnvironmentList):
            total += 8 * len(value) + (0 if value._vals is None else value._vals.nbytes)
    for key, (x, u) in sim._steady_cache.items():
        total += sum(len(part) for part in key if isinstance(part, bytes) and part is not key[0])
        total += x.nbytes + u.nbytes
    total += sum(len(b) for b in sim._param_bytes.values())
    return total


@pytest.mark.parametrize("environment", [CALM, WIND], ids=["calm", "wind"])
def test_memory_per_vessel_is_under_2_kB(environment):
    n = 4096
    sim = Simulation("kvlcc2", n=n, environment=environment)
    sim.reset(heading_deg=np.random.default_rng(1).uniform(0.0, 360.0, n))
    assert len(sim._steady_cache) <= STEADY_CACHE_SIZE
    per_vessel = nbytes_held(sim) / n
    assert per_vessel <= 2048, f"{per_vessel:.0f} B per vessel"


def test_telegraph_table_matches_the_ships_rpm_tables():
    sim = Simulation(["kvlcc2", "mariner"], n=6, ship_index=[0, 1, 1, 0, 0, 1])
    steps = np.array([-4, -1, 0, 2, 4, 9])  # 9 is clipped to 4
    got = sim.telegraph_rev(steps)
    for j in range(6):
        table = sim.ship(j).engine.telegraph_rpm
        assert got[j] == table[min(steps[j], 4) + 4] / 60.0
        assert sim.telegraph_rev(steps, k=j) == got[j]
    assert np.array_equal(
        sim.telegraph_rev(3), [sim.ship(j).engine.telegraph_rpm[7] / 60.0 for j in range(6)]
    )


def test_construction_and_reset_call_the_solver_once_per_distinct_approach(monkeypatch):
    """Set-up cost in counts, not time: building and resetting N vessels evaluates one environment row per
    ship and solves one steady approach per distinct (ship, speed, environment) in calm water, whatever N."""
    from vessel_gym.physics import environment as envmod

    counts = {"row": 0, "steady": 0}
    row, solve = envmod.Environment.row, steady_state

    def counted_row(self, *a, **kw):
        counts["row"] += 1
        return row(self, *a, **kw)

    def counted_steady(*a, **kw):
        counts["steady"] += 1
        return solve(*a, **kw)

    monkeypatch.setattr(envmod.Environment, "row", counted_row)
    monkeypatch.setattr(simmod, "steady_state", counted_steady)
    for n in (10, 10_000):
        counts.update(row=0, steady=0)
        sim = Simulation("kvlcc2", n=n)
        sim.reset(heading_deg=np.linspace(0.0, 360.0, n))
        assert counts == {"row": 1, "steady": 1}
