"""A harbour tug as a force component: it pushes or pulls the ship at one point of the hull, within its bollard
pull, along a line at a given angle, and answers an order with a lag.

The tug's force on the ship is a vector in the ship's body axes at the attachment point (``x_m`` forward of
midship, on the centre line: the towline's fairlead or the push point's lever about midship are the same to
within B/2 of lateral offset, neglected). Its direction is the line angle ``line_angle_deg`` from the ship's
starboard beam towards the bow (0: square to starboard, the usual push or pull of berthing; 90: ahead along
the ship). The order o in [-1, 1] is a fraction of the bollard pull along that line: + towards starboard
(a push on the port side or a pull on the starboard side), - towards port. The force follows the order with a
first-order lag (``time_constant_s``, the time a tug needs to build up or change its pull: tens of seconds,
Hensen 2003, *Tug use in port: a practical guide*, 2nd ed., Nautical Institute, ch. "tug capabilities");
its states are the two body components of the force over the bollard pull.

What a tug does not do here: lose pull as the ship gathers way (above some 5-6 kn a tug at the bow can no
longer hold its position: Hensen 2003), swing round, or slacken its line; berthing is at a few tenths of a
knot, where the bollard pull is the limit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.physics.components import State
from vessel_gym.physics.components.thrusters import OrderedComponent
from vessel_gym.physics.schema import param

G = 9.80665  # m/s^2, standard gravity: a tonne-force of bollard pull is 9.80665 kN


@dataclass(frozen=True, kw_only=True)
class TugParams:
    """A tug's keys (a ``[[components]]`` entry's ``params``, or a scenario's tug)."""

    name: str = param("tug", doc="name of its forces and states (unique on the ship)")
    bollard_pull_t: float = param(unit="t", lo=1.0, hi=200.0, doc="bollard pull, tonnes-force")
    x_m: float = param(unit="m", lo=-300.0, hi=300.0, doc="attachment point forward of midship")
    line_angle_deg: float = param(
        0.0, unit="deg", lo=-90.0, hi=90.0, doc="line from the starboard beam towards the bow (0: square)"
    )
    time_constant_s: float = param(
        20.0, unit="s", lo=1.0, hi=300.0, doc="first-order time constant of the force following the order"
    )


class Tug(OrderedComponent):
    """A tug pushing or pulling at ``x_m`` (module docstring); order: fraction of the bollard pull along its
    line, + towards starboard."""

    slot = "extra"
    Params = TugParams
    states = (
        State("fx", "-", 0.0, "surge component of the tug's force / bollard pull"),
        State("fy", "-", 0.0, "sway component of the tug's force / bollard pull, + starboard"),
    )

    def __init__(self, ship: Any, params: TugParams) -> None:
        super().__init__(ship, params)
        self.F_max = params.bollard_pull_t * 1e3 * G  # N
        a = math.radians(params.line_angle_deg)
        self.direction = (math.sin(a), math.cos(a))  # (x, y) of the line, body axes

    @property
    def name(self) -> str:
        return self.params.name

    def rates(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        o = self.orders(x.shape[0])
        target = np.column_stack([o * self.direction[0], o * self.direction[1]])
        return (target - s) / self.params.time_constant_s

    def delivered(self, s: np.ndarray) -> np.ndarray:
        """The force along its line / bollard pull (+ towards starboard, as the order)."""
        return s[:, 0] * self.direction[0] + s[:, 1] * self.direction[1]

    def forces(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:  # type: ignore[override]
        X, Y = self.F_max * s[:, 0], self.F_max * s[:, 1]
        return np.column_stack([X, Y, self.params.x_m * Y])
