"""CollisionAvoidance: an own ship with the full ship dynamics follows a route to its goal among target ships
simulated in the same batch, the COLREG rules scored per encounter (docs/colreg.md).

Beside this file: the declaration and its columns (``colreg_columns.py``), the step (``colreg_step.py``),
the encounter geometry (``colreg_geometry.py``), the Imazu cases and the generator (``colreg_encounters.py``),
the rule checks and the episode metrics (``colreg_rules.py``), the encounters' bookkeeping and the
rule-following targets (``colreg_world.py``) and the baselines (``colreg_pilots.py``, ``colreg_mpc.py``).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.envs.config import ShipEnvConfig
from vessel_gym.envs.helm import make_helm
from vessel_gym.envs.registration import register_task
from vessel_gym.envs.task import Task, _uniform, start, task_arrays
from vessel_gym.envs.tasks.colreg_ais import AisReceiver
from vessel_gym.envs.tasks.colreg_columns import K_MAX, OUTCOMES, SC, SENSOR_MAX, SPEC, P, S
from vessel_gym.envs.tasks.colreg_encounters import GENERATED, IMAZU, LANES, Encounter, generate, imazu, lanes
from vessel_gym.envs.tasks.colreg_geometry import sweep_bearings
from vessel_gym.envs.tasks.colreg_rules import R, episode_metrics, new_record
from vessel_gym.envs.tasks.colreg_situation import DNV_COUNT, dnv_situation, read_situation, within_speed
from vessel_gym.envs.tasks.colreg_step import colreg_update
from vessel_gym.envs.tasks.colreg_world import OwnShips, World, steer_targets
from vessel_gym.envs.tasks.common import motion_observed
from vessel_gym.physics.schema import SpecError, param
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.units import DEG
from vessel_gym.scenarios.geometry import point_in_polygon
from vessel_gym.scenarios.scenario import load_scenario

CollisionAvoidanceReward = SPEC.weights_class(
    "CollisionAvoidanceReward", __name__, "CollisionAvoidance reward weights."
)


@dataclass(frozen=True, kw_only=True)
class CollisionAvoidanceConfig(ShipEnvConfig):
    """CollisionAvoidance configuration (see :class:`CollisionAvoidanceTask`)."""

    ship: str | None = param("kvlcc2_full", doc="built-in ship name or ship file path (own ship and targets)")
    control_interval_s: float = param(
        10.0, unit="s", lo=1e-4, hi=60.0, doc="time between actions; hull contact is tested at each"
    )
    encounters: str = param(
        "imazu",
        choices=("imazu", "generated", "mixed", "lanes", "dnv"),
        doc="what a reset draws: an Imazu case, a generated encounter, either (half each), traffic in a "
        "two-lane scheme (own lane and opposite lane, colreg_encounters.lanes), or one of DNV's 55 baseline "
        "situations (colreg_situation.dnv_situation)",
    )
    initial_heading_deg: tuple[float, ...] = param(
        (0.0, 360.0),
        unit="deg",
        lo=-360.0,
        hi=360.0,
        doc="[min, max] own ship's heading (the encounter turns with it)",
    )
    max_targets: int = param(3, unit="-", lo=1, hi=8, doc="target ships simulated per encounter")
    observed_targets: int = param(3, unit="-", lo=1, hi=K_MAX, doc="target-list slots observed (K)")
    tcpa_L: float = param(
        25.0,
        unit="L",
        lo=5.0,
        hi=200.0,
        doc="own ship's run to the meeting point, ship lengths at test speed",
    )
    imazu_heading_jitter_deg: float = param(3.0, unit="deg", lo=0.0, hi=30.0, doc="Imazu targets' heading +-")
    imazu_speed_jitter: float = param(0.05, unit="-", lo=0.0, hi=0.5, doc="Imazu targets' speed +- fraction")
    generated_targets: tuple[int, ...] = param(
        (1, 3), unit="-", lo=1, hi=8, doc="[min, max] generated targets"
    )
    generated_dcpa_L: tuple[float, ...] = param(
        (0.0, 1.0), unit="L", lo=0.0, hi=50.0, doc="[min, max] planned DCPA of a generated target"
    )
    generated_tcpa_fraction: tuple[float, ...] = param(
        (0.8, 1.2),
        unit="-",
        lo=0.1,
        hi=5.0,
        doc="[min, max] planned TCPA of a generated target / tcpa_L's time",
    )
    detection_range_L: float = param(
        60.0, unit="L", lo=1.0, hi=1000.0, doc="targets are seen within this range"
    )
    risk_dcpa_L: float = param(3.0, unit="L", lo=0.1, hi=50.0, doc="DCPA below which a target is a risk")
    max_cross_track_L: float = param(15.0, unit="L", lo=1.0, hi=1000.0, doc="cross-track error that ends it")
    goal_radius_L: float = param(2.0, unit="L", lo=0.1, hi=100.0, doc="arrival: within this of the goal")
    action_deg: float = param(
        5.0, unit="deg", lo=0.5, hi=90.0, doc="course alteration that counts as an action"
    )
    substantial_deg: float = param(
        30.0, unit="deg", lo=1.0, hi=180.0, doc="rule 8(b): a substantial alteration"
    )
    early_tcpa_fraction: float = param(
        0.5, unit="-", lo=0.0, hi=1.0, doc="rule 8/16: early = acting with TCPA >= this x TCPA at detection"
    )
    release_range_L: float = param(
        4.0, unit="L", lo=0.0, hi=100.0, doc="rule 17: a stand-on ship may act once the range is below this"
    )
    stand_on_tolerance_deg: float = param(
        10.0, unit="deg", lo=0.0, hi=90.0, doc="rule 17: course kept within"
    )
    stand_on_speed_fraction: float = param(0.1, unit="-", lo=0.0, hi=1.0, doc="rule 17: speed kept within")
    agents: int = param(
        1,
        unit="-",
        lo=1,
        hi=8,
        doc="own ships per encounter (the multi-agent env's agents; Gymnasium envs: 1)",
    )
    targets_react: bool = param(
        False,
        doc="targets keep the rules too: a target that must give way to an own ship turns target_turn_deg to "
        "starboard once its TCPA is below half the meeting time, and resumes its course past the CPA",
    )
    target_turn_deg: float = param(35.0, unit="deg", lo=5.0, hi=90.0, doc="a reacting target's alteration")
    waters: str = param(
        "",
        doc="restricted waters: a scenario (built-in name or TOML path) whose land and depth areas the own ship "
        "must keep off, in the frame of the own ship's start (origin, heading north: the heading is not drawn); "
        "its goal point is the goal. Empty: open sea",
    )
    under_keel_m: float = param(
        2.0, unit="m", lo=0.0, hi=50.0, doc="grounding: charted depth below the draught plus this margin"
    )
    opposite_lane_L: float = param(
        7.5, unit="L", lo=0.0, hi=100.0, doc="lanes: the opposite lane's centre line, this far to port"
    )
    sensors: int = param(0, unit="-", lo=0, hi=SENSOR_MAX, doc="range-sensor sectors observed (0: no sweep)")
    sensor_range_L: float = param(10.0, unit="L", lo=0.5, hi=200.0, doc="the range-sensor sweep's reach")
    tss_lane_half_L: float = param(
        0.0,
        unit="L",
        lo=0.0,
        hi=100.0,
        doc="rule 10 scored in a traffic-separation scheme: the own lane's half width about the route "
        "(0: not scored); the separation zone lies beyond it to port, the opposite lane beyond that",
    )
    tss_zone_width_L: float = param(
        2.5, unit="L", lo=0.0, hi=100.0, doc="rule 10: the separation zone's width"
    )
    tss_direction_deg: float = param(
        45.0,
        unit="deg",
        lo=1.0,
        hi=180.0,
        doc="rule 10: heading off the lane's flow that counts as against it",
    )
    channel_half_L: float = param(
        0.0,
        unit="L",
        lo=0.0,
        hi=100.0,
        doc="rule 9 scored in a narrow channel along the route: its half width (0: not scored)",
    )
    channel_offset_L: float = param(
        0.0, unit="L", lo=-100.0, hi=100.0, doc="rule 9: the channel's centre line, this far to port of the route"
    )
    channel_pass_L: float = param(
        1.0, unit="L", lo=0.0, hi=100.0, doc="rule 9(e): overtaking closer than this needs the overtaken's action"
    )
    lane_spread: float = param(
        1.0, unit="-", lo=0.0, hi=1.0, doc="lanes: the lateral offsets' ranges times this (narrow waters)"
    )
    targets_observed: str = param(
        "true",
        choices=("true", "ais"),
        doc="the target list from the truth, or as received over AIS (colreg_ais: reporting intervals of "
        "ITU-R M.1371-5, dropouts, noise, dead reckoning between reports)",
    )
    ais_class: str = param(
        "A", choices=("A", "B"), doc="AIS: the targets' station class (M.1371-5 Annex 1 Table 1 or 2 rates)"
    )
    ais_dropout: float = param(0.0, unit="-", lo=0.0, hi=0.99, doc="AIS: probability a report is lost")
    ais_position_sigma_m: float = param(10.0, unit="m", lo=0.0, hi=1000.0, doc="AIS: position error, std")
    ais_sog_sigma_kn: float = param(0.1, unit="kn", lo=0.0, hi=10.0, doc="AIS: speed over ground error, std")
    ais_cog_sigma_deg: float = param(
        1.0, unit="deg", lo=0.0, hi=45.0, doc="AIS: course over ground error, std"
    )
    ais_turning_deg_min: float = param(
        5.0, unit="deg/min", lo=0.0, hi=720.0, doc="AIS: a rate of turn above this is 'changing course'"
    )
    reward: CollisionAvoidanceReward = param(CollisionAvoidanceReward(), doc="reward weights")  # type: ignore[valid-type]


#: the record of the task's arrays (the step's ``t``): per own ship the task state, the COLREG scores, the
#: encounter's name (an index into ``scenario_names``) and smallest planned DCPA; the pair records, the
#: parameter row and the encounters
CollisionAvoidanceArrays = task_arrays(
    "CollisionAvoidanceArrays",
    __name__,
    vessel=("ts", "scores", "scenario_id", "planned_dcpa"),
    shared=("pairs", "p", "world"),
)


def route_pilot(env: Any) -> Any:
    from vessel_gym.envs.tasks.colreg_pilots import RouteFollower

    return RouteFollower(env)


def vo_pilot(env: Any) -> Any:
    from vessel_gym.envs.tasks.colreg_pilots import VelocityObstaclePilot

    return VelocityObstaclePilot(env)


def mpc_pilot(env: Any) -> Any:
    from vessel_gym.envs.tasks.colreg_mpc import ScenarioMPCPilot

    return ScenarioMPCPilot(env)


def vo_nomoto_pilot(env: Any) -> Any:
    from vessel_gym.envs.tasks.colreg_pilots import VelocityObstaclePilot
    from vessel_gym.policy import nomoto_pid_kwargs

    return VelocityObstaclePilot(env, **nomoto_pid_kwargs(env))


@register_task(
    presets={
        "CollisionAvoidance-v0": {},
        "CollisionAvoidanceChannel-v0": {
            "waters": "colreg_tss",
            "encounters": "lanes",
            "sensors": 24,
            "initial_heading_deg": (0.0, 0.0),
            "tss_lane_half_L": 2.5,  # colreg_tss: the northbound lane 1.6 km wide, the zone 0.8 km
            "tss_zone_width_L": 2.5,
        },
        "CollisionAvoidanceNarrow-v0": {  # colreg_narrow: a 1.6 km channel, the route on its starboard half
            "waters": "colreg_narrow",
            "encounters": "lanes",
            "sensors": 24,
            "initial_heading_deg": (0.0, 0.0),
            "channel_half_L": 2.5,
            "channel_offset_L": 1.25,
            "opposite_lane_L": 2.5,
            "lane_spread": 0.3,
            # ships passing in the channel's two halves (about 2.5 L apart) meet without risk of collision:
            # rule 9, not rule 14, is what applies to them
            "risk_dcpa_L": 1.5,
        },
    },
    max_episode_steps=400,
    pilots={"pid": vo_pilot, "pid-nomoto": vo_nomoto_pilot, "scripted": route_pilot, "mpc": mpc_pilot},
    metrics=episode_metrics,
    train={
        # PPO as the shipped CollisionAvoidance-v0 agents were trained (docs/colreg.md, "PPO from scratch"; their
        # encounter draw is the id's block of agents/hyperparams/ppo.yml). 750k steps: 7 min at the 1800 steps/s
        # of PPO on 16 ships with the machine idle
        "common": {"n_timesteps": 750_000, "n_envs": 16},
        "ppo": {
            "n_steps": 256,
            "batch_size": 1024,
            "n_epochs": 5,
            "gamma": 0.99,
            "gae_lambda": 0.95,
            "learning_rate": 3e-4,
            "clip_range": 0.2,
            "ent_coef": 0.0,
            "policy_kwargs": {"net_arch": [128, 128], "activation_fn": "tanh", "log_std_init": -0.5},
        },
    },
)
class CollisionAvoidanceTask(Task):
    """CollisionAvoidance: follow a route to the goal among target ships, keeping the COLREGs.

    The own ship (the full ship dynamics of ``ship``) starts at its test speed on its route, a straight leg
    of 2 ``tcpa_L`` ship lengths; the targets (the same ship, simulated in the same batch, keeping course and
    speed) are those of an Imazu case or of the generator (``encounters``; docs/colreg.md). Observation: the
    own ship's motion, route and goal, then a list of the K = ``observed_targets`` most dangerous targets
    (smallest DCPA + range / 10), each with a validity flag, in the own ship's body frame (bearings clockwise
    from the bow). Contact of the hull outlines (pointed-bow rectangles of L x B) ends the episode as a
    collision. Every target's situation is classified when it is detected as a risk and the own ship's
    conduct scored by rules 8 and 13-17 (``info["colreg_*"]``).

    ## Action Space

    The helm (``action_type``, ``engine_control``): rudder order as a fraction of the rudder limit.

    ## Rewards

    | Term | Default weight | Value per step |
    |------|----------------|----------------|
    | progress | 1.0 | (decrease of the distance to the goal) / (U_T x control interval) |
    | cross_track | 0.05 | -min(abs(cross-track error) / (max_cross_track_L L), 1) |
    | danger | 1.0 | -max(0, 1 - closest range / (risk_dcpa_L L)) |
    | colreg | 0.5 | -1 while the rudder order is to port with a head-on or give-way target closing |
    | rudder | 0.05 | -abs(change of rudder order) / (2 x rudder limit) |
    | collision | 20.0 | -1 at contact of the hull outlines |
    | grounding | 20.0 | -1 when the hull outline reaches land or a shoal |
    | arrival | 10.0 | +1 on reaching the goal |

    ## Episode End

    * Termination: arrival (within ``goal_radius_L`` of the goal or abeam of it), collision, grounding
      (restricted waters, ``waters``: the hull outline reaches land or water shallower than the draught plus
      ``under_keel_m``), straying
      beyond ``max_cross_track_L`` from the route, divergence.
    * Truncation: 400 steps (4000 s at the default 10 s control interval, twice the route at test speed).

    ## Info

    ``reward_terms``, ``scenario``, ``outcome``, ``success``, ``is_success``, ``collision``, ``grounding``, ``time_s``,
    ``min_separation_m``, ``min_separation_L``, ``planned_dcpa_m`` (smallest planned DCPA of the encounter),
    ``path_ratio``, ``rudder_reversals``, ``colreg_score``, ``colreg_checks``, ``colreg_violations``,
    ``reaction_delay_s`` (mean over the pairs acted for, from detection to the first alteration; -1 before any),
    ``colreg_passed`` and ``colreg_applied`` (per check), ``diverged``.

    ## Arguments

    ``reset(options={"scenario": "imazu:12" | "imazu" | "generated" | "generated:head_on+give_way" |
    "dnv:7" | "file:situation.json", "heading_deg": h})`` pins the encounter (``file:``: a maritime-schema traffic
    situation, ``colreg_situation``) and the own ship's heading.
    """

    Config = CollisionAvoidanceConfig
    spec = SPEC
    kernel = staticmethod(colreg_update)
    Arrays = CollisionAvoidanceArrays
    reset_options = ("scenario", "heading_deg")  # what reset(options=...) reads

    def __init__(self, config: CollisionAvoidanceConfig, n: int) -> None:
        if n % config.agents:
            raise SpecError(
                f"CollisionAvoidance: {n} own ships do not make encounters of agents = {config.agents}"
            )
        super().__init__(config, n)
        worlds = n // config.agents
        # the own ships, then every encounter's target slots, in one batch
        self.sim = Simulation(self.ship, n=n + worlds * config.max_targets, dt=self.dt, method=config.method)
        self.helm = make_helm(config, OwnShips(self.sim, n))
        B = self.ship.particulars.B_m
        self.world = World(n, config.agents, config.max_targets, self.L, B, config.observed_targets)
        self.waters = None
        if config.waters:
            self.waters = _load_waters(config.waters)
            draught = self.ship.particulars.T_m + config.under_keel_m  # m: shallower than this grounds
            polys = [pts for _kind, _name, pts in self.waters.hard_obstacles()]
            polys += [pts for _name, pts in self.waters.shoals(draught)]
            if self.waters.water_depth_m < draught:  # the open water itself would be a shoal
                raise SpecError(
                    f"CollisionAvoidance: waters {config.waters!r}: water_depth_m "
                    f"{self.waters.water_depth_m:g} m is below the draught + under_keel_m ({draught:g} m)"
                )
            self.world.set_waters(polys)
            if not point_in_polygon((0.0, 0.0), [tuple(q) for q in self.waters.start.points]):
                raise SpecError(
                    f"CollisionAvoidance: waters {config.waters!r}: its start region must hold "
                    "the origin (the own ship's start)"
                )
        if config.targets_observed == "ais":
            self.world.ais = AisReceiver(
                n,
                config.agents + config.max_targets,
                config.ais_class,
                config.ais_dropout,
                config.ais_position_sigma_m,
                config.ais_sog_sigma_kn,
                config.ais_cog_sigma_deg,
                config.ais_turning_deg_min,
            )
        if config.sensors:
            self.world.sensors = config.sensors
            self.world.bearings = sweep_bearings(config.sensors)
        self.ts = np.zeros((n, len(S)))
        self.scores = np.zeros((n, len(SC)))
        self.scores[:, SC.score] = 1.0
        self.scores[:, SC.delay] = -1.0
        self.scenario_id = np.zeros(n, dtype=np.int64)
        self.scenario_names: list[str] = [""]  # the encounters met so far, by scenario_id
        self.planned_dcpa = np.zeros(n)
        self.pairs = np.zeros((n, config.agents + config.max_targets, len(R)))
        c = config
        p = np.zeros(len(P))
        p[P.dt] = c.control_interval_s
        p[P.U_T] = self.U_T
        p[P.rudder_limit] = float(getattr(self.helm, "rudder_limit_rad", np.array([self.delta_max]))[0])
        p[P.max_cross] = c.max_cross_track_L * self.L
        p[P.goal_radius] = c.goal_radius_L * self.L
        p[P.risk] = c.risk_dcpa_L * self.L
        p[P.detection] = c.detection_range_L * self.L
        p[P.action] = c.action_deg * DEG
        p[P.release] = c.release_range_L * self.L
        p[P.port_order] = 1.0 * DEG  # rad: a rudder order beyond this is to a side (reversals, colreg term)
        p[P.early_fraction] = c.early_tcpa_fraction
        p[P.substantial] = c.substantial_deg * DEG
        p[P.stand_on_course] = c.stand_on_tolerance_deg * DEG
        p[P.stand_on_speed] = c.stand_on_speed_fraction
        p[P.sensor_range] = c.sensor_range_L * self.L
        p[P.tss_lane] = c.tss_lane_half_L * self.L
        p[P.tss_zone] = c.tss_zone_width_L * self.L
        p[P.tss_direction] = c.tss_direction_deg * DEG
        p[P.ch_half], p[P.ch_offset], p[P.ch_pass] = (
            x * self.L for x in (c.channel_half_L, c.channel_offset_L, c.channel_pass_L)
        )
        self.p = p
        T = self.L / self.U_T  # s
        # the reacting targets' heading law (PIDHeadingAutopilot's default gains): Kp, Kd (s), rudder limit,
        # alteration (rad), TCPA (s) below which a give-way target acts, risk distance (m)
        self.target_law = (
            1.5,
            1.0 * T,
            self.delta_max,
            c.target_turn_deg * DEG,
            0.5 * c.tcpa_L * T,
            p[P.risk],
        )

    # --- declaration hooks ---------------------------------------------------------------------------------
    def scales(self) -> dict[str, float]:
        c = self.config
        out = super().scales()
        out.update(
            {
                "detection range": c.detection_range_L * self.L,
                "tcpa scale": c.tcpa_L * self.L / self.U_T,
                "route length": 2.0 * c.tcpa_L * self.L,
                "max cross track": c.max_cross_track_L * self.L,
                "sensor range": c.sensor_range_L * self.L,
            }
        )
        return out

    def observed(self) -> tuple[str, ...]:
        own = ("cross_track", "course_error", "goal_sin", "goal_cos", "goal_distance")
        slots = tuple(f"t{j}_{f}" for j in range(self.config.observed_targets) for f in _field_names())
        sensors = tuple(f"sensor{i}" for i in range(self.config.sensors))
        return motion_observed(rev=self.config.engine_control) + own + slots + sensors

    # --- the start of an encounter -------------------------------------------------------------------------
    def _target_types(
        self, name: str | None, arg: str, pool: Any, need: int, rng: np.random.Generator
    ) -> tuple[str, ...]:
        """The targets' types of a generated or lane encounter: as ``arg`` names them ("a+b"), or a count
        drawn from ``generated_targets`` (at least ``need``) of types drawn from ``pool``."""
        c = self.config
        if arg:
            types = tuple(arg.split("+"))
        else:
            lo, hi = max(c.generated_targets[0], need, 1), min(c.generated_targets[-1], c.max_targets)
            count = int(rng.integers(lo, max(lo, hi) + 1))
            types = tuple(str(rng.choice(list(pool))) for _ in range(count))
        if not need <= len(types) <= c.max_targets:
            raise ValueError(f"{name}: {len(types)} targets; this task takes {need} to {c.max_targets}")
        return types

    def draw(self, name: str | None, rng: np.random.Generator) -> Encounter:
        """The encounter ``name`` (a reset option; None: as ``encounters`` says), drawn with ``rng``."""
        c = self.config
        need = c.agents - 1  # targets whose roles the other own ships take
        if name is None:
            kind = c.encounters
            if kind == "mixed":
                kind = "imazu" if rng.random() < 0.5 else "generated"
            name = kind
        kind, _, arg = name.partition(":")
        if kind == "imazu":
            cases = [i for i, t in IMAZU.items() if need <= len(t) <= c.max_targets]
            case = int(rng.choice(cases)) if not arg else _case(arg)
            if not need <= len(IMAZU[case]) <= c.max_targets:
                raise ValueError(
                    f"imazu:{case} has {len(IMAZU[case])} targets; this task takes {need} to {c.max_targets}"
                )
            jitter = (c.imazu_heading_jitter_deg, c.imazu_speed_jitter)
            return imazu(case, self.L, self.U_T, c.tcpa_L, rng, jitter)
        if kind == "generated":
            types = self._target_types(name, arg, GENERATED, need, rng)
            T = c.tcpa_L * self.L / self.U_T
            dcpa = tuple(rng.uniform(*c.generated_dcpa_L) * self.L for _ in types)
            tcpa = tuple(rng.uniform(*c.generated_tcpa_fraction) * T for _ in types)
            return generate(types, dcpa, tcpa, self.U_T, rng)
        if kind == "lanes":
            types = self._target_types(name, arg, LANES, need, rng)
            T = c.tcpa_L * self.L / self.U_T
            tcpa = tuple(rng.uniform(*c.generated_tcpa_fraction) * T for _ in types)
            return lanes(types, tcpa, self.U_T, self.L, c.opposite_lane_L * self.L, rng, c.lane_spread)
        if kind == "dnv":
            fits = [i for i in range(1, DNV_COUNT + 1) if need <= DNV_TARGETS[i - 1] <= c.max_targets]
            number = int(rng.choice(fits)) if not arg else _numbered("dnv", arg, DNV_COUNT)
            enc = within_speed(dnv_situation(number), self.U_T)
            if not need <= len(enc.targets) <= c.max_targets:
                raise ValueError(
                    f"{name}: {len(enc.targets)} targets; this task takes {need} to {c.max_targets}"
                )
            return enc
        if kind == "file" and arg:
            enc = within_speed(read_situation(arg), self.U_T)
            if not need <= len(enc.targets) <= c.max_targets:
                raise ValueError(
                    f"{name}: {len(enc.targets)} targets; this task takes {need} to {c.max_targets}"
                )
            return enc
        raise ValueError(
            f"unknown scenario {name!r} (imazu, imazu:1..22, generated, generated:<type>[+<type>...], "
            "lanes, lanes:<type>[+<type>...], dnv, dnv:1..55, file:<path>)"
        )

    def reset_vessel(self, k: int, rng: np.random.Generator, options: Mapping | None) -> None:
        """A new encounter for own ship k's encounter (drawn by its first own ship; the others are set with it)."""
        c = self.config
        world = self.world
        if world.slot_of[k] != 0:
            return
        opts = dict(options or {})
        scenario = opts.pop("scenario", None)
        drawn = _uniform(rng, c.initial_heading_deg)
        heading = float(opts.pop("heading_deg", drawn))
        if self.waters is not None:  # the waters are fixed on the chart: the own ship starts heading north
            if heading != 0.0 and "heading_deg" in (options or {}):
                raise ValueError("heading_deg: restricted waters fix the own ship's start heading (north, 0)")
            heading = 0.0
        if opts:
            raise ValueError(f"unknown reset option(s) {sorted(opts)} (allowed: heading_deg, scenario)")
        enc = self.draw(scenario, rng)
        if self.waters is not None:  # the goal is the waters' goal point
            enc = dataclasses.replace(enc, goal=self.waters.goal_point)
        w = world.world_of[k]
        if enc.name not in self.scenario_names:
            self.scenario_names.append(enc.name)
        name_id = self.scenario_names.index(enc.name)
        planned = min((d for d, _t in enc.planned_cpa), default=math.inf)
        h = heading * DEG
        ch, sh = math.cos(h), math.sin(h)
        members = world.members[w]
        run = 2.0 * c.tcpa_L * self.L
        # slot 0: the own ship; slots 1..agents-1: own ships in the first targets' roles; then the targets
        ships = [(0.0, 0.0, 0.0, enc.speed, run / 2.0 / enc.speed)]
        ships += [(t.n, t.e, t.psi, t.speed, tc) for t, (_d, tc) in zip(enc.targets, enc.planned_cpa)]
        slots = list(range(c.agents)) + [c.agents + j for j in range(len(enc.targets) - (c.agents - 1))]
        world.active[members] = False
        for slot, (n0, e0, psi, speed, tcpa) in zip(slots, ships):
            j = members[slot]
            n, e = n0 * ch - e0 * sh, n0 * sh + e0 * ch
            start(self, j, speed, (psi + h) / DEG, n, e)
            world.active[j] = True
            world.course[j] = psi + h
            if slot < c.agents:  # an own ship: its route runs through its meeting point to twice as far
                reach = 2.0 * speed * tcpa
                s = self.ts[j]
                s[:] = 0.0
                s[S.n0], s[S.e0] = n, e
                s[S.n1], s[S.e1] = n + reach * math.cos(psi + h), e + reach * math.sin(psi + h)
                if slot == 0 and enc.goal is not None:  # the situation's own goal
                    gn, ge = enc.goal
                    s[S.n1], s[S.e1] = gn * ch - ge * sh, gn * sh + ge * ch
                    reach = math.hypot(gn, ge)
                s[S.prev_n], s[S.prev_e] = n, e
                s[S.prev_goal] = s[S.straight] = reach
                s[S.min_sep] = math.inf
                for row in self.pairs[j]:
                    new_record(row)
                if world.ais is not None:
                    world.ais.reset(j, rng)
                self.scenario_id[j] = name_id
                self.planned_dcpa[j] = planned
                self.scores[j] = 0.0
                self.scores[j, SC.score] = 1.0
                self.scores[j, SC.delay] = -1.0
        for slot in range(len(enc.targets) + 1, len(members)):  # empty slots: parked
            start(self, members[slot], enc.speed, 0.0, 0.0, 0.0)

    def update(self, phase: np.ndarray) -> None:
        """The task's step, then (``targets_react``) the scripted targets' rudder orders for the next step."""
        super().update(phase)
        if self.config.targets_react:
            steer_targets(self.sim, self.world, self.target_law)

    def started(self, k: int | np.ndarray) -> None:
        ks = np.atleast_1d(np.asarray(k))
        own = ks[ks < self.n]
        self.ts[own, S.prev_order] = self.sim.rudder_order[own]

    def overlay(self, k: int) -> dict[str, Any]:
        """The chart's extras: the route (from its start along its course), the encounter's name, the outcome
        and the closest range so far (the targets themselves are not drawn yet)."""
        s = self.ts[k]
        return {
            "original_course_rad": math.atan2(s[S.e1] - s[S.e0], s[S.n1] - s[S.n0]),
            "origin_m": (float(s[S.n0]), float(s[S.e0])),
            "title": self.scenario_names[int(self.scenario_id[k])],
            "outcome": OUTCOMES[int(s[S.outcome])],
            "clearance_m": float(s[S.min_sep]) if math.isfinite(s[S.min_sep]) else 0.0,
        }


def _load_waters(name: str) -> Any:
    try:
        return load_scenario(name)
    except SpecError as exc:
        raise SpecError(f"CollisionAvoidance waters: {exc}") from None


def _case(text: str) -> int:
    try:
        case = int(text)
    except ValueError:
        raise ValueError(f"imazu:{text}: the case must be a number 1..22") from None
    if case not in IMAZU:
        raise ValueError(f"Imazu case {case} does not exist (1..22)")
    return case


def _numbered(kind: str, text: str, count: int) -> int:
    try:
        number = int(text)
    except ValueError:
        raise ValueError(f"{kind}:{text}: the situation must be a number 1..{count}") from None
    if not 1 <= number <= count:
        raise ValueError(f"{kind}:{number} does not exist (1..{count})")
    return number


#: targets of each DNV baseline situation (1..55): 1-5 one, 6-20 two, 21-55 three (the files' order)
DNV_TARGETS = (1,) * 5 + (2,) * 15 + (3,) * 35


def _field_names() -> tuple[str, ...]:
    from vessel_gym.envs.tasks.colreg_columns import TARGET_FIELDS

    return TARGET_FIELDS._fields
