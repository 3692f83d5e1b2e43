"""``vessel-gym fmu SHIP --out ship.fmu``: the whole ship as an FMI 2.0 co-simulation FMU (pythonfmu).

The FMU carries the ship file and the slave script (:mod:`vessel_gym.fmi.ship_slave`) and runs the native
simulation in the host's Python: its trajectory at a communication step equal to the internal step is the
native simulation's (tests/fmi/test_export.py). Units are declared on every variable (pythonfmu writes none;
they are added to the model description here).
"""

from __future__ import annotations

import io
import json
import shutil
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

from vessel_gym.fmi import require
from vessel_gym.outputs import check_free, output_target, safe_name, write_new

#: the internal step of an exported ship, s: the IMO trials' step (manoeuvres.trials)
DEFAULT_DT_S = 0.1
#: FMI 2.0 unit definitions (base units, exponents of SI) of the units the ship's variables use
_BASE_UNITS = {
    "m": {"m": "1"},
    "s": {"s": "1"},
    "rad": {"rad": "1"},
    "m/s": {"m": "1", "s": "-1"},
    "rad/s": {"rad": "1", "s": "-1"},
    "N.m": {"kg": "1", "m": "2", "s": "-2"},
    "1/s": {"s": "-1"},
}


def ship_fmu_path(ship_name: str, out: str | Path) -> Path:
    """The FMU file ``out`` names: a ``.fmu`` file, or ``<ship>.fmu`` in a directory (vessel_gym.outputs)."""
    path, is_dir = output_target(out, (".fmu",), "--out")
    return path / f"{safe_name(ship_name)}.fmu" if is_dir else path


def build_ship_fmu(
    ship: str | Path, out: str | Path, force: bool = False, dt: float = DEFAULT_DT_S, allow_code: bool = False
) -> Path:
    """Write the FMU of ``ship`` (built-in name or ship file) to ``out`` and return its path.

    The ship is loaded and its steady approach solved first (a bad ship file is one ValueError naming it);
    an existing file is never replaced without ``force``. ``allow_code`` carries the consent to run code a
    ship file names (docs/components.md) into the FMU.
    """
    require("pythonfmu")
    from vessel_gym.fmi.ship_slave import INPUTS, OUTPUTS, PARAMETERS
    from vessel_gym.physics.shipfile import load_ship, resolve_ship_path
    from vessel_gym.physics.simulation import Simulation

    if not (dt > 0.0 and dt < 10.0):
        raise ValueError(f"--dt: expected an internal step in (0, 10) s, got {dt!r}")
    loaded = load_ship(ship)
    path = ship_fmu_path(loaded.name, out)
    check_free([path], force, "--out")
    source = resolve_ship_path(ship)
    sim = Simulation(loaded, dt=dt)
    sim.reset()
    settings = {"dt": dt, "rev_order": float(sim.rev_order[0]), "allow_code": allow_code, "ship": loaded.name}
    units = {name: unit for name, unit, _ in (*INPUTS, *OUTPUTS, *PARAMETERS)}
    description = f"vessel-gym ship {loaded.name!r}, 3-DOF manoeuvring model (resources/ship.toml)"
    data = _build("ship_slave.py", "vessel_gym_ship.py", source, settings, units, description)
    return write_new(path, data, force)


def build_engine_fmu(ship: str | Path, out: str | Path, force: bool = False) -> Path:
    """Write an FMU of ``ship``'s own engine and governor (:mod:`vessel_gym.fmi.engine_slave`) to the file
    ``out``: the built-in plant as another simulator sees it, e.g. to put it back in the ship as an ``fmu``
    engine (docs/fmi.md, tests/fmi/test_import.py)."""
    require("pythonfmu")
    from vessel_gym.fmi.engine_slave import VARIABLES
    from vessel_gym.physics.shipfile import load_ship, resolve_ship_path

    loaded = load_ship(ship)
    if loaded.engine is None:
        raise ValueError(f"{loaded.path or loaded.name}: the ship has no [engine] to export")
    path = Path(out)
    check_free([path], force, "engine FMU")
    units = {name: unit for name, _, unit, _ in VARIABLES if unit != "1"}
    description = f"vessel-gym engine and governor of {loaded.name!r} (resources/ship.toml)"
    data = _build("engine_slave.py", "vessel_gym_engine.py", resolve_ship_path(ship), {}, units, description)
    return write_new(path, data, force)


