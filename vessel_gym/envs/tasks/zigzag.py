"""ZigZag: a course-changing autopilot task built around the IMO zig-zag manoeuvre, in one file.

Its versions are presets of one configuration (``ZigZag-v1``: the IMO schedule; ``ZigZagRandom-v1``: random
course changes), registered by :func:`~vessel_gym.envs.registration.register_task`. The declaration (reward terms,
features), the configuration, the start of an episode, the compiled step and the environment classes (whose
docstrings are the spec sheet, :class:`ZigZagEnv`) sit together here.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import njit

from vessel_gym.control.angles import PI, wrap_pi
from vessel_gym.control.zigzag import (
    OVERSHOOT_V1,
    overshoot_excursion,
    overshoot_step,
    target_reached,
    zigzag_execute,
)
from vessel_gym.envs.config import RollOptionsConfig
from vessel_gym.envs.declare import RAD_TO_DEG, FeatureSpec, Info, Term, columns
from vessel_gym.envs.disturbances import Disturbances, DisturbedOpenWaterConfig
from vessel_gym.envs.env import ShipEnv, ShipVectorEnv
from vessel_gym.envs.generators import vessels_draws
from vessel_gym.envs.registration import register_task
from vessel_gym.envs.task import _uniform
from vessel_gym.envs.tasks.common import (
    DIVERGED,
    HEEL_TERM,
    ROLL_FEATURES,
    RUDDER_ACTIVITY_DOC,
    SPEED_LOSS_DOC,
    OpenWaterTask,
    clear_row,
    draw_side,
    encode_row,
    finish,
    heel,
    motion,
    motion_features,
    motion_observed,
    reset_options,
    roll_features,
    rudder_activity,
    speed_loss,
    task_spec,
)
from vessel_gym.physics.kinematics import speed_through_water
from vessel_gym.physics.schema import check_ranges, param
from vessel_gym.physics.units import DEG
from vessel_gym.physics.vessel import NO_REFCOUNT

_ZERO = np.zeros(1, dtype=np.int64)  # the one vessel of a single environment

#: the IMO schedule's next course change starts at the latest this many ship time scales L / U_T after the
#: last one. It must not cut the zig-zag of a helm that completes it: the IMO 10/10 rule itself takes 4.5-6.7
#: L / U_T from execute to execute on kvlcc2_l7 (27-40 s), a PID helm 2-3.3 L / U_T; so the limit bites only on
#: a helm that stops short of a target or never gets there, and gives it the next course change anyway
LEG_TIME_LIMIT_L_U = 10.0
#: the target_reached bonus of a course change equals the heading_error charge of a turn whose error falls
#: linearly to zero in 2 x this many L / U_T, the leg time limit: a helm that reaches a target within the
#: limit earns about what the turn costs it or more, so completing a course change always beats stopping
#: short of it, and, in the IMO schedule, a helm gains by completing more course changes
REACH_TIME_L_U = 5.0


# --- declaration ------------------------------------------------------------------------------------------------
#: the features after the motion
ZIGZAG_FEATURES = (
    FeatureSpec("heading_error", "rad", (1.0, "pi"), "target heading - heading, wrapped"),
    FeatureSpec("heading_deviation", "rad", (1.0, "pi"), "heading - original course, wrapped"),
    FeatureSpec("target_deviation", "rad", (1.0, "pi"), "target heading - original course"),
)
INFO_ENTRIES = (
    Info("time_s", doc="time since the start of the episode, s"),
    Info("target_heading_deg", doc="target heading, deg"),
    Info("heading_error_deg", doc="target - heading, deg"),
    Info("course_changes", doc="course changes started", kind=int),
    Info("targets_reached", doc="targets reached", kind=int),
    Info("targets_missed", doc="course changes that ended with the target missed", kind=int),
    Info("overshoot_deg", doc="overshoot per course change, deg"),
    Info("max_overshoot_deg", doc="largest overshoot, deg"),
    Info("overshoot_1_deg", doc="first overshoot (IMO), deg"),
    Info("overshoot_2_deg", doc="second overshoot (IMO), deg"),
    Info(
        "success",
        doc="no target missed, one reached, overshoot per change within success_overshoot",
        kind=bool,
    ),
    Info("is_success", same_as="success"),
    DIVERGED,
)
SPEC = task_spec(
    "ZigZag",
    terms=(
        Term("heading_error", 1.0, "-|target - heading| / pi"),
        Term("overshoot", 1.0, "-growth of the course change's overshoot / overshoot scale"),
        Term(
            "target_reached",
            1.0,
            "on reaching a target: +|course change| / pi x 5 (L / U_T) / control interval",
        ),
        Term("rudder_activity", 0.1, RUDDER_ACTIVITY_DOC),
        Term("speed_loss", 0.1, SPEED_LOSS_DOC),
    ),
    features=ZIGZAG_FEATURES + ROLL_FEATURES,
    options=(HEEL_TERM,),
    info=INFO_ENTRIES,
)
TERM = SPEC.TERM
FEAT = SPEC.FEAT
OPT = SPEC.OPT
INFO = SPEC.INFO

# One schedule for both target kinds: a course change starts when its start time comes (the first after the
# seeded delay; in the random schedule every leg time; in the IMO schedule the leg time limit) or, in the IMO
# schedule, at the execute (the target reached). Overshoots are measured with the OVERSHOOT_V1 tracker.
#: per-vessel task state (columns of ``ts``)
S = columns(
    "psi0",  # original course, rad
    "target",  # target of the current course change, rad (unwrapped, same branch as the heading)
    "sign",  # direction in which the current target is reached, +1 starboard / -1 port; 0 before the first
    "side",  # IMO schedule: side of the current target (the first change flips it: set -first side)
    "reached",  # current target reached
    "next",  # time at which the next course change starts, s
    "dpsi",  # size of the current course change |target - previous target|, rad
    "os_on",  # an overshoot measurement is open
    "os_sign",  # its side (+1 starboard)
    "os_target",  # its target, rad
    "os_peak",  # its overshoot so far (largest excursion past the target), rad
    "os_sum",  # overshoots of the closed measurements, summed, rad
    "os_max",  # largest closed overshoot, rad
    "os_n",  # closed measurements
    "os1",  # first and second closed overshoot, rad (the IMO first and second overshoot angles)
    "os2",
    "changes",  # course changes started
    "n_reached",  # targets reached
    "missed",  # course changes that ended with their target not reached
    "prev_order",  # rudder order of the previous step, rad
    "U0",  # approach speed, m/s
    "t",  # time since the start of the episode, s
    "pending_change",  # random schedule: the next course change, drawn in advance (signed), rad
    "pending_leg",  # random schedule: the duration of the leg it starts, s
    "draw",  # random schedule: the pending change was used; the task draws the next one
    typename="ZigZagState",
)
#: the kernel's parameter row
P = columns(
    "psi_z",  # IMO heading deviation psi_z, rad
    "os_ref",  # overshoot scale of the reward, rad
    "rudder_max",  # rudder scale (limit), rad
    "imo",  # 1: IMO schedule, 0: random course changes
    "dt",  # control interval, s
    "leg_limit",  # IMO schedule: the next change starts at the latest this long after the last, s
    "reach",  # target_reached term per radian of course change, 1/rad
    "heel_ref",  # heel reference of the heel term, rad; 0: the term is off (no column)
    "success_overshoot",  # success: overshoot per course change at most this, rad
    typename="ZigZagParams",
)

ZigZagReward = SPEC.weights_class(
    "ZigZagReward", __name__, "Weights of the ZigZag reward terms (reward = sum of weight x term)."
)


@dataclass(frozen=True, kw_only=True)
class ZigZagConfig(RollOptionsConfig, DisturbedOpenWaterConfig):
    """ZigZag configuration (see :class:`ZigZagEnv`)."""

    schedule: str = param("imo", choices=("imo", "random"), doc="target schedule")
    zigzag_heading_deg: float = param(10.0, unit="deg", lo=1.0, hi=90.0, doc="imo: target deviation psi")
    first_side: str = param(
        "random", choices=("starboard", "port", "random"), doc="imo: first target side"
    )
    first_change_s: tuple[float, ...] = param(
        (0.0, 10.0), unit="s", lo=0.0, hi=1e5, doc="[min, max] time of the first course change"
    )
    leg_time_limit_s: float | None = param(
        None,
        unit="s",
        lo=0.01,
        hi=1e5,
        doc="imo: the next course change starts at the latest this long after the last (default 10 L / U_T)",
    )
    course_change_deg: tuple[float, ...] = param(
        (10.0, 40.0), unit="deg", lo=1.0, hi=180.0, doc="random: [min, max] course change, either side"
    )
    leg_time_s: tuple[float, ...] = param(
        (20.0, 40.0), unit="s", lo=0.01, hi=1e5, doc="random: [min, max] time between course changes"
    )
    initial_heading_deg: tuple[float, ...] = param(
        (0.0, 360.0), unit="deg", lo=-360.0, hi=360.0, doc="[min, max] original course"
    )
    success_overshoot_deg: float | None = param(
        None,
        unit="deg",
        lo=0.0,
        hi=180.0,
        doc="success: mean overshoot per course change at most this (default half the overshoot scale)",
    )
    reward: ZigZagReward = param(ZigZagReward(), doc="reward weights")


# --- start of an episode ------------------------------------------------------------------------
def course_change(c: Any, rng: Any) -> Any:
    """Random schedule: a signed course change of ``course_change_deg``, either side (- for a draw >= 0.5),
    rad (an array over the vessels of :class:`~vessel_gym.envs.generators.BatchDraws`)."""
    return _uniform(rng, c.course_change_deg) * DEG * (1.0 - 2.0 * (rng.random() >= 0.5))


# --- compiled step ----------------------------------------------------------------------------------------------
@njit(cache=True, inline="always")
def close_row(v, k, s):
    """End of a zig-zag step of vessel k (task state row ``s``): done, reward, rudder memory, features,
    observation."""
    uk, vk, rk, psik, _n, _e, dk, dck, revk, _revc = motion(v, k)
    v.done[k] = not v.alive[k]
    if v.done[k]:
        clear_row(v.terms, k)
    finish(v, k)
    s[S.prev_order] = dck
    f = v.feat[k]
    motion_features(f, uk, vk, rk, dk, dck, revk)
    f[FEAT.heading_error] = wrap_pi(s[S.target] - psik)
    f[FEAT.heading_deviation] = wrap_pi(psik - s[S.psi0])
    f[FEAT.target_deviation] = wrap_pi(s[S.target] - s[S.psi0])
    encode_row(v, k)


@njit(cache=True, inline="always")
def write_info(v, k, s, p):
    """Vessel k's info row from its task state row ``s`` (the open measurement counts with its overshoot so
    far); degrees as Python's math.degrees computes them (x * (180 / pi)), so the values are its to the bit."""
    i = v.info[k]
    running = s[S.os_peak] * s[S.os_on]
    per_change = (s[S.os_sum] + running) / max(s[S.changes], 1.0)
    i[INFO.time_s] = s[S.t]
    i[INFO.target_heading_deg] = (s[S.target] * RAD_TO_DEG) % 360.0
    i[INFO.heading_error_deg] = v.feat[k, FEAT.heading_error] * RAD_TO_DEG
    i[INFO.course_changes] = s[S.changes]
    i[INFO.targets_reached] = s[S.n_reached]
    i[INFO.targets_missed] = s[S.missed]
    i[INFO.overshoot_deg] = per_change * RAD_TO_DEG
    i[INFO.max_overshoot_deg] = max(s[S.os_max], running) * RAD_TO_DEG
    i[INFO.overshoot_1_deg] = s[S.os1] * RAD_TO_DEG
    i[INFO.overshoot_2_deg] = s[S.os2] * RAD_TO_DEG
    good = s[S.missed] == 0.0 and s[S.n_reached] >= 1.0 and per_change <= p[P.success_overshoot]
    i[INFO.success] = 1.0 if good else 0.0


