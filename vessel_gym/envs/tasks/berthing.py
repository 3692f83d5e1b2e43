"""Berthing: from 3-10 ship lengths off a berth to alongside its fenders, with thrusters or tugs.

The berth is a scenario's ``[[berth]]`` entry (quay face, the ship's side to it, its fenders and their type,
tugs if the ship has them there; :class:`~vessel_gym.scenarios.scenario.Berth`). The simulation carries the
berth's fenders (:class:`~vessel_gym.physics.components.fenders.QuayFenders`), the ship file's tunnel thrusters
and the berth's tugs; the action is [rudder, engine, one order per thruster or tug] in [-1, 1]
(:class:`BerthingHelm`). Success: the ship lies alongside (its side within ``gap_tolerance_m`` of the fender
faces or pressing on them, parallel within ``heading_tolerance_deg``, midship within ``along_tolerance_m`` of
its place on the berth, speed over ground below ``speed_tolerance_m_s``) for ``hold_s``, having touched the
fenders no faster than the PIANC design berthing velocity of its displacement (Brolsma, condition
``pianc_condition``) and with no fender beyond its rated energy. Failures: a fender overloaded, touching too
fast, the hull on the quay or any other obstacle, grounding, leaving the chart, time. docs/berthing.md.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from gymnasium import spaces

from vessel_gym.envs.config import ShipEnvConfig
from vessel_gym.envs.declare import FeatureSpec, Info, Term, columns, degrees, maximum, pick, whole_rows
from vessel_gym.envs.helm import ContinuousHelm, continuous_orders, real_values
from vessel_gym.envs.registration import register_task
from vessel_gym.envs.task import Task, _uniform, start, task_arrays
from vessel_gym.envs.tasks.common import MOTION, task_spec
from vessel_gym.physics.components.fenders import QuayFenders, QuayFendersParams, design_berthing_velocity
from vessel_gym.physics.components.thrusters import OrderedComponent
from vessel_gym.physics.components.tug import Tug
from vessel_gym.physics.schema import SpecError, param
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.units import DEG
from vessel_gym.scenarios import load_scenario
from vessel_gym.scenarios.geometry import hull_outline

#: outcomes (flags), 0 while the episode runs
OUTCOMES = (
    "running",
    "success",
    "fender_overload",
    "contact_speed",
    "contact",
    "grounding",
    "out_of_bounds",
    "diverged",
)
OK, SUCCESS, OVERLOAD, FAST, CONTACT, GROUNDING, OUT, DIVERGED = range(len(OUTCOMES))
S: Any = columns("t", "d_prev", "held", "effort", "touched", "contact_speed")  # per-vessel task state
FEAT: Any = None  # set below from SPEC; the info entries read it


def _limit(v: Any) -> Any:
    """The task's PIANC contact-speed limit, one per vessel (a number for one)."""
    return v.task.v_limit + 0.0 * v.ts[S.t]


def _rated(v: Any) -> Any:
    """The fenders' rated energy, kJ, one per vessel (a number for one)."""
    return v.task.E_rated / 1e3 + 0.0 * v.ts[S.t]


