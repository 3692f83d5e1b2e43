"""The columns of the HarbourApproach task: its reward terms and observation features (``SPEC``, whose
``TERM`` and ``FEAT`` index the kernel's term and feature rows), its per-vessel state ``S`` and its parameter
row ``P``.

They are the layout that the task (:mod:`vessel_gym.envs.tasks.harbour`) and its compiled step
(:mod:`vessel_gym.envs.tasks.harbour_kernel`) share: both import them from here, and numba compiles the column
indices into the step as constants.
"""

from __future__ import annotations

from vessel_gym.envs.declare import FeatureSpec, Info, Term, columns, pick
from vessel_gym.envs.task import task_arrays
from vessel_gym.envs.tasks.chart import OUTCOMES
from vessel_gym.envs.tasks.common import RUDDER_ACTIVITY_DOC, task_spec

#: the ``info`` entries: the outcome (a vessel's ``flags``) and the episode's figures (its task state ``ts``)
INFO_ENTRIES = (
    Info("outcome", lambda v: pick(OUTCOMES, v.flags), "running, success, contact, grounding, ..."),
    Info("success", doc="stopped in the goal area, on heading", kind=bool),
    Info("is_success", same_as="success"),
    Info("contact", doc="the hull touched a hard obstacle", kind=bool),
    Info("grounding", doc="the hull touched a shoal", kind=bool),
    Info("out_of_bounds", doc="the ship left the chart", kind=bool),
    Info("diverged", doc="the simulation diverged", kind=bool),
    Info("time_s", doc="time since the start of the episode, s"),
    Info("clearance_m", doc="clearance of the hull now, m"),
    Info("min_clearance_m", doc="smallest clearance this episode, m"),
    Info("distance_to_goal_m", doc="distance to the goal point, m"),
    Info("speed_over_ground_m_s", doc="speed over ground, m/s"),
    Info("heading_error_deg", doc="goal heading - heading, deg"),
    Info("path_m", doc="distance sailed over ground, m"),
)

SPEC = task_spec(
    "HarbourApproach",
    terms=(
        Term("progress", 1.0, "decrease of the distance to the goal point / L"),
        Term("speed_excess", 1.0, "-(SOG above the allowed speed) / U_T"),
        Term("proximity", 0.5, "-(1 - clearance / safe clearance) when closer"),
        Term("rudder_activity", 0.05, RUDDER_ACTIVITY_DOC),
        Term("time", 0.5, "-(control interval) x U_T / L per step: -1 per time the ship sails its length"),
        Term("success", 50.0, "+1 on arrival"),
        Term("collision", 20.0, "-1 on contact, grounding or divergence"),
        Term("out_of_bounds", 20.0, "-1 on leaving the chart"),
    ),
    features=(
        FeatureSpec("rev_order", "rev/s", (1.5, "full rev"), "shaft-speed order"),
        FeatureSpec("goal_x", "m", (1.0, "R"), "goal point ahead of midship (body x)"),
        FeatureSpec("goal_y", "m", (1.0, "R"), "goal point to starboard of midship (body y)"),
        FeatureSpec("goal_distance", "m", (1.0, "R"), "distance to the goal point"),
        FeatureSpec("goal_heading_error", "rad", (1.0, "pi"), "goal heading - heading, wrapped"),
        FeatureSpec("sog", "m/s", (1.5, "U_T"), "speed over ground"),
        FeatureSpec("wind_speed", "m/s", (1.0, "wind max + 2 U_T"), "apparent wind speed (anemometer)"),
        FeatureSpec(
            "wind_angle_sin", "-", (1.0, "1"), "sin of apparent wind angle from the bow (+ from starboard)"
        ),
        FeatureSpec("wind_angle_cos", "-", (1.0, "1"), "cos of apparent wind angle"),
        FeatureSpec(
            "current_x", "m/s", (1.0, "current max"), "current along the body x axis (GNSS minus log)"
        ),
        FeatureSpec("current_y", "m/s", (1.0, "current max"), "current along the body y axis"),
        FeatureSpec(
            "beam", "m", (1.0, "beam range"), "free range at {angle} deg clockwise from the bow", "n_beams"
        ),
    ),
    info=INFO_ENTRIES,
)
TERM = SPEC.TERM
FEAT = SPEC.FEAT
INFO = SPEC.INFO

#: per-vessel task state (columns of ``ts``); the current and the wind are not task state: the kernel asks the
#: physics for those it applies
S = columns(
    "d_prev",  # distance to the goal point at the previous step, m
    "prev_order",  # rudder order of the previous step, rad
    "min_clearance",  # smallest clearance this episode, m
    "clearance",  # clearance now, m
    "t",  # time since the start of the episode, s
    "path",  # distance sailed over ground, m
    "prev_north",  # position at the previous step, m
    "prev_east",
    "sog",  # speed over ground, m/s
    typename="HarbourState",
)
#: the kernel's parameter row
P = columns(
    "L",  # ship length, m
    "rudder_max",  # rudder scale (limit), rad
    "dt",  # control interval, s
    "beam_range",  # m
    "goal_north",  # goal point, m
    "goal_east",
    "goal_heading",  # rad
    "goal_tolerance",  # heading tolerance, rad
    "goal_max_speed",  # speed over ground at most, m/s
    "U_T",  # ship test speed (speed scale), m/s
    "slow_distance",  # distance from the goal inside which the allowed speed falls linearly, m
    "clearance_ref",  # clearance below which the proximity term grows, m
    "north_min",  # chart bounds, m
    "north_max",
    "east_min",
    "east_max",
    typename="HarbourParams",
)

#: the task's record, the kernel's ``t``: per vessel its state and outcome flag; the parameter row, the chart's
#: tables (:func:`~vessel_gym.envs.tasks.chart.chart_tables`), the hull outline, the goal area, the beam
#: directions and the chart query's scratch arrays (beams, hull north/east, beam work rows)
HarbourArrays = task_arrays(
    "HarbourArrays",
    __name__,
    vessel=("ts", "flags"),
    shared=("p", "hull", "edges", "polys", "pbox", "goal_verts", "beam_dirs", "beams", "hn", "he", "bw"),
)