@njit(cache=True)
def _close_overshoot(s):
    s[S.os_on] = 0.0
    s[S.os_n] += 1.0
    peak = s[S.os_peak]
    s[S.os_sum] += peak
    s[S.os_max] = max(s[S.os_max], peak)
    if s[S.os_n] == 1.0:
        s[S.os1] = peak
    elif s[S.os_n] == 2.0:
        s[S.os2] = peak


@njit(cache=True, **NO_REFCOUNT)
def zigzag_update(phase, v, t):
    """The ZigZag step of every vessel in ``phase`` (0 skip, 1 step, 2 reset: features only); a course change due
    at the reset starts there. ``v``: the vessels' record, ``t``: the task's (``ts``, ``p``)."""
    p, ts, terms = t.p, t.ts, v.terms
    psiz = p[P.psi_z]
    osref = p[P.os_ref]
    imo = p[P.imo] > 0.0
    for k in range(ts.shape[0]):
        if phase[k] == 0:
            continue
        uk, vk, rk, psik, nk, ek, dk, dck, revk, revck = motion(v, k)
        s = ts[k]
        clear_row(terms, k)
        reached_now = False
        if phase[k] == 1:
            s[S.t] += p[P.dt]
            if s[S.os_on] > 0.0:
                before = s[S.os_peak]
                s[S.os_peak], _rose, _fin = overshoot_step(
                    s[S.os_sign], s[S.os_target], before, psik, rk, OVERSHOOT_V1
                )
                terms[k, TERM.overshoot] = -(s[S.os_peak] - before) / osref
            if s[S.sign] != 0.0 and s[S.reached] == 0.0 and target_reached(s[S.sign], psik, s[S.target]):
                reached_now = True
                s[S.reached] = 1.0
                s[S.n_reached] += 1.0
                if s[S.os_on] > 0.0:  # the previous change's measurement ends where this one begins
                    _close_overshoot(s)
                s[S.os_on] = 1.0
                s[S.os_sign] = s[S.sign]
                s[S.os_target] = s[S.target]
                s[S.os_peak] = max(overshoot_excursion(s[S.sign], s[S.target], psik), 0.0)
                terms[k, TERM.overshoot] -= s[S.os_peak] / osref
                terms[k, TERM.target_reached] = s[S.dpsi] * p[P.reach]
        if s[S.t] >= s[S.next] - 1e-9 or (imo and reached_now):  # a course change starts
            if s[S.sign] != 0.0 and s[S.reached] == 0.0:
                s[S.missed] += 1.0
            # closed when the next change starts; the IMO execute starts a change at the very sample the
            # measurement opens, and the change after that closes it
            if s[S.os_on] > 0.0 and not (imo and reached_now):
                _close_overshoot(s)
            previous = s[S.target]
            if imo:
                s[S.side], s[S.target] = zigzag_execute(s[S.psi0], s[S.side], psiz)
                s[S.sign] = s[S.side]
                s[S.next] = s[S.t] + p[P.leg_limit]
            else:
                s[S.target] += s[S.pending_change]
                s[S.sign] = 1.0 if s[S.target] >= psik else -1.0
                s[S.next] = s[S.t] + s[S.pending_leg]
                s[S.draw] = 1.0
            s[S.dpsi] = abs(s[S.target] - previous)
            s[S.reached] = 0.0
            s[S.changes] += 1.0
        if phase[k] == 1:
            terms[k, TERM.heading_error] = -abs(wrap_pi(s[S.target] - psik)) / PI
            terms[k, TERM.rudder_activity] = rudder_activity(dck, s[S.prev_order], p[P.rudder_max])
            terms[k, TERM.speed_loss] = speed_loss(speed_through_water(uk, vk), s[S.U0])
            if p[P.heel_ref] > 0.0:
                terms[k, OPT.heel] = heel(v, k, p[P.heel_ref])
        roll_features(v, k, FEAT.phi, FEAT.p)
        close_row(v, k, s)
        write_info(v, k, s, p)


