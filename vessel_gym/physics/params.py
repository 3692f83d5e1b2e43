"""The compiled model's parameters, as one named record per component kind.

Each component kind (the rigid body, the hull and its Abkowitz, MMG and large-drift models, the propeller,
transmission, engine, governor, rudder, steering gear, windage, wave drift, roll) declares here the fields its
equations read, each with its unit and meaning. The records are built from the ship file's sections by
:func:`vessel_gym.physics.vessel.pack` (and, for the large-drift and roll records, by ``crossflow.pack`` and
``roll.pack_roll``), which writes every value by field name (:func:`put`: a name the record does not
declare, or a table of the wrong length, is an error).

A vessel's records lie side by side in one float64 row, so that a batch of vessels of different ships is one
(N, NP) array and one compiled signature; a record is the offsets of its fields in that row, a named tuple of
integers (``PROPELLER.k_0``) that numba folds into the machine code as constants, so reading ``P[PROPELLER.k_0]``
costs one load, as an index constant did. A table field (``ENGINE.map_torque``) is the offset of its first
value. Codes that select a model (``layout.HULL_MMG``, ...) are stored as floats.

All records live in this one module, not in the modules of their equations, because the equations read one
another's parameters (the wake fraction of the propeller is read by the shallow-water, MMG-rudder and
Son & Nomoto equations; the hull's low-speed limit by the rudder and roll equations) and those modules import
one another: a record here is importable by every equation without a cycle. Adding a parameter to a built-in
component touches its record here (field, unit, doc), the line of its builder that fills it from the ship
file, its schema entry (the section's dataclass in ``shipfile.py``) and the equation that reads it; a
component written in Python declares its parameters as the frozen dataclass ``Params`` of its own file
(docs/components.md).
"""

from __future__ import annotations

from collections import namedtuple
from dataclasses import dataclass

import numpy as np

from vessel_gym.physics import layout as lo


@dataclass(frozen=True)
class Field:
    """One field of a record: its name, unit, meaning and size (1, or the length of a table)."""

    name: str
    unit: str
    doc: str
    size: int = 1


@dataclass(frozen=True)
class Record:
    """A record type: the component kind it belongs to and its fields, with their offsets in the row."""

    kind: str
    doc: str
    fields: tuple[Field, ...]
    at: tuple  # the named tuple of offsets the kernels read


RECORDS: dict[str, Record] = {}
_row: list[str] = []  # the name of every float of the row, "kind.field" or "kind.field[i]"


def record(kind: str, doc: str, *fields: Field):
    """Declare the record of one component kind; returns the named tuple of its fields' offsets in the row."""
    if kind in RECORDS:
        raise ValueError(f"record {kind!r} declared twice")
    offsets = []
    for f in fields:
        offsets.append(len(_row))
        _row.extend([f"{kind}.{f.name}"] if f.size == 1 else [f"{kind}.{f.name}[{i}]" for i in range(f.size)])
    cls = namedtuple("".join(w.capitalize() for w in kind.split("_")) + "Record", [f.name for f in fields])
    at = cls(*offsets)
    RECORDS[kind] = Record(kind, doc, tuple(fields), at)
    return at


def _record_of(at) -> Record:
    for rec in RECORDS.values():
        if rec.at is at:
            return rec
    raise ValueError(f"{at!r} is not a parameter record")


def put(P: np.ndarray, at, **values) -> None:
    """Write ``values`` into the record ``at`` of the parameter row ``P`` by field name; a table field takes
    a sequence of at most its size (the rest stays as it is)."""
    rec = _record_of(at)
    sizes = {f.name: f.size for f in rec.fields}
    for name, value in values.items():
        if name not in sizes:
            raise ValueError(f"record {rec.kind!r} has no field {name!r}")
        i = getattr(at, name)
        if sizes[name] == 1:
            P[i] = value
        else:
            a = np.asarray(value, dtype=float).ravel()
            if a.size > sizes[name]:
                raise ValueError(f"{rec.kind}.{name}: {a.size} values for a table of {sizes[name]}")
            P[i : i + a.size] = a


