"""``vessel-gym ships``: the built-in ships with their particulars and sources, ``ships check SHIP`` (the hull
model's plausibility) and ``ships --example FILE``, a ship file to start one's own from.

The example is the built-in 7 m KVLCC2 model (``kvlcc2_l7``: MMG hull, propeller, rudder, engine), renamed, with
every key annotated from the loader's own schema (unit, allowed range, meaning), so that the comments cannot
drift from what the loader accepts. ``docs/ship-file.md`` explains the format.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections.abc import Callable
from pathlib import Path

from vessel_gym.cli_args import UsageError

#: prints a command's result: ``emit(data, as_json, text)``
Emit = Callable[[dict, bool, str], None]

#: the built-in ship the example copies
TEMPLATE = "kvlcc2_l7"

HEADER = """\
# A vessel-gym ship file to start from: a copy of the built-in '{template}' (the KVLCC2 tanker's 7 m model of
# Yasukawa & Yoshimura 2015, MMG standard method), with each key's unit, allowed range and meaning added
# as a comment. Change the name, the [source] and the values; the format, every table and the optional ones
# ([windage], [roll], [large_drift], [wave_drift], [components]) are in docs/ship-file.md.
#
#   vessel-gym ships check {file}   # are the hull's derivatives and rudder plausible?
#   vessel-gym imo {file}           # all IMO MSC.137(76) criteria
#
# SI units; angles in degrees where the key says _deg; primed (') coefficients are non-dimensional as the hull
# model defines them (MMG: forces by 1/2 rho L d U^2). Unknown keys and values out of range are errors naming
# the file and the key.
"""

_KEY = re.compile(r"^(\w+)\s*=")
_TABLE = re.compile(r"^\[(\w+)\]")


def _annotations() -> dict[str, dict[str, str]]:
    """table -> key -> "unit, range: meaning" from the loader's dataclasses."""
    from vessel_gym.physics import sections, shipfile
    from vessel_gym.physics.schema import describe

    tables = {**shipfile._SECTIONS, "hull": sections.MMGHull}
    out: dict[str, dict[str, str]] = {}
    for table, cls in tables.items():
        rows = {}
        for key, _type, unit, rng, doc in describe(cls):
            parts = [p for p in (unit if unit not in ("", "-") else "", rng) if p]
            head = ", ".join(parts)
            rows[key.removesuffix(" (required)")] = f"{head}: {doc}" if head and doc else head or doc
        out[table] = rows
    return out


def example_text(file_name: str = "my_ship.toml") -> str:
    """The annotated example ship file."""
    from vessel_gym.physics.shipfile import resolve_ship_path

    notes = _annotations()
    lines = resolve_ship_path(TEMPLATE).read_text().splitlines()
    out = [HEADER.format(template=TEMPLATE, file=file_name).rstrip("\n")]
    table = ""
    in_string = False
    for line in lines:
        if line.count('"""') % 2:
            in_string = not in_string
        m_table, m_key = _TABLE.match(line), _KEY.match(line)
        if m_table and not in_string:
            table = m_table.group(1)
        elif m_key and not in_string and "#" not in line and not line.rstrip().endswith(("[", '"""')):
            key = m_key.group(1)
            if key == "name" and not table:
                line = f'name = "{Path(file_name).stem}"'
            note = notes.get(table, {}).get(key)
            if note:
                line = f"{line:<29} # {note}"
        out.append(line)
    return "\n".join(out) + "\n"


def write_example(path: Path, force: bool = False) -> Path:
    """Write the example to ``path`` (an existing file is replaced only with ``force``)."""
    from vessel_gym.outputs import check_free

    check_free([path], force, "--example")
    path.write_text(example_text(path.name))
    return path


def _ships_check(args, emit: Emit) -> int:
    """The hull model's checks (physics.plausibility): exit 1 if one finds the ship impossible."""
    from vessel_gym.physics.plausibility import check_ship, impossible
    from vessel_gym.physics.shipfile import load_ship

    ship = load_ship(args.ship)
    findings = check_ship(ship)
    bad = impossible(findings)
    text = [
        f"hull model checks - {ship.name}",
        "",
        f"{'check':<34}{'value':>10}  {'expected':<9}{'result':>10}",
    ]
    text.append("-" * 65)
    for f in findings:
        text.append(f"{f.quantity:<34}{f.value:>10.4g}  {f.expected:<9}{f.status.upper():>10}")
        text.append(f"    {f.note}; source: {f.source}" if f.note else f"    source: {f.source}")
    verdict = "IMPOSSIBLE" if bad else "possible"
    text += ["", f"overall: {verdict}" + (" (see 'impossible' above)" if bad else "")]
    data = {"ship": ship.name, "findings": [f.to_dict() for f in findings], "possible": not bad}
    emit(data, args.json, "\n".join(text))
    return 1 if bad else 0


def cmd_ships(args: argparse.Namespace, emit: Emit) -> int:
    """``vessel-gym ships [check SHIP | --example FILE]``; ``emit(data, as_json, text)`` prints the result."""
    from vessel_gym.physics.shipfile import builtin_ships, load_ship

    if args.example is not None:
        if args.action is not None or args.ship is not None:
            raise UsageError("vessel-gym ships --example: takes only FILE (and --force)")
        print(f"wrote: {write_example(Path(args.example), args.force)}", file=sys.stderr)
        return 0
    if args.action == "check":
        if args.ship is None:
            raise UsageError("vessel-gym ships check: name a ship: built-in name or ship file (.toml)")
        return _ships_check(args, emit)
    if args.ship is not None:
        raise UsageError(
            f"vessel-gym ships: unexpected {args.ship!r} (did you mean 'ships check {args.ship}'?)"
        )
    rows = []
    for name in builtin_ships():
        ship = load_ship(name)
        p = ship.particulars
        rows.append(
            {
                "ship": name,
                "hull_model": type(ship.hull).__name__.removesuffix("Hull"),
                "L_m": p.L_m,
                "B_m": p.B_m,
                "T_m": p.T_m,
                "displacement_t": round(ship.mass_kg / 1000.0, 1),
                "test_speed_kn": p.test_speed_kn,
                "source": ship.source.citation,
            }
        )
    if args.json:
        print(json.dumps(rows, allow_nan=False))
        return 0
    w = max([10, *(len(r["ship"]) for r in rows)]) + 2  # the name column fits the longest name
    head = f"{'ship':<{w}}{'hull':<10}{'L m':>8}{'B m':>8}{'T m':>7}{'displ. t':>12}{'test kn':>9}"
    lines = [head]
    for r in rows:
        lines.append(
            f"{r['ship']:<{w}}{r['hull_model']:<10}{r['L_m']:8.2f}{r['B_m']:8.2f}{r['T_m']:7.2f}"
            f"{r['displacement_t']:12,.1f}{r['test_speed_kn']:9.2f}"
        )
        lines.append(f"    source: {r['source']}")
    print("\n".join(lines))
    return 0