# --- capabilities: the classical pilots and the episode metrics ------------------------------------------------
def nomoto_pilot(env: Any, omega_n_UL: float = 0.6, zeta: float = 0.9) -> Any:
    """PID heading autopilot, gains by pole placement on the ship's Nomoto model at ``omega_n_UL`` U/L and
    ``zeta`` (:func:`vessel_gym.policy.nomoto_pid_kwargs`; the defaults: the untuned design)."""
    from vessel_gym.envs.policies import PIDHeadingAutopilot
    from vessel_gym.policy import nomoto_pid_kwargs

    return PIDHeadingAutopilot(env, **nomoto_pid_kwargs(env, omega_n_UL, zeta))


def pid_pilot(env: Any) -> Any:
    """:func:`nomoto_pilot` with the parameters tuned for the id (:func:`vessel_gym.policy.pilot_gains`)."""
    from vessel_gym.policy import pilot_gains

    return nomoto_pilot(env, **pilot_gains(env, "pid"))


def rule_pilot(env: Any) -> Any:
    """The IMO zig-zag rule (:class:`~vessel_gym.envs.policies.ZigZagRule`): the trial itself as a helm."""
    from vessel_gym.envs.policies import ZigZagRule

    return ZigZagRule(env)


def episode_metrics(infos: list[Mapping[str, Any]], terminated: bool) -> dict[str, Any]:
    """``heading_error_deg`` (mean |target - heading| over the steps), ``overshoot_deg`` (per course change, the
    open measurement included), ``max_overshoot_deg``, ``reached_pct`` (targets reached / course changes),
    ``course_changes`` and ``success``, from the environment's own per-course-change accounting."""
    last = infos[-1]
    legs = int(last["course_changes"])
    return {
        "heading_error_deg": float(np.mean([abs(float(i["heading_error_deg"])) for i in infos])),
        "overshoot_deg": float(last["overshoot_deg"]),
        "max_overshoot_deg": float(last["max_overshoot_deg"]),
        "reached_pct": 100.0 * int(last["targets_reached"]) / max(legs, 1),
        "course_changes": legs,
        "success": bool(last["is_success"]),
    }


