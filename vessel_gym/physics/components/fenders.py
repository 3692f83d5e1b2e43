"""Quay and fender contact: rubber fenders on a straight quay face, the ship's side pressing on them.

**Geometry.** A berth's quay face is a straight line between two points [north, east] (the wall); its fenders
stand on it at given distances along it, their faces ``height_m`` out from the wall into the water. The
ship's hull is a box of its length and beam in plan (the side is straight over the fenders: a berth puts its
fenders under the parallel middle body); the side that berths (port or starboard) meets the fender faces.
A fender is compressed by delta = B/2 - s y_f >= 0, y_f the body-y of its face point and s = +1 for the
starboard side, -1 for port, when its body-x lies within the hull's length.

**Load-deflection.** The reaction of a buckling (cone) fender, R = R_R c(delta / H), with c the normalised
curve :data:`CONE_CURVE`: the generic performance curve of a cone fender of the Trelleborg Super Cone (SCN)
type (Trelleborg Marine Systems, *Fender Systems* product brochure, "Super Cone" generic performance curve;
the shape PIANC WG33 (2002) shows for buckling fenders, section 3.2): the reaction rises to its peak at about
35-40 % deflection, buckles to a shallow dip and is back at the rated reaction R_R at the rated deflection
(72 %); beyond, the rubber bottoms out and the reaction climbs steeply. The ordinates are read from the
published curve (about +-0.03), not from a table. The energy the fender absorbs in compression is
W(delta) = R_R H integral_0^(delta/H) c, and its rated energy E_R = W(rated deflection): with this curve
E_R = 0.56 R_R H. Unloading follows the curve times (1 - ``hysteresis``): the rubber's hysteresis (ESTIMATE
0.3: the energy a buckling fender returns is well under what it absorbed), so that a ship does not bounce
off for ever.

**Friction along the face.** mu R against the sliding of the hull past the fender, smoothed as mu R
tanh(v_t / 0.02 m/s) (a Coulomb law regularised for a fixed integration step); mu = 0.2 for the UHMW-PE
facing of a fender panel on a steel hull (PIANC WG33 2002, table of friction coefficients: 0.1-0.2).

**Energy absorbed** per fender is tracked as the deepest compression reached, a state of the component
(``peak_<j>``, m) integrated from the rate of compression while the fender is at its deepest; the energy is
W(peak). For one berthing blow this is what PIANC WG33 (2002, eq. 4.1) sizes fenders for: the part of the
ship's kinetic energy, with its added mass, that the fenders must take, E = 1/2 M (C_M) v^2 C_E C_S C_C.

The component is a scenario-level one (the quay is in the harbour, not in the ship file): the Berthing task
builds it from a scenario's ``[[berth]]`` entry and hands it to the simulation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import Component, State
from vessel_gym.physics.schema import param

#: deflection / height (-) and reaction / rated reaction (-) of a cone fender (module docstring)
CONE_CURVE = (
    (0.0, 0.05, 0.10, 0.15, 0.20, 0.25, 0.30, 0.35, 0.40, 0.45, 0.50, 0.55, 0.60, 0.65, 0.70, 0.72, 0.75),
    (0.0, 0.19, 0.38, 0.55, 0.70, 0.82, 0.91, 0.97, 1.00, 0.99, 0.97, 0.95, 0.93, 0.93, 0.97, 1.00, 1.12),
)
#: PIANC WG33 (2002) design berthing velocities normal to the berth (Brolsma et al. 1977), m/s, by displacement
#: (t) for the five navigation conditions: a good berthing, sheltered; b difficult, sheltered; c easy, exposed;
#: d good, exposed; e difficult, exposed (as tabulated in fender makers' design manuals from PIANC fig. 4.2.1)
BROLSMA = {
    "displacement_t": (1e3, 3e3, 5e3, 1e4, 2e4, 3e4, 4e4, 5e4, 1e5, 2e5),
    "a": (0.179, 0.136, 0.117, 0.094, 0.075, 0.066, 0.060, 0.056, 0.044, 0.036),
    "b": (0.343, 0.269, 0.236, 0.192, 0.156, 0.138, 0.127, 0.118, 0.094, 0.075),
    "c": (0.517, 0.404, 0.354, 0.287, 0.233, 0.206, 0.188, 0.176, 0.139, 0.110),
    "d": (0.669, 0.537, 0.476, 0.393, 0.329, 0.293, 0.270, 0.254, 0.206, 0.166),
    "e": (0.865, 0.713, 0.641, 0.542, 0.453, 0.405, 0.375, 0.353, 0.290, 0.234),
}


def design_berthing_velocity(displacement_t: float, condition: str = "a") -> float:
    """PIANC's design berthing velocity (m/s) for a ship of ``displacement_t`` in navigation ``condition``
    (a-e, :data:`BROLSMA`): log-log interpolation, extrapolated along the end segments beyond the table."""
    x = np.log(np.asarray(BROLSMA["displacement_t"]))
    y = np.log(np.asarray(BROLSMA[condition]))
    lx = math.log(displacement_t)
    i = int(np.clip(np.searchsorted(x, lx) - 1, 0, len(x) - 2))
    return float(math.exp(y[i] + (y[i + 1] - y[i]) * (lx - x[i]) / (x[i + 1] - x[i])))


def added_mass_coefficient(draught_m: float, beam_m: float) -> float:
    """PIANC WG33 (2002, section 4.2.5) virtual mass factor of Vasco Costa (1964): C_M = 1 + 2 T / B."""
    return 1.0 + 2.0 * draught_m / beam_m


def berthing_energy(mass_kg: float, velocity_m_s: float, C_M: float) -> float:
    """Kinetic energy (J) a side-on berthing brings to the fenders, 1/2 M C_M v^2 (PIANC WG33 2002, eq. 4.1
    with C_E = C_S = C_C = 1: contact abreast the centre of mass, hard fenders, an open quay)."""
    return 0.5 * mass_kg * C_M * velocity_m_s**2


#: slope of the reaction beyond the curve (bottoming out), rated reactions per fender height
BOTTOM_SLOPE = 20.0
#: sliding speed over which the friction builds up, m/s (regularised Coulomb friction)
SLIP_SPEED = 0.02


@dataclass(frozen=True, kw_only=True)
class FenderParams:
    """One fender type of a berth (a ``[[berth]]`` entry's ``fender`` table)."""

    model: str = param("cone", choices=("cone",), doc="load-deflection curve: the cone fender's (CONE_CURVE)")
    height_m: float = param(1.0, unit="m", lo=0.1, hi=5.0, doc="fender height H, wall to face, unloaded")
    rated_reaction_kN: float = param(660.0, unit="kN", lo=1.0, hi=2e4, doc="rated reaction R_R")
    rated_deflection: float = param(0.72, unit="-", lo=0.3, hi=0.75, doc="rated deflection / height")
    hysteresis: float = param(
        0.3, unit="-", lo=0.0, hi=0.9, doc="unloading reaction lost, fraction (ESTIMATE)"
    )
    friction: float = param(0.2, unit="-", lo=0.0, hi=1.0, doc="friction coefficient, fender face on hull")


class FenderCurve:
    """Reaction (N) and absorbed energy (J) of one fender type as functions of its deflection (m)."""

    def __init__(self, p: FenderParams) -> None:
        self.H, self.R_R = p.height_m, p.rated_reaction_kN * 1e3
        self.xi, self.c = np.asarray(CONE_CURVE[0]), np.asarray(CONE_CURVE[1])
        self.rated = p.rated_deflection
        # W at the curve's points: trapezoids of the piecewise-linear curve are exact
        self.W_nodes = np.concatenate([[0.0], np.cumsum(np.diff(self.xi) * (self.c[1:] + self.c[:-1]) / 2)])

    def reaction(self, delta: Any) -> Any:
        """R (N) at deflection ``delta`` (m) along the loading curve."""
        xi = np.maximum(np.asarray(delta, dtype=float) / self.H, 0.0)
        c = np.interp(xi, self.xi, self.c) + BOTTOM_SLOPE * np.maximum(xi - self.xi[-1], 0.0)
        return self.R_R * np.where(xi > 0.0, c, 0.0)

    def energy(self, delta: Any) -> Any:
        """W (J) absorbed by compressing to ``delta`` (m) along the loading curve."""
        xi = np.maximum(np.asarray(delta, dtype=float) / self.H, 0.0)
        x = np.minimum(xi, self.xi[-1])
        i = np.clip(np.searchsorted(self.xi, x, side="right") - 1, 0, len(self.xi) - 2)
        c0 = self.c[i]
        dx = x - self.xi[i]
        slope = (self.c[i + 1] - c0) / (self.xi[i + 1] - self.xi[i])
        w = self.W_nodes[i] + c0 * dx + 0.5 * slope * dx**2
        over = np.maximum(xi - self.xi[-1], 0.0)  # beyond the curve: its last value plus the bottoming slope
        w = w + self.c[-1] * over + 0.5 * BOTTOM_SLOPE * over**2
        return self.R_R * self.H * w

    @property
    def rated_energy(self) -> float:
        """E_R (J): the energy absorbed at the rated deflection."""
        return float(self.energy(self.rated * self.H))


@dataclass(frozen=True, kw_only=True)
class QuayFendersParams:
    """The berth seen by the contact component (from a scenario's ``[[berth]]``)."""

    quay_m: tuple[tuple[float, ...], ...] = param(
        unit="m", lo=-1e6, hi=1e6, doc="[[north, east], [north, east]]"
    )
    fenders_m: tuple[float, ...] = param(unit="m", lo=-1e5, hi=1e5, doc="fender positions along the quay")
    side: str = param("port", choices=("port", "starboard"), doc="the ship's side that berths")
    fender: FenderParams = param(FenderParams(), doc="the fender type")


class QuayFenders(Component):
    """Contact of the ship's side with a berth's fenders (module docstring): reactions, friction, and the
    deepest compression of each fender as states."""

    slot = "extra"
    Params = QuayFendersParams

    def __init__(self, ship: Any, params: QuayFendersParams) -> None:
        super().__init__(ship, params)
        pt = ship.particulars
        self.half_L, self.half_B = pt.L_m / 2.0, pt.B_m / 2.0
        self.curve = FenderCurve(params.fender)
        (n0, e0), (n1, e1) = params.quay_m[0], params.quay_m[1]
        length = math.hypot(n1 - n0, e1 - e0)
        self.along = ((n1 - n0) / length, (e1 - e0) / length)  # unit vector of the quay line
        self.s = 1.0 if params.side == "starboard" else -1.0
        # the water is on the side of the line opposite to the ship's berthing side, the ship heading along it:
        # port side to (s = -1), the quay is to port of the line's direction and the water to starboard
        a = self.along
        self.to_water = (-self.s * -a[1], -self.s * a[0])  # starboard normal of the line times -s
        d = np.asarray(params.fenders_m, dtype=float)
        H = params.fender.height_m
        #: fender face points (unloaded), [north, east] (M, 2)
        self.faces = np.column_stack(
            [n0 + d * a[0] + H * self.to_water[0], e0 + d * a[1] + H * self.to_water[1]]
        )
        self._touch = np.full(1, np.nan)
        self.states = tuple(
            State(f"peak_{j}", "m", 0.0, f"deepest compression of fender {j}") for j in range(len(d))
        )

    @property
    def name(self) -> str:
        return "QuayFenders"

    def geometry(self, sim: Any, x: np.ndarray) -> tuple[np.ndarray, ...]:
        """(deflection (N, M) m, rate of compression (N, M) m/s, body x of the fenders (N, M) m, sliding speed
        of the hull past them (N, M) m/s) at the states ``x``."""
        psi = x[:, lo.X_PSI][:, None]
        c, sn = np.cos(psi), np.sin(psi)
        dn = self.faces[None, :, 0] - x[:, lo.X_N][:, None]
        de = self.faces[None, :, 1] - x[:, lo.X_E][:, None]
        xb, yb = c * dn + sn * de, -sn * dn + c * de
        # the hull's half-breadth at the fender: the waterline of scenarios.geometry.hull_outline (parallel from
        # the stern to 0.3 L forward, then tapering to the stem)
        half = self.half_B * np.clip((self.half_L - xb) / (0.4 * self.half_L), 0.0, 1.0)
        on_hull = np.abs(xb) <= self.half_L
        delta = np.where(on_hull, np.maximum(half - self.s * yb, 0.0), 0.0)
        # velocity over ground, body axes (the current carries the ship, not the quay)
        env = sim.env
        cn, ce = env[:, lo.E_CUR_N][:, None], env[:, lo.E_CUR_E][:, None]
        u = x[:, lo.X_U][:, None] + c * cn + sn * ce
        v = x[:, lo.X_V][:, None] - sn * cn + c * ce
        r = x[:, lo.X_R][:, None]
        y_side = self.s * self.half_B
        rate = np.where(delta > 0.0, self.s * (v + r * xb), 0.0)  # the side moving into the fender
        slide = u - r * y_side
        return delta, rate, xb, slide

    def touch_speed(self, n: int) -> np.ndarray:
        """(n,) speed of compression (m/s) at each vessel's first touch of a fender since :meth:`clear`; NaN
        before it touched. Recorded at the first integration stage that finds a fender compressed."""
        if self._touch.shape != (n,):
            self._touch = np.full(n, np.nan)
        return self._touch

    def clear(self, k: int, n: int) -> None:
        """Forget vessel ``k``'s first touch (a new episode)."""
        self.touch_speed(n)[k] = np.nan

    def forces(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:  # type: ignore[override]
        delta, rate, xb, slide = self.geometry(sim, x)
        touching = (delta > 0.0).any(axis=1)
        if touching.any():
            t = self.touch_speed(x.shape[0])
            new = touching & np.isnan(t)
            t[new] = np.where(delta > 0.0, rate, 0.0).max(axis=1)[new]
        f = self.params.fender
        R = self.curve.reaction(delta) * np.where(rate < 0.0, 1.0 - f.hysteresis, 1.0)
        Y = -self.s * R  # the fender pushes the side away from the quay
        X = -f.friction * R * np.tanh(slide / SLIP_SPEED)
        N = xb * Y - (self.s * self.half_B) * X
        return np.column_stack([X.sum(axis=1), Y.sum(axis=1), N.sum(axis=1)])

    def rates(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        delta, rate, _xb, _slide = self.geometry(sim, x)
        deepest = (delta > 0.0) & (delta >= s - 1e-9) & (rate > 0.0)
        return np.where(deepest, rate, 0.0)

    def deflections(self, sim: Any) -> np.ndarray:
        """(N, M) deflection of every fender now, m."""
        return self.geometry(sim, sim.state)[0]

    def energies(self, peaks: np.ndarray) -> np.ndarray:
        """Energy absorbed (J) for the deepest compressions ``peaks`` (m)."""
        return self.curve.energy(peaks)
