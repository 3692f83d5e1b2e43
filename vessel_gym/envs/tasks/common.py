"""What every task's kernel shares: the motion features every observation begins with, the reward terms more
than one task uses, and the compiled steps that close a vessel's row (weighting, encoding the observation).

Every task's features begin with :data:`MOTION` (:func:`task_spec` prepends it), so :func:`motion_features`
writes the same columns for all of them. The motion comes from the physics by name
(:mod:`vessel_gym.physics.kinematics` accessors), never from a column of the state row.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from numba import njit

from vessel_gym.envs.declare import FeatureSpec, TaskSpec, Term, columns
from vessel_gym.physics.kinematics import (
    heading,
    helm_orders,
    position,
    rudder_angle,
    shaft_speed,
    velocity_through_water,
)

#: the features every task begins with: motion through the water and the helm (the shaft speed is observed
#: only with engine control)
MOTION = (
    FeatureSpec("u", "m/s", (1.5, "U_T"), "surge velocity through the water"),
    FeatureSpec("v", "m/s", (0.5, "U_T"), "sway velocity through the water (+ starboard)"),
    FeatureSpec("r", "rad/s", (2.0, "U_T / L"), "rate of turn (+ starboard)"),
    FeatureSpec("rudder", "rad", (1.0, "rudder max"), "actual rudder angle (+ starboard)"),
    FeatureSpec("rudder_order", "rad", (1.0, "rudder max"), "rudder order"),
    FeatureSpec("rev", "rev/s", (1.5, "full rev"), "propeller shaft speed (tachometer)"),
)
M = columns(*(f.name for f in MOTION), typename="Motion")

#: the reward terms of the same name in several tasks
RUDDER_ACTIVITY_DOC = "-|change of rudder order| / (2 rudder limit)"
SPEED_LOSS_DOC = "-max(0, U0 - U) / U0"


def task_spec(title: str, terms: Sequence[Term], features: Sequence[FeatureSpec]) -> TaskSpec:
    """The declaration of a task whose features are :data:`MOTION` followed by ``features``."""
    return TaskSpec(title, terms, MOTION + tuple(features))


@njit(cache=True)
def motion(x, inp, k):
    """Vessel k's (u, v, r, heading, north, east, rudder, rudder order, rev, rev order), asked of the physics by
    name from the simulation's state and input rows."""
    u, v, r = velocity_through_water(x, k)
    n, e = position(x, k)
    delta_c, rev_c = helm_orders(inp, k)
    return u, v, r, heading(x, k), n, e, rudder_angle(x, k), delta_c, shaft_speed(x, k), rev_c


@njit(cache=True)
def motion_features(f, u, v, r, delta, delta_c, rev):
    """Write the :data:`MOTION` columns of one feature row ``f``."""
    f[M.u] = u
    f[M.v] = v
    f[M.r] = r
    f[M.rudder] = delta
    f[M.rudder_order] = delta_c
    f[M.rev] = rev


@njit(cache=True)
def clear_row(a, k):
    """Zero row k of a 2-D array (a vessel's reward terms)."""
    for j in range(a.shape[1]):
        a[k, j] = 0.0


@njit(cache=True)
def rudder_activity(order, prev_order, rudder_limit):
    """Reward term -|change of rudder order| / (2 rudder limit), in [-1, 0]."""
    return -abs(order - prev_order) / (2.0 * rudder_limit)


@njit(cache=True)
def speed_loss(U, U0):
    """Reward term -max(0, U0 - U) / U0: speed lost against the approach speed U0."""
    return -(U0 - U) / U0 if U < U0 else 0.0


@njit(cache=True)
def encode_row(feat, k, enc, out):
    """Observation of vessel k from its features. ``enc`` rows: (feature column, scale, normalized flag);
    normalized = clip(feature / scale, -1, 1), else clip(feature, -scale, scale); non-finite -> 0."""
    for j in range(enc.shape[0]):
        x = feat[k, int(enc[j, 0])]
        sc = enc[j, 1]
        if not math.isfinite(x):
            x = 0.0
        if enc[j, 2] > 0.0:
            x = x / sc
            x = -1.0 if x < -1.0 else (1.0 if x > 1.0 else x)
        else:
            x = -sc if x < -sc else (sc if x > sc else x)
        out[k, j] = x


@njit(cache=True)
def finish(terms, k, w, reward):
    """Weight the terms of vessel k in place and sum them into its reward."""
    tot = 0.0
    for j in range(terms.shape[1]):
        terms[k, j] *= w[j]
        tot += terms[k, j]
    reward[k] = tot
