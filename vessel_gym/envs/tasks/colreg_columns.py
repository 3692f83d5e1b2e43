"""The declaration of CollisionAvoidance (reward terms and features by name) and the columns derived from it:
the task state, the parameter row and the target-list slots, which the task and its step both import."""

from __future__ import annotations

from vessel_gym.envs.declare import FeatureSpec, Info, Term, as_int, columns, pick
from vessel_gym.envs.tasks.common import RUDDER_ACTIVITY_DOC, task_spec

#: target-list slots declared (the config observes the first ``observed_targets`` of them)
K_MAX = 4
#: the fields of one target slot: (name, unit, scale, meaning)
_FIELDS = (
    ("valid", "-", (1.0, "1"), "1 if slot {j} holds a target, else 0 (and the slot's other fields are 0)"),
    ("range", "m", (1.0, "detection range"), "distance between midship points"),
    ("bearing_sin", "-", (1.0, "1"), "sin of the relative bearing (clockwise from the bow: + starboard)"),
    ("bearing_cos", "-", (1.0, "1"), "cos of the relative bearing (+ ahead)"),
    (
        "rel_u",
        "m/s",
        (2.0, "U_T"),
        "target's velocity over ground minus the own ship's, own body x (forward)",
    ),
    ("rel_v", "m/s", (2.0, "U_T"), "the same, own body y (starboard)"),
    ("dcpa", "m", (1.0, "detection range"), "distance at the closest point of approach (opening: the range)"),
    ("tcpa", "s", (1.0, "tcpa scale"), "time to the closest point of approach (< 0: opening)"),
    ("head_on", "-", (1.0, "1"), "1 if classified head-on at detection (rule 14)"),
    ("overtaking", "-", (1.0, "1"), "1 if the own ship overtakes it (rule 13)"),
    ("give_way", "-", (1.0, "1"), "1 if crossing with the target on the starboard side (rule 15: give way)"),
    ("stand_on", "-", (1.0, "1"), "1 if crossing from port or overtaking the own ship (rule 17: stand on)"),
    ("length", "m", (2.0, "L"), "target's length over all"),
)
TARGET_FIELDS = columns(*(f[0] for f in _FIELDS), typename="TargetFields")
SLOT = len(_FIELDS)  # feature columns per slot
#: range-sensor sectors declared (the config observes the first ``sensors`` of them)
SENSOR_MAX = 36

#: the rule checks (colreg_rules.CHECKS is this tuple)
CHECKS = ("early", "substantial", "starboard", "not_ahead", "stand_on", "no_port")
#: a vessel's COLREG scores so far, written by the step from its pair records (the task's ``scores``)
SC = columns(
    *(f"passed_{c}" for c in CHECKS),
    *(f"applied_{c}" for c in CHECKS),
    "checks",  # checks that apply
    "violations",  # pairs with a failed check
    "score",  # passed / applied (1 with none)
    "delay",  # s, mean reaction delay over the pairs acted for (-1 before any)
    typename="ColregScores",
)
OUTCOMES = ("running", "arrived", "collision", "strayed", "diverged", "grounding")
_ARRIVED, _COLLISION, _DIVERGED, _GROUNDING = (
    OUTCOMES.index(o) for o in ("arrived", "collision", "diverged", "grounding")
)


def _checks(prefix: str):  # an info entry's value: a count per check
    return lambda v: {c: as_int(v.scores[getattr(SC, f"{prefix}_{c}")]) for c in CHECKS}