def get(P: np.ndarray, at) -> dict:
    """The record ``at`` of the row ``P`` by field name (tables as arrays): for reading and printing."""
    rec = _record_of(at)
    return {
        f.name: (float(P[getattr(at, f.name)]) if f.size == 1 else P[getattr(at, f.name) :][: f.size].copy())
        for f in rec.fields
    }


F = Field

BODY = record(
    "body",
    "particulars, rigid body and mass matrix (rigid body + added mass, inverted once at pack time), "
    "M = [[m11, 0, 0], [0, m22, m23], [0, m32, m33]]; Coriolis coefficients on the right-hand side: "
    "X += CX_vr v r + CX_rr r^2, Y -= CY_ur u r, N -= CN_ur u r",
    F("L", "m", "length between perpendiculars"),
    F("B", "m", "beam"),
    F("T", "m", "mean draught"),
    F("rho", "kg/m^3", "water density"),
    F("m", "kg", "mass"),
    F("x_G", "m", "centre of gravity forward of the origin (midship)"),
    F("m11", "kg", "surge mass, rigid body + added"),
    F("Minv22", "1/kg", "inverse sway-yaw mass matrix, (v, v)"),
    F("Minv23", "1/(kg m)", "inverse sway-yaw mass matrix, (v, r)"),
    F("Minv32", "1/(kg m)", "inverse sway-yaw mass matrix, (r, v)"),
    F("Minv33", "1/(kg m^2)", "inverse sway-yaw mass matrix, (r, r)"),
    F("CX_vr", "kg", "surge Coriolis coefficient of v r"),
    F("CX_rr", "kg m", "surge Coriolis coefficient of r^2"),
    F("CY_ur", "kg", "sway Coriolis coefficient of u r"),
    F("CN_ur", "kg m", "yaw Coriolis coefficient of u r"),
)

HULL = record(
    "hull",
    "the hull model in use and its low-speed limits (hull.py)",
    F("kind", "-", "layout.HULL_NONE (a user's hull), HULL_ABKOWITZ or HULL_MMG"),
    F("r_prime_max", "-", "clip of r' in nonlinear terms at low speed"),
    F("U_min", "m/s", "speed below which nondimensional hull terms are faded out"),
)

ABKOWITZ = record(
    "abkowitz",
    "Abkowitz (1964) polynomial hull (hull.abkowitz_forces); terms merged by monomial u'^e_u v'^e_v r'^e_r "
    "delta^e_d: n_monomials rows of (e_u, e_v, e_r, e_d, c_X, c_Y, c_N), so that a monomial shared by X, Y "
    "and N (e.g. Y_vvr, N_vvr) is evaluated once; a coefficient is 0 where the equation has no such term",
    F("force_norm", "kg/m^3", "1/2 (SNAME prime) or 1 (seed eq. 5-6), times rho"),
    F("U_ref", "m/s", "reference speed of the u-perturbation terms (0: u' = u/U)"),
    F("R_res", "N s^2/m^2", "added resistance coefficient R/(u|u|)"),
    F("cross_flow_Cd", "-", "2-D cross-flow drag coefficient of the hull sections"),
    F("n_monomials", "-", "number of distinct monomials"),
    F("monomials", "-", "monomial rows, layout.ABK_STRIDE values each", lo.ABK_STRIDE * lo.MAX_MONOMIALS),
)

MMG = record(
    "mmg_hull",
    "MMG hull (Yasukawa & Yoshimura 2015, eq. 8-10), nondimensional on 1/2 rho L d U^2 (1/2 rho L^2 d U^2 "
    "for N)",
    *(
        F(name, "-", "")
        for name in (
            "R_0", "X_vv", "X_vr", "X_rr", "X_vvvv",
            "Y_v", "Y_r", "Y_vvv", "Y_vvr", "Y_vrr", "Y_rrr",
            "N_v", "N_r", "N_vvv", "N_vvr", "N_vrr", "N_rrr",
        )  # fmt: skip
    ),
)

