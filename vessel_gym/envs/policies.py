"""Scripted reference helms and classical baselines as policies: ``action = policy(observation)``.

Each policy reads the observation through the environment's :class:`~vessel_gym.envs.observation.ObservationLayout`
(so it sees exactly what an agent sees, in either observation type) and returns an action in the
environment's action type (continuous or discrete helm). Observations may be one (obs_dim,) vector or a
batch (N, obs_dim) from a vector environment; stateful policies keep one state per row (``reset(mask)``).

* :class:`ZigZagRule`: the IMO zig-zag rule in ``ZigZag-v1`` (rudder to the side of the
  current target).
* :class:`TurningRule`: a constant rudder (the IMO 35-degree turning circle) in ``TurningCircle-v0``.
* :class:`PIDHeadingAutopilot`: PID on heading error with rate-of-turn damping (ZigZag, HarbourApproach).
* :class:`HarbourPilot`: line-of-sight PID steering and a distance-scheduled engine order (HarbourApproach).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from gymnasium import spaces

from vessel_gym.control.angles import wrap_pi
from vessel_gym.control.guidance import pursuit_heading, waypoint_reached
from vessel_gym.control.pid import pid_integral_batch, pid_rudder_batch
from vessel_gym.physics.units import DEG


class HelmPolicy:
    """Base: knows the environment's observation layout and action type."""

    def __init__(self, env: Any) -> None:
        base = env.unwrapped
        self.layout = base.observation_layout
        self.config = base.config
        task = base.task
        self.rudder_limit_rad = float(getattr(task.helm, "rudder_limit_rad", np.array([task.delta_max]))[0])
        self.engine = bool(self.config.engine_control)
        self.discrete = self.config.action_type == "discrete"
        self.space = base.single_action_space if hasattr(base, "single_action_space") else base.action_space
        self.dt = float(self.config.control_interval_s)
        self.L = task.L
        self.U_T = task.U_T
        self.rev_full_ahead = float(task.helm.rev_table[0, 8])
        if self.discrete:
            self.orders = np.asarray(self.config.rudder_orders_deg) * DEG
            self.steps = np.asarray(self.config.telegraph_steps)

    def reset(self, mask: np.ndarray | None = None) -> None:
        """Forget controller state (of the rows in ``mask``, default all)."""

    def get(self, obs: np.ndarray, name: str) -> np.ndarray:
        return self.layout.value(obs, name)

    def action(self, rudder_rad: np.ndarray, engine: np.ndarray | None = None) -> np.ndarray:
        """Helm order(s) -> action(s): rudder in rad (+ starboard), engine in [-1, 1] (fraction of full)."""
        rudder = np.asarray(rudder_rad, dtype=np.float64)
        eng = (
            np.zeros_like(rudder)
            if engine is None
            else np.broadcast_to(np.asarray(engine, float), rudder.shape)
        )
        if not self.discrete:
            a = np.clip(rudder / self.rudder_limit_rad, -1.0, 1.0)
            cols = [a, np.clip(eng, -1.0, 1.0)] if self.engine else [a]
            return np.stack(cols, axis=-1).astype(np.float32)
        i = np.abs(rudder[..., None] - self.orders).argmin(axis=-1)
        if not self.engine:
            return i if i.ndim else np.int64(i)
        j = np.abs(np.rint(eng * 4.0)[..., None] - self.steps).argmin(axis=-1)
        return np.stack([i, j], axis=-1).astype(np.int64)

    def hold_engine(self, obs: np.ndarray) -> np.ndarray | None:
        """Engine action that keeps the present shaft speed (for policies that only steer)."""
        if not self.engine:
            return None
        return self.get(obs, "rev") / self.rev_full_ahead


class ZigZagRule(HelmPolicy):
    """The IMO zig-zag: rudder ``rudder_deg`` to the side of the current target heading.

    In ``ZigZag-v1`` with ``schedule="imo"`` the target flips when the heading reaches it, so this policy
    performs the psi/delta zig-zag test (default delta = psi = ``zigzag_heading_deg``), the execute being
    detected at the control step after the heading passes the target.
    """

    def __init__(self, env: Any, rudder_deg: float | None = None) -> None:
        super().__init__(env)
        self.rudder_rad = (rudder_deg if rudder_deg is not None else self.config.zigzag_heading_deg) * DEG

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        side = np.sign(self.get(obs, "target_deviation"))
        return self.action(side * self.rudder_rad, self.hold_engine(obs))