#: the per-ship task state
S = columns(
    "n0",
    "e0",
    "n1",
    "e1",  # route start and goal, m
    "t",  # s since the start
    "prev_goal",  # m, distance to the goal at the last step
    "prev_order",  # rad
    "prev_side",  # +1/-1: side of the last rudder order beyond port_order (0: none yet)
    "reversals",  # rudder reversals (port <-> starboard orders)
    "min_sep",  # m, closest range to any other ship
    "path",  # m sailed
    "prev_n",
    "prev_e",  # m
    "outcome",  # OUTCOMES index
    "straight",  # m, the route's length
    "tss_zone",  # s in the separation zone (rule 10(b)(ii), (e))
    "tss_wrong_lane",  # s in the opposite lane (rule 10(b)(i))
    "tss_against",  # s in the own lane off its direction of flow (rule 10(b)(i))
    "rule9_port_side",  # s on the port half of a narrow channel (rule 9(a); colreg_rules.narrow_channel)
    "rule9_crossing",  # s crossing a narrow channel, impeding a ship in it (rule 9(d))
    "rule9_close_overtake",  # s overtaking closer than channel_pass_L (rule 9(e)(i))
    typename="CollisionAvoidanceState",
)


#: the parameter row
P = columns(
    "dt",
    "U_T",
    "rudder_limit",
    "max_cross",
    "goal_radius",
    "risk",
    "detection",
    "action",
    "release",
    "port_order",
    "early_fraction",  # rule checks (colreg_rules.pair_checks): early_tcpa_fraction
    "substantial",  # rad
    "stand_on_course",  # rad
    "stand_on_speed",  # fraction
    "sensor_range",  # m, the range-sensor sweep's reach
    "tss_lane",  # m, the own lane's half width about the route (0: rule 10 not scored)
    "tss_zone",  # m, the separation zone's width, beyond the own lane to port
    "tss_direction",  # rad, heading off the lane's direction of flow that counts as against it
    "ch_half",  # m, a narrow channel's half width (0: rule 9 not scored)
    "ch_offset",  # m, its centre line to port of the route
    "ch_pass",  # m, rule 9(e): an overtaking pass closer than this needs the overtaken ship's action
    typename="CollisionAvoidanceParams",
)

#: the info entries (their values read the task state ``ts``, the ``scores``, ``scenario_id`` and
#: ``planned_dcpa``: the columns S below, read when an info is made)
INFO = (
    Info(
        "scenario",
        lambda v: pick(v.task.scenario_names, as_int(v.scenario_id)),
        "the encounter: imazu:<case>, generated:<types>, file:<title>",
    ),
    Info(
        "outcome", lambda v: pick(OUTCOMES, as_int(v.ts[S.outcome])), "running / " + " / ".join(OUTCOMES[1:])
    ),
    Info("success", lambda v: v.ts[S.outcome] == _ARRIVED, "arrived at the goal"),
    Info("is_success", same_as="success", doc="success, as Stable-Baselines3 logs it"),
    Info("collision", lambda v: v.ts[S.outcome] == _COLLISION, "the hull outlines touched"),
    Info(
        "grounding",
        lambda v: v.ts[S.outcome] == _GROUNDING,
        "the hull outline reached land or water shallower than the draught + under_keel_m",
    ),
    Info("time_s", lambda v: v.ts[S.t], "time since the start, s"),
    Info("min_separation_m", lambda v: v.ts[S.min_sep], "closest centre-to-centre range so far, m"),
    Info("min_separation_L", lambda v: v.ts[S.min_sep] / v.task.L, "the same in own ship lengths"),
    Info("planned_dcpa_m", lambda v: v.planned_dcpa, "smallest planned DCPA of the encounter, m"),
    Info("path_ratio", lambda v: v.ts[S.path] / v.ts[S.straight], "path sailed / route length"),
    Info(
        "rudder_reversals", lambda v: as_int(v.ts[S.reversals]), "port-starboard changes of the rudder order"
    ),
    Info("colreg_score", lambda v: v.scores[SC.score], "passed / applied rule checks (1 while none applies)"),
    Info("colreg_checks", lambda v: as_int(v.scores[SC.checks]), "rule checks that apply"),
    Info("colreg_violations", lambda v: as_int(v.scores[SC.violations]), "pairs with a failed check"),
    Info(
        "reaction_delay_s", lambda v: v.scores[SC.delay], "mean detection-to-alteration delay, s (-1: none)"
    ),
    Info("colreg_passed", _checks("passed"), "per check: pairs passing it"),
    Info("colreg_applied", _checks("applied"), "per check: pairs it applies to"),
    Info("diverged", lambda v: v.ts[S.outcome] == _DIVERGED, "the simulation diverged"),
    Info(
        "tss_scored",
        lambda v: v.ts[S.t] * 0.0 + (v.task.p[P.tss_lane] > 0.0) > 0.5,
        "rule 10 is scored (tss_lane_half_L > 0)",
    ),
    Info("tss_zone_s", lambda v: v.ts[S.tss_zone], "time in the separation zone, s (rule 10(b)(ii), (e))"),
    Info(
        "tss_wrong_lane_s", lambda v: v.ts[S.tss_wrong_lane], "time in the opposite lane, s (rule 10(b)(i))"
    ),
    Info(
        "channel_scored",
        lambda v: v.ts[S.t] * 0.0 + (v.task.p[P.ch_half] > 0.0) > 0.5,
        "rule 9 is scored (channel_half_L > 0)",
    ),
    Info("rule9_port_side_s", lambda v: v.ts[S.rule9_port_side], "time on the channel's port half, s (rule 9(a))"),
    Info(
        "rule9_crossing_s",
        lambda v: v.ts[S.rule9_crossing],
        "time crossing the channel while a ship in it has a risk of collision with the own ship, s (rule 9(d))",
    ),
    Info(
        "rule9_close_overtake_s",
        lambda v: v.ts[S.rule9_close_overtake],
        "time overtaking in the channel closer than channel_pass_L, s (rule 9(e)(i))",
    ),
    Info(
        "tss_against_flow_s",
        lambda v: v.ts[S.tss_against],
        "time in the own lane heading more than tss_direction_deg off its flow, s (rule 10(b)(i))",
    ),
)

