"""HarbourApproach-v1: the harbour task with its control interval and time limit from the ship's time scale,
difficulty levels (start regions on the scenario's track) and procedural layouts.

What differs from v0 (:mod:`vessel_gym.envs.tasks.harbour`): the declaration's default weights, the config, the
start pose; the compiled step is v0's. The environment classes are in :mod:`vessel_gym.envs.harbour`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.envs.declare import Term
from vessel_gym.envs.generators import vessel_draws
from vessel_gym.envs.tasks.harbour import (
    SPEC,
    HarbourApproachConfig,
    HarbourApproachReward,
    HarbourApproachTask,
    P,
)
from vessel_gym.physics.schema import param
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.units import DEG
from vessel_gym.scenarios import Scenario, load_scenario
from vessel_gym.scenarios import geometry as geo

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


SPEC_V1 = SPEC.variant(
    "HarbourApproach-v1",
    time=Term("time", 0.5, "-(control interval) x U_T / L per step: -1 per time the ship sails its length"),
    success=Term("success", 50.0, "+1 on arrival"),
)
HarbourApproachV1Reward = SPEC_V1.weights_class(
    "HarbourApproachV1Reward",
    __name__,
    "Weights of the HarbourApproach-v1 reward terms; ``time`` is charged per ship time scale.",
    base=HarbourApproachReward,
)


@dataclass(frozen=True, kw_only=True)
class HarbourApproachV1Config(HarbourApproachConfig):
    """HarbourApproach-v1 configuration (see :class:`~vessel_gym.envs.harbour.HarbourApproachV1Env`)."""

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
    spec = SPEC_V1
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

    def start_poses(self, idx: np.ndarray, rng: Any) -> tuple[Any, Any, Any, Any]:
        if self.difficulty >= len(TRACK_FRACTION):  # the open region: v0's start
            return super().start_poses(idx, rng)
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
