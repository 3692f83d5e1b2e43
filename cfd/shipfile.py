"""Writing the simulator's ship file (TOML) from CFD results.

The hull table comes from the CFD; ``[particulars]`` from the CFD hull (scaled to the template's
length when ``scale_to = "template"``); every other table (propeller, rudder, steering gear,
engine, windage, ...) is copied unchanged from a template ship file. See docs/cfd.md.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")
PARTICULAR_KEYS = (
    "L_m",
    "B_m",
    "T_m",
    "displacement_m3",
    "x_G_m",
    "k_zz_m",
    "rho_kg_m3",
    "C_b",
    "test_speed_kn",
)
# keys that would contradict the CFD values (the loader takes exactly one of each pair)
_REPLACED = {"displacement_m3": "mass_kg", "k_zz_m": "I_zG_kgm2"}


# ---------------------------------------------------------------------------------- TOML writer
def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k, ensure_ascii=False)


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if hasattr(v, "tolist"):  # numpy scalars and arrays
        return _value(v.tolist())
    if hasattr(v, "isoformat"):
        return v.isoformat()
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _is_table_array(v: Any) -> bool:
    return isinstance(v, (list, tuple)) and len(v) > 0 and all(isinstance(x, Mapping) for x in v)


def _emit(table: Mapping[str, Any], path: list[str], out: list[str]) -> None:
    simple = [(k, v) for k, v in table.items() if not isinstance(v, Mapping) and not _is_table_array(v)]
    for k, v in simple:
        out.append(f"{_key(k)} = {_value(v)}")
    for k, v in table.items():
        if isinstance(v, Mapping):
            sub = [*path, _key(k)]
            out.append("")
            out.append(f"[{'.'.join(sub)}]")
            _emit(v, sub, out)
        elif _is_table_array(v):
            sub = [*path, _key(k)]
            for item in v:
                out.append("")
                out.append(f"[[{'.'.join(sub)}]]")
                _emit(item, sub, out)


def dumps_toml(data: Mapping[str, Any], header: str = "") -> str:
    """TOML text of nested dicts (tables), lists, strings, numbers and booleans."""
    out: list[str] = [f"# {line}" if line else "#" for line in header.splitlines()]
    _emit(data, [], out)
    text = "\n".join(out).strip("\n") + "\n"
    tomllib.loads(text)  # never write a file the loader cannot read
    return text


# ---------------------------------------------------------------------------------- ship file
def default_template() -> Path | None:
    """The project's built-in DTC ship file, if this installation has it."""
    try:
        from vessel_gym.physics.shipfile import SHIP_DIR  # noqa: PLC0415 - optional, only to locate package data
    except ImportError:
        return None
    path = SHIP_DIR / "dtc.toml"
    return path if path.is_file() else None


def load_template(path: Path | None) -> dict[str, Any]:
    """Parsed template ship file, or an empty dict."""
    if path is None:
        return {}
    return tomllib.loads(Path(path).read_text())


def scale_factor_to(template: Mapping[str, Any], L_cfd: float, scale_to: str) -> float:
    """λ = L_template / L_cfd when scaling to the template, else 1."""
    if scale_to != "template":
        return 1.0
    L_t = template.get("particulars", {}).get("L_m")
    if isinstance(L_t, (int, float)) and L_t > 0:
        return float(L_t) / L_cfd
    return 1.0


def build_ship(
    template: Mapping[str, Any],
    *,
    name: str,
    source: Mapping[str, Any],
    particulars: Mapping[str, float],
    hull: Mapping[str, Any],
) -> dict[str, Any]:
    """Ship-file dict: name, source, particulars, hull, then the template's other tables unchanged.

    Template particulars keys other than :data:`PARTICULAR_KEYS` are kept as they are.
    """
    ship: dict[str, Any] = {"name": name, "source": dict(source)}
    parts = dict(template.get("particulars", {}))
    for k, other in _REPLACED.items():
        if k in particulars:
            parts.pop(other, None)
    parts.update({k: particulars[k] for k in PARTICULAR_KEYS if k in particulars})
    ship["particulars"] = parts
    ship["hull"] = dict(hull)
    for k, v in template.items():
        if k not in ("name", "source", "particulars", "hull"):
            ship[k] = v
    return ship


def write_ship(path: Path, ship: Mapping[str, Any], header: str = "") -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(dumps_toml(ship, header))
    return path


def validate_ship(path: Path) -> str | None:
    """Load ``path`` with vessel-gym's ship-file loader; the error message, or None if it loads
    (or if vessel-gym's physics package is not importable here)."""
    try:
        from vessel_gym.physics.shipfile import load_ship  # noqa: PLC0415 - optional
    except ImportError:
        return None
    try:
        load_ship(Path(path))
    except ValueError as exc:
        return str(exc)
    return None


def borrowed_note(
    template: Mapping[str, Any], path: Path | None, L_cfd: float, lam: float
) -> tuple[str, dict[str, Any]]:
    """What a ship file for a bare CFD hull borrows from its template, and how it was scaled: one sentence
    for ``[source] notes`` and the command line, and the same as a provenance table."""
    tables = [k for k in template if k not in ("name", "source", "particulars", "hull")]
    if not tables:
        return "No tables borrowed: the ship file holds the CFD hull only.", {"tables": []}
    name = str(template.get("name", Path(path).stem if path else "the template"))
    L_t = template.get("particulars", {}).get("L_m")
    L_t = float(L_t) if isinstance(L_t, (int, float)) and L_t > 0 else None
    text = f"The CFD hull is bare; [{'], ['.join(tables)}] are borrowed unchanged from {name} ({path})" + (
        f", a ship of L = {L_t:g} m" if L_t else ""
    )
    if lam != 1.0:
        text += (
            f"; the hull (CFD model L = {L_cfd:g} m) is scaled by {lam:.6g} to that length (lengths x lambda, "
            "displacement x lambda^3, speeds x sqrt(lambda), resistance by the ITTC-1978 form factor method) "
            "so that they fit it."
        )
    elif L_t and abs(L_t / L_cfd - 1.0) > 0.01:
        text += (
            f"; NOT scaled (scale_to = cfd): the hull keeps L = {L_cfd:g} m, so these tables were sized for a "
            f"ship {L_t / L_cfd:.3g} times as long."
        )
    else:
        text += "; same length, nothing scaled."
    info = {"from": name, "file": str(path), "tables": tables, "template_L_m": L_t, "scale_factor": lam}
    return text, info
