"""ZigZag-v0: a course-changing autopilot task built around the IMO zig-zag manoeuvre (deprecated for v1).

The declaration (reward terms, features), the configuration, the start of an episode and the compiled step sit
together here; the environment classes and their spec sheets are in :mod:`vessel_gym.envs.zigzag`. What ZigZag-v1
shares with v0 (its features, the close of a vessel's row, the Python side in :class:`ZigZagCommon`) is defined
here once.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numba import njit

from vessel_gym.control.angles import PI, wrap_pi
from vessel_gym.control.zigzag import (
    OVERSHOOT_V0,
    overshoot_excursion,
    overshoot_step,
    target_reached,
    zigzag_execute,
)
from vessel_gym.envs.config import OpenWaterConfig
from vessel_gym.envs.declare import FeatureSpec, Term, columns
from vessel_gym.envs.generators import vessels_draws
from vessel_gym.envs.task import PHASE_STEP, _uniform
from vessel_gym.envs.tasks.common import (
    RUDDER_ACTIVITY_DOC,
    SPEED_LOSS_DOC,
    OpenWaterTask,
    clear_row,
    draw_side,
    encode_row,
    finish,
    motion,
    motion_features,
    reset_options,
    rudder_activity,
    speed_loss,
    task_spec,
)
from vessel_gym.physics.kinematics import speed_through_water
from vessel_gym.physics.schema import check_ranges, param
from vessel_gym.physics.units import DEG
from vessel_gym.physics.vessel import NO_REFCOUNT

# --- declaration ------------------------------------------------------------------------------------------------
#: the features of both ZigZag versions after the motion
ZIGZAG_FEATURES = (
    FeatureSpec("heading_error", "rad", (1.0, "pi"), "target heading - heading, wrapped"),
    FeatureSpec("heading_deviation", "rad", (1.0, "pi"), "heading - original course, wrapped"),
    FeatureSpec("target_deviation", "rad", (1.0, "pi"), "target heading - original course"),
)
SPEC = task_spec(
    "ZigZag-v0",
    terms=(
        Term("heading_error", 1.0, "-|target - heading| / pi"),
        Term("overshoot", 1.0, "-min(excursion past the reached target / psi, 1)"),
        Term("rudder_activity", 0.1, RUDDER_ACTIVITY_DOC),
        Term("speed_loss", 0.5, SPEED_LOSS_DOC),
    ),
    features=ZIGZAG_FEATURES,
)
TERM = SPEC.TERM
FEAT = SPEC.FEAT

#: per-vessel task state (columns of ``ts``)
S = columns(
    "psi0",  # original course, rad
    "target",  # current target heading, rad (unwrapped, same branch as the heading)
    "side",  # IMO schedule: side of the current target, +1 starboard / -1 port
    "leg_sign",  # random schedule: direction of the course change of this leg
    "reached",  # random schedule: target of this leg reached
    "os_on",  # overshoot being measured
    "os_sign",
    "os_target",  # heading past which the overshoot is measured, rad
    "os_max",  # largest excursion past it so far, rad
    "os_n",  # overshoots completed
    "os1",  # first overshoot angle, rad
    "os2",  # second overshoot angle, rad
    "os_last",  # last completed overshoot angle, rad
    "executes",  # rudder executes (target changes) so far
    "prev_order",  # rudder order of the previous step, rad
    "U0",  # approach speed, m/s
    "t",  # time since the start of the episode, s
    "next",  # random schedule: time of the next course change, s
    typename="ZigZagState",
)
#: the kernel's parameter row
P = columns(
    "psi_z",  # IMO heading deviation psi_z (or random-schedule overshoot reference), rad
    "rudder_max",  # rudder scale (limit), rad
    "imo",  # 1: IMO schedule, 0: random course changes
    "dt",  # control interval, s
    typename="ZigZagParams",
)

ZigZagReward = SPEC.weights_class(
    "ZigZagReward", __name__, "Weights of the ZigZag reward terms (reward = sum of weight x term)."
)


# The keys both versions' configurations have, declared once (a dataclass field belongs to one class, so each
# is made by a function; the configurations list them in their own order).
def schedule_param(default: str = "imo") -> Any:
    return param(default, choices=("imo", "random"), doc="target schedule")


def zigzag_heading_param() -> Any:
    return param(10.0, unit="deg", lo=1.0, hi=90.0, doc="imo: target deviation psi")


def first_side_param(default: str) -> Any:
    return param(default, choices=("starboard", "port", "random"), doc="imo: first target side")


def course_change_param() -> Any:
    return param(
        (10.0, 40.0), unit="deg", lo=1.0, hi=180.0, doc="random: [min, max] course change, either side"
    )


def leg_time_param() -> Any:
    return param(
        (20.0, 40.0), unit="s", lo=0.01, hi=1e5, doc="random: [min, max] time between course changes"
    )


@dataclass(frozen=True, kw_only=True)
class ZigZagConfig(OpenWaterConfig):
    """ZigZag-v0 configuration (see :class:`~vessel_gym.envs.zigzag.ZigZagEnv`)."""

    schedule: str = schedule_param()
    zigzag_heading_deg: float = zigzag_heading_param()
    first_side: str = first_side_param("starboard")
    course_change_deg: tuple[float, ...] = course_change_param()
    leg_time_s: tuple[float, ...] = leg_time_param()
    reward: ZigZagReward = param(ZigZagReward(), doc="reward weights")


# --- start of an episode (both versions) ------------------------------------------------------------------------
def course_change(c: Any, rng: Any) -> Any:
    """Random schedule: a signed course change of ``course_change_deg``, either side (- for a draw >= 0.5),
    rad (an array over the vessels of :class:`~vessel_gym.envs.generators.BatchDraws`)."""
    return _uniform(rng, c.course_change_deg) * DEG * (1.0 - 2.0 * (rng.random() >= 0.5))


# --- compiled step ----------------------------------------------------------------------------------------------
@njit(cache=True)
def _finish_overshoot(s):
    s[S.os_on] = 0.0
    s[S.os_n] += 1.0
    if s[S.os_n] == 1.0:
        s[S.os1] = s[S.os_max]
    elif s[S.os_n] == 2.0:
        s[S.os2] = s[S.os_max]
    s[S.os_last] = s[S.os_max]


@njit(cache=True, inline="always")
def close_row(k, s, i_psi0, i_target, i_prev_order, x, inp, alive, w, enc, feat, obs, terms, reward, done):
    """End of a zig-zag step of vessel k, both versions: done, reward, rudder memory, features, observation.

    ``i_psi0``, ``i_target`` and ``i_prev_order``: where the version keeps the original course, the target and
    the previous rudder order in its task state ``s``.
    """
    uk, vk, rk, psik, _n, _e, dk, dck, revk, _revc = motion(x, inp, k)
    done[k] = not alive[k]
    if done[k]:
        clear_row(terms, k)
    finish(terms, k, w, reward)
    s[i_prev_order] = dck
    f = feat[k]
    motion_features(f, uk, vk, rk, dk, dck, revk)
    f[FEAT.heading_error] = wrap_pi(s[i_target] - psik)
    f[FEAT.heading_deviation] = wrap_pi(psik - s[i_psi0])
    f[FEAT.target_deviation] = wrap_pi(s[i_target] - s[i_psi0])
    encode_row(feat, k, enc, obs)


# The task kernels loop over vessels taking row views (ts[k], feat[k]); compiled without reference counting
# (vessel.NO_REFCOUNT, which explains why) they allocate nothing: scratch comes from their caller.
@njit(cache=True, **NO_REFCOUNT)
def zigzag_update(phase, x, inp, alive, ts, p, w, enc, feat, obs, terms, reward, done):
    """Zig-zag task: vessels in phase 1 advance one control step, phase 2 (just reset) get features only."""
    psiz = p[P.psi_z]
    dmax = p[P.rudder_max]
    imo = p[P.imo] > 0.0
    for k in range(x.shape[0]):
        if phase[k] == 0:
            continue
        uk, vk, rk, psik, nk, ek, dk, dck, revk, revck = motion(x, inp, k)
        s = ts[k]
        clear_row(terms, k)
        if phase[k] == 1:
            s[S.t] += p[P.dt]
            if s[S.os_on] > 0.0:
                s[S.os_max], _rose, finished = overshoot_step(
                    s[S.os_sign], s[S.os_target], s[S.os_max], psik, rk, OVERSHOOT_V0
                )
                if finished:
                    _finish_overshoot(s)
            crossed = False
            sign = 0.0
            if imo:
                if target_reached(s[S.side], psik, s[S.target]):
                    crossed = True
                    sign = s[S.side]
            elif s[S.reached] == 0.0 and target_reached(s[S.leg_sign], psik, s[S.target]):
                crossed = True
                sign = s[S.leg_sign]
                s[S.reached] = 1.0
            if crossed:
                if s[S.os_on] > 0.0:  # v0: a measurement still running counts as complete
                    _finish_overshoot(s)
                s[S.os_on] = 1.0
                s[S.os_sign] = sign
                s[S.os_target] = s[S.target]
                s[S.os_max] = overshoot_excursion(sign, s[S.target], psik)
                if imo:  # the IMO execute: the target flips to the other side of the original course
                    s[S.side], s[S.target] = zigzag_execute(s[S.psi0], s[S.side], psiz)
                    s[S.executes] += 1.0
            err = wrap_pi(s[S.target] - psik)
            terms[k, TERM.heading_error] = -abs(err) / PI
            if s[S.os_on] > 0.0:
                exc = overshoot_excursion(s[S.os_sign], s[S.os_target], psik)
                if exc > 0.0:
                    terms[k, TERM.overshoot] = -min(exc / psiz, 1.0)
            terms[k, TERM.rudder_activity] = rudder_activity(dck, s[S.prev_order], dmax)
            terms[k, TERM.speed_loss] = speed_loss(speed_through_water(uk, vk), s[S.U0])
        close_row(k, s, S.psi0, S.target, S.prev_order, x, inp, alive, w, enc, feat, obs, terms, reward, done)


# --- the task ---------------------------------------------------------------------------------------------------
class ZigZagCommon(OpenWaterTask):
    """What both ZigZag versions share on the Python side: the schedule, the parameter columns both kernels
    read, the observation, the chart overlay and the head of the ``info`` (their task states and parameter rows
    name the same quantities in different columns, ``S`` and ``P``)."""

    P: ClassVar[Any]  # the columns of the parameter row

    def __init__(self, config: Any, n: int) -> None:
        super().__init__(config, n)
        self.imo = config.schedule == "imo"
        self.psi_z = config.zigzag_heading_deg * DEG
        self.ts = np.zeros((n, len(self.S)))
        P = self.P
        self.p = p = np.zeros(len(P))
        p[P.rudder_max] = self.rudder_scale()
        p[P.imo] = 1.0 if self.imo else 0.0
        p[P.dt] = config.control_interval_s

    def observed(self) -> tuple[str, ...]:
        return self.motion_observed(rev=self.config.engine_control) + tuple(f.name for f in ZIGZAG_FEATURES)

    def heading_info(self, s: list[float], terms: list[float], f: list[float]) -> dict[str, Any]:
        """The ``info`` entries of one vessel that both versions begin with, from its task state ``s``, weighted
        terms and features ``f`` (:meth:`info_snapshot`)."""
        S = self.S
        return {
            "reward_terms": self.terms_dict(terms),
            "time_s": s[S.t],
            "target_heading_deg": math.degrees(s[S.target]) % 360.0,
            "heading_error_deg": math.degrees(f[FEAT.heading_error]),
        }

    def batch_heading_info(self, s: np.ndarray) -> dict[str, Any]:
        """:meth:`heading_info` of all vessels; ``s`` is :meth:`task_columns`."""
        S = self.S
        return {
            "reward_terms": self.batch_weighted_terms(),
            "time_s": s[S.t],
            "target_heading_deg": np.degrees(s[S.target]) % 360.0,
            "heading_error_deg": np.degrees(self.feat[:, FEAT.heading_error]),
        }

    def overlay(self, k: int) -> dict[str, Any]:
        return {
            "target_heading_rad": float(self.ts[k, self.S.target]),
            "original_course_rad": float(self.ts[k, self.S.psi0]),
            "title": "ZigZag",
        }


class ZigZagTask(ZigZagCommon):
    S = S
    P = P
    spec = SPEC
    Config = ZigZagConfig
    kernel = staticmethod(zigzag_update)

    def __init__(self, config: ZigZagConfig, n: int) -> None:
        check_ranges(config, ("course_change_deg", "leg_time_s", "initial_heading_deg"), "ZigZag config")
        super().__init__(config, n)
        self.p[P.psi_z] = self.psi_z if self.imo else config.course_change_deg[0] * DEG

    def reset_vessel(self, k: int, rng: np.random.Generator, options: Mapping | None) -> None:
        self.reset_batch(np.array([k]), rng, options)

    def reset_batch(self, idx: np.ndarray, rng: Any, options: Mapping | None) -> None:
        # each draw gives one number per vessel of idx, in the order a lone reset draws them
        c = self.config
        heading, speed, _ = reset_options(c, options, rng, self.U_T)
        self.start_vessels(idx, rng, heading, speed)
        ts = self.ts
        psi0 = ts[idx, S.psi0]
        if self.imo:
            side = draw_side(c.first_side, rng)
            ts[idx, S.side] = side
            ts[idx, S.target] = psi0 + side * self.psi_z
            ts[idx, S.executes] = 1.0  # the first execute is the rudder order at t = 0
        else:
            ts[idx, S.target] = psi0
            self._new_legs(idx, rng)

    def _new_legs(self, idx: np.ndarray, rng: Any) -> None:
        """A new random leg for the vessels ``idx`` (their draws ``rng``), from their heading now."""
        c = self.config
        ts = self.ts
        ts[idx, S.target] += course_change(c, rng)
        ts[idx, S.leg_sign] = np.where(ts[idx, S.target] >= self.sim.heading[idx], 1.0, -1.0)
        ts[idx, S.reached] = 0.0
        ts[idx, S.executes] += 1.0
        ts[idx, S.next] = ts[idx, S.t] + _uniform(rng, c.leg_time_s)

    def update(self, phase: np.ndarray) -> None:
        if not self.imo:  # random schedule: a new leg on vessels whose leg time is up
            due = (phase == PHASE_STEP) & (
                self.ts[:, S.t] + self.config.control_interval_s >= self.ts[:, S.next] - 1e-9
            )
            idx = np.flatnonzero(due)
            if len(idx):
                self._new_legs(idx, vessels_draws(self.rngs, idx))
        super().update(phase)

    # --- info -------------------------------------------------------------------------------------------
    def info_from(self, snap: tuple) -> dict[str, Any]:
        s, terms, f, alive = snap
        return {
            **self.heading_info(s, terms, f),
            "executes": int(s[S.executes]),
            "overshoot_count": int(s[S.os_n]),
            "overshoot_1_deg": math.degrees(s[S.os1]),
            "overshoot_2_deg": math.degrees(s[S.os2]),
            "last_overshoot_deg": math.degrees(s[S.os_last]),
            "diverged": not alive,
        }

    def batch_info(self) -> dict[str, Any]:
        s = self.task_columns()
        return {
            **self.batch_heading_info(s),
            "executes": s[S.executes].astype(np.int64),
            "overshoot_count": s[S.os_n].astype(np.int64),
            "overshoot_1_deg": np.degrees(s[S.os1]),
            "overshoot_2_deg": np.degrees(s[S.os2]),
            "last_overshoot_deg": np.degrees(s[S.os_last]),
            "diverged": ~self.sim.alive,
        }