def build_gearbox_fmu(ship: str | Path, out: str | Path, force: bool = False) -> Path:
    """Write an FMU of ``ship``'s geared plant with friction clutches (:mod:`vessel_gym.fmi.gearbox_slave`,
    the ``ReversingGearbox`` component's equations) to the file ``out``; it needs the ``load_torque`` input
    (docs/fmi.md, "The governor and the gearbox")."""
    require("pythonfmu")
    from vessel_gym.fmi.gearbox_slave import VARIABLES
    from vessel_gym.physics.components.gearbox import ReversingGearbox
    from vessel_gym.physics.shipfile import load_ship, resolve_ship_path

    loaded = load_ship(ship)
    if loaded.engine is None or not any(e.cls is ReversingGearbox for e in loaded.components):
        raise ValueError(f"{loaded.path or loaded.name}: the ship has no ReversingGearbox engine to export")
    path = Path(out)
    check_free([path], force, "gearbox FMU")
    units = {name: unit for name, _, unit, _ in VARIABLES if unit != "1"}
    description = f"vessel-gym geared plant with friction clutches of {loaded.name!r} (resources/ship.toml)"
    data = _build("gearbox_slave.py", "vessel_gym_gearbox.py", resolve_ship_path(ship), {}, units, description)
    return write_new(path, data, force)


def build_steering_gear_fmu(ship: str | Path, out: str | Path, force: bool = False) -> Path:
    """Write an FMU of ``ship``'s own steering gear (:mod:`vessel_gym.fmi.gear_slave`) to the file ``out``."""
    require("pythonfmu")
    from vessel_gym.fmi.gear_slave import VARIABLES
    from vessel_gym.physics.shipfile import load_ship, resolve_ship_path

    loaded = load_ship(ship)
    path = Path(out)
    check_free([path], force, "steering-gear FMU")
    units = {name: unit for name, _, unit, _ in VARIABLES}
    description = f"vessel-gym steering gear of {loaded.name!r} (resources/ship.toml)"
    data = _build("gear_slave.py", "vessel_gym_gear.py", resolve_ship_path(ship), {}, units, description)
    return write_new(path, data, force)


def _build(slave: str, module: str, ship_file: Path, settings: dict, units: dict, description: str) -> bytes:
    """The FMU of the slave script ``slave`` (this package's, copied as ``module``) with the ship file and the
    settings in its resources, units on its variables and ``description``."""
    from pythonfmu.builder import FmuBuilder

    with tempfile.TemporaryDirectory(prefix="vessel-gym-fmu-") as tmp:
        t = Path(tmp)
        script = t / "script" / module
        script.parent.mkdir()
        shutil.copyfile(Path(__file__).with_name(slave), script)
        shutil.copyfile(ship_file, t / "ship.toml")
        (t / "settings.json").write_text(json.dumps(settings), encoding="utf-8")
        built = FmuBuilder.build_FMU(
            script,
            dest=t / "out.fmu",
            project_files=[t / "ship.toml", t / "settings.json"],
            canGetAndSetFMUstate=False,
            canSerializeFMUstate=False,
        )
        return _with_units(Path(built).read_bytes(), units, description)


def _with_units(fmu: bytes, units: dict[str, str], description: str) -> bytes:
    """The FMU ``fmu`` with the ``units`` (variable name -> unit) and ``description``."""
    src = zipfile.ZipFile(io.BytesIO(fmu))
    root = ET.fromstring(src.read("modelDescription.xml"))
    root.set("description", description)
    defs = ET.Element("UnitDefinitions")
    for unit in sorted(set(units.values())):
        ET.SubElement(ET.SubElement(defs, "Unit", name=unit), "BaseUnit", _BASE_UNITS[unit])
    # FMI 2.0 order: CoSimulation, UnitDefinitions, TypeDefinitions, LogCategories, ...
    children = list(root)
    at = next(i for i, c in enumerate(children) if c.tag == "CoSimulation") + 1
    root.insert(at, defs)
    outputs = []
    for i, var in enumerate(root.iter("ScalarVariable"), start=1):
        real = var.find("Real")
        if real is not None and var.get("name") in units:
            real.set("unit", units[var.get("name")])
        if var.get("causality") == "output":
            outputs.append(i)
    # FMI 2.0 section 2.2.8: outputs computed at initialisation are initial unknowns (pythonfmu lists none)
    structure = root.find("ModelStructure")
    initial = ET.Element("InitialUnknowns")
    for i in outputs:
        ET.SubElement(initial, "Unknown", index=str(i))
    children = list(structure)
    at = next((k + 1 for k, c in enumerate(children) if c.tag in ("Outputs", "Derivatives")), 0)
    structure.insert(at, initial)
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as dst:
        for item in src.infolist():
            if item.filename == "modelDescription.xml":
                dst.writestr(item.filename, ET.tostring(root, encoding="utf-8", xml_declaration=True))
            else:
                dst.writestr(item, src.read(item.filename))
    return buf.getvalue()