LARGE_DRIFT = record(
    "large_drift",
    "hull at any drift angle (crossflow.py, ship-file table [large_drift]): Yoshimura, Nakao & Ishibashi "
    "(2009) cross-flow model, blended with the polynomial hull outside its fitted range",
    F("on", "-", "1 with a [large_drift] table, 0 off"),
    F("C_D", "-", "cross-flow drag coefficient of the hull at 90 deg drift, on 1/2 rho L d"),
    F("C_rY", "-", "yaw-rate factor of the cross flow in the sway force"),
    F("C_rN", "-", "yaw-rate factor of the cross flow in the yaw moment"),
    F("R_0_astern", "-", "straight-astern resistance coefficient, on 1/2 rho L d u^2"),
    F("mmg_drift_max", "rad", "flow angle up to which the polynomial is used alone"),
    F("cross_flow_drift_min", "rad", "flow angle from which the cross-flow model is used alone"),
    F("mmg_r_prime_max", "-", "|r'| up to which the polynomial is used alone"),
    F("cross_flow_r_prime_min", "-", "|r'| from which the cross-flow model is used alone"),
    # the model's linear terms on 1/2 rho L d U^2 (L for N): the MMG set's, or converted from an Abkowitz set
    F("R_0", "-", "straight-ahead resistance coefficient"),
    F("X_vr", "-", "linear term"),
    F("Y_v", "-", "linear term"),
    F("Y_r", "-", "linear term"),
    F("N_v", "-", "linear term"),
    F("N_r", "-", "linear term"),
    F("C_X_rr", "kg m", "x_G m r^2 surge term an Abkowitz hull's equations of motion leave out"),
    F("C_N_ur", "kg m", "-x_G m u r yaw term an Abkowitz hull's equations of motion leave out"),
    F("polynomial_u_prime_max", "-", "|u'| up to which an Abkowitz polynomial is used alone"),
    F("cross_flow_u_prime_min", "-", "|u'| from which the cross-flow model is used alone"),
    # bounds of the polynomial's range for the test without square root, atan2 or division
    # (crossflow.inside_polynomial_range), each shortened by the factor 1 - 1e-9
    F("tan_mmg_drift_max", "-", "tan(mmg_drift_max)"),
    F("mmg_r_prime_max_squared", "-", "mmg_r_prime_max^2"),
    F("polynomial_u_prime_max_squared", "-", "polynomial_u_prime_max^2"),
)

PROPELLER = record(
    "propeller",
    "open-water propeller (K_T, K_Q quadratics in J), its wake and thrust deduction, the MMG wake change in "
    "manoeuvres, astern and four-quadrant behaviour (propulsion.py), the Son & Nomoto (1982) inflow "
    "1 - w = 1 - w_P0 + tau_P ((v' + x'_P r')^2 + c_pv v' + c_pr r') (sonnomoto.py)",
    F("on", "-", "1 on a ship with a propeller"),
    F("D_P", "m", "diameter"),
    F("k_0", "-", "K_T = k_0 + k_1 J + k_2 J^2"),
    F("k_1", "-", ""),
    F("k_2", "-", ""),
    F("q_0", "-", "K_Q = q_0 + q_1 J + q_2 J^2"),
    F("q_1", "-", ""),
    F("q_2", "-", ""),
    F("w_P0", "-", "wake fraction in straight running"),
    F("t_P", "-", "thrust deduction factor"),
    F("x_P_prime", "-", "propeller position / L"),
    F("C_1", "-", "MMG wake change in manoeuvres"),
    F("C_2_plus", "-", ""),
    F("C_2_minus", "-", ""),
    F("astern_kt_ratio", "-", "astern bollard K_T / ahead bollard K_T"),
    F("astern_kq_ratio", "-", "astern bollard K_Q / ahead bollard K_Q"),
    F("astern_inflow_slope", "-", "d(C_T*)/d(u_a/|n|D) in quadrant 4 relative to k_0"),
    F("four_quadrant", "-", "four-quadrant table code, propeller4q.TABLE_NAMES index + 1 (0: none)"),
    F("wake_kind", "-", "layout.WAKE_MMG or WAKE_SON_NOMOTO"),
    F("tau_P", "-", "Son & Nomoto wake: factor of the squared transverse inflow"),
    F("c_pv", "-", "Son & Nomoto wake: per v'"),
    F("c_pr", "-", "Son & Nomoto wake: per r'"),
)

