"""HarbourApproach-v0: from outside a harbour, through the entrance, to a stop in the goal area.

Declaration, configuration, start of an episode and compiled step together (the chart geometry is
:mod:`vessel_gym.envs.tasks.chart`); HarbourApproach-v1's changes are :mod:`vessel_gym.envs.tasks.harbour_v1`, the
environment classes and their spec sheets :mod:`vessel_gym.envs.harbour`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import njit, prange

from vessel_gym.control.angles import wrap_pi
from vessel_gym.envs.config import ShipEnvConfig, make_config
from vessel_gym.envs.declare import FeatureSpec, Term, columns
from vessel_gym.envs.task import Task, _uniform
from vessel_gym.envs.tasks.chart import (
    CONTACT,
    DIVERGED,
    GROUNDING,
    OK,
    OUT_OF_BOUNDS,
    OUTCOMES,
    SUCCESS,
    chart_query,
    chart_tables,
    inside_polygon,
    poses_clear,
)
from vessel_gym.envs.tasks.common import (
    RUDDER_ACTIVITY_DOC,
    clear_row,
    encode_row,
    finish,
    motion,
    motion_features,
    rudder_activity,
    task_spec,
)
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
from vessel_gym.physics.schema import param
from vessel_gym.physics.units import DEG
from vessel_gym.physics.vessel import NO_REFCOUNT
from vessel_gym.scenarios import Scenario, load_scenario
from vessel_gym.scenarios.geometry import hull_outline

#: the scenario's [weather] ranges, in the order a reset draws them (each an Environment field)
WEATHER_DRAWS = (
    "wind_speed_m_s",
    "wind_from_deg",
    "current_speed_m_s",
    "current_to_deg",
    "Hs_m",
    "Tp_s",
    "wave_from_deg",
)


# --- declaration ------------------------------------------------------------------------------------------------
SPEC = task_spec(
    "HarbourApproach-v0",
    terms=(
        Term("progress", 1.0, "decrease of the distance to the goal point / L"),
        Term("speed_excess", 1.0, "-(SOG above the allowed speed) / U_T"),
        Term("proximity", 0.5, "-(1 - clearance / safe clearance) when closer"),
        Term("rudder_activity", 0.05, RUDDER_ACTIVITY_DOC),
        Term("time", 0.01, "-1 per step"),
        Term("success", 20.0, "+1 on arrival"),
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
)
TERM = SPEC.TERM
FEAT = SPEC.FEAT

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

HarbourApproachReward = SPEC.weights_class(
    "HarbourApproachReward",
    __name__,
    "Weights of the HarbourApproach reward terms (reward = sum of weight x term).",
)


@dataclass(frozen=True, kw_only=True)
class HarbourApproachConfig(ShipEnvConfig):
    """HarbourApproach-v0 configuration (see :class:`~vessel_gym.envs.harbour.HarbourApproachEnv`)."""

    scenario: str = param("harbour", doc="built-in scenario name or scenario file path")
    ship: str | None = param(None, doc="ship name or file (default: the scenario's ship)")
    engine_control: bool = param(True, doc="the agent also gives the engine order")
    n_beams: int = param(16, unit="-", lo=0, hi=360, doc="range beams, evenly spaced clockwise from the bow")
    beam_range_L: float = param(10.0, unit="L", lo=0.1, hi=1000.0, doc="range-beam reach in ship lengths")
    slow_down_L: float = param(
        8.0,
        unit="L",
        lo=0.1,
        hi=1000.0,
        doc="allowed speed falls linearly from U_T to the goal speed within this distance",
    )
    safe_clearance_L: float = param(
        0.5, unit="L", lo=0.001, hi=100.0, doc="proximity term below this clearance"
    )
    reward: HarbourApproachReward = param(HarbourApproachReward(), doc="reward weights")


# --- compiled step ----------------------------------------------------------------------------------------------
@njit(cache=True)
def harbour_update(phase, *args):
    """Harbour task for vessels k0..k1-1 (phases as :func:`zigzag_update`); ``flags`` get the outcome of
    stepped vessels. ``args`` are :func:`_harbour_range`'s from ``x`` to ``k1`` (``env`` is the simulation's
    environment rows, ``sim.env``: current and wind as the physics sees them; the range comes last, so that the
    task binds (0, N) with the other arguments). Allocates the chart query's scratch and runs
    :func:`_harbour_range`."""
    hull, beam_dirs = args[6], args[11]
    nb = beam_dirs.shape[0]
    beams = np.empty(nb)
    hn = np.empty(hull.shape[0])
    he = np.empty(hull.shape[0])
    bw = np.empty((2, nb))
    _harbour_range(phase, *args, beams, hn, he, bw)


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
    L = p[P.L]
    UT = p[P.U_T]
    for k in range(k0, k1):
        if phase[k] == 0:
            continue
        uk, vk, rk, psik, nk, ek, dk, dck, revk, revck = motion(x, inp, k)
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
        finish(terms, k, w, reward)
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


# --- the task ---------------------------------------------------------------------------------------------------
# batches from this size run the task kernel on all threads (about 0.6 us of work per ship; waking the threads
# costs tens of microseconds on an idle machine)
PARALLEL_MIN_SHIPS = 256


class HarbourApproachTask(Task):
    Config = HarbourApproachConfig
    spec = SPEC
    kernel = staticmethod(harbour_update)

    def __init__(self, config: HarbourApproachConfig, n: int, scenario: Scenario | None = None) -> None:
        self.scenario = scenario if scenario is not None else load_scenario(config.scenario)
        sc = self.scenario
        ship = config.ship if config.ship is not None else sc.load_ship()
        angles = np.arange(config.n_beams) * (2.0 * math.pi / max(config.n_beams, 1))
        self.beam_dirs = np.stack([np.cos(angles), np.sin(angles)], axis=1).reshape(-1, 2)  # body-axis units
        super().__init__(
            config,
            n,
            ship=ship,
            reference_latlon_deg=(sc.reference_latlon_deg[0], sc.reference_latlon_deg[1]),
        )
        T = self.ship.particulars.T_m
        polys = [(1, pts) for _kind, _name, pts in sc.hard_obstacles()] + [
            (2, pts) for _n, pts in sc.shoals(T)
        ]
        self.edges, self.polys, self.pbox = chart_tables(polys)
        self.hull = np.array(hull_outline(self.L, self.ship.particulars.B_m), dtype=np.float64)
        self.goal_verts = np.array([(p[0], p[1]) for p in sc.goal.points], dtype=np.float64)
        self.ts = np.zeros((n, len(S)))
        self.flags = np.zeros(n, dtype=np.int64)
        gn, ge = sc.goal_point
        p = np.zeros(len(P))
        p[P.L] = self.L
        p[P.rudder_max] = getattr(self.helm, "rudder_limit_rad", np.array([self.delta_max]))[0]
        p[P.dt] = config.control_interval_s
        p[P.beam_range] = self.beam_range
        p[P.goal_north], p[P.goal_east] = gn, ge
        p[P.goal_heading] = sc.goal.heading_deg * DEG
        p[P.goal_tolerance] = sc.goal.heading_tolerance_deg * DEG
        p[P.goal_max_speed] = sc.goal.max_speed_m_s
        p[P.U_T] = self.U_T
        p[P.slow_distance] = config.slow_down_L * self.L
        p[P.clearance_ref] = config.safe_clearance_L * self.L
        p[P.north_min], p[P.north_max], p[P.east_min], p[P.east_max] = sc.bounds_m
        self.p = p
        self._beams = np.empty(config.n_beams)
        if n >= PARALLEL_MIN_SHIPS:
            self.kernel = harbour_update_parallel
        else:  # harbour_update's loop with the chart query's scratch made once (kernel_args), not per call
            self.kernel = _harbour_range

    @property
    def beam_range(self) -> float:
        return self.config.beam_range_L * self.L

    def observed(self) -> tuple[str, ...]:
        return self.spec.feature_names  # all of them, the shaft speed included: the agent has the engine

    def feature_counts(self) -> dict[str, int]:
        return {"n_beams": self.config.n_beams}

    def scales(self) -> dict[str, float]:
        U, sc = self.U_T, self.scenario
        n0, n1, e0, e1 = sc.bounds_m
        w = sc.weather
        return {
            **super().scales(),
            "R": math.hypot(n1 - n0, e1 - e0),  # chart diagonal, m
            "wind max + 2 U_T": max(w.wind_speed_m_s[1], 1.0) + 2.0 * U,  # m/s (scenario's strongest wind)
            "current max": max(w.current_speed_m_s[1], 0.1 * U),  # m/s (its strongest current, >= 0.1 U_T)
            "beam range": self.beam_range,  # m
        }

    def _pose_clear(self, n: float, e: float, psi: float) -> bool:
        flag, _c = chart_query(
            n,
            e,
            psi,
            self.hull,
            self.edges,
            self.polys,
            self.pbox,
            self.beam_dirs,
            self.beam_range,
            self._beams,
            np.empty(len(self.hull)),
            np.empty(len(self.hull)),
            np.empty((2, len(self.beam_dirs))),
        )
        return flag == OK

    def start_poses(self, idx: np.ndarray, rng: Any) -> tuple[Any, Any, Any, Any]:
        """(north, east, heading deg, speed) of the vessels ``idx``' starts, uniform in the scenario's
        ``[start]`` region: each vessel draws north, east and heading until its pose is inside the region and
        clear of the chart (the vessels still looking draw again together), then its speed."""
        st = self.scenario.start
        pts = np.array([(p[0], p[1]) for p in st.points])
        lo_, hi_ = pts.min(axis=0), pts.max(axis=0)
        xs, ys = pts[:, 0].copy(), pts[:, 1].copy()
        m = len(idx)
        n0, e0, heading = np.empty(m), np.empty(m), np.empty(m)
        todo = np.arange(m)
        for _ in range(1000):
            draws = rng if len(todo) == m else rng.subset(todo)
            n0[todo] = draws.uniform(lo_[0], hi_[0])
            e0[todo] = draws.uniform(lo_[1], hi_[1])
            heading[todo] = _uniform(draws, st.heading_deg)
            clear = poses_clear(
                n0[todo], e0[todo], heading[todo] * DEG, xs, ys, self.hull, self.edges, self.polys,
                self.pbox, self.beam_dirs, self.beam_range,
            )  # fmt: skip
            todo = todo[~clear]
            if not len(todo):
                break
        else:  # pragma: no cover - validated scenarios have room
            sc = self.scenario
            raise RuntimeError(f"{sc.path or sc.name}: no clear start pose found in [start] points")
        return n0, e0, heading, _uniform(rng, st.speed_m_s)

    def reset_vessel(self, k: int, rng: np.random.Generator, options: Mapping | None) -> None:
        self.reset_batch(np.array([k]), rng, options)

    def reset_batch(self, idx: np.ndarray, rng: Any, options: Mapping | None) -> None:
        # each draw gives one number per vessel of idx, in the order a lone reset draws them
        opts = dict(options or {})
        n0, e0, heading, speed = self.start_poses(idx, rng)
        w = self.scenario.weather
        weather = {key: _uniform(rng, getattr(w, key)) for key in WEATHER_DRAWS}
        n0 = float(opts.pop("north_m")) if "north_m" in opts else n0
        e0 = float(opts.pop("east_m")) if "east_m" in opts else e0
        heading = float(opts.pop("heading_deg")) if "heading_deg" in opts else heading
        speed = float(opts.pop("speed_m_s")) if "speed_m_s" in opts else speed
        env = opts.pop("environment", None)
        if opts:
            raise ValueError(
                f"unknown reset option(s) {sorted(opts)} (allowed: north_m, east_m, heading_deg, "
                "speed_m_s, environment)"
            )
        if env is None:
            self.sim.set_environments(idx, **weather)
        else:
            for k in idx.tolist():
                self.sim.set_environment(env, k)
        n0, e0 = np.broadcast_to(n0, idx.shape), np.broadcast_to(e0, idx.shape)
        gn, ge = self.p[P.goal_north], self.p[P.goal_east]
        ts = self.ts
        ts[idx] = 0.0
        ts[idx, S.d_prev] = [math.hypot(gn - a, ge - b) for a, b in zip(n0.tolist(), e0.tolist())]
        ts[idx, S.prev_north], ts[idx, S.prev_east] = n0, e0
        self.flags[idx] = OK
        self.start_batch(idx, speed, heading, n0, e0)

    def started(self, k: int | np.ndarray) -> None:
        self.ts[k, S.prev_order] = self.sim.rudder_order[k]

    def kernel_args(self) -> tuple:
        return (
            self.sim.state,
            self.sim.inputs,
            self.sim.env,
            self.sim.alive,
            self.ts,
            self.p,
            self.hull,
            self.edges,
            self.polys,
            self.pbox,
            self.goal_verts,
            self.beam_dirs,
            self.weights,
            self.enc,
            self.feat,
            self.obs,
            self.terms,
            self.reward,
            self.flags,
            self.terminated,
            0,
            self.n,
        ) + (self._scratch() if self.kernel is _harbour_range else ())

    def _scratch(self) -> tuple:
        """The chart query's scratch arrays, as :func:`harbour_update` allocates them."""
        nb, nh = len(self.beam_dirs), len(self.hull)
        return np.empty(nb), np.empty(nh), np.empty(nh), np.empty((2, nb))

    def info_snapshot(self, k: int) -> tuple:
        # of the features the info reads the goal heading error only (a harbour row holds the range beams too)
        return self.ts[k].tolist(), self.terms[k].tolist(), self.feat.item(k, FEAT.goal_heading_error), self.flags.item(k)

    def info_from(self, snap: tuple) -> dict[str, Any]:
        s, terms, heading_error, f = snap
        success = f == SUCCESS
        return {
            "reward_terms": self.terms_dict(terms),
            "outcome": OUTCOMES[f],
            "success": success,
            "is_success": success,
            **self._state_info(f, s, math.degrees(heading_error)),
        }

    def batch_info(self) -> dict[str, Any]:
        s = self.task_columns()
        f = self.flags
        success = f == SUCCESS
        return {
            "reward_terms": self.batch_weighted_terms(),
            "outcome": np.array(OUTCOMES, dtype=object)[f],
            "success": success,
            "is_success": success.copy(),
            **self._state_info(f, s, np.degrees(self.feat[:, FEAT.goal_heading_error])),
        }

    @staticmethod
    def _state_info(f: Any, s: Any, heading_error_deg: Any) -> dict[str, Any]:
        """The ``info`` entries after the outcome, of one vessel (``f`` its flag, ``s`` its task state as a
        list) or of all (``f`` the flags, ``s`` :meth:`task_columns`)."""
        return {
            "contact": f == CONTACT,
            "grounding": f == GROUNDING,
            "out_of_bounds": f == OUT_OF_BOUNDS,
            "diverged": f == DIVERGED,
            "time_s": s[S.t],
            "clearance_m": s[S.clearance],
            "min_clearance_m": s[S.min_clearance],
            "distance_to_goal_m": s[S.d_prev],
            "speed_over_ground_m_s": s[S.sog],
            "heading_error_deg": heading_error_deg,
            "path_m": s[S.path],
        }

    def overlay(self, k: int) -> dict[str, Any]:
        return {
            "title": f"HarbourApproach: {self.scenario.name}",
            "goal_point_m": self.scenario.goal_point,
            "clearance_m": float(self.ts[k, S.clearance]),
            "outcome": OUTCOMES[int(self.flags[k])],
        }


def make_task(
    cls: type,
    config: Any,
    overrides: Mapping[str, Any],
    n: int,
    task_cls: type | None = None,
) -> HarbourApproachTask:
    """The task of ``cls`` (v0's unless ``task_cls`` says otherwise) from a config and keyword overrides; a
    ``Scenario`` object given as ``scenario`` is used as it is (the config records its path or name)."""
    task_cls = HarbourApproachTask if task_cls is None else task_cls
    over = dict(overrides)
    scenario = over.get("scenario")
    if isinstance(scenario, Scenario):
        over["scenario"] = scenario.path or scenario.name
    else:
        scenario = None
    cfg = make_config(task_cls.Config, config, where=f"{cls.env_name} config", **over)
    return task_cls(cfg, n, scenario=scenario)
