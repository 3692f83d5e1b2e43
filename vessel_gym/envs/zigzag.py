"""ZigZag environments: a course-changing autopilot task built around the IMO zig-zag manoeuvre.

The environment classes and their spec sheets. Each task's declaration, configuration, reset and compiled step
are in :mod:`vessel_gym.envs.tasks.zigzag` (v0) and :mod:`vessel_gym.envs.tasks.zigzag_v1` (v1); their names
are re-exported here.
"""

from __future__ import annotations

from vessel_gym.envs.env import ShipEnv, ShipVectorEnv
from vessel_gym.envs.tasks.zigzag import ZigZagConfig, ZigZagReward, ZigZagTask
from vessel_gym.envs.tasks.zigzag_v1 import (
    LEG_TIME_LIMIT_L_U,
    REACH_TIME_L_U,
    ZigZagRandomConfig,
    ZigZagRandomTask,
    ZigZagV1Config,
    ZigZagV1Reward,
    ZigZagV1Task,
)

__all__ = [
    "LEG_TIME_LIMIT_L_U",
    "REACH_TIME_L_U",
    "ZigZagConfig",
    "ZigZagEnv",
    "ZigZagRandomConfig",
    "ZigZagRandomEnv",
    "ZigZagRandomTask",
    "ZigZagRandomVectorEnv",
    "ZigZagReward",
    "ZigZagTask",
    "ZigZagV1Config",
    "ZigZagV1Env",
    "ZigZagV1Reward",
    "ZigZagV1Task",
    "ZigZagV1VectorEnv",
    "ZigZagVectorEnv",
]


class ZigZagEnv(ShipEnv):
    """Course-changing autopilot built around the IMO zig-zag manoeuvre (MSC.137(76)).

    Deprecated: use ``vessel_gym/ZigZag-v1`` (:class:`ZigZagV1Env`) and ``vessel_gym/ZigZagRandom-v1``.
    v0 stays registered with unchanged behaviour, but its reward ranks badly: its overshoot term keeps
    charging a target the ship has already left behind, a helm that stops just short of a target stalls
    the IMO schedule, and every seed gives the same episode (version history below).

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

    * v0: initial version. Deprecated in favour of v1: the overshoot term charges the running measurement
      of the last reached target until the yaw rate reverses, also while the ship turns correctly toward a
      new target in the same direction; ``overshoot_count`` and the overshoot angles count only finished
      measurements; the IMO schedule waits for the target indefinitely, so a helm that aims 0.5-2 deg short
      stalls it and scores better than one that completes it; the default episode ignores the seed.
    """

    Task = ZigZagTask
    env_name = "ZigZag-v0"


class ZigZagVectorEnv(ShipVectorEnv):
    """Native vector version of :class:`ZigZagEnv` (one simulation of ``num_envs`` ships)."""

    Env = ZigZagEnv