INFO = (
    Info("outcome", lambda v: pick(OUTCOMES, v.flags), "running, success or the failure that ended it"),
    Info("success", lambda v: v.flags == SUCCESS, "alongside within the tolerances, held"),
    Info("is_success", same_as="success", doc="as success (the agents' name)"),
    Info("time_s", lambda v: v.ts[S.t], "time since the start, s"),
    Info("along_error_m", lambda v: v.feat[FEAT.along_error], "midship ahead of its place on the berth, m"),
    Info("off_error_m", lambda v: v.feat[FEAT.off_error], "side's distance off the unloaded fender faces, m"),
    Info("heading_error_deg", lambda v: degrees(v.feat[FEAT.berth_heading_error]), "heading - berth's, deg"),
    Info("held_s", lambda v: v.ts[S.held], "time alongside within the tolerances so far, s"),
    Info("touched", lambda v: v.ts[S.touched] > 0.5, "the ship has touched a fender"),
    Info(
        "contact_speed_m_s",
        lambda v: v.ts[S.contact_speed],
        "speed of compression at the first touch (0 before)",
    ),
    Info("contact_speed_limit_m_s", _limit, "PIANC design berthing velocity of the ship's displacement"),
    Info("fender_energy_kJ", lambda v: whole_rows(v.fender_energy_kJ), "energy absorbed by each fender, kJ"),
    Info("fender_rated_energy_kJ", _rated, "rated energy of a fender, kJ"),
    Info("max_fender_energy_fraction", lambda v: v.feat[FEAT.fender_load], "largest fender energy / rating"),
    Info(
        "assist_effort",
        lambda v: v.ts[S.effort] / maximum(v.ts[S.t], 1e-9),
        "mean over time of the thruster and tug orders squared",
    ),
)
SPEC = task_spec(
    "Berthing",
    terms=(
        Term(
            "progress",
            1.0,
            "(d_prev - d) / L, d the distance to the berthed pose (heading error x L / pi added)",
        ),
        Term("effort", 0.01, "-mean over the thrusters and tugs of order^2"),
        Term(
            "overspeed",
            0.05,
            "-(speed towards the quay beyond the pilot's profile, 0.5 v_PIANC + 0.01 x distance off) / v_PIANC,"
            " at most 1",
        ),
        Term("alongside", 1.0, "control interval / hold time while alongside within the tolerances"),
        Term("outcome", 10.0, "+1 on success, -1 on a failure (the step it ends)"),
    ),
    features=(
        FeatureSpec(
            "along_error", "m", (12.0, "L"), "midship ahead (+) of its place on the berth, along the quay"
        ),
        FeatureSpec(
            "off_error", "m", (12.0, "L"), "side's distance out from the unloaded fender faces (+ off)"
        ),
        FeatureSpec("berth_heading_error", "rad", (1.0, "pi"), "heading - berth heading, wrapped"),
        FeatureSpec("vg_along", "m/s", (1.5, "U_T"), "velocity over ground along the quay"),
        FeatureSpec("vg_off", "m/s", (0.5, "U_T"), "velocity over ground away from the quay (+ off)"),
        FeatureSpec("fender_load", "-", (1.5, "1"), "largest energy absorbed by a fender / its rated energy"),
        FeatureSpec(
            "assist",
            "-",
            (1.0, "1"),
            "thruster j's thrust, or tug j's force along its line, / its maximum (+ to starboard)",
            repeat="n_assist",
        ),
    ),
    info=INFO,
)
TERM = SPEC.TERM
FEAT = SPEC.FEAT
BerthingReward = SPEC.weights_class("BerthingReward", __name__, "Berthing reward weights.")
#: the task's record, the kernel's ``t``: per vessel its state, outcome flag and fender energies (kJ); the
#: berth's geometry, its components and the simulation (the kernel is numpy over the vessels, not compiled)
BerthingArrays = task_arrays(
    "BerthingArrays", __name__, vessel=("ts", "flags", "fender_energy_kJ"), shared=("berth_frame",)
)


