"""Turning-circle geometry (IMO MSC.137(76) Annex §4.2.2 and MSC/Circ.1053 §3.3).

Advance: distance of the midship point along the original course, from the position at the rudder order to
where the heading has changed 90 deg; transfer: its distance perpendicular to the original course at that
moment; tactical diameter: that perpendicular distance where the heading has changed 180 deg. Between two
samples the event is placed by linear interpolation in the heading change.

Compiled scalar functions shared by the trial (:func:`vessel_gym.manoeuvres.trials.turning_circle`, also the
initial-turning test) and the TurningCircle task kernel (:mod:`vessel_gym.envs.tasks.turning`).
"""

from __future__ import annotations

import math

from numba import njit

#: heading change at which advance and transfer are measured, rad
ADVANCE_HEADING_RAD = 0.5 * math.pi
#: heading change at which the tactical diameter is measured, rad
TACTICAL_HEADING_RAD = math.pi


@njit(cache=True)
def course_axes(psi0, n0, e0, n, e):
    """(advance, transfer) of the point (n, e), m: its position relative to (n0, e0) along the original course
    ``psi0`` (rad) and perpendicular to it (+ starboard)."""
    c0 = math.cos(psi0)
    s0 = math.sin(psi0)
    dn = n - n0
    de = e - e0
    return c0 * dn + s0 * de, -s0 * dn + c0 * de


@njit(cache=True)
def crossing_fraction(prev_turned, turned, level):
    """Fraction of the last sample interval at which the heading change (rad, magnitude) reached ``level``:
    (level - prev) / (now - prev), or 1 when it did not grow."""
    return (level - prev_turned) / (turned - prev_turned) if turned > prev_turned else 1.0


@njit(cache=True)
def at_crossing(prev_value, value, fraction):
    """A quantity at the crossing, linearly between its previous and present samples."""
    return prev_value + fraction * (value - prev_value)


__all__ = ["ADVANCE_HEADING_RAD", "TACTICAL_HEADING_RAD", "at_crossing", "course_axes", "crossing_fraction"]
