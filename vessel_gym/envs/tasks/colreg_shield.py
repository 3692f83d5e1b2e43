"""A COLREG safety shield for CollisionAvoidance: a Gymnasium wrapper that changes the own ship's action, before
the step, where it would break a rule the observation shows to apply. It reads the observation only (the
target list's flags, bearings, TCPA and range), as the agent does.

What it guarantees, per control step, from the observation the action answers:

1. **No turn to port begun against a give-way or port-bow target** (rules 14(a), 15 with 8, 17(c)): while
   the list holds a target classified head-on or crossing give-way, or any target classified as a risk
   (a situation flag set) on the own port bow (relative bearing 270-360 deg), with TCPA > 0, the rudder
   order is not to port of amidships - except to check a swing to starboard (rate of turn > 0), where a
   port order down to the one the heading autopilot of the route follower would give is let through, so
   the ship is not driven into an endless starboard circle. So the ship never starts a turn to port then.
2. **Stand-on keeps course and speed** (rule 17(a)(i)): while the list holds a stand-on target (crossing
   from port, or overtaking the own ship) beyond ``release_range_L`` and no head-on or crossing give-way
   target, the action is replaced by a heading hold on the heading the ship had when this state began (the
   route follower's heading PD; the engine held at its present order). Inside the release range the agent acts freely (17(a)(ii), (b)),
   under guarantee 1.

It does not guarantee: that the alteration is early or substantial (rule 8), not crossing ahead (rule 15),
or any collision avoidance: the shield removes rule-breaking actions, it does not plan. The agent's
action outside those states is passed unchanged. ``info["shielded"]`` says whether the step's action was
changed. Continuous actions only (``action_type="continuous"``); a discrete action space raises.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np

from vessel_gym.envs.tasks.colreg_pilots import RouteFollower


class ColregShield(gym.Wrapper):
    """The COLREG safety shield (module doc) around a ``CollisionAvoidance`` env."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        base: Any = env.unwrapped  # a CollisionAvoidance ShipEnv (its config, layout and task)
        if base.config.action_type != "continuous":
            raise ValueError("ColregShield: takes continuous actions (action_type='continuous')")
        self.layout = base.observation_layout
        self.K = base.task.config.observed_targets
        self.release = base.task.config.release_range_L * base.task.L
        self.follower = RouteFollower(env)
        self.obs: np.ndarray | None = None
        self.held: float | None = None  # course error (route course - heading, rad) kept while standing on

    def reset(self, **kwargs: Any):
        obs, info = self.env.reset(**kwargs)
        self.obs = obs
        self.held = None
        self.follower.reset()
        return obs, info

    def _get(self, name: str) -> float:
        return float(self.layout.value(self.obs, name))

    def state(self) -> tuple[bool, bool]:
        """(no port turn: guarantee 1 applies, stand on: guarantee 2 applies) at the last observation."""
        no_port = give_way = False
        stand_on = False
        for j in range(self.K):
            f = f"t{j}_"
            if self._get(f + "valid") < 0.5 or self._get(f + "tcpa") <= 0.0:
                continue
            flags = {k: self._get(f + k) > 0.5 for k in ("head_on", "give_way", "overtaking", "stand_on")}
            port_bow = self._get(f + "bearing_sin") < 0.0 and self._get(f + "bearing_cos") > 0.0
            give_way = give_way or flags["head_on"] or flags["give_way"]
            if flags["head_on"] or flags["give_way"] or (any(flags.values()) and port_bow):
                no_port = True
            if flags["stand_on"] and self._get(f + "range") > self.release:
                stand_on = True
        return no_port, stand_on and not give_way

    def shield(self, action: np.ndarray) -> np.ndarray:
        """The action the shield lets through for the last observation."""
        assert self.obs is not None, "reset() first"
        a = np.array(action, dtype=np.float32, copy=True)
        no_port, stand_on = self.state()
        hold = np.asarray(self.follower(self.obs), dtype=np.float32)
        if stand_on:
            ce = self._get("course_error")
            if self.held is None:
                self.held = ce
            f = self.follower
            e = ce - self.held  # rad: the held heading - the heading (+ starboard)
            rudder = np.clip(f.Kp * e - f.Kd * self._get("r"), -f.rudder_limit_rad, f.rudder_limit_rad)
            return np.asarray(f.action(np.float64(rudder), f.hold_engine(self.obs)), dtype=np.float32)
        self.held = None
        if no_port and a[0] < 0.0:
            # a port order only to check a starboard swing, and no more than the autopilot's
            a[0] = max(a[0], min(hold[0], 0.0)) if self._get("r") > 0.0 else 0.0
        return a

    def step(self, action: Any):
        a = self.shield(action)
        obs, reward, terminated, truncated, info = self.env.step(a)
        info = dict(info)
        info["shielded"] = bool(np.any(a != np.asarray(action, dtype=np.float32)))
        self.obs = obs
        return obs, reward, terminated, truncated, info
