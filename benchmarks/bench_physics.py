"""Throughput of the physics core, printed as figures (a benchmark, not a timed test).

Measures vessel-RK4-steps per second of the full model -- hull, propeller with engine, governor and shaft,
rudder and steering gear, wind loads -- through the public API, ``Simulation.step(nsteps)``:

* kvlcc2 (MMG hull, MMG rudder) in a 12 m/s wind from 30 deg, and mariner (Abkowitz hull, rudder in the hull
  derivatives) in the same wind;
* batches of 1, 1024 and 16384 vessels, each turning with 10 deg of rudder from spread headings;
* a reasonable number of steps per call (a control interval's worth or more) and nsteps=1, whose extra cost
  per call is the Python-side overhead of one ``step``;
* with a user component written in Python (numpy): ``reset`` and ``step`` at N = 256, 1024 and 4096, whose
  cost per vessel should not grow with N.

Every figure is the median over ``--repeats`` timed repeats, after a warm-up call (compilation and caches).
Targets on the 2-core reference machine: >= 1,000,000 steps/s for one ship, >= 5,000,000 vessel-steps/s
batched; a missed target prints its gap. ``--drivers`` also times the serial and parallel batch drivers
directly against each other (that is how ``drivers.THREADED_MIN_BATCH`` was chosen), ``--cli`` times
``vessel-gym imo kvlcc2`` (target < 3 s wall) when the command exists.

    python benchmarks/bench_physics.py [--repeats 7] [--drivers] [--cli] [--quick] [--only]
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import os
import platform
import shutil
import statistics
import subprocess
import sys
import time

import numba
import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.drivers import threaded
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.integrate import RK4, drivers_for
from vessel_gym.physics.simulation import Simulation

TARGET_SINGLE = 1_000_000  # vessel-RK4-steps/s, one ship
TARGET_BATCH = 5_000_000  # vessel-RK4-steps/s, batched
TARGET_CLI_S = 3.0  # s wall, `vessel-gym imo kvlcc2`
MIN_TIMED_S = 0.25  # each repeat runs whole calls until at least this long

WIND = Environment(wind_speed_m_s=12.0, wind_from_deg=30.0)
SHIPS = ("kvlcc2", "mariner")
# (batch size, steps per call); a 0.1 s physics step, so 100 steps = 10 s of simulated time per call
CASES = ((1, 1000), (1, 1), (1024, 100), (1024, 1), (16384, 10), (16384, 1))


def driver_args(sim, nsteps: int) -> tuple:
    """The arguments of the compiled drivers (:func:`sim_drivers`) for ``nsteps`` RK4 steps of ``sim``."""
    return (sim.Ps, sim.ship_index, sim.state, sim.inputs, sim.env, sim.F_ext, sim.dt, nsteps, RK4, sim.alive)


def sim_drivers(sim) -> tuple:
    """(serial, threaded) drivers of the kind ``Simulation.step`` runs for ``sim`` (integrate.drivers_for)."""
    return drivers_for(sim.Ps, sim.env)


def make_sim(ship: str, n: int) -> Simulation:
    """n copies of ``ship`` at their test speed, headings spread, 10 deg rudder to starboard, in wind."""
    sim = Simulation(ship, n=n, dt=0.1, environment=WIND)
    sim.reset(heading_deg=np.linspace(0.0, 360.0, n, endpoint=False))
    sim.set_helm(rudder_order_rad=np.deg2rad(10.0))
    return sim


def time_calls(call, repeats: int) -> tuple[float, float]:
    """(median, best) seconds per call over ``repeats`` repeats of at least MIN_TIMED_S each.

    The median is the figure; the best repeat is printed next to it because on a shared machine it is the
    closest to what an idle one does.
    """
    call()  # warm-up: compilation (or cache load) and first-touch of the arrays
    per_call = [seconds_per_call(call) for _ in range(repeats)]
    return statistics.median(per_call), min(per_call)


def seconds_per_call(call, min_s: float = MIN_TIMED_S) -> float:
    """Wall seconds per call of ``call``, called again and again until at least ``min_s`` have passed."""
    calls = 0
    t0 = time.perf_counter()
    while True:
        call()
        calls += 1
        elapsed = time.perf_counter() - t0
        if elapsed >= min_s:
            return elapsed / calls


def fmt_rate(rate: float) -> str:
    return f"{rate / 1e6:8.3f} M"


def gap(rate: float, target: float) -> str:
    if rate >= target:
        return f"meets {target / 1e6:g} M"
    return f"MISSES {target / 1e6:g} M by x{target / rate:.1f}"


def bench_step(repeats: int, cases) -> None:
    print("\nSimulation.step(nsteps): vessel-RK4-steps/s, median (best) over repeats, dt = 0.1 s")
    print(
        f"{'ship':8s} {'N':>6s} {'nsteps':>6s} {'steps/s':>10s} {'(best)':>9s} {'us/call':>11s} "
        f"{'ns/vessel-step':>15s}  target"
    )
    for ship in SHIPS:
        for n, nsteps in cases:
            sim = make_sim(ship, n)
            t, best = time_calls(lambda sim=sim, k=nsteps: sim.step(k), repeats)
            rate = n * nsteps / t
            target = TARGET_SINGLE if n == 1 else TARGET_BATCH
            print(
                f"{ship:8s} {n:6d} {nsteps:6d} {fmt_rate(rate):>10s} {fmt_rate(n * nsteps / best):>9s} "
                f"{t * 1e6:11.1f} {1e9 / rate:15.1f}  {gap(rate, target)}"
            )
            if not sim.alive.all():
                print(f"  warning: {int((~sim.alive).sum())} vessels diverged during the benchmark")


class SwayYawDamping:
    """A user component written in numpy: extra linear sway and yaw damping (Y = -c_v v, N = -c_r r), the
    kind of force a user adds from Python. Vectorised over the batch, as components should be."""

    def __init__(self, c_v_N_s_m: float, c_r_N_m_s: float) -> None:
        self.c_v = c_v_N_s_m
        self.c_r = c_r_N_m_s

    def forces(self, sim: Simulation, x: np.ndarray) -> np.ndarray:
        F = np.zeros((x.shape[0], 3))
        F[:, 1] = -self.c_v * x[:, lo.X_V]
        F[:, 2] = -self.c_r * x[:, lo.X_R]
        return F


COMPONENT_BATCHES = (256, 1024, 4096)


def bench_components(repeats: int) -> None:
    """A Python component's cost: ``reset`` of all vessels and ``step(10)``, both O(N) (per-vessel figures
    should stay flat as N grows; a reset once cost O(N^2): 20 / 105 / 978 ms at N = 256 / 1024 /
    4096)."""
    print(
        "\nwith a Python component (kvlcc2, numpy sway-yaw damping): reset of all vessels and step(10), median"
    )
    print(f"{'N':>6s} {'reset ms':>9s} {'us/vessel':>10s} {'step ms':>9s} {'ns/vessel-step':>15s}")
    for n in COMPONENT_BATCHES:
        sim = Simulation("kvlcc2", n=n, dt=0.1, environment=WIND, components=[SwayYawDamping(1e6, 1e10)])
        headings = np.linspace(0.0, 360.0, n, endpoint=False)
        tr, _ = time_calls(lambda sim=sim, h=headings: sim.reset(heading_deg=h), repeats)
        sim.set_helm(rudder_order_rad=np.deg2rad(10.0))
        ts, _ = time_calls(lambda sim=sim: sim.step(10), repeats)
        print(f"{n:6d} {tr * 1e3:9.1f} {tr / n * 1e6:10.1f} {ts * 1e3:9.2f} {ts / (10 * n) * 1e9:15.1f}")


def cpu_per_call(call, repeats: int) -> float:
    """Best process CPU seconds (all threads) per call: the work a driver does, whatever else runs."""
    call()
    best = math.inf
    for _ in range(repeats):
        c0 = time.process_time()
        call()
        best = min(best, time.process_time() - c0)
    return best


def bench_drivers(repeats: int) -> None:
    """Serial vs parallel driver on the same arrays: where threads start to pay (drivers.THREADED_MIN_*).

    Wall time says what a user sees on this machine now; CPU time (all threads) says what the threads cost:
    where the parallel driver's CPU time equals the serial one, an idle 2-core machine runs it twice as fast.
    """
    print(
        "\nbatch drivers called directly (kvlcc2): vessel-steps/s (wall, median) and CPU ns per vessel-step"
    )
    print(
        f"{'N':>6s} {'nsteps':>6s} {'work':>7s} {'serial':>10s} {'parallel':>10s}  "
        f"{'CPU serial':>10s} {'CPU par.':>9s} {'ratio':>6s}  Simulation.step uses"
    )
    for n in (16, 64, 256, 1024, 4096):
        sim = make_sim("kvlcc2", n)
        for nsteps in (1, 10, 100):
            if n * nsteps > 100_000:
                continue
            args = driver_args(sim, nsteps)
            run_serial, run_parallel = sim_drivers(sim)
            work = n * nsteps
            ts, _ = time_calls(lambda a=args, run=run_serial: run(*a), repeats)
            tp, _ = time_calls(lambda a=args, run=run_parallel: run(*a), repeats)
            cs = cpu_per_call(lambda a=args, run=run_serial: run(*a), repeats) / work * 1e9
            cp = cpu_per_call(lambda a=args, run=run_parallel: run(*a), repeats) / work * 1e9
            uses = "parallel" if threaded(n, nsteps) else "serial"
            print(
                f"{n:6d} {nsteps:6d} {work:7d} {fmt_rate(work / ts):>10s} {fmt_rate(work / tp):>10s}  "
                f"{cs:10.0f} {cp:9.0f} {cp / cs:6.2f}  {uses}"
            )


# (N, nsteps per call) of the load comparison: the vector environments' call (1024 ships, one or two RK4 steps per
# action), a control interval of 16384 ships
LOAD_CASES = ((1024, 1), (1024, 2), (1024, 10), (16384, 1))
TARGET_THREADS_LOSS = 0.10  # the driver Simulation.step uses is at most 10 % slower than the serial one


SETUP_SIZES = (1024, 16384, 262144)
TARGET_SETUP_S = 5.0  # s, Simulation of 262144 vessels built and reset
TARGET_BYTES_PER_VESSEL = 2048  # B held by a Simulation per vessel


def bench_setup() -> None:
    """Construction and reset of N vessels (kvlcc2), calm and in wind with distinct headings, and the bytes of
    arrays the simulation holds per vessel (its steady-state cache included)."""
    print(
        f"\nset-up (kvlcc2): construction and reset of N vessels, wall, one run each; goals: N = 262144 built and "
        f"reset in < {TARGET_SETUP_S:g} s, <= {TARGET_BYTES_PER_VESSEL} B per vessel"
    )
    print(
        f"{'N':>7s} {'build s':>8s} {'reset s':>8s} {'us/vessel':>9s} {'reset, headings s':>17s} "
        f"{'wind+headings s':>15s} {'B/vessel':>8s}  goal"
    )
    Simulation("kvlcc2", n=2, environment=WIND).reset(heading_deg=[0.0, 90.0])  # load the compiled code
    for n in SETUP_SIZES:
        hd = np.random.default_rng(0).uniform(0.0, 360.0, n)
        t0 = time.perf_counter()
        sim = Simulation("kvlcc2", n=n, dt=0.1)
        t1 = time.perf_counter()
        sim.reset()
        t2 = time.perf_counter()
        sim.reset(heading_deg=hd)
        t3 = time.perf_counter()
        windy = Simulation("kvlcc2", n=min(n, 16384), dt=0.1, environment=WIND)
        t4 = time.perf_counter()
        windy.reset(heading_deg=hd[: windy.n])
        t5 = time.perf_counter()
        held = sum(v.nbytes for v in vars(windy).values() if isinstance(v, np.ndarray))
        held += sum(8 * len(v) for v in vars(windy).values() if isinstance(v, list))
        held += sum(x.nbytes + u.nbytes + len(key[3]) for key, (x, u) in windy._steady_cache.items())
        held += sum(len(b) for b in windy._param_bytes.values())
        per_vessel = held / windy.n
        total = t2 - t0
        ok = total < TARGET_SETUP_S and per_vessel <= TARGET_BYTES_PER_VESSEL
        goal = ("meets" if ok else "MISSES") if n == SETUP_SIZES[-1] else ""
        print(
            f"{n:7d} {t1 - t0:8.3f} {t2 - t1:8.3f} {total / n * 1e6:9.2f} {t3 - t2:17.3f} "
            f"{(t5 - t4) * n / windy.n:15.3f} {per_vessel:8.0f}  {goal}"
        )
    print("  (wind+headings: N distinct approaches, one solve each; timed at min(N, 16384) and scaled to N)")


def busy_loop() -> subprocess.Popen:
    """Another process keeping one core busy (a pure-Python loop), as a learner or a second simulation would."""
    return subprocess.Popen([sys.executable, "-c", "while True: pass"])


def bench_load(repeats: int) -> None:
    """Serial driver, threaded driver and ``Simulation.step`` (which chooses by the call's size) on the
    machine as it is, then with a busy-loop process started for the second table; one run, medians of
    interleaved repeats (kvlcc2 in wind, dt 0.1 s)."""
    print(
        f"\nthreads under load: vessel-steps/s (wall, median of {repeats} interleaved repeats), kvlcc2; goal: "
        f"Simulation.step never more than {TARGET_THREADS_LOSS:.0%} slower than the serial driver"
    )
    for loaded in (False, True):
        hog = busy_loop() if loaded else None
        try:
            time.sleep(0.5 if loaded else 0.0)
            load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
            what = "with a busy-loop process" if loaded else "as the machine is (no busy loop of ours)"
            print(f"\n{what}, load average {load:.2f}")
            print(
                f"{'N':>6s} {'nsteps':>6s} {'serial':>10s} {'threaded':>10s} {'step()':>10s} "
                f"{'thr/ser':>7s} {'step/ser':>8s}  goal"
            )
            for n, nsteps in LOAD_CASES:
                sim = make_sim("kvlcc2", n)
                args = driver_args(sim, nsteps)
                run_serial, run_parallel = sim_drivers(sim)
                calls = {
                    "serial": lambda a=args, run=run_serial: run(*a),
                    "threaded": lambda a=args, run=run_parallel: run(*a),
                    "step": lambda sim=sim, k=nsteps: sim.step(k),
                }
                for call in calls.values():  # warm-up (code loading, thread start)
                    for _ in range(20):
                        call()
                per = {name: [] for name in calls}
                for _ in range(repeats):  # interleaved, so a change of load hits all three alike
                    for name, call in calls.items():
                        k, t0 = 0, time.perf_counter()
                        while time.perf_counter() - t0 < MIN_TIMED_S:
                            call()
                            k += 1
                        per[name].append((time.perf_counter() - t0) / k)
                rate = {name: n * nsteps / statistics.median(v) for name, v in per.items()}
                loss = rate["serial"] / rate["step"] - 1.0
                verdict = "meets" if loss <= TARGET_THREADS_LOSS else f"MISSES ({loss:+.0%})"
                print(
                    f"{n:6d} {nsteps:6d} {fmt_rate(rate['serial']):>10s} {fmt_rate(rate['threaded']):>10s} "
                    f"{fmt_rate(rate['step']):>10s} {rate['threaded'] / rate['serial']:7.2f} "
                    f"{rate['step'] / rate['serial']:8.2f}  {verdict}"
                )
        finally:
            if hog is not None:
                hog.kill()
                hog.wait()


def bench_cli(repeats: int) -> None:
    print("\nvessel-gym imo kvlcc2 (wall, median of runs after one warm-up run)")
    exe = shutil.which("vessel-gym")
    if exe is None or importlib.util.find_spec("vessel_gym.cli") is None:
        print("  skipped: the vessel-gym command (vessel_gym.cli) is not available")
        return
    walls = []
    for i in range(repeats + 1):
        t0 = time.perf_counter()
        proc = subprocess.run([exe, "imo", "kvlcc2"], capture_output=True, text=True)
        wall = time.perf_counter() - t0
        if proc.returncode != 0:
            print(f"  failed (exit {proc.returncode}): {proc.stderr.strip().splitlines()[-1:]}")
            return
        if i > 0:
            walls.append(wall)
    w = statistics.median(walls)
    verdict = "meets" if w < TARGET_CLI_S else f"MISSES by {w - TARGET_CLI_S:.2f} s"
    print(
        f"  {w:.2f} s (runs: {', '.join(f'{x:.2f}' for x in walls)})  target < {TARGET_CLI_S:g} s: {verdict}"
    )


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7, help="timed repeats per figure (median)")
    ap.add_argument("--drivers", action="store_true", help="also time serial vs parallel drivers")
    ap.add_argument("--cli", action="store_true", help="also time `vessel-gym imo kvlcc2`")
    ap.add_argument(
        "--load",
        action="store_true",
        help="serial vs threaded vs step(), without and with a busy-loop process",
    )
    ap.add_argument("--setup", action="store_true", help="also time construction and reset up to N = 262144")
    ap.add_argument("--only", action="store_true", help="skip the Simulation.step and component sections")
    ap.add_argument("--quick", action="store_true", help="3 repeats, batches of 1 and 1024 only")
    args = ap.parse_args(argv)
    repeats = 3 if args.quick else args.repeats
    cases = [c for c in CASES if not args.quick or c[0] <= 1024]
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, "
        f"numba {numba.__version__}, {os.cpu_count()} CPUs, "
        f"load average {load:.2f}, {repeats} repeats"
    )
    if not args.only:
        bench_step(repeats, cases)
        bench_components(repeats)
    if args.load:
        bench_load(repeats)
    if args.setup:
        bench_setup()
    if args.drivers:
        bench_drivers(repeats)
    if args.cli:
        bench_cli(min(repeats, 3))
    if hasattr(os, "getloadavg"):
        print(f"\nload average at the end {os.getloadavg()[0]:.2f} (2.0 = both cores busy)")


if __name__ == "__main__":
    sys.exit(main())
