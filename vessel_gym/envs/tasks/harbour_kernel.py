"""The compiled step of the HarbourApproach task (:mod:`vessel_gym.envs.tasks.harbour`): the chart query, the
outcome, the reward terms and the features of every vessel (:func:`harbour_update`), and its threaded driver for
large batches (:func:`harbour_update_parallel`). The columns it reads and writes are
:mod:`vessel_gym.envs.tasks.harbour_columns`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from vessel_gym.control.angles import wrap_pi
from vessel_gym.envs.declare import RAD_TO_DEG
from vessel_gym.envs.tasks.chart import (
    CONTACT,
    DIVERGED,
    GROUNDING,
    OK,
    OUT_OF_BOUNDS,
    SUCCESS,
    chart_query,
    inside_polygon,
)
from vessel_gym.envs.tasks.common import (
    clear_row,
    encode_row,
    finish,
    motion,
    motion_features,
    rudder_activity,
)
from vessel_gym.envs.tasks.harbour_columns import FEAT, INFO, TERM, P, S
from vessel_gym.physics.integrate import MAX_CHUNKS
from vessel_gym.physics.kinematics import (
    air_velocity,
    apparent_wind,
    current_body,
    current_velocity,
    earth_to_body,
    ground_velocity,
    speed_over_ground,
)
from vessel_gym.physics.vessel import NO_REFCOUNT

# batches from this size run the task kernel on all threads (about 0.6 us of work per ship; waking the threads
# costs tens of microseconds on an idle machine)
PARALLEL_MIN_SHIPS = 256


@njit(cache=True, **NO_REFCOUNT)
def harbour_update(phase, v, t):
    """Harbour task of every vessel in ``phase`` (phases as :func:`~vessel_gym.envs.tasks.zigzag.zigzag_update`;
    ``v`` the vessels' record, ``t`` the task's, :data:`~vessel_gym.envs.tasks.harbour_columns.HarbourArrays`):
    ``flags`` get the outcome of stepped vessels. The chart query's scratch is the task's."""
    _harbour_range(phase, v, t, 0, t.ts.shape[0], t.beams, t.hn, t.he, t.bw)


@njit(cache=True, **NO_REFCOUNT)
def _harbour_range(phase, v, t, k0, k1, beams, hn, he, bw):
    """:func:`harbour_update`'s loop over vessels k0..k1-1, with the chart query's scratch arrays."""
    env, alive, feat, terms, done = v.env, v.alive, v.feat, v.terms, v.done
    ts, p, flags, beam_dirs = t.ts, t.p, t.flags, t.beam_dirs
    hull, edges, polys, pbox, goal_verts = t.hull, t.edges, t.polys, t.pbox, t.goal_verts
    nb = beam_dirs.shape[0]
    L = p[P.L]
    UT = p[P.U_T]
    for k in range(k0, k1):
        if phase[k] == 0:
            continue
        uk, vk, rk, psik, nk, ek, dk, dck, revk, revck = motion(v, k)
        s = ts[k]
        clear_row(terms, k)
        c = math.cos(psik)
        sn = math.sin(psik)
        cur_n, cur_e = current_velocity(env, k)
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
            p[P.beam_range],
            beams,
            hn,
            he,
            bw,
        )
        gn = p[P.goal_north] - nk
        ge = p[P.goal_east] - ek
        dist = math.sqrt(gn * gn + ge * ge)
        herr = wrap_pi(p[P.goal_heading] - psik)
        if flag == OK:
            if not alive[k]:
                flag = DIVERGED
            elif not (p[P.north_min] <= nk <= p[P.north_max] and p[P.east_min] <= ek <= p[P.east_max]):
                flag = OUT_OF_BOUNDS
            elif (
                sog <= p[P.goal_max_speed]
                and abs(herr) <= p[P.goal_tolerance]
                and inside_polygon(nk, ek, goal_verts[:, 0], goal_verts[:, 1], 0, goal_verts.shape[0])
            ):
                flag = SUCCESS
        s[S.clearance] = clear
        if phase[k] == 1:
            flags[k] = flag
            s[S.t] += p[P.dt]
            dpn = nk - s[S.prev_north]
            dpe = ek - s[S.prev_east]
            s[S.path] += math.sqrt(dpn * dpn + dpe * dpe)
            if clear < s[S.min_clearance]:
                s[S.min_clearance] = clear
            terms[k, TERM.progress] = (s[S.d_prev] - dist) / L
            allowed = max(p[P.goal_max_speed], UT * min(1.0, dist / p[P.slow_distance]))
            if sog > allowed:
                terms[k, TERM.speed_excess] = -(sog - allowed) / UT
            if clear < p[P.clearance_ref]:
                terms[k, TERM.proximity] = -(1.0 - clear / p[P.clearance_ref])
            terms[k, TERM.rudder_activity] = rudder_activity(dck, s[S.prev_order], p[P.rudder_max])
            terms[k, TERM.time] = -1.0
            if flag == SUCCESS:
                terms[k, TERM.success] = 1.0
            elif flag == CONTACT or flag == GROUNDING or flag == DIVERGED:
                terms[k, TERM.collision] = -1.0
            elif flag == OUT_OF_BOUNDS:
                terms[k, TERM.out_of_bounds] = -1.0
            if flag == DIVERGED:
                clear_row(terms, k)
                terms[k, TERM.collision] = -1.0
        else:
            flags[k] = OK
            s[S.min_clearance] = clear
        done[k] = flags[k] != OK
        finish(v, k)
        s[S.d_prev] = dist
        s[S.prev_order] = dck
        s[S.prev_north] = nk
        s[S.prev_east] = ek
        s[S.sog] = sog
        # body-frame quantities as sensed on the bridge
        wind_n, wind_e = air_velocity(env, k)
        Vrw, _gamma, cos_g, sin_g = apparent_wind(uk, vk, c, sn, cur_n, cur_e, wind_n, wind_e)
        f = feat[k]
        motion_features(f, uk, vk, rk, dk, dck, revk)
        f[FEAT.rev_order] = revck
        f[FEAT.goal_x], f[FEAT.goal_y] = earth_to_body(c, sn, gn, ge)
        f[FEAT.goal_distance] = dist
        f[FEAT.goal_heading_error] = herr
        f[FEAT.sog] = sog
        f[FEAT.wind_speed] = Vrw
        f[FEAT.wind_angle_sin] = sin_g
        f[FEAT.wind_angle_cos] = cos_g
        f[FEAT.current_x], f[FEAT.current_y] = current_body(c, sn, cur_n, cur_e)
        for j in range(nb):
            f[FEAT.beam + j] = beams[j]
        encode_row(v, k)
        fl = flags[k]
        i = v.info[k]
        i[INFO.success] = 1.0 if fl == SUCCESS else 0.0
        i[INFO.contact] = 1.0 if fl == CONTACT else 0.0
        i[INFO.grounding] = 1.0 if fl == GROUNDING else 0.0
        i[INFO.out_of_bounds] = 1.0 if fl == OUT_OF_BOUNDS else 0.0
        i[INFO.diverged] = 1.0 if fl == DIVERGED else 0.0
        i[INFO.time_s] = s[S.t]
        i[INFO.clearance_m] = s[S.clearance]
        i[INFO.min_clearance_m] = s[S.min_clearance]
        i[INFO.distance_to_goal_m] = s[S.d_prev]
        i[INFO.speed_over_ground_m_s] = s[S.sog]
        i[INFO.heading_error_deg] = herr * RAD_TO_DEG  # as math.degrees computes it
        i[INFO.path_m] = s[S.path]


@njit(cache=True, parallel=True)
def harbour_update_parallel(phase, v, t):
    """:func:`harbour_update` with contiguous chunks of vessels spread over threads, each with its own scratch
    (large batches: the chart query costs about half a microsecond per vessel, the threads' wake-up tens of
    microseconds)."""
    n = t.ts.shape[0]
    nb = t.beam_dirs.shape[0]
    nh = t.hull.shape[0]
    nchunks = min(n, MAX_CHUNKS)
    for c in prange(nchunks):
        beams = np.empty(nb)
        hn = np.empty(nh)
        he = np.empty(nh)
        bw = np.empty((2, nb))
        _harbour_range(phase, v, t, c * n // nchunks, (c + 1) * n // nchunks, beams, hn, he, bw)
