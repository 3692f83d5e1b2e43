"""HarbourApproach: from outside a harbour, through the entrance, to a stop in the goal area."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.envs import kernels as kn
from vessel_gym.envs.config import ShipEnvConfig, make_config, weight
from vessel_gym.envs.core import Feature, ShipEnv, ShipVectorEnv, Task, _uniform
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.schema import param
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.units import DEG
from vessel_gym.scenarios import Scenario, load_scenario
from vessel_gym.scenarios import geometry as geo
from vessel_gym.scenarios.geometry import hull_outline


@dataclass(frozen=True, kw_only=True)
class HarbourApproachReward:
    """Weights of the HarbourApproach reward terms (reward = sum of weight x term)."""

    progress: float = weight(1.0, "decrease of the distance to the goal point / L")
    speed_excess: float = weight(1.0, "-(SOG above the allowed speed) / U_T")
    proximity: float = weight(0.5, "-(1 - clearance / safe clearance) when closer")
    rudder_activity: float = weight(0.05, "-|change of rudder order| / (2 rudder limit)")
    time: float = weight(0.01, "-1 per step")
    success: float = weight(20.0, "+1 on arrival")
    collision: float = weight(20.0, "-1 on contact, grounding or divergence")
    out_of_bounds: float = weight(20.0, "-1 on leaving the chart")


@dataclass(frozen=True, kw_only=True)
class HarbourApproachConfig(ShipEnvConfig):
    """HarbourApproach-v0 configuration (see :class:`HarbourApproachEnv`)."""

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


# batches from this size run the task kernel on all threads (about 0.6 us of work per ship; waking the threads
# costs tens of microseconds on an idle machine)
PARALLEL_MIN_SHIPS = 256


class HarbourApproachTask(Task):
    Config = HarbourApproachConfig
    kernel = staticmethod(kn.harbour_update)

    def __init__(self, config: HarbourApproachConfig, n: int, scenario: Scenario | None = None) -> None:
        self.scenario = scenario if scenario is not None else load_scenario(config.scenario)
        sc = self.scenario
        ship = config.ship if config.ship is not None else sc.load_ship()
        self.n_features = kn.HFN0 + config.n_beams
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
        self.edges, self.polys, self.pbox = kn.chart_tables(polys)
        self.hull = np.array(hull_outline(self.L, self.ship.particulars.B_m), dtype=np.float64)
        self.goal_verts = np.array([(p[0], p[1]) for p in sc.goal.points], dtype=np.float64)
        self.ts = np.zeros((n, kn.HSN))
        self.flags = np.zeros(n, dtype=np.int64)
        gn, ge = sc.goal_point
        p = np.zeros(kn.HPN)
        p[kn.HP_L] = self.L
        p[kn.HP_DMAX] = getattr(self.helm, "rudder_limit_rad", np.array([self.delta_max]))[0]
        p[kn.HP_DT] = config.control_interval_s
        p[kn.HP_BEAM_RANGE] = self.beam_range
        p[kn.HP_GOAL_N], p[kn.HP_GOAL_E] = gn, ge
        p[kn.HP_GOAL_HDG] = sc.goal.heading_deg * DEG
        p[kn.HP_GOAL_TOL] = sc.goal.heading_tolerance_deg * DEG
        p[kn.HP_GOAL_VMAX] = sc.goal.max_speed_m_s
        p[kn.HP_UT] = self.U_T
        p[kn.HP_SLOW_DIST] = config.slow_down_L * self.L
        p[kn.HP_CLEAR_REF] = config.safe_clearance_L * self.L
        p[kn.HP_N_MIN], p[kn.HP_N_MAX], p[kn.HP_E_MIN], p[kn.HP_E_MAX] = sc.bounds_m
        self.p = p
        self._beams = np.empty(config.n_beams)
        if n >= PARALLEL_MIN_SHIPS:
            self.kernel = kn.harbour_update_parallel

    @property
    def beam_range(self) -> float:
        return self.config.beam_range_L * self.L

    def observation_features(self) -> list[Feature]:
        U, sc = self.U_T, self.scenario
        n0, n1, e0, e1 = sc.bounds_m
        R = math.hypot(n1 - n0, e1 - e0)
        w = sc.weather
        wind = max(w.wind_speed_m_s[1], 1.0) + 2.0 * U
        cur = max(w.current_speed_m_s[1], 0.1 * U)
        rev = 1.5 * self.rev_full
        f = self.motion_observation(rev=True) + [
            Feature("rev_order", "rev/s", rev, "shaft-speed order", kn.HF_REV_C),
            Feature("goal_x", "m", R, "goal point ahead of midship (body x)", kn.HF_GOAL_X),
            Feature("goal_y", "m", R, "goal point to starboard of midship (body y)", kn.HF_GOAL_Y),
            Feature("goal_distance", "m", R, "distance to the goal point", kn.HF_GOAL_DIST),
            Feature(
                "goal_heading_error", "rad", math.pi, "goal heading - heading, wrapped", kn.HF_GOAL_HDG_ERR
            ),
            Feature("sog", "m/s", 1.5 * U, "speed over ground", kn.HF_SOG),
            Feature("wind_speed", "m/s", wind, "apparent wind speed (anemometer)", kn.HF_WIND_SPEED),
            Feature(
                "wind_angle_sin",
                "-",
                1.0,
                "sin of apparent wind angle from the bow (+ from starboard)",
                kn.HF_WIND_SIN,
            ),
            Feature("wind_angle_cos", "-", 1.0, "cos of apparent wind angle", kn.HF_WIND_COS),
            Feature("current_x", "m/s", cur, "current along the body x axis (GNSS minus log)", kn.HF_CUR_X),
            Feature("current_y", "m/s", cur, "current along the body y axis", kn.HF_CUR_Y),
        ]
        for j in range(self.config.n_beams):
            f.append(
                Feature(
                    f"beam_{j}",
                    "m",
                    self.beam_range,
                    f"free range at {360.0 * j / self.config.n_beams:g} deg clockwise from the bow",
                    kn.HFN0 + j,
                )
            )
        return f

    def _pose_clear(self, n: float, e: float, psi: float) -> bool:
        flag, _c = kn.chart_query(
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
        return flag == kn.OK

    def start_pose(self, rng: np.random.Generator) -> tuple[float, float, float, float]:
        """(north, east, heading deg, speed) of a start: uniform in the scenario's ``[start]`` region."""
        sc = self.scenario
        st = sc.start
        pts = np.array([(p[0], p[1]) for p in st.points])
        lo_, hi_ = pts.min(axis=0), pts.max(axis=0)
        for _ in range(1000):
            n0 = float(rng.uniform(lo_[0], hi_[0]))
            e0 = float(rng.uniform(lo_[1], hi_[1]))
            heading = _uniform(rng, st.heading_deg)
            if kn._inside(n0, e0, pts[:, 0], pts[:, 1], 0, len(pts)) and self._pose_clear(
                n0, e0, heading * DEG
            ):
                break
        else:  # pragma: no cover - validated scenarios have room
            raise RuntimeError(f"{sc.path or sc.name}: no clear start pose found in [start] points")
        return n0, e0, heading, _uniform(rng, st.speed_m_s)

    def reset_vessel(self, k: int, rng: np.random.Generator, options: Mapping | None) -> None:
        opts = dict(options or {})
        n0, e0, heading, speed = self.start_pose(rng)
        w = self.scenario.weather
        env = Environment(
            wind_speed_m_s=_uniform(rng, w.wind_speed_m_s),
            wind_from_deg=_uniform(rng, w.wind_from_deg),
            current_speed_m_s=_uniform(rng, w.current_speed_m_s),
            current_to_deg=_uniform(rng, w.current_to_deg),
            Hs_m=_uniform(rng, w.Hs_m),
            Tp_s=_uniform(rng, w.Tp_s),
            wave_from_deg=_uniform(rng, w.wave_from_deg),
        )
        n0 = float(opts.pop("north_m", n0))
        e0 = float(opts.pop("east_m", e0))
        heading = float(opts.pop("heading_deg", heading))
        speed = float(opts.pop("speed_m_s", speed))
        if "environment" in opts:
            env = opts.pop("environment")
        if opts:
            raise ValueError(
                f"unknown reset option(s) {sorted(opts)} (allowed: north_m, east_m, heading_deg, "
                "speed_m_s, environment)"
            )
        self.sim.set_environment(env, k)
        self.sim.reset(speed_m_s=speed, heading_deg=heading, x_m=n0, y_m=e0, k=k)
        s = self.ts[k]
        s[:] = 0.0
        s[kn.HS_D_PREV] = math.hypot(self.p[kn.HP_GOAL_N] - n0, self.p[kn.HP_GOAL_E] - e0)
        s[kn.HS_PREV_N], s[kn.HS_PREV_E] = n0, e0
        s[kn.HS_PREV_ORDER] = float(self.sim.rudder_order[k])
        self.flags[k] = kn.OK

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
        )

    def info(self, k: int) -> dict[str, Any]:
        s = self.ts[k].tolist()
        f = int(self.flags[k])
        success = f == kn.SUCCESS
        return {
            "reward_terms": self.weighted_terms(k),
            "outcome": kn.OUTCOMES[f],
            "success": success,
            "is_success": success,
            "contact": f == kn.CONTACT,
            "grounding": f == kn.GROUNDING,
            "out_of_bounds": f == kn.OUT_OF_BOUNDS,
            "diverged": f == kn.DIVERGED,
            "time_s": s[kn.HS_T],
            "clearance_m": s[kn.HS_CLEAR],
            "min_clearance_m": s[kn.HS_MIN_CLEAR],
            "distance_to_goal_m": s[kn.HS_D_PREV],
            "speed_over_ground_m_s": s[kn.HS_SOG],
            "heading_error_deg": math.degrees(self.feat[k, kn.HF_GOAL_HDG_ERR]),
            "path_m": s[kn.HS_PATH],
        }

    def batch_info(self) -> dict[str, Any]:
        s = self.task_columns()
        f = self.flags
        success = f == kn.SUCCESS
        return {
            "reward_terms": self.batch_weighted_terms(),
            "outcome": np.array(kn.OUTCOMES, dtype=object)[f],
            "success": success,
            "is_success": success.copy(),
            "contact": f == kn.CONTACT,
            "grounding": f == kn.GROUNDING,
            "out_of_bounds": f == kn.OUT_OF_BOUNDS,
            "diverged": f == kn.DIVERGED,
            "time_s": s[kn.HS_T],
            "clearance_m": s[kn.HS_CLEAR],
            "min_clearance_m": s[kn.HS_MIN_CLEAR],
            "distance_to_goal_m": s[kn.HS_D_PREV],
            "speed_over_ground_m_s": s[kn.HS_SOG],
            "heading_error_deg": np.degrees(self.feat[:, kn.HF_GOAL_HDG_ERR]),
            "path_m": s[kn.HS_PATH],
        }

    def overlay(self, k: int) -> dict[str, Any]:
        return {
            "title": f"HarbourApproach: {self.scenario.name}",
            "goal_point_m": self.scenario.goal_point,
            "clearance_m": float(self.ts[k, kn.HS_CLEAR]),
            "outcome": kn.OUTCOMES[int(self.flags[k])],
        }


