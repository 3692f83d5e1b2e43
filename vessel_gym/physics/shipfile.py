"""Ship files: one TOML file per ship, loaded strictly into frozen parameter dataclasses.

Format reference: docs/ship-file.md. A ship is named either by a built-in name (``mariner``, ``kvlcc2``,
``kvlcc2_l7``, ``dtc``, ``coaster``; see :func:`builtin_ships`) or by a path to a ``.toml`` file.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

from vessel_gym.physics.crossflow import LargeDrift
from vessel_gym.physics.crossflow import check as check_large_drift
from vessel_gym.physics.propeller4q import TABLE_NAMES
from vessel_gym.physics.roll import Roll, check_roll
from vessel_gym.physics.schema import (
    SpecError,
    build,
    builtin_names,
    param,
    read_toml,
    resolve_data_path,
)
from vessel_gym.physics.shipchecks import ShipFileError, check_abkowitz, check_engine, check_plausible

SHIP_DIR = Path(__file__).parent / "data" / "ships"

#: size bound of a ship file, bytes (the built-in files are under 10 kB)
MAX_SHIP_FILE_BYTES = 1 << 20

@dataclass(frozen=True, kw_only=True)
class Source:
    citation: str = param(doc="published source of the parameter set")
    notes: str = param("", doc="what was converted, estimated or added, and why")
    sign_convention: str = param("", doc="how the published signs were mapped to vessel-gym's axes")
    provenance: dict = param(
        {}, doc="machine-written provenance (cfd/ writes hull, mesh, solver, fit residuals)"
    )


@dataclass(frozen=True, kw_only=True)
class Particulars:
    L_m: float = param(unit="m", lo=1.0, hi=500.0, doc="length between perpendiculars")
    B_m: float = param(unit="m", lo=0.1, hi=100.0, doc="moulded beam")
    T_m: float = param(unit="m", lo=0.02, hi=40.0, doc="mean draught")
    test_speed_kn: float = param(
        unit="kn", lo=0.5, hi=50.0, doc="IMO MSC.137(76) test speed (approach speed)"
    )
    mass_kg: float | None = param(None, unit="kg", lo=1.0, hi=1e9, doc="mass (or give displacement_m3)")
    displacement_m3: float | None = param(
        None, unit="m^3", lo=1e-3, hi=1e6, doc="displaced volume (mass = rho * volume)"
    )
    x_G_m: float = param(0.0, unit="m", lo=-100.0, hi=100.0, doc="centre of gravity forward of midship")
    k_zz_m: float | None = param(None, unit="m", lo=0.01, hi=200.0, doc="yaw radius of gyration about G")
    I_zG_kgm2: float | None = param(
        None, unit="kg m^2", lo=1e-6, hi=1e14, doc="yaw moment of inertia about G (or k_zz_m)"
    )
    rho_kg_m3: float = param(1025.0, unit="kg/m^3", lo=990.0, hi=1035.0, doc="water density")
    C_b: float | None = param(None, unit="-", lo=0.3, hi=0.95, doc="block coefficient (informative)")
    origin: str = param("midship", choices=("midship",), doc="body-axes origin")


@dataclass(frozen=True, kw_only=True)
class AbkowitzHull:
    model: str = param(choices=("abkowitz",))
    normalisation: str = param(
        "half_rho_L2_U2",
        choices=("half_rho_L2_U2", "rho_L2_U2"),
        doc="prime system: forces / (1/2 rho L^2 U^2) (SNAME) or / (rho L^2 U^2) (seed eq. 5-6)",
    )
    U_ref_m_s: float = param(
        0.0,
        unit="m/s",
        lo=0.0,
        hi=30.0,
        doc="reference speed; > 0: u-terms use the perturbation (u - U_ref)/U",
    )
    coriolis: str = param(
        "separate",
        choices=("separate", "in_derivatives"),
        doc="'in_derivatives' when Y_r, N_r, X_vr already contain the rigid-body m u r terms",
    )
    resistance_N: float = param(
        0.0, unit="N", lo=0.0, hi=1e8, doc="resistance at resistance_speed_m_s, R = c u|u|"
    )
    resistance_speed_m_s: float = param(1.0, unit="m/s", lo=0.01, hi=30.0)
    cross_flow_Cd: float = param(
        0.0,
        unit="-",
        lo=0.0,
        hi=2.0,
        doc="2-D cross-flow drag coefficient (0: none); nonlinear sway-yaw damping",
    )
    r_prime_max: float = param(2.0, unit="-", lo=0.1, hi=10.0, doc="clip of r' in the polynomial (low speed)")
    U_min_m_s: float = param(0.05, unit="m/s", lo=1e-4, hi=2.0, doc="nondimensionalising speed floor")
    derivatives: dict = param(doc="named derivatives, e.g. Y_vvr = -0.379 (see docs/ship-file.md)")


@dataclass(frozen=True, kw_only=True)
class MMGHull:
    model: str = param(choices=("mmg",))
    m_x: float = param(unit="-", lo=0.0, hi=1.0, doc="surge added mass / (1/2 rho L^2 d)")
    m_y: float = param(unit="-", lo=0.0, hi=2.0, doc="sway added mass / (1/2 rho L^2 d)")
    J_z: float = param(unit="-", lo=0.0, hi=0.2, doc="yaw added inertia / (1/2 rho L^4 d)")
    R_0: float = param(unit="-", lo=0.0, hi=0.2)
    X_vv: float = param(unit="-", lo=-5, hi=5)
    X_vr: float = param(unit="-", lo=-5, hi=5)
    X_rr: float = param(unit="-", lo=-5, hi=5)
    X_vvvv: float = param(unit="-", lo=-10, hi=10)
    Y_v: float = param(unit="-", lo=-5, hi=0)
    Y_r: float = param(unit="-", lo=-5, hi=5)
    Y_vvv: float = param(unit="-", lo=-20, hi=20)
    Y_vvr: float = param(unit="-", lo=-20, hi=20)
    Y_vrr: float = param(unit="-", lo=-20, hi=20)
    Y_rrr: float = param(unit="-", lo=-20, hi=20)
    N_v: float = param(unit="-", lo=-5, hi=5)
    N_r: float = param(unit="-", lo=-5, hi=0)
    N_vvv: float = param(unit="-", lo=-20, hi=20)
    N_vvr: float = param(unit="-", lo=-20, hi=20)
    N_vrr: float = param(unit="-", lo=-20, hi=20)
    N_rrr: float = param(unit="-", lo=-20, hi=20)
    r_prime_max: float = param(2.0, unit="-", lo=0.1, hi=10.0)
    U_min_m_s: float = param(0.05, unit="m/s", lo=1e-4, hi=2.0)


@dataclass(frozen=True)
class ComponentEntry:
    """A user's component named in a ship file: ``[hull] model = "pkg.module:Class"`` or a
    ``[[components]]`` entry. ``model`` is the import path, ``cls`` the class it names, ``params`` its table
    (the class's ``Params`` dataclass when it declares one, else the table as a dict), ``replace`` whether it
    takes the slot of the ship's built-in, ``where`` the file and key for messages."""

    slot: str
    model: str
    cls: type
    params: object
    replace: bool
    where: str

    def build(self, ship: Ship) -> object:
        """An instance for ``ship``: ``cls(ship, params)``; a failure is a one-line ShipFileError."""
        try:
            return self.cls(ship, self.params)
        except Exception as exc:  # noqa: BLE001 - user code: report it on one line naming the file and key
            raise ShipFileError(
                f"{self.where}: {self.model} failed to build ({type(exc).__name__}: {exc})"
            ) from None


@dataclass(frozen=True, kw_only=True)
class UserHull:
    """A hull of the user's own, ``[hull] model = "pkg.module:Class"`` (docs/components.md)."""

    model: str
    r_prime_max: float = 2.0  # unused by the compiled kernel without a built-in hull; kept for pack
    U_min_m_s: float = 0.05


@dataclass(frozen=True, kw_only=True)
class Propeller:
    D_m: float = param(unit="m", lo=0.01, hi=15.0, doc="propeller diameter D_P")
    k_0: float = param(unit="-", lo=0.0, hi=1.0, doc="K_T = k_0 + k_1 J + k_2 J^2")
    k_1: float = param(unit="-", lo=-2.0, hi=0.5)
    k_2: float = param(unit="-", lo=-2.0, hi=0.5)
    q_0: float = param(unit="-", lo=0.0, hi=0.2, doc="K_Q = q_0 + q_1 J + q_2 J^2")
    q_1: float = param(unit="-", lo=-0.5, hi=0.1)
    q_2: float = param(unit="-", lo=-0.5, hi=0.1)
    w_P0: float = param(unit="-", lo=0.0, hi=0.7, doc="wake fraction in straight running")
    t_P: float = param(unit="-", lo=0.0, hi=0.5, doc="thrust deduction factor")
    x_P_prime: float = param(-0.5, unit="-", lo=-0.7, hi=0.0, doc="propeller position / L")
    C_1: float = param(0.0, unit="-", lo=0.0, hi=10.0, doc="MMG wake change in manoeuvres (0: none)")
    C_2_plus: float = param(1.0, unit="-", lo=0.0, hi=5.0)
    C_2_minus: float = param(1.0, unit="-", lo=0.0, hi=5.0)
    astern_kt_ratio: float = param(
        0.7, unit="-", lo=0.1, hi=1.5, doc="astern bollard K_T / ahead bollard K_T"
    )
    astern_kq_ratio: float = param(
        0.8, unit="-", lo=0.1, hi=1.5, doc="astern bollard K_Q / ahead bollard K_Q"
    )
    astern_inflow_slope: float = param(
        0.5, unit="-", lo=0.0, hi=3.0, doc="growth of astern thrust with ahead inflow (quadrant 4)"
    )
    four_quadrant: str = param(
        "",
        choices=("",) + TABLE_NAMES,
        doc="published Wageningen four-quadrant curves outside quadrant 1 ('': the astern_* approximation)",
    )
    wake_model: str = param(
        "mmg",
        choices=("mmg", "son_nomoto"),
        doc="wake in manoeuvres: MMG C_1, C_2 or Son & Nomoto (1982) tau_P, c_pv, c_pr (sonnomoto.py)",
    )
    tau_P: float = param(0.0, unit="-", lo=0.0, hi=5.0, doc="Son & Nomoto wake change with drift and yaw")
    c_pv: float = param(0.0, unit="-", lo=-1.0, hi=1.0, doc="Son & Nomoto wake change per v'")
    c_pr: float = param(0.0, unit="-", lo=-1.0, hi=1.0, doc="Son & Nomoto wake change per r'")


@dataclass(frozen=True, kw_only=True)
class Rudder:
    model: str = param(
        choices=("mmg", "derivatives", "son_nomoto"),
        doc="'derivatives': rudder forces are hull delta-terms; 'son_nomoto': Son & Nomoto (1982)",
    )
    A_R_m2: float = param(1.0, unit="m^2", lo=1e-4, hi=500.0)
    H_R_m: float = param(1.0, unit="m", lo=0.01, hi=30.0, doc="rudder span")
    t_R: float = param(0.3, unit="-", lo=0.0, hi=1.0)
    a_H: float = param(0.3, unit="-", lo=0.0, hi=1.5)
    x_H_prime: float = param(-0.45, unit="-", lo=-1.0, hi=0.0)
    x_R_prime: float = param(-0.5, unit="-", lo=-0.7, hi=-0.3)
    gamma_R_minus: float = param(0.4, unit="-", lo=0.0, hi=2.0)
    gamma_R_plus: float = param(0.6, unit="-", lo=0.0, hi=2.0)
    l_R_prime: float = param(-0.7, unit="-", lo=-2.0, hi=0.0)
    epsilon: float = param(1.0, unit="-", lo=0.3, hi=2.0)
    kappa: float = param(0.5, unit="-", lo=0.0, hi=1.5)
    f_alpha: float = param(2.7, unit="1/rad", lo=0.5, hi=7.0)
    # Son & Nomoto (1982) rudder only (sonnomoto.py): v'_R polynomial and drag factor
    gamma_R: float = param(0.0, unit="-", lo=-2.0, hi=2.0, doc="Son & Nomoto: v'_R per v'")
    c_Rr: float = param(0.0, unit="-", lo=-2.0, hi=2.0, doc="Son & Nomoto: v'_R per r'")
    c_Rrrr: float = param(0.0, unit="-", lo=-5.0, hi=5.0, doc="Son & Nomoto: v'_R per r'^3")
    c_Rrrv: float = param(0.0, unit="-", lo=-10.0, hi=10.0, doc="Son & Nomoto: v'_R per r'^2 v'")
    c_RX: float = param(1.0, unit="-", lo=0.0, hi=2.0, doc="Son & Nomoto: X_R = c_RX F_N sin(delta)")


@dataclass(frozen=True, kw_only=True)
class SteeringGear:
    max_angle_deg: float = param(35.0, unit="deg", lo=1.0, hi=70.0)
    max_rate_deg_s: float = param(2.32, unit="deg/s", lo=0.1, hi=60.0)
    time_constant_s: float = param(1.0, unit="s", lo=0.01, hi=20.0)


@dataclass(frozen=True, kw_only=True)
class Engine:
    rated_power_kW: float = param(unit="kW", lo=0.01, hi=2e5, doc="maximum continuous rating (MCR)")
    rated_rpm: float = param(unit="rpm", lo=10.0, hi=10000.0, doc="engine speed at MCR")
    inertia_kgm2: float = param(unit="kg m^2", lo=1e-4, hi=1e7, doc="engine rotating inertia")
    torque_map_speed: tuple[float, ...] = param(
        unit="-", lo=0.0, hi=2.0, doc="engine speed / rated, 8 values"
    )
    torque_map_fuel: tuple[float, ...] = param(unit="-", lo=0.0, hi=1.0, doc="fuel index, 6 values")
    torque_map: tuple[tuple[float, ...], ...] = param(
        unit="-", lo=-1.0, hi=2.0, doc="torque / rated torque, [speed][fuel]"
    )
    astern_torque_ratio: float = param(
        1.0,
        unit="-",
        lo=0.05,
        hi=1.0,
        doc="astern torque / ahead torque (e.g. a steam plant's astern turbine)",
    )
    governor_Kp: float = param(unit="-", lo=0.0, hi=100.0, doc="fuel index per relative speed error")
    governor_Ki: float = param(unit="1/s", lo=0.0, hi=100.0)
    telegraph_rpm: tuple[float, ...] = param(
        unit="rpm", lo=-10000.0, hi=10000.0, doc="propeller rpm for full astern ... stop ... full ahead (9)"
    )
    reversing: str = param(
        "clutch",
        choices=("clutch", "direct_air_start"),
        doc="clutch: ahead/neutral/astern clutch and gearbox (or an ideal drive), instant; direct_air_start: "
        "direct-reversing diesel, fuel off, reversing gear, starting air, fuel astern",
    )
    reversal_time_s: float = param(
        15.0, unit="s", lo=1.0, hi=120.0, doc="direct_air_start: time to shift the reversing gear"
    )
    air_brake_rpm_fraction: float = param(
        0.35,
        unit="-",
        lo=0.05,
        hi=0.6,
        doc="direct_air_start: engine speed / rated below which starting air may be applied",
    )
    firing_rpm_fraction: float = param(
        0.15, unit="-", lo=0.02, hi=0.5, doc="direct_air_start: engine speed / rated at which fuel is admitted"
    )
    starting_air_torque_fraction: float = param(
        0.5, unit="-", lo=0.05, hi=2.0, doc="direct_air_start: starting-air torque / rated torque"
    )


@dataclass(frozen=True, kw_only=True)
class Transmission:
    gear_ratio: float = param(1.0, unit="-", lo=0.05, hi=50.0, doc="engine rev / propeller rev")
    efficiency: float = param(0.98, unit="-", lo=0.5, hi=1.0)
    shaft_inertia_kgm2: float = param(
        unit="kg m^2", lo=1e-6, hi=1e7, doc="propeller + entrained water + shafting"
    )
    friction_torque_fraction: float = param(
        0.02, unit="-", lo=0.0, hi=0.3, doc="shaft friction at rated speed / rated torque"
    )
    clutch_min_rpm: float = param(1.0, unit="rpm", lo=0.0, hi=1000.0, doc="|order| below: clutch out")


@dataclass(frozen=True, kw_only=True)
class Windage:
    A_F_m2: float = param(unit="m^2", lo=0.01, hi=1e4, doc="frontal projected area above water")
    A_L_m2: float = param(unit="m^2", lo=0.01, hi=5e4, doc="lateral projected area above water")
    s_L_m: float = param(0.0, unit="m", lo=-300.0, hi=300.0, doc="centre of A_L forward of midship")
    CD_t: float = param(unit="-", lo=0.1, hi=2.0, doc="Blendermann (1994) Table: transverse drag coefficient")
    CD_l_AF_0: float = param(unit="-", lo=0.1, hi=2.0, doc="longitudinal coefficient, head wind")
    CD_l_AF_pi: float = param(unit="-", lo=0.1, hi=2.0, doc="longitudinal coefficient, stern wind")
    delta: float = param(unit="-", lo=0.0, hi=1.0, doc="cross-force parameter")
    kappa: float = param(1.0, unit="-", lo=0.0, hi=5.0, doc="rolling-moment factor (unused in 3 DOF)")
    ship_type: str = param("", doc="Blendermann ship type the coefficients were taken for")


@dataclass(frozen=True, kw_only=True)
class WaveDrift:
    C_wp: float = param(0.85, unit="-", lo=0.5, hi=0.98, doc="waterplane coefficient of the drift waterline")
    reflection: float = param(
        1.0, unit="-", lo=0.0, hi=1.0, doc="short-wave reflection factor (1: wall-sided)"
    )


@dataclass(frozen=True, kw_only=True)
class Ship:
    """A ship parameter set: particulars and one parameter object per component."""

    name: str
    source: Source
    particulars: Particulars
    hull: AbkowitzHull | MMGHull | UserHull
    rudder: Rudder
    steering_gear: SteeringGear
    propeller: Propeller | None = None
    engine: Engine | None = None
    transmission: Transmission | None = None
    windage: Windage | None = None
    wave_drift: WaveDrift | None = None
    large_drift: LargeDrift | None = None
    roll: Roll | None = None  # the fourth degree of freedom (roll.py); None: a 3-DOF ship
    components: tuple[ComponentEntry, ...] = ()
    path: str = ""

    @property
    def mass_kg(self) -> float:
        p = self.particulars
        return p.mass_kg if p.mass_kg is not None else p.rho_kg_m3 * p.displacement_m3

    @property
    def I_zG_kgm2(self) -> float:
        p = self.particulars
        return p.I_zG_kgm2 if p.I_zG_kgm2 is not None else self.mass_kg * p.k_zz_m**2

    @property
    def test_speed_m_s(self) -> float:
        return self.particulars.test_speed_kn * 1852.0 / 3600.0

    def with_hull(self, hull: AbkowitzHull | MMGHull | UserHull) -> Ship:
        """This ship with another hull (a user's hull component named by the file leaves with the old one)."""
        kept = tuple(e for e in self.components if e.slot != "hull")
        return dataclasses.replace(self, hull=hull, components=kept)


_SECTIONS = {
    "source": Source,
    "particulars": Particulars,
    "rudder": Rudder,
    "steering_gear": SteeringGear,
    "propeller": Propeller,
    "engine": Engine,
    "transmission": Transmission,
    "windage": Windage,
    "wave_drift": WaveDrift,
    "large_drift": LargeDrift,
    "roll": Roll,
}
_REQUIRED = ("source", "particulars", "hull", "rudder", "steering_gear")


def parse_ship(data: dict, where: str, name: str = "") -> Ship:
    """Build a :class:`Ship` from a parsed TOML document; ``where`` names the file in messages."""
    allowed = set(_SECTIONS) | {"hull", "name", "components"}
    for key in data:
        if key not in allowed:
            raise ShipFileError(f"{where}: unknown key {key!r} (allowed: {', '.join(sorted(allowed))})")
    for key in _REQUIRED:
        if key not in data:
            raise ShipFileError(f"{where}: missing required table [{key}]")
    try:
        parts = {k: build(cls, data[k], f"{where} [{k}]") for k, cls in _SECTIONS.items() if k in data}
        hull_table = data["hull"]
        if not isinstance(hull_table, dict):
            raise ShipFileError(f"{where} [hull]: expected a table")
        model = hull_table.get("model")
        user: list[ComponentEntry] = []
        if model == "abkowitz":
            hull = build(AbkowitzHull, hull_table, f"{where} [hull]")
            check_abkowitz(hull.derivatives, where)
        elif model == "mmg":
            hull = build(MMGHull, hull_table, f"{where} [hull]")
        elif isinstance(model, str) and ":" in model:
            hull = UserHull(model=model)
            params = {k: v for k, v in hull_table.items() if k != "model"}
            user = [_component_entry("hull", model, params, True, f"{where} [hull]")]
        else:
            raise ShipFileError(
                f"{where} [hull] model: {model!r} is not one of 'abkowitz', 'mmg' or an import path 'pkg.module:Class'"
            )
        if "large_drift" in parts:
            check_large_drift(parts["large_drift"], str(model), where, getattr(hull, "resistance_N", 0.0))
        user += _component_list(data.get("components", []), where)
    except SpecError as exc:
        raise ShipFileError(str(exc)) from None
    p: Particulars = parts["particulars"]
    if (p.mass_kg is None) == (p.displacement_m3 is None):
        raise ShipFileError(f"{where} [particulars]: give exactly one of mass_kg, displacement_m3")
    if (p.k_zz_m is None) == (p.I_zG_kgm2 is None):
        raise ShipFileError(f"{where} [particulars]: give exactly one of k_zz_m, I_zG_kgm2")
    if abs(p.x_G_m) > 0.2 * p.L_m:
        raise ShipFileError(f"{where} [particulars] x_G_m: |{p.x_G_m:g}| m exceeds 0.2 L")
    if p.B_m > p.L_m or p.T_m > p.B_m * 2:
        raise ShipFileError(f"{where} [particulars]: implausible proportions (B > L or T > 2 B)")
    rudder: Rudder = parts["rudder"]
    prop = parts.get("propeller")
    if rudder.model in ("mmg", "son_nomoto") and prop is None:
        raise ShipFileError(f"{where} [rudder] model: {rudder.model!r} needs a [propeller] table")
    if "roll" in parts:
        try:
            check_roll(parts["roll"], where)
        except SpecError as exc:
            raise ShipFileError(str(exc)) from None
    if prop is not None:
        for k in ("engine", "transmission"):
            if k not in parts:
                raise ShipFileError(f"{where}: a ship with a [propeller] needs an [{k}] table")
        check_engine(parts["engine"], where)
    check_plausible(parts, where)
    if "name" in data and not isinstance(data["name"], str):
        raise ShipFileError(f"{where} name: expected a string")
    return Ship(
        name=data.get("name", name),
        hull=hull,
        components=tuple(user),
        path=where,
        **parts,
    )


def _component_entry(slot: str, model: object, table: object, replace: bool, where: str) -> ComponentEntry:
    """Resolve a user's component: import ``model``, check ``table`` against the class's ``Params``."""
    from vessel_gym.physics.components import import_model

    try:
        cls = import_model(model, f"{where} model")
    except ValueError as exc:
        raise ShipFileError(str(exc)) from None
    if not isinstance(table, dict):
        raise ShipFileError(f"{where} params: expected a table")
    declared = getattr(cls, "Params", None)
    params = build(declared, table, f"{where} params") if declared is not None else dict(table)
    return ComponentEntry(slot, str(model), cls, params, replace, where)


def _component_list(entries: object, where: str) -> list[ComponentEntry]:
    """The ``[[components]]`` array: each entry has ``slot``, ``model`` and optional ``params``, ``replace``."""
    from vessel_gym.physics.components import SLOTS

    if not isinstance(entries, list):
        raise ShipFileError(f"{where} components: expected an array of tables [[components]]")
    out = []
    for i, entry in enumerate(entries):
        w = f"{where} [[components]][{i}]"
        if not isinstance(entry, dict):
            raise ShipFileError(f"{w}: expected a table")
        unknown = set(entry) - {"slot", "model", "params", "replace"}
        if unknown:
            raise ShipFileError(
                f"{w}: unknown key {sorted(unknown)[0]!r} (allowed: model, params, replace, slot)"
            )
        if "model" not in entry:
            raise ShipFileError(f"{w}: missing key 'model' (an import path 'pkg.module:Class')")
        slot = entry.get("slot", "extra")
        if slot not in SLOTS:
            raise ShipFileError(f"{w} slot: {slot!r} is not one of {', '.join(SLOTS)}")
        replace = entry.get("replace", False)
        if not isinstance(replace, bool):
            raise ShipFileError(f"{w} replace: expected true or false")
        out.append(_component_entry(slot, entry["model"], entry.get("params", {}), replace, w))
    return out


def builtin_ships() -> list[str]:
    """Names of the ship files shipped with vessel-gym."""
    return builtin_names(SHIP_DIR)


def resolve_ship_path(ship: str | Path) -> Path:
    """A built-in name or a path to a TOML file -> path. Raises ShipFileError naming the choices."""
    return resolve_data_path(ship, SHIP_DIR, "ship", ShipFileError)


def load_ship(ship: str | Path | Ship) -> Ship:
    """Load a ship by built-in name or file path (a :class:`Ship` passes through)."""
    if isinstance(ship, Ship):
        return ship
    path = resolve_ship_path(ship)
    try:
        return parse_ship(read_toml(path, MAX_SHIP_FILE_BYTES), str(path), name=path.stem)
    except SpecError as exc:
        raise ShipFileError(str(exc)) from None