TRANSMISSION = record(
    "transmission",
    "transmission and shaft (propulsion.py)",
    F("gear_ratio", "-", "engine rev / propeller rev"),
    F("eta_gear", "-", "transmission efficiency"),
    F("I_shaft", "kg m^2", "propeller + entrained water + shafting + i^2 engine inertia"),
    F("Q_friction", "N m", "shaft friction torque at rated speed (scaled linearly with speed)"),
    F("clutch_min_rev", "rev/s", "|order| (propeller) below which the clutch is out"),
)

ENGINE = record(
    "engine",
    "engine torque map and reversing (propulsion.py): a clutch/gearbox (or ideal) drive, or a "
    "direct-reversing two-stroke diesel started and braked on starting air",
    F("n_e_rated", "rev/s", "rated speed"),
    F("Q_e_rated", "N m", "rated (MCR) torque"),
    F("map_speed", "-", "torque map speed breakpoints, engine speed / rated", lo.MAP_NS),
    F("map_fuel", "-", "torque map fuel-index breakpoints", lo.MAP_NF),
    F("map_torque", "-", "torque / rated torque, row-major [speed, fuel]", lo.MAP_NS * lo.MAP_NF),
    F("astern_torque_ratio", "-", "astern torque / ahead torque"),
    F("reversing", "-", "layout.REVERSING_CLUTCH or REVERSING_DIRECT_AIR"),
    F("reversal_time", "s", "time to shift the reversing gear from one direction to the other"),
    F("air_brake_rev", "rev/s", "engine speed below which starting air may be applied"),
    F("firing_rev", "rev/s", "engine speed in the ordered direction at which fuel is admitted"),
    F("Q_air", "N m", "engine torque of the starting air"),
    # the slot taken over by a user's component written in Python (components.compose): the built-in's
    # equations stay in the kernel and read this flag
    F("by_component", "-", "1: a user's engine gives the shaft's drive torque (F_ext[3]); governor held"),
)

GOVERNOR = record(
    "governor",
    "PI speed governor (propulsion.py)",
    F("Kp", "-", "fuel index per unit relative speed error"),
    F("Ki", "1/s", "fuel index per (unit relative speed error * s)"),
)

RUDDER = record(
    "rudder",
    "rudder: MMG (Yasukawa & Yoshimura 2015, steering.py), Son & Nomoto (1982, sonnomoto.py: the flow angle "
    "at the rudder from a polynomial in v', r', the propeller race from momentum theory; A_R, a_H, x'_H, "
    "x'_R, epsilon, kappa and f_alpha shared with the MMG rudder) or in the hull's delta terms",
    F("kind", "-", "layout.RUDDER_DERIVATIVES, RUDDER_MMG or RUDDER_SON_NOMOTO"),
    F("A_R", "m^2", "rudder area"),
    F("H_R", "m", "rudder span"),
    F("t_R", "-", "steering resistance deduction"),
    F("a_H", "-", "rudder force increase factor"),
    F("x_H_prime", "-", "position of the additional lateral force / L"),
    F("x_R_prime", "-", "rudder position / L"),
    F("gamma_R_minus", "-", "flow straightening, beta_R < 0"),
    F("gamma_R_plus", "-", "flow straightening, beta_R > 0"),
    F("l_R_prime", "-", "effective longitudinal rudder position / L"),
    F("epsilon", "-", "wake ratio at rudder and propeller"),
    F("kappa", "-", "propeller race factor"),
    F("f_alpha", "1/rad", "rudder lift gradient"),
    F("eta", "-", "D_P / H_R (at most 1)"),
    F("gamma_R", "-", "Son & Nomoto: flow-straightening factor of the sway velocity at the rudder"),
    F("c_Rr", "-", "Son & Nomoto: v'_R per r'"),
    F("c_Rrrr", "-", "Son & Nomoto: v'_R per r'^3"),
    F("c_Rrrv", "-", "Son & Nomoto: v'_R per r'^2 v'"),
    F("c_RX", "-", "Son & Nomoto: rudder drag X_R = c_RX F_N sin(delta)"),
)

