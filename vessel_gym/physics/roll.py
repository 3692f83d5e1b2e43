"""Roll, the optional fourth degree of freedom: its parameters and its forces (its ship-file table is
``sections.Roll``).

A ship file with a ``[roll]`` table adds roll angle phi (rad, starboard down) and roll rate p (rad/s) to the
states (layout.X_PHI, X_P). The roll equation is written about the longitudinal axis through the centre of
gravity G, as in Son & Nomoto (1982), so the rigid body adds no sway-roll inertia; the added mass does
(Y_pdot, K_vdot). The roll moment K is the sum of

* the hull's roll terms, a polynomial in u', v', r', p' = pL/U and phi in the SNAME prime system
  (``[roll.derivatives]``, e.g. K_v, K_vvphi, Y_phi, N_rrphi, X_phiphi), which also carry the heel-induced
  sway force and yaw moment into Y and N;
* the hydrostatic restoring -rho g nabla GZ(phi): the ship file's righting-lever curve where it gives one
  (``GZ_heel_deg``, ``GZ_m``), else the wall-sided small-angle arm GZ = GM sin(phi);
* roll damping -K_p1 p - K_p2 p|p| (dimensional, linear and quadratic) besides the hull's K_p p';
* the rudder's roll moment -z_R Y_R, its sway force acting z_R below the roll axis;
* optionally the reaction of the shaft torque on the hull, -Q_P for a right-handed propeller (clockwise seen
  from astern when going ahead), +Q_P for a left-handed one, with Q_P the propeller's absorbed torque (equal
  to the shaft's drive torque in steady running).

A ship without ``[roll]`` never evaluates any of this: phi and p stay exactly 0 and the 3-DOF equations are
untouched (vessel.derivatives).
"""

from __future__ import annotations

import math
import re

import numpy as np
from numba import njit

from vessel_gym.physics import layout as lo
from vessel_gym.physics.params import BODY, HULL, ROLL, put, put_keys
from vessel_gym.physics.schema import SpecError, as_float
from vessel_gym.physics.sections import Roll

#: acceleration due to gravity, m/s^2 (standard gravity)
G_M_S2 = 9.80665
#: heel up to which the roll model holds, deg: the Intact Stability Code (2008, Part A 2.2) judges righting levers
#: up to 40 deg at most (or the downflooding angle); beyond it GM sin(phi), a GZ curve's use in a manoeuvring
#: model and hull terms fitted at small heel have no basis (runaway.py stops a vessel there)
HEEL_RANGE_DEG = 40.0

_TOKEN = re.compile(r"phi|[uvrp]")
_TERM = re.compile(r"^([XYKN])_((?:phi|[uvrp])+)$")
#: added-mass derivatives of roll read from [roll.derivatives] (SNAME prime, 1/2 rho L^4 or L^5)
ROLL_ACCEL = ("Y_pdot", "K_vdot", "K_pdot", "K_rdot", "N_pdot")


def roll_term(name: str) -> tuple[str, int, int, int, int, int] | None:
    """Parse a roll-term name: 'K_vvphi' -> ('K', e_u, e_v, e_r, e_p, e_phi) = ('K', 0, 2, 0, 0, 1); None if
    not a term. A term of the roll table either is a K term or contains p or phi."""
    m = _TERM.match(name)
    if not m:
        return None
    tokens = _TOKEN.findall(m.group(2))
    e = tuple(tokens.count(t) for t in ("u", "v", "r", "p", "phi"))
    if m.group(1) != "K" and e[3] == 0 and e[4] == 0:
        return None  # a 3-DOF term: its home is [hull.derivatives]
    return (m.group(1), *e)


