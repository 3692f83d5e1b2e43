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
DRIVER_WINDOW = 9  # calls: a driver is judged by its last so many timed calls (median and quartiles)
DRIVER_FIRST_TIMINGS = 3  # timed calls of each driver, alternating, before the first choice
# The threaded driver is chosen only when its median cost is lower by DRIVER_THREADED_MARGIN and its upper
# quartile is below the serial driver's median: where the two are within their own spread (a busy
# second core: a threaded call then waits for the worker thread's share of that core, and its time swings by
# more than the difference), serial costs one core less and its time does not depend on a second core.
DRIVER_THREADED_MARGIN = 0.05  # fraction of the serial median cost per vessel-step
# the driver not in use is timed again every so many calls, so that a change of load is noticed; the interval
# grows with its measured extra cost so that trying it costs at most DRIVER_TRIAL_COST of the run time
DRIVER_TRIAL_COST = 0.02  # fraction of run time
DRIVER_TRIAL_EVERY = (8, 512)  # calls, least and most between two trials
# A trial that loses (slower than the lower quartile of the driver in use) doubles the interval to the next
# one, up to DRIVER_TRIAL_EVERY[1]; one that wins resets it, so a driver that keeps losing is tried ever more
# rarely and one that starts winning (the machine became idle) is tried again soon, until its window shows it.


def _rank(ordered: list[float], q: float) -> float:
    """The q-quantile (nearest rank) of the ascending list ``ordered``."""
    return ordered[round((len(ordered) - 1) * q)]


class _DriverChoice:
    """Serial or threaded batch driver for a call, judged by the median and quartiles of each driver's last
    DRIVER_WINDOW timed calls (wall time per vessel-step).

    Both drivers give bitwise identical results, so the choice changes timing only. Each driver's first call
    is not timed (code loading, thread start); then both are timed DRIVER_FIRST_TIMINGS times, alternating.
    The threaded driver is chosen only when it is clearly cheaper (:meth:`best`); the other driver is tried once
    every k calls, k = (its mean cost / the median cost in use - 1) / DRIVER_TRIAL_COST, doubled after each
    trial it lost and reset when it won, within DRIVER_TRIAL_EVERY. The choice reads medians and quartiles:
    a call descheduled by another process is one sample of nine and moves neither. Timings come in through
    :meth:`record` (seconds of one call), so the logic is tested with made-up times.
    """

    __slots__ = ("times", "warm", "choice", "calls", "every", "backoff")

    def __init__(self) -> None:
        # s per vessel-step of the last timed calls, serial and threaded, oldest first
        self.times: tuple[list[float], list[float]] = ([], [])
        self.warm = [False, False]  # a driver's first call loads its code and starts threads: not timed
        self.choice = 0  # the driver in use once both are timed
        self.calls = 0
        self.every = DRIVER_TRIAL_EVERY[0]
        self.backoff = 1  # factor on the trial interval: doubled by each lost trial, 1 after a won one

    def ready(self) -> bool:
        """Whether both drivers have their first timings."""
        return min(len(self.times[0]), len(self.times[1])) >= DRIVER_FIRST_TIMINGS

    def best(self) -> int:
        """0 (serial) or 1 (threaded): threaded only when its median cost is lower by DRIVER_THREADED_MARGIN
        and its upper quartile below the serial median (it wins three calls in four); both must have been
        timed."""
        s, t = sorted(self.times[0]), sorted(self.times[1])
        serial = _rank(s, 0.5)
        return 1 if _rank(t, 0.75) < serial and _rank(t, 0.5) < (1.0 - DRIVER_THREADED_MARGIN) * serial else 0

    def pick(self) -> int:
        """0 for the serial driver, 1 for the threaded one."""
        if not self.warm[1]:
            return 1
        if not self.warm[0]:
            return 0
        if not self.ready():
            return 1 if len(self.times[1]) <= len(self.times[0]) else 0
        self.calls += 1
        if self.calls >= self.every:
            self.calls = 0
            return 1 - self.choice
        return self.choice

    def record(self, driver: int, seconds: float, work: int) -> None:
        """Account one call of ``driver`` that took ``seconds`` (wall) for ``work`` vessel-steps."""
        if not self.warm[driver]:
            self.warm[driver] = True
            return
        c = seconds / work
        trial = self.ready() and driver != self.choice
        window = self.times[driver]
        window.append(c)
        if len(window) > DRIVER_WINDOW:
            del window[0]
        if not self.ready():
            return
        if trial:
            # a trial of the driver not in use: back off while it loses, try it soon again once it won
            bar = _rank(sorted(self.times[self.choice]), 0.25)
            if driver:
                bar *= 1.0 - DRIVER_THREADED_MARGIN
            self.backoff = 1 if c < bar else min(2 * self.backoff, DRIVER_TRIAL_EVERY[1])
        self.choice = self.best()
        # a trial's expected extra cost is the other driver's mean (its slow calls included) over the median
        # of the one in use
        used = _rank(sorted(self.times[self.choice]), 0.5)
        other = sum(self.times[1 - self.choice]) / len(self.times[1 - self.choice])
        k = self.backoff * max((other / used - 1.0) / DRIVER_TRIAL_COST, DRIVER_TRIAL_EVERY[0])
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
