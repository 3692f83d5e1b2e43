"""Strict loading of typed, frozen dataclasses from TOML tables.

Every field of a parameter dataclass carries its unit and allowed range in ``metadata``; loading rejects
unknown keys, missing required keys, wrong types, non-finite numbers and out-of-range values with a one-line
message naming the file and the key. Shared by ship files and scenario files.
"""

from __future__ import annotations

import dataclasses
import math
import os
import stat
import sys
import typing
from pathlib import Path
from typing import Any

from vessel_gym.cli_args import printable  # how a file name goes into a one-line error

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


class SpecError(ValueError):
    """A data file (ship, scenario, study) is invalid. The message is one line naming file and key."""


def param(
    default: Any = dataclasses.MISSING,
    *,
    unit: str = "-",
    lo: float | None = None,
    hi: float | None = None,
    doc: str = "",
    choices: tuple | None = None,
) -> Any:
    """A dataclass field with unit, range and documentation (read by the loader and the docs generator)."""
    md = {"unit": unit, "lo": lo, "hi": hi, "doc": doc, "choices": choices}
    if default is dataclasses.MISSING:
        return dataclasses.field(metadata=md)
    if isinstance(default, (list, dict)):
        return dataclasses.field(default_factory=lambda: default, metadata=md)
    return dataclasses.field(default=default, metadata=md)


#: default size bound of a data file, bytes (ship files and environment configs are a few kB; 1 MiB leaves
#: room for long provenance notes while refusing to read a device or a runaway file into memory)
MAX_FILE_BYTES = 1 << 20


def read_toml(path: Path, max_bytes: int = MAX_FILE_BYTES) -> dict:
    """Read a TOML file; every failure becomes a one-line SpecError naming the file.

    Only a regular file of at most ``max_bytes`` is read: a directory, a device (``/dev/zero``), a pipe or
    terminal (``/dev/stdin``) is refused before reading, so a wrong path can neither hang nor fill memory.
    The file is opened non-blocking (opening a FIFO would otherwise wait for a writer) and checked again
    on the open descriptor, so a path replaced between the checks is still caught.
    """
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise SpecError(f"{printable(path)}: file not found") from None
    except (OSError, ValueError) as exc:  # permission, name too long, loop, embedded NUL byte
        raise SpecError(f"{printable(path)}: cannot read ({_reason(exc)})") from None
    _check_regular(path, st, max_bytes)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
    except (OSError, ValueError) as exc:
        raise SpecError(f"{printable(path)}: cannot read ({_reason(exc)})") from None
    try:
        with os.fdopen(fd, "rb") as fh:
            _check_regular(path, os.fstat(fh.fileno()), max_bytes)
            raw = fh.read(max_bytes + 1)
    except OSError as exc:
        raise SpecError(f"{printable(path)}: cannot read ({_reason(exc)})") from None
    if len(raw) > max_bytes:  # grew after the size check
        raise SpecError(f"{printable(path)}: file is larger than the limit of {_size(max_bytes)}")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SpecError(f"{printable(path)}: not UTF-8 text (invalid byte at offset {exc.start})") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"{printable(path)}: TOML syntax error: {exc}") from None
    except RecursionError:
        raise SpecError(f"{printable(path)}: arrays or tables nested too deeply") from None
    except ValueError as exc:  # an integer beyond Python's digit limit for str -> int (4300 by default)
        raise SpecError(f"{printable(path)}: a number is too long ({exc})") from None


def _reason(exc: Exception) -> str:
    return exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)


def _size(n: int) -> str:
    return f"{n / (1 << 20):g} MiB" if n >= 1 << 20 else f"{n} bytes"


def _check_regular(path: Path, st: os.stat_result, max_bytes: int) -> None:
    if stat.S_ISDIR(st.st_mode):
        raise SpecError(f"{printable(path)}: is a directory, expected a .toml file")
    if not stat.S_ISREG(st.st_mode):
        raise SpecError(f"{printable(path)}: not a regular file (a device, pipe or socket is not read)")
    if st.st_size > max_bytes:
        raise SpecError(f"{printable(path)}: file is {_size(st.st_size)}, larger than the limit of {_size(max_bytes)}")


def as_float(value: int | float, where: str) -> float:
    """A TOML number as a float; an integer too large for a float is a SpecError (not OverflowError)."""
    try:
        return float(value)
    except OverflowError:
        try:
            digits = str(len(str(abs(value))))
        except ValueError:  # beyond Python's int -> str digit limit
            digits = "thousands of"
        raise SpecError(f"{where}: an integer of {digits} digits is too large") from None


def _short(value: Any, n: int = 60) -> str:
    """repr of a value cut to ``n`` characters, so that a message stays one short line."""
    try:
        r = repr(value)
    except (RecursionError, ValueError):  # deeply nested list; int beyond str conversion limit
        r = f"<{type(value).__name__}>"
    r = r.replace("\n", " ")
    return r if len(r) <= n else r[: n - 3] + "..."


def _check_number(value: Any, where: str, md: dict) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SpecError(f"{where}: expected a number, got {type(value).__name__} {_short(value)}")
    x = as_float(value, where)
    if not math.isfinite(x):
        raise SpecError(f"{where}: value must be finite, got {_short(value)}")
    lo, hi = md.get("lo"), md.get("hi")
    if (lo is not None and x < lo) or (hi is not None and x > hi):
        lo_s = "-inf" if lo is None else f"{lo:g}"
        hi_s = "inf" if hi is None else f"{hi:g}"
        raise SpecError(f"{where}: {x:g} {md.get('unit', '')} is outside the allowed range [{lo_s}, {hi_s}]")
    return x


