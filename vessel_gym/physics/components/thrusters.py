"""Tunnel thrusters: the bow and stern thrusters of a ship, as components of slot ``extra``.

A tunnel thruster is a fixed-pitch propeller in a transverse tunnel. Its order is a fraction of rated shaft
speed in [-1, 1] (+ pushes the hull to starboard); the thrust of a fixed-pitch propeller goes as n^2, so the
thrust ordered is T_max * o |o|. The actual thrust follows the order with a first-order lag (the drive's
run-up: ``time_constant_s``); it is the component's state ``thrust`` (a fraction of T_max, signed).

**Bollard thrust from power** (momentum theory of an actuator disc with a figure of merit, e.g. Carlton 2019,
*Marine Propellers and Propulsion*, 4th ed., ch. 6 "bollard pull"): T_max = (FM P sqrt(2 rho A))^(2/3), A the
tunnel's cross-section pi D^2 / 4, FM the figure of merit of a tunnel thruster (0.7: ducted-propeller
class, ESTIMATE). For the supply vessel's 880 kW, 2.0 m bow thruster this gives 136 kN, 15.7 kgf/kW, in the
range thruster makers quote for tunnel thrusters at bollard (11-16 kgf/kW).

**Loss of thrust with forward speed.** With way on, the jet is bent aft and reattaches to the hull downstream,
where its low pressure pulls the hull back: the net side force at speed U falls to a fraction of the bollard
force, a function of the ratio of ship speed to jet speed, U / V_j (V_j = sqrt(T / (rho A)), the jet of the
same momentum flux). The curve :data:`SPEED_LOSS` is the side force of a bow tunnel thruster measured by
Chislett & Bjorheden (1966), *Influence of ship speed on the effectiveness of a lateral-thrust unit*, Hydro-
og Aerodynamisk Laboratorium report Hy-8, Lyngby, as reproduced in Brix (ed., 1993) *Manoeuvring Technical
Manual*, Seehafen Verlag, section on transverse thrusters: a fall to about half the bollard force near
U / V_j = 0.3 and a partial recovery at higher speed ratios. The ordinates are read from the published figure
(reading accuracy about +-0.03), not from a table; the curve is used for both ahead and astern speed (the
source is ahead only). The moment takes the same factor at the tunnel position (the shift of the force
centre aft at speed, which lowers the moment further, is not modelled).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import Component, State
from vessel_gym.physics.schema import param

#: U / V_j (-) and the side force over its bollard value (-): Chislett & Bjorheden (1966), read from the figure
#: reproduced in Brix (1993); beyond the last ratio the last value holds
SPEED_LOSS = (
    (0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.5, 0.6, 0.8, 1.0),
    (1.0, 0.90, 0.78, 0.67, 0.58, 0.52, 0.49, 0.48, 0.49, 0.53, 0.58, 0.66, 0.72),
)


def speed_loss_factor(speed_ratio: Any) -> Any:
    """Side force / bollard side force of a tunnel thruster at the ratio |U| / V_j (:data:`SPEED_LOSS`)."""
    return np.interp(np.abs(speed_ratio), SPEED_LOSS[0], SPEED_LOSS[1])


def bollard_thrust(power_W: float, diameter_m: float, figure_of_merit: float, rho: float) -> float:
    """Bollard thrust (N) of a ducted propeller absorbing ``power_W``: (FM P sqrt(2 rho A))^(2/3)."""
    area = math.pi * diameter_m**2 / 4.0  # m^2
    return (figure_of_merit * power_W * math.sqrt(2.0 * rho * area)) ** (2.0 / 3.0)


class OrderedComponent(Component):
    """A component commanded by an order per vessel: ``order`` holds it, one value or one per vessel of the
    simulation (the environment writes it every control step with :meth:`set_order`)."""

    def __init__(self, ship: Any = None, params: Any = None) -> None:
        super().__init__(ship, params)
        self.order = np.zeros(1)

    def set_order(self, value: Any, k: int | None = None, n: int | None = None) -> None:
        """Order ``value`` (clipped to [-1, 1]) for vessel ``k`` of ``n``, or for all (``k`` None)."""
        if k is None:
            self.order = np.clip(np.array(value, dtype=float).reshape(-1), -1.0, 1.0)
            return
        n = n or max(self.order.size, k + 1)
        if self.order.size != n:
            self.order = np.broadcast_to(self.order, (n,)).copy() if self.order.size == 1 else np.zeros(n)
        self.order[k] = min(max(float(value), -1.0), 1.0)

    def orders(self, n: int) -> np.ndarray:
        """The order of each of ``n`` vessels."""
        o = self.order
        return np.broadcast_to(o, (n,)) if o.size in (1, n) else np.zeros(n)

    def delivered(self, s: np.ndarray) -> np.ndarray:
        """What it delivers now, on its order's scale (signed, 1: its maximum along the ordered direction), from
        its states ``s`` (N, len(states)): the first state, for a component whose state is that."""
        return s[:, 0]


@dataclass(frozen=True, kw_only=True)
class TunnelThrusterParams:
    """A tunnel thruster's ship-file keys (``[[components]] params``)."""

    name: str = param("bow_thruster", doc="name of its forces and state (unique on the ship)")
    power_kW: float = param(unit="kW", lo=1.0, hi=1e4, doc="rated shaft power")
    diameter_m: float = param(unit="m", lo=0.2, hi=6.0, doc="propeller (tunnel) diameter")
    figure_of_merit: float = param(
        0.7,
        unit="-",
        lo=0.3,
        hi=1.0,
        doc="FM of momentum theory at bollard (0.7 ducted propellers, ESTIMATE)",
    )
    x_m: float = param(unit="m", lo=-300.0, hi=300.0, doc="tunnel position forward of midship")
    time_constant_s: float = param(
        3.0, unit="s", lo=0.1, hi=60.0, doc="first-order time constant of the thrust following the order"
    )


