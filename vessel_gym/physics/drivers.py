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


class _DriverChoice:
    """Serial or threaded batch driver for a call, whichever has the lower running wall time per vessel-step.

    Both drivers give bitwise identical results, so the choice changes timing only. Each driver is timed on
    its first eligible calls; afterwards the slower one is tried once every k calls, k = (cost ratio - 1) /
    DRIVER_TRIAL_COST within DRIVER_TRIAL_EVERY, so that a wrong choice costs at most ~2 % and a change of
    the machine's load is followed within a few hundred calls.
    """

    __slots__ = ("cost", "warm", "calls", "every")

    def __init__(self) -> None:
        self.cost = [0.0, 0.0]  # s per vessel-step, serial and threaded; 0 until measured
        self.warm = [False, False]  # a driver's first call loads its code and starts threads: not timed
        self.calls = 0
        self.every = DRIVER_TRIAL_EVERY[0]

    def pick(self) -> int:
        """0 for the serial driver, 1 for the threaded one."""
        serial, threaded = self.cost
        if threaded == 0.0:
            return 1
        if serial == 0.0:
            return 0
        best = 0 if serial <= threaded else 1
        self.calls += 1
        if self.calls >= self.every:
            self.calls = 0
            return 1 - best
        return best

    def record(self, driver: int, seconds: float, work: int) -> None:
        if not self.warm[driver]:
            self.warm[driver] = True
            return
        c = seconds / work
        old = self.cost[driver]
        # a call descheduled by another process counts as DRIVER_SPIKE x the running cost at most
        if old > 0.0:
            c = min(c, DRIVER_SPIKE * old)
        self.cost[driver] = c if old == 0.0 else old + DRIVER_SMOOTHING * (c - old)
        lo_c, hi_c = sorted(self.cost)
        if lo_c > 0.0:
            k = (hi_c / lo_c - 1.0) / DRIVER_TRIAL_COST
            self.every = int(min(max(k, DRIVER_TRIAL_EVERY[0]), DRIVER_TRIAL_EVERY[1]))
