"""What every task's kernel shares: the motion features every observation begins with, the reward terms more
than one task uses, and the compiled steps that close a vessel's row (weighting, encoding the observation);
and what the open-water tasks (ZigZag, TurningCircle) share on the Python side: the reset options, the side
of a turn, the start of a vessel's episode, the rudder scale, the roll options (roll observed, the optional heel
term; on a ship with roll) and the kernel's arguments (:class:`OpenWaterTask`).

Every task's features begin with :data:`MOTION` (:func:`task_spec` prepends it), so :func:`motion_features`
writes the same columns for all of them. The motion comes from the physics by name
(:mod:`vessel_gym.physics.kinematics` accessors), never from a column of the state row.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, ClassVar

import numpy as np
from numba import njit

from vessel_gym.envs.config import RollOptionsConfig
from vessel_gym.envs.declare import FeatureSpec, Info, TaskSpec, Term, columns, logical_not
from vessel_gym.envs.task import Task, _uniform, start, start_batch, task_arrays
from vessel_gym.physics.kinematics import (
    heading,
    helm_orders,
    position,
    roll,
    rudder_angle,
    shaft_speed,
    velocity_through_water,
)
from vessel_gym.physics.roll import free_roll_frequency
from vessel_gym.physics.schema import SpecError
from vessel_gym.physics.units import DEG

#: the features every task begins with: motion through the water and the helm (the shaft speed is observed
#: only with engine control)
MOTION = (
    FeatureSpec("u", "m/s", (1.5, "U_T"), "surge velocity through the water"),
    FeatureSpec("v", "m/s", (0.5, "U_T"), "sway velocity through the water (+ starboard)"),
    FeatureSpec("r", "rad/s", (2.0, "U_T / L"), "rate of turn (+ starboard)"),
    FeatureSpec("rudder", "rad", (1.0, "rudder max"), "actual rudder angle (+ starboard)"),
    FeatureSpec("rudder_order", "rad", (1.0, "rudder max"), "rudder order"),
    FeatureSpec("rev", "rev/s", (1.5, "full rev"), "propeller shaft speed (tachometer)"),
)
M = columns(*(f.name for f in MOTION), typename="Motion")

def motion_observed(rev: bool) -> tuple[str, ...]:
    """The features every observation begins with: motion through the water and the helm; the shaft speed only
    if ``rev``."""
    return ("u", "v", "r", "rudder", "rudder_order") + (("rev",) if rev else ())


#: the roll features of the open-water tasks (observed with ``observe_roll``, on a ship with roll). A harmonic
#: roll of amplitude heel_ref at the ship's upright free-roll frequency omega_phi has the peak rate
#: heel_ref x omega_phi: the two scales describe the same motion
ROLL_FEATURES = (
    FeatureSpec("phi", "rad", (1.0, "heel ref"), "roll (heel) angle, + starboard down (observe_roll)"),
    FeatureSpec("p", "rad/s", (1.0, "heel ref x omega_phi"), "roll rate, + rolling to starboard (observe_roll)"),
)
#: the optional heel term of the open-water tasks (on with heel_weight != 0, a ship with roll)
HEEL_TERM = Term("heel", 0.0, "heel_weight != 0: -(phi / heel ref)^2")

#: the reward terms of the same name in several tasks
RUDDER_ACTIVITY_DOC = "-|change of rudder order| / (2 rudder limit)"
SPEED_LOSS_DOC = "-max(0, U0 - U) / U0"


def task_spec(
    title: str,
    terms: Sequence[Term],
    features: Sequence[FeatureSpec],
    options: Sequence[Term] = (),
    info: Sequence[Info] = (),
) -> TaskSpec:
    """The declaration of a task whose features are :data:`MOTION` followed by ``features`` (optional reward
    terms ``options``, ``info`` entries ``info``)."""
    return TaskSpec(title, terms, MOTION + tuple(features), options, info)


@njit(cache=True)
def motion(v, k):
    """Vessel k's (u, v, r, heading, north, east, rudder, rudder order, rev, rev order), asked of the physics by
    name from the state and input rows of the vessels' record ``v``."""
    x = v.x
    u, vv, r = velocity_through_water(x, k)
    n, e = position(x, k)
    delta_c, rev_c = helm_orders(v.inp, k)
    return u, vv, r, heading(x, k), n, e, rudder_angle(x, k), delta_c, shaft_speed(x, k), rev_c


