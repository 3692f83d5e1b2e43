"""Wall-clock pacing of a fixed-step loop (live mode: a simulation that humans join over the UDP link).

Deadlines are computed from the start time, ``t0 + k * period``, never from the previous wake-up, so sleep
overshoot does not accumulate into drift: after an hour at 20 Hz the loop has made exactly 72000 ticks.

Skip-ahead policy. A tick that starts late (the loop body took longer than a period) does not sleep, so short
overruns are caught up by running the next ticks back to back and the loop stays locked to wall-clock time. If
the loop is more than ``max_lag_s`` behind, catching up would mean a burst of fast ticks that humans see as the
ship jumping; instead the missed deadlines are dropped (counted in ``skipped``) and the schedule resumes from the
next future deadline. Simulation time then falls behind wall-clock time by the skipped periods, which is the
honest outcome for a loop that cannot keep up.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numpy as np


class RealTimePacer:
    """Paces a loop to ``rate_hz`` ticks per simulated second at ``time_factor`` times real time.

    The wall-clock period is ``1 / (rate_hz * time_factor)`` s (``time_factor`` 2.0 runs twice as fast as real
    time). Call :meth:`wait` once per loop iteration, after the work. ``max_lag_s`` (s of wall-clock time) is the
    lag beyond which deadlines are skipped instead of caught up (see the module docstring). ``spin_s`` (s) ends
    each sleep that long before the deadline and busy-waits the rest, trading CPU for lower lateness. The last
    ``history`` lateness samples are kept for the statistics. ``clock`` and ``sleep`` can be injected for tests.
    """

    def __init__(
        self,
        rate_hz: float,
        time_factor: float = 1.0,
        *,
        max_lag_s: float = 0.25,
        spin_s: float = 0.0,
        history: int = 100_000,
        clock: Callable[[], float] = time.perf_counter,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        for name, value in (("rate_hz", rate_hz), ("time_factor", time_factor)):
            if not math.isfinite(value) or value <= 0.0:
                raise ValueError(f"{name} must be a positive number, not {value!r}")
        if not math.isfinite(max_lag_s) or max_lag_s < 0.0:
            raise ValueError(f"max_lag_s must be >= 0, not {max_lag_s!r}")
        if not math.isfinite(spin_s) or spin_s < 0.0:
            raise ValueError(f"spin_s must be >= 0, not {spin_s!r}")
        if history < 1:
            raise ValueError("history must be >= 1")
        self.rate_hz = float(rate_hz)
        self.time_factor = float(time_factor)
        self.period_s = 1.0 / (self.rate_hz * self.time_factor)  # wall-clock seconds per tick
        self.max_lag_s = float(max_lag_s)
        self.spin_s = float(spin_s)
        self._clock = clock
        self._sleep = sleep
        self._late = np.zeros(history)
        self.reset()

    def reset(self) -> None:
        """Re-anchor the schedule at the current time (e.g. after a pause) and clear the statistics."""
        self._t0 = self._clock()
        self._k = 0  # index of the last deadline served
        self.ticks = 0
        self.skipped = 0
        self._n = 0

    @property
    def next_deadline(self) -> float:
        """Clock time of the next deadline."""
        return self._t0 + (self._k + 1) * self.period_s

    def wait(self) -> float:
        """Sleep until the next deadline; return how late (s, >= 0) the loop resumed after it."""
        self._k += 1
        deadline = self._t0 + self._k * self.period_s
        now = self._clock()
        if now < deadline:
            remaining = deadline - now - self.spin_s
            if remaining > 0.0:
                self._sleep(remaining)
            while self.spin_s > 0.0 and self._clock() < deadline:
                pass
            now = self._clock()
        lateness = max(now - deadline, 0.0)
        if lateness > self.max_lag_s:
            missed = int(lateness / self.period_s)
            self._k += missed
            self.skipped += missed
        self._late[self._n % self._late.size] = lateness
        self._n += 1
        self.ticks += 1
        return lateness

    @property
    def sim_time_s(self) -> float:
        """Simulated time paced so far: ticks / rate_hz (s)."""
        return self.ticks / self.rate_hz

    def lateness_percentiles(self, *percentiles: float) -> tuple[float, ...]:
        """Percentiles (0-100) of the recorded lateness, s; NaN before the first tick."""
        n = min(self._n, self._late.size)
        if n == 0:
            return tuple(math.nan for _ in percentiles)
        return tuple(float(v) for v in np.percentile(self._late[:n], percentiles))

    def stats(self) -> dict[str, float]:
        """Ticks, skipped deadlines, and lateness p50/p99/max in ms."""
        p50, p99, p100 = self.lateness_percentiles(50.0, 99.0, 100.0)
        return {
            "ticks": self.ticks,
            "skipped": self.skipped,
            "late_p50_ms": p50 * 1e3,
            "late_p99_ms": p99 * 1e3,
            "late_max_ms": p100 * 1e3,
        }