def check_roll(roll: Roll, where: str) -> None:
    """Reject an unknown or implausible roll derivative or a malformed GZ curve with a one-line message naming
    the key."""
    h, gz = roll.GZ_heel_deg, roll.GZ_m
    w = f"{where} [roll]"
    if len(h) != len(gz):
        raise SpecError(f"{w} GZ_m: {len(gz)} values for {len(h)} GZ_heel_deg")
    if h:
        if not 2 <= len(h) <= lo.MAX_GZ_POINTS:
            raise SpecError(f"{w} GZ_heel_deg: needs 2 to {lo.MAX_GZ_POINTS} values, got {len(h)}")
        if h[0] != 0.0 or gz[0] != 0.0:
            raise SpecError(f"{w} GZ_heel_deg: the curve starts at 0 deg with GZ_m 0")
        if any(b <= a for a, b in zip(h, h[1:])):
            raise SpecError(f"{w} GZ_heel_deg: values must increase strictly")
        if h[-1] < HEEL_RANGE_DEG:
            raise SpecError(
                f"{w} GZ_heel_deg: the curve ends at {h[-1]:g} deg, it must reach {HEEL_RANGE_DEG:g} deg"
            )
    for key, value in roll.derivatives.items():
        w = f"{where} [roll.derivatives] {key}"
        number = isinstance(value, (int, float)) and not isinstance(value, bool)
        if not number or not math.isfinite(as_float(value, w)):
            raise SpecError(f"{w}: expected a finite number, got {value!r}")
        if key in ROLL_ACCEL:
            continue
        term = roll_term(key)
        if term is None:
            raise SpecError(
                f"{w}: not a roll derivative (expected K_<u|v|r|p|phi...>, X/Y/N terms with p or phi, or one of "
                f"{', '.join(ROLL_ACCEL)})"
            )
        if max(term[1:]) > 4:
            raise SpecError(f"{w}: powers above 4 are not supported")
        if abs(value) > 10.0:
            raise SpecError(f"{w}: |{value:g}| > 10 is not a plausible nondimensional derivative")


def roll_mass_matrix(M3: np.ndarray, roll: Roll, L: float, rho: float) -> np.ndarray:
    """The 3x3 mass matrix over (v, r, p) from the sway-yaw block ``M3[1:, 1:]`` of the 3-DOF mass matrix,
    the roll inertia about G and the roll added masses (prime system, 1/2 rho L^4 and 1/2 rho L^5)."""
    d = roll.derivatives
    q4 = 0.5 * rho * L**4
    q5 = 0.5 * rho * L**5
    M = np.zeros((3, 3))
    M[:2, :2] = M3[1:, 1:]
    M[0, 2] = -d.get("Y_pdot", 0.0) * q4
    M[2, 0] = -d.get("K_vdot", d.get("Y_pdot", 0.0)) * q4
    M[1, 2] = -d.get("N_pdot", 0.0) * q5
    M[2, 1] = -d.get("K_rdot", d.get("N_pdot", 0.0)) * q5
    M[2, 2] = roll.I_xG_kgm2 - d.get("K_pdot", 0.0) * q5
    return M


def pack_roll(P: np.ndarray, M3: np.ndarray, roll: Roll, mass: float, L: float, rho: float) -> None:
    """Fill the record params.ROLL of the parameter row ``P``: the [roll] table's keys and the fields derived
    from them."""
    put_keys(P, ROLL, roll)
    put(
        P,
        ROLL,
        on=1.0,
        Minv=np.linalg.inv(roll_mass_matrix(M3, roll, L, rho)).ravel(),
        rho_g_nabla_GM=mass * G_M_S2 * roll.GM_m,  # rho g nabla GM with rho nabla = m
        rho_g_nabla=mass * G_M_S2,
        GZ_points=len(roll.GZ_heel_deg),
        GZ_heel=np.radians(roll.GZ_heel_deg),
        GZ=roll.GZ_m,
        torque_sign={"none": 0.0, "right_handed": -1.0, "left_handed": 1.0}[roll.propeller_torque_reaction],
    )
    column = {"X": 5, "Y": 6, "K": 7, "N": 8}
    monomials: dict[tuple[int, ...], list[float]] = {}
    for name, value in roll.derivatives.items():
        term = roll_term(name) if name not in ROLL_ACCEL else None
        if term is None or value == 0.0:
            continue
        eq, *exponents = term
        row = monomials.setdefault(tuple(exponents), [*exponents, 0.0, 0.0, 0.0, 0.0])
        row[column[eq]] += value
    if len(monomials) > lo.MAX_ROLL_MONOMIALS:
        raise ValueError(f"more than {lo.MAX_ROLL_MONOMIALS} distinct roll monomials")
    for k, row in enumerate(monomials.values()):
        P[ROLL.monomials + lo.ROLL_STRIDE * k : ROLL.monomials + lo.ROLL_STRIDE * (k + 1)] = row
    P[ROLL.n_monomials] = len(monomials)