class TurningRule(HelmPolicy):
    """A constant rudder order: the IMO turning circle with ``rudder_deg`` = 35 (or the gear limit).

    ``side``: +1 starboard, -1 port; default the side of the commanded turn where the observation has one,
    else starboard.
    """

    def __init__(self, env: Any, rudder_deg: float = 35.0, side: float | None = None) -> None:
        super().__init__(env)
        self.rudder_rad = min(rudder_deg * DEG, self.rudder_limit_rad)
        self.side = side

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        obs = np.asarray(obs)
        if self.side is not None:
            side = np.full(obs.shape[:-1], float(self.side))
        else:
            side = np.ones(obs.shape[:-1])
            for name in ("commanded_rate", "commanded_curvature"):
                if name in self.layout.names:
                    side = np.where(self.get(obs, name) < 0.0, -1.0, 1.0)
        return self.action(side * self.rudder_rad, self.hold_engine(obs))


class PIDHeadingAutopilot(HelmPolicy):
    """Heading autopilot: rudder = Kp e + Ki integral(e) - Kd r, clipped to the rudder limit.

    e is the heading error (ZigZag: to the target; HarbourApproach: to the line of sight to the goal
    point). Gains are nondimensional on the ship: Kd and 1/Ki in units of L / U_T seconds. The law is
    :func:`vessel_gym.control.pid.pid_rudder` (batched); the integral is always integrated and held within
    +-1 rad s.
    """

    def __init__(self, env: Any, Kp: float = 1.5, Ki: float = 0.0, Kd: float = 1.0) -> None:
        super().__init__(env)
        T = self.L / self.U_T
        self.Kp, self.Ki, self.Kd = Kp, Ki / T, Kd * T
        self.integral: np.ndarray | float = 0.0

    def reset(self, mask: np.ndarray | None = None) -> None:
        if mask is None or np.ndim(self.integral) == 0:
            self.integral = 0.0
        else:
            self.integral = np.where(mask, 0.0, self.integral)

    def heading_error(self, obs: np.ndarray) -> np.ndarray:
        if "heading_error" in self.layout.names:
            return self.get(obs, "heading_error")
        return np.arctan2(self.get(obs, "goal_y"), self.get(obs, "goal_x"))

    def rudder(self, obs: np.ndarray) -> np.ndarray:
        e = self.heading_error(obs)
        self.error = e  # the last heading error the rudder answered (rad)
        self.integral = pid_integral_batch(self.integral, e, self.dt, 1.0, np.inf)
        r = self.get(obs, "r")
        return pid_rudder_batch(e, self.integral, r, self.Kp, self.Ki, self.Kd, self.rudder_limit_rad)

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        return self.action(self.rudder(obs), self.hold_engine(obs))


