"""TurningCircle-v0: bring the ship into and hold a commanded turn, or reverse course in little room.

Declaration (its one id ``TurningCircle-v0``, registered by :func:`~vessel_gym.envs.registration.register_task`),
configuration, start of an episode, compiled step and the environment classes (the spec sheet:
:class:`TurningCircleEnv`) together.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import njit

from vessel_gym.control.angles import PI
from vessel_gym.control.turning import (
    ADVANCE_HEADING_RAD,
    TACTICAL_HEADING_RAD,
    at_crossing,
    course_axes,
    crossing_fraction,
)
from vessel_gym.envs.config import RollOptionsConfig
from vessel_gym.envs.declare import RAD_TO_DEG, FeatureSpec, Info, Term, columns
from vessel_gym.envs.disturbances import Disturbances, DisturbedOpenWaterConfig
from vessel_gym.envs.env import ShipEnv, ShipVectorEnv
from vessel_gym.envs.registration import register_task
from vessel_gym.envs.task import _uniform
from vessel_gym.envs.tasks.common import (
    DIVERGED,
    HEEL_TERM,
    ROLL_FEATURES,
    RUDDER_ACTIVITY_DOC,
    SPEED_LOSS_DOC,
    M,
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
from vessel_gym.physics.vessel import NO_REFCOUNT

MODES = ("rate", "radius", "reverse")
REVERSE = MODES.index("reverse")


# --- declaration ------------------------------------------------------------------------------------------------
def turning_radius(u: Any, v: Any, r: Any) -> Any:
    """Radius of the path through the water, m: U / |r| (0 while the ship does not turn), of one vessel's
    numbers or of arrays."""
    if isinstance(r, np.ndarray):
        r = np.abs(r)
        return np.where(r > 1e-9, np.hypot(u, v) / np.maximum(r, 1e-9), 0.0)
    r = abs(r)
    return math.hypot(u, v) / r if r > 1e-9 else 0.0


INFO_ENTRIES = (
    Info("time_s", doc="time since the start of the episode, s"),
    Info("heading_change_deg", doc="heading - original course, deg"),
    Info("rate_of_turn_deg_s", doc="rate of turn, deg/s"),
    # the motion as the kernel asked the physics for it (velocity_through_water), kept in the features; Python's
    # math.hypot is not the C library's hypot a kernel would call, so this one stays a function
    Info("turning_radius_m", lambda v: turning_radius(v.feat[M.u], v.feat[M.v], v.feat[M.r]), "U / |r|, m"),
    Info(
        "commanded_rate_deg_s",
        doc="rate mode: the commanded rate of turn, deg/s",
        when=lambda c: c.mode == "rate",
        otherwise=0.0,
    ),
    Info(
        "commanded_radius_m",
        doc="radius mode: the commanded radius, m",
        when=lambda c: c.mode == "radius",
        otherwise=0.0,
    ),
    Info("advance_m", doc="advance at 90 deg heading change, m"),
    Info("transfer_m", doc="transfer at 90 deg, m"),
    Info("tactical_diameter_m", doc="transfer at 180 deg, m"),
    Info("reached_90", doc="90 deg heading change reached", kind=bool),
    Info("reached_180", doc="180 deg heading change reached", kind=bool),
    Info("success", doc="the episode ended with its goal (reverse mode)", kind=bool),
    DIVERGED,
    Info(  # the only mode with an end state to reach
        "is_success", doc="reverse mode: the same as `success`", same_as="success", when=lambda c: c.mode == "reverse"
    ),
)
SPEC = task_spec(
    "TurningCircle-v0",
    terms=(
        Term("tracking_error", 1.0, "rate/radius: -min(relative error, 1)"),
        Term("progress", 5.0, "reverse: heading change this step / pi"),
        Term("footprint", 1.0, "reverse: -(growth of max advance + max transfer) / L"),
        Term("rudder_activity", 0.1, RUDDER_ACTIVITY_DOC),
        Term("speed_loss", 0.1, SPEED_LOSS_DOC),
        Term("time", 0.1, "reverse: -control interval x U0 / L"),
    ),
    features=(
        FeatureSpec("commanded_rate", "rad/s", (2.0, "U_T / L"), "commanded rate of turn"),
        FeatureSpec("rate_error", "rad/s", (2.0, "U_T / L"), "commanded - actual rate of turn"),
        FeatureSpec("commanded_curvature", "-", (1.0, "1"), "L / commanded radius (+ starboard)"),
        FeatureSpec("curvature_error", "-", (1.0, "1"), "L x (commanded - actual curvature r / U)"),
        FeatureSpec("heading_change", "rad", (2.0, "pi"), "heading - original course (unwrapped)"),
        FeatureSpec("advance", "m", (10.0, "L"), "displacement along the original course"),
        FeatureSpec("transfer", "m", (10.0, "L"), "displacement across it (+ starboard)"),
        *ROLL_FEATURES,
    ),
    options=(HEEL_TERM,),
    info=INFO_ENTRIES,
)
TERM = SPEC.TERM
FEAT = SPEC.FEAT
OPT = SPEC.OPT
INFO = SPEC.INFO
#: the features each mode observes after the motion
MODE_FEATURES = {
    "rate": ("commanded_rate", "rate_error"),
    "radius": ("commanded_curvature", "curvature_error"),
    "reverse": ("heading_change", "advance", "transfer"),
}

#: per-vessel task state (columns of ``ts``)
S = columns(
    "psi0",  # heading at the rudder order (episode start), rad
    "north0",  # midship position at the rudder order, m
    "east0",
    "command",  # rate mode: commanded rate of turn, rad/s; radius mode: commanded curvature, 1/m
    "prev_order",  # rudder order of the previous step, rad
    "U0",  # approach speed, m/s
    "t",  # time since the start of the episode, s
    "advance",  # advance at 90 deg heading change, m
    "transfer",  # transfer at 90 deg, m
    "tactical_diameter",  # tactical diameter (transfer at 180 deg), m
    "reached_90",  # 90 deg reached
    "reached_180",  # 180 deg reached
    "max_advance",  # largest advance so far, m
    "max_transfer",  # largest |transfer| so far, m
    "prev_turned",  # |heading change| at the previous step, rad
    "prev_advance",  # advance and transfer at the previous step, m
    "prev_transfer",
    typename="TurningState",
)
#: the kernel's parameter row
P = columns(
    "mode",  # 0 rate, 1 radius, 2 reverse
    "L",  # ship length, m
    "rudder_max",  # rudder scale (limit), rad
    "dt",  # control interval, s
    "heel_ref",  # heel reference of the heel term, rad; 0: the term is off (no column)
    typename="TurningParams",
)

TurningCircleReward = SPEC.weights_class(
    "TurningCircleReward",
    __name__,
    "Weights of the TurningCircle reward terms (reward = sum of weight x term).",
)


@dataclass(frozen=True, kw_only=True)
class TurningCircleConfig(RollOptionsConfig, DisturbedOpenWaterConfig):
    """TurningCircle-v0 configuration (see :class:`TurningCircleEnv`)."""

    mode: str = param("rate", choices=MODES, doc="task: hold a rate of turn, a radius, or reverse course")
    rate_prime: tuple[float, ...] = param(
        (0.05, 0.3), unit="-", lo=0.001, hi=5.0, doc="rate: [min, max] commanded r' = r L / U0"
    )
    radius_L: tuple[float, ...] = param(
        (2.0, 6.0),
        unit="L",
        lo=0.1,
        hi=1000.0,
        doc="radius: [min, max] commanded turning radius in ship lengths",
    )
    side: str = param("random", choices=("random", "starboard", "port"), doc="side of the commanded turn")
    reward: TurningCircleReward = param(TurningCircleReward(), doc="reward weights")


# --- compiled step ----------------------------------------------------------------------------------------------
@njit(cache=True, **NO_REFCOUNT)
def turning_update(phase, v, t):
    """Turning task (phases and records as :func:`zigzag_update`); ``done`` set on a completed course reversal."""
    p, ts, terms, feat, done = t.p, t.ts, v.terms, v.feat, v.done
    mode = int(p[P.mode])
    L = p[P.L]
    for k in range(ts.shape[0]):
        if phase[k] == 0:
            continue
        uk, vk, rk, psik, nk, ek, dk, dck, revk, revck = motion(v, k)
        s = ts[k]
        done[k] = False
        clear_row(terms, k)
        adv, trf = course_axes(s[S.psi0], s[S.north0], s[S.east0], nk, ek)
        turned = abs(psik - s[S.psi0])
        U = speed_through_water(uk, vk)
        U0 = s[S.U0]
        curv = rk / max(U, 0.1 * U0)
        if phase[k] == 1:
            s[S.t] += p[P.dt]
            tp = s[S.prev_turned]
            if s[S.reached_90] == 0.0 and turned >= ADVANCE_HEADING_RAD:
                fr = crossing_fraction(tp, turned, ADVANCE_HEADING_RAD)
                s[S.advance] = at_crossing(s[S.prev_advance], adv, fr)
                s[S.transfer] = abs(at_crossing(s[S.prev_transfer], trf, fr))
                s[S.reached_90] = 1.0
            if s[S.reached_180] == 0.0 and turned >= TACTICAL_HEADING_RAD:
                fr = crossing_fraction(tp, turned, TACTICAL_HEADING_RAD)
                s[S.tactical_diameter] = abs(at_crossing(s[S.prev_transfer], trf, fr))
                s[S.reached_180] = 1.0
            ma = max(s[S.max_advance], adv)
            mt = max(s[S.max_transfer], abs(trf))
            if mode == 0:
                terms[k, TERM.tracking_error] = -min(abs(rk - s[S.command]) / abs(s[S.command]), 1.0)
            elif mode == 1:
                terms[k, TERM.tracking_error] = -min(abs(curv - s[S.command]) / abs(s[S.command]), 1.0)
            else:
                terms[k, TERM.progress] = (min(turned, PI) - min(tp, PI)) / PI
                terms[k, TERM.footprint] = -((ma - s[S.max_advance]) + (mt - s[S.max_transfer])) / L
                terms[k, TERM.time] = -p[P.dt] * U0 / L
                done[k] = turned >= PI
            s[S.max_advance] = ma
            s[S.max_transfer] = mt
            terms[k, TERM.rudder_activity] = rudder_activity(dck, s[S.prev_order], p[P.rudder_max])
            terms[k, TERM.speed_loss] = speed_loss(U, U0)
            if p[P.heel_ref] > 0.0:
                terms[k, OPT.heel] = heel(v, k, p[P.heel_ref])
        if not v.alive[k]:
            done[k] = True
            clear_row(terms, k)
        finish(v, k)
        s[S.prev_order] = dck
        s[S.prev_turned] = turned
        s[S.prev_advance] = adv
        s[S.prev_transfer] = trf
        f = feat[k]
        motion_features(f, uk, vk, rk, dk, dck, revk)
        f[FEAT.commanded_rate] = s[S.command] if mode == 0 else 0.0
        f[FEAT.rate_error] = s[S.command] - rk if mode == 0 else 0.0
        f[FEAT.commanded_curvature] = s[S.command] * L if mode == 1 else 0.0
        f[FEAT.curvature_error] = (s[S.command] - curv) * L if mode == 1 else 0.0
        f[FEAT.heading_change] = psik - s[S.psi0]
        f[FEAT.advance] = adv
        f[FEAT.transfer] = trf
        roll_features(v, k, FEAT.phi, FEAT.p)
        encode_row(v, k)
        i = v.info[k]  # degrees as math.degrees computes them (RAD_TO_DEG)
        i[INFO.time_s] = s[S.t]
        i[INFO.heading_change_deg] = f[FEAT.heading_change] * RAD_TO_DEG
        i[INFO.rate_of_turn_deg_s] = f[M.r] * RAD_TO_DEG
        i[INFO.commanded_rate_deg_s] = s[S.command] * RAD_TO_DEG
        i[INFO.commanded_radius_m] = 1.0 / s[S.command] if s[S.command] != 0.0 else 0.0
        i[INFO.advance_m] = s[S.advance]
        i[INFO.transfer_m] = s[S.transfer]
        i[INFO.tactical_diameter_m] = s[S.tactical_diameter]
        i[INFO.reached_90] = 1.0 if s[S.reached_90] > 0.0 else 0.0
        i[INFO.reached_180] = 1.0 if s[S.reached_180] > 0.0 else 0.0
        i[INFO.success] = 1.0 if done[k] and v.alive[k] else 0.0


# --- the task ---------------------------------------------------------------------------------------------------
# --- capabilities: the classical pilots and the episode metrics ------------------------------------------------
def nomoto_pilot(env: Any, omega_UL: float = 1.0, zeta: float = 1.0) -> Any:
    """PI on the rate-of-turn error, gains by pole placement on the ship's Nomoto model at ``omega_UL`` U/L
    and ``zeta`` (:class:`vessel_gym.policy.RatePI`; the defaults: the untuned design)."""
    from vessel_gym.policy import RatePI

    return RatePI(env, omega_UL, zeta)


def pid_pilot(env: Any) -> Any:
    """:func:`nomoto_pilot` with the parameters tuned for the id (:func:`vessel_gym.policy.pilot_gains`)."""
    from vessel_gym.policy import pilot_gains

    return nomoto_pilot(env, **pilot_gains(env, "pid"))


def rule_pilot(env: Any) -> Any:
    """The IMO turning-circle test as a helm: 35 deg to the commanded side (:class:`~vessel_gym.envs.policies.TurningRule`)."""
    from vessel_gym.envs.policies import TurningRule

    return TurningRule(env)


def episode_metrics(infos: list[Mapping[str, Any]], terminated: bool) -> dict[str, Any]:
    """``rate_error_pct`` (rate mode: mean |r - r_c| / |r_c| over the steps), ``success``, and the IMO figures
    ``advance_m``, ``transfer_m``, ``tactical_diameter_m``."""
    errors = [
        abs(float(i["rate_of_turn_deg_s"]) - float(i["commanded_rate_deg_s"])) / abs(float(i["commanded_rate_deg_s"]))
        for i in infos
        if float(i.get("commanded_rate_deg_s", 0.0)) != 0.0
    ]
    last = infos[-1]
    return {
        "rate_error_pct": 100.0 * float(np.mean(errors)) if errors else math.nan,
        "success": bool(last.get("success", False)),
        **{key: float(last[key]) for key in ("advance_m", "transfer_m", "tactical_diameter_m")},
    }


@register_task(
    presets={"TurningCircle-v0": {}},
    max_episode_steps=480,
    env="vessel_gym.envs.tasks.turning:TurningCircleEnv",
    pilots={"pid": pid_pilot, "pid-nomoto": nomoto_pilot, "scripted": rule_pilot},
    metrics=episode_metrics,
)
class TurningCircleTask(OpenWaterTask):
    S = S
    Config = TurningCircleConfig
    spec = SPEC
    kernel = staticmethod(turning_update)

    def __init__(self, config: TurningCircleConfig, n: int) -> None:
        check_ranges(config, ("rate_prime", "radius_L", "initial_heading_deg"), "TurningCircle config")
        super().__init__(config, n)
        self.disturbances = Disturbances(config, self.ship, "TurningCircle config")
        self.mode = MODES.index(config.mode)
        self.ts = np.zeros((n, len(S)))
        p = np.zeros(len(P))
        p[P.mode] = self.mode
        p[P.L] = self.L
        p[P.rudder_max] = self.rudder_scale()
        p[P.dt] = config.control_interval_s
        self.p = p
        self.switch_on_heel(P.heel_ref)

    def observed(self) -> tuple[str, ...]:
        return (
            motion_observed(rev=self.config.engine_control)
            + MODE_FEATURES[self.config.mode]
            + self.roll_observed()
        )

    def reset_vessel(self, k: int, rng: np.random.Generator, options: Mapping | None) -> None:
        self.reset_batch(np.array([k]), rng, options)

    def reset_batch(self, idx: np.ndarray, rng: Any, options: Mapping | None) -> None:
        # each line draws one number per vessel of idx, in the order a lone reset draws them
        c = self.config
        heading, speed, opts = reset_options(c, options, rng, self.U_T, extra=("command",))
        side = draw_side(c.side, rng)
        if self.mode == 0:
            cmd = side * _uniform(rng, c.rate_prime) * speed / self.L
        elif self.mode == 1:
            cmd = side / (_uniform(rng, c.radius_L) * self.L)
        else:
            cmd = 0.0
        cmd = float(opts["command"]) if "command" in opts else cmd
        self.start_vessels(idx, rng, heading, speed)
        self.ts[idx, S.command] = cmd

    def started(self, k: int | np.ndarray) -> None:
        super().started(k)
        self.ts[k, S.north0] = self.sim.north[k]
        self.ts[k, S.east0] = self.sim.east[k]

    def overlay(self, k: int) -> dict[str, Any]:
        s = self.ts[k]
        out: dict[str, Any] = {
            "origin_m": (float(s[S.north0]), float(s[S.east0])),
            "original_course_rad": float(s[S.psi0]),
            "title": "TurningCircle",
        }
        if self.mode == 1:
            out["commanded_radius_m"] = float(1.0 / s[S.command])
        return out


# --- the environments (their docstrings are the spec sheets) -----------------------------------------------
class TurningCircleEnv(ShipEnv):
    """Bring the ship into a commanded turn and hold it, or reverse course with the least room.

    ## Description

    A ship starts in a steady straight approach; the agent holds the helm. ``mode="rate"`` (default):
    reach and hold a commanded rate of turn, drawn per episode as ``r' = r L / U0`` in ``rate_prime``
    (U0 approach speed) to ``side``. ``mode="radius"``: reach and hold a commanded turning radius drawn in
    ``radius_L`` ship lengths (curvature r / U). ``mode="reverse"``: turn the ship through 180 degrees
    with the smallest advance and transfer (the episode succeeds and terminates at 180 degrees).
    ``info`` reports the IMO MSC.137(76) turning-circle figures measured from the episode start (the
    rudder-order position) for the midship point: advance and transfer at 90 degrees heading change and
    tactical diameter (transfer at 180 degrees), interpolated between control steps. The scripted 35-degree
    turn (:class:`vessel_gym.envs.policies.TurningRule`) applied here is the IMO turning-circle test.

    Default ship ``kvlcc2_l7``, physics step 0.25 s (chosen from the ship, docs/envs.md), control
    interval 0.25 s.

    ## Action Space

    As :class:`~vessel_gym.envs.tasks.zigzag.ZigZagEnv`: ``Box(-1, 1, (1,))`` rudder order x rudder limit
    (+ starboard), ``(2,)`` with ``engine_control`` (engine order x full ahead / full astern rpm);
    clipped; NaN raises. ``action_type="discrete"``: helm orders (x telegraph steps).

    ## Observation Space

    ``Box(-1, 1, (7,), float32)`` normalized (``observation_type="physical"``: SI units clipped to
    +-scale). Rows 0-4 for every mode, then 2 or 3 rows for the mode; ``rev`` is inserted after row 4
    with ``engine_control``.

    | Num | Name | Unit | Scale | Meaning |
    |-----|------|------|-------|---------|
    | 0 | u | m/s | 1.5 U_T | surge velocity through the water |
    | 1 | v | m/s | 0.5 U_T | sway velocity (+ starboard) |
    | 2 | r | rad/s | 2 U_T / L | rate of turn (+ starboard) |
    | 3 | rudder | rad | rudder max | actual rudder angle |
    | 4 | rudder_order | rad | rudder max | rudder order |
    | 5 | commanded_rate | rad/s | 2 U_T / L | rate mode: commanded rate of turn |
    | 6 | rate_error | rad/s | 2 U_T / L | rate mode: commanded - actual |
    | 5 | commanded_curvature | - | 1 | radius mode: L / commanded radius (signed) |
    | 6 | curvature_error | - | 1 | radius mode: L (commanded - r / U) |
    | 5 | heading_change | rad | 2 pi | reverse mode: heading - original course |
    | 6 | advance | m | 10 L | reverse mode: displacement along the original course |
    | 7 | transfer | m | 10 L | reverse mode: displacement across it (+ starboard) |

    ## Rewards

    reward = sum of weight x term (config ``reward``); weighted terms in ``info["reward_terms"]``.

    | Term | Default weight | Value per step |
    |------|----------------|----------------|
    | tracking_error | 1.0 | rate: -min(abs(r - r_c) / abs(r_c), 1); radius: same on curvature r / U |
    | progress | 5.0 | reverse: increase of abs(heading change) (up to pi) / pi |
    | footprint | 1.0 | reverse: -(growth of max advance + growth of max abs(transfer)) / L |
    | rudder_activity | 0.1 | -abs(change of rudder order) / (2 x rudder limit) |
    | speed_loss | 0.1 | -max(0, U0 - U) / U0 |
    | time | 0.1 | reverse: -control interval x U0 / L |

    ## Starting State

    Steady straight approach at ``approach_speed_m_s`` (default test speed), rudder amidships, heading
    uniform in ``initial_heading_deg`` (default 0), at the origin. Calm water by default; the opt-in
    disturbance keys (``wind_speed_m_s``, ``current_speed_m_s``, ``Hs_m`` and their direction and period
    ranges, :class:`~vessel_gym.envs.disturbances.DisturbedOpenWaterConfig`) draw wind, current and waves
    per episode with the reset seed and set them as the vessel's environment in the simulation before the
    steady approach is solved (wind and waves need a ship with ``[windage]`` / ``[wave_drift]``, else
    construction raises ``SpecError``; the default ``kvlcc2_l7`` has neither, ``kvlcc2``, ``mariner`` and
    ``dtc`` have both). With all ranges at their calm defaults nothing is drawn and episodes are those of
    calm water, bit for bit. Advance, transfer and tactical diameter are measured over the ground, so a
    current carries them; the IMO figures are defined in calm water.

    ## Episode End

    * Termination: reverse mode, heading changed by 180 degrees (``info["success"]``); divergence.
    * Truncation: 480 steps (120 s) by the registered time limit.

    ## Info

    ``reward_terms``, ``time_s``, ``heading_change_deg``, ``rate_of_turn_deg_s``, ``turning_radius_m``,
    ``commanded_rate_deg_s``, ``commanded_radius_m``, ``advance_m``, ``transfer_m`` (at 90 deg),
    ``tactical_diameter_m`` (at 180 deg) (0 until reached), ``reached_90``, ``reached_180``, ``success``,
    ``diverged``; in reverse mode also ``is_success``.

    Success exists in reverse mode only: the heading has changed by 180 degrees without divergence (the
    termination above). There ``is_success`` repeats ``success`` under the key Stable-Baselines3's ``Monitor``
    and ``EvalCallback`` log as a success rate. Rate and radius mode are tracking tasks with no end state:
    they have no ``is_success`` (``success`` stays False) and are judged by the tracking error.

    ## Arguments

    ``gymnasium.make("vessel_gym/TurningCircle-v0", render_mode=None, config=None, **overrides)``; keys of
    :class:`~vessel_gym.envs.tasks.zigzag.ZigZagEnv`'s shared part plus ``mode``, ``rate_prime``, ``radius_L``,
    ``side``, ``approach_speed_m_s``, ``initial_heading_deg``, the disturbance ranges ``wind_speed_m_s``,
    ``wind_from_rel_deg``, ``current_speed_m_s``, ``current_to_rel_deg``, ``Hs_m``, ``Tp_s``,
    ``wave_from_rel_deg`` (directions relative to the original course), ``reward``. Strict: unknown keys
    raise.
    ``reset(options={"heading_deg", "speed_m_s", "command"})``: ``command`` is r_c in rad/s (rate mode) or
    the curvature in 1/m (radius mode).

    ## Vectorized environment

    ``gymnasium.make_vec("vessel_gym/TurningCircle-v0", num_envs=N)``: :class:`TurningCircleVectorEnv`.

    ## Version History

    * v0: initial version; later given the opt-in disturbance keys (their calm defaults leave v0's
      episodes unchanged).
    """

    Task = TurningCircleTask
    env_name = "TurningCircle-v0"


class TurningCircleVectorEnv(ShipVectorEnv):
    """Native vector version of :class:`TurningCircleEnv` (one simulation of ``num_envs`` ships)."""

    Env = TurningCircleEnv
