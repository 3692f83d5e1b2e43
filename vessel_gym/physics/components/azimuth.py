"""Azimuth thrusters: a ducted propeller on a pod that turns about the vertical, as a component of slot ``extra``.

The unit has two orders: the shaft speed as a fraction of rated rpm in [-1, 1] (``order``, as every
:class:`~vessel_gym.physics.components.thrusters.OrderedComponent`) and the azimuth, the direction of its
thrust on the hull measured from ahead towards starboard (``azimuth_order``, rad). Both are followed by the
unit's states: the rpm fraction with a first-order lag (``time_constant_s``, the drive's run-up), the azimuth
at most at the slewing rate (``slew_rate_deg_s``: an azimuth unit turns at a few rpm, 2 rpm = 12 deg/s) and
otherwise with a time constant of one second (the slewing drive's own response).

**Thrust from power and rpm: the Ka 4-70 ducted propeller in nozzle 19A.** The open-water thrust and torque
coefficients are the regression polynomials of the Wageningen ducted series (Oosterveld 1970, *Wake adapted
ducted propellers*, NSMB Publication 345, the Ka 4-70 / nozzle 19A table of K_T (propeller and nozzle) and
K_Q; reproduced in Kuiper 1992, *The Wageningen Propeller Series*, MARIN Publication 92-001, and in Carlton,
*Marine Propellers and Propulsion*): K = sum c (P/D)^x J^y, :data:`KA470_KT` and :data:`KA470_KQ`, valid for
P/D 0.6-1.4. The rated rpm n_R is the speed at which the propeller absorbs the rated power at bollard
(J = 0): transmission_efficiency x P = 2 pi rho n_R^3 D^5 K_Q(0); the thrust at shaft speed n and advance
coefficient J = V_A / (|n| D) is rho n |n| D^4 K_T(J), the nozzle's thrust included.

**Loss of thrust with forward speed** is the K_T(J) curve itself, with the advance speed the component of the
water's velocity at the unit along its thrust axis, V_A = (1 - w) (u_p cos a + v_p sin a), (u_p, v_p) the
hull's velocity through the water at the unit's position (the yaw rate included). Outside the polynomial's
range the curve is held: below J = 0 (the unit pushing against the flow, as when stopping the ship) at its
bollard value, above the zero of K_T at zero (no windmilling drag). Astern rpm uses the ahead curve mirrored:
an azimuth unit is turned rather than reversed in practice, and the series has no astern polynomials.

**Thrust deduction**: the thrust on the hull is (1 - t) times the propeller's, ``thrust_deduction`` t (0 for
a unit clear of the hull; a pod under a flat stern loses some 5-15 % to the suction on the hull, ESTIMATE).

**Berthing** drives the unit with one order per unit (``berthing_order``): ``"side"`` turns it athwartships,
to starboard for a positive order and to port for a negative one, at the order's magnitude of rated rpm: a
lateral unit like a tunnel thruster, which must slew through 180 deg to reverse its push; ``"fixed"`` keeps the
azimuth it was last ordered (``azimuth_deg`` at the start) and takes the order as signed rpm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import State
from vessel_gym.physics.components.thrusters import OrderedComponent
from vessel_gym.physics.schema import param

#: Ka 4-70 in nozzle 19A (Oosterveld 1970, NSMB Publ. 345; Kuiper 1992): total thrust coefficient (propeller
#: and nozzle), (c, x, y) of c (P/D)^x J^y
KA470_KT = (
    (0.030550, 0, 0),
    (-0.148687, 0, 1),
    (-0.391137, 0, 3),
    (-0.432612, 1, 1),
    (0.667657, 2, 0),
    (0.285076, 2, 2),
    (-0.172529, 3, 0),
    (-0.017283, 6, 1),
)
#: Ka 4-70 in nozzle 19A: torque coefficient, (c, x, y) of c (P/D)^x J^y
KA470_KQ = (
    (0.006735, 0, 0),
    (-0.016306, 0, 2),
    (-0.007244, 0, 4),
    (-0.024012, 1, 2),
    (0.005193, 2, 2),
    (0.046605, 3, 0),
    (-0.007366, 4, 0),
    (-0.001730, 6, 0),
    (-0.000337, 6, 1),
    (0.000861, 6, 2),
)
#: the azimuth servo's time constant inside its rate limit, s (a slewing drive settles within a second or so)
AZIMUTH_TAU_S = 1.0


def series(coeffs: tuple[tuple[float, int, int], ...], J: Any, pitch_ratio: float) -> Any:
    """sum c (P/D)^x J^y of a Ka-series table at advance coefficient(s) ``J``."""
    J = np.asarray(J, dtype=float)
    return sum(c * pitch_ratio**x * J**y for c, x, y in coeffs)


def zero_thrust_J(pitch_ratio: float) -> float:
    """The advance coefficient at which the Ka 4-70's K_T falls to zero (bisection on [0, 2])."""
    lo_, hi_ = 0.0, 2.0
    for _ in range(60):
        mid = 0.5 * (lo_ + hi_)
        if float(series(KA470_KT, mid, pitch_ratio)) > 0.0:
            lo_ = mid
        else:
            hi_ = mid
    return 0.5 * (lo_ + hi_)


