"""Kinematics in 3 DOF: rotations between body and earth axes, velocity over ground and through the
water, apparent wind, and the Coriolis-centripetal forces of the rigid body and its added mass; and the named
accessors of a simulation's rows (the roll accessor reads the optional fourth degree of freedom, roll.py).

Each quantity has this one home. The vessel's equations of motion, the bridge readings, the captive rig and
the task kernels call these functions; none of them derives a velocity or a rotation itself. All are compiled
(numba), take and return plain floats (so that they inline into the hot loops and allocate nothing), and run
un-jitted through ``.py_func`` as well.

Frames (Fossen 2011, sec. 2.2): earth axes north-east, body axes x forward and y to starboard with the origin at
midship; heading psi clockwise from north. The functions take psi as (cos psi, sin psi), which a caller
computes once per state. The state carries the velocities *through the water* nu_r = (u, v, r); a uniform,
irrotational current V_c (north, east) adds to the kinematics only (Fossen 2011, sec. 10.3, Property 10.1):

    nu = nu_r + R(psi)^T V_c   (over ground, body axes),
    eta' = R(psi) nu_r + V_c   (over ground, earth axes).
"""

from __future__ import annotations

import math

from numba import njit

from vessel_gym.physics import layout as lo
from vessel_gym.physics.params import BODY


@njit(cache=True)
def body_to_earth(cos_psi, sin_psi, x, y):
    """R(psi) (x, y): a horizontal body-axis vector (forward, starboard) in earth axes (north, east)
    (Fossen 2011 eq. 2.40, yaw only)."""
    return cos_psi * x - sin_psi * y, sin_psi * x + cos_psi * y


@njit(cache=True)
def earth_to_body(cos_psi, sin_psi, n, e):
    """R(psi)^T (n, e): a horizontal earth-axis vector (north, east) in body axes (forward, starboard)."""
    return cos_psi * n + sin_psi * e, -sin_psi * n + cos_psi * e


@njit(cache=True)
def body_point_to_earth(n0, e0, cos_psi, sin_psi, x, y):
    """Earth position (north, east) in m of the point (x, y) m of the body (forward, starboard of midship)
    of a ship whose midship point is at (n0, e0): (n0, e0) + R(psi) (x, y)."""
    return n0 + cos_psi * x - sin_psi * y, e0 + sin_psi * x + cos_psi * y


@njit(cache=True)
def current_body(cos_psi, sin_psi, cur_n, cur_e):
    """Current velocity (m/s) in body axes (forward, starboard), from its (north, east) components: the
    velocity over ground minus the velocity through the water (GNSS minus log)."""
    return earth_to_body(cos_psi, sin_psi, cur_n, cur_e)


@njit(cache=True)
def ground_velocity(u, v, cos_psi, sin_psi, cur_n, cur_e):
    """Velocity over ground (north, east) in m/s of the body origin: eta' = R(psi) nu_r + V_c, from the
    velocity through the water (u, v) m/s and the current (cur_n, cur_e) m/s."""
    vn, ve = body_to_earth(cos_psi, sin_psi, u, v)
    return vn + cur_n, ve + cur_e


@njit(cache=True)
def speed_over_ground(v_n, v_e):
    """Speed over ground (m/s) from the velocity over ground (north, east) of :func:`ground_velocity`."""
    return math.sqrt(v_n * v_n + v_e * v_e)


@njit(cache=True)
def ground_velocity_body(u, v, cos_psi, sin_psi, cur_n, cur_e):
    """Velocity over ground in body axes (forward, starboard), m/s: nu = nu_r + R(psi)^T V_c.

    Written out rather than through :func:`current_body` so that the sums round as they always have (the
    wind loads, and through them every trajectory, stay bitwise the same)."""
    return u + cos_psi * cur_n + sin_psi * cur_e, v - sin_psi * cur_n + cos_psi * cur_e


@njit(cache=True)
def relative_wind(u_g, v_g, cos_psi, sin_psi, w_n, w_e):
    """Apparent (relative) wind in the body frame from the air velocity (w_n, w_e) over ground (m/s,
    north/east).

    (u_g, v_g) is the ship's velocity over ground in body axes (:func:`ground_velocity_body`).
    Returns (V m/s, gamma rad, cos gamma, sin gamma): speed and the angle the wind comes from relative to the
    bow, positive from starboard, also as a unit vector (cos gamma = -w_x/V, sin gamma = -w_y/V, exact, so
    that the wind loads need no trigonometry of gamma); gamma = 0 in still air.
    """
    wx = cos_psi * w_n + sin_psi * w_e - u_g  # air relative to the ship, body axes
    wy = -sin_psi * w_n + cos_psi * w_e - v_g
    V = math.sqrt(wx * wx + wy * wy)
    if V > 0.0:
        return V, math.atan2(-wy, -wx), -wx / V, -wy / V
    return V, 0.0, 1.0, 0.0


