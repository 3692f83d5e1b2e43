"""Scenario-based MPC (``mpc``), a CollisionAvoidance baseline after Johansen, Perez and Cristofaro (2016),
"Ship collision avoidance and COLREGS compliance using simulation-based control behavior selection with
predictive hazard assessment", IEEE Trans. Intell. Transp. Syst. 17(12), 3407-3422.

A finite set of control behaviours, each a course offset chi from the route's line of sight (``offsets_deg``,
-90..+90 deg) and a speed factor P (``speed_factors``: 1, 0.5, 0 of the present engine order; with the
rudder alone, ``engine_control`` off, only P = 1), is predicted over a horizon and the cheapest chosen every
``interval_s`` seconds (held between choices). Reading only the observation, as an agent does (the body
frame of the target list, docs/colreg.md).

Prediction (simple, as the paper's own "simplified" predictions): each target straight on at its observed
velocity; the own ship on its present heading until the turn to the new course is done (at ``turn_rate_L``
U/L rad/s) and straight on that course after, its speed decaying from U to P U with time constant
``speed_time_L`` L/U (a large ship does not stop at once).

Cost of a behaviour (the paper's eq. (4), with our weights): the worst over targets i and predicted times t of

    C_i(t) R_i(t) + kappa mu_i

plus the deviation f = k_P (1 - P) + k_chi chi^2 (k_chi larger to port than to starboard) and the change
g = k_dP |P - P_last| + k_dchi (chi - chi_last)^2. The collision risk R_i(t) = (d_safe / d_i(t))^q /
(1 + t / T) inside ``safe_L`` ship lengths (0 outside), weighted by C_i = (|v_own - v_i| / U)^2 (a collision
at a high closing speed is worse). The COLREG penalty mu_i (1 where a rule is broken, else 0) for a target
classified as (the situation flags):

* head-on or crossing give-way: an offset to port (rules 14, 15 with 8); for crossing give-way also passing
  ahead of the target (the predicted own ship forward of its beam at the closest point, rule 15);
* these and overtaking (rule 13 leaves the side free): an alteration of less than ``substantial_deg`` while
  the line of sight is in conflict counts half (rule 8(b));
* stand-on: any offset or speed change while the target is beyond ``release_range_L`` (rule 17(a)(i)), where
  its collision risk is not counted (the other ship is to keep out of the way); an offset to port for a
  target on the port side at any range (17(c)).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from vessel_gym.envs.tasks.colreg_pilots import _FIELDS, RouteFollower, _wrap


class ScenarioMPCPilot(RouteFollower):
    """Scenario-based MPC with COLREG penalties (Johansen et al. 2016; module doc)."""

    def __init__(
        self,
        env: Any,
        Kp: float = 1.5,
        Ki: float = 0.0,
        Kd: float = 1.0,
        lookahead_L: float = 5.0,
        offsets_deg: tuple[float, ...] = tuple(range(-90, 91, 15)),
        speed_factors: tuple[float, ...] = (1.0, 0.5, 0.0),
        interval_s: float = 30.0,
        horizon_tcpa: float = 1.2,
        step_s: float = 20.0,
        safe_L: float = 2.5,
        q: float = 2.0,
        kappa: float = 2.0,
        k_p: float = 1.0,
        k_chi_starboard: float = 0.5,
        k_chi_port: float = 1.0,
        k_dp: float = 0.3,
        k_dchi: float = 0.3,
        turn_rate_L: float = 0.3,
        speed_time_L: float = 15.0,
    ) -> None:
        super().__init__(env, Kp, Ki, Kd, lookahead_L)
        c = env.unwrapped.task.config
        T = c.tcpa_L * self.L / self.U_T  # s, the time to the meeting point
        self.horizon_T = T
        self.t = np.arange(step_s, horizon_tcpa * T + 1e-9, step_s)  # s, predicted times
        chi = np.radians(np.asarray(offsets_deg, dtype=float))
        P = np.asarray(speed_factors if self.engine else (1.0,), dtype=float)
        self.chi = np.repeat(chi, len(P))  # the behaviours: every offset with every speed factor
        self.P = np.tile(P, len(chi))
        self.every = max(1, round(interval_s / self.dt))  # control steps between choices
        self.safe = safe_L * self.L
        self.q, self.kappa = q, kappa
        self.k_p, self.k_sb, self.k_port, self.k_dp, self.k_dchi = (
            k_p,
            k_chi_starboard,
            k_chi_port,
            k_dp,
            k_dchi,
        )
        self.turn_rate = turn_rate_L * self.U_T / self.L  # rad/s
        self.speed_time = speed_time_L * self.L / self.U_T  # s
        self.release = c.release_range_L * self.L
        self.substantial = math.radians(c.substantial_deg)
        self.K = c.observed_targets
        self.state: dict[
            int, list[float]
        ] = {}  # per row: [steps since the choice, chi, P, engine order at start]

    def reset(self, mask: np.ndarray | None = None) -> None:
        super().reset(mask)
        if mask is None:
            self.state = {}
        else:
            for i in np.flatnonzero(np.atleast_1d(mask)):
                self.state.pop(int(i), None)

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        o = np.atleast_2d(obs)
        los = np.atleast_1d(self.los_error(obs))
        err = np.empty(o.shape[0])
        eng = np.empty(o.shape[0])
        for i in range(o.shape[0]):
            err[i], eng[i] = self._step(o[i], float(los[i]), i)
        self.error = err
        self.integral = 0.0
        r = np.atleast_1d(self.get(o, "r"))
        rudder = np.clip(self.Kp * err - self.Kd * r, -self.rudder_limit_rad, self.rudder_limit_rad)
        engine = eng if self.engine else None
        if np.ndim(obs) == 1:
            return self.action(rudder[0], None if engine is None else engine[0])
        return self.action(rudder, engine)

    def _step(self, obs: np.ndarray, los: float, i: int) -> tuple[float, float]:
        """(heading error rad, engine order) of row i: a new behaviour every ``every`` steps, held between."""
        st = self.state.get(i)
        if st is None:
            rev = float(self.get(obs, "rev")) / self.rev_full_ahead if self.engine else 1.0
            st = self.state[i] = [self.every, 0.0, 1.0, rev]
        if st[0] >= self.every:
            st[1], st[2] = self.choose(obs, los, st[1], st[2])
            st[0] = 0
        st[0] += 1
        return float(_wrap(los + st[1])), st[2] * st[3]

    def _targets(self, obs: np.ndarray) -> list[dict[str, float]]:
        out = []
        for j in range(self.K):
            t = {f: float(self.get(obs, f"t{j}_{f}")) for f in _FIELDS}
            if t["valid"] > 0.5:
                out.append(t)
        return out

    def costs(self, obs: np.ndarray, los: float, chi_last: float, p_last: float) -> np.ndarray:
        """The cost of every behaviour (``self.chi``, ``self.P``) at this observation."""
        u, v = float(self.get(obs, "u")), float(self.get(obs, "v"))
        U = max(math.hypot(u, v), 0.1 * self.U_T)
        chi, P, t = self.chi[:, None], self.P[:, None], self.t[None, :]
        course = los + chi  # rad, relative to the bow
        # own ship: present heading until the turn is done, then the new course; speed decays to P U
        s = U * (P * t + (1.0 - P) * self.speed_time * (1.0 - np.exp(-t / self.speed_time)))  # m sailed
        t_turn = np.abs(course) / self.turn_rate
        s_turn = U * (P * t_turn + (1.0 - P) * self.speed_time * (1.0 - np.exp(-t_turn / self.speed_time)))
        s_turn = np.minimum(s_turn, s)
        ox = s_turn + (s - s_turn) * np.cos(course)
        oy = (s - s_turn) * np.sin(course)
        speed_end = U * (P + (1.0 - P) * np.exp(-t / self.speed_time))
        ovx, ovy = speed_end * np.cos(course), speed_end * np.sin(course)
        cost = self.k_p * (1.0 - self.P) + np.where(self.chi > 0.0, self.k_sb, self.k_port) * self.chi**2
        cost += self.k_dp * np.abs(self.P - p_last) + self.k_dchi * (self.chi - chi_last) ** 2
        worst = np.zeros(len(self.chi))
        nominal = (self.chi == 0.0) & (self.P == 1.0)
        for tg in self._targets(obs):
            rng = tg["range"]
            px, py = rng * tg["bearing_cos"], rng * tg["bearing_sin"]
            tvx, tvy = u + tg["rel_u"], v + tg["rel_v"]
            dx, dy = px + tvx * t - ox, py + tvy * t - oy  # target - own, per behaviour and time
            d = np.maximum(np.hypot(dx, dy), 1.0)
            C = ((ovx - tvx) ** 2 + (ovy - tvy) ** 2) / (self.U_T * self.U_T)
            R = np.where(d < self.safe, (self.safe / d) ** self.q, 0.0) / (1.0 + t / self.horizon_T)
            risk = (C * R).max(axis=1)
            if tg["stand_on"] > 0.5 and rng > self.release:
                risk[:] = 0.0  # rule 17(a): the other ship is to keep out of the way; keep course and speed
            mu = np.zeros(len(self.chi))
            give_way = tg["head_on"] + tg["give_way"] > 0.5
            if give_way:
                mu += self.chi < 0.0
                k_cpa = d.argmin(axis=1)
                rows = np.arange(len(self.chi))
                close = d[rows, k_cpa] < 2.0 * self.safe
                if tg["give_way"] > 0.5:  # ahead of the target's beam at the closest point: crossing ahead
                    hx, hy = tvx, tvy
                    ahead = (-dx[rows, k_cpa] * hx - dy[rows, k_cpa] * hy) > 0.0
                    mu += close & ahead
            if give_way or tg["overtaking"] > 0.5:  # the route in conflict: an alteration readily apparent
                if risk[nominal].max(initial=0.0) > 0.0:
                    mu += 0.5 * (np.abs(self.chi) < self.substantial)
            if tg["stand_on"] > 0.5:
                if rng > self.release:
                    mu += (self.chi != 0.0) | (self.P != 1.0)
                if tg["bearing_sin"] < 0.0:
                    mu += self.chi < 0.0
            worst = np.maximum(worst, risk + self.kappa * np.minimum(mu, 1.0))
        return cost + worst

    def choose(self, obs: np.ndarray, los: float, chi_last: float, p_last: float) -> tuple[float, float]:
        best = int(np.argmin(self.costs(obs, los, chi_last, p_last)))
        return float(self.chi[best]), float(self.P[best])
