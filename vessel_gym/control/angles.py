"""Angle wrapping: one function per documented range.

Compiled with numba so that the task kernels call the same functions as Python code; ``f.py_func`` is the
same body un-jitted, and it also takes numpy arrays (the operators are elementwise).

* :func:`wrap_pi`: [-pi, pi), the heading errors and deviations of the environments and the baselines.
* :func:`wrap_pi_upper`: (-pi, pi], the autopilot's error psi - psi_ref and the traffic readings.

Compass angles in degrees, [0, 360), are :func:`vessel_gym.physics.environment.wrap_deg` (the bridge's
readings belong to the physics, which must not depend on this package).
"""

from __future__ import annotations

import math

from numba import njit

PI = math.pi  # rad
TWO_PI = 2.0 * math.pi  # rad


@njit(cache=True)
def wrap_pi(angle_rad):
    """Angle in [-pi, pi), rad (pi maps to -pi)."""
    return (angle_rad + PI) % TWO_PI - PI


@njit(cache=True)
def wrap_pi_upper(angle_rad):
    """Angle in (-pi, pi], rad (-pi maps to pi). Scalars only.

    The arithmetic of :func:`wrap_pi` except that a remainder of exactly 0 becomes 2 pi: the two agree
    everywhere but on the boundary.
    """
    a = (angle_rad + PI) % TWO_PI
    if a == 0.0:
        a = TWO_PI
    return a - PI


__all__ = ["PI", "TWO_PI", "wrap_pi", "wrap_pi_upper"]