@dataclass(frozen=True, kw_only=True)
class AzimuthThrusterParams:
    """An azimuth thruster's ship-file keys (``[[components]] params``)."""

    name: str = param("azimuth_thruster", doc="name of its forces and states (unique on the ship)")
    power_kW: float = param(unit="kW", lo=1.0, hi=2e4, doc="rated power of the drive")
    diameter_m: float = param(unit="m", lo=0.2, hi=6.0, doc="propeller diameter (inside the nozzle)")
    pitch_ratio: float = param(
        1.0, unit="-", lo=0.6, hi=1.4, doc="P/D of the Ka 4-70 propeller (the series' range)"
    )
    transmission_efficiency: float = param(
        0.95, unit="-", lo=0.5, hi=1.0, doc="power reaching the propeller / rated (two bevel gears, ESTIMATE)"
    )
    x_m: float = param(unit="m", lo=-300.0, hi=300.0, doc="unit position forward of midship")
    y_m: float = param(0.0, unit="m", lo=-50.0, hi=50.0, doc="unit position to starboard of the centre line")
    wake_fraction: float = param(0.0, unit="-", lo=0.0, hi=0.6, doc="w: V_A = (1 - w) x inflow speed")
    thrust_deduction: float = param(0.0, unit="-", lo=0.0, hi=0.5, doc="t: hull force = (1 - t) x thrust")
    time_constant_s: float = param(
        3.0, unit="s", lo=0.1, hi=60.0, doc="first-order time constant of the rpm following the order"
    )
    slew_rate_deg_s: float = param(
        12.0, unit="deg/s", lo=0.5, hi=90.0, doc="largest azimuth rate (12 deg/s: 2 rpm of slewing)"
    )
    azimuth_deg: float = param(
        90.0, unit="deg", lo=-180.0, hi=180.0, doc="azimuth at the start, from ahead towards starboard"
    )
    berthing_order: str = param(
        "side",
        choices=("side", "fixed"),
        doc="one order in Berthing: 'side' athwartships, sign = side, |order| = rpm; 'fixed' signed rpm",
    )


