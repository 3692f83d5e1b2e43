"""Is a ship's hull model physically possible? Checks of the hydrodynamic derivatives before any trial runs.

A ship file can hold every derivative inside its allowed range and still describe a hull that pushes the ship
along when it drifts, or a rudder that turns it the wrong way. These checks state such problems (format
reference: docs/ship-file.md, "Is the hull possible?"); ``vessel-gym ships check FILE`` prints them and the IMO
report refuses to pass a ship with an impossible one.

- **Signs.** Sway and yaw damping, the Munk-dominated yaw moment from drift and the drift's added resistance
  have one sign in every published captive-model set: Y'_v < 0, N'_v < 0, N'_r < 0 (Clarke, Gedling & Hine
  1983, Trans. RINA 125, the regressions Y'_v = -pi (T/L)^2 (1 + 0.40 C_b B/T), N'_v = -pi (T/L)^2
  (1/2 + 2.4 T/L), N'_r = -pi (T/L)^2 (1/4 + 0.039 B/T - 0.56 B/L), negative for any hull); X'_vv < 0
  (Yasukawa & Yoshimura 2015, J. Mar. Sci. Technol. 20, Table 3: -0.040 for KVLCC2; Chislett & Stroem-Tejsen
  1965: -0.00899 for the Mariner). Another sign is *unusual*: stated, not refused.
- **Energy.** In calm water the hull only takes energy from the ship: the power of the hull forces together
  with the Coriolis and centripetal terms the equations of motion add (whose rigid-body and added-mass parts
  do no work) is never positive; hydrodynamic damping is dissipative, D(nu) > 0 (Fossen 2011, Handbook of
  Marine Craft Hydrodynamics and Motion Control, sec. 6.4). Checked on the ship's own force model at small
  drift and yaw about the straight approach, where the polynomial was fitted; a positive power is
  *impossible*.
- **Rudder.** Rudder to starboard turns the bow to starboard: a short run with 10 deg of rudder from the
  straight approach must turn the ship the way of the rudder; the other way is *impossible*.
- **Course stability** of the linear sway-yaw equations (eigenvalues of M^-1 dF/d(v, r)) is stated for
  information only: many full-form ships are unstable and the IMO zig-zag limits judge them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.hull import hull_forces, hull_forces_near, hull_forces_not_abkowitz
from vessel_gym.physics.kinematics import coriolis_forces
from vessel_gym.physics.params import HULL
from vessel_gym.physics.sections import AbkowitzHull, MMGHull
from vessel_gym.physics.shipfile import Ship, load_ship
from vessel_gym.physics.units import DEG
from vessel_gym.physics.vessel import far_models, mass_matrix, pack

#: finding statuses, from harmless to refused
OK, INFO, UNUSUAL, IMPOSSIBLE = "ok", "info", "unusual", "impossible"

CLARKE_1983 = "Clarke, Gedling & Hine 1983, Trans. RINA 125 (linear regressions)"
DRIFT_RESISTANCE_SRC = "Yasukawa & Yoshimura 2015 Table 3; Chislett & Stroem-Tejsen 1965"
DISSIPATION_SRC = "Fossen 2011 sec. 6.4: hydrodynamic damping is dissipative, D(nu) > 0"

#: (derivative, expected sign, source): the signs every published set shares (module text)
EXPECTED_SIGNS = (
    ("Y_v", -1.0, CLARKE_1983),
    ("N_v", -1.0, CLARKE_1983),
    ("N_r", -1.0, CLARKE_1983),
    ("X_vv", -1.0, DRIFT_RESISTANCE_SRC),
)
#: amplitude of v' = v/U and r' = r L/U for the energy check: small enough that the quadratic terms
#: dominate the quartic ones (|X'_vvvv v'^4| < 0.1 |X'_vv v'^2| for KVLCC2 at 0.03), inside every polynomial's
#: fitted range (PMM tests reach v' ~ 0.3, r' ~ 0.6)
ENERGY_AMPLITUDE = 0.03
#: directions in the (v', r') plane the energy check samples
ENERGY_DIRECTIONS = 36
#: normalised power P / (1/2 rho L^2 U^3 eps^2) above this is positive beyond rounding (the forces are
#: evaluated to ~1e-15 relative; the published quadratic forms are -0.01 ... -0.4)
ENERGY_ROUNDING = 1e-9
#: the rudder check: order (deg) and duration in ship lengths travelled
RUDDER_CHECK_DEG = 10.0
RUDDER_CHECK_LENGTHS = 1.0


@dataclass(frozen=True)
class Finding:
    """One line of the check: what was checked, its value, what is expected, the source, the status."""

    quantity: str
    value: float | None
    expected: str
    source: str
    status: str
    note: str = ""

    def to_dict(self) -> dict:
        d = {"quantity": self.quantity, "value": self.value, "expected": self.expected}
        d.update(source=self.source, status=self.status)
        if self.note:
            d["note"] = self.note
        return d


def _derivatives(ship: Ship) -> dict[str, float]:
    h = ship.hull
    if isinstance(h, MMGHull):
        return {name: float(getattr(h, name)) for name, _, _ in EXPECTED_SIGNS}
    if isinstance(h, AbkowitzHull):
        return {name: float(h.derivatives[name]) for name, _, _ in EXPECTED_SIGNS if name in h.derivatives}
    return {}


def sign_findings(ship: Ship) -> list[Finding]:
    """The derivatives of :data:`EXPECTED_SIGNS` the hull model has, each against its expected sign."""
    values = _derivatives(ship)
    out = []
    for name, sign, src in EXPECTED_SIGNS:
        if name not in values:
            continue
        v = values[name]
        status = OK if v * sign > 0.0 else UNUSUAL
        out.append(Finding(name, v, "< 0", src, status))
    return out


def _hull_forces_for(P: np.ndarray):
    """The deep-water hull forces compiled as the drivers of this ship compile them (no Abkowitz model for an
    MMG hull, no cross-flow model without ``[large_drift]``), so that a check before the first step compiles
    nothing the run does not."""
    if P[HULL.kind] == lo.HULL_ABKOWITZ:
        return hull_forces
    return hull_forces_not_abkowitz if far_models(P) else hull_forces_near


def hull_power(ship: Ship) -> tuple[float, float, float]:
    """The largest power of hull plus Coriolis forces at small drift and yaw about the straight approach at
    the test speed, normalised by 1/2 rho L^2 U^3 eps^2 (eps = :data:`ENERGY_AMPLITUDE`), with the (v', r')
    direction where it occurs. <= 0 for a hull that only takes energy from the ship."""
    P = pack(ship)
    hull_forces = _hull_forces_for(P)
    p = ship.particulars
    U, L = ship.test_speed_m_s, p.L_m

    def forces(v: float, r: float) -> np.ndarray:
        X, Y, N = hull_forces(P, U, v, r, 0.0)
        cX, cY, cN = coriolis_forces(P, U, v, r)
        return np.array([X + cX, Y + cY, N + cN])

    base = forces(0.0, 0.0)  # straight ahead: resistance only (bias terms of an asymmetric hull too)
    scale = 0.5 * p.rho_kg_m3 * L * L * U**3 * ENERGY_AMPLITUDE**2
    worst = (-math.inf, 0.0, 0.0)
    for k in range(ENERGY_DIRECTIONS):
        a = 2.0 * math.pi * k / ENERGY_DIRECTIONS
        vp, rp = ENERGY_AMPLITUDE * math.cos(a), ENERGY_AMPLITUDE * math.sin(a)
        v, r = vp * U, rp * U / L
        power = float(np.dot(forces(v, r) - base, (U, v, r)))  # the change the drift and yaw make, W
        worst = max(worst, (power / scale, vp / ENERGY_AMPLITUDE, rp / ENERGY_AMPLITUDE))
    return worst


def energy_finding(ship: Ship) -> Finding:
    q, cv, cr = hull_power(ship)
    ok = q <= ENERGY_ROUNDING
    note = "" if ok else f"the hull pushes the ship when it drifts and yaws (v', r') ~ ({cv:+.2f}, {cr:+.2f})"
    return Finding("hull power P'(v', r')", q, "<= 0", DISSIPATION_SRC, OK if ok else IMPOSSIBLE, note)


def rudder_finding(ship: Ship) -> Finding:
    """Rudder to starboard from the straight approach: the heading change after one ship length, deg."""
    from vessel_gym.physics.simulation import Simulation

    U = ship.test_speed_m_s
    sim = Simulation(ship)
    sim.reset(speed_m_s=U)
    sim.set_helm(rudder_order_rad=RUDDER_CHECK_DEG * DEG)
    sim.step(max(1, round(RUDDER_CHECK_LENGTHS * ship.particulars.L_m / U / sim.dt)))
    change = math.degrees(float(sim.heading[0]))
    change = (change + 180.0) % 360.0 - 180.0  # heading is 0 at the start
    ok = change > 0.0
    return Finding(
        "turn with starboard rudder, deg",
        change,
        "> 0",
        f"rudder to starboard turns the bow to starboard ({RUDDER_CHECK_DEG:g} deg for "
        f"{RUDDER_CHECK_LENGTHS:g} L from the approach)",
        OK if ok else IMPOSSIBLE,
        "" if ok else "the rudder turns the ship the wrong way",
    )


def stability_finding(ship: Ship) -> Finding:
    """Linear course stability: the largest real part of the sway-yaw eigenvalues, 1/s (info only)."""
    P = pack(ship)
    hull_forces = _hull_forces_for(P)
    U, L = ship.test_speed_m_s, ship.particulars.L_m
    dv, dr = 1e-4 * U, 1e-4 * U / L

    def yn(v: float, r: float) -> np.ndarray:
        X, Y, N = hull_forces(P, U, v, r, 0.0)
        cX, cY, cN = coriolis_forces(P, U, v, r)
        return np.array([Y + cY, N + cN])

    J = np.column_stack([(yn(dv, 0.0) - yn(-dv, 0.0)) / (2 * dv), (yn(0.0, dr) - yn(0.0, -dr)) / (2 * dr)])
    M = mass_matrix(ship)[1:, 1:]
    if not (np.isfinite(M).all() and np.isfinite(J).all()):
        # derivatives so large (a typo such as 1e300) that the sway-yaw mass or damping overflows: say where
        raise ValueError(
            f"{ship.path or ship.name}: the sway-yaw mass or damping is not finite at the test speed "
            "(check the hull derivatives and the added-mass terms for a misplaced exponent)"
        )
    lam = np.linalg.eigvals(np.linalg.solve(M, J))
    top = float(max(lam.real))
    return Finding(
        "course stability, 1/s",
        top,
        "< 0",
        "largest sway-yaw eigenvalue, Abkowitz 1964; an unstable ship is allowed, the zig-zag judges it",
        INFO,
        "course-stable" if top < 0.0 else "course-unstable: the helm must keep it straight",
    )


def check_ship(ship: str | Ship) -> list[Finding]:
    """Every check of the module text, in order: signs, energy, rudder, course stability. A hull given as
    code (``[hull] model = "module:Class"``) has no derivatives to read: only the rudder is checked."""
    s = load_ship(ship)
    if not isinstance(s.hull, (MMGHull, AbkowitzHull)):
        return [rudder_finding(s)]
    return [*sign_findings(s), energy_finding(s), rudder_finding(s), stability_finding(s)]


def impossible(findings: list[Finding]) -> list[Finding]:
    return [f for f in findings if f.status == IMPOSSIBLE]
