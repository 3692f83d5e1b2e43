"""Propulsion: propeller open-water model in four quadrants, transmission, engine torque map, speed governor
and shaft dynamics.

The chain follows the seed report's engine subsystem: a torque map (engine speed x fuel index) with a
closed-loop speed governor (PI) setting the fuel index, lumped inertia, driving a transmission (gear ratio,
efficiency, clutch ahead / neutral / astern) and the propeller shaft against the propeller's torque.

Shaft equation (rigid shafting, clutch engaged):
    2 pi I dn/dt = s eta_G i Q_E(n_E, f) - Q_P(u_a, n) - Q_f(n),     n_E = s i n
with s = +1 ahead / -1 astern (clutch direction, from the sign of the order) and s = 0 clutch out.

A ship file may instead declare a direct-reversing two-stroke diesel (``[engine] reversing =
"direct_air_start"``): engine and propeller are one shaft, there is no clutch, and reversing follows the
sequence of :func:`direct_reversing_drive` (fuel off, windmilling, reversing gear shifted, starting air
against the rotation below a threshold speed, fuel in the new direction above the firing speed).
"""

from __future__ import annotations

import math

from numba import njit

from vessel_gym.physics import layout as lo
from vessel_gym.physics.params import BODY, ENGINE, PROPELLER, TRANSMISSION
from vessel_gym.physics.propeller4q import BOLLARD_FACTOR, blended_coefficients
from vessel_gym.physics.shallow_water import wake_fraction


@njit(cache=True)
def propeller_thrust_torque(P, u_a, n):
    """:func:`thrust_torque` with every model compiled in (the general form; see there)."""
    return thrust_torque(P, u_a, n, True)


@njit(cache=True)
def thrust_torque(P, u_a, n, far):
    """Propeller thrust T (N, positive ahead) and absorbed torque Q (N m, same sign convention as n).

    Quadrant 1 (n >= 0, u_a >= 0): the open-water quadratics K_T = k_0 + k_1 J + k_2 J^2 (and K_Q), written
    as T = rho D^2 (k_0 (nD)^2 + k_1 (nD) u_a + k_2 u_a^2) so that they stay finite at n = 0 (locked-propeller
    drag k_2 u_a^2) and need no division by n.
    Quadrants 2-4 use the astern approximation documented in docs/physics.md: bollard values in quadrant 2
    (plus quadrant 3's locked-propeller drag, so that T and Q are continuous at n = 0);
    astern bollard coefficients ``astern_kt_ratio * k_0`` (and K_Q) in quadrants 3 and 4, with the
    magnitude growing linearly with ahead inflow in quadrant 4 (crash stop) at ``astern_inflow_slope``.
    With ``[propeller] four_quadrant`` set, quadrants 2-4 are instead the published Wageningen B-series
    curves joined to quadrant 1 by :func:`four_quadrant_thrust_torque`.

    ``far`` (True or None) chooses whether the four-quadrant curves are compiled in (vessel.far_models): a
    kernel for ships without them passes None and numba prunes the branch before typing.
    """
    if far is not None:
        if P[PROPELLER.four_quadrant] > 0.0 and not (n >= 0.0 and u_a >= 0.0):
            return four_quadrant_thrust_torque(P, u_a, n)
    D = P[PROPELLER.D_m]
    rho = P[BODY.rho_kg_m3]
    k0 = P[PROPELLER.k_0]
    k1 = P[PROPELLER.k_1]
    k2 = P[PROPELLER.k_2]
    q0 = P[PROPELLER.q_0]
    q1 = P[PROPELLER.q_1]
    q2 = P[PROPELLER.q_2]
    cT = rho * D * D
    cQ = cT * D
    nD = n * D
    if n >= 0.0:
        if u_a >= 0.0:
            T = cT * (k0 * nD * nD + k1 * nD * u_a + k2 * u_a * u_a)
            Q = cQ * (q0 * nD * nD + q1 * nD * u_a + q2 * u_a * u_a)
        else:  # ship moving astern, propeller ahead: bollard values plus the locked-propeller drag of quadrant 3
            w2 = u_a * u_a
            T = cT * (k0 * nD * nD - P[PROPELLER.astern_kt_ratio] * k2 * w2)
            Q = cQ * (q0 * nD * nD - P[PROPELLER.astern_kq_ratio] * q2 * w2)
    else:
        m = -nD
        at = P[PROPELLER.astern_kt_ratio]
        aq = P[PROPELLER.astern_kq_ratio]
        if u_a <= 0.0:
            w = -u_a
            T = -at * cT * (k0 * m * m + k1 * m * w + k2 * w * w)
            Q = -aq * cQ * (q0 * m * m + q1 * m * w + q2 * w * w)
        else:
            s = P[PROPELLER.astern_inflow_slope]
            T = -at * cT * k0 * (m * m + s * m * u_a) + cT * k2 * u_a * u_a
            Q = -aq * cQ * q0 * (m * m + s * m * u_a) + cQ * q2 * u_a * u_a
    return T, Q