# --- the task ---------------------------------------------------------------------------------------------------
@register_task(
    presets={"ZigZag-v1": {}, "ZigZagRandom-v1": {"schedule": "random"}},
    max_episode_steps=480,
    env="vessel_gym.envs.tasks.zigzag:ZigZagEnv",
    pilots={"pid": pid_pilot, "pid-nomoto": nomoto_pilot, "scripted": rule_pilot},
    metrics=episode_metrics,
)
class ZigZagTask(OpenWaterTask):
    """The zig-zag task: the schedule of course changes, honest overshoot accounting per course change, the
    leg time limit, seeded starts and disturbances (spec sheet: :class:`ZigZagEnv`)."""

    S = S
    P = P
    Config = ZigZagConfig
    spec = SPEC
    kernel = staticmethod(zigzag_update)

    def __init__(self, config: ZigZagConfig, n: int) -> None:
        where = f"{type(config).__name__}"
        check_ranges(
            config, ("course_change_deg", "leg_time_s", "initial_heading_deg", "first_change_s"), where
        )
        super().__init__(config, n)
        self.imo = config.schedule == "imo"
        self.psi_z = config.zigzag_heading_deg * DEG
        self.ts = np.zeros((n, len(S)))
        self.p = p = np.zeros(len(P))
        p[P.rudder_max] = self.rudder_scale()
        p[P.imo] = 1.0 if self.imo else 0.0
        p[P.dt] = config.control_interval_s
        self.disturbances = Disturbances(config, self.ship, where)
        self.overshoot_ref = self.psi_z if self.imo else config.course_change_deg[0] * DEG
        self.leg_time_limit = (
            config.leg_time_limit_s
            if config.leg_time_limit_s is not None
            else LEG_TIME_LIMIT_L_U * self.L / self.U_T
        )
        self.success_overshoot = (
            config.success_overshoot_deg * DEG
            if config.success_overshoot_deg is not None
            else 0.5 * self.overshoot_ref
        )
        p[P.success_overshoot] = self.success_overshoot
        p[P.psi_z] = self.psi_z
        p[P.os_ref] = self.overshoot_ref
        p[P.leg_limit] = self.leg_time_limit
        p[P.reach] = REACH_TIME_L_U * (self.L / self.U_T) / (math.pi * config.control_interval_s)
        self.switch_on_heel(P.heel_ref)

    def observed(self) -> tuple[str, ...]:
        motion_and_heading = motion_observed(rev=self.config.engine_control)
        return motion_and_heading + tuple(f.name for f in ZIGZAG_FEATURES) + self.roll_observed()


    def reset_vessel(self, k: int, rng: np.random.Generator, options: Mapping | None) -> None:
        self.reset_batch(np.array([k]), rng, options)

    def reset_batch(self, idx: np.ndarray, rng: Any, options: Mapping | None) -> None:
        # each draw gives one number per vessel of idx, in the order a lone reset draws them
        c = self.config
        heading, speed, _ = reset_options(c, options, rng, self.U_T)
        self.start_vessels(idx, rng, heading, speed)
        ts = self.ts
        ts[idx, S.target] = ts[idx, S.psi0]
        ts[idx, S.next] = _uniform(rng, c.first_change_s)
        if self.imo:
            side = draw_side(c.first_side, rng)
            ts[idx, S.side] = -side  # the first change flips it to the first side
        else:
            self._draw_changes(idx, rng)

    def _draw_changes(self, idx: np.ndarray, rng: Any) -> None:
        """Draw the vessels ``idx``' next random course change and the duration of the leg it starts."""
        c = self.config
        ts = self.ts
        ts[idx, S.pending_change] = course_change(c, rng)
        ts[idx, S.pending_leg] = _uniform(rng, c.leg_time_s)
        ts[idx, S.draw] = 0.0

    def update(self, phase: np.ndarray) -> None:
        super().update(phase)
        if not self.imo:
            self._draw_started()

    def _draw_started(self) -> None:
        """Random schedule, after the kernel: the vessels whose kernel started a course change draw the one
        after it."""
        if self.n == 1:  # a scalar test: the one-ship step should not pay for flatnonzero
            if self.ts[0, S.draw]:
                self._draw_changes(_ZERO, self.rngs[0])
            return
        idx = np.flatnonzero(self.ts[:, S.draw])
        if len(idx):
            self._draw_changes(idx, vessels_draws(self.rngs, idx))

    def overlay(self, k: int) -> dict[str, Any]:
        return {
            "target_heading_rad": float(self.ts[k, S.target]),
            "original_course_rad": float(self.ts[k, S.psi0]),
            "title": "ZigZag",
        }