def _make_task(
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


class HarbourApproachEnv(ShipEnv):
    """Bring a ship from outside a harbour through the entrance to a stop in the goal area.

    ## Description

    The ship starts at a random pose and speed in the scenario's start region, under wind and current drawn
    from the scenario's ranges. The agent gives rudder and engine orders and must pass the breakwater
    entrance and stop in the goal area (berth or turning basin) with the required heading, without touching
    land, breakwaters or quays and without grounding on depth areas shallower than the ship's draught. The
    chart, start and goal regions, ship and weather come from a scenario file (:mod:`vessel_gym.scenarios`;
    built-in ``harbour``: a harbour sized for the 7 m ``kvlcc2_l7`` model, 17 m entrance, a pier and a shoal
    inside, turning basin in front of the north quay).

    Physics step 0.25 s (chosen from the ship, docs/envs.md), control interval 0.25 s.

    ## Action Space

    ``Box(-1, 1, (2,), float32)`` (default ``action_type="continuous"``, ``engine_control=True``):

    | Num | Action | Mapping |
    |-----|--------|---------|
    | 0 | rudder order | x rudder limit (35 deg), + starboard |
    | 1 | engine order | x full-ahead rpm (a > 0) / x full-astern rpm (a < 0) of the telegraph table |

    Clipped to [-1, 1]; NaN raises ``ValueError``. ``action_type="discrete"``: ``MultiDiscrete([helm orders,
    telegraph steps])``, e.g. "port 20 / midships / starboard 10" x "half astern ... full ahead" from
    ``rudder_orders_deg`` and ``telegraph_steps``; out-of-range indices raise.

    ## Observation Space

    ``Box(-1, 1, (17 + n_beams,), float32)`` normalized (value / scale, clipped) or ``"physical"`` (SI,
    clipped to +-scale). U_T test speed, L ship length, R chart diagonal.

    | Num | Name | Unit | Scale | Meaning |
    |-----|------|------|-------|---------|
    | 0 | u | m/s | 1.5 U_T | surge velocity through the water |
    | 1 | v | m/s | 0.5 U_T | sway velocity (+ starboard) |
    | 2 | r | rad/s | 2 U_T / L | rate of turn (+ starboard) |
    | 3 | rudder | rad | rudder max | actual rudder angle |
    | 4 | rudder_order | rad | rudder max | rudder order |
    | 5 | rev | rev/s | 1.5 full rpm | shaft speed (tachometer) |
    | 6 | rev_order | rev/s | 1.5 full rpm | shaft-speed order |
    | 7 | goal_x | m | R | goal point ahead of midship (body frame) |
    | 8 | goal_y | m | R | goal point to starboard (body frame) |
    | 9 | goal_distance | m | R | distance to the goal point |
    | 10 | goal_heading_error | rad | pi | required heading - heading |
    | 11 | sog | m/s | 1.5 U_T | speed over ground |
    | 12 | wind_speed | m/s | wind max + 2 U_T | apparent wind speed (anemometer) |
    | 13-14 | wind_angle_sin, _cos | - | 1 | apparent wind angle from the bow (+ from starboard) |
    | 15-16 | current_x, current_y | m/s | 1.5 current max | current in body axes (GNSS velocity - log) |
    | 17.. | beam_j | m | beam_range_L x L | free range from midship, beam j at 360 j / n_beams deg from the bow |

    Range beams see land, breakwaters, quays and depth areas shallower than the draught.

    ## Rewards

    reward = sum of weight x term (config ``reward``); weighted terms in ``info["reward_terms"]``.

    | Term | Default weight | Value per step |
    |------|----------------|----------------|
    | progress | 1.0 | (previous - current distance to the goal point) / L |
    | speed_excess | 1.0 | -max(0, SOG - allowed) / U_T; allowed falls from U_T to the goal speed within slow_down_L |
    | proximity | 0.5 | -(1 - clearance / (safe_clearance_L L)) when the hull is closer than that to an obstacle |
    | rudder_activity | 0.05 | -abs(change of rudder order) / (2 x rudder limit) |
    | time | 0.01 | -1 |
    | success | 20.0 | +1 on arrival |
    | collision | 20.0 | -1 on contact, grounding or divergence |
    | out_of_bounds | 20.0 | -1 on leaving the chart bounds |

    ## Starting State

    Midship point uniform in the scenario's ``[start] points`` (poses whose hull would touch an obstacle are
    drawn again), heading and speed uniform in its ranges, steady approach (rpm solved), rudder amidships;
    wind, current and waves uniform in ``[weather]``.

    ## Episode End

    * Termination, success: midship inside the goal polygon, speed over ground <= goal ``max_speed_m_s``,
      heading within ``heading_tolerance_deg`` of the goal heading.
    * Termination, failure: hull outline touching land, breakwater or quay (``info["contact"]``), or a depth
      area shallower than the draught (``info["grounding"]``); midship outside ``bounds_m``
      (``info["out_of_bounds"]``); divergence.
    * Truncation: 1600 steps (400 s) by the registered time limit.

    ## Info

    ``reward_terms``, ``outcome`` (running/success/contact/grounding/out_of_bounds/diverged) and one flag per
    outcome, ``time_s``, ``clearance_m`` (hull to the nearest obstacle edge, capped at the beam range),
    ``min_clearance_m``, ``distance_to_goal_m``, ``speed_over_ground_m_s``, ``heading_error_deg``, ``path_m``.

    Success means arrival: the success termination above (goal polygon, speed and heading). ``success`` and
    ``is_success`` carry the same flag; ``is_success`` is the key Stable-Baselines3's ``Monitor`` and
    ``EvalCallback`` read for their success rate, so it is True only on the step that ends an episode in the
    berth.

    ## Arguments

    ``gymnasium.make("vessel_gym/HarbourApproach-v0", render_mode=None, config=None, scenario="harbour",
    **overrides)``: ``scenario`` is a built-in name, a TOML path or a :class:`~vessel_gym.scenarios.Scenario`;
    further keys: the shared ones (``ship`` overrides the scenario's, ``dt_s``, ``control_interval_s`` (0.25),
    ``action_type``, ``engine_control`` (True), ``rudder_orders_deg``, ``telegraph_steps``,
    ``observation_type``, ...), ``n_beams`` (16), ``beam_range_L`` (10), ``slow_down_L`` (8),
    ``safe_clearance_L`` (0.5), ``reward``. Strict: unknown keys raise ``SpecError``.
    ``reset(options={"north_m", "east_m", "heading_deg", "speed_m_s", "environment"})`` fixes the start.

    ## Vectorized environment

    ``gymnasium.make_vec("vessel_gym/HarbourApproach-v0", num_envs=N)``: :class:`HarbourApproachVectorEnv`.

    ## Version History

    * v0: initial version.
    """

    Task = HarbourApproachTask
    env_name = "HarbourApproach-v0"

    @classmethod
    def make_task(cls, config: Any, overrides: Mapping[str, Any], n: int) -> Task:
        return _make_task(cls, config, overrides, n)


class HarbourApproachVectorEnv(ShipVectorEnv):
    """Native vector version of :class:`HarbourApproachEnv` (one simulation of ``num_envs`` ships)."""

    Env = HarbourApproachEnv


# --- HarbourApproach-v1 ----------------------------------------------------------------------------------------
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


@dataclass(frozen=True, kw_only=True)
class HarbourApproachV1Reward(HarbourApproachReward):
    """Weights of the HarbourApproach-v1 reward terms; ``time`` is charged per ship time scale."""

    time: float = weight(0.5, "-(control interval) x U_T / L per step: -1 per time the ship sails its length")
    success: float = weight(50.0, "+1 on arrival")


@dataclass(frozen=True, kw_only=True)
class HarbourApproachV1Config(HarbourApproachConfig):
    """HarbourApproach-v1 configuration (see :class:`HarbourApproachV1Env`)."""

    ship: str | None = param(
        "kvlcc2_l7_windage",
        doc="ship name or file (default: the L7 model with its estimated windage, so that wind acts; "
        "None: the scenario's ship)",
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
    reward: HarbourApproachV1Reward = param(HarbourApproachV1Reward(), doc="reward weights")


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


class HarbourApproachV1Task(HarbourApproachTask):
    Config = HarbourApproachV1Config

    def __init__(self, config: HarbourApproachV1Config, n: int, scenario: Scenario | None = None) -> None:
        if scenario is None and config.layout == "procedural":
            from vessel_gym.scenarios.generator import generate_harbour, split_seed

            seed = split_seed(config.layout_split, config.layout_index)
            scenario = generate_harbour(seed, config.ship if config.ship is not None else "kvlcc2_l7")
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
        super().__init__(config, n, scenario=sc)
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

    def start_pose(self, rng: np.random.Generator) -> tuple[float, float, float, float]:
        if self.difficulty >= len(TRACK_FRACTION):
            return super().start_pose(rng)
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
        dist = math.hypot(self.p[kn.HP_GOAL_N] - n0, self.p[kn.HP_GOAL_E] - e0)
        allowed = max(self.p[kn.HP_GOAL_VMAX], self.U_T * min(1.0, dist / self.p[kn.HP_SLOW_DIST]))
        speed = allowed * rng.uniform(*START_SPEED_FRACTION)
        return n0, e0, heading, speed


class HarbourApproachV1Env(HarbourApproachEnv):
    """Bring a ship from outside a harbour through the entrance to a stop in the goal area (v1).

    ## Description

    The task, actions, observations, success and ``info`` of :class:`HarbourApproachEnv` (v0, deprecated),
    with the changes below. Built-in scenarios ``harbour``, ``harbour_east``, ``harbour_channel``; or a
    generated harbour (``layout="procedural"``, :mod:`vessel_gym.scenarios.generator`), whose ``eval`` split
    is held out for evaluation. Wind acts on the ship: the default ship ``kvlcc2_l7_windage`` is the L7 model
    with a Froude-scaled windage table (an estimate); ``kvlcc2_l7`` itself, as tested in the tank, has none.

    Control interval L / U_T / 6 of the ship (0.99 s for ``kvlcc2_l7``; 4 RK4 steps of 0.2475 s).

    ## Rewards

    As v0, except ``time`` (weight 0.5): -control interval x U_T / L per step (time in ship time scales),
    and ``success`` weight 50.

    ## Starting State

    ``difficulty`` 3 (``open``, default): the scenario's ``[start]`` region, as v0. 0 ``basin``, 1
    ``entrance``, 2 ``approach``: on the scenario's track with 25 %, 45 % or 70 % of its length to go, spread
    +-5 % along and +-0.5 L across it, heading along it +-10 deg, at 50-90 % of the allowed speed there.
    Wind, current and waves uniform in the scenario's ``[weather]``, drawn by the reset seed.

    ## Episode End

    As v0; truncation after ``time_limit_s`` (default 100 L / U_T: 590 s, 596 steps, for ``kvlcc2_l7``),
    counted by this environment (no step-count TimeLimit is registered).

    ## Arguments

    ``gymnasium.make("vessel_gym/HarbourApproach-v1", difficulty=3, scenario="harbour", layout="scenario",
    layout_split="train", layout_index=0, control_interval_s=None, time_limit_s=None, **overrides)`` (v0
    keys otherwise). Curriculum hook: ``env.unwrapped.set_difficulty(k)`` (index or name), effective from
    the next reset; vector env: ``venv.set_difficulty(k)`` or ``venv.call("set_difficulty", k)``.

    ## Version History

    * v1: control interval and time limit from the ship's time scale, time charged per ship time scale,
      success 50, difficulty levels, wind with force, three built-in harbours and procedural layouts.
    * v0: initial version (deprecated).
    """

    Task = HarbourApproachV1Task
    env_name = "HarbourApproach-v1"

    def __init__(self, render_mode: str | None = None, config: Any = None, **overrides: Any) -> None:
        super().__init__(render_mode, config, **overrides)
        self._elapsed = 0

    @classmethod
    def make_task(cls, config: Any, overrides: Mapping[str, Any], n: int) -> Task:
        return _make_task(cls, config, overrides, n, HarbourApproachV1Task)

    @property
    def difficulty(self) -> int:
        """Current difficulty level (0 basin .. 3 open)."""
        return self.task.difficulty

    def set_difficulty(self, level: int | str) -> None:
        """Curriculum hook: start region of the episodes reset from now on (index 0..3 or a name)."""
        self.task.set_difficulty(level)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        self._elapsed = 0
        return super().reset(seed=seed, options=options)

    def step(self, action: Any):
        obs, reward, terminated, _truncated, info = super().step(action)
        self._elapsed += 1
        return obs, reward, terminated, (not terminated) and self._elapsed >= self.task.max_steps, info


class HarbourApproachV1VectorEnv(HarbourApproachVectorEnv):
    """Native vector version of :class:`HarbourApproachV1Env`; ``set_difficulty(k)`` (also through
    ``call("set_difficulty", k)``) applies to every sub-environment from its next reset on."""

    Env = HarbourApproachV1Env

    def __init__(self, num_envs: int = 1, max_episode_steps: int | None = None, **kwargs: Any) -> None:
        super().__init__(num_envs, max_episode_steps, **kwargs)
        if self.max_episode_steps is None:
            self.max_episode_steps = self.task.max_steps

    @property
    def difficulty(self) -> int:
        return self.task.difficulty

    def set_difficulty(self, level: int | str) -> None:
        self.task.set_difficulty(level)

    def call(self, name: str, *args: Any, **kwargs: Any) -> tuple:
        """Call method ``name`` (or read attribute ``name``) once; one result per sub-environment, as
        Gymnasium's ``SyncVectorEnv.call`` returns (the sub-environments share one task)."""
        attr = getattr(self, name)
        out = attr(*args, **kwargs) if callable(attr) else attr
        return (out,) * self.num_envs