@njit(cache=True)
def four_quadrant_thrust_torque(P, u_a, n):
    """Thrust T (N) and torque Q (N m) outside quadrant 1 from the ship's four-quadrant table
    (:mod:`propeller4q`): T = C_T ½ rho V_r^2 (pi/4) D^2, Q = C_Q ½ rho V_r^2 (pi/4) D^3 with
    V_r^2 = u_a^2 + (0.7 pi n D)^2 and beta = atan2(u_a, 0.7 pi n D).

    The ship's own quadratics fix C_T*, C_Q* at the quadrant-1 boundaries: bollard ahead (beta = 0)
    C_T* = k_0 / BOLLARD_FACTOR, and the locked propeller (n = 0, beta = 90 deg) T = rho D^2 k_2 u_a^2, i.e.
    C_T* = 8 k_2 / pi (torque likewise); :func:`propeller4q.blended_coefficients` joins the published curves
    to them.
    """
    D = P[PROPELLER.D_m]
    rho = P[BODY.rho_kg_m3]
    vt = 0.7 * math.pi * n * D
    beta = math.atan2(u_a, vt)
    ct, cq = blended_coefficients(
        int(P[PROPELLER.four_quadrant]),
        beta,
        P[PROPELLER.k_0] / BOLLARD_FACTOR,
        P[PROPELLER.q_0] / BOLLARD_FACTOR,
        8.0 * P[PROPELLER.k_2] / math.pi,
        8.0 * P[PROPELLER.q_2] / math.pi,
    )
    qa = 0.125 * rho * (u_a * u_a + vt * vt) * math.pi * D * D  # 1/2 rho V_r^2 (pi/4) D^2, N
    return ct * qa, cq * qa * D


@njit(cache=True)
def effective_wake(P, U, beta, r, H):
    """Wake fraction at the propeller in a manoeuvre, Yasukawa & Yoshimura (2015) eq. 15-16.

    (1 - w_P)/(1 - w_P0) = 1 + (1 - exp(-C_1 |beta_P|)) (C_2 - 1),  beta_P = beta - x'_P r',
    at the ship's speed U = sqrt(u^2 + v^2) (m/s) and drift angle beta (rad, :func:`hull.drift_angle`).
    C_1 = 0 gives the straight-running wake w_P0 for all motions. In shallow water (draught-to-depth
    ratio H = T/h > 0) w_P0 is the shallow-water wake of :func:`shallow_water.wake_fraction`.
    Returns w_P (-).
    """
    w0 = wake_fraction(P, H)
    C1 = P[PROPELLER.C_1]
    if C1 == 0.0:
        return w0
    if U < 1e-6:
        return w0
    betaP = beta - P[PROPELLER.x_P_prime] * r * P[BODY.L_m] / U
    C2 = P[PROPELLER.C_2_plus] if betaP > 0.0 else P[PROPELLER.C_2_minus]
    one_minus_w = (1.0 - w0) * (1.0 + (1.0 - math.exp(-C1 * abs(betaP))) * (C2 - 1.0))
    return 1.0 - one_minus_w


