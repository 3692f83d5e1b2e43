"""The baselines of CollisionAvoidance, reading only the observation (as an agent does):

* :class:`RouteFollower` (``scripted``): line-of-sight guidance on the route and a heading PD autopilot,
  blind to the targets: the lower bound.
* :class:`VelocityObstaclePilot` (``pid``, ``pid-nomoto``): velocity obstacles with COLREG constraints after
  Kuwata, Wolf, Zarzhitsky and Huntsberger (2014), "Safe maritime autonomous navigation with COLREGS, using
  velocity obstacles", IEEE J. Oceanic Eng. 39(1), 110-119: among candidate headings (speed held), the one
  nearest the route's line of sight whose relative velocity to every target stays out of the target's
  collision cone (radius ``safe_L`` L) within ``horizon`` and, for a target the own ship must keep out of the
  way of (head-on, crossing give-way, overtaking), passes it on the rule's side (Kuwata's constraint: the
  relative velocity on the starboard side of the line of sight, so the target is left to port). A stand-on
  target is ignored until it is within ``release_range_L`` (rule 17(a)), then avoided without turning to
  port for a target on the port side (17(c)). When the line of sight is blocked by a give-way target, the
  alteration is at least ``substantial_deg`` (rule 8(b)). In restricted waters, with the range-sensor sweep
  observed (``sensors``), a heading whose sector reads land, a shoal or a hull nearer than ``land_L`` ship
  lengths is blocked too: the pilot keeps off the coast.

Everything is computed in the own ship's body frame (x forward, y starboard) from the target list.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from vessel_gym.control.angles import wrap_pi
from vessel_gym.envs.policies import PIDHeadingAutopilot

_wrap = wrap_pi.py_func  # elementwise on arrays, rad in [-pi, pi)
#: the target-slot fields the pilots read
_FIELDS = (
    "valid",
    "range",
    "bearing_sin",
    "bearing_cos",
    "rel_u",
    "rel_v",
    "tcpa",
    "head_on",
    "overtaking",
    "give_way",
    "stand_on",
)


class RouteFollower(PIDHeadingAutopilot):
    """Line of sight on the route (Fossen 2011 eq. 10.73, look-ahead ``lookahead_L`` ship lengths) and the
    heading PD of :class:`~vessel_gym.envs.policies.PIDHeadingAutopilot`; no collision avoidance."""

    def __init__(
        self, env: Any, Kp: float = 1.5, Ki: float = 0.0, Kd: float = 1.0, lookahead_L: float = 5.0
    ) -> None:
        super().__init__(env, Kp, Ki, Kd)
        self.lookahead = lookahead_L * self.L

    def los_error(self, obs: np.ndarray) -> np.ndarray:
        """Line-of-sight course - heading, rad (+ starboard)."""
        cross = self.get(obs, "cross_track")
        e = self.get(obs, "course_error") + np.arctan2(-cross, self.lookahead)
        return _wrap(e)

    def heading_error(self, obs: np.ndarray) -> np.ndarray:
        return self.los_error(obs)


class VelocityObstaclePilot(RouteFollower):
    """Velocity obstacles with COLREG constraints (Kuwata et al. 2014) over a fan of headings (module doc)."""

    def __init__(
        self,
        env: Any,
        Kp: float = 1.5,
        Ki: float = 0.0,
        Kd: float = 1.0,
        lookahead_L: float = 5.0,
        safe_L: float = 2.5,
        horizon_tcpa: float = 1.2,
        fan_deg: float = 90.0,
        step_deg: float = 2.5,
        land_L: float = 6.0,
    ) -> None:
        super().__init__(env, Kp, Ki, Kd, lookahead_L)
        task = env.unwrapped.task
        c = task.config
        self.safe = safe_L * self.L
        self.horizon = horizon_tcpa * c.tcpa_L * self.L / self.U_T
        self.release = c.release_range_L * self.L
        self.substantial = math.radians(c.substantial_deg)
        self.fan = np.radians(np.arange(-fan_deg, fan_deg + 1e-9, step_deg))  # route-relative headings
        self.K = c.observed_targets
        self.chosen: np.ndarray | None = None  # route-relative heading chosen at the last step, per row
        self.sensors = c.sensors
        self.land = land_L * self.L

    def reset(self, mask: np.ndarray | None = None) -> None:
        super().reset(mask)
        if mask is None or self.chosen is None:
            self.chosen = None
        else:
            self.chosen = np.where(mask, np.nan, self.chosen)

    def heading_error(self, obs: np.ndarray) -> np.ndarray:
        los = self.los_error(obs)
        o = np.atleast_2d(obs)
        l2 = np.atleast_1d(los)
        rows = o.shape[0]
        if self.chosen is None or self.chosen.shape != (rows,):
            self.chosen = np.full(rows, np.nan)
        out = np.array([self._choose(o[i], float(l2[i]), i) for i in range(rows)])
        return out if np.ndim(los) else out[0]

    def _targets(self, obs: np.ndarray) -> list[dict[str, float]]:
        out = []
        for j in range(self.K):
            t = {f: float(self.get(obs, f"t{j}_{f}")) for f in _FIELDS}
            if t["valid"] > 0.5:
                out.append(t)
        return out

    def _choose(self, obs: np.ndarray, los: float, i: int) -> float:
        psi_rel = -float(self.get(obs, "course_error"))  # heading - route course, rad
        u, v = float(self.get(obs, "u")), float(self.get(obs, "v"))
        speed = math.hypot(u, v)
        h = np.append(self.fan, psi_rel + los)  # candidate headings, route-relative
        c = _wrap(h - psi_rel)  # the same, relative to the bow
        vx, vy = speed * np.cos(c), speed * np.sin(c)
        cost = np.abs(_wrap(c - los)) / np.pi
        blocked = np.zeros(len(c))
        give_way_block = False
        for t in self._targets(obs):
            rng = t["range"]
            px, py = rng * t["bearing_cos"], rng * t["bearing_sin"]
            tx, ty = u + t["rel_u"], v + t["rel_v"]  # target's velocity in own body axes
            wx, wy = vx - tx, vy - ty  # own relative to target, per candidate
            w2 = np.maximum(wx * wx + wy * wy, 1e-9)
            tc = (px * wx + py * wy) / w2  # time of closest approach
            miss = np.hypot(px - wx * tc, py - wy * tc)
            conflict = (tc > 0.0) & (tc < self.horizon) & (miss < self.safe)
            give_way = t["head_on"] + t["give_way"] + t["overtaking"] > 0.5
            stand_on = t["stand_on"] > 0.5
            if stand_on and rng > self.release:
                continue  # rule 17(a): keep course and speed
            blocked += conflict
            if give_way and t["tcpa"] > 0.0 and conflict[-1]:  # the route's velocity needs avoiding
                cross = px * wy - py * wx  # > 0: the relative velocity passes the target on its port side
                if t["overtaking"] < 0.5:
                    blocked += (cross < 0.0) & (tc > 0.0)  # Kuwata's COLREG constraint
                give_way_block = True
            if stand_on and t["bearing_sin"] < 0.0:
                blocked += c < -math.radians(2.0)  # rule 17(c): no turn to port for a target on the port side
        if self.sensors:  # a heading into land, a shoal or a hull within land_L is blocked
            reads = np.array([float(self.get(obs, f"sensor{i}")) for i in range(self.sensors)])
            sector = np.rint((c % (2.0 * np.pi)) / (2.0 * np.pi / self.sensors)).astype(int) % self.sensors
            blocked += reads[sector] < self.land
        if give_way_block:  # rule 8(b): an alteration large enough to be readily apparent
            cost += (np.abs(_wrap(c - los)) < self.substantial) * 0.5
        assert self.chosen is not None  # sized by the caller, act(), before any choice
        prev = self.chosen[i]
        if math.isfinite(prev):
            cost += 0.2 * np.abs(h - prev) / np.pi  # hold a choice rather than chatter
        best = int(np.argmin(cost + 10.0 * blocked))
        self.chosen[i] = h[best]
        return float(c[best])
