"""ZigZag: a course-changing autopilot task built around the IMO zig-zag manoeuvre."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.envs import kernels as kn
from vessel_gym.envs.config import OpenWaterConfig, weight
from vessel_gym.envs.core import PHASE_STEP, Feature, ShipEnv, ShipVectorEnv, Task, _uniform
from vessel_gym.physics.schema import check_ranges, param
from vessel_gym.physics.units import DEG


@dataclass(frozen=True, kw_only=True)
class ZigZagReward:
    """Weights of the ZigZag reward terms (reward = sum of weight x term)."""

    heading_error: float = weight(1.0, "-|target - heading| / pi")
    overshoot: float = weight(1.0, "-min(excursion past the reached target / psi, 1)")
    rudder_activity: float = weight(0.1, "-|change of rudder order| / (2 rudder limit)")
    speed_loss: float = weight(0.5, "-max(0, U0 - U) / U0")


@dataclass(frozen=True, kw_only=True)
class ZigZagConfig(OpenWaterConfig):
    """ZigZag-v0 configuration (see :class:`ZigZagEnv`)."""

    schedule: str = param("imo", choices=("imo", "random"), doc="target schedule")
    zigzag_heading_deg: float = param(10.0, unit="deg", lo=1.0, hi=90.0, doc="imo: target deviation psi")
    first_side: str = param(
        "starboard", choices=("starboard", "port", "random"), doc="imo: first target side"
    )
    course_change_deg: tuple[float, ...] = param(
        (10.0, 40.0), unit="deg", lo=1.0, hi=180.0, doc="random: [min, max] course change, either side"
    )
    leg_time_s: tuple[float, ...] = param(
        (20.0, 40.0), unit="s", lo=0.01, hi=1e5, doc="random: [min, max] time between course changes"
    )
    reward: ZigZagReward = param(ZigZagReward(), doc="reward weights")


class ZigZagTask(Task):
    Config = ZigZagConfig
    kernel = staticmethod(kn.zigzag_update)
    n_features = kn.ZFN

    def __init__(self, config: ZigZagConfig, n: int) -> None:
        check_ranges(config, ("course_change_deg", "leg_time_s", "initial_heading_deg"), "ZigZag config")
        super().__init__(config, n)
        self.imo = config.schedule == "imo"
        self.psi_z = config.zigzag_heading_deg * DEG
        self.ts = np.zeros((n, kn.ZN))
        p = np.zeros(kn.ZPN)
        p[kn.ZP_PSIZ] = self.psi_z if self.imo else config.course_change_deg[0] * DEG
        p[kn.ZP_DMAX] = (
            self.helm.rudder_limit_rad[0] if hasattr(self.helm, "rudder_limit_rad") else self.delta_max
        )
        p[kn.ZP_IMO] = 1.0 if self.imo else 0.0
        p[kn.ZP_DT] = config.control_interval_s
        self.p = p

    def observation_features(self) -> list[Feature]:
        f = self.motion_observation(rev=self.config.engine_control)
        f += [
            Feature("heading_error", "rad", math.pi, "target heading - heading, wrapped", kn.ZF_HEAD_ERR),
            Feature(
                "heading_deviation", "rad", math.pi, "heading - original course, wrapped", kn.ZF_HEAD_DEV
            ),
            Feature("target_deviation", "rad", math.pi, "target heading - original course", kn.ZF_TARGET_DEV),
        ]
        return f

    def reset_vessel(self, k: int, rng: np.random.Generator, options: Mapping | None) -> None:
        c = self.config
        opts = dict(options or {})
        heading = float(opts.pop("heading_deg", _uniform(rng, c.initial_heading_deg)))
        speed = float(opts.pop("speed_m_s", c.approach_speed_m_s or self.U_T))
        if opts:
            raise ValueError(f"unknown reset option(s) {sorted(opts)} (allowed: heading_deg, speed_m_s)")
        self.sim.reset(speed_m_s=speed, heading_deg=heading, k=k)
        s = self.ts[k]
        s[:] = 0.0
        psi0 = float(self.sim.heading[k])
        s[kn.Z_PSI0] = psi0
        s[kn.Z_U0] = speed
        s[kn.Z_PREV_ORDER] = float(self.sim.rudder_order[k])
        if self.imo:
            side = {"starboard": 1.0, "port": -1.0}.get(c.first_side)
            if side is None:
                side = 1.0 if rng.random() < 0.5 else -1.0
            s[kn.Z_SIDE] = side
            s[kn.Z_TARGET] = psi0 + side * self.psi_z
            s[kn.Z_EXEC] = 1.0  # the first execute is the rudder order at t = 0
        else:
            s[kn.Z_TARGET] = psi0
            self._new_leg(k, rng)

    def _new_leg(self, k: int, rng: np.random.Generator) -> None:
        c = self.config
        s = self.ts[k]
        change = _uniform(rng, c.course_change_deg) * DEG * (1.0 if rng.random() < 0.5 else -1.0)
        s[kn.Z_TARGET] += change
        s[kn.Z_LEG_SIGN] = 1.0 if s[kn.Z_TARGET] >= self.sim.heading[k] else -1.0
        s[kn.Z_REACHED] = 0.0
        s[kn.Z_EXEC] += 1.0
        s[kn.Z_NEXT] = s[kn.Z_T] + _uniform(rng, c.leg_time_s)

    def kernel_args(self) -> tuple:
        return (
            self.sim.state,
            self.sim.inputs,
            self.sim.alive,
            self.ts,
            self.p,
            self.weights,
            self.enc,
            self.feat,
            self.obs,
            self.terms,
            self.reward,
            self.terminated,
        )

    def update(self, phase: np.ndarray) -> None:
        if not self.imo:  # random schedule: a new leg on vessels whose leg time is up
            due = (phase == PHASE_STEP) & (
                self.ts[:, kn.Z_T] + self.config.control_interval_s >= self.ts[:, kn.Z_NEXT] - 1e-9
            )
            for k in np.flatnonzero(due):
                self._new_leg(int(k), self.rngs[k])
        super().update(phase)

    # --- info -------------------------------------------------------------------------------------------
    def info(self, k: int) -> dict[str, Any]:
        s = self.ts[k].tolist()
        return {
            "reward_terms": self.weighted_terms(k),
            "time_s": s[kn.Z_T],
            "target_heading_deg": math.degrees(s[kn.Z_TARGET]) % 360.0,
            "heading_error_deg": math.degrees(self.feat[k, kn.ZF_HEAD_ERR]),
            "executes": int(s[kn.Z_EXEC]),
            "overshoot_count": int(s[kn.Z_OS_N]),
            "overshoot_1_deg": math.degrees(s[kn.Z_OS1]),
            "overshoot_2_deg": math.degrees(s[kn.Z_OS2]),
            "last_overshoot_deg": math.degrees(s[kn.Z_OS_LAST]),
            "diverged": not self.sim.alive[k],
        }

    def batch_info(self) -> dict[str, Any]:
        s = self.task_columns()
        return {
            "reward_terms": self.batch_weighted_terms(),
            "time_s": s[kn.Z_T],
            "target_heading_deg": np.degrees(s[kn.Z_TARGET]) % 360.0,
            "heading_error_deg": np.degrees(self.feat[:, kn.ZF_HEAD_ERR]),
            "executes": s[kn.Z_EXEC].astype(np.int64),
            "overshoot_count": s[kn.Z_OS_N].astype(np.int64),
            "overshoot_1_deg": np.degrees(s[kn.Z_OS1]),
            "overshoot_2_deg": np.degrees(s[kn.Z_OS2]),
            "last_overshoot_deg": np.degrees(s[kn.Z_OS_LAST]),
            "diverged": ~self.sim.alive,
        }

    def overlay(self, k: int) -> dict[str, Any]:
        return {
            "target_heading_rad": float(self.ts[k, kn.Z_TARGET]),
            "original_course_rad": float(self.ts[k, kn.Z_PSI0]),
            "title": "ZigZag",
        }


class ZigZagEnv(ShipEnv):
    """Course-changing autopilot built around the IMO zig-zag manoeuvre (MSC.137(76)).

    ## Description

    A ship starts in a steady straight approach. Its target heading alternates between
    ``original course + psi`` and ``original course - psi`` exactly as the IMO zig-zag schedule moves the
    rudder: the target flips to the other side when the heading reaches the current target (the IMO
    "execute"). The agent holds the helm and should turn onto each new target quickly, with as little
    overshoot, rudder activity and speed loss as possible. With ``schedule="random"`` the targets are instead
    random course changes of ``course_change_deg`` every ``leg_time_s`` seconds. ``info`` reports the
    overshoot angles as IMO MSC.137(76) defines them: the first overshoot is the additional heading deviation
    after the second execute, the second overshoot after the third execute (the largest excursion past the
    target before the ship turns back). The scripted IMO rule
    (:class:`vessel_gym.envs.policies.ZigZagRule`) applied here is the IMO zig-zag test itself.

    Default ship: ``kvlcc2_l7`` (7 m KVLCC2 model, 1.18 m/s test speed), physics step 0.25 s (chosen from
    the ship, docs/envs.md), control interval 0.25 s.

    ## Action Space

    ``action_type="continuous"`` (default): ``Box(-1, 1, (1,))`` (``(2,)`` with ``engine_control=True``).

    | Num | Action | Unit | Mapping |
    |-----|--------|------|---------|
    | 0 | rudder order | - | x rudder limit (steering-gear max angle, 35 deg), + starboard |
    | 1 | engine order (optional) | - | x full-ahead rpm (a > 0) or x full-astern rpm (a < 0) |

    Out-of-range values are clipped to [-1, 1]; NaN raises ``ValueError``. Without engine control the
    shaft-speed order stays at the approach value. ``action_type="discrete"``: ``Discrete(len(rudder_orders_deg))``
    helm orders (default port 35 ... midships ... starboard 35), or ``MultiDiscrete`` helm order x telegraph
    step with engine control; an index out of range raises ``ValueError``.

    ## Observation Space

    ``Box(-1, 1, (8,), float32)`` with ``observation_type="normalized"`` (value / scale, clipped); SI values
    clipped to +-scale with ``"physical"``. U_T: ship test speed, L: ship length.

    | Num | Name | Unit | Scale | Meaning |
    |-----|------|------|-------|---------|
    | 0 | u | m/s | 1.5 U_T | surge velocity through the water |
    | 1 | v | m/s | 0.5 U_T | sway velocity through the water (+ starboard) |
    | 2 | r | rad/s | 2 U_T / L | rate of turn (+ starboard) |
    | 3 | rudder | rad | rudder max | actual rudder angle |
    | 4 | rudder_order | rad | rudder max | rudder order |
    | (5) | rev | rev/s | 1.5 full-ahead | shaft speed (only with ``engine_control``) |
    | 5 | heading_error | rad | pi | target heading - heading, wrapped to [-pi, pi) |
    | 6 | heading_deviation | rad | pi | heading - original course |
    | 7 | target_deviation | rad | pi | target heading - original course (+-psi in the IMO schedule) |

    ``env.unwrapped.observation_layout`` gives names, units and scales and decodes observations.

    ## Rewards

    reward = sum of weight x term over the terms below (weights: config ``reward`` table); the weighted
    terms are in ``info["reward_terms"]`` and sum to the reward.

    | Term | Default weight | Value per step |
    |------|----------------|----------------|
    | heading_error | 1.0 | -abs(heading error) / pi |
    | overshoot | 1.0 | -min(excursion past the last reached target / psi, 1) while it lasts |
    | rudder_activity | 0.1 | -abs(change of rudder order) / (2 x rudder limit) |
    | speed_loss | 0.5 | -max(0, U0 - U) / U0 (U speed through the water, U0 approach speed) |

    ## Starting State

    Steady straight approach (rpm solved for zero surge acceleration) at ``approach_speed_m_s`` (default
    the test speed), rudder amidships, heading uniform in ``initial_heading_deg`` (default 0), at the
    origin. Calm water. First target: ``psi`` to ``first_side`` (default starboard).

    ## Episode End

    * Termination: the simulation diverged (non-finite state; ``info["diverged"]``).
    * Truncation: 480 steps (120 s) by the registered time limit.

    ## Info

    ``reward_terms``, ``time_s``, ``target_heading_deg``, ``heading_error_deg``, ``executes`` (target
    changes including the first order), ``overshoot_count``, ``overshoot_1_deg``, ``overshoot_2_deg``
    (0 until measured), ``last_overshoot_deg``, ``diverged``. v0 measures overshoots with its own accounting
    (the ``OVERSHOOT_V0`` mode of :mod:`vessel_gym.control.zigzag`, docs/control.md), which can differ from
    the IMO trial's with coarse control steps or when the next target is reached before the ship turns back.

    ZigZag has no success: the course changes go on until the time limit, so there is no end state to
    reach, and ``info`` has no ``is_success`` (SB3 logs no success rate). An episode is judged by its
    return and metrics (heading error, overshoot per course change, rudder effort).

    ## Arguments

    ``gymnasium.make("vessel_gym/ZigZag-v0", render_mode=None, config=None, **overrides)``: ``config`` is a
    :class:`ZigZagConfig`, a mapping or a TOML file; keyword overrides are config keys. Unknown keys and
    out-of-range values raise ``SpecError``; ``control_interval_s`` must be a whole multiple of ``dt_s``.
    Keys: ``ship``, ``dt_s`` (default from the ship), ``control_interval_s`` (0.25), ``method``, ``action_type``,
    ``engine_control`` (False), ``rudder_limit_deg``, ``rudder_orders_deg``, ``telegraph_steps``,
    ``observation_type``, ``schedule`` ("imo" | "random"), ``zigzag_heading_deg`` (10), ``first_side``,
    ``course_change_deg``, ``leg_time_s``, ``approach_speed_m_s``, ``initial_heading_deg``, ``reward``.
    ``reset(options={"heading_deg": ..., "speed_m_s": ...})`` fixes the start.

    ## Vectorized environment

    ``gymnasium.make_vec("vessel_gym/ZigZag-v0", num_envs=N)`` steps N ships in one batched physics call
    (:class:`ZigZagVectorEnv`); vessel k seeded with ``seed + k`` follows the single environment seeded so.

    ## Version History

    * v0: initial version.
    """

    Task = ZigZagTask
    env_name = "ZigZag-v0"


class ZigZagVectorEnv(ShipVectorEnv):
    """Native vector version of :class:`ZigZagEnv` (one simulation of ``num_envs`` ships)."""

    Env = ZigZagEnv
