"""The HarbourApproach environments (:class:`HarbourApproachEnv`, :class:`HarbourApproachVectorEnv`) over the
task of :mod:`vessel_gym.envs.tasks.harbour`, whose declaration names them as its entry points; their
docstrings are the spec sheet, and they add the curriculum hook and the charted depth to the shared
environments.
"""

from __future__ import annotations

from typing import Any

from vessel_gym.envs.env import ShipEnv, ShipVectorEnv
from vessel_gym.envs.tasks.harbour import HarbourApproachTask


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
    | time | 0.5 | -control interval x U_T / L: -1 per time the ship sails its length |
    | success | 50.0 | +1 on arrival |
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

    ``gymnasium.make("vessel_gym/HarbourApproach-v2", render_mode=None, config=None, scenario="harbour",
    **overrides)``: ``scenario`` is a built-in name, a TOML path or a :class:`~vessel_gym.scenarios.Scenario`;
    further keys: the shared ones (``ship`` overrides the scenario's, ``dt_s``, ``control_interval_s`` (0.25),
    ``action_type``, ``engine_control`` (True), ``rudder_orders_deg``, ``telegraph_steps``,
    ``observation_type``, ...), ``n_beams`` (16), ``beam_range_L`` (10), ``slow_down_L`` (8),
    ``safe_clearance_L`` (0.5), ``reward``. Strict: unknown keys raise ``SpecError``.
    ``reset(options={"north_m", "east_m", "heading_deg", "speed_m_s", "environment"})`` fixes the start.

    ## HarbourApproach-v1

    What v1 changed from v0 (removed), which the sections above do not say: Built-in scenarios ``harbour``, ``harbour_east``, ``harbour_channel``; or a
    generated harbour (``layout="procedural"``, :mod:`vessel_gym.scenarios.generator`), whose ``eval`` split
    is held out for evaluation. Wind acts on the ship: the default ship ``kvlcc2_l7_windage`` is the L7 model
    with a Froude-scaled windage table (an estimate); ``kvlcc2_l7`` itself, as tested in the tank, has none.

    Control interval L / U_T / 6 of the ship (0.99 s for ``kvlcc2_l7``; 4 RK4 steps of 0.2475 s).

    Rewards:
    As v0, except ``time`` (weight 0.5): -control interval x U_T / L per step (time in ship time scales),
    and ``success`` weight 50.

    Starting state:
    ``difficulty`` 3 (``open``, default): the scenario's ``[start]`` region, as v0. 0 ``basin``, 1
    ``entrance``, 2 ``approach``: on the scenario's track with 25 %, 45 % or 70 % of its length to go, spread
    +-5 % along and +-0.5 L across it, heading along it +-10 deg, at 50-90 % of the allowed speed there.
    Wind, current and waves uniform in the scenario's ``[weather]``, drawn by the reset seed.

    Episode end:
    As v0; truncation after ``time_limit_s`` (default 100 L / U_T: 590 s, 596 steps, for ``kvlcc2_l7``),
    counted by this environment (no step-count TimeLimit is registered).

    Arguments:
    ``gymnasium.make("vessel_gym/HarbourApproach-v1", difficulty=3, scenario="harbour", layout="scenario",
    layout_split="train", layout_index=0, control_interval_s=None, time_limit_s=None, **overrides)`` (v0
    keys otherwise). Curriculum hook: ``env.unwrapped.set_difficulty(k)`` (index or name), effective from
    the next reset; vector env: ``venv.set_difficulty(k)`` or ``venv.call("set_difficulty", k)``.

    ## HarbourApproach-v2 (the config defaults)

    The v1 task (actions, observations, rewards, start, episode end, ``info``, arguments and curriculum hook
    unchanged), with two changes of the dynamics (config ``ship`` and ``chart_depth``; the preset
    ``HarbourApproach-v1`` sets ``ship="kvlcc2_l7_windage"``, ``chart_depth=False``):

    * the default ship ``kvlcc2_l7_harbour``: ``kvlcc2_l7_windage`` plus the cross-flow hull at large drift
      (``[large_drift]``, Yoshimura et al. 2009): at large drift, in sternway and turning on the spot the hull
      forces stay physical where the MMG polynomial runs away;
    * the water depth under each ship from the scenario's chart (``Scenario.depth_at`` of the midship point:
      the shallowest depth area containing it, else ``water_depth_m``), with the Taimuri et al. (2020)
      shallow-water corrections of the MMG hull, propeller and rudder. The depth is read after every reset and
      control step and acts over the next control step; depths between the draught and 1.2 T (the method's
      range ends at h/T = 1.2) act as h/T = 1.2. The chart's depth replaces that of an ``environment`` reset
      option. Grounding is v1's rule. The ship must have an MMG hull (others raise ``SpecError``).

    ``env.unwrapped.depth_m`` (vector env: ``venv.depth_m``, one per ship): the charted depth under each ship.

    ``gymnasium.make_vec("vessel_gym/HarbourApproach-v2", num_envs=N)``: :class:`HarbourApproachVectorEnv`.

    ## HarbourApproach-v3

    The v2 task (ship, physics, observations, start, episode end, ``info``) with a smooth helm by construction
    (config ``rudder_action="lag"``, ``rudder_lag_time_scales=1``, ``rudder_rate_fraction=0.25``, reward
    ``rudder_activity`` 0.5):

    * action 0 is the rudder asked for (x rudder limit, as v2); the rudder order in force follows it as a
      first-order lag of one ship time scale L / U_T (5.9 s on ``kvlcc2_l7``: 15.4 % of the gap closed per
      0.99 s control step), its change capped at 0.25 x the steering gear's max rate (3.9 deg/s on
      ``kvlcc2_l7``; 0.58 deg/s at full scale). The order in force is observed (``rudder_order``), so the
      state stays Markov. Action 1 (engine) as v2;
    * ``rudder_activity`` weighs 0.5 (v2: 0.05): hard over and back (70 deg of order changes) costs 0.5, a
      hundredth of the success bonus.

    The pilots (``pid``, ``pid-nomoto``, ``scripted``) give their orders through the same lag. Why a lag with a
    rate cap: docs/agents.md, "HarbourApproach-v3: the smooth helm".

    ## Version History

    * v3: the rudder order lags the action (one time scale, capped at a quarter of the gear's rate) and rudder
      changes are charged 10x; v2 unchanged.
    * v2: the cross-flow hull at large drift (default ship ``kvlcc2_l7_harbour``) and the depth from the chart
      with the shallow-water corrections; v1 unchanged.
    * v1: control interval and time limit from the ship's time scale, time charged per ship time scale,
      success 50, difficulty levels, wind with force, three built-in harbours and procedural layouts.
    * v0: initial version; removed (``gymnasium.make("vessel_gym/HarbourApproach-v0")`` raises
      ``DeprecatedEnv`` naming ``HarbourApproach-v2``). Its reward weights (time 0.01 per step, success 20),
      0.25 s control interval and 1600-step limit are no longer a preset.
    """

    Task = HarbourApproachTask
    task: HarbourApproachTask
    env_name = "HarbourApproach"

    def __init__(self, render_mode: str | None = None, config: Any = None, **overrides: Any) -> None:
        super().__init__(render_mode, config, **overrides)
        self._max_steps = self.task.max_steps  # truncation after time_limit_s, counted by ShipEnv.step

    @property
    def difficulty(self) -> int:
        """Current difficulty level (0 basin .. 3 open)."""
        return self.task.difficulty

    def set_difficulty(self, level: int | str) -> None:
        """Curriculum hook: start region of the episodes reset from now on (index 0..3 or a name)."""
        self.task.set_difficulty(level)

    @property
    def depth_m(self) -> float:
        """Charted depth under the ship's midship point (m), as the physics sees it over the next control step
        (before the clamp to 1.2 x draught; the scenario's water depth without ``chart_depth``)."""
        return float(self.task.depth_m[0])


class HarbourApproachVectorEnv(ShipVectorEnv):
    """Native vector version of :class:`HarbourApproachEnv`; ``set_difficulty(k)`` (also through
    ``call("set_difficulty", k)``) applies to every sub-environment from its next reset on."""

    Env = HarbourApproachEnv
    task: HarbourApproachTask

    def __init__(self, num_envs: int = 1, max_episode_steps: int | None = None, **kwargs: Any) -> None:
        super().__init__(num_envs, max_episode_steps, **kwargs)
        if self.max_episode_steps is None:
            self.max_episode_steps = self.task.max_steps

    @property
    def difficulty(self) -> int:
        return self.task.difficulty

    def set_difficulty(self, level: int | str) -> None:
        self.task.set_difficulty(level)

    @property
    def depth_m(self) -> Any:
        """Charted depth under each ship's midship point (m), a copy (see :attr:`HarbourApproachEnv.depth_m`)."""
        return self.task.depth_m.copy()

    def call(self, name: str, *args: Any, **kwargs: Any) -> tuple:
        """Call method ``name`` (or read attribute ``name``) once; one result per sub-environment, as
        Gymnasium's ``SyncVectorEnv.call`` returns (the sub-environments share one task)."""
        attr = getattr(self, name)
        out = attr(*args, **kwargs) if callable(attr) else attr
        return (out,) * self.num_envs