class TunnelThruster(OrderedComponent):
    """A tunnel thruster (module docstring): side force T_max f(|u| / V_j) thrust at ``x_m``, thrust lagging the
    order ``o`` (fraction of rated rpm; thrust ordered T_max o |o|) with ``time_constant_s``."""

    slot = "extra"
    Params = TunnelThrusterParams
    states = (State("thrust", "-", 0.0, "actual thrust / bollard thrust at rated rpm, + to starboard"),)

    def __init__(self, ship: Any, params: TunnelThrusterParams) -> None:
        super().__init__(ship, params)
        rho = ship.particulars.rho_kg_m3 if ship is not None else 1025.0
        self.rho = rho
        self.area = math.pi * params.diameter_m**2 / 4.0  # m^2
        #: bollard thrust at rated rpm, N
        self.T_max = bollard_thrust(params.power_kW * 1e3, params.diameter_m, params.figure_of_merit, rho)

    @property
    def name(self) -> str:
        return self.params.name

    def side_force(self, u: Any, thrust: Any) -> Any:
        """Side force (N) at surge speed ``u`` (m/s) with the actual thrust fraction ``thrust``."""
        T = self.T_max * np.asarray(thrust, dtype=float)  # N
        V_j = np.sqrt(np.abs(T) / (self.rho * self.area))  # jet speed of the same momentum flux, m/s
        ratio = np.abs(u) / np.maximum(V_j, 1e-6)
        return T * speed_loss_factor(ratio)

    def rates(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        o = self.orders(x.shape[0])
        return ((o * np.abs(o) - s[:, 0]) / self.params.time_constant_s)[:, None]

    def forces(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:  # type: ignore[override]
        Y = self.side_force(x[:, lo.X_U], s[:, 0])
        return np.column_stack([np.zeros_like(Y), Y, self.params.x_m * Y])