class AzimuthThruster(OrderedComponent):
    """An azimuth thruster (module docstring): thrust rho n|n| D^4 K_T(J) of the Ka 4-70 in nozzle 19A along the
    azimuth, the rpm lagging the order, the azimuth rate-limited."""

    slot = "extra"
    Params = AzimuthThrusterParams
    states = (
        State("rpm", "-", 0.0, "shaft speed / rated, signed"),
        State("azimuth", "rad", 0.0, "thrust direction on the hull from ahead towards starboard"),
    )

    def __init__(self, ship: Any, params: AzimuthThrusterParams) -> None:
        super().__init__(ship, params)
        self.rho = ship.particulars.rho_kg_m3 if ship is not None else 1025.0  # kg/m^3
        p = params
        D = p.diameter_m
        self.KQ0 = float(series(KA470_KQ, 0.0, p.pitch_ratio))
        self.KT0 = float(series(KA470_KT, 0.0, p.pitch_ratio))
        self.J_max = zero_thrust_J(p.pitch_ratio)
        #: rated shaft speed, rev/s: the propeller absorbs the power delivered at bollard
        self.n_rated = (
            p.transmission_efficiency * p.power_kW * 1e3 / (2.0 * math.pi * self.rho * D**5 * self.KQ0)
        ) ** (1.0 / 3.0)
        #: bollard thrust at rated rpm, N (the propeller's, before thrust deduction)
        self.T_max = self.rho * self.n_rated**2 * D**4 * self.KT0
        self.azimuth_order = np.array([math.radians(p.azimuth_deg)])
        # a reset starts stopped at the azimuth of the ship file (the class's states start at 0 deg)
        self.states = (self.states[0], self.states[1]._replace(initial=math.radians(p.azimuth_deg)))

    @property
    def name(self) -> str:
        return self.params.name

    # --- orders -------------------------------------------------------------------------------------------
    def set_azimuth(self, value_rad: Any, k: int | None = None, n: int | None = None) -> None:
        """Azimuth order (rad, from ahead towards starboard) for vessel ``k`` of ``n``, or all (``k`` None)."""
        if k is None:
            self.azimuth_order = np.array(value_rad, dtype=float).reshape(-1)
            return
        n = n or max(self.azimuth_order.size, k + 1)
        if self.azimuth_order.size != n:
            a = self.azimuth_order
            self.azimuth_order = np.broadcast_to(a, (n,)).copy() if a.size == 1 else np.zeros(n)
        self.azimuth_order[k] = float(value_rad)

    def set_order(self, value: Any, k: int | None = None, n: int | None = None) -> None:
        """The one order of a lateral unit (``berthing_order``): 'side' turns the unit to starboard (+) or port
        (-) at |value| of rated rpm; 'fixed' takes ``value`` as signed rpm at the azimuth last ordered."""
        super().set_order(value, k, n)
        if self.params.berthing_order != "side":
            return
        o = self.order if k is None else self.order[k]
        side = np.where(np.asarray(o) >= 0.0, 0.5 * math.pi, -0.5 * math.pi)
        self.set_azimuth(side, k, n)
        if k is None:
            self.order = np.abs(self.order)
        else:
            self.order[k] = abs(self.order[k])

    def azimuth_orders(self, n: int) -> np.ndarray:
        a = self.azimuth_order
        return np.broadcast_to(a, (n,)) if a.size in (1, n) else np.zeros(n)

    def delivered(self, s: np.ndarray) -> np.ndarray:
        """The bollard-equivalent thrust to starboard / bollard thrust at rated rpm (+ as a 'side' order):
        (rpm fraction)^2 sin(azimuth), signed with the rpm."""
        return s[:, 0] * np.abs(s[:, 0]) * np.sin(s[:, 1])

    # --- physics ------------------------------------------------------------------------------------------
    def thrust(self, rpm_fraction: Any, azimuth: Any, u: Any, v: Any, r: Any) -> Any:
        """Propeller thrust (N, along its axis, before thrust deduction) at rpm fraction ``rpm_fraction`` and
        azimuth ``azimuth`` (rad), the hull moving through the water at ``u``, ``v`` (m/s) and ``r`` (rad/s)."""
        p = self.params
        n = self.n_rated * np.asarray(rpm_fraction, dtype=float)  # rev/s
        u_p = np.asarray(u) - np.asarray(r) * p.y_m  # the unit's velocity through the water, body axes, m/s
        v_p = np.asarray(v) + np.asarray(r) * p.x_m
        # the unit moves along its thrust axis: + ahead of its own jet (the usual case, J > 0)
        V_axis = u_p * np.cos(azimuth) + v_p * np.sin(azimuth)
        V_A = (1.0 - p.wake_fraction) * V_axis * np.sign(np.where(n == 0.0, 1.0, n))
        J = np.clip(V_A / np.maximum(np.abs(n) * p.diameter_m, 1e-9), 0.0, self.J_max)
        KT = np.maximum(series(KA470_KT, J, p.pitch_ratio), 0.0)
        return self.rho * n * np.abs(n) * p.diameter_m**4 * KT

    def rates(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        N = x.shape[0]
        d_rpm = (self.orders(N) - s[:, 0]) / self.params.time_constant_s
        err = (self.azimuth_orders(N) - s[:, 1] + math.pi) % (2.0 * math.pi) - math.pi  # the short way round
        limit = math.radians(self.params.slew_rate_deg_s)
        d_az = np.clip(err / AZIMUTH_TAU_S, -limit, limit)
        return np.column_stack([d_rpm, d_az])

    def forces(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:  # type: ignore[override]
        p = self.params
        a = s[:, 1]
        T = (1.0 - p.thrust_deduction) * self.thrust(s[:, 0], a, x[:, lo.X_U], x[:, lo.X_V], x[:, lo.X_R])
        X, Y = T * np.cos(a), T * np.sin(a)
        return np.column_stack([X, Y, p.x_m * Y - p.y_m * X])