@njit(cache=True)
def engine_torque(P, n_e, fuel):
    """Engine brake torque (N m) from the 2-D torque map, bilinear in (n_E / n_rated, fuel index).

    Outside the map the nearest edge value is used (below the lowest speed: the starting-torque row).
    """
    s = n_e / P[ENGINE.n_e_rated]
    S0 = ENGINE.map_speed
    F0 = ENGINE.map_fuel
    s = P[S0] if s <= P[S0] else (P[S0 + lo.MAP_NS - 1] if s >= P[S0 + lo.MAP_NS - 1] else s)
    f = P[F0] if fuel <= P[F0] else (P[F0 + lo.MAP_NF - 1] if fuel >= P[F0 + lo.MAP_NF - 1] else fuel)
    # the interval of each axis: the count of inner breakpoints below the clipped value (the breakpoints
    # increase strictly, shipchecks), so i = 0 at the lowest speed and MAP_NS - 2 at the highest. A count over
    # a fixed number of breakpoints, not a search: no loop of data-dependent length, so the kernel stays one
    # straight block that a loop over vessels can vectorise (docs/performance.md, "Structure-of-arrays kernel")
    i = 0
    for k in range(1, lo.MAP_NS - 1):
        i += P[S0 + k] < s
    j = 0
    for k in range(1, lo.MAP_NF - 1):
        j += P[F0 + k] < f
    ts = (s - P[S0 + i]) / (P[S0 + i + 1] - P[S0 + i])
    tf = (f - P[F0 + j]) / (P[F0 + j + 1] - P[F0 + j])
    Q0 = ENGINE.map_torque
    nf = lo.MAP_NF
    q00 = P[Q0 + i * nf + j]
    q01 = P[Q0 + i * nf + j + 1]
    q10 = P[Q0 + (i + 1) * nf + j]
    q11 = P[Q0 + (i + 1) * nf + j + 1]
    q = (1 - ts) * ((1 - tf) * q00 + tf * q01) + ts * ((1 - tf) * q10 + tf * q11)
    return q * P[ENGINE.Q_e_rated]


@njit(cache=True)
def clutch_direction(P, n_order):
    """+1 ahead, -1 astern, 0 clutch out (|order| below the clutch threshold)."""
    if n_order > P[TRANSMISSION.clutch_min_rev]:
        return 1.0
    if n_order < -P[TRANSMISSION.clutch_min_rev]:
        return -1.0
    return 0.0


@njit(cache=True)
def governor(P, n, gov_i, n_order):
    """PI speed governor with conditional-integration anti-windup.

    Speed error e = (i |n_order| - n_E) / n_E,rated; fuel index f = clip(K_p e + x_gov, 0, 1);
    dx_gov/dt = K_i e, frozen while f is saturated in the direction of e. Returns (fuel, dx_gov/dt, s, n_E).
    """
    s = clutch_direction(P, n_order)
    i_g = P[TRANSMISSION.gear_ratio]
    if s == 0.0:
        return 0.0, -gov_i * 0.2, 0.0, 0.0  # clutch out: integrator bleeds off (5 s), engine idles
    n_e = s * i_g * n
    e = (i_g * abs(n_order) - n_e) / P[ENGINE.n_e_rated]
    f_raw = P[ENGINE.governor_Kp] * e + gov_i
    f = min(max(f_raw, 0.0), 1.0)
    di = P[ENGINE.governor_Ki] * e
    if (f_raw >= 1.0 and e > 0.0) or (f_raw <= 0.0 and e < 0.0):
        di = 0.0
    return f, di, s, n_e


# phases of a direct-reversing engine (direct_reversing_drive); a clutch drive reports RUNNING or FUEL_OFF
PHASE_RUNNING = 0  # fuel on, governed, turning in the ordered direction
PHASE_FUEL_OFF = 1  # stop ordered, or turning against the order faster than starting air may be applied
PHASE_SHIFTING = 2  # reversing gear moving to the ordered direction, fuel off
PHASE_AIR = 3  # starting air in the ordered direction: braking the windmilling shaft, then starting it
#: part of the reversal time spent in the final exponential approach of the reversing gear, so that its
#: derivative is continuous enough for RK4 (the gear counts as set within CAM_SET of its end position), -
CAM_TAU_FRACTION = 0.1
CAM_SET = 0.05  # reversing-gear travel units (full travel 2), -
#: engine speed band over which the fuel-off drag torque changes sign through n = 0 (a Coulomb-like drag
#: regularised so that a stopped shaft stays at rest instead of chattering), fraction of rated speed, -
DRAG_BAND = 0.02


