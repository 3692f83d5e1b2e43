"""TurningCircle: bring the ship into and hold a commanded turn, or reverse course in little room."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.envs import kernels as kn
from vessel_gym.envs.config import weight
from vessel_gym.envs.core import Feature, ShipEnv, ShipVectorEnv, Task, _uniform
from vessel_gym.envs.disturbances import Disturbances, DisturbedOpenWaterConfig
from vessel_gym.physics import layout as lo
from vessel_gym.physics.schema import check_ranges, param

MODES = ("rate", "radius", "reverse")
REVERSE = MODES.index("reverse")


@dataclass(frozen=True, kw_only=True)
class TurningCircleReward:
    """Weights of the TurningCircle reward terms (reward = sum of weight x term)."""

    tracking_error: float = weight(1.0, "rate/radius: -min(relative error, 1)")
    progress: float = weight(5.0, "reverse: heading change this step / pi")
    footprint: float = weight(1.0, "reverse: -(growth of max advance + max transfer) / L")
    rudder_activity: float = weight(0.1, "-|change of rudder order| / (2 rudder limit)")
    speed_loss: float = weight(0.1, "-max(0, U0 - U) / U0")
    time: float = weight(0.1, "reverse: -control interval x U0 / L")


@dataclass(frozen=True, kw_only=True)
class TurningCircleConfig(DisturbedOpenWaterConfig):
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


class TurningCircleTask(Task):
    Config = TurningCircleConfig
    kernel = staticmethod(kn.turning_update)
    n_features = kn.TCFN

    def __init__(self, config: TurningCircleConfig, n: int) -> None:
        check_ranges(config, ("rate_prime", "radius_L", "initial_heading_deg"), "TurningCircle config")
        super().__init__(config, n)
        self.disturbances = Disturbances(config, self.ship, "TurningCircle config")
        self.mode = MODES.index(config.mode)
        self.ts = np.zeros((n, kn.TCN))
        p = np.zeros(kn.TCPN)
        p[kn.TCP_MODE] = self.mode
        p[kn.TCP_L] = self.L
        p[kn.TCP_DMAX] = getattr(self.helm, "rudder_limit_rad", np.array([self.delta_max]))[0]
        p[kn.TCP_DT] = config.control_interval_s
        self.p = p

    def observation_features(self) -> list[Feature]:
        U, L = self.U_T, self.L
        f = self.motion_observation(rev=self.config.engine_control)
        if self.config.mode == "rate":
            f += [
                Feature("commanded_rate", "rad/s", 2.0 * U / L, "commanded rate of turn", kn.TCF_CMD_RATE),
                Feature(
                    "rate_error", "rad/s", 2.0 * U / L, "commanded - actual rate of turn", kn.TCF_RATE_ERR
                ),
            ]
        elif self.config.mode == "radius":
            f += [
                Feature(
                    "commanded_curvature", "-", 1.0, "L / commanded radius (+ starboard)", kn.TCF_CMD_CURV
                ),
                Feature(
                    "curvature_error", "-", 1.0, "L x (commanded - actual curvature r / U)", kn.TCF_CURV_ERR
                ),
            ]
        else:
            f += [
                Feature(
                    "heading_change",
                    "rad",
                    2.0 * math.pi,
                    "heading - original course (unwrapped)",
                    kn.TCF_HEAD_CHANGE,
                ),
                Feature("advance", "m", 10.0 * L, "displacement along the original course", kn.TCF_ADVANCE),
                Feature("transfer", "m", 10.0 * L, "displacement across it (+ starboard)", kn.TCF_TRANSFER),
            ]
        return f

    def reset_vessel(self, k: int, rng: np.random.Generator, options: Mapping | None) -> None:
        c = self.config
        opts = dict(options or {})
        heading = float(opts.pop("heading_deg", _uniform(rng, c.initial_heading_deg)))
        speed = float(opts.pop("speed_m_s", c.approach_speed_m_s or self.U_T))
        side = {"starboard": 1.0, "port": -1.0}.get(c.side)
        if side is None:
            side = 1.0 if rng.random() < 0.5 else -1.0
        if self.mode == 0:
            cmd = side * _uniform(rng, c.rate_prime) * speed / self.L
        elif self.mode == 1:
            cmd = side / (_uniform(rng, c.radius_L) * self.L)
        else:
            cmd = 0.0
        cmd = float(opts.pop("command", cmd))
        if opts:
            raise ValueError(
                f"unknown reset option(s) {sorted(opts)} (allowed: heading_deg, speed_m_s, command)"
            )
        self.disturbances.apply(self.sim, k, rng, heading)
        self.sim.reset(speed_m_s=speed, heading_deg=heading, k=k)
        s = self.ts[k]
        s[:] = 0.0
        s[kn.TC_PSI0] = float(self.sim.heading[k])
        s[kn.TC_N0] = float(self.sim.north[k])
        s[kn.TC_E0] = float(self.sim.east[k])
        s[kn.TC_CMD] = cmd
        s[kn.TC_U0] = speed
        s[kn.TC_PREV_ORDER] = float(self.sim.rudder_order[k])

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

    def _radius(self, k: Any) -> Any:
        U = np.hypot(self.sim.u[k], self.sim.v[k])
        r = np.abs(self.sim.r[k])
        return np.where(r > 1e-9, U / np.maximum(r, 1e-9), 0.0)

    def _radius_k(self, k: int) -> float:
        x = self.sim.state[k]
        r = abs(float(x[lo.X_R]))
        return math.hypot(float(x[lo.X_U]), float(x[lo.X_V])) / r if r > 1e-9 else 0.0

    def info(self, k: int) -> dict[str, Any]:
        s = self.ts[k].tolist()
        cmd = s[kn.TC_CMD]
        info = {
            "reward_terms": self.weighted_terms(k),
            "time_s": s[kn.TC_T],
            "heading_change_deg": math.degrees(self.feat[k, kn.TCF_HEAD_CHANGE]),
            "rate_of_turn_deg_s": math.degrees(self.sim.state[k, lo.X_R]),
            "turning_radius_m": self._radius_k(k),
            "commanded_rate_deg_s": float(math.degrees(cmd)) if self.mode == 0 else 0.0,
            "commanded_radius_m": float(1.0 / cmd) if self.mode == 1 else 0.0,
            "advance_m": s[kn.TC_ADV],
            "transfer_m": s[kn.TC_TRF],
            "tactical_diameter_m": s[kn.TC_TD],
            "reached_90": s[kn.TC_R90] > 0.0,
            "reached_180": s[kn.TC_R180] > 0.0,
            "success": bool(self.terminated[k] and self.sim.alive[k]),
            "diverged": bool(not self.sim.alive[k]),
        }
        if self.mode == REVERSE:  # the only mode with an end state to reach
            info["is_success"] = info["success"]
        return info

    def batch_info(self) -> dict[str, Any]:
        s = self.task_columns()
        cmd = s[kn.TC_CMD]
        zeros = np.zeros(self.n)
        info = {
            "reward_terms": self.batch_weighted_terms(),
            "time_s": s[kn.TC_T],
            "heading_change_deg": np.degrees(self.feat[:, kn.TCF_HEAD_CHANGE]),
            "rate_of_turn_deg_s": np.degrees(self.sim.r),
            "turning_radius_m": self._radius(slice(None)),
            "commanded_rate_deg_s": np.degrees(cmd) if self.mode == 0 else zeros,
            "commanded_radius_m": 1.0 / cmd if self.mode == 1 else zeros.copy(),
            "advance_m": s[kn.TC_ADV],
            "transfer_m": s[kn.TC_TRF],
            "tactical_diameter_m": s[kn.TC_TD],
            "reached_90": s[kn.TC_R90] > 0.0,
            "reached_180": s[kn.TC_R180] > 0.0,
            "success": self.terminated & self.sim.alive,
            "diverged": ~self.sim.alive,
        }
        if self.mode == REVERSE:
            info["is_success"] = info["success"].copy()
        return info

    def overlay(self, k: int) -> dict[str, Any]:
        s = self.ts[k]
        out: dict[str, Any] = {
            "origin_m": (float(s[kn.TC_N0]), float(s[kn.TC_E0])),
            "original_course_rad": float(s[kn.TC_PSI0]),
            "title": "TurningCircle",
        }
        if self.mode == 1:
            out["commanded_radius_m"] = float(1.0 / s[kn.TC_CMD])
        return out


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

    As :class:`~vessel_gym.envs.zigzag.ZigZagEnv`: ``Box(-1, 1, (1,))`` rudder order x rudder limit
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
    :class:`~vessel_gym.envs.zigzag.ZigZagEnv`'s shared part plus ``mode``, ``rate_prime``, ``radius_L``,
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
