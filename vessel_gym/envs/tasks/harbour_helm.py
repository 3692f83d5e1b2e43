"""The smooth helm of the HarbourApproach task (config ``rudder_action="lag"``, HarbourApproach-v3): the action
is the helm order the policy asks for, and the rudder order in force follows it as a first-order lag whose
change per control step is capped at a set rate (:class:`LagHelm`), so the order can never jump, whatever the
policy outputs; and the adapter that gives a pilot's orders the same way (:class:`LagPilot`).

Why in the task and not in a wrapper: every consumer of the environment (training, ``evaluate.py``, ``serve
--agent``, the chart view) then steers the same ship; an action filter outside the environment is seen only
by the code that applies it.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from vessel_gym.envs.config import ShipEnvConfig
from vessel_gym.envs.helm import ContinuousHelm, Helmed, continuous_orders
from vessel_gym.physics.units import DEG


def lag_gain(interval_s: float, time_constant_s: float) -> float:
    """The fraction of the gap between asked and ordered rudder closed per control step: the exact discrete
    first-order lag ``1 - exp(-interval / time constant)``."""
    return 1.0 - math.exp(-interval_s / time_constant_s)


class LagHelm(ContinuousHelm):
    """Box(-1, 1): a[0] the rudder the policy asks for, as a fraction of the rudder limit (+ starboard); the
    order in force moves towards it by ``gain`` of the gap per control step, at most ``step_rad`` (the rate
    cap times the control interval). With engine control a[1] is the shaft-speed order as
    :class:`~vessel_gym.envs.helm.ContinuousHelm`'s. Out-of-range values are clipped; NaN raises
    ValueError."""

    def __init__(
        self, config: ShipEnvConfig, sim: Helmed, gain: float, rate_rad_s: np.ndarray, interval_s: float
    ) -> None:
        super().__init__(config, sim)
        self.gain = float(gain)
        #: largest change of the rudder order per control step, rad (one per vessel)
        self.step_rad = np.asarray(rate_rad_s, dtype=np.float64) * interval_s
        self._step0 = float(self.step_rad[0])

    def _order_now(self) -> np.ndarray:
        """The rudder orders in force (a view of the simulation's inputs)."""
        return self.sim.rudder_order  # type: ignore[attr-defined]

    def apply_single(self, action: Any) -> None:
        x, e = self._fractions(action)
        if x != x or e != e:
            raise ValueError(f"action contains NaN: {action!r}")
        asked, rev = continuous_orders(x, e, self._lim0, self._fa0, self._fs0)
        now = float(self._order_now()[0])
        change = min(max(self.gain * (asked - now), -self._step0), self._step0)
        self.sim.set_helm(rudder_order_rad=now + change, rev_order=rev if self.engine else None, k=0)

    def apply(self, actions: np.ndarray) -> None:
        if np.isnan(actions).any():
            raise ValueError(f"action contains NaN: {actions.tolist()!r}")
        asked = np.clip(actions[:, 0], -1.0, 1.0) * self.rudder_limit_rad
        now = self._order_now()
        orders = now + np.clip(self.gain * (asked - now), -self.step_rad, self.step_rad)
        if self.engine:
            e = np.clip(actions[:, 1], -1.0, 1.0)
            self._rev[:] = np.where(e >= 0.0, e * self.full_ahead, e * self.full_astern)
        self.sim.set_helm(rudder_order_rad=orders, rev_order=self._rev if self.engine else None)


def cap_rate(fraction: float, sim: Helmed) -> np.ndarray:
    """The rate cap of the rudder order of every vessel: ``fraction`` of its steering gear's rate, rad/s."""
    return np.array([fraction * sim.ship(k).steering_gear.max_rate_deg_s * DEG for k in range(sim.n)])
