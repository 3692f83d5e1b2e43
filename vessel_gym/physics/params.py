"""The compiled model's parameters, as one named record per component kind.

Each component kind (the rigid body, the hull and its Abkowitz, MMG and large-drift models, the propeller,
transmission, engine, rudder, steering gear, windage, wave drift, roll) has a record: the fields its equations
read, each with its unit and meaning. A record is derived from its ship-file table, the dataclass of
:mod:`vessel_gym.physics.sections`: every number key of the table (a ``float`` field; not a string, a table, a
dict or a key that may be left out) is a field of the record under the key's own name, with the unit and doc of
its ``param(...)``, and :func:`put_keys` copies them all from a loaded table by name, as written (a key in deg,
rpm or kW too: the equations read such a value in SI through a derived field). The table is the one home
of such a parameter: its unit and meaning are not written a second time here. What the table does not hold as it
stands is declared below, where its record is: a code chosen by a string key (``PROPELLER.wake_kind``), a flag
(``on``), a value in the equations' SI unit converted from the file's (``STEERING_GEAR.delta_max`` in rad from
``max_angle_deg``), a value computed from several tables (the mass matrix), a table of fixed size. These
derived fields are written by :func:`vessel_gym.physics.vessel.pack` (and, for the large-drift and roll
records, by ``crossflow.pack`` and ``roll.pack_roll``) by field name (:func:`put`: a name the record does not
declare, or a table of the wrong length, is an error).

Adding a parameter to a built-in component therefore touches its key in the table's dataclass
(``sections.py``) and the equation that reads ``P[RECORD.key]``; a derived parameter touches its field here, the
line of its builder that computes it, and the equation. A component written in Python declares its parameters
as the frozen dataclass ``Params`` of its own file (docs/components.md).

A vessel's records lie side by side in one float64 row, so that a batch of vessels of different ships is one
(N, NP) array and one compiled signature; a record is the offsets of its fields in that row, a named tuple of
integers (``PROPELLER.k_0``) that numba folds into the machine code as constants, so reading ``P[PROPELLER.k_0]``
costs one load, as an index constant did. A table field (``ENGINE.map_torque``) is the offset of its first
value. Codes that select a model (``layout.HULL_MMG``, ...) are stored as floats.

All records live in this one module, not in the modules of their equations, because the equations read one
another's parameters (the wake fraction of the propeller is read by the shallow-water, MMG-rudder and
Son & Nomoto equations; the hull's low-speed limit by the rudder and roll equations) and those modules import
one another: a record here is importable by every equation without a cycle.
"""

from __future__ import annotations

import dataclasses
import typing
from collections import namedtuple
from dataclasses import dataclass

import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics import sections as sc


@dataclass(frozen=True)
class Field:
    """One field of a record: its name, unit, meaning and size (1, or the length of a table); ``key`` when it
    is a number key of the record's ship-file table, copied as written (:func:`put_keys`)."""

    name: str
    unit: str
    doc: str
    size: int = 1
    key: bool = False


@dataclass(frozen=True)
class Record:
    """A record type: the component kind it belongs to, its fields with their offsets in the row, and the
    ship-file table its key fields are copied from (None: every field derived)."""

    kind: str
    doc: str
    fields: tuple[Field, ...]
    at: tuple  # the named tuple of offsets the kernels read
    section: type | None = None


RECORDS: dict[str, Record] = {}
_row: list[str] = []  # the name of every float of the row, "kind.field" or "kind.field[i]"


def table_keys(section: type) -> tuple[Field, ...]:
    """The fields a record takes from its ship-file table ``section`` (a dataclass of ``schema.param``
    fields): every key typed ``float``, under its own name, with the unit and doc of its ``param``. A key
    that may be left out (``float | None``) has no value to copy: what stands in its place is derived."""
    hints = typing.get_type_hints(section)
    return tuple(
        Field(f.name, f.metadata.get("unit", "-"), f.metadata.get("doc", ""), key=True)
        for f in dataclasses.fields(section)
        if hints[f.name] is float
    )


def record(kind: str, doc: str, *derived: Field, section: type | None = None):
    """Declare the record of one component kind: the number keys of its ship-file table ``section`` (if any),
    then the ``derived`` fields; returns the named tuple of its fields' offsets in the row."""
    if kind in RECORDS:
        raise ValueError(f"record {kind!r} declared twice")
    fields = (*(table_keys(section) if section is not None else ()), *derived)
    names = [f.name for f in fields]
    twice = [n for n in names if names.count(n) > 1]
    if twice:  # a derived field named like a key of the table: one name, one home
        raise ValueError(f"record {kind!r}: field {twice[0]!r} declared twice")
    offsets = []
    for f in fields:
        offsets.append(len(_row))
        _row.extend([f"{kind}.{f.name}"] if f.size == 1 else [f"{kind}.{f.name}[{i}]" for i in range(f.size)])
    cls = namedtuple("".join(w.capitalize() for w in kind.split("_")) + "Record", [f.name for f in fields])
    at = cls(*offsets)
    RECORDS[kind] = Record(kind, doc, tuple(fields), at, section)
    return at


