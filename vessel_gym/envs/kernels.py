"""Compiled per-step task computations, batched over N vessels: one call per control step for all N.

The environments and their vector twins call the same kernels (N = 1 and N = 1024 run the same code). Each
task keeps its per-vessel task state in a float array ``ts`` (N, *N) whose named columns are defined here,
reads the ship's motion from the simulation's state and input rows (``sim.state``, ``sim.inputs``, columns
named in :mod:`vessel_gym.physics.layout`), and fills features (physical units), reward terms and outcome
flags. Physics equations are not repeated here: the velocities over ground, the apparent wind and the
rotations come from :mod:`vessel_gym.physics.kinematics`, the current and the wind from the simulation's
environment rows (``sim.env``). Nor are the control rules: angle wrapping, the zig-zag rule and overshoot
tracker, and the turning-circle geometry are those of :mod:`vessel_gym.control`.

These kernels inline physics and control functions, so their numba cache is keyed by a hash of this file and
the physics and control sources (:mod:`vessel_gym.physics.jitcache`): stale machine code is never loaded.

Why whole rows and not the named accessors (``sim.u``, ...): a numba call unboxes every array argument, about
0.06 us for a contiguous array and 0.15 us for a strided view such as ``sim.u``; ten views cost a one-ship
environment step more than its task arithmetic.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from vessel_gym.control.angles import PI, wrap_pi
from vessel_gym.control.turning import (
    ADVANCE_HEADING_RAD,
    TACTICAL_HEADING_RAD,
    at_crossing,
    course_axes,
    crossing_fraction,
)
from vessel_gym.control.zigzag import (
    OVERSHOOT_V0,
    OVERSHOOT_V1,
    overshoot_excursion,
    overshoot_step,
    target_reached,
    zigzag_execute,
)
from vessel_gym.physics import layout as lo
from vessel_gym.physics.integrate import MAX_CHUNKS
from vessel_gym.physics.kinematics import (
    body_point_to_earth,
    body_to_earth,
    current_body,
    earth_to_body,
    ground_velocity,
    ground_velocity_body,
    relative_wind,
    speed_over_ground,
)
from vessel_gym.physics.vessel import NO_REFCOUNT

# outcome flags (HarbourApproach)
OK = 0
SUCCESS = 1
CONTACT = 2
GROUNDING = 3
OUT_OF_BOUNDS = 4
DIVERGED = 5
OUTCOMES = ("running", "success", "contact", "grounding", "out_of_bounds", "diverged")


@njit(cache=True)
def motion(x, inp, k):
    """Vessel k's (u, v, r, heading, north, east, rudder, rudder order, rev, rev order) from the simulation's
    state and input rows (layout columns)."""
    return (
        x[k, lo.X_U],
        x[k, lo.X_V],
        x[k, lo.X_R],
        x[k, lo.X_PSI],
        x[k, lo.X_N],
        x[k, lo.X_E],
        x[k, lo.X_DELTA],
        inp[k, lo.U_DELTA_C],
        x[k, lo.X_REV],
        inp[k, lo.U_REV_C],
    )


# Every task's features begin with the ship's motion and helm, in these columns (physical units)
F_U, F_V, F_R, F_DELTA, F_DELTA_C, F_REV = range(6)
FN_MOTION = 6


@njit(cache=True)
def motion_features(f, u, v, r, delta, delta_c, rev):
    """Write the shared motion columns F_U..F_REV of one feature row ``f``."""
    f[F_U] = u
    f[F_V] = v
    f[F_R] = r
    f[F_DELTA] = delta
    f[F_DELTA_C] = delta_c
    f[F_REV] = rev


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
def _finish(terms, k, w, reward):
    """Weight the terms of vessel k in place and sum them into its reward."""
    tot = 0.0
    for j in range(terms.shape[1]):
        terms[k, j] *= w[j]
        tot += terms[k, j]
    reward[k] = tot


@njit(cache=True)
def clip_helm(actions, limit, full_ahead, full_astern, engine, rudder_order, rev_order):
    """Continuous helm: clip actions to [-1, 1] and scale to rudder (rad) and shaft-speed (rev/s) orders.

    Returns False if any action is NaN (nothing is written then).
    """
    for k in range(actions.shape[0]):
        for j in range(actions.shape[1]):
            if actions[k, j] != actions[k, j]:
                return False
    for k in range(actions.shape[0]):
        a = min(max(actions[k, 0], -1.0), 1.0)
        rudder_order[k] = a * limit[k]
        if engine:
            e = min(max(actions[k, 1], -1.0), 1.0)
            rev_order[k] = e * full_ahead[k] if e >= 0.0 else e * full_astern[k]
    return True


# --- ZigZag -------------------------------------------------------------------------------------------------
Z_PSI0 = 0  # original course, rad
Z_TARGET = 1  # current target heading, rad (unwrapped, same branch as the heading)
Z_SIDE = 2  # IMO schedule: side of the current target, +1 starboard / -1 port
Z_LEG_SIGN = 3  # random schedule: direction of the course change of this leg
Z_REACHED = 4  # random schedule: target of this leg reached
Z_OS_ON = 5  # overshoot being measured
Z_OS_SIGN = 6
Z_OS_TGT = 7  # heading past which the overshoot is measured, rad
Z_OS_MAX = 8  # largest excursion past it so far, rad
Z_OS_N = 9  # overshoots completed
Z_OS1 = 10  # first overshoot angle, rad
Z_OS2 = 11  # second overshoot angle, rad
Z_OS_LAST = 12  # last completed overshoot angle, rad
Z_EXEC = 13  # rudder executes (target changes) so far
Z_PREV_ORDER = 14  # rudder order of the previous step, rad
Z_U0 = 15  # approach speed, m/s
Z_T = 16  # time since the start of the episode, s
Z_NEXT = 17  # random schedule: time of the next course change, s
ZN = 18

ZP_PSIZ = 0  # IMO heading deviation psi_z (or random-schedule overshoot reference), rad
ZP_DMAX = 1  # rudder scale (limit), rad
ZP_IMO = 2  # 1: IMO schedule, 0: random course changes
ZP_DT = 3  # control interval, s
ZPN = 4

ZF_HEAD_ERR, ZF_HEAD_DEV, ZF_TARGET_DEV = range(FN_MOTION, FN_MOTION + 3)
ZFN = 9
ZT_HEADING, ZT_OVERSHOOT, ZT_RUDDER, ZT_SPEED = range(4)
ZTN = 4


@njit(cache=True)
def _finish_overshoot(s):
    s[Z_OS_ON] = 0.0
    s[Z_OS_N] += 1.0
    if s[Z_OS_N] == 1.0:
        s[Z_OS1] = s[Z_OS_MAX]
    elif s[Z_OS_N] == 2.0:
        s[Z_OS2] = s[Z_OS_MAX]
    s[Z_OS_LAST] = s[Z_OS_MAX]


@njit(cache=True, inline="always")
def _zigzag_close_row(k, s, i_prev_order, x, inp, alive, w, enc, feat, obs, terms, reward, done):
    """End of a zig-zag step of vessel k, both versions: done, reward, rudder memory, features, observation.

    Both task states keep the original course and the target in the same columns (Z_PSI0 == ZV_PSI0,
    Z_TARGET == ZV_TARGET); ``i_prev_order`` is where the version keeps the previous rudder order.
    """
    uk, vk, rk, psik, _n, _e, dk, dck, revk, _revc = motion(x, inp, k)
    done[k] = not alive[k]
    if done[k]:
        clear_row(terms, k)
    _finish(terms, k, w, reward)
    s[i_prev_order] = dck
    f = feat[k]
    motion_features(f, uk, vk, rk, dk, dck, revk)
    f[ZF_HEAD_ERR] = wrap_pi(s[Z_TARGET] - psik)
    f[ZF_HEAD_DEV] = wrap_pi(psik - s[Z_PSI0])
    f[ZF_TARGET_DEV] = wrap_pi(s[Z_TARGET] - s[Z_PSI0])
    encode_row(feat, k, enc, obs)


# The task kernels loop over vessels taking row views (ts[k], feat[k]); compiled without reference counting
# (vessel.NO_REFCOUNT, which explains why) they allocate nothing: scratch comes from their caller.
@njit(cache=True, **NO_REFCOUNT)
def zigzag_update(
    phase,
    x,
    inp,
    alive,
    ts,
    p,
    w,
    enc,
    feat,
    obs,
    terms,
    reward,
    done,
):
    """Zig-zag task: vessels in phase 1 advance one control step, phase 2 (just reset) get features only."""
    psiz = p[ZP_PSIZ]
    dmax = p[ZP_DMAX]
    imo = p[ZP_IMO] > 0.0
    for k in range(x.shape[0]):
        if phase[k] == 0:
            continue
        uk, vk, rk, psik, nk, ek, dk, dck, revk, revck = motion(x, inp, k)
        s = ts[k]
        clear_row(terms, k)
        if phase[k] == 1:
            s[Z_T] += p[ZP_DT]
            if s[Z_OS_ON] > 0.0:
                s[Z_OS_MAX], _rose, finished = overshoot_step(
                    s[Z_OS_SIGN], s[Z_OS_TGT], s[Z_OS_MAX], psik, rk, OVERSHOOT_V0
                )
                if finished:
                    _finish_overshoot(s)
            crossed = False
            sign = 0.0
            if imo:
                if target_reached(s[Z_SIDE], psik, s[Z_TARGET]):
                    crossed = True
                    sign = s[Z_SIDE]
            elif s[Z_REACHED] == 0.0 and target_reached(s[Z_LEG_SIGN], psik, s[Z_TARGET]):
                crossed = True
                sign = s[Z_LEG_SIGN]
                s[Z_REACHED] = 1.0
            if crossed:
                if s[Z_OS_ON] > 0.0:  # v0: a measurement still running counts as complete
                    _finish_overshoot(s)
                s[Z_OS_ON] = 1.0
                s[Z_OS_SIGN] = sign
                s[Z_OS_TGT] = s[Z_TARGET]
                s[Z_OS_MAX] = overshoot_excursion(sign, s[Z_TARGET], psik)
                if imo:  # the IMO execute: the target flips to the other side of the original course
                    s[Z_SIDE], s[Z_TARGET] = zigzag_execute(s[Z_PSI0], s[Z_SIDE], psiz)
                    s[Z_EXEC] += 1.0
            err = wrap_pi(s[Z_TARGET] - psik)
            terms[k, ZT_HEADING] = -abs(err) / PI
            if s[Z_OS_ON] > 0.0:
                exc = overshoot_excursion(s[Z_OS_SIGN], s[Z_OS_TGT], psik)
                if exc > 0.0:
                    terms[k, ZT_OVERSHOOT] = -min(exc / psiz, 1.0)
            terms[k, ZT_RUDDER] = rudder_activity(dck, s[Z_PREV_ORDER], dmax)
            terms[k, ZT_SPEED] = speed_loss(math.sqrt(uk * uk + vk * vk), s[Z_U0])
        _zigzag_close_row(k, s, Z_PREV_ORDER, x, inp, alive, w, enc, feat, obs, terms, reward, done)


# --- ZigZag-v1 ----------------------------------------------------------------------------------------------
# One schedule for both target kinds: a course change starts when its start time comes (the first after the
# seeded delay; in the random schedule every leg time; in the IMO schedule the leg time limit) or, in the IMO
# schedule, at the execute (the target reached). Overshoots are measured with the OVERSHOOT_V1 tracker.
ZV_PSI0 = Z_PSI0  # original course, rad (the column _zigzag_close_row reads in both versions)
ZV_TARGET = Z_TARGET  # target of the current course change, rad (unwrapped, same branch as the heading)
ZV_SIGN = 2  # direction in which the current target is reached, +1 starboard / -1 port; 0 before the first
ZV_SIDE = 3  # IMO schedule: side of the current target (the first change flips it: set -first side)
ZV_REACHED = 4  # current target reached
ZV_NEXT = 5  # time at which the next course change starts, s
ZV_DPSI = 6  # size of the current course change |target - previous target|, rad
ZV_OS_ON = 7  # an overshoot measurement is open
ZV_OS_SIGN = 8  # its side (+1 starboard)
ZV_OS_TGT = 9  # its target, rad
ZV_OS_PEAK = 10  # its overshoot so far (largest excursion past the target), rad
ZV_OS_SUM = 11  # overshoots of the closed measurements, summed, rad
ZV_OS_MAX = 12  # largest closed overshoot, rad
ZV_OS_N = 13  # closed measurements
ZV_OS1 = 14  # first and second closed overshoot, rad (the IMO first and second overshoot angles)
ZV_OS2 = 15
ZV_CHANGES = 16  # course changes started
ZV_NREACH = 17  # targets reached
ZV_MISSED = 18  # course changes that ended with their target not reached
ZV_PREV_ORDER = 19  # rudder order of the previous step, rad
ZV_U0 = 20  # approach speed, m/s
ZV_T = 21  # time since the start of the episode, s
ZV_PEND_CHANGE = 22  # random schedule: the next course change, drawn in advance (signed), rad
ZV_PEND_LEG = 23  # random schedule: the duration of the leg it starts, s
ZV_DRAW = 24  # random schedule: the pending change was used; the task draws the next one
ZVN = 25

ZVP_PSIZ = 0  # IMO heading deviation psi_z, rad
ZVP_OS_REF = 1  # overshoot scale of the reward, rad
ZVP_DMAX = 2  # rudder scale (limit), rad
ZVP_IMO = 3  # 1: IMO schedule, 0: random course changes
ZVP_DT = 4  # control interval, s
ZVP_LEG_LIMIT = 5  # IMO schedule: the next change starts at the latest this long after the last, s
ZVP_REACH = 6  # target_reached term per radian of course change, 1/rad
ZVPN = 7

ZVT_HEADING, ZVT_OVERSHOOT, ZVT_REACHED, ZVT_RUDDER, ZVT_SPEED = range(5)
ZVTN = 5


@njit(cache=True)
def _close_overshoot_v1(s):
    s[ZV_OS_ON] = 0.0
    s[ZV_OS_N] += 1.0
    peak = s[ZV_OS_PEAK]
    s[ZV_OS_SUM] += peak
    s[ZV_OS_MAX] = max(s[ZV_OS_MAX], peak)
    if s[ZV_OS_N] == 1.0:
        s[ZV_OS1] = peak
    elif s[ZV_OS_N] == 2.0:
        s[ZV_OS2] = peak


@njit(cache=True, **NO_REFCOUNT)
def zigzag_v1_update(
    phase,
    x,
    inp,
    alive,
    ts,
    p,
    w,
    enc,
    feat,
    obs,
    terms,
    reward,
    done,
):
    """ZigZag-v1 (phases as :func:`zigzag_update`; a course change due at the reset starts there)."""
    psiz = p[ZVP_PSIZ]
    osref = p[ZVP_OS_REF]
    imo = p[ZVP_IMO] > 0.0
    for k in range(x.shape[0]):
        if phase[k] == 0:
            continue
        uk, vk, rk, psik, nk, ek, dk, dck, revk, revck = motion(x, inp, k)
        s = ts[k]
        clear_row(terms, k)
        reached_now = False
        if phase[k] == 1:
            s[ZV_T] += p[ZVP_DT]
            if s[ZV_OS_ON] > 0.0:
                before = s[ZV_OS_PEAK]
                s[ZV_OS_PEAK], _rose, _fin = overshoot_step(
                    s[ZV_OS_SIGN], s[ZV_OS_TGT], before, psik, rk, OVERSHOOT_V1
                )
                terms[k, ZVT_OVERSHOOT] = -(s[ZV_OS_PEAK] - before) / osref
            if s[ZV_SIGN] != 0.0 and s[ZV_REACHED] == 0.0 and target_reached(s[ZV_SIGN], psik, s[ZV_TARGET]):
                reached_now = True
                s[ZV_REACHED] = 1.0
                s[ZV_NREACH] += 1.0
                if s[ZV_OS_ON] > 0.0:  # the previous change's measurement ends where this one begins
                    _close_overshoot_v1(s)
                s[ZV_OS_ON] = 1.0
                s[ZV_OS_SIGN] = s[ZV_SIGN]
                s[ZV_OS_TGT] = s[ZV_TARGET]
                s[ZV_OS_PEAK] = max(overshoot_excursion(s[ZV_SIGN], s[ZV_TARGET], psik), 0.0)
                terms[k, ZVT_OVERSHOOT] -= s[ZV_OS_PEAK] / osref
                terms[k, ZVT_REACHED] = s[ZV_DPSI] * p[ZVP_REACH]
        if s[ZV_T] >= s[ZV_NEXT] - 1e-9 or (imo and reached_now):  # a course change starts
            if s[ZV_SIGN] != 0.0 and s[ZV_REACHED] == 0.0:
                s[ZV_MISSED] += 1.0
            # closed when the next change starts; the IMO execute starts a change at the very sample the
            # measurement opens, and the change after that closes it
            if s[ZV_OS_ON] > 0.0 and not (imo and reached_now):
                _close_overshoot_v1(s)
            previous = s[ZV_TARGET]
            if imo:
                s[ZV_SIDE], s[ZV_TARGET] = zigzag_execute(s[ZV_PSI0], s[ZV_SIDE], psiz)
                s[ZV_SIGN] = s[ZV_SIDE]
                s[ZV_NEXT] = s[ZV_T] + p[ZVP_LEG_LIMIT]
            else:
                s[ZV_TARGET] += s[ZV_PEND_CHANGE]
                s[ZV_SIGN] = 1.0 if s[ZV_TARGET] >= psik else -1.0
                s[ZV_NEXT] = s[ZV_T] + s[ZV_PEND_LEG]
                s[ZV_DRAW] = 1.0
            s[ZV_DPSI] = abs(s[ZV_TARGET] - previous)
            s[ZV_REACHED] = 0.0
            s[ZV_CHANGES] += 1.0
        if phase[k] == 1:
            terms[k, ZVT_HEADING] = -abs(wrap_pi(s[ZV_TARGET] - psik)) / PI
            terms[k, ZVT_RUDDER] = rudder_activity(dck, s[ZV_PREV_ORDER], p[ZVP_DMAX])
            terms[k, ZVT_SPEED] = speed_loss(math.sqrt(uk * uk + vk * vk), s[ZV_U0])
        _zigzag_close_row(k, s, ZV_PREV_ORDER, x, inp, alive, w, enc, feat, obs, terms, reward, done)


# --- TurningCircle ------------------------------------------------------------------------------------------
TC_PSI0 = 0  # heading at the rudder order (episode start), rad
TC_N0 = 1  # midship position at the rudder order, m
TC_E0 = 2
TC_CMD = 3  # rate mode: commanded rate of turn, rad/s; radius mode: commanded curvature, 1/m
TC_PREV_ORDER = 4
TC_U0 = 5  # approach speed, m/s
TC_T = 6
TC_ADV = 7  # advance at 90 deg heading change, m
TC_TRF = 8  # transfer at 90 deg, m
TC_TD = 9  # tactical diameter (transfer at 180 deg), m
TC_R90 = 10  # 90 deg reached
TC_R180 = 11  # 180 deg reached
TC_MAXADV = 12  # largest advance so far, m
TC_MAXTRF = 13  # largest |transfer| so far, m
TC_PREV_TURNED = 14  # |heading change| at the previous step, rad
TC_PREV_ADV = 15  # advance and transfer at the previous step, m
TC_PREV_TRF = 16
TCN = 17

TCP_MODE = 0  # 0 rate, 1 radius, 2 reverse
TCP_L = 1
TCP_DMAX = 2
TCP_DT = 3
TCPN = 4

(
    TCF_CMD_RATE,
    TCF_RATE_ERR,
    TCF_CMD_CURV,
    TCF_CURV_ERR,
    TCF_HEAD_CHANGE,
    TCF_ADVANCE,
    TCF_TRANSFER,
) = range(FN_MOTION, 13)
TCFN = 13
TCT_TRACK, TCT_PROGRESS, TCT_FOOTPRINT, TCT_RUDDER, TCT_SPEED, TCT_TIME = range(6)
TCTN = 6


@njit(cache=True, **NO_REFCOUNT)
def turning_update(
    phase,
    x,
    inp,
    alive,
    ts,
    p,
    w,
    enc,
    feat,
    obs,
    terms,
    reward,
    done,
):
    """Turning task (phases as :func:`zigzag_update`); ``done`` set on a completed course reversal."""
    mode = int(p[TCP_MODE])
    L = p[TCP_L]
    for k in range(x.shape[0]):
        if phase[k] == 0:
            continue
        uk, vk, rk, psik, nk, ek, dk, dck, revk, revck = motion(x, inp, k)
        s = ts[k]
        done[k] = False
        clear_row(terms, k)
        adv, trf = course_axes(s[TC_PSI0], s[TC_N0], s[TC_E0], nk, ek)
        turned = abs(psik - s[TC_PSI0])
        U = math.sqrt(uk * uk + vk * vk)
        U0 = s[TC_U0]
        curv = rk / max(U, 0.1 * U0)
        if phase[k] == 1:
            s[TC_T] += p[TCP_DT]
            tp = s[TC_PREV_TURNED]
            if s[TC_R90] == 0.0 and turned >= ADVANCE_HEADING_RAD:
                fr = crossing_fraction(tp, turned, ADVANCE_HEADING_RAD)
                s[TC_ADV] = at_crossing(s[TC_PREV_ADV], adv, fr)
                s[TC_TRF] = abs(at_crossing(s[TC_PREV_TRF], trf, fr))
                s[TC_R90] = 1.0
            if s[TC_R180] == 0.0 and turned >= TACTICAL_HEADING_RAD:
                fr = crossing_fraction(tp, turned, TACTICAL_HEADING_RAD)
                s[TC_TD] = abs(at_crossing(s[TC_PREV_TRF], trf, fr))
                s[TC_R180] = 1.0
            ma = max(s[TC_MAXADV], adv)
            mt = max(s[TC_MAXTRF], abs(trf))
            if mode == 0:
                terms[k, TCT_TRACK] = -min(abs(rk - s[TC_CMD]) / abs(s[TC_CMD]), 1.0)
            elif mode == 1:
                terms[k, TCT_TRACK] = -min(abs(curv - s[TC_CMD]) / abs(s[TC_CMD]), 1.0)
            else:
                terms[k, TCT_PROGRESS] = (min(turned, PI) - min(tp, PI)) / PI
                terms[k, TCT_FOOTPRINT] = -((ma - s[TC_MAXADV]) + (mt - s[TC_MAXTRF])) / L
                terms[k, TCT_TIME] = -p[TCP_DT] * U0 / L
                done[k] = turned >= PI
            s[TC_MAXADV] = ma
            s[TC_MAXTRF] = mt
            terms[k, TCT_RUDDER] = rudder_activity(dck, s[TC_PREV_ORDER], p[TCP_DMAX])
            terms[k, TCT_SPEED] = speed_loss(U, U0)
        if not alive[k]:
            done[k] = True
            clear_row(terms, k)
        _finish(terms, k, w, reward)
        s[TC_PREV_ORDER] = dck
        s[TC_PREV_TURNED] = turned
        s[TC_PREV_ADV] = adv
        s[TC_PREV_TRF] = trf
        f = feat[k]
        motion_features(f, uk, vk, rk, dk, dck, revk)
        f[TCF_CMD_RATE] = s[TC_CMD] if mode == 0 else 0.0
        f[TCF_RATE_ERR] = s[TC_CMD] - rk if mode == 0 else 0.0
        f[TCF_CMD_CURV] = s[TC_CMD] * L if mode == 1 else 0.0
        f[TCF_CURV_ERR] = (s[TC_CMD] - curv) * L if mode == 1 else 0.0
        f[TCF_HEAD_CHANGE] = psik - s[TC_PSI0]
        f[TCF_ADVANCE] = adv
        f[TCF_TRANSFER] = trf
        encode_row(feat, k, enc, obs)


# --- geometry -------------------------------------------------------------------------------------------------
# Helpers that take arrays are inlined where they are called (inline="always"): a call to a compiled function
# with array arguments keeps numba from pruning the caller's reference counts, an atomic increment and
# decrement per array per call (the chart query paid 16 of them per ship).
@njit(cache=True)
def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


@njit(cache=True)
def _seg_intersect(ax, ay, bx, by, cx, cy, dx, dy):
    d1 = _cross(bx - ax, by - ay, cx - ax, cy - ay)
    d2 = _cross(bx - ax, by - ay, dx - ax, dy - ay)
    d3 = _cross(dx - cx, dy - cy, ax - cx, ay - cy)
    d4 = _cross(dx - cx, dy - cy, bx - cx, by - cy)
    return ((d1 > 0.0) != (d2 > 0.0)) and ((d3 > 0.0) != (d4 > 0.0))


@njit(cache=True)
def _point_seg_dist2(px, py, ax, ay, bx, by):
    """Squared distance from point p to segment ab, m^2 (callers take one sqrt of the minimum)."""
    ex = bx - ax
    ey = by - ay
    ll = ex * ex + ey * ey
    t = 0.0 if ll == 0.0 else ((px - ax) * ex + (py - ay) * ey) / ll
    t = min(max(t, 0.0), 1.0)  # min/max, not branches: which end clamps varies from call to call
    qx = ax + t * ex - px
    qy = ay + t * ey - py
    return qx * qx + qy * qy


@njit(cache=True, inline="always")
def _inside(px, py, xs, ys, start, count):
    """Point (px, py) inside the polygon of vertices (xs, ys)[start : start + count] (even-odd rule)."""
    inside = False
    x0 = xs[start + count - 1]  # each edge runs from the previous vertex (no modulo per vertex)
    y0 = ys[start + count - 1]
    for i in range(start, start + count):
        x1 = xs[i]
        y1 = ys[i]
        if (y0 > py) != (y1 > py) and px < x0 + (py - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
        x0 = x1
        y0 = y1
    return inside


def chart_tables(polygons: list[tuple[int, list]]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The chart as :func:`chart_query` reads it, from (kind, [(north, east), ...]) polygons (kind 1 hard
    obstacle, 2 shoal): three arrays, because every array argument of a compiled call costs a little.

    ``edges`` (n_vertices, 6): vertex (north, east), then the bounding box (n min, n max, e min, e max) of
    the edge from it to the next vertex of its polygon; ``polys`` (n_polygons, 4) int: first vertex row,
    vertex count, kind, orientation (+1 if the vertices run anticlockwise in (north, east) axes, i.e. the
    interior lies left of each edge, else -1); ``pbox`` (n_polygons, 4): each polygon's bounding box.
    """
    verts = np.array([p for _k, pts in polygons for p in pts], dtype=np.float64).reshape(-1, 2)
    count = np.array([len(pts) for _k, pts in polygons], dtype=np.int64)
    start = np.concatenate([[0], np.cumsum(count)[:-1]]).astype(np.int64) if polygons else count
    kind = np.array([k for k, _p in polygons], dtype=np.int64)
    polys = np.stack([start, count, kind, np.ones_like(count)], axis=1)
    edges = np.zeros((verts.shape[0], 6))
    pbox = np.zeros((len(polygons), 4))
    for q, (st, cnt) in enumerate(zip(start, count)):
        a = verts[st : st + cnt]
        b = np.roll(a, -1, axis=0)
        edges[st : st + cnt, 0:2] = a
        edges[st : st + cnt, 2] = np.minimum(a[:, 0], b[:, 0])
        edges[st : st + cnt, 3] = np.maximum(a[:, 0], b[:, 0])
        edges[st : st + cnt, 4] = np.minimum(a[:, 1], b[:, 1])
        edges[st : st + cnt, 5] = np.maximum(a[:, 1], b[:, 1])
        pbox[q] = a[:, 0].min(), a[:, 0].max(), a[:, 1].min(), a[:, 1].max()
        area2 = float(np.sum(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]))  # shoelace: twice the signed area
        polys[q, 3] = 1 if area2 > 0.0 else -1
    return edges, polys.reshape(-1, 4), pbox