STEERING_GEAR = record(
    "steering_gear",
    "rate-limited first-order steering gear (steering.py)",
    F("delta_max", "rad", "rudder angle limit"),
    F("delta_rate_max", "rad/s", "rudder rate limit"),
    F("time_constant", "s", "first-order lag"),
    F("by_component", "-", "1: a user's steering gear gives the rudder rate"),
)

WINDAGE = record(
    "windage",
    "wind loads of Blendermann (1994) (atmosphere.py)",
    F("on", "-", "1 with a [windage] table"),
    F("A_FW", "m^2", "frontal projected area"),
    F("A_LW", "m^2", "lateral projected area"),
    F("s_L", "m", "centre of lateral area forward of the origin"),
    F("CD_t", "-", "transverse drag coefficient"),
    F("CD_l_AF_0", "-", "longitudinal drag coefficient, wind from ahead"),
    F("CD_l_AF_pi", "-", "longitudinal drag coefficient, wind from astern"),
    F("delta", "-", "cross-force parameter"),
    F("kappa", "-", "rolling-moment factor"),
)

WAVE_DRIFT = record(
    "wave_drift",
    "mean wave drift: nondimensional X, Y, N coefficients tabulated over the encounter angle, 0..360 deg in "
    "5 deg steps (seastate.py)",
    F("on", "-", "1 with a [wave_drift] table"),
    F("table", "-", "zero-speed coefficients, 3 x layout.WAVE_NA", 3 * lo.WAVE_NA),
    F("speed_table", "-", "forward-speed term per unit 2 omega_0 U / g, 3 x layout.WAVE_NA", 3 * lo.WAVE_NA),
)

ROLL = record(
    "roll",
    "roll, the optional fourth degree of freedom (roll.py); every field 0 on a 3-DOF ship. Hull roll terms "
    "in the SNAME prime system (1/2 rho L^2 U^2, times L for K and N) merged by monomial u'^a v'^b r'^c "
    "p'^d phi^e: n_monomials rows of (a, b, c, d, e, c_X, c_Y, c_K, c_N)",
    F("on", "-", "1 with a [roll] table"),
    F("Minv", "SI", "inverse of the 3x3 mass matrix over (v, r, p), rigid body and added mass, row-major", 9),
    F("rho_g_nabla_GM", "N m/rad", "hydrostatic restoring (times sin phi)"),
    F("rho_g_nabla", "N", "weight of the displaced water"),
    F("GZ_points", "-", "number of points of the righting-lever curve (0: GM sin phi)"),
    F("GZ_heel", "rad", "heel breakpoints, from 0, increasing", lo.MAX_GZ_POINTS),
    F("GZ", "m", "righting lever at the breakpoints", lo.MAX_GZ_POINTS),
    F("K_p_linear", "N m s/rad", "linear roll damping"),
    F("K_p_quadratic", "N m s^2/rad^2", "quadratic roll damping"),
    F("z_R", "m", "rudder's centre of effort below the roll axis (through G)"),
    F("torque_sign", "-", "shaft torque reaction K = sign Q_P: -1 right-handed, +1 left-handed, 0 off"),
    F("n_monomials", "-", "number of distinct monomials"),
    F("monomials", "-", "monomial rows, layout.ROLL_STRIDE values each", lo.ROLL_STRIDE * lo.MAX_ROLL_MONOMIALS),
)

NP = len(_row)  # floats in a parameter row
PARAM_NAMES = tuple(_row)  # "kind.field" of every float of the row
