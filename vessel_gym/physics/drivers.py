"""Which batch driver runs a call of a simulation without Python components: serial or threaded, chosen by the
size of the call and numba's thread count, never by timing.

Both drivers give bitwise identical results (:mod:`~vessel_gym.physics.integrate`), so the choice changes
timing only, and a rule of size keeps it reproducible: the same call takes the same driver on every run and
machine load. The threaded driver pays when a call carries enough work to cover waking the worker threads
(tens of microseconds on an idle machine); below the bounds the serial driver is never slower. Both bounds
are measured with ``benchmarks/bench_physics.py --drivers`` (docs/performance.md, "Serial or threaded").
``NUMBA_NUM_THREADS=1`` makes every call serial (one core for the physics, e.g. beside a learner that uses
the other).
"""

from __future__ import annotations

from numba import config

THREADED_MIN_BATCH = 64  # vessels
THREADED_MIN_WORK = 1024  # vessel-steps per call (about 1 ms of single-thread work)


def threaded(n: int, nsteps: int) -> bool:
    """Whether a call of ``nsteps`` steps of ``n`` vessels runs on the threaded driver: at least
    THREADED_MIN_BATCH vessels and THREADED_MIN_WORK vessel-steps, and numba may use more than one thread."""
    return n >= THREADED_MIN_BATCH and n * nsteps >= THREADED_MIN_WORK and config.NUMBA_NUM_THREADS > 1