@njit(cache=True)
def engine_drag_torque(P, n_e):
    """Torque (N m, signed like the engine speed n_e rev/s, opposing rotation) of an engine turned without
    fuel: the zero-fuel column of the torque map (friction and pumping losses), regularised through n_e = 0."""
    q = engine_torque(P, abs(n_e), 0.0)  # <= 0: a drag
    band = DRAG_BAND * P[ENGINE.n_e_rated]
    return q * max(-1.0, min(1.0, n_e / band))


@njit(cache=True)
def direct_reversing_drive(P, n, cam, gov_i, n_order):
    """Drive torque of a direct-reversing two-stroke diesel and the rates of its internal states.

    The reversing sequence of a slow-speed crosshead engine on bridge control (engine and propeller on one
    shaft, no clutch): when the order's direction d (+1 ahead, -1 astern, 0 stop; the clutch threshold of
    :func:`clutch_direction`) differs from the way the engine is set, fuel is cut at once and the
    reversing gear (fuel-pump cams, starting-air distributor; state ``cam``) moves towards d at 2/T_rev, so
    the shift takes about the reversal time T_rev. The ship's way keeps the propeller windmilling ahead
    meanwhile. With the gear set, starting air is admitted in direction d only once the engine speed
    against d is below the air-braking threshold (``air_brake_rev``): it brakes the shaft to rest and
    starts it the other way, with the starting-air torque ``Q_air``. Fuel is admitted (PI governor) once
    the engine turns in direction d at the firing speed; astern its torque is limited to
    ``astern_torque_ratio`` of the ahead map. Without fuel the engine's friction and pumping drag acts.

    The phase is a function of the state (cam, n), so the integrator steps it as it steps any state; a
    phase changes inside a step where the state crosses a threshold (order held over the step).
    Returns (drive torque at the propeller shaft N m, d cam/dt 1/s, d x_gov/dt 1/s, fuel index, engine
    speed rev/s signed, engine torque N m, phase).
    """
    d = clutch_direction(P, n_order)
    T_rev = P[ENGINE.reversal_time_s]
    dcam = 0.0
    if d != 0.0:
        rate = 2.0 / T_rev
        dcam = max(-rate, min(rate, (d - cam) / (CAM_TAU_FRACTION * T_rev)))
    i_g = P[TRANSMISSION.gear_ratio]
    n_e = i_g * n
    bleed = -gov_i * 0.2  # governor integrator bleeds off (5 s) while there is no fuel, as with the clutch out
    if d == 0.0 or abs(d - cam) > CAM_SET:
        phase = PHASE_FUEL_OFF if d == 0.0 else PHASE_SHIFTING
        Q_e = engine_drag_torque(P, n_e)
        return i_g * Q_e, dcam, bleed, 0.0, n_e, Q_e, phase
    w = d * n_e  # engine speed in the ordered direction, rev/s
    if w >= P[ENGINE.firing_rev]:
        e = (i_g * abs(n_order) - w) / P[ENGINE.n_e_rated]
        f_raw = P[ENGINE.governor_Kp] * e + gov_i
        f = min(max(f_raw, 0.0), 1.0)
        di = P[ENGINE.governor_Ki] * e
        if (f_raw >= 1.0 and e > 0.0) or (f_raw <= 0.0 and e < 0.0):
            di = 0.0
        Q_e = d * engine_torque(P, w, f)
        if d < 0.0:
            Q_e *= P[ENGINE.astern_torque_ratio]
        return P[TRANSMISSION.efficiency] * i_g * Q_e, dcam, di, f, n_e, Q_e, PHASE_RUNNING
    if w > -P[ENGINE.air_brake_rev]:
        Q_e = d * P[ENGINE.Q_air]
        return i_g * Q_e, dcam, bleed, 0.0, n_e, Q_e, PHASE_AIR
    Q_e = engine_drag_torque(P, n_e)
    return i_g * Q_e, dcam, bleed, 0.0, n_e, Q_e, PHASE_FUEL_OFF