SPEC = task_spec(
    "CollisionAvoidance",
    terms=(
        Term("progress", 1.0, "(decrease of the distance to the goal) / (U_T x control interval)"),
        Term("cross_track", 0.05, "-min(abs(cross-track error) / (max_cross_track_L L), 1)"),
        Term("danger", 1.0, "-max(0, 1 - closest range / (risk_dcpa_L L))"),
        Term("colreg", 0.5, "-1 while the rudder order is to port with a head-on or give-way target closing"),
        Term("rudder", 0.05, RUDDER_ACTIVITY_DOC),
        Term("collision", 20.0, "-1 at contact of the hull outlines (the episode's last step)"),
        Term("grounding", 20.0, "-1 when the hull outline reaches land or a shoal (the episode's last step)"),
        Term("arrival", 10.0, "+1 on reaching the goal (within goal_radius_L L, or abeam of it)"),
    ),
    features=(
        FeatureSpec(
            "cross_track", "m", (1.0, "max cross track"), "cross-track error from the route (+ starboard)"
        ),
        FeatureSpec("course_error", "rad", (1.0, "pi"), "route course - heading, wrapped"),
        FeatureSpec("goal_sin", "-", (1.0, "1"), "sin of the goal's relative bearing (+ starboard)"),
        FeatureSpec("goal_cos", "-", (1.0, "1"), "cos of the goal's relative bearing (+ ahead)"),
        FeatureSpec("goal_distance", "m", (1.0, "route length"), "distance to the goal"),
        *(
            FeatureSpec(f"t{j}_{name}", unit, scale, f"target slot {j}: " + doc.format(j=j))
            for j in range(K_MAX)
            for name, unit, scale, doc in _FIELDS
        ),
        *(
            FeatureSpec(
                f"sensor{i}",
                "m",
                (1.0, "sensor range"),
                f"range-sensor sector {i}: nearest land, shoal or hull outline (sector i of N centred on "
                "i x 360 / N deg clockwise from the bow; the sensor range where none)",
            )
            for i in range(SENSOR_MAX)
        ),
    ),
    info=INFO,
)
TERM, FEAT = SPEC.TERM, SPEC.FEAT