class ZigZagV1Env(ShipEnv):
    """Course-changing autopilot around the IMO zig-zag manoeuvre, with honest overshoot accounting.

    ## Description

    A ship starts in a steady straight approach on a seeded original course and holds it until the first
    course change (seeded time in ``first_change_s``); from then on its target heading changes by a
    schedule, and the agent, holding the helm, should bring the ship onto each new target quickly, with
    little overshoot, rudder activity and speed loss.

    * ``schedule="imo"`` (``vessel_gym/ZigZag-v1``): the target alternates between ``original course +
      psi`` and ``original course - psi`` (first side seeded), changing when the heading reaches the
      current target (the IMO MSC.137(76) execute) or, at the latest, ``leg_time_limit_s`` after the last
      change (default 10 L / U_T, 59 s for ``kvlcc2_l7``, where the IMO 10/10 rule needs up to 6.7 L / U_T and a
      PID helm 2-3.3 L / U_T from one course change to the next). So the schedule
      cannot be stalled by stopping short of a target.
    * ``schedule="random"`` (``vessel_gym/ZigZagRandom-v1``, :class:`ZigZagRandomEnv`): course changes of
      ``course_change_deg`` either side every ``leg_time_s`` seconds (drawn with the reset seed).

    A target counts as reached when the heading reaches or passes it (:func:`vessel_gym.control.zigzag.
    target_reached`, the IMO execute); a helm that approaches it asymptotically from one side never
    reaches it. Overshoot is measured per course change (``OVERSHOOT_V1`` of :mod:`vessel_gym.control.zigzag`):
    the largest excursion past the change's target from the moment it is reached until the measurement is
    closed when the next course change starts (IMO schedule: the change after the one the execute
    starts). A course change whose target is never reached has overshoot 0; a measurement still open at
    the end of the episode counts with what it has, in the reward and in ``info`` alike.

    Default ship: ``kvlcc2_l7`` (7 m KVLCC2 model, 1.18 m/s test speed, L / U_T = 5.9 s), physics step and
    control interval 0.25 s.

    ## Action Space

    As ZigZag-v0: ``Box(-1, 1, (1,))`` rudder order x rudder limit (+ starboard); ``(2,)`` with
    ``engine_control`` (engine order x full ahead / full astern rpm); clipped; NaN raises.
    ``action_type="discrete"``: helm orders (x telegraph steps).

    ## Observation Space

    As ZigZag-v0 (``Box(-1, 1, (8,), float32)`` normalized): u, v, r, rudder, rudder_order, (rev),
    heading_error (target - heading), heading_deviation (heading - original course), target_deviation
    (target - original course). The original course itself is not observed (the task is the same on every
    course), nor are the disturbances (only their effect on the motion).

    ## Rewards

    reward = sum of weight x term (config ``reward``); weighted terms in ``info["reward_terms"]``. psi_ref
    is the overshoot scale: ``zigzag_heading_deg`` (IMO) or the smallest ``course_change_deg`` (random).

    | Term | Default weight | Value per step |
    |------|----------------|----------------|
    | heading_error | 1.0 | -abs(target - heading) / pi |
    | overshoot | 1.0 | -(growth this step of the current course change's overshoot) / psi_ref |
    | target_reached | 1.0 | at the step a target is reached: +abs(course change) / pi x 5 (L / U_T) / control interval |
    | rudder_activity | 0.1 | -abs(change of rudder order) / (2 x rudder limit) |
    | speed_loss | 0.1 | -max(0, U0 - U) / U0 |

    Over an episode the overshoot term sums to -(sum of the overshoots per course change, the open one
    included) / psi_ref. The target_reached bonus equals the heading_error charge of a turn whose error
    falls linearly to zero in 10 L / U_T, the IMO leg time limit: a helm that reaches a target earns
    about what the turn costs it or more, so no helm gains by stopping short of a target or never reaching
    it, and in the IMO schedule completing more course changes pays (``tests/envs/test_zigzag_v1.py``
    ranks a completing PID helm above helms that aim 0.5-2 deg short and above timid helms, on both
    schedules). The speed-loss weight is 0.1 (v0: 0.5, under which the speed every turn costs outweighed
    the heading error and a helm that turned less scored better).

    ## Starting State

    Steady straight approach at ``approach_speed_m_s`` (default the test speed), rudder amidships,
    original course uniform in ``initial_heading_deg`` (default 0-360 deg), at the origin. IMO first side
    ``first_side`` (default random); first course change at a time uniform in ``first_change_s``
    (default 0-10 s). Calm water unless the disturbance ranges are set: ``wind_speed_m_s`` /
    ``wind_from_rel_deg``, ``current_speed_m_s`` / ``current_to_rel_deg``, ``Hs_m`` / ``Tp_s`` /
    ``wave_from_rel_deg`` (directions relative to the original course; wind and waves from, current
    towards) are drawn per episode with the reset seed and set as the vessel's environment in the
    simulation before the steady approach is solved. Wind and waves need a ship with ``[windage]`` /
    ``[wave_drift]`` tables (``kvlcc2``, ``mariner``, ``dtc``; the default ``kvlcc2_l7`` tank model has
    neither): on a ship without, construction raises ``SpecError``. All of these come from the reset
    seed: seeds give different episodes.

    ## Episode End

    * Termination: the simulation diverged (``info["diverged"]``).
    * Truncation: 480 steps (120 s) by the registered time limit.

    ## Success

    ``info["is_success"]`` (and ``info["success"]``, the same): no course change has ended with its target
    unreached, at least one target has been reached, and the overshoot per course change (the open one
    included) is at most ``success_overshoot_deg`` (default psi_ref / 2: 5 deg on the 10 deg IMO
    schedule). Read at the end of the episode (SB3's ``Monitor`` does), it says the helm completed the
    schedule with small overshoot; the current course change, still running at the time limit, is not
    held against it.

    ## Info

    ``reward_terms``, ``time_s``, ``target_heading_deg``, ``heading_error_deg``, ``course_changes``
    (started so far), ``targets_reached``, ``targets_missed`` (course changes ended unreached),
    ``overshoot_deg`` (overshoot per course change: the sum of the overshoots, the open measurement
    included, / course changes), ``max_overshoot_deg``, ``overshoot_1_deg`` and ``overshoot_2_deg``
    (the first two closed measurements: in the IMO schedule the IMO first and second overshoot angles,
    sampled at the control steps; 0 until closed), ``is_success``, ``success``, ``diverged``.

    ## Arguments

    ``gymnasium.make("vessel_gym/ZigZag-v1", render_mode=None, config=None, **overrides)``; config class
    :class:`ZigZagV1Config` (strict, as ZigZag-v0). Keys: the shared ones, ``schedule``,
    ``zigzag_heading_deg``, ``first_side``, ``first_change_s``, ``leg_time_limit_s``,
    ``course_change_deg``, ``leg_time_s``, ``approach_speed_m_s``, ``initial_heading_deg``, the
    disturbance ranges above, ``success_overshoot_deg``, ``reward``.
    ``reset(options={"heading_deg": ..., "speed_m_s": ...})`` fixes the start.

    ## Vectorized environment

    ``gymnasium.make_vec("vessel_gym/ZigZag-v1", num_envs=N)`` (:class:`ZigZagV1VectorEnv`; and
    ``ZigZagRandom-v1``, :class:`ZigZagRandomVectorEnv`): one simulation of N ships, the same task code;
    vessel k seeded with ``seed + k`` follows the single environment seeded so.

    ## Version History

    * v1: overshoot measured per course change and closed when the next change starts, the open one
      counted at the end (v0 charged a running measurement against a target the ship had left behind and
      counted only finished ones); IMO leg time limit; seeded original course, first side and first change
      time; target_reached term, speed-loss weight 0.1; wind, current and waves; ``is_success``; the
      random schedule registered as ``ZigZagRandom-v1``.
    * v0: initial version (:class:`ZigZagEnv`, deprecated).
    """

    Task = ZigZagV1Task
    env_name = "ZigZag-v1"


class ZigZagV1VectorEnv(ShipVectorEnv):
    """Native vector version of :class:`ZigZagV1Env` (one simulation of ``num_envs`` ships)."""

    Env = ZigZagV1Env


class ZigZagRandomEnv(ZigZagV1Env):
    """ZigZag-v1 with the random course-change schedule as its default (``schedule="random"``): course
    changes of ``course_change_deg`` (10-40 deg, either side) every ``leg_time_s`` (20-40 s), the first after
    ``first_change_s``. Everything else, the reward, the overshoot accounting and success included, is
    :class:`ZigZagV1Env`'s; see its docstring."""

    Task = ZigZagRandomTask
    env_name = "ZigZagRandom-v1"


class ZigZagRandomVectorEnv(ShipVectorEnv):
    """Native vector version of :class:`ZigZagRandomEnv`."""

    Env = ZigZagRandomEnv
