"""ZigZag environment: a course-changing autopilot task built around the IMO zig-zag manoeuvre.

The environment class and its spec sheet; the task (declaration, presets ``ZigZag-v1`` and ``ZigZagRandom-v1``,
configuration, reset and compiled step) is :mod:`vessel_gym.envs.tasks.zigzag`.
"""

from __future__ import annotations

from vessel_gym.envs.env import ShipEnv, ShipVectorEnv
from vessel_gym.envs.tasks.zigzag import ZigZagTask

__all__ = ["ZigZagEnv", "ZigZagVectorEnv"]


class ZigZagEnv(ShipEnv):
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
    * ``schedule="random"`` (``vessel_gym/ZigZagRandom-v1``: the preset ``schedule="random"``): course changes of
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

    ``Box(-1, 1, (1,))`` rudder order x rudder limit (+ starboard); ``(2,)`` with
    ``engine_control`` (engine order x full ahead / full astern rpm); clipped; NaN raises.
    ``action_type="discrete"``: helm orders (x telegraph steps).

    ## Observation Space

    ``Box(-1, 1, (8,), float32)`` normalized (value / scale, clipped; SI values with ``"physical"``): u, v, r, rudder, rudder_order, (rev),
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
    :class:`~vessel_gym.envs.tasks.zigzag.ZigZagConfig` (strict: unknown keys and out-of-range values raise ``SpecError``). Keys: the shared ones, ``schedule``,
    ``zigzag_heading_deg``, ``first_side``, ``first_change_s``, ``leg_time_limit_s``,
    ``course_change_deg``, ``leg_time_s``, ``approach_speed_m_s``, ``initial_heading_deg``, the
    disturbance ranges above, ``success_overshoot_deg``, ``reward``.
    ``reset(options={"heading_deg": ..., "speed_m_s": ...})`` fixes the start.

    ## Vectorized environment

    ``gymnasium.make_vec("vessel_gym/ZigZag-v1", num_envs=N)`` (:class:`ZigZagVectorEnv`; and
    ``ZigZagRandom-v1``): one simulation of N ships, the same task code;
    vessel k seeded with ``seed + k`` follows the single environment seeded so.

    ## Version History

    * v1: overshoot measured per course change and closed when the next change starts, the open one
      counted at the end (v0 charged a running measurement against a target the ship had left behind and
      counted only finished ones); IMO leg time limit; seeded original course, first side and first change
      time; target_reached term, speed-loss weight 0.1; wind, current and waves; ``is_success``; the
      random schedule registered as ``ZigZagRandom-v1``.
    * v0: initial version; removed (``gymnasium.make("vessel_gym/ZigZag-v0")`` raises ``DeprecatedEnv`` naming
      ``ZigZag-v1``).

    Both ids are presets of the one task :class:`~vessel_gym.envs.tasks.zigzag.ZigZagTask` (its
    ``register_task`` declaration): ``ZigZagRandom-v1`` is ``ZigZag-v1`` with ``schedule="random"``.
    """

    Task = ZigZagTask
    env_name = "ZigZag"


class ZigZagVectorEnv(ShipVectorEnv):
    """Native vector version of :class:`ZigZagEnv` (one simulation of ``num_envs`` ships)."""

    Env = ZigZagEnv