# --- the environments (their docstrings are the spec sheets) -----------------------------------------------
class ZigZagEnv(ShipEnv):
    """Course-changing autopilot around the IMO zig-zag manoeuvre, with honest overshoot accounting.

    ## Description

    A ship starts in a steady straight approach on a seeded original course and holds it until the first
    course change (seeded time in ``first_change_s``); from then on its target heading changes by a
    schedule, and the agent, holding the helm, should bring the ship onto each new target quickly, with
    little overshoot, rudder activity and speed loss.

    * ``schedule="imo"`` (``vessel_gym/ZigZag-v1``): the target alternates between ``original course +
      psi`` and ``original course - psi`` (first side seeded), changing when the heading reaches the
      current target (the IMO MSC.137(76) execute) or, at the latest, ``leg_time_limit_s`` after the last
      change (default 10 L / U_T, 59 s for ``kvlcc2_l7``, where the IMO 10/10 rule needs up to 6.7 L / U_T and a
      PID helm 2-3.3 L / U_T from one course change to the next). So the schedule
      cannot be stalled by stopping short of a target.
    * ``schedule="random"`` (``vessel_gym/ZigZagRandom-v1``: the preset ``schedule="random"``): course changes of
      ``course_change_deg`` either side every ``leg_time_s`` seconds (drawn with the reset seed).

    A target counts as reached when the heading reaches or passes it (:func:`vessel_gym.control.zigzag.
    target_reached`, the IMO execute); a helm that approaches it asymptotically from one side never
    reaches it. Overshoot is measured per course change (``OVERSHOOT_V1`` of :mod:`vessel_gym.control.zigzag`):
    the largest excursion past the change's target from the moment it is reached until the measurement is
    closed when the next course change starts (IMO schedule: the change after the one the execute
    starts). A course change whose target is never reached has overshoot 0; a measurement still open at
    the end of the episode counts with what it has, in the reward and in ``info`` alike.

    Default ship: ``kvlcc2_l7`` (7 m KVLCC2 model, 1.18 m/s test speed, L / U_T = 5.9 s), physics step and
    control interval 0.25 s.

    ## Action Space

    ``Box(-1, 1, (1,))`` rudder order x rudder limit (+ starboard); ``(2,)`` with
    ``engine_control`` (engine order x full ahead / full astern rpm); clipped; NaN raises.
    ``action_type="discrete"``: helm orders (x telegraph steps).

    ## Observation Space

    ``Box(-1, 1, (8,), float32)`` normalized (value / scale, clipped; SI values with ``"physical"``): u, v, r, rudder, rudder_order, (rev),
    heading_error (target - heading), heading_deviation (heading - original course), target_deviation
    (target - original course). The original course itself is not observed (the task is the same on every
    course), nor are the disturbances (only their effect on the motion).

    ## Rewards

    reward = sum of weight x term (config ``reward``); weighted terms in ``info["reward_terms"]``. psi_ref
    is the overshoot scale: ``zigzag_heading_deg`` (IMO) or the smallest ``course_change_deg`` (random).

    | Term | Default weight | Value per step |
    |------|----------------|----------------|
    | heading_error | 1.0 | -abs(target - heading) / pi |
    | overshoot | 1.0 | -(growth this step of the current course change's overshoot) / psi_ref |
    | target_reached | 1.0 | at the step a target is reached: +abs(course change) / pi x 5 (L / U_T) / control interval |
    | rudder_activity | 0.1 | -abs(change of rudder order) / (2 x rudder limit) |
    | speed_loss | 0.1 | -max(0, U0 - U) / U0 |

    Over an episode the overshoot term sums to -(sum of the overshoots per course change, the open one
    included) / psi_ref. The target_reached bonus equals the heading_error charge of a turn whose error
    falls linearly to zero in 10 L / U_T, the IMO leg time limit: a helm that reaches a target earns
    about what the turn costs it or more, so no helm gains by stopping short of a target or never reaching
    it, and in the IMO schedule completing more course changes pays (``tests/envs/test_zigzag_v1.py``
    ranks a completing PID helm above helms that aim 0.5-2 deg short and above timid helms, on both
    schedules). The speed-loss weight is 0.1 (v0: 0.5, under which the speed every turn costs outweighed
    the heading error and a helm that turned less scored better).

    ## Starting State

    Steady straight approach at ``approach_speed_m_s`` (default the test speed), rudder amidships,
    original course uniform in ``initial_heading_deg`` (default 0-360 deg), at the origin. IMO first side
    ``first_side`` (default random); first course change at a time uniform in ``first_change_s``
    (default 0-10 s). Calm water unless the disturbance ranges are set: ``wind_speed_m_s`` /
    ``wind_from_rel_deg``, ``current_speed_m_s`` / ``current_to_rel_deg``, ``Hs_m`` / ``Tp_s`` /
    ``wave_from_rel_deg`` (directions relative to the original course; wind and waves from, current
    towards) are drawn per episode with the reset seed and set as the vessel's environment in the
    simulation before the steady approach is solved. Wind and waves need a ship with ``[windage]`` /
    ``[wave_drift]`` tables (``kvlcc2``, ``mariner``, ``dtc``; the default ``kvlcc2_l7`` tank model has
    neither): on a ship without, construction raises ``SpecError``. All of these come from the reset
    seed: seeds give different episodes.

    ## Episode End

    * Termination: the simulation diverged (``info["diverged"]``).
    * Truncation: 480 steps (120 s) by the registered time limit.

    ## Success

    ``info["is_success"]`` (and ``info["success"]``, the same): no course change has ended with its target
    unreached, at least one target has been reached, and the overshoot per course change (the open one
    included) is at most ``success_overshoot_deg`` (default psi_ref / 2: 5 deg on the 10 deg IMO
    schedule). Read at the end of the episode (SB3's ``Monitor`` does), it says the helm completed the
    schedule with small overshoot; the current course change, still running at the time limit, is not
    held against it.

    ## Info

    ``reward_terms``, ``time_s``, ``target_heading_deg``, ``heading_error_deg``, ``course_changes``
    (started so far), ``targets_reached``, ``targets_missed`` (course changes ended unreached),
    ``overshoot_deg`` (overshoot per course change: the sum of the overshoots, the open measurement
    included, / course changes), ``max_overshoot_deg``, ``overshoot_1_deg`` and ``overshoot_2_deg``
    (the first two closed measurements: in the IMO schedule the IMO first and second overshoot angles,
    sampled at the control steps; 0 until closed), ``is_success``, ``success``, ``diverged``.

    ## Arguments

    ``gymnasium.make("vessel_gym/ZigZag-v1", render_mode=None, config=None, **overrides)``; config class
    :class:`~vessel_gym.envs.tasks.zigzag.ZigZagConfig` (strict: unknown keys and out-of-range values raise ``SpecError``). Keys: the shared ones, ``schedule``,
    ``zigzag_heading_deg``, ``first_side``, ``first_change_s``, ``leg_time_limit_s``,
    ``course_change_deg``, ``leg_time_s``, ``approach_speed_m_s``, ``initial_heading_deg``, the
    disturbance ranges above, ``success_overshoot_deg``, ``reward``.
    ``reset(options={"heading_deg": ..., "speed_m_s": ...})`` fixes the start.

    ## Vectorized environment

    ``gymnasium.make_vec("vessel_gym/ZigZag-v1", num_envs=N)`` (:class:`ZigZagVectorEnv`; and
    ``ZigZagRandom-v1``): one simulation of N ships, the same task code;
    vessel k seeded with ``seed + k`` follows the single environment seeded so.

    ## Version History

    * v1: overshoot measured per course change and closed when the next change starts, the open one
      counted at the end (v0 charged a running measurement against a target the ship had left behind and
      counted only finished ones); IMO leg time limit; seeded original course, first side and first change
      time; target_reached term, speed-loss weight 0.1; wind, current and waves; ``is_success``; the
      random schedule registered as ``ZigZagRandom-v1``.
    * v0: initial version; removed (``gymnasium.make("vessel_gym/ZigZag-v0")`` raises ``DeprecatedEnv`` naming
      ``ZigZag-v1``).

    Both ids are presets of the one task :class:`~vessel_gym.envs.tasks.zigzag.ZigZagTask` (its
    ``register_task`` declaration): ``ZigZagRandom-v1`` is ``ZigZag-v1`` with ``schedule="random"``.
    """

    Task = ZigZagTask
    env_name = "ZigZag"


class ZigZagVectorEnv(ShipVectorEnv):
    """Native vector version of :class:`ZigZagEnv` (one simulation of ``num_envs`` ships)."""

    Env = ZigZagEnv