@dataclass(frozen=True, kw_only=True)
class BerthingConfig(ShipEnvConfig):
    ship: str | None = param(None, doc="ship (default: the scenario's)")  # type: ignore[assignment]
    engine_control: bool = param(True, doc="the agent gives the engine order (always, in this task)")  # type: ignore[assignment]
    control_interval_s: float = param(2.0, unit="s", lo=0.1, hi=60.0, doc="time between actions")  # type: ignore[assignment]
    scenario: str = param("supply_base", doc="scenario with a [[berth]] (built-in name or path)")
    berth: str | None = param(None, doc="the berth's name (default: the scenario's first)")
    start_distance_L: tuple[float, ...] = param(
        (3.0, 6.0), unit="L", lo=1.0, hi=10.0, doc="[min, max] start distance from the approach point"
    )
    approach_offset_L: float = param(
        0.6,
        unit="L",
        lo=0.0,
        hi=5.0,
        doc="the approach point lies this far off the berth, square to the quay",
    )
    start_sector_deg: float = param(
        60.0, unit="deg", lo=0.0, hi=180.0, doc="start bearings within this of square off the quay"
    )
    heading_noise_deg: float = param(
        15.0, unit="deg", lo=0.0, hi=90.0, doc="start heading about the approach"
    )
    start_speed_m_s: tuple[float, ...] = param(
        (0.5, 1.0), unit="m/s", lo=0.01, hi=10.0, doc="[min, max] start"
    )
    weather: bool = param(True, doc="draw wind and current from the scenario's [weather] (else calm)")
    wind_m_s: tuple[float, ...] | None = param(
        None, unit="m/s", lo=0.0, hi=40.0, doc="[min, max] wind speed instead of the scenario's (directions its)"
    )
    current_m_s: tuple[float, ...] | None = param(
        None, unit="m/s", lo=0.0, hi=3.0, doc="[min, max] current speed instead of the scenario's (directions its)"
    )
    gap_tolerance_m: float = param(
        0.1, unit="m", lo=0.0, hi=10.0, doc="side at most this off the fender faces, having touched them"
    )
    heading_tolerance_deg: float = param(3.0, unit="deg", lo=0.1, hi=45.0, doc="parallel to the quay within")
    along_tolerance_m: float = param(5.0, unit="m", lo=0.1, hi=100.0, doc="midship within this of its place")
    speed_tolerance_m_s: float = param(0.05, unit="m/s", lo=0.001, hi=1.0, doc="speed over ground below")
    hold_s: float = param(30.0, unit="s", lo=0.0, hi=600.0, doc="alongside for this long: success")
    pianc_condition: str = param(
        "a", choices=("a", "b", "c", "d", "e"), doc="PIANC navigation condition of the contact speed limit"
    )
    reward: BerthingReward = param(BerthingReward(), doc="reward weights")  # type: ignore[valid-type]


