"""The batch driver of a simulation without Python components: serial or threaded, chosen per call by measured
wall time per vessel-step (both give bitwise identical results; the choice changes timing only)."""

from __future__ import annotations

# The threaded driver pays when a call carries enough work to cover waking the worker threads: tens of
# microseconds on an idle machine, milliseconds when other processes hold the cores. Both bounds are
# measured with benchmarks/bench_physics.py --drivers (docs/performance.md).
PARALLEL_MIN_BATCH = 64  # vessels
PARALLEL_MIN_WORK = 1024  # vessel-steps per call (about 2 ms of single-thread work)
# Above those bounds the driver is chosen per call by measured wall time per vessel-step (_DriverChoice): the
# second core may be taken by another process at any time, and then the threaded driver waits for it.
DRIVER_SMOOTHING = 0.2  # weight of the newest call in the running cost of a driver (exponential average)
# the driver not in use is timed again every so many calls, so that a change of load is noticed; the interval
# grows with its measured extra cost so that trying it costs at most DRIVER_TRIAL_COST of the run time
DRIVER_TRIAL_COST = 0.02  # fraction of run time
DRIVER_SPIKE = 4.0  # most a single call's time per vessel-step may exceed the running cost by (a factor)
DRIVER_TRIAL_EVERY = (8, 512)  # calls, least and most between two trials
# A trial that loses doubles the interval to the next one (up to DRIVER_TRIAL_EVERY[1]); one that wins resets
# it. With another process on the second core the two drivers cost about the same on average, so the interval
# from the cost ratio alone stays at its least (8 calls), while a single threaded call that waits for a
# descheduled worker costs several serial calls: trying it every 8 calls made Simulation.step 0.84 x serial.
# The threaded driver is chosen only when it is cheaper by DRIVER_THREADED_MARGIN: where the two are within
# the machine's noise of each other, serial costs one core less and its time does not depend on a second core.
DRIVER_THREADED_MARGIN = 0.05  # fraction of the serial cost per vessel-step


class _DriverChoice:
    """Serial or threaded batch driver for a call, whichever has the lower running wall time per vessel-step
    (threaded only when lower by DRIVER_THREADED_MARGIN).

    Both drivers give bitwise identical results, so the choice changes timing only. Each driver is timed on
    its first eligible calls; afterwards the other one is tried once every k calls, k = (cost ratio - 1) /
    DRIVER_TRIAL_COST, doubled after each trial the tried driver lost and reset when it won, within
    DRIVER_TRIAL_EVERY: a wrong choice costs at most ~2 %, a driver that keeps losing is tried ever more
    rarely, and a change of the machine's load is followed within a few hundred calls. Timings come in
    through :meth:`record` (seconds of one call), so the logic is tested with made-up times.
    """

    __slots__ = ("cost", "warm", "calls", "every", "backoff")

    def __init__(self) -> None:
        self.cost = [0.0, 0.0]  # s per vessel-step, serial and threaded; 0 until measured
        self.warm = [False, False]  # a driver's first call loads its code and starts threads: not timed
        self.calls = 0
        self.every = DRIVER_TRIAL_EVERY[0]
        self.backoff = 1  # factor on the trial interval: doubled by each lost trial, 1 after a won one

    def best(self) -> int:
        """The driver with the lower running cost (0 serial, 1 threaded); both must have been timed."""
        serial, threaded = self.cost
        return 1 if threaded < (1.0 - DRIVER_THREADED_MARGIN) * serial else 0

    def pick(self) -> int:
        """0 for the serial driver, 1 for the threaded one."""
        serial, threaded = self.cost
        if threaded == 0.0:
            return 1
        if serial == 0.0:
            return 0
        best = self.best()
        self.calls += 1
        if self.calls >= self.every:
            self.calls = 0
            return 1 - best
        return best

    def record(self, driver: int, seconds: float, work: int) -> None:
        """Account one call of ``driver`` that took ``seconds`` (wall) for ``work`` vessel-steps."""
        if not self.warm[driver]:
            self.warm[driver] = True
            return
        c = seconds / work
        old = self.cost[driver]
        if old > 0.0 and self.cost[1 - driver] > 0.0 and driver != self.best():
            # a trial of the driver not in use: back off while it loses, try it soon again once it won
            won = c < self.cost[1 - driver] * ((1.0 - DRIVER_THREADED_MARGIN) if driver else 1.0)
            self.backoff = 1 if won else min(2 * self.backoff, DRIVER_TRIAL_EVERY[1])
        # a call descheduled by another process counts as DRIVER_SPIKE x the running cost at most
        if old > 0.0:
            c = min(c, DRIVER_SPIKE * old)
        self.cost[driver] = c if old == 0.0 else old + DRIVER_SMOOTHING * (c - old)
        lo_c, hi_c = sorted(self.cost)
        if lo_c > 0.0:
            k = self.backoff * max((hi_c / lo_c - 1.0) / DRIVER_TRIAL_COST, DRIVER_TRIAL_EVERY[0])
            self.every = int(min(k, DRIVER_TRIAL_EVERY[1]))


# Lane drivers (lanes.py, the same equations over vessels of one ship in structure-of-arrays form): with exact
# math they give the scalar drivers' results to the bit, so they may replace them call by call, only where they
# are measured faster (a _DriverChoice of scalar = 0, lanes = 1: the lanes must be clearly cheaper, as the
# threaded driver must be); with vector math the results differ in the last bits, so the choice may not depend on
# timing: a simulation that asked for them uses them on every call.
MATH_FLAVOURS = (None, "exact", "vector")


class _LaneChoice:
    """Scalar or lane drivers for a call of a simulation of ``math`` flavour (None: scalar drivers only), and
    the serial/threaded choice within the lane drivers (a :class:`_DriverChoice` of its own)."""

    __slots__ = ("math", "kind", "threads")

    def __init__(self, math: str | None) -> None:
        if math not in MATH_FLAVOURS:
            raise ValueError(f"math must be one of {MATH_FLAVOURS}, got {math!r}")
        self.math = math
        self.kind = _DriverChoice()  # 0 the scalar drivers, 1 the lane drivers
        self.threads = _DriverChoice()  # serial or threaded lane driver

    def pick(self, large: bool) -> int:
        """1 to run the lane drivers, 0 the scalar ones, -1 when lanes are not considered (scalar drivers, and
        their own choices); ``large``: the call is one where the serial/threaded choice is made."""
        if self.math == "vector":
            return 1
        if self.math is None or not large:
            return -1
        return self.kind.pick()

    def record(self, lane: int, seconds: float, work: int) -> None:
        """Account one call that :meth:`pick` gave ``lane`` (0 or 1) for, ``seconds`` of wall, ``work``
        vessel-steps."""
        if self.math == "exact" and lane >= 0:
            self.kind.record(lane, seconds, work)