@njit(cache=True, inline="always")
def _box_gap2(n0, n1, e0, e1, table, row, col):
    """Squared distance between the box [n0, n1] x [e0, e1] and the box (n min, n max, e min, e max) in
    ``table[row, col : col + 4]``, m^2 (read in place: a row view would cost a reference count)."""
    gn = max(table[row, col] - n1, n0 - table[row, col + 1], 0.0)
    ge = max(table[row, col + 2] - e1, e0 - table[row, col + 3], 0.0)
    return gn * gn + ge * ge


@njit(cache=True)
def _reach2(cull2, rh):
    """Squared distance from the midship point beyond which an edge cannot come within sqrt(cull2) of a hull
    of radius ``rh`` about that point, m^2; widened by 1e-9 relative so that rounding never skips an edge
    that holds the minimum."""
    r = (math.sqrt(cull2) + rh) * (1.0 + 1e-9)
    return r * r


@njit(cache=True, error_model="numpy")
def chart_query(n0, e0, psi, hull, edges, polys, pbox, beam_dirs, beam_range, beams, hn, he, bw):
    """Contact, grounding, clearance and range beams of one ship at (n0, e0, psi) among chart polygons.

    ``hull``: outline in body axes (x forward, y starboard), m. ``edges``, ``polys``, ``pbox``: the chart
    (:func:`chart_tables`).
    ``beam_dirs``: (n_beams, 2) unit vectors of the beams in body axes (x forward, y starboard).
    Fills ``beams`` (m, capped at ``beam_range``) measured from the midship point; returns
    (outcome flag OK/CONTACT/GROUNDING, clearance m = distance hull outline to the nearest polygon edge).
    ``hn``, ``he``: scratch arrays of the hull's length; ``bw``: scratch of shape (2, n_beams). Compiled
    with numpy's floating-point error model: a division by zero gives inf or nan (no exception check in the
    beam loop, so that it vectorises).

    The beams go first, then contact and clearance. Polygons and edges whose bounding box is farther than
    the beam range (beams) or than the clearance found so far are skipped: the distance to a box bounds the
    distance to what is inside it. The nearest beam hit t bounds the clearance from above by t + the hull's
    radius about the midship point (the hit lies on an edge, every hull vertex within that radius of the
    midship point), so that the clearance pass skips, from its start, the polygons and edges farther than
    that, and gives the vertex-to-segment distances only to the few edges near the nearest one. Skipping only
    what cannot be nearer, the results are those of testing every edge.
    """
    c = math.cos(psi)
    s = math.sin(psi)
    nh = hull.shape[0]
    hb0 = hb1 = hb2 = hb3 = 0.0  # the hull's box
    rh2 = 0.0  # squared radius of the hull about the midship point
    for i in range(nh):
        x = hull[i, 0]
        y = hull[i, 1]
        hn[i], he[i] = body_point_to_earth(n0, e0, c, s, x, y)
        if i == 0:
            hb0 = hb1 = hn[0]
            hb2 = hb3 = he[0]
        hb0 = min(hb0, hn[i])  # min/max, not branches: which vertex is extreme depends on the heading
        hb1 = max(hb1, hn[i])
        hb2 = min(hb2, he[i])
        hb3 = max(hb3, he[i])
        rh2 = max(rh2, x * x + y * y)
    rh = math.sqrt(rh2)
    nb = beams.shape[0]
    for j in range(nb):
        x = beam_dirs[j, 0]
        y = beam_dirs[j, 1]
        beams[j] = beam_range
        bw[0, j], bw[1, j] = body_to_earth(c, s, x, y)  # beam direction (north, east)
    npoly = polys.shape[0]
    vn = edges[:, 0]
    ve = edges[:, 1]
    range2 = beam_range * beam_range

    # Range beams from the midship point o. A ray from outside a polygon meets it first on an edge that faces
    # o (it enters there), so edges that face away are skipped, unless o is inside this polygon (aground or
    # in contact).
    for q in range(npoly):
        pgap2 = _box_gap2(n0, n0, e0, e0, pbox, q, 0)
        if pgap2 >= range2:
            continue
        st = polys[q, 0]
        cnt = polys[q, 1]
        orient = polys[q, 3]
        inside = pgap2 == 0.0 and _inside(n0, e0, vn, ve, st, cnt)
        r = st + cnt - 1  # edge r -> m (its box is in row r): the closing edge first, no modulo per edge
        for m in range(st, st + cnt):
            ax = vn[r]
            ay = ve[r]
            ex = vn[m] - ax
            ey = ve[m] - ay
            aon = ax - n0
            aoe = ay - e0
            tn = _cross(aon, aoe, ex, ey)  # o is on the interior side of the edge's line if orient * tn > 0
            if (inside or orient * tn <= 0.0) and _box_gap2(n0, n0, e0, e0, edges, r, 2) < range2:
                for j in range(nb):
                    # ray o + t d meets a + s e at t = (a - o) x e / (d x e), s = (a - o) x d / (d x e);
                    # 0 <= s <= 1 is tested on the numerator against the denominator (sign-aware), so one
                    # division per beam. Branch-free so that the beams run in SIMD lanes: d x e = 0 gives
                    # inf or nan (no hit); fmin, not a conditional store, because a conditional store
                    # vectorises to a masked store, slow and not forwarded to the next edge's loads.
                    dn = bw[0, j]
                    de = bw[1, j]
                    den = _cross(dn, de, ex, ey)
                    t = tn / den
                    sn = _cross(aon, aoe, dn, de)
                    sn = sn if den > 0.0 else -sn
                    hit = (t >= 0.0) & (sn >= 0.0) & (sn <= abs(den))
                    beams[j] = np.fmin(beams[j], t if hit else np.inf)
            r = m

    # contact and clearance
    flag = OK
    clear2 = range2  # squared clearance so far
    bmin = beam_range
    for j in range(nb):
        bmin = min(bmin, beams[j])
    near = (bmin + rh) * (1.0 + 1e-9)  # every hull vertex is at most this far from the nearest hit (if any)
    cull2 = min(clear2, near * near)  # the clearance is at most this: farther polygons and edges are skipped
    reach2 = _reach2(cull2, rh)
    for q in range(npoly):
        st = polys[q, 0]
        cnt = polys[q, 1]
        gap2 = _box_gap2(hb0, hb1, hb2, hb3, pbox, q, 0)
        if gap2 == 0.0:  # the boxes overlap: does the hull touch the polygon?
            hit = False
            r = st + cnt - 1
            for m in range(st, st + cnt):
                if _box_gap2(hb0, hb1, hb2, hb3, edges, r, 2) == 0.0:  # else it cannot cross the hull
                    i2 = nh - 1
                    for i in range(nh):
                        if _seg_intersect(hn[i2], he[i2], hn[i], he[i], vn[r], ve[r], vn[m], ve[m]):
                            hit = True
                            break
                        i2 = i
                    if hit:
                        break
                r = m
            # no crossing: each outline lies wholly inside or wholly outside the other
            hit = hit or _inside(hn[0], he[0], vn, ve, st, cnt) or _inside(vn[st], ve[st], hn, he, 0, nh)
            if hit:
                clear2 = cull2 = 0.0
                if polys[q, 2] == 1:
                    flag = CONTACT
                elif flag == OK:
                    flag = GROUNDING
        if gap2 < cull2:  # (cull2 <= clear2: the box test of testing every edge is included)
            r = st + cnt - 1
            for m in range(st, st + cnt):
                ax = vn[r]
                ay = ve[r]
                bx = vn[m]
                by = ve[m]
                # an edge farther than reach from o is farther than sqrt(cull2) from the hull
                if (
                    _box_gap2(hb0, hb1, hb2, hb3, edges, r, 2) < cull2
                    and _point_seg_dist2(n0, e0, ax, ay, bx, by) <= reach2
                ):
                    # the distance between the outlines is that between a vertex of one and an edge of the
                    # other; vertex a's distances to the hull's edges only if a is within reach
                    near_a = (ax - n0) * (ax - n0) + (ay - e0) * (ay - e0) <= reach2
                    i2 = nh - 1
                    for i in range(nh):
                        clear2 = min(clear2, _point_seg_dist2(hn[i], he[i], ax, ay, bx, by))
                        if near_a:
                            clear2 = min(clear2, _point_seg_dist2(ax, ay, hn[i2], he[i2], hn[i], he[i]))
                        i2 = i
                    if clear2 < cull2:
                        cull2 = clear2
                        reach2 = _reach2(cull2, rh)
                r = m
    return flag, math.sqrt(clear2)