def _plain_floats(values: list, md: dict) -> bool:
    """True if every value is a finite float within the range; otherwise the element-wise path names the
    first bad one."""
    lo = -math.inf if md.get("lo") is None else md["lo"]
    hi = math.inf if md.get("hi") is None else md["hi"]
    return all(type(v) is float and lo <= v <= hi and math.isfinite(v) for v in values)


def _convert(value: Any, tp: Any, where: str, md: dict) -> Any:
    origin = typing.get_origin(tp)
    if tp is float:
        return _check_number(value, where, md)
    if tp is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise SpecError(f"{where}: expected an integer, got {_short(value)}")
        _check_number(value, where, md)
        return value
    if tp is dict:
        if not isinstance(value, dict):
            raise SpecError(f"{where}: expected a table, got {_short(value)}")
        return value
    if tp is bool:
        if not isinstance(value, bool):
            raise SpecError(f"{where}: expected true or false, got {_short(value)}")
        return value
    if tp is str:
        if not isinstance(value, str):
            raise SpecError(f"{where}: expected a string, got {_short(value)}")
        choices = md.get("choices")
        if choices and value not in choices:
            raise SpecError(f"{where}: {_short(value)} is not one of {', '.join(map(repr, choices))}")
        return value
    if origin is tuple:
        (inner, _ell) = typing.get_args(tp)
        if not isinstance(value, list):
            raise SpecError(f"{where}: expected a list, got {_short(value)}")
        if inner is float and _plain_floats(value, md):  # fast path for long coordinate lists
            return tuple(value)
        return tuple(_convert(v, inner, f"{where}[{i}]", md) for i, v in enumerate(value))
    if origin is typing.Union or str(origin) == "<class 'types.UnionType'>":
        args = [a for a in typing.get_args(tp) if a is not type(None)]
        return _convert(value, args[0], where, md)
    if dataclasses.is_dataclass(tp):
        if not isinstance(value, dict):
            raise SpecError(f"{where}: expected a table, got {_short(value)}")
        return build(tp, value, where)
    raise TypeError(f"unsupported field type {tp!r} at {where}")  # programming error, not user input


def build(cls: type, table: dict, where: str) -> Any:
    """Build dataclass ``cls`` from a TOML table; ``where`` prefixes messages ("file.toml: [hull]")."""
    if not isinstance(table, dict):
        raise SpecError(f"{where}: expected a table")
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    unknown = [k for k in table if k not in fields]
    if unknown:
        raise SpecError(f"{where}: unknown key {_short(unknown[0])} (allowed: {', '.join(fields)})")
    kwargs = {}
    for name, f in fields.items():
        key_where = f"{where} {name}"
        if name in table:
            kwargs[name] = _convert(table[name], hints[name], key_where, dict(f.metadata))
        elif f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
            raise SpecError(f"{key_where}: missing required key")
    return cls(**kwargs)


def check_fields(obj: Any, where: str) -> None:
    """Check a dataclass instance's float fields against their declared ranges (``param`` metadata).

    For objects built in code rather than read from a file: a NaN, an infinity, a non-number or a value
    outside the range raises :class:`SpecError` naming ``where``, the field and its allowed range.
    """
    for f in dataclasses.fields(obj):
        md = f.metadata
        if md.get("lo") is None and md.get("hi") is None:
            continue
        _check_number(getattr(obj, f.name), f"{where} {f.name}", md)


def describe(cls: type) -> list[tuple[str, str, str, str, str]]:
    """(key, type, unit, range, doc) rows for documentation of a parameter dataclass."""
    rows = []
    hints = typing.get_type_hints(cls)
    for f in dataclasses.fields(cls):
        md = f.metadata
        lo, hi = md.get("lo"), md.get("hi")
        rng = (
            ""
            if lo is None and hi is None
            else f"[{'' if lo is None else f'{lo:g}'}, {'' if hi is None else f'{hi:g}'}]"
        )
        if md.get("choices"):
            rng = " | ".join(md["choices"])
        req = f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
        tname = getattr(hints[f.name], "__name__", str(hints[f.name]))
        rows.append(
            (f.name + (" (required)" if req else ""), tname, md.get("unit", ""), rng, md.get("doc", ""))
        )
    return rows


def builtin_names(directory: Path) -> list[str]:
    """Names (file stems) of the TOML files in a data directory."""
    return sorted(p.stem for p in directory.glob("*.toml"))


def resolve_data_path(
    name: str | Path, directory: Path, kind: str, error: type[SpecError] = SpecError
) -> Path:
    """A built-in name (a TOML file in ``directory``) or a path to a ``.toml`` file -> path.

    An unknown built-in name raises ``error`` naming the ``kind`` ("ship", "scenario") and the choices.
    """
    s = str(name)
    if s.endswith(".toml") or "/" in s or "\\" in s:
        return Path(s)
    path = directory / f"{s}.toml"
    try:
        known = path.is_file()
    except (OSError, ValueError):  # name too long for the file system, embedded NUL byte
        known = False
    if not known:
        shown = s if s.isprintable() and len(s) <= 60 else _short(s)
        raise error(
            f"{shown}: unknown {kind} (built-in: {', '.join(builtin_names(directory))}; or give a .toml path)"
        )
    return path


def check_ranges(config: Any, keys: tuple[str, ...], where: str) -> None:
    """Each of ``keys`` of ``config`` must be a [min, max] pair with min <= max (SpecError otherwise)."""
    for key in keys:
        rng = getattr(config, key)
        if len(rng) != 2 or rng[0] > rng[1]:
            raise SpecError(f"{where} {key}: expected [min, max], got {list(rng)}")
