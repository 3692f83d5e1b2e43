"""The step of CollisionAvoidance for every own ship in ``phase``: its route, the targets it sees (CPA,
situation at detection, the K most dangerous as a fixed-size list), contact between hull outlines, the COLREG
records of every pair, reward terms and the episode's end.

Plain Python over scalars (an encounter has a handful of ships; the physics of all of them is one batched
simulation). The columns it writes are the declaration's (``colreg_columns``).
"""

from __future__ import annotations

import math

import numpy as np

from vessel_gym.control.angles import wrap_pi
from vessel_gym.envs.task import PHASE_STEP
from vessel_gym.envs.tasks.colreg_columns import FEAT, OUTCOMES, SLOT, TARGET_FIELDS, TERM, P, S
from vessel_gym.envs.tasks.colreg_geometry import (
    GIVE_WAY,
    HEAD_ON,
    OVERTAKEN,
    OVERTAKING,
    SAFE,
    STAND_ON,
    classify,
    cpa,
    hulls_touch,
    place,
    polygon_edges,
    relative_bearing,
    sector_minima,
    sweep,
)
from vessel_gym.envs.tasks.colreg_rules import R, detect, narrow_channel, score_row, track
from vessel_gym.envs.tasks.common import (
    clear_row,
    encode_row,
    finish,
    motion,
    motion_features,
    rudder_activity,
)
from vessel_gym.physics.kinematics import (
    current_velocity,
    earth_to_body,
    ground_velocity,
    heading,
    position,
    velocity_through_water,
)
from vessel_gym.scenarios.geometry import polygons_overlap

#: the one-hot situation columns of a target slot; being overtaken is a stand-on role (rule 17), as crossing
ONE_HOT = {
    HEAD_ON: "head_on",
    OVERTAKING: "overtaking",
    GIVE_WAY: "give_way",
    STAND_ON: "stand_on",
    OVERTAKEN: "stand_on",
}
ARRIVED, COLLISION, STRAYED, DIVERGED, GROUNDING = (
    OUTCOMES.index(o) for o in ("arrived", "collision", "strayed", "diverged", "grounding")
)


def _ship(x, env, j):
    """(north, east, heading, velocity over ground north, east) of vessel j."""
    n, e = position(x, j)
    psi = heading(x, j)
    u, v, _r = velocity_through_water(x, j)
    cn, ce = current_velocity(env, j)
    vn, ve = ground_velocity(u, v, math.cos(psi), math.sin(psi), cn, ce)
    return n, e, psi, vn, ve


