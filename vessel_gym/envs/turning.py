"""TurningCircle environment: bring the ship into and hold a commanded turn, or reverse course in little room.

The environment classes and their spec sheet; the task's declaration, configuration, reset and compiled step are
in :mod:`vessel_gym.envs.tasks.turning` (names re-exported here).
"""

from __future__ import annotations

from vessel_gym.envs.env import ShipEnv, ShipVectorEnv
from vessel_gym.envs.tasks.turning import (
    MODES,
    REVERSE,
    TurningCircleConfig,
    TurningCircleReward,
    TurningCircleTask,
)

__all__ = [
    "MODES",
    "REVERSE",
    "TurningCircleConfig",
    "TurningCircleEnv",
    "TurningCircleReward",
    "TurningCircleTask",
    "TurningCircleVectorEnv",
]


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