class HarbourPilot(PIDHeadingAutopilot):
    """HarbourApproach baseline: follow the scenario's ``route_m`` and then the goal point by line of sight
    (turning to the goal heading in the last ship lengths), with speed ordered by the distance to go and
    astern to stop in the goal area. Its own position and heading it reconstructs from the observed goal
    bearing and heading error and the charted goal point (a pilot with local knowledge). Guidance: pursuit
    of the next waypoint, passed within ``accept_L`` ship lengths (:mod:`vessel_gym.control.guidance`).

    Kick ahead (``kick_ahead``, a fraction of full ahead): when the rudder is hard over, the heading error
    exceeds ``kick_error_deg`` and the ship does not answer (it turns toward the wanted heading at less than
    ``answer_rate`` U_T / L), the engine order is raised to at least ``kick_ahead`` for that control step, so
    that the propeller's race over the rudder gives the steering the speed through the water cannot (a
    harbour pilot's kick ahead). Default: on (0.5, half ahead) in an environment whose physics takes the
    water depth from the chart (HarbourApproach-v2), where the shallow basin changes the ship's yaw response
    and the swing that the slow ship's rudder cannot check in the wake alone; off (0) otherwise, which leaves
    the pilot of HarbourApproach-v1 as it was (docs/envs.md, HarbourApproach-v2)."""

    def __init__(
        self,
        env: Any,
        Kp: float = 1.5,
        Ki: float = 0.0,
        Kd: float = 1.0,
        slow_L: float = 12.0,
        approach: float = 0.6,
        accept_L: float = 2.0,
        speed_gain: float = 4.0,
        kick_ahead: float | None = None,
        kick_error_deg: float = 10.0,
        answer_rate: float = 0.01,
    ) -> None:
        super().__init__(env, Kp, Ki, Kd)
        sc = env.unwrapped.task.scenario
        self.goal_speed = sc.goal.max_speed_m_s
        self.goal_point = np.array(sc.goal_point)
        self.goal_heading = math.radians(sc.goal.heading_deg)
        self.route = np.array([(p[0], p[1]) for p in sc.route_m] + [sc.goal_point], dtype=np.float64)
        self.slow = slow_L * self.L
        self.approach = approach
        self.accept = accept_L * self.L
        self.speed_gain = speed_gain
        if kick_ahead is None:
            kick_ahead = 0.5 if getattr(env.unwrapped.task, "depth_from_chart", False) else 0.0
        if not 0.0 <= kick_ahead <= 1.0:
            raise ValueError(f"kick_ahead: {kick_ahead:g} must be in [0, 1] (fraction of full ahead)")
        self.kick_ahead = float(kick_ahead)
        self.kick_error = math.radians(kick_error_deg)
        self.answer_rate = answer_rate * self.U_T / self.L  # rad/s
        self.wp: np.ndarray | int = 0

    def reset(self, mask: np.ndarray | None = None) -> None:
        super().reset(mask)
        if mask is None or np.ndim(self.wp) == 0:
            self.wp = 0
        else:
            self.wp = np.where(mask, 0, self.wp)

    def _pose(self, obs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        psi = self.goal_heading - self.get(obs, "goal_heading_error")
        gx, gy = self.get(obs, "goal_x"), self.get(obs, "goal_y")
        c, s = np.cos(psi), np.sin(psi)
        return self.goal_point[0] - (c * gx - s * gy), self.goal_point[1] - (s * gx + c * gy), psi

    def heading_error(self, obs: np.ndarray) -> np.ndarray:
        n, e, psi = self._pose(obs)
        wp = np.broadcast_to(self.wp, np.shape(n)).copy()
        last = len(self.route) - 1
        for _ in range(last):  # advance past waypoints already reached
            tgt = self.route[wp]
            # reached, or passed: ahead of the line through the waypoint square to the next leg (a ship
            # starting inside the harbour does not turn back for the outer waypoints)
            nxt = self.route[np.minimum(wp + 1, last)]
            passed = (n - tgt[..., 0]) * (nxt[..., 0] - tgt[..., 0]) + (e - tgt[..., 1]) * (
                nxt[..., 1] - tgt[..., 1]
            ) > 0.0
            near = (waypoint_reached.py_func(n, e, tgt[..., 0], tgt[..., 1], self.accept) | passed) & (
                wp < last
            )
            if not np.any(near):
                break
            wp = np.where(near, wp + 1, wp)
        self.wp = wp
        tgt = self.route[wp]
        los = pursuit_heading.py_func(n, e, tgt[..., 0], tgt[..., 1])
        err = wrap_pi.py_func(los - psi)
        d = self.get(obs, "goal_distance")
        w = np.where(wp == last, np.clip((d - 0.5 * self.L) / (1.5 * self.L), 0.0, 1.0), 1.0)
        return w * err + (1.0 - w) * self.get(obs, "goal_heading_error")

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        d = self.get(obs, "goal_distance")
        sog = self.get(obs, "sog")
        want = np.maximum(self.U_T * self.approach * np.clip(d / self.slow, 0.0, 1.0), 0.5 * self.goal_speed)
        want = np.where(self.get(obs, "goal_x") < 0.0, 0.0, want)  # goal point abeam or astern: stop
        eng = np.clip(0.85 * want / self.U_T + self.speed_gain * (want - sog) / self.U_T, -1.0, 1.0)
        rudder = self.rudder(obs)
        if self.kick_ahead > 0.0:
            eng = self.kick(obs, rudder, eng)
        return self.action(rudder, eng if self.engine else None)

    def kick(self, obs: np.ndarray, rudder: np.ndarray, eng: np.ndarray) -> np.ndarray:
        """The engine order with the kick ahead (class docstring) where the ship does not answer its rudder."""
        e = self.error
        hard_over = np.abs(rudder) >= self.rudder_limit_rad * (1.0 - 1e-9)
        answering = self.get(obs, "r") * np.sign(e) > self.answer_rate
        return np.where(hard_over & (np.abs(e) > self.kick_error) & ~answering, np.maximum(eng, self.kick_ahead), eng)


def is_batch(space: spaces.Space, obs: np.ndarray) -> bool:
    """True if ``obs`` is a batch of observations of ``space``."""
    return np.ndim(obs) == len(space.shape) + 1