def colreg_update(phase, v, t):
    """The step of every own ship k with ``phase[k]`` 1 (stepped) or 2 (just reset: features only).

    ``v``: the framework's record of the vessels; ``t``: the task's (``CollisionAvoidanceArrays``): the task
    state ``ts``, the COLREG ``scores``, ``pairs[k, s]`` own ship k's record of the ship in slot s of its
    encounter (:data:`~vessel_gym.envs.tasks.colreg_rules.R`), the parameter row ``p`` and the ``world``
    (:class:`~vessel_gym.envs.tasks.colreg_world.World`: which vessels share an encounter, which are in it, their
    outline).
    """
    x, env, alive, feat, terms = v.x, v.env, v.alive, v.feat, v.terms
    ts, pairs, p, world = t.ts, t.pairs, t.p, t.world
    leaving = []
    for k in range(ts.shape[0]):
        if phase[k] == 0:
            continue
        stepped = phase[k] == PHASE_STEP
        u, vv, r, psi, n, e, rudder, order, rev, _rev_order = motion(v, k)
        s = ts[k]
        clear_row(terms, k)
        feat[k, :] = 0.0
        if stepped:
            s[S.t] += p[P.dt]
            s[S.path] += math.hypot(n - s[S.prev_n], e - s[S.prev_e])
        s[S.prev_n], s[S.prev_e] = n, e
        # the route: a straight leg from the start to the goal
        ln, le = s[S.n1] - s[S.n0], s[S.e1] - s[S.e0]
        leg = math.hypot(ln, le)
        alpha = math.atan2(le, ln)
        cross = -(n - s[S.n0]) * math.sin(alpha) + (e - s[S.e0]) * math.cos(alpha)
        gn, ge = s[S.n1] - n, s[S.e1] - e
        goal = math.hypot(gn, ge)
        goal_brg = relative_bearing(gn, ge, psi)
        U = math.hypot(u, vv)
        # the other ships of the encounter
        w_slot = world.slot_of[k]
        own_outline = place(world.outline, n, e, psi)
        closest = math.inf
        collided = False
        port_with_give_way = False
        listed = []
        channel = []  # rule 9: the others' (offset, heading off the channel, DCPA, TCPA, range, situation)
        sa, ca = math.sin(alpha), math.cos(alpha)
        hulls = []  # the other ships' outlines within the sensors' reach
        sensing = world.sensors > 0
        grounded = stepped and _aground(own_outline, n, e, world)
        on, oe, opsi, ovn, ove = _ship(x, env, k)
        for slot, j in enumerate(world.members[world.world_of[k]]):
            if slot == w_slot or not world.active[j]:
                continue
            tn, te, tpsi, tvn, tve = _ship(x, env, j)
            pn, pe = tn - on, te - oe
            wn, we = tvn - ovn, tve - ove
            rng = math.hypot(pn, pe)
            dcpa, tcpa = cpa(pn, pe, wn, we)
            closest = min(closest, rng)
            if (stepped and rng < world.reach) or (sensing and rng < p[P.sensor_range] + world.reach):
                outline = place(world.outline, tn, te, tpsi)
                if stepped and rng < world.reach and hulls_touch(own_outline, outline):
                    collided = True
                if sensing:
                    hulls.append(outline)
            rec = pairs[k, slot]
            if rec[R.situation] == SAFE and rng <= p[P.detection]:
                sit = classify(pn, pe, psi, tpsi, dcpa < p[P.risk] and tcpa > 0.0)
                if sit != SAFE:
                    detect(rec, sit, s[S.t], psi, U, rng, tcpa)
            sit = int(rec[R.situation])
            if sit != SAFE and stepped:
                ahead = (
                    -pn * math.cos(tpsi) - pe * math.sin(tpsi) > 0.0
                )  # own ship forward of the target's beam
                track(rec, s[S.t], psi, U, rng, tcpa, ahead, p[P.action], p[P.release])
            if sit in (HEAD_ON, GIVE_WAY) and tcpa > 0.0 and order < -p[P.port_order]:
                port_with_give_way = True
            if p[P.ch_half] > 0.0:  # the truth, as the rule records
                off = -(tn - s[S.n0]) * sa + (te - s[S.e0]) * ca + p[P.ch_offset]
                channel.append((off, wrap_pi(tpsi - alpha), dcpa, tcpa, rng, sit))
            if world.ais is not None:  # the target as received over AIS, dead-reckoned to now
                _u, _v, tr = velocity_through_water(x, j)
                an, ae, avn, ave = world.ais.observe(k, slot, s[S.t], tn, te, tvn, tve, tr)
                pn, pe, wn, we = an - on, ae - oe, avn - ovn, ave - ove
                rng = math.hypot(pn, pe)
                dcpa, tcpa = cpa(pn, pe, wn, we)
            listed.append((dcpa + 0.1 * rng, rng, pn, pe, wn, we, dcpa, tcpa, sit))
        listed.sort()
        cos_p, sin_p = math.cos(psi), math.sin(psi)
        for i, (_key, rng, pn, pe, wn, we, dcpa, tcpa, sit) in enumerate(listed[: world.slots_observed]):
            base = FEAT.t0_valid + i * SLOT
            beta = relative_bearing(pn, pe, psi)
            ru, rv = earth_to_body(cos_p, sin_p, wn, we)
            row = feat[k]
            row[base + TARGET_FIELDS.valid] = 1.0
            row[base + TARGET_FIELDS.range] = rng
            row[base + TARGET_FIELDS.bearing_sin] = math.sin(beta)
            row[base + TARGET_FIELDS.bearing_cos] = math.cos(beta)
            row[base + TARGET_FIELDS.rel_u] = ru
            row[base + TARGET_FIELDS.rel_v] = rv
            row[base + TARGET_FIELDS.dcpa] = dcpa
            row[base + TARGET_FIELDS.tcpa] = tcpa
            if sit != SAFE:
                row[base + getattr(TARGET_FIELDS, ONE_HOT[sit])] = 1.0
            row[base + TARGET_FIELDS.length] = world.length
        # outcome
        outcome = 0
        if not alive[k]:
            outcome = DIVERGED
        elif collided:
            outcome = COLLISION
        elif grounded:
            outcome = GROUNDING
        elif goal <= p[P.goal_radius] or (leg > 0.0 and (ln * gn + le * ge) <= 0.0):
            outcome = ARRIVED  # at the goal, or past its abeam line
        elif abs(cross) > p[P.max_cross]:
            outcome = STRAYED
        if stepped and p[P.tss_lane] > 0.0:  # rule 10: where in the scheme, and which way
            if cross < -p[P.tss_lane] - p[P.tss_zone]:
                s[S.tss_wrong_lane] += p[P.dt]
            elif cross < -p[P.tss_lane]:
                s[S.tss_zone] += p[P.dt]
            elif abs(wrap_pi(alpha - psi)) > p[P.tss_direction]:
                s[S.tss_against] += p[P.dt]
        if stepped and p[P.ch_half] > 0.0:  # rule 9 in a narrow channel along the route
            breach = narrow_channel(
                cross + p[P.ch_offset], wrap_pi(psi - alpha), channel, p[P.ch_half], p[P.tss_direction],
                p[P.risk], p[P.ch_pass],
            )  # fmt: skip
            s[S.rule9_port_side] += p[P.dt] * breach[0]
            s[S.rule9_crossing] += p[P.dt] * breach[1]
            s[S.rule9_close_overtake] += p[P.dt] * breach[2]
        if stepped:
            terms[k, TERM.progress] = (s[S.prev_goal] - goal) / (p[P.U_T] * p[P.dt])
            terms[k, TERM.cross_track] = -min(abs(cross) / p[P.max_cross], 1.0)
            terms[k, TERM.danger] = -max(0.0, 1.0 - closest / p[P.risk]) if math.isfinite(closest) else 0.0
            terms[k, TERM.colreg] = -1.0 if port_with_give_way else 0.0
            terms[k, TERM.rudder] = rudder_activity(order, s[S.prev_order], p[P.rudder_limit])
            terms[k, TERM.collision] = -1.0 if outcome == COLLISION else 0.0
            terms[k, TERM.grounding] = -1.0 if outcome == GROUNDING else 0.0
            terms[k, TERM.arrival] = 1.0 if outcome == ARRIVED else 0.0
            side = 1.0 if order > p[P.port_order] else (-1.0 if order < -p[P.port_order] else 0.0)
            if side != 0.0:
                if s[S.prev_side] != 0.0 and side != s[S.prev_side]:
                    s[S.reversals] += 1.0
                s[S.prev_side] = side
            s[S.outcome] = outcome
            if outcome in (ARRIVED, COLLISION, STRAYED, GROUNDING):
                leaving.append(k)
        if math.isfinite(closest):
            s[S.min_sep] = min(s[S.min_sep], closest)
        v.done[k] = outcome != 0
        finish(v, k)
        s[S.prev_order] = order
        s[S.prev_goal] = goal
        motion_features(feat[k], u, vv, r, rudder, order, rev)
        feat[k, FEAT.cross_track] = cross
        feat[k, FEAT.course_error] = wrap_pi(alpha - psi)
        feat[k, FEAT.goal_sin] = math.sin(goal_brg)
        feat[k, FEAT.goal_cos] = math.cos(goal_brg)
        feat[k, FEAT.goal_distance] = goal
        if sensing:
            edges = world.edges if not hulls else _stack(world.edges, polygon_edges(hulls))
            reach = sweep(n, e, psi, world.bearings, edges, p[P.sensor_range])
            feat[k, FEAT.sensor0 : FEAT.sensor0 + world.sensors] = sector_minima(reach, world.sensors)
        encode_row(v, k)
        score_row(pairs[k], t.scores[k], p)
    for k in leaving:  # a ship whose episode ended leaves the encounter (after every ship has seen it)
        world.active[k] = False


def _aground(outline, n, e, world) -> bool:
    """Whether a hull outline on the chart reaches one of the waters' obstacles (land, or a depth area
    shallower than the draught plus the under-keel margin): the polygons share a point."""
    r = world.reach
    for poly, (n0, n1, e0, e1) in world.obstacles:
        if n0 - r <= n <= n1 + r and e0 - r <= e <= e1 + r and polygons_overlap(outline, poly):
            return True
    return False


def _stack(a, b):
    return np.concatenate((a, b)) if len(a) else b
