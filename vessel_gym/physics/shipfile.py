"""Ship files: one TOML file per ship, loaded strictly into frozen parameter dataclasses.

Format reference: docs/ship-file.md. A ship is named either by a built-in name (``mariner``, ``kvlcc2``,
``kvlcc2_l7``, ``dtc``, ``coaster``; see :func:`builtin_ships`) or by a path to a ``.toml`` file.

The tables of the built-in components are the dataclasses of :mod:`vessel_gym.physics.sections` (the compiled
model's parameter records are derived from them); this module holds the ship as a whole and its loading.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

from vessel_gym.physics.crossflow import check as check_large_drift
from vessel_gym.physics.roll import check_roll
from vessel_gym.physics.schema import (
    SpecError,
    build,
    builtin_names,
    param,
    read_toml,
    resolve_data_path,
)
from vessel_gym.physics.sections import (
    AbkowitzHull,
    Engine,
    LargeDrift,
    MMGHull,
    Particulars,
    Propeller,
    Roll,
    Rudder,
    SteeringGear,
    Transmission,
    WaveDrift,
    Windage,
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