@njit(cache=True)
def motion_features(f, u, v, r, delta, delta_c, rev):
    """Write the :data:`MOTION` columns of one feature row ``f``."""
    f[M.u] = u
    f[M.v] = v
    f[M.r] = r
    f[M.rudder] = delta
    f[M.rudder_order] = delta_c
    f[M.rev] = rev


@njit(cache=True)
def roll_features(v, k, i_phi, i_p):
    """Write vessel k's roll angle and roll rate into its feature row at columns ``i_phi``, ``i_p``."""
    phi, p = roll(v.x, k)
    v.feat[k, i_phi] = phi
    v.feat[k, i_p] = p


@njit(cache=True)
def heel(v, k, heel_ref):
    """Reward term -(phi / heel_ref)^2 of vessel k (heel_ref rad): 0 upright, -1 at the reference heel."""
    phi, _p = roll(v.x, k)
    h = phi / heel_ref
    return -h * h


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
def encode_row(v, k):
    """Observation of vessel k from its features. ``v.enc`` rows: (feature column, scale, normalized flag);
    normalized = clip(feature / scale, -1, 1), else clip(feature, -scale, scale); non-finite -> 0."""
    feat, enc, out = v.feat, v.enc, v.obs
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
def finish(v, k):
    """Weight the terms of vessel k in place (``v.w``) and sum them into its reward."""
    terms, w = v.terms, v.w
    tot = 0.0
    for j in range(terms.shape[1]):
        terms[k, j] *= w[j]
        tot += terms[k, j]
    v.reward[k] = tot


#: the ``info`` entry of the open-water tasks: the simulation diverged (the episode's end)
DIVERGED = Info("diverged", lambda v: logical_not(v.alive), "the simulation diverged")


# --- the open-water tasks' Python side --------------------------------------------------------------------------
def reset_options(
    c: Any, options: Mapping | None, rng: Any, U_T: float, extra: tuple[str, ...] = ()
) -> tuple[Any, float, dict[str, Any]]:
    """(heading, deg; approach speed, m/s; the ``extra`` options given) of an open-water reset: the options,
    else drawn from ``initial_heading_deg`` / the config's approach speed (default U_T). ``rng``: a numpy
    Generator (the heading a float) or :class:`~vessel_gym.envs.generators.BatchDraws` (an array if drawn)."""
    opts = dict(options or {})
    drawn = _uniform(rng, c.initial_heading_deg)  # drawn with the option too: the stream stays the same
    heading = float(opts.pop("heading_deg")) if "heading_deg" in opts else drawn
    speed = float(opts.pop("speed_m_s", c.approach_speed_m_s or U_T))
    unknown = sorted(set(opts) - set(extra))
    if unknown:
        allowed = ", ".join(("heading_deg", "speed_m_s", *extra))
        raise ValueError(f"unknown reset option(s) {unknown} (allowed: {allowed})")
    return heading, speed, opts


def draw_side(side: str, rng: Any) -> Any:
    """Side of a turn, +1 starboard / -1 port ("random": drawn, -1 for a draw >= 0.5; an array of them from
    :class:`~vessel_gym.envs.generators.BatchDraws`)."""
    value = {"starboard": 1.0, "port": -1.0}.get(side)
    return 1.0 - 2.0 * (rng.random() >= 0.5) if value is None else value


#: the record of an open-water task's arrays (the kernel's ``t``): task state ``ts``, parameter row ``p``
OpenWaterArrays = task_arrays("OpenWaterArrays", __name__, vessel=("ts",), shared=("p",))