def free_roll_frequency(P: np.ndarray) -> float:
    """Upright free-roll natural frequency omega_phi = sqrt(rho g nabla GM / I_eff), rad/s, of a packed
    parameter row ``P``; I_eff is the roll inertia the equations integrate, added mass included, with sway and
    yaw free (1 / the (p, p) entry of the inverse sway-yaw-roll mass matrix). 0 on a 3-DOF ship."""
    return math.sqrt(max(P[ROLL.rho_g_nabla_GM] * P[ROLL.Minv + 8], 0.0))


@njit(cache=True)
def _powers(x):
    return (1.0, x, x * x, x * x * x, x * x * x * x)


@njit(cache=True)
def restoring_moment(P, phi):
    """Hydrostatic roll moment, N m: -rho g nabla GZ(|phi|) sign(phi) from the ship file's GZ curve (linear
    between its points, the last segment continued beyond it), else -rho g nabla GM sin(phi)."""
    k = int(P[ROLL.GZ_points])
    if k == 0:
        return -P[ROLL.rho_g_nabla_GM] * math.sin(phi)
    a = abs(phi)
    i = 1
    while i < k - 1 and a > P[ROLL.GZ_heel + i]:
        i += 1
    p0 = P[ROLL.GZ_heel + i - 1]
    p1 = P[ROLL.GZ_heel + i]
    g0 = P[ROLL.GZ + i - 1]
    g1 = P[ROLL.GZ + i]
    gz = g0 + (g1 - g0) * (a - p0) / (p1 - p0)
    return -P[ROLL.rho_g_nabla] * (gz if phi >= 0.0 else -gz)


@njit(cache=True)
def roll_forces(P, u, v, r, p, phi):
    """The roll-dependent forces of a 4-DOF ship: hull roll terms, restoring and damping.

    Nondimensional as the Abkowitz hull (hull.abkowitz_forces): u' = u/U, v' = v/U, r' = rL/U (clipped at
    r_prime_max), p' = pL/U, with U held at U_min at low speed. Returns (X, Y, K, N) in N, N, N m, N m;
    the rudder's roll moment is added by the caller (it needs Y_R).
    """
    L = P[BODY.L_m]
    U = math.sqrt(u * u + v * v)
    Ue = max(U, P[HULL.U_min])
    rmax = P[HULL.r_prime_max]
    rp = r * L / Ue
    rp = -rmax if rp < -rmax else (rmax if rp > rmax else rp)
    pu = _powers(u / Ue)
    pv = _powers(v / Ue)
    pr = _powers(rp)
    pp = _powers(p * L / Ue)
    pf = _powers(phi)
    Xs = 0.0
    Ys = 0.0
    Ks = 0.0
    Ns = 0.0
    for k in range(int(P[ROLL.n_monomials])):
        j = ROLL.monomials + lo.ROLL_STRIDE * k
        m = pu[int(P[j])] * pv[int(P[j + 1])] * pr[int(P[j + 2])] * pp[int(P[j + 3])] * pf[int(P[j + 4])]
        Xs += P[j + 5] * m
        Ys += P[j + 6] * m
        Ks += P[j + 7] * m
        Ns += P[j + 8] * m
    q = 0.5 * P[BODY.rho_kg_m3] * L * L * Ue * Ue
    K = q * L * Ks + restoring_moment(P, phi) - P[ROLL.damping_linear_Nms] * p - P[ROLL.damping_quadratic_Nms2] * p * abs(p)
    return q * Xs, q * Ys, K, q * L * Ns