# --- HarbourApproach -----------------------------------------------------------------------------------------
# (the current and the wind are not task state: the kernel reads the environment rows the physics uses)
HS_D_PREV = 0  # distance to the goal point at the previous step, m
HS_PREV_ORDER = 1
HS_MIN_CLEAR = 2  # smallest clearance this episode, m
HS_CLEAR = 3  # clearance now, m
HS_T = 4
HS_PATH = 5  # distance sailed over ground, m
HS_PREV_N = 6
HS_PREV_E = 7
HS_SOG = 8  # speed over ground, m/s
HSN = 9

HP_L = 0
HP_DMAX = 1
HP_DT = 2
HP_BEAM_RANGE = 3
HP_GOAL_N = 4
HP_GOAL_E = 5
HP_GOAL_HDG = 6
HP_GOAL_TOL = 7
HP_GOAL_VMAX = 8
HP_UT = 9  # ship test speed (speed scale), m/s
HP_SLOW_DIST = 10  # distance from the goal inside which the allowed speed falls linearly, m
HP_CLEAR_REF = 11  # clearance below which the proximity term grows, m
HP_N_MIN = 12  # chart bounds, m
HP_N_MAX = 13
HP_E_MIN = 14
HP_E_MAX = 15
HPN = 16

(
    HF_REV_C,
    HF_GOAL_X,
    HF_GOAL_Y,
    HF_GOAL_DIST,
    HF_GOAL_HDG_ERR,
    HF_SOG,
    HF_WIND_SPEED,
    HF_WIND_SIN,
    HF_WIND_COS,
    HF_CUR_X,
    HF_CUR_Y,
) = range(FN_MOTION, 17)
HFN0 = 17  # range beams follow
HT_PROGRESS, HT_SPEED, HT_PROXIMITY, HT_RUDDER, HT_TIME, HT_SUCCESS, HT_COLLISION, HT_OUT = range(8)
HTN = 8


