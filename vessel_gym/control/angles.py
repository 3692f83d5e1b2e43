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
from numba.extending import overload

PI = math.pi  # rad
TWO_PI = 2.0 * math.pi  # rad


def mod_two_pi(a):
    """``a`` modulo 2 pi, in [0, 2 pi) (Python's float modulo; elementwise on numpy arrays), rad."""
    return a % TWO_PI


@overload(mod_two_pi, jit_options={"cache": True})
def _mod_two_pi_compiled(a):
    """:func:`mod_two_pi` in compiled code: the same result, bit for bit, without the libm ``fmod`` call (tens of
    nanoseconds, the largest cost of a ZigZag task update) when ``a`` is already in [0, 2 pi), where the modulo
    is the identity (``fmod`` is exact, and -0.0 becomes +0.0 there, which callers' ``- PI`` cannot tell apart).
    A scalar path only: arrays keep Python's operator (the un-jitted ``py_func`` of the callers)."""

    def impl(a):
        if 0.0 <= a < TWO_PI:  # false for nan: the modulo gives nan
            return a + 0.0  # + 0.0: -0.0 becomes +0.0, as the modulo gives it
        return a % TWO_PI

    return impl


@njit(cache=True)
def wrap_pi(angle_rad):
    """Angle in [-pi, pi), rad (pi maps to -pi)."""
    return mod_two_pi(angle_rad + PI) - PI


@njit(cache=True)
def wrap_pi_upper(angle_rad):
    """Angle in (-pi, pi], rad (-pi maps to pi). Scalars only.

    The arithmetic of :func:`wrap_pi` except that a remainder of exactly 0 becomes 2 pi: the two agree
    everywhere but on the boundary.
    """
    a = mod_two_pi(angle_rad + PI)
    if a == 0.0:
        a = TWO_PI
    return a - PI


__all__ = ["PI", "TWO_PI", "mod_two_pi", "wrap_pi", "wrap_pi_upper"]