def _pip(px: np.ndarray, py: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Points (px, py) inside the polygon ``poly`` (M, 2), even-odd ray casting, vectorised over the points."""
    inside = np.zeros(px.shape, dtype=bool)
    x0, y0 = poly[-1]
    for x1, y1 in poly:
        crosses = (y1 > py) != (y0 > py)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = x1 + (py - y1) * (x0 - x1) / (y0 - y1)
        inside ^= crosses & (px < xc)
        x0, y0 = x1, y1
    return inside


class BerthingHelm(ContinuousHelm):
    """Box(-1, 1)^(2 + k): rudder and engine as the continuous helm, then one order per thruster or tug (its
    ``set_order``: a thruster's fraction of rated rpm, a tug's of its bollard pull; + towards starboard)."""

    def __init__(self, config: ShipEnvConfig, sim: Simulation, assist: list[OrderedComponent]) -> None:
        super().__init__(config, sim)
        self.assist = assist
        self.dim = 2 + len(assist)
        self._shape = (self.dim,)
        self.space = spaces.Box(-1.0, 1.0, shape=(self.dim,), dtype=np.float32)

    def single(self, action: Any) -> np.ndarray:
        a = real_values(action, "action")
        if a.size != self.dim:
            raise ValueError(f"action must have {self.dim} values, got shape {a.shape}")
        return a.reshape(1, self.dim)

    def apply_single(self, action: Any) -> None:
        a = self.single(action)[0]
        if np.isnan(a).any():
            raise ValueError(f"action contains NaN: {action!r}")
        rudder, rev = continuous_orders(a[0], a[1], self._lim0, self._fa0, self._fs0)
        self.sim.set_helm(rudder_order_rad=rudder, rev_order=rev, k=0)
        for c, o in zip(self.assist, a[2:]):
            c.set_order(o)

    def apply(self, actions: np.ndarray) -> None:
        super().apply(actions[:, :2])
        for j, c in enumerate(self.assist):
            c.set_order(actions[:, 2 + j])


def episode_metrics(infos: list[Mapping[str, Any]], terminated: bool) -> dict[str, Any]:
    """success, outcome, time, contact speed against its limit, the largest fender energy against its rating,
    thruster and tug effort."""
    last = infos[-1]
    return {
        "success": bool(last["success"]),
        "outcome": str(last["outcome"]) if terminated else "timeout",
        "time_s": float(last["time_s"]),
        "contact_speed_m_s": float(last["contact_speed_m_s"]),
        "contact_speed_limit_m_s": float(last["contact_speed_limit_m_s"]),
        "max_fender_energy_fraction": float(last["max_fender_energy_fraction"]),
        "assist_effort": float(last["assist_effort"]),
    }


def scripted_pilot(env: Any) -> Any:
    from vessel_gym.envs.tasks.berthing_pilot import BerthingPilot

    return BerthingPilot(env)


class BerthGeometry:
    """What the kernel reads besides the arrays: the simulation (its named quantities), the fenders and the
    thrusters and tugs, the berth's frame, the hull outline, the chart's obstacles and shoals, the limits."""

    def __init__(self, task: Any) -> None:
        self.sim: Simulation = task.sim
        self.fenders: QuayFenders = task.fenders
        self.assist: list[OrderedComponent] = task.assist
        self.config: BerthingConfig = task.config
        self.berthed, self.along_dir, self.to_water = task.berthed, task.along_dir, task.to_water  # m, -, -
        self.psi_b: float = task.psi_b  # rad
        self.hull: np.ndarray = task.hull  # the waterline outline, body axes, m
        self.hard: list[np.ndarray] = task.hard  # land, breakwaters, quays
        self.shoals: list[np.ndarray] = task.shoals  # depth areas shallower than the draught
        self.L: float = task.L
        self.v_limit: float = task.v_limit  # m/s
        self.E_rated: float = task.E_rated  # J
        self.peaks: list[int] = task.peaks  # columns of the fenders' deepest compressions
        self.assist_states: list[list[int]] = task.assist_states  # columns of each unit's states
        self.n: int = task.n
        self.bounds = task.scenario.bounds_m

    def frame(self) -> tuple[np.ndarray, ...]:
        """(along error m, off error m, heading error rad, ground velocity along and off, m/s) of every vessel."""
        sim = self.sim
        dn, de = sim.north - self.berthed[0], sim.east - self.berthed[1]
        along = dn * self.along_dir[0] + de * self.along_dir[1]
        off = dn * self.to_water[0] + de * self.to_water[1]
        vn, ve = sim.ground_velocity()
        va = vn * self.along_dir[0] + ve * self.along_dir[1]
        vo = vn * self.to_water[0] + ve * self.to_water[1]
        dpsi = (sim.heading - self.psi_b + math.pi) % (2.0 * math.pi) - math.pi
        return along, off, dpsi, va, vo

    def hull_on(self, polys: list[np.ndarray]) -> np.ndarray:
        """Every vessel's hull outline has a point inside one of ``polys``."""
        sim = self.sim
        psi = sim.heading[:, None]
        c, s = np.cos(psi), np.sin(psi)
        px = sim.north[:, None] + c * self.hull[None, :, 0] - s * self.hull[None, :, 1]
        py = sim.east[:, None] + s * self.hull[None, :, 0] + c * self.hull[None, :, 1]
        hit = np.zeros(px.shape[0], dtype=bool)
        for p in polys:
            hit |= _pip(px, py, p).any(axis=1)
        return hit


def berthing_update(phase: np.ndarray, v: Any, t: Any) -> None:
    """The step of every vessel in ``phase`` (1 stepped, 2 just reset), numpy over the vessels: ``v`` the
    framework's record of the vessels, ``t`` the task's (:data:`BerthingArrays`)."""
    g = t.berth_frame
    c, sim, ts, n = g.config, g.sim, t.ts, g.n
    act = phase > 0
    stepped = phase == 1
    along, off, dpsi, va, vo = g.frame()
    z = sim.component_states
    energy = g.fenders.energies(z[:, g.peaks])  # J
    t.fender_energy_kJ[:] = energy / 1e3
    load = energy.max(axis=1) / g.E_rated
    touch = g.fenders.touch_speed(n)
    first = act & (ts[:, S.touched] == 0.0) & np.isfinite(touch)
    ts[first, S.touched] = 1.0
    ts[first, S.contact_speed] = touch[first]
    ci = c.control_interval_s
    d = np.hypot(along, off) + g.L * np.abs(dpsi) / math.pi
    orders = np.array([np.broadcast_to(a.orders(n), (n,)) for a in g.assist]).reshape(len(g.assist), n)
    effort = (orders**2).mean(axis=0) if len(g.assist) else np.zeros(n)
    # alongside: touched, the side within the gap tolerance of the fender faces (or pressing on them), parallel,
    # in place, still
    sog = np.hypot(va, vo)
    alongside = (
        (ts[:, S.touched] > 0.0)
        & (off <= c.gap_tolerance_m)
        & (np.abs(dpsi) <= c.heading_tolerance_deg * DEG)
        & (np.abs(along) <= c.along_tolerance_m)
        & (sog <= c.speed_tolerance_m_s)
    )
    flags = t.flags
    running = act & (flags == OK)
    ts[stepped, S.t] += ci
    ts[stepped, S.effort] += effort[stepped] * ci
    ts[:, S.held] = np.where(stepped & alongside, ts[:, S.held] + ci, np.where(stepped, 0.0, ts[:, S.held]))
    n_lo, n_hi, e_lo, e_hi = g.bounds
    out = (sim.north < n_lo) | (sim.north > n_hi) | (sim.east < e_lo) | (sim.east > e_hi)
    new = np.full(n, OK)
    new = np.where(ts[:, S.held] >= c.hold_s - 1e-9, SUCCESS, new)
    new = np.where(ts[:, S.contact_speed] > g.v_limit, FAST, new)
    new = np.where(load > 1.0, OVERLOAD, new)
    new = np.where(g.hull_on(g.shoals), GROUNDING, new)
    new = np.where(g.hull_on(g.hard), CONTACT, new)
    new = np.where(out, OUT, new)
    new = np.where(~v.alive, DIVERGED, new)
    ended = running & stepped & (new != OK)
    flags[ended] = new[ended]
    terms = v.terms
    terms[act] = 0.0
    # a diverged hull's position is not a number or far off: no progress from it (the outcome term ends it)
    progress = np.where(stepped & v.alive & np.isfinite(d), (ts[:, S.d_prev] - d) / g.L, 0.0)
    # closing on the quay faster than a gentle approach profile (half the PIANC velocity at the fenders,
    # 1 cm/s more per metre off): a dense signal of the contact-speed limit, which otherwise speaks only at
    # the touch
    profile = 0.5 * g.v_limit + 0.01 * np.maximum(off, 0.0)
    overspeed = np.nan_to_num(np.clip((-vo - profile) / g.v_limit, 0.0, 1.0), nan=0.0)
    terms[:, TERM.progress] = np.where(act, progress, terms[:, TERM.progress])
    terms[:, TERM.effort] = np.where(stepped, -effort, np.where(act, 0.0, terms[:, TERM.effort]))
    terms[:, TERM.overspeed] = np.where(stepped, -overspeed, np.where(act, 0.0, terms[:, TERM.overspeed]))
    held = np.where(stepped & alongside, ci / max(c.hold_s, ci), 0.0)
    terms[:, TERM.alongside] = np.where(stepped, held, np.where(act, 0.0, terms[:, TERM.alongside]))
    outcome = np.where(flags == SUCCESS, 1.0, -1.0)
    terms[:, TERM.outcome] = np.where(ended, outcome, np.where(act, 0.0, terms[:, TERM.outcome]))
    ts[act, S.d_prev] = d[act]
    terms[act] *= v.w
    v.reward[act] = terms[act].sum(axis=1)
    v.done[act] = flags[act] != OK
    f = v.feat
    motion_now = np.column_stack([sim.u, sim.v, sim.r, sim.rudder, sim.rudder_order, sim.rev])
    f[act, : len(MOTION)] = motion_now[act]
    fixed = np.column_stack([along, off, dpsi, va, vo, load])
    f[act, FEAT.along_error : FEAT.fender_load + 1] = fixed[act]
    if g.assist:
        for j, (c, cols) in enumerate(zip(g.assist, g.assist_states)):
            f[act, FEAT.assist + j] = c.delivered(z[:, cols])[act]
    enc = v.enc
    cols, scale = enc[:, 0].astype(int), enc[:, 1]
    vals = np.nan_to_num(f[:, cols], nan=0.0, posinf=0.0, neginf=0.0)
    normalized = enc[:, 2] > 0.0
    obs = np.where(normalized, np.clip(vals / scale, -1.0, 1.0), np.clip(vals, -scale, scale))
    v.obs[act] = obs[act]


@register_task(
    presets={
        "Berthing-v0": {},
        "BerthingTanker-v0": {
            "scenario": "tanker_berth",
            "control_interval_s": 6.0,
            "start_distance_L": [3.0, 4.0],
            "approach_offset_L": 0.3,
            "start_speed_m_s": [2.0, 2.5],
        },
    },
    max_episode_steps=900,  # 30 minutes at the default 2 s control interval
    pilots={"scripted": scripted_pilot},
    metrics=episode_metrics,
    train={
        # PPO as the shipped Berthing-v0 agents were trained (docs/berthing.md, "PPO from scratch"): 1.2M steps,
        # about 11 minutes of a loaded 2-core machine; observations normalised (the contact speeds are
        # hundredths of the scales the features are clipped to)
        "common": {
            "n_timesteps": 1_200_000,
            "n_envs": 16,
            "normalize": {"norm_obs": True, "norm_reward": True},
        },
        "ppo": {
            "n_steps": 256,
            "batch_size": 1024,
            "n_epochs": 5,
            "gamma": 0.995,
            "gae_lambda": 0.95,
            "learning_rate": 3e-4,
            "clip_range": 0.2,
            "ent_coef": 0.0,
            "policy_kwargs": {"net_arch": [128, 128], "activation_fn": "tanh", "log_std_init": -0.5},
        },
    },
)
class BerthingTask(Task):
    """Berthing: from 3-10 ship lengths off a scenario's berth to alongside its fenders (docs/berthing.md).

    ## Description

    The ship (default: the scenario's, ``supply`` at ``supply_base``) starts ``start_distance_L`` ship lengths
    from the approach point off the berth (``approach_offset_L`` out, square to the quay), within
    ``start_sector_deg`` of square off the quay, heading for it within ``heading_noise_deg``, at a speed of
    ``start_speed_m_s``, in wind and current drawn from the scenario's ``[weather]``. It must come alongside
    the berth's fenders, on the side the berth names.

    ## Action Space

    Box(-1, 1, (2 + k,)): rudder order / rudder limit, engine order / full ahead (astern), then one order per
    thruster (fraction of rated rpm) or tug (fraction of bollard pull), + pushing to starboard, in the order
    of the ship file's thrusters and the berth's tugs.

    ## Rewards

    reward = sum of weight x term (config ``reward``); weighted terms in ``info["reward_terms"]``.

    | Term | Default weight | Value per step |
    |------|----------------|----------------|
    | progress | 1.0 | (d_prev - d) / L, d the distance to the berthed pose plus L x heading error / pi |
    | effort | 0.01 | -mean over the thrusters and tugs of order^2 |
    | overspeed | 0.05 | -(closing speed on the quay beyond 0.5 v_PIANC + 0.01 x distance off) / v_PIANC, <= 1 |
    | alongside | 1.0 | control interval / hold time while alongside within the tolerances |
    | outcome | 10.0 | +1 on success, -1 on a failure (the step it ends) |

    ## Episode End

    Success: having touched the fenders no faster than the PIANC design velocity (``pianc_condition``), the
    side within ``gap_tolerance_m`` of the fender faces, parallel within ``heading_tolerance_deg``, midship
    within ``along_tolerance_m`` of its place, speed over ground below ``speed_tolerance_m_s``, for
    ``hold_s``. Failures: ``fender_overload`` (a fender past its rated energy), ``contact_speed``,
    ``contact`` (the hull on the quay or any obstacle), ``grounding``, ``out_of_bounds``, ``diverged``.
    Truncation after 900 control steps.
    """

    Config = BerthingConfig
    spec = SPEC
    S = S
    kernel = staticmethod(berthing_update)
    Arrays = BerthingArrays

    def __init__(self, config: BerthingConfig, n: int) -> None:
        if config.action_type != "continuous":
            raise SpecError("Berthing config action_type: only 'continuous' (thruster and tug orders)")
        sc = load_scenario(config.scenario)
        if not sc.berth:
            raise SpecError(f"Berthing config scenario: {sc.path or sc.name} has no [[berth]]")
        self.scenario, self.berth = sc, sc.find_berth(config.berth)
        ship = config.ship if config.ship is not None else sc.load_ship()
        ref = (sc.reference_latlon_deg[0], sc.reference_latlon_deg[1])
        self._assist_count: int | None = None
        super().__init__(config, n, ship=ship, reference_latlon_deg=ref)
        b, pt = self.berth, self.ship.particulars
        self.fenders = QuayFenders(
            self.ship, QuayFendersParams(quay_m=b.quay_m, fenders_m=b.fenders_m, side=b.side, fender=b.fender)
        )
        extra: list[Any] = [self.fenders, *(Tug(self.ship, t) for t in b.tugs)]
        # the simulation again, with the berth's fenders and tugs (scenario-level components)
        self.sim = Simulation(
            self.ship, n=n, dt=self.dt, method=config.method, components=extra,
            reference_latlon_deg=ref,
        )  # fmt: skip
        self.assist = [c for c in self.sim.components if isinstance(c, OrderedComponent)]
        self.helm = BerthingHelm(config, self.sim, self.assist)
        self.assist_states = [
            [self.sim.component_state_names.index(f"{c.name}.{st.name}") for st in c.states]
            for c in self.assist
        ]
        if len(self.assist) != self.n_features - self.spec.n_fixed:  # the layout was made before the sim
            raise RuntimeError("Berthing: assist count changed")  # pragma: no cover
        self.peaks = [
            self.sim.component_state_names.index(f"QuayFenders.peak_{j}") for j in range(len(b.fenders_m))
        ]
        self.E_rated = self.fenders.curve.rated_energy  # J
        self.v_limit = design_berthing_velocity(self.ship.mass_kg / 1e3, config.pianc_condition)  # m/s
        self.psi_b = b.heading_deg * DEG
        self.along_dir = np.array(b.direction)
        self.to_water = np.array(b.to_water())
        self.berthed = np.array(b.berthed_point(pt.B_m / 2.0))
        if math.hypot(*self.berthed) < 2.0 * self.L:
            # Simulation.reset solves the steady start with the components' forces at a trial state whose
            # position is the local origin: a fender there would take part in it
            raise SpecError(
                f"Berthing config scenario: berth {b.name!r} of {sc.path or sc.name} lies within 2 ship lengths "
                "of the local origin; keep berths away from [0, 0] (the steady start is solved there)"
            )
        self.hull = np.array(hull_outline(self.L, pt.B_m))
        self.hard = [np.array(p) for _k, _n, p in sc.hard_obstacles()]
        self.shoals = [np.array(p) for _n, p in sc.shoals(pt.T_m)]
        self.ts = np.zeros((n, len(S)))
        self.flags = np.zeros(n, dtype=np.int64)
        self.fender_energy_kJ = np.zeros((n, len(b.fenders_m)))
        self.berth_frame = BerthGeometry(self)

    # --- declaration hooks ----------------------------------------------------------------------------------
    def feature_counts(self) -> dict[str, int]:
        if (
            self._assist_count is None
        ):  # before the simulation with the berth exists: the ship file's and tugs'
            # every commanded unit of the ship file (tunnel and azimuth thrusters; tugs), then the berth's tugs
            own = sum(1 for e in self.ship.components if issubclass(e.cls, OrderedComponent))
            self._assist_count = own + len(self.berth.tugs)
        return {"n_assist": self._assist_count}

    def observed(self) -> tuple[str, ...]:
        return self.spec.feature_names

    def scales(self) -> dict[str, float]:
        return {**super().scales(), "1": 1.0}

    # --- starts -------------------------------------------------------------------------------------------------
    def _clear(self, n0: float, e0: float, psi: float) -> bool:
        """The hull at this pose is in the chart, in water deeper than its draught and off every obstacle."""
        c, s = math.cos(psi), math.sin(psi)
        px = n0 + c * self.hull[:, 0] - s * self.hull[:, 1]
        py = e0 + s * self.hull[:, 0] + c * self.hull[:, 1]
        n_lo, n_hi, e_lo, e_hi = self.scenario.bounds_m
        if px.min() < n_lo or px.max() > n_hi or py.min() < e_lo or py.max() > e_hi:
            return False
        return not any(_pip(px, py, p).any() for p in self.hard + self.shoals)

    def reset_vessel(self, k: int, rng: np.random.Generator, options: Mapping | None) -> None:
        c = self.config
        if options:
            raise ValueError(f"unknown reset option(s) {sorted(options)} (Berthing takes none)")
        approach = self.berthed + c.approach_offset_L * self.L * self.to_water
        square = math.atan2(self.to_water[1], self.to_water[0])
        for _ in range(1000):
            d = rng.uniform(*c.start_distance_L) * self.L
            bearing = square + rng.uniform(-1.0, 1.0) * c.start_sector_deg * DEG
            n0, e0 = approach[0] + d * math.cos(bearing), approach[1] + d * math.sin(bearing)
            heading = bearing + math.pi + rng.uniform(-1.0, 1.0) * c.heading_noise_deg * DEG
            if self._clear(n0, e0, heading):
                break
        else:  # pragma: no cover - a berth without room in front of it
            raise RuntimeError(f"{self.scenario.name}: no clear start in front of berth {self.berth.name!r}")
        speed = _uniform(rng, c.start_speed_m_s)
        w = self.scenario.weather
        keys = ("wind_speed_m_s", "wind_from_deg", "current_speed_m_s", "current_to_deg")
        ranges = {key: getattr(w, key) for key in keys}
        if c.wind_m_s is not None:  # a stronger (or calmer) sea than the scenario's, its directions kept
            ranges["wind_speed_m_s"] = c.wind_m_s
        if c.current_m_s is not None:
            ranges["current_speed_m_s"] = c.current_m_s
        weather = {key: _uniform(rng, ranges[key]) for key in keys}
        if not c.weather:
            weather = {"wind_speed_m_s": 0.0, "current_speed_m_s": 0.0}
        self.sim.set_environments(np.array([k]), **weather)
        for a in self.assist:
            a.set_order(0.0, k, self.n)
        self.fenders.clear(k, self.n)
        self.ts[k] = 0.0
        self.flags[k] = OK
        start(self, k, speed, math.degrees(heading), n0, e0)

    def overlay(self, k: int) -> dict[str, Any]:
        """What the chart draws (``vessel_gym.ui.chart``): the berth (quay face, fenders coloured by the larger
        of the energy they absorbed and their compression now, each against its rating; the berthed pose) and
        panel rows (distance off, contact speed against the PIANC limit, the most loaded fender)."""
        fenders, b = self.fenders, self.berth
        H = b.fender.height_m
        compression = fenders.deflections(self.sim)[k] / (b.fender.rated_deflection * H)
        energy = self.fender_energy_kJ[k] * 1e3 / self.E_rated
        load = np.maximum(compression, energy)
        base = fenders.faces - H * np.asarray(fenders.to_water)
        along, off = self.berth_frame.frame()[:2]
        v_touch = float(self.ts[k, S.contact_speed])
        contact = f"{v_touch:.3f} / {self.v_limit:.3f} m/s" if self.ts[k, S.touched] > 0.0 else "-"
        return {
            "title": f"Berthing: {self.scenario.name}, {b.name}",
            "outcome": OUTCOMES[int(self.flags[k])],
            "berth": {
                "name": b.name,
                "quay_m": [tuple(p) for p in b.quay_m[:2]],
                "fender_base_m": base.tolist(),
                "fender_face_m": fenders.faces.tolist(),
                "fender_load": load.tolist(),
                "target": (float(self.berthed[0]), float(self.berthed[1]), float(self.psi_b)),
            },
            "rows": [
                ("off fenders", f"{float(off[k]):6.1f} m"),
                ("along", f"{float(along[k]):+6.1f} m"),
                ("contact", contact),
                ("fender max", f"{100.0 * float(energy.max()):5.1f} % of E_R"),
            ],
        }
