"""A small, predictable writer for OpenFOAM dictionaries.

Python values map to OpenFOAM syntax as follows:

* ``dict`` -> a sub-dictionary ``{ ... }`` (keys in insertion order);
* ``bool`` -> ``yes`` / ``no``; ``int`` / ``float`` -> a number;
* ``str`` -> written verbatim (quote it yourself where OpenFOAM wants a string);
* ``list`` / ``tuple`` / 1-D numpy array -> a list ``( ... )``;
* :class:`Words` -> several tokens of one entry, e.g. ``Words("uniform", (1, 0, 0))``;
* :class:`Named` -> a named sub-dictionary inside a list (blockMesh ``boundary``);
* a key mapped to ``None`` -> the key alone (directives such as ``#include "file"``).

foamlib can parse every file written here (the tests check that); it is not used for writing
because its one-line output is hard for people to read and edit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

HEADER = """/*--------------------------------*- C++ -*----------------------------------*\\
  Written by vessel-cfd (cfd.foamdict) for OpenFOAM v1912 (openfoam.com)
\\*---------------------------------------------------------------------------*/
"""


class Words(tuple):
    """Several space-separated tokens forming one value (``uniform (1 0 0)``)."""

    def __new__(cls, *items: Any) -> Words:
        return super().__new__(cls, items)


@dataclass(frozen=True)
class Named:
    """A ``name { ... }`` element of a list (blockMesh ``boundary`` entries)."""

    name: str
    body: Mapping[str, Any]


def fmt_number(x: float | int) -> str:
    """Format a number the way OpenFOAM reads it (finite only)."""
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"non-finite number {x!r} in an OpenFOAM dictionary")
    if x == int(x) and abs(x) < 1e15:
        return str(int(x))
    return f"{x:.10g}"


def _is_scalar(v: Any) -> bool:
    return isinstance(v, (str, bool, int, float, np.integer, np.floating))


def _inline(value: Any) -> str:
    """Value written on one line (scalars, flat lists, Words)."""
    if isinstance(value, str):
        return value
    if isinstance(value, (bool, int, float, np.integer, np.floating)):
        return fmt_number(value)
    if isinstance(value, Words):
        return " ".join(_inline(v) for v in value)
    if isinstance(value, (list, tuple, np.ndarray)):
        return "(" + " ".join(_inline(v) for v in value) + ")"
    raise TypeError(f"cannot write {type(value).__name__} inline")


def _fits_inline(value: Any) -> bool:
    if _is_scalar(value):
        return True
    if isinstance(value, (Words, list, tuple, np.ndarray)):
        flat = all(_fits_inline(v) and not isinstance(v, Named) for v in value)
        return flat and len(_inline(value)) <= 100
    return False


def _lines(value: Any, indent: int) -> list[str]:
    """Lines of a list written one element per line."""
    pad = "    " * indent
    out = [pad + "("]
    for item in value:
        if isinstance(item, Named):
            out.append(pad + "    " + item.name)
            out.extend(_dict_lines(item.body, indent + 1))
        elif isinstance(item, Mapping):
            out.extend(_dict_lines(item, indent + 1))
        elif _fits_inline(item):
            out.append(pad + "    " + _inline(item))
        else:
            out.extend(_lines(item, indent + 1))
    out.append(pad + ")")
    return out


def _entry_lines(key: str, value: Any, indent: int) -> list[str]:
    pad = "    " * indent
    if value is None:
        return [pad + key]
    if isinstance(value, Mapping):
        return [pad + key, *_dict_lines(value, indent)]
    if _fits_inline(value):
        return [f"{pad}{key:<15} {_inline(value)};"]
    if isinstance(value, Words):
        raise TypeError(f"entry {key!r}: Words too long or nested for one line")
    body = _lines(value, indent)
    body[-1] += ";"
    return [pad + key, *body]


def _dict_lines(d: Mapping[str, Any], indent: int) -> list[str]:
    pad = "    " * indent
    out = [pad + "{"]
    for k, v in d.items():
        out.extend(_entry_lines(k, v, indent + 1))
    out.append(pad + "}")
    return out


def dumps(
    entries: Mapping[str, Any],
    *,
    foam_class: str = "dictionary",
    location: str | None = None,
    obj: str = "dict",
) -> str:
    """Text of an OpenFOAM dictionary file with a ``FoamFile`` header."""
    header: dict[str, Any] = {"version": "2.0", "format": "ascii", "class": foam_class}
    if location is not None:
        header["location"] = f'"{location}"'
    header["object"] = obj
    lines = [HEADER.rstrip("\n"), *_entry_lines("FoamFile", header, 0), ""]
    for k, v in entries.items():
        lines.extend(_entry_lines(k, v, 0))
        lines.append("")
    return (
        "\n".join(lines) + "// ************************************************************************* //\n"
    )


def write(
    path: str | Path, entries: Mapping[str, Any], *, foam_class: str = "dictionary", obj: str | None = None
) -> Path:
    """Write an OpenFOAM dictionary file; ``location`` is derived from the case layout."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    location = path.parent.name if path.parent.name in {"system", "constant"} else None
    if location is None and path.parent.name.replace(".", "", 1).isdigit():
        location = path.parent.name
    path.write_text(dumps(entries, foam_class=foam_class, location=location, obj=obj or path.name))
    return path