def _record_of(at) -> Record:
    for rec in RECORDS.values():
        if rec.at is at:
            return rec
    raise ValueError(f"{at!r} is not a parameter record")


def put_keys(P: np.ndarray, at, table: object) -> None:
    """Copy every number key of the ship-file table ``table`` (an instance of the record's section) into the
    record ``at`` of the parameter row ``P``, by name."""
    rec = _record_of(at)
    if rec.section is None or not isinstance(table, rec.section):
        source = rec.section.__name__ if rec.section is not None else "no ship-file table"
        raise TypeError(f"record {rec.kind!r} is built from {source}, not {type(table).__name__}")
    for f in rec.fields:
        if f.key:
            P[getattr(at, f.name)] = getattr(table, f.name)


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
    "particulars ([particulars] keys), rigid body and mass matrix (rigid body + added mass, inverted once at "
    "pack time), M = [[m11, 0, 0], [0, m22, m23], [0, m32, m33]]; Coriolis coefficients on the right-hand side: "
    "X += CX_vr v r + CX_rr r^2, Y -= CY_ur u r, N -= CN_ur u r",
    F("m", "kg", "mass (mass_kg, or rho_kg_m3 times displacement_m3)"),
    F("m11", "kg", "surge mass, rigid body + added"),
    F("Minv22", "1/kg", "inverse sway-yaw mass matrix, (v, v)"),
    F("Minv23", "1/(kg m)", "inverse sway-yaw mass matrix, (v, r)"),
    F("Minv32", "1/(kg m)", "inverse sway-yaw mass matrix, (r, v)"),
    F("Minv33", "1/(kg m^2)", "inverse sway-yaw mass matrix, (r, r)"),
    F("CX_vr", "kg", "surge Coriolis coefficient of v r"),
    F("CX_rr", "kg m", "surge Coriolis coefficient of r^2"),
    F("CY_ur", "kg", "sway Coriolis coefficient of u r"),
    F("CN_ur", "kg m", "yaw Coriolis coefficient of u r"),
    section=sc.Particulars,
)

HULL = record(
    "hull",
    "the hull model in use and the low-speed limits both hull tables give (hull.py), from whichever hull "
    "table the ship has",
    F("kind", "-", "layout.HULL_NONE (a user's hull), HULL_ABKOWITZ or HULL_MMG"),
    F("r_prime_max", "-", "clip of r' in nonlinear terms at low speed"),
    F("U_min", "m/s", "speed below which nondimensional hull terms are faded out"),
)

ABKOWITZ = record(
    "abkowitz",
    "Abkowitz (1964) polynomial hull (hull.abkowitz_forces), [hull] model = 'abkowitz'; terms merged by "
    "monomial u'^e_u v'^e_v r'^e_r delta^e_d: n_monomials rows of (e_u, e_v, e_r, e_d, c_X, c_Y, c_N), so that a "
    "monomial shared by X, Y and N (e.g. Y_vvr, N_vvr) is evaluated once; a coefficient is 0 where the equation "
    "has no such term",
    F("force_norm", "kg/m^3", "1/2 (SNAME prime) or 1 (seed eq. 5-6), times rho"),
    F("R_res", "N s^2/m^2", "added resistance coefficient R/(u|u|)"),
    F("n_monomials", "-", "number of distinct monomials"),
    F("monomials", "-", "monomial rows, layout.ABK_STRIDE values each", lo.ABK_STRIDE * lo.MAX_MONOMIALS),
    section=sc.AbkowitzHull,
)

MMG = record(
    "mmg_hull",
    "MMG hull (Yasukawa & Yoshimura 2015, eq. 8-10), [hull] model = 'mmg', nondimensional on 1/2 rho L d U^2 "
    "(1/2 rho L^2 d U^2 for N)",
    section=sc.MMGHull,
)

LARGE_DRIFT = record(
    "large_drift",
    "hull at any drift angle (crossflow.py, ship-file table [large_drift]): Yoshimura, Nakao & Ishibashi "
    "(2009) cross-flow model, blended with the polynomial hull outside its fitted range",
    F("on", "-", "1 with a [large_drift] table, 0 off"),
    F("mmg_drift_max", "rad", "flow angle up to which the polynomial is used alone"),
    F("cross_flow_drift_min", "rad", "flow angle from which the cross-flow model is used alone"),
    # the model's linear terms on 1/2 rho L d U^2 (L for N): the MMG set's, or converted from an Abkowitz set
    F("R_0", "-", "straight-ahead resistance coefficient"),
    F("X_vr", "-", "linear term"),
    F("Y_v", "-", "linear term"),
    F("Y_r", "-", "linear term"),
    F("N_v", "-", "linear term"),
    F("N_r", "-", "linear term"),
    F("C_X_rr", "kg m", "x_G m r^2 surge term an Abkowitz hull's equations of motion leave out"),
    F("C_N_ur", "kg m", "-x_G m u r yaw term an Abkowitz hull's equations of motion leave out"),
    # bounds of the polynomial's range for the test without square root, atan2 or division
    # (crossflow.inside_polynomial_range), each shortened by the factor 1 - 1e-9
    F("tan_mmg_drift_max", "-", "tan(mmg_drift_max)"),
    F("mmg_r_prime_max_squared", "-", "mmg_r_prime_max^2"),
    F("polynomial_u_prime_max_squared", "-", "polynomial_u_prime_max^2"),
    section=sc.LargeDrift,
)

