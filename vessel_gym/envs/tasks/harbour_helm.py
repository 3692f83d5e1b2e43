"""The rate-commanded rudder of the HarbourApproach task (config ``rudder_action="rate"``, HarbourApproach-v3):
the action moves the rudder order instead of setting it, so that the order a policy gives changes by at most
a set rate, whatever the policy outputs (:class:`RateHelm`); and the adapter that lets a pilot which gives
orders steer through it (:class:`RatePilot`).

Why in the task and not in a wrapper: every consumer of the environment (training, ``evaluate.py``, ``serve
--agent``, the chart view) then steers the same ship; an action filter outside the environment is seen only
by the code that applies it.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from vessel_gym.envs.config import ShipEnvConfig
from vessel_gym.envs.helm import ContinuousHelm, Helmed, continuous_orders
from vessel_gym.physics.units import DEG


class RateHelm(ContinuousHelm):
    """Box(-1, 1): a[0] the rate of the rudder order as a fraction of ``rate_rad_s`` (+ towards starboard),
    integrated into the order over the control interval and clipped to the rudder limit; with engine control
    a[1] the shaft-speed order as :class:`~vessel_gym.envs.helm.ContinuousHelm`'s. Out-of-range values are
    clipped; NaN raises ValueError."""

    def __init__(self, config: ShipEnvConfig, sim: Helmed, rate_rad_s: np.ndarray, interval_s: float) -> None:
        super().__init__(config, sim)
        #: rudder-order change per control step at |a[0]| = 1, rad (one per vessel)
        self.step_rad = np.asarray(rate_rad_s, dtype=np.float64) * interval_s
        self._step0 = float(self.step_rad[0])

    def _order_now(self) -> np.ndarray:
        """The rudder orders in force (a view of the simulation's inputs)."""
        return self.sim.rudder_order  # type: ignore[attr-defined]

    def apply_single(self, action: Any) -> None:
        x, e = self._fractions(action)
        if x != x or e != e:
            raise ValueError(f"action contains NaN: {action!r}")
        order = float(self._order_now()[0]) + min(max(x, -1.0), 1.0) * self._step0
        order = min(max(order, -self._lim0), self._lim0)
        _rudder, rev = continuous_orders(0.0, e, self._lim0, self._fa0, self._fs0)
        self.sim.set_helm(rudder_order_rad=order, rev_order=rev if self.engine else None, k=0)

    def apply(self, actions: np.ndarray) -> None:
        if np.isnan(actions).any():
            raise ValueError(f"action contains NaN: {actions.tolist()!r}")
        rate = np.clip(actions[:, 0], -1.0, 1.0)
        orders = np.clip(self._order_now() + rate * self.step_rad, -self.rudder_limit_rad, self.rudder_limit_rad)
        if self.engine:
            e = np.clip(actions[:, 1], -1.0, 1.0)
            self._rev[:] = np.where(e >= 0.0, e * self.full_ahead, e * self.full_astern)
        self.sim.set_helm(rudder_order_rad=orders, rev_order=self._rev if self.engine else None)


class RatePilot:
    """A pilot that gives rudder orders (``policy(obs)``: the order as a fraction of the rudder limit in the
    action's first entry), steering through :class:`RateHelm`: the rate action that brings the observed order
    to the pilot's within one control step where the rate allows, else at the full rate."""

    def __init__(self, env: Any, pilot: Any) -> None:
        base = env.unwrapped
        helm = base.task.helm
        self.pilot = pilot
        self.layout = base.observation_layout
        self.limit = float(helm.rudder_limit_rad[0])  # rad
        self.step = float(helm.step_rad[0])  # rad per control step at |a| = 1

    def reset(self, mask: np.ndarray | None = None) -> None:
        self.pilot.reset(mask)

    def __getattr__(self, name: str) -> Any:  # the pilot's own state (waypoint, gains) stays readable
        if name == "pilot":
            raise AttributeError(name)
        return getattr(self.pilot, name)

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        a = np.array(self.pilot(obs), dtype=np.float32, copy=True)
        now = np.asarray(self.layout.value(obs, "rudder_order"), dtype=np.float64)  # rad
        a[..., 0] = np.clip((a[..., 0] * self.limit - now) / self.step, -1.0, 1.0)
        return a


def rate_of(fraction: float, sim: Helmed) -> np.ndarray:
    """The rudder-order rate at |a| = 1 of every vessel: ``fraction`` of its steering gear's rate, rad/s."""
    return np.array([fraction * sim.ship(k).steering_gear.max_rate_deg_s * DEG for k in range(sim.n)])