@njit(cache=True)
def engine_drive(P, n, cam, gov_i, n_order):
    """Drive torque at the propeller shaft (N m) of the ship's plant and its state rates: the direct-reversing
    engine, or the engine through a clutch (ahead / neutral / astern, instant) and gearbox.

    Returns (drive torque, d cam/dt, d x_gov/dt, fuel index, engine speed rev/s, engine torque N m, phase).
    """
    if P[ENGINE.reversing] == lo.REVERSING_DIRECT_AIR:
        return direct_reversing_drive(P, n, cam, gov_i, n_order)
    fuel, di, s, n_e = governor(P, n, gov_i, n_order)
    if s == 0.0:
        return 0.0, 0.0, di, fuel, n_e, 0.0, PHASE_FUEL_OFF
    Q_e = engine_torque(P, n_e, fuel)
    Q_drive = s * P[TRANSMISSION.efficiency] * P[TRANSMISSION.gear_ratio] * Q_e
    if s < 0.0:
        Q_drive *= P[ENGINE.astern_torque_ratio]
    return Q_drive, 0.0, di, fuel, n_e, Q_e, PHASE_RUNNING


@njit(cache=True)
def shaft_acceleration(P, n, cam, gov_i, n_order, Q_prop):
    """dn/dt (rev/s^2), the reversing-gear rate (1/s) and the governor integrator rate for the propeller shaft.

    Returns (dn/dt, d cam/dt, dx_gov/dt, fuel index, engine speed rev/s, engine torque N m).
    """
    Q_drive, dcam, di, fuel, n_e, Q_e, _phase = engine_drive(P, n, cam, gov_i, n_order)
    return shaft_rate(P, n, Q_drive, Q_prop), dcam, di, fuel, n_e, Q_e


@njit(cache=True)
def shaft_rate(P, n, Q_drive, Q_prop):
    """dn/dt (rev/s^2) of the propeller shaft at n rev/s driven with Q_drive N m (at the propeller shaft,
    after the gearbox) against the propeller's torque Q_prop N m: 2 pi I dn/dt = Q_drive - Q_P - Q_f(n),
    I the shaft's inertia with the engine's referred to it (``TRANSMISSION.I_shaft``)."""
    return (Q_drive - Q_prop - shaft_friction_torque(P, n)) / (2.0 * math.pi * P[TRANSMISSION.I_shaft])


@njit(cache=True)
def shaft_friction_torque(P, n):
    """Friction torque of shafting and gearbox (N m at the propeller shaft), Q_f = Q_f,rated n / n_rated,P:
    linear in the shaft speed n (rev/s), ``friction_torque_fraction`` of the rated torque at rated speed."""
    n_rated_p = P[ENGINE.n_e_rated] / P[TRANSMISSION.gear_ratio]
    return P[TRANSMISSION.Q_friction] * n / n_rated_p


@njit(cache=True)
def engine_torque_to_hold(P, n, Q_prop):
    """Engine torque (N m) that holds the shaft at n rev/s ahead against the propeller torque Q_prop (N m):
    the shaft equation with dn/dt = 0 and the clutch ahead, Q_E = (Q_P + Q_f(n)) / (eta_G i)."""
    return shaft_torque_to_hold(P, n, Q_prop) / (P[TRANSMISSION.efficiency] * P[TRANSMISSION.gear_ratio])


@njit(cache=True)
def shaft_torque_to_hold(P, n, Q_prop):
    """Drive torque at the propeller shaft (N m) that holds it at n rev/s against the propeller torque Q_prop
    (N m): :func:`shaft_rate` = 0, Q_drive = Q_P + Q_f(n)."""
    return Q_prop + shaft_friction_torque(P, n)
