"""Waypoint guidance: line of sight on a leg, pursuit of a point, and the circle of acceptance.

Fossen 2011, Handbook of Marine Craft Hydrodynamics and Motion Control, §10.3.2 (lookahead-based steering):
on the leg from waypoint p_k to p_k+1 with path-tangential angle alpha_k, the cross-track error y_e (positive
when the ship is to starboard of the leg) and a look-ahead distance Delta > 0 give the desired course

    chi_d = alpha_k + atan2(-y_e, Delta)                                  (eq. 10.73 with K_p = 1 / Delta)

and pursuit of a point steers along the line of sight from the ship to it, chi_d = atan2(e_t - e, n_t - n)
(the limit Delta -> 0 with the point as the next waypoint). Angles in rad, clockwise from north; positions
(north, east) in m.

Compiled with numba; ``f.py_func`` is the same body un-jitted and takes numpy arrays (batches of vessels).
Used by the scenarios' traffic (:mod:`vessel_gym.scenarios.traffic`) and the harbour baseline
(:class:`vessel_gym.envs.policies.HarbourPilot`).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def leg_frame(n0, e0, n1, e1, n, e):
    """(alpha, along, cross, length) of the point (n, e) on the leg from (n0, e0) to (n1, e1): the leg's
    direction alpha (rad), the along-track distance from its start and the cross-track error (+ starboard of
    the leg), m, and the leg's length, m."""
    dn = n1 - n0
    de = e1 - e0
    length = np.hypot(dn, de)
    alpha = np.arctan2(de, dn)
    along = (n - n0) * np.cos(alpha) + (e - e0) * np.sin(alpha)
    cross = -(n - n0) * np.sin(alpha) + (e - e0) * np.cos(alpha)
    return alpha, along, cross, length


@njit(cache=True)
def los_heading(alpha, cross, lookahead):
    """Lookahead-based line-of-sight course (rad) on a leg of direction ``alpha`` (rad) at cross-track error
    ``cross`` (m, + starboard) with look-ahead distance ``lookahead`` (m) (Fossen 2011 eq. 10.73)."""
    return alpha + np.arctan2(-cross, lookahead)


@njit(cache=True)
def pursuit_heading(n, e, n_t, e_t):
    """Course (rad) along the line of sight from (n, e) to the point (n_t, e_t)."""
    return np.arctan2(e_t - e, n_t - n)


@njit(cache=True)
def waypoint_reached(n, e, n_t, e_t, accept):
    """True inside the circle of acceptance: closer than ``accept`` (m) to the waypoint (n_t, e_t)."""
    return np.hypot(n_t - n, e_t - e) < accept


__all__ = ["leg_frame", "los_heading", "pursuit_heading", "waypoint_reached"]