@njit(cache=True)
def harbour_update(phase, x, inp, env, alive, ts, p, hull, edges, polys, pbox, goal_verts, beam_dirs, *args):
    """Harbour task for vessels k0..k1-1 (phases as :func:`zigzag_update`); ``flags`` get the outcome of
    stepped vessels. ``env`` is the simulation's environment rows (``sim.env``: current and wind as the
    physics sees them). Arguments after ``beam_dirs``: w, enc, feat, obs, terms, reward, flags, done, k0, k1
    (the range last, so that the task binds (0, N) with the other arguments). Allocates the chart query's
    scratch and runs :func:`_harbour_range`."""
    nb = beam_dirs.shape[0]
    beams = np.empty(nb)
    hn = np.empty(hull.shape[0])
    he = np.empty(hull.shape[0])
    bw = np.empty((2, nb))
    _harbour_range(
        phase,
        x,
        inp,
        env,
        alive,
        ts,
        p,
        hull,
        edges,
        polys,
        pbox,
        goal_verts,
        beam_dirs,
        *args,
        beams,
        hn,
        he,
        bw,
    )


@njit(cache=True, **NO_REFCOUNT)
def _harbour_range(
    phase,
    x,
    inp,
    env,
    alive,
    ts,
    p,
    hull,
    edges,
    polys,
    pbox,
    goal_verts,
    beam_dirs,
    w,
    enc,
    feat,
    obs,
    terms,
    reward,
    flags,
    done,
    k0,
    k1,
    beams,
    hn,
    he,
    bw,
):
    """:func:`harbour_update`'s loop over vessels k0..k1-1, with the chart query's scratch arrays."""
    nb = beam_dirs.shape[0]
    L = p[HP_L]
    UT = p[HP_UT]
    for k in range(k0, k1):
        if phase[k] == 0:
            continue
        uk, vk, rk, psik, nk, ek, dk, dck, revk, revck = motion(x, inp, k)
        s = ts[k]
        clear_row(terms, k)
        c = math.cos(psik)
        sn = math.sin(psik)
        cur_n = env[k, lo.E_CUR_N]
        cur_e = env[k, lo.E_CUR_E]
        vn, ve = ground_velocity(uk, vk, c, sn, cur_n, cur_e)
        sog = speed_over_ground(vn, ve)
        flag, clear = chart_query(
            nk,
            ek,
            psik,
            hull,
            edges,
            polys,
            pbox,
            beam_dirs,
            p[HP_BEAM_RANGE],
            beams,
            hn,
            he,
            bw,
        )
        gn = p[HP_GOAL_N] - nk
        ge = p[HP_GOAL_E] - ek
        dist = math.sqrt(gn * gn + ge * ge)
        herr = wrap_pi(p[HP_GOAL_HDG] - psik)
        if flag == OK:
            if not alive[k]:
                flag = DIVERGED
            elif not (p[HP_N_MIN] <= nk <= p[HP_N_MAX] and p[HP_E_MIN] <= ek <= p[HP_E_MAX]):
                flag = OUT_OF_BOUNDS
            elif (
                sog <= p[HP_GOAL_VMAX]
                and abs(herr) <= p[HP_GOAL_TOL]
                and _inside(nk, ek, goal_verts[:, 0], goal_verts[:, 1], 0, goal_verts.shape[0])
            ):
                flag = SUCCESS
        s[HS_CLEAR] = clear
        if phase[k] == 1:
            flags[k] = flag
            s[HS_T] += p[HP_DT]
            dpn = nk - s[HS_PREV_N]
            dpe = ek - s[HS_PREV_E]
            s[HS_PATH] += math.sqrt(dpn * dpn + dpe * dpe)
            if clear < s[HS_MIN_CLEAR]:
                s[HS_MIN_CLEAR] = clear
            terms[k, HT_PROGRESS] = (s[HS_D_PREV] - dist) / L
            allowed = max(p[HP_GOAL_VMAX], UT * min(1.0, dist / p[HP_SLOW_DIST]))
            if sog > allowed:
                terms[k, HT_SPEED] = -(sog - allowed) / UT
            if clear < p[HP_CLEAR_REF]:
                terms[k, HT_PROXIMITY] = -(1.0 - clear / p[HP_CLEAR_REF])
            terms[k, HT_RUDDER] = rudder_activity(dck, s[HS_PREV_ORDER], p[HP_DMAX])
            terms[k, HT_TIME] = -1.0
            if flag == SUCCESS:
                terms[k, HT_SUCCESS] = 1.0
            elif flag == CONTACT or flag == GROUNDING or flag == DIVERGED:
                terms[k, HT_COLLISION] = -1.0
            elif flag == OUT_OF_BOUNDS:
                terms[k, HT_OUT] = -1.0
            if flag == DIVERGED:
                clear_row(terms, k)
                terms[k, HT_COLLISION] = -1.0
        else:
            flags[k] = OK
            s[HS_MIN_CLEAR] = clear
        done[k] = flags[k] != OK
        _finish(terms, k, w, reward)
        s[HS_D_PREV] = dist
        s[HS_PREV_ORDER] = dck
        s[HS_PREV_N] = nk
        s[HS_PREV_E] = ek
        s[HS_SOG] = sog
        # body-frame quantities as sensed on the bridge
        ug, vg = ground_velocity_body(uk, vk, c, sn, cur_n, cur_e)
        Vrw, _gamma, cos_g, sin_g = relative_wind(ug, vg, c, sn, env[k, lo.E_WIND_N], env[k, lo.E_WIND_E])
        f = feat[k]
        motion_features(f, uk, vk, rk, dk, dck, revk)
        f[HF_REV_C] = revck
        f[HF_GOAL_X], f[HF_GOAL_Y] = earth_to_body(c, sn, gn, ge)
        f[HF_GOAL_DIST] = dist
        f[HF_GOAL_HDG_ERR] = herr
        f[HF_SOG] = sog
        f[HF_WIND_SPEED] = Vrw
        f[HF_WIND_SIN] = sin_g
        f[HF_WIND_COS] = cos_g
        f[HF_CUR_X], f[HF_CUR_Y] = current_body(c, sn, cur_n, cur_e)
        for j in range(nb):
            f[HFN0 + j] = beams[j]
        encode_row(feat, k, enc, obs)


@njit(cache=True, parallel=True)
def harbour_update_parallel(phase, x, *args):
    """:func:`harbour_update` (same arguments; its range is ignored: all vessels) with contiguous chunks of
    vessels spread over threads (large batches: the chart query costs about half a microsecond per vessel,
    the threads' wake-up tens of microseconds)."""
    n = x.shape[0]
    nchunks = min(n, MAX_CHUNKS)
    for c in prange(nchunks):
        harbour_update(phase, x, *args[:-2], c * n // nchunks, (c + 1) * n // nchunks)