class OpenWaterTask(Task):
    """A task in open water: its task state ``ts`` (columns ``S``) keeps the original course ``psi0``, the
    approach speed ``U0`` and the previous rudder order ``prev_order``; its parameter row is ``p`` (its record
    ``Arrays``: ``ts`` and ``p``, unless the task declares more). ``disturbances`` (if the task has them) are drawn at each start."""

    S: ClassVar[Any]  # the columns of the task state
    Arrays = OpenWaterArrays
    disturbances: Any = None

    def rudder_scale(self) -> float:
        """Scale of the rudder_activity term: the helm's rudder limit, rad."""
        return self.helm.rudder_limit_rad[0] if hasattr(self.helm, "rudder_limit_rad") else self.delta_max

    def start_vessel(self, k: int, rng: np.random.Generator, heading: float, speed: float) -> np.ndarray:
        """Put vessel k on ``heading`` (deg) at ``speed`` (m/s), its disturbances drawn first; clear its task
        state but for the original course, the approach speed and (:meth:`started`) the rudder order, and
        return that row."""
        self._clear_start(k, rng, float(heading), speed)
        start(self, k, speed, heading)
        return self.ts[k]

    def start_vessels(self, idx: np.ndarray, rng: Any, heading: Any, speed: Any) -> None:
        """:meth:`start_vessel` of the vessels ``idx`` at once (``heading``, ``speed``: scalars or arrays over
        ``idx``; ``rng``: their draws), with one batched ``Simulation.reset``."""
        self._clear_start(idx, rng, heading, speed)
        start_batch(self, idx, speed, heading)

    def _clear_start(self, k: Any, rng: Any, heading: Any, speed: Any) -> None:
        """Disturbances drawn and set, task state rows cleared but for the original course and approach speed."""
        if self.disturbances is not None:
            self.disturbances.apply(self.sim, k, rng, heading)
        S = self.S
        self.ts[k] = 0.0
        self.ts[k, S.psi0] = heading * DEG  # the simulation's start heading, rad (Simulation.reset's product)
        self.ts[k, S.U0] = speed

    def started(self, k: int | np.ndarray) -> None:
        self.ts[k, self.S.prev_order] = self.sim.rudder_order[k]

    # --- the roll options (tasks whose config is a RollOptionsConfig) ------------------------------------------
    def check_roll_options(self) -> None:
        """Refuse the roll options on a 3-DOF ship, with a one-line error naming the option."""
        c = self.config
        asked = [name for name, on in (("observe_roll", c.observe_roll), ("heel_weight", c.heel_weight != 0.0)) if on]
        if asked and self.ship.roll is None:
            raise SpecError(
                f"{type(c).__name__}: {asked[0]} needs a ship with roll (a [roll] table, e.g. ship = "
                f"'container'); ship {self.ship.name!r} is 3-DOF"
            )

    def scales(self) -> dict[str, float]:
        """The shared scale names and, with the roll options, those of :data:`ROLL_FEATURES`: the heel
        reference, rad, and that times the ship's upright free-roll frequency omega_phi, 1/s
        (:func:`~vessel_gym.physics.roll.free_roll_frequency`): the peak rate of a harmonic roll of amplitude
        heel_ref. The roll options are checked here, the first point of the construction at which the ship is
        known, before the observation layout or anything else uses them."""
        if isinstance(self.config, RollOptionsConfig):
            self.check_roll_options()
        out = super().scales()
        if isinstance(self.config, RollOptionsConfig):
            omega = free_roll_frequency(self.sim.Ps[0])
            ref = self.config.heel_ref_deg * DEG
            out.update({"heel ref": ref, "heel ref x omega_phi": ref * omega})
        return out

    def roll_observed(self) -> tuple[str, ...]:
        """The roll features the observation ends with: both with ``observe_roll``, else none."""
        return tuple(f.name for f in ROLL_FEATURES) if self.config.observe_roll else ()

    def switch_on_heel(self, i_heel_ref: int) -> None:
        """With ``heel_weight`` != 0: the spec's optional block (the heel term) joins the reward terms, and the
        parameter row's column ``i_heel_ref`` gets the heel reference (rad; 0 leaves the term off)."""
        if self.config.heel_weight == 0.0:
            return
        self.term_names = self.spec.term_names_with(True)
        self.weights = np.append(self.weights, self.config.heel_weight)
        self.terms = np.zeros((self.n, len(self.term_names)))
        self.p[i_heel_ref] = self.config.heel_ref_deg * DEG
