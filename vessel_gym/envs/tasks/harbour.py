"""HarbourApproach: from outside a harbour, through the entrance, to a stop in the goal area.

Its versions are presets of one configuration, registered by :func:`~vessel_gym.envs.registration.register_task`:
``HarbourApproach-v1`` (the L7 model with windage, calm-depth physics), ``HarbourApproach-v2`` (v1 plus the
harbour physics: the cross-flow hull at large drift, default ship ``kvlcc2_l7_harbour``, and the water depth
under each ship read from the scenario's chart, ``chart_depth``) and ``HarbourApproach-v3`` (v2 with the
rudder order lagging the action at a capped rate, :mod:`.harbour_helm`, and rudder changes charged 10x: the
smooth-helm task). This module is the task: its declaration (ids
as presets, configuration, reward weights, pilots, metrics, training defaults), the start of an episode and its
``info``. Its other jobs have their own modules: the columns of its reward terms, features, state and parameters
(:mod:`.harbour_columns`), the compiled step (:mod:`.harbour_kernel`), the chart's geometry and depth
(:mod:`.chart`) and the environment classes with the spec sheet (:class:`.harbour_env.HarbourApproachEnv`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.envs.config import ShipEnvConfig
from vessel_gym.envs.generators import vessel_draws
from vessel_gym.envs.registration import register_task
from vessel_gym.envs.task import Task, _uniform, compiled_call, start_batch, task_config
from vessel_gym.envs.tasks.chart import (
    OK,
    OUTCOMES,
    chart_depth,
    chart_query,
    chart_tables,
    depth_tables,
    poses_clear,
)
from vessel_gym.envs.tasks.harbour_columns import FEAT, SPEC, HarbourArrays, P, S
from vessel_gym.envs.tasks.harbour_helm import LagHelm, cap_rate, lag_gain
from vessel_gym.envs.tasks.harbour_kernel import PARALLEL_MIN_SHIPS, harbour_update, harbour_update_parallel
from vessel_gym.physics.schema import SpecError, param
from vessel_gym.physics.shallow_water import check_hull
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.units import DEG
from vessel_gym.scenarios import Scenario, load_scenario
from vessel_gym.scenarios import geometry as geo
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


#: default control interval as a fraction of the ship's time scale L / U_T (0.99 s for kvlcc2_l7, 6.7 s for the
#: full-scale kvlcc2): about 1/6 of the time the ship needs to sail its own length, short enough for the rudder
#: (15.8 deg/s on the model) to be re-ordered well within a turn, long enough that an episode is ~400 decisions
CONTROL_FRACTION = 1.0 / 6.0
#: default episode time limit in ship time scales L / U_T (590 s for kvlcc2_l7): the harbour pilot
#: (envs.policies.HarbourPilot) needs 45-65 of them on the built-in and generated layouts
TIME_LIMIT_TIME_SCALES = 100.0
#: difficulty levels: where episodes start (level 3 is the scenario's own [start] region)
DIFFICULTIES = ("basin", "entrance", "approach", "open")
#: levels 0-2: fraction of the track length (start region centroid -> route_m -> goal point) still to go
TRACK_FRACTION = (0.25, 0.45, 0.7)
#: levels 0-2: spread of the start about its track point: along track (fraction of the track length),
#: across track (ship lengths), heading about the track direction (deg)
ALONG_SPREAD, ACROSS_SPREAD_L, HEADING_SPREAD_DEG = 0.05, 0.5, 10.0
#: levels 0-2: start speed through the water, fraction of the speed the reward allows at that distance
START_SPEED_FRACTION = (0.5, 0.9)


HarbourApproachReward = SPEC.weights_class(
    "HarbourApproachReward",
    __name__,
    "Weights of the HarbourApproach reward terms (reward = sum of weight x term); ``time`` is charged per ship "
    "time scale.",
)


@dataclass(frozen=True, kw_only=True)
class HarbourApproachConfig(ShipEnvConfig):
    """HarbourApproach configuration (see :class:`~vessel_gym.envs.tasks.harbour_env.HarbourApproachEnv`); its
    defaults are HarbourApproach-v2, the preset ``HarbourApproach-v1`` sets ``ship`` and ``chart_depth``."""

    scenario: str = param("harbour", doc="built-in scenario name or scenario file path")
    ship: str | None = param(
        "kvlcc2_l7_harbour",
        doc="ship name or file (default: the L7 model with its estimated windage and the cross-flow hull at large "
        "drift; MMG hull with chart_depth; None: the scenario's ship)",
    )
    chart_depth: bool = param(
        True,
        doc="the physics sees the charted depth under each ship (shallow-water corrections of the MMG hull)",
    )
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
    control_interval_s: float | None = param(  # type: ignore[assignment]
        None,
        unit="s",
        lo=1e-4,
        hi=600.0,
        doc="time between actions (default: L / U_T / 6 of the ship, rounded to 2 digits: 0.99 s for kvlcc2_l7)",
    )
    time_limit_s: float | None = param(
        None, unit="s", lo=1.0, hi=1e6, doc="episode time limit (default: 100 L / U_T, 590 s for kvlcc2_l7)"
    )
    difficulty: int = param(
        3,
        unit="-",
        lo=0,
        hi=len(DIFFICULTIES) - 1,
        doc="start region: 0 basin (inside the entrance), 1 entrance, 2 approach, 3 open (the scenario's [start])",
    )
    layout: str = param(
        "scenario", choices=("scenario", "procedural"), doc="chart: the scenario file, or a generated harbour"
    )
    layout_split: str = param(
        "train", choices=("train", "eval"), doc="procedural: seed range of the layout (eval: held out)"
    )
    layout_index: int = param(0, unit="-", lo=0, hi=99_999, doc="procedural: which layout of the split")
    rudder_action: str = param(
        "order",
        choices=("order", "lag"),
        doc="continuous helm: action[0] is the rudder order (order), or the rudder asked for, which the order "
        "follows as a first-order lag (rudder_lag_time_scales) capped at rudder_rate_fraction of the gear's rate",
    )
    rudder_lag_time_scales: float = param(
        1.0, unit="L/U_T", lo=0.01, hi=100.0, doc="lag: time constant of the order's lag behind the action"
    )
    rudder_rate_fraction: float = param(
        1.0,
        unit="-",
        lo=0.01,
        hi=1.0,
        doc="lag: the order changes at most at this fraction of the steering gear's max rate",
    )
    # sensor noise (robustness studies; 0: exact sensors, every registered version): white Gaussian errors, drawn
    # afresh each control step, in what the observation reports; the physics, reward, outcome and info keep the truth
    position_noise_m: float = param(
        0.0,
        unit="m",
        lo=0.0,
        hi=1e4,
        doc="sensor noise: standard deviation of the position fix per axis (north, east); goal_x, goal_y and "
        "goal_distance are observed from the noisy fix",
    )
    heading_noise_deg: float = param(
        0.0,
        unit="deg",
        lo=0.0,
        hi=180.0,
        doc="sensor noise: standard deviation of the compass heading; goal_heading_error and the body axes of "
        "goal_x, goal_y are the noisy heading's",
    )
    speed_noise_m_s: float = param(
        0.0,
        unit="m/s",
        lo=0.0,
        hi=100.0,
        doc="sensor noise: standard deviation of the speed log (u) and of the speed over ground (sog), each its "
        "own draw",
    )
    reward: HarbourApproachReward = param(HarbourApproachReward(), doc="reward weights")


# --- the task ---------------------------------------------------------------------------------------------------
def _round2(x: float) -> float:
    """``x`` rounded to 2 significant digits."""
    return float(f"{x:.2g}")


def difficulty_level(level: int | str) -> int:
    """A difficulty as an index 0..3 from an index or a name of DIFFICULTIES; raises ValueError otherwise."""
    if isinstance(level, str) and level in DIFFICULTIES:
        return DIFFICULTIES.index(level)
    if (
        isinstance(level, (int, np.integer))
        and not isinstance(level, bool)
        and 0 <= level < len(DIFFICULTIES)
    ):
        return int(level)
    raise ValueError(
        f"difficulty: expected 0..{len(DIFFICULTIES) - 1} or one of {DIFFICULTIES}, got {level!r}"
    )


def own_ship(scenario: Scenario) -> dict[str, Any]:
    """Config values that sail ``scenario`` with its own ship and the chart's depth where that ship's hull has
    the shallow-water corrections (an MMG hull; any other sails in deep water)."""
    ship = scenario.load_ship()
    try:
        check_hull(ship, scenario.water_depth_m)
    except ValueError:
        return {"ship": ship.path or ship.name, "chart_depth": False}
    return {"ship": ship.path or ship.name, "chart_depth": True}


# --- capabilities: the classical pilots and the episode metrics ------------------------------------------------
def nomoto_pilot(env: Any, omega_n_UL: float = 0.6, zeta: float = 0.9, **pilot: float) -> Any:
    """The harbour pilot (:class:`~vessel_gym.envs.policies.HarbourPilot`) with heading gains from the ship's
    Nomoto model at ``omega_n_UL`` U/L and ``zeta``, and its other arguments ``pilot`` (the defaults: the
    untuned design)."""
    from vessel_gym.envs.policies import HarbourPilot
    from vessel_gym.policy import nomoto_pid_kwargs

    return HarbourPilot(env, **nomoto_pid_kwargs(env, omega_n_UL, zeta), **pilot)


def pid_pilot(env: Any) -> Any:
    """:func:`nomoto_pilot` with the parameters tuned for the id (:func:`vessel_gym.policy.pilot_gains`)."""
    from vessel_gym.policy import pilot_gains

    return nomoto_pilot(env, **pilot_gains(env, "pid"))


def rule_pilot(env: Any) -> Any:
    """The harbour pilot with its default gains."""
    from vessel_gym.envs.policies import HarbourPilot

    return HarbourPilot(env)


def episode_metrics(infos: list[Mapping[str, Any]], terminated: bool) -> dict[str, Any]:
    """``success``, ``outcome`` (``timeout`` when truncated), ``min_clearance_m``, ``time_s``."""
    last = infos[-1]
    return {
        "success": bool(last["success"]),
        "outcome": str(last["outcome"]) if terminated else "timeout",
        "min_clearance_m": float(last["min_clearance_m"]),
        "time_s": float(last["time_s"]),
    }


# The time limit is the task's own (time_limit_s, from the ship's time scale): no step count is registered.
@register_task(
    presets={
        "HarbourApproach-v1": {"ship": "kvlcc2_l7_windage", "chart_depth": False},
        "HarbourApproach-v2": {},
        # the smooth-helm task: the rudder order follows the action with a lag of one ship time scale, at most
        # a quarter of the gear's rate (3.9 deg/s on kvlcc2_l7), and a change of order costs 10x v2's
        # (docs/agents.md, "HarbourApproach-v3: the smooth helm")
        "HarbourApproach-v3": {
            "rudder_action": "lag",
            "rudder_lag_time_scales": 1.0,
            "rudder_rate_fraction": 0.25,
            "reward": {"rudder_activity": 0.5},
        },
    },
    max_episode_steps=None,
    env="vessel_gym.envs.tasks.harbour_env:HarbourApproachEnv",
    pilots={"pid": pid_pilot, "pid-nomoto": nomoto_pilot, "scripted": rule_pilot},
    metrics=episode_metrics,
    train={
        # PPO as the shipped HarbourApproach-v1 agents were trained (agents/hyperparams/ppo.yml, docs/results.md)
        "ppo": {
            "n_steps": 256,
            "batch_size": 1024,
            "n_epochs": 5,
            "gamma": 0.995,
            "gae_lambda": 0.95,
            "learning_rate": 3e-4,
            "clip_range": 0.2,
            "ent_coef": 0.0,
            "use_sde": True,
            "sde_sample_freq": 8,
            "policy_kwargs": {"net_arch": [128, 128], "activation_fn": "tanh", "log_std_init": -1.0},
        },
    },
)
class HarbourApproachTask(Task):
    Config = HarbourApproachConfig
    spec = SPEC
    Arrays = HarbourArrays
    kernel = staticmethod(harbour_update)

    @classmethod
    def from_config(cls, config: Any, overrides: Mapping[str, Any], n: int) -> HarbourApproachTask:
        """As :meth:`Task.from_config`; a ``Scenario`` object given as ``scenario`` is used as it is (the config
        records its path or name)."""
        over = dict(overrides)
        preset = over.pop("preset", None)
        scenario = over.get("scenario")
        if isinstance(scenario, Scenario):
            over["scenario"] = scenario.path or scenario.name
        else:
            scenario = None
        task = cls(task_config(cls, config, over, preset), n, scenario=scenario)
        task.preset = preset
        return task

    def __init__(self, config: HarbourApproachConfig, n: int, scenario: Scenario | None = None) -> None:
        if scenario is None and config.layout == "procedural":
            from vessel_gym.scenarios.generator import generate_harbour, split_seed

            seed = split_seed(config.layout_split, config.layout_index)
            scenario = generate_harbour(seed, config.ship if config.ship is not None else "kvlcc2_l7")
        if scenario is None and "\x00" in config.scenario:  # the OS refuses it, with a message of its own
            raise SpecError(
                f"HarbourApproach config scenario: {config.scenario!r} contains U+0000, which no file name holds"
            )
        sc = scenario if scenario is not None else load_scenario(config.scenario)
        ship = load_ship(config.ship if config.ship is not None else sc.load_ship())
        time_scale = ship.particulars.L_m / ship.test_speed_m_s  # s
        ci = config.control_interval_s
        if ci is None:
            ci = _round2(CONTROL_FRACTION * time_scale)
        tl = (
            config.time_limit_s
            if config.time_limit_s is not None
            else _round2(TIME_LIMIT_TIME_SCALES * time_scale)
        )
        config = dataclasses.replace(config, control_interval_s=ci, time_limit_s=tl)
        if config.rudder_action == "lag" and config.action_type != "continuous":
            raise SpecError(
                'HarbourApproach config rudder_action: "lag" smooths the order of a continuous helm; '
                'action_type="discrete" orders fixed helm angles (choose rudder_action="order")'
            )
        self.scenario = sc
        ship_named = config.ship if config.ship is not None else sc.load_ship()
        angles = np.arange(config.n_beams) * (2.0 * math.pi / max(config.n_beams, 1))
        self.beam_dirs = np.stack([np.cos(angles), np.sin(angles)], axis=1).reshape(-1, 2)  # body-axis units
        super().__init__(
            config,
            n,
            ship=ship_named,
            reference_latlon_deg=(sc.reference_latlon_deg[0], sc.reference_latlon_deg[1]),
            shallow_water=bool(config.chart_depth),  # one kind of kernel for the chart's depths (Simulation)
        )
        T = self.ship.particulars.T_m
        polys = [(1, pts) for _kind, _name, pts in sc.hard_obstacles()] + [
            (2, pts) for _n, pts in sc.shoals(T)
        ]
        self.edges, self.polys, self.pbox = chart_tables(polys)
        if config.rudder_action == "lag":
            gain = lag_gain(ci, config.rudder_lag_time_scales * time_scale)
            self.helm = LagHelm(config, self.sim, gain, cap_rate(config.rudder_rate_fraction, self.sim), ci)
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
        if n >= PARALLEL_MIN_SHIPS:
            self.kernel = harbour_update_parallel
        #: sensor noise standard deviations (m, rad, m/s); all zero: the observation is the kernel's, untouched
        self.noise_sd = np.array(
            [config.position_noise_m, config.heading_noise_deg * DEG, config.speed_noise_m_s], dtype=np.float64
        )
        #: the noise's generator, seeded by each reset's draws (so an episode's noise follows its reset seed)
        self.noise_rng = np.random.default_rng(0)
        self.beams, self.hn, self.he, self.bw = self._scratch()  # the serial kernel's, made once
        #: steps per episode before truncation (time limit / control interval, rounded up)
        self.max_steps = math.ceil(tl / ci - 1e-9)
        # the time term is -1 per step in the kernel; charged per ship time scale here
        self.weights[self.term_names.index("time")] *= ci / time_scale
        self.difficulty = config.difficulty
        track = [geo.centroid([(p[0], p[1]) for p in sc.start.points])]
        track += [(p[0], p[1]) for p in sc.route_m] + [sc.goal_point]
        self.track = np.array(track, dtype=np.float64)
        seg = np.hypot(*np.diff(self.track, axis=0).T)
        self.track_s = np.concatenate([[0.0], np.cumsum(seg)])  # arc length from the start centroid, m
        #: the physics sees the charted depth under each ship (a pilot policy adapts to it: envs.policies)
        self.depth_from_chart = bool(config.chart_depth)
        #: charted depth under each ship's midship point (m), as the physics sees it from the next control
        #: step on (before the clamp to 1.2 T; the scenario's water depth without chart_depth)
        self.depth_m = np.full(n, float(self.scenario.water_depth_m))
        self._depth_call: tuple | None = None  # chart_depth's compiled code and its arguments, bound once
        if self.depth_from_chart:
            try:  # the chart's depth is finite: the ship's hull must be one the corrections are for
                check_hull(self.ship, self.scenario.water_depth_m)
            except ValueError:
                raise SpecError(
                    f"HarbourApproach config ship: {self.ship.name!r} has a "
                    f"{self.ship.hull.model!r} hull; chart_depth applies the chart's depth through the shallow-water "
                    "corrections of the MMG hull (Taimuri et al. 2020): choose an MMG ship (default "
                    "kvlcc2_l7_harbour), chart_depth=False or HarbourApproach-v1"
                ) from None
            self.depth_verts, self.depth_areas, self.depth_area = depth_tables(self.scenario)
            self._draught = float(self.ship.particulars.T_m)

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
        """The hull at this pose is clear of the chart (:func:`chart_query` with fresh scratch arrays)."""
        tables = (self.hull, self.edges, self.polys, self.pbox, self.beam_dirs, self.beam_range)
        flag, _c = chart_query(n, e, psi, *tables, *self._scratch())
        return flag == OK

    def open_start_poses(self, idx: np.ndarray, rng: Any) -> tuple[Any, Any, Any, Any]:
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

    def set_difficulty(self, level: int | str) -> None:
        """Start region of the episodes reset from now on (0 basin .. 3 open, or a name of DIFFICULTIES)."""
        self.difficulty = difficulty_level(level)

    def _track_point(self, s: float) -> tuple[float, float, float]:
        """(north, east, direction rad) of the track at arc length ``s``."""
        i = int(np.clip(np.searchsorted(self.track_s, s) - 1, 0, len(self.track) - 2))
        a, b = self.track[i], self.track[i + 1]
        f = (s - self.track_s[i]) / max(self.track_s[i + 1] - self.track_s[i], 1e-9)
        d = b - a
        return float(a[0] + f * d[0]), float(a[1] + f * d[1]), math.atan2(d[1], d[0])

    def start_poses(self, idx: np.ndarray, rng: Any) -> tuple[Any, Any, Any, Any]:
        if self.difficulty >= len(TRACK_FRACTION):  # the open region: the scenario's [start]
            return self.open_start_poses(idx, rng)
        poses = [self.start_pose(vessel_draws(rng, j)) for j in range(len(idx))]
        n0, e0, heading, speed = (np.array(c, dtype=float) for c in zip(*poses))
        return n0, e0, heading, speed

    def start_pose(self, rng: Any) -> tuple[float, float, float, float]:
        """(north, east, heading deg, speed) of one vessel's start on the track at this difficulty (``rng``: its
        numpy Generator or :class:`~vessel_gym.envs.generators.OneVessel` draws)."""
        total = float(self.track_s[-1])
        to_go = TRACK_FRACTION[self.difficulty]
        for tries in range(1000):
            spread = 0.0 if tries >= 900 else 1.0  # last resort: on the track itself
            s = total * (1.0 - to_go + spread * rng.uniform(-ALONG_SPREAD, ALONG_SPREAD))
            n0, e0, chi = self._track_point(min(max(s, 0.0), total))
            off = spread * rng.uniform(-ACROSS_SPREAD_L, ACROSS_SPREAD_L) * self.L
            n0, e0 = n0 - off * math.sin(chi), e0 + off * math.cos(chi)
            heading = math.degrees(chi) + spread * rng.uniform(-HEADING_SPREAD_DEG, HEADING_SPREAD_DEG)
            if self._pose_clear(n0, e0, heading * DEG):
                break
        else:  # pragma: no cover - validated scenarios have a clear track
            raise RuntimeError(
                f"{self.scenario.path or self.scenario.name}: no clear start pose on the track"
            )
        dist = math.hypot(self.p[P.goal_north] - n0, self.p[P.goal_east] - e0)
        allowed = max(self.p[P.goal_max_speed], self.U_T * min(1.0, dist / self.p[P.slow_distance]))
        speed = allowed * rng.uniform(*START_SPEED_FRACTION)
        return n0, e0, heading, speed

    def update(self, phase: np.ndarray) -> None:
        """The task update, then (``chart_depth``) the depth under every ship for the next control step (:func:`chart_depth`:
        one compiled call over all vessels).

        The depth is read once per control step, not in every physics step within it: over one
        control step (L / U_T / 6: 0.99 s on kvlcc2_l7) the ship moves about a sixth of its length, while the
        shallow-water corrections already take the depth at the midship point for the whole hull, and the
        chart's depth areas change by steps at their edges: a reading per physics step would move where a
        step in depth takes effect by at most a sixth of a ship length."""
        super().update(phase)
        if self.noise_sd.any():
            self.sense(phase)
        if not self.depth_from_chart:
            return
        call = self._depth_call
        if call is None:
            sim = self.sim
            # views of the simulation's state: the simulation keeps its arrays (and the task kernel binds them)
            args = (
                sim.north,
                sim.east,
                self.depth_verts,
                self.depth_areas,
                self.depth_area,
                float(self.scenario.water_depth_m),
                self._draught,
                self.depth_m,
                sim.env,
            )
            chart_depth(*args)  # compiles, or loads from the cache, the lookup for these arguments
            self._depth_call = compiled_call(chart_depth, args)
            return
        call[0](*call[1])

    def sense(self, phase: np.ndarray) -> None:
        """The observations of the vessels in ``phase`` as noisy sensors report them (config ``position_noise_m``,
        ``heading_noise_deg``, ``speed_noise_m_s``): the true features (``feat``, kept) with a position fix,
        compass heading and speeds off by fresh Gaussian errors, encoded as the kernel encodes
        (:func:`~vessel_gym.envs.tasks.common.encode_row`) into the observation columns they feed."""
        idx = np.flatnonzero(phase)
        if not len(idx):
            return
        f = self.feat[idx]
        sd_pos, sd_psi, sd_speed = self.noise_sd
        z = self.noise_rng.standard_normal((5, len(idx)))
        goal_heading = self.p[P.goal_heading]
        psi = goal_heading - f[:, FEAT.goal_heading_error]  # the true heading (mod 2 pi)
        c, s = np.cos(psi), np.sin(psi)
        gx, gy = f[:, FEAT.goal_x], f[:, FEAT.goal_y]
        # goal point minus the noisy fix, in earth axes
        gn = c * gx - s * gy - sd_pos * z[0]
        ge = s * gx + c * gy - sd_pos * z[1]
        psi_hat = psi + sd_psi * z[2]
        ch, sh = np.cos(psi_hat), np.sin(psi_hat)
        sensed = {
            FEAT.goal_x: ch * gn + sh * ge,
            FEAT.goal_y: -sh * gn + ch * ge,
            FEAT.goal_distance: np.hypot(gn, ge),
            FEAT.goal_heading_error: (goal_heading - psi_hat + math.pi) % (2.0 * math.pi) - math.pi,
            FEAT.sog: np.abs(f[:, FEAT.sog] + sd_speed * z[3]),  # a speed over ground has no sign
            FEAT.u: f[:, FEAT.u] + sd_speed * z[4],
        }
        enc = self.enc
        for j in np.flatnonzero(np.isin(enc[:, 0].astype(np.int64), list(sensed))).tolist():
            x = np.nan_to_num(sensed[int(enc[j, 0])], nan=0.0, posinf=0.0, neginf=0.0)
            sc = enc[j, 1]
            self.obs[idx, j] = np.clip(x / sc, -1.0, 1.0) if enc[j, 2] > 0.0 else np.clip(x, -sc, sc)

    def __getstate__(self) -> dict:
        state = super().__getstate__()
        state["_depth_call"] = None  # compiled code does not pickle; a copy binds its own at its first update
        return state

    def reset_vessel(self, k: int, rng: np.random.Generator, options: Mapping | None) -> None:
        self.reset_batch(np.array([k]), rng, options)

    def reset_batch(self, idx: np.ndarray, rng: Any, options: Mapping | None) -> None:
        # each draw gives one number per vessel of idx, in the order a lone reset draws them
        opts = dict(options or {})
        n0, e0, heading, speed = self.start_poses(idx, rng)
        w = self.scenario.weather
        weather = {key: _uniform(rng, getattr(w, key)) for key in WEATHER_DRAWS}
        if self.noise_sd.any():  # one more draw only with noise: without, every reset draws what it always did
            words = np.atleast_1d(rng.uniform(0.0, 2.0**32)).astype(np.uint64)
            self.noise_rng = np.random.default_rng(words.tolist())
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
        start_batch(self, idx, speed, heading, n0, e0)

    def started(self, k: int | np.ndarray) -> None:
        self.ts[k, S.prev_order] = self.sim.rudder_order[k]

    def _scratch(self) -> tuple:
        """The chart query's scratch arrays, as :func:`harbour_update` allocates them."""
        nb, nh = len(self.beam_dirs), len(self.hull)
        return np.empty(nb), np.empty(nh), np.empty(nh), np.empty((2, nb))

    def overlay(self, k: int) -> dict[str, Any]:
        return {
            "title": f"HarbourApproach: {self.scenario.name}",
            "goal_point_m": self.scenario.goal_point,
            "clearance_m": float(self.ts[k, S.clearance]),
            "outcome": OUTCOMES[int(self.flags[k])],
        }