@njit(cache=True)
def add_coriolis_forces(P, u, v, r, X, Y, N):
    """The force sums (X, Y, N) in N, N, N m with -C(nu_r) nu_r of the rigid body and the added mass added:
    X + c_X,vr v r + c_X,rr r^2, Y - c_Y,ur u r, N - c_N,ur u r.

    The coefficients are those :func:`vessel.pack` puts in the parameter row: for an MMG hull (m + m_y),
    x_G m, (m + m_x), x_G m (Yasukawa & Yoshimura 2015 eq. 4); for an Abkowitz hull with
    ``coriolis = "separate"`` the rigid body's m, m x_G, m, m x_G; zero for an Abkowitz hull whose
    derivatives already contain them (Mariner). The terms are added to the other forces one by one, in this
    order, so that every trajectory rounds as it always has.
    """
    return (
        X + P[BODY.CX_vr] * v * r + P[BODY.CX_rr] * r * r,
        Y - P[BODY.CY_ur] * u * r,
        N - P[BODY.CN_ur] * u * r,
    )


@njit(cache=True)
def coriolis_forces(P, u, v, r):
    """-C(nu_r) nu_r of the rigid body and the added mass as forces (X, Y, N) in N, N, N m at the origin
    (:func:`add_coriolis_forces` to nothing)."""
    return add_coriolis_forces(P, u, v, r, 0.0, 0.0, 0.0)


@njit(cache=True)
def rigid_body_coriolis_forces(P, u, v, r):
    """-C_RB(nu_r) nu_r of the rigid body alone, (X, Y, N) in N, N, N m at the origin: m (v r + x_G r^2),
    -m u r, -m x_G u r (Fossen 2011 eq. 3.57 in 3 DOF, origin at midship)."""
    m = P[BODY.m]
    mxG = m * P[BODY.x_G_m]
    return m * v * r + mxG * r * r, -m * u * r, -mxG * u * r


@njit(cache=True)
def added_mass_coriolis_forces(P, u, v, r):
    """-C_A(nu_r) nu_r, the added mass's part of :func:`coriolis_forces` (what a captive rig measures with the
    hull), (X, Y, N) in N, N, N m."""
    X, Y, N = coriolis_forces(P, u, v, r)
    Xb, Yb, Nb = rigid_body_coriolis_forces(P, u, v, r)
    return X - Xb, Y - Yb, N - Nb


# --- named accessors of one vessel's rows ------------------------------------------------------------------------
# What a task asks the physics for, by name: the motion in the state row x[k] and the helm in the input row
# inp[k] of a simulation (``sim.state``, ``sim.inputs``), the current and the air velocity in its environment row
# env[k] (``sim.env``). Inlined into the caller (numba IR inlining): a call with array arguments would otherwise
# cost reference counts in the task kernels' loops.
@njit(cache=True, inline="always")
def velocity_through_water(x, k):
    """(u m/s, v m/s, r rad/s) of vessel k: surge and sway through the water at midship, rate of turn."""
    return x[k, lo.X_U], x[k, lo.X_V], x[k, lo.X_R]


@njit(cache=True, inline="always")
def heading(x, k):
    """Heading psi of vessel k, rad, clockwise from north, unwrapped (as integrated)."""
    return x[k, lo.X_PSI]


@njit(cache=True, inline="always")
def position(x, k):
    """(north m, east m) of vessel k's midship point."""
    return x[k, lo.X_N], x[k, lo.X_E]


@njit(cache=True, inline="always")
def roll(x, k):
    """(phi rad, p rad/s) of vessel k: roll (heel) angle, positive starboard side down, and roll rate; both
    exactly 0 on a 3-DOF ship (roll.py)."""
    return x[k, lo.X_PHI], x[k, lo.X_P]


@njit(cache=True, inline="always")
def rudder_angle(x, k):
    """Actual rudder angle of vessel k, rad, positive to starboard."""
    return x[k, lo.X_DELTA]


@njit(cache=True, inline="always")
def shaft_speed(x, k):
    """Propeller shaft speed of vessel k, rev/s (negative astern)."""
    return x[k, lo.X_REV]


@njit(cache=True, inline="always")
def helm_orders(inp, k):
    """(rudder order rad, shaft-speed order rev/s) of vessel k."""
    return inp[k, lo.U_DELTA_C], inp[k, lo.U_REV_C]


@njit(cache=True, inline="always")
def current_velocity(env, k):
    """Current velocity (north m/s, east m/s) at vessel k, as the physics applies it."""
    return env[k, lo.E_CUR_N], env[k, lo.E_CUR_E]


@njit(cache=True, inline="always")
def air_velocity(env, k):
    """Air velocity over ground (north m/s, east m/s) at vessel k (the true wind blows towards it)."""
    return env[k, lo.E_WIND_N], env[k, lo.E_WIND_E]


@njit(cache=True)
def speed_through_water(u, v):
    """Speed through the water U = sqrt(u^2 + v^2), m/s, from surge and sway (m/s)."""
    return math.sqrt(u * u + v * v)


@njit(cache=True)
def apparent_wind(u, v, cos_psi, sin_psi, cur_n, cur_e, w_n, w_e):
    """Apparent wind as an anemometer on board senses it, (V m/s, gamma rad, cos gamma, sin gamma) as
    :func:`relative_wind`, from the velocity through the water (u, v), the current (cur_n, cur_e) and the air
    velocity (w_n, w_e) over ground (m/s): the wind relative to the ship's velocity over ground."""
    u_g, v_g = ground_velocity_body(u, v, cos_psi, sin_psi, cur_n, cur_e)
    return relative_wind(u_g, v_g, cos_psi, sin_psi, w_n, w_e)