PROPELLER = record(
    "propeller",
    "open-water propeller (K_T, K_Q quadratics in J), its wake and thrust deduction, the MMG wake change in "
    "manoeuvres, astern and four-quadrant behaviour (propulsion.py), the Son & Nomoto (1982) inflow "
    "1 - w = 1 - w_P0 + tau_P ((v' + x'_P r')^2 + c_pv v' + c_pr r') (sonnomoto.py)",
    F("on", "-", "1 on a ship with a propeller"),
    F("four_quadrant", "-", "four-quadrant table code, propeller4q.TABLE_NAMES index + 1 (0: none)"),
    F("wake_kind", "-", "layout.WAKE_MMG or WAKE_SON_NOMOTO"),
    section=sc.Propeller,
)

TRANSMISSION = record(
    "transmission",
    "transmission and shaft (propulsion.py)",
    F("I_shaft", "kg m^2", "propeller + entrained water + shafting + i^2 engine inertia"),
    F("Q_friction", "N m", "shaft friction torque at rated speed (scaled linearly with speed)"),
    F("clutch_min_rev", "rev/s", "|order| (propeller) below which the clutch is out"),
    section=sc.Transmission,
)

ENGINE = record(
    "engine",
    "engine torque map, PI speed governor and reversing (propulsion.py): a clutch/gearbox (or ideal) drive, or a "
    "direct-reversing two-stroke diesel started and braked on starting air",
    F("n_e_rated", "rev/s", "rated speed"),
    F("Q_e_rated", "N m", "rated (MCR) torque"),
    F("map_speed", "-", "torque map speed breakpoints, engine speed / rated", lo.MAP_NS),
    F("map_fuel", "-", "torque map fuel-index breakpoints", lo.MAP_NF),
    F("map_torque", "-", "torque / rated torque, row-major [speed, fuel]", lo.MAP_NS * lo.MAP_NF),
    F("reversing", "-", "layout.REVERSING_CLUTCH or REVERSING_DIRECT_AIR"),
    F("air_brake_rev", "rev/s", "engine speed below which starting air may be applied"),
    F("firing_rev", "rev/s", "engine speed in the ordered direction at which fuel is admitted"),
    F("Q_air", "N m", "engine torque of the starting air"),
    # the slot taken over by a user's component written in Python (components.compose): the built-in's
    # equations stay in the kernel and read this flag
    F("by_component", "-", "1: a user's engine gives the shaft's drive torque (F_ext[3]); governor held"),
    section=sc.Engine,
)

RUDDER = record(
    "rudder",
    "rudder: MMG (Yasukawa & Yoshimura 2015, steering.py), Son & Nomoto (1982, sonnomoto.py: the flow angle "
    "at the rudder from a polynomial in v', r', the propeller race from momentum theory; A_R, a_H, x'_H, "
    "x'_R, epsilon, kappa and f_alpha shared with the MMG rudder) or in the hull's delta terms",
    F("kind", "-", "layout.RUDDER_DERIVATIVES, RUDDER_MMG or RUDDER_SON_NOMOTO"),
    F("eta", "-", "D_P / H_R (at most 1)"),
    section=sc.Rudder,
)

STEERING_GEAR = record(
    "steering_gear",
    "rate-limited first-order steering gear (steering.py)",
    F("delta_max", "rad", "rudder angle limit"),
    F("delta_rate_max", "rad/s", "rudder rate limit"),
    F("by_component", "-", "1: a user's steering gear gives the rudder rate"),
    section=sc.SteeringGear,
)

WINDAGE = record(
    "windage",
    "wind loads of Blendermann (1994) (atmosphere.py)",
    F("on", "-", "1 with a [windage] table"),
    section=sc.Windage,
)

WAVE_DRIFT = record(
    "wave_drift",
    "mean wave drift: nondimensional X, Y, N coefficients tabulated over the encounter angle, 0..360 deg in "
    "5 deg steps (seastate.py)",
    F("on", "-", "1 with a [wave_drift] table"),
    F("table", "-", "zero-speed coefficients, 3 x layout.WAVE_NA", 3 * lo.WAVE_NA),
    F("speed_table", "-", "forward-speed term per unit 2 omega_0 U / g, 3 x layout.WAVE_NA", 3 * lo.WAVE_NA),
    section=sc.WaveDrift,
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
    F("torque_sign", "-", "shaft torque reaction K = sign Q_P: -1 right-handed, +1 left-handed, 0 off"),
    F("n_monomials", "-", "number of distinct monomials"),
    F("monomials", "-", "monomial rows, layout.ROLL_STRIDE values each", lo.ROLL_STRIDE * lo.MAX_ROLL_MONOMIALS),
    section=sc.Roll,
)

NP = len(_row)  # floats in a parameter row
PARAM_NAMES = tuple(_row)  # "kind.field" of every float of the row
