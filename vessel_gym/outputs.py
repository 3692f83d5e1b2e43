"""Output files and JSON numbers: where a command writes, that it never replaces a user's file unless told to,
and the precision numbers are reported with.

Path rule (the same for every ``--plot``, ``--report`` and ``--out`` option): a path whose suffix names a file
format the option can write (``.png``, ``.svg``, ``.pdf``, ``.html``) is that file; anything else (a path ending
in ``/``, an existing directory, a name without such a suffix) is a directory, created if missing, into which
the command writes its default file names. An existing file is never replaced unless ``force`` is given.

``force`` replaces the named file itself and nothing else: a symbolic link at an output path is refused even
with ``force`` (its target may be any file of the user's; remove the link or name another path), and the file
is opened with ``O_NOFOLLOW``, so a link that appears after the check is refused too. Names that come from file
contents (a scenario's or a ship's name) pass through :func:`safe_name`, one path segment, before they become
part of an output path.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable
from pathlib import Path


class OutputExistsError(ValueError):
    """An output file exists already and ``force`` was not given (or an output path is unusable)."""


def output_target(arg: str | Path, allowed_suffixes: Iterable[str], what: str) -> tuple[Path, bool]:
    """Interpret an output option: ``(path, is_dir)`` by the module's path rule.

    Raises :class:`OutputExistsError` (a ValueError, one line naming ``what``) when the path names a file of
    another format, or when a directory is meant and a regular file of that name exists.
    """
    text = str(arg)
    p = Path(text)
    allowed = tuple(s.lower() for s in allowed_suffixes)
    if text.endswith(("/", os.sep)) or p.is_dir():
        if p.exists() and not p.is_dir():
            raise OutputExistsError(f"{what}: {text!r} exists and is not a directory")
        return p, True
    suffix = p.suffix.lower()
    if suffix in allowed:
        if p.is_dir():  # pragma: no cover - handled above
            return p, True
        return p, False
    if suffix and suffix in _FORMAT_SUFFIXES:
        raise OutputExistsError(
            f"{what}: cannot write a {suffix} file here; name a {', '.join(allowed)} file or a directory"
        )
    if p.exists():
        raise OutputExistsError(
            f"{what}: {text!r} exists and is not a directory (name a {', '.join(allowed)} file, "
            "or a directory to write into)"
        )
    return p, True


# suffixes that look like a file name rather than a directory name
_FORMAT_SUFFIXES = {".png", ".svg", ".pdf", ".html", ".htm", ".jpg", ".jpeg", ".gif", ".eps", ".ps", ".txt"}


def check_free(paths: Iterable[Path], force: bool, what: str) -> None:
    """Refuse (one line) if any of ``paths`` exists and ``force`` is False, if a folder on the way is a
    file, or if nothing can be written where they go; checked before any work starts."""
    paths = list(paths)
    probed: set[Path] = set()
    for p in paths:
        for parent in Path(p).parents:
            if parent.exists():
                if not parent.is_dir():
                    raise OutputExistsError(f"{what}: {str(parent)!r} is not a directory")
                if parent not in probed:
                    probed.add(parent)
                    _probe_writable(parent, what)
                break
    for p in paths:
        if Path(p).is_symlink():
            raise OutputExistsError(
                f"{what}: {str(p)!r} is a symbolic link; not replaced, not even with --force "
                "(remove the link or name another file)"
            )
    if force:
        for p in paths:
            if p.exists() and not p.is_file():
                raise OutputExistsError(f"{what}: {str(p)!r} exists and is not a regular file")
        return
    taken = [str(p) for p in paths if p.exists() or p.is_symlink()]
    if taken:
        more = f" (and {len(taken) - 1} more)" if len(taken) > 1 else ""
        raise OutputExistsError(f"{what}: {taken[0]!r} exists{more}; not replaced (use --force to overwrite)")


def _probe_writable(folder: Path, what: str) -> None:
    """Create and remove an empty file in ``folder``: permissions, a read-only mount or a pseudo file system
    such as /proc refuse it now rather than after minutes of trials (``os.access`` says yes to root)."""
    import tempfile

    try:
        fd, name = tempfile.mkstemp(prefix=".vessel-gym-probe-", dir=folder)
    except OSError as exc:
        raise OutputExistsError(f"{what}: cannot write in {str(folder)!r} ({exc.strerror})") from None
    os.close(fd)
    os.unlink(name)


# Longest part of a file name taken from a file's contents, in UTF-8 bytes: file systems allow 255 bytes per
# name, and the callers add a prefix and a suffix (``debrief_``, ``_turning_circle.png``) of a few dozen.
MAX_NAME_BYTES = 120


def safe_name(text: str) -> str:
    """``text`` as one file-name component: characters other than letters, digits, ``-``, ``_`` and ``.``
    become ``_``, leading dots go, and it is cut to :data:`MAX_NAME_BYTES` (a ship's or scenario's name may
    come from a user's file)."""
    name = "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in text).lstrip(".")
    return name.encode("utf-8")[:MAX_NAME_BYTES].decode("utf-8", "ignore") or "unnamed"


def write_new(path: Path, data: bytes, force: bool) -> Path:
    """Write ``data`` to ``path``; without ``force`` the file must not exist (exclusive create, so a file
    that appeared since :func:`check_free` is not replaced either)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.is_symlink():
        raise OutputExistsError(f"{str(path)!r} is a symbolic link; not replaced, not even with --force")
    # O_NOFOLLOW: --force replaces the named file, never a symbolic link's target (see the module docstring)
    flags = os.O_WRONLY | os.O_CREAT | os.O_NOFOLLOW | (os.O_TRUNC if force else os.O_EXCL)
    try:
        fd = os.open(path, flags, 0o666)
    except FileExistsError:
        raise OutputExistsError(f"{str(path)!r} exists; not replaced (use --force to overwrite)") from None
    except IsADirectoryError:
        raise OutputExistsError(f"{str(path)!r} is a directory; not replaced") from None
    except OSError as exc:
        if path.is_symlink():
            raise OutputExistsError(
                f"{str(path)!r} is a symbolic link; not replaced, not even with --force"
            ) from None
        raise OutputExistsError(f"{str(path)!r}: cannot write ({exc.strerror})") from None
    with os.fdopen(fd, "wb") as fh:
        fh.write(data)
    return path


# Decimal places per unit suffix of a JSON key (its unit, by the project's naming rule), chosen from what the
# trials resolve: positions to a centimetre / 1e-3 L, angles to 0.01 deg, times to 0.1 s (the trial step is
# at most 0.1 s), speeds to 0.01 kn (about 5 mm/s), rates of turn to 1e-4 deg/s.
_DECIMALS = (
    ("_deg_s", 4),
    ("_m_s", 3),
    ("_kn", 2),
    ("_deg", 2),
    ("_rpm", 1),
    ("_m", 2),
    ("_L", 3),
    ("_s", 1),
)
# criteria carry their unit in a sibling "unit" key
_UNIT_DECIMALS = {"L": 3, "deg": 2, "m": 2, "s": 1, "kn": 2}
_SIGNIFICANT = 6  # any other float: six significant figures


def _round_sig(x: float, digits: int = _SIGNIFICANT) -> float:
    if x == 0.0 or not math.isfinite(x):
        return x
    return round(x, digits - 1 - int(math.floor(math.log10(abs(x)))))


def _decimals_for(key: str) -> int | None:
    for suffix, dec in _DECIMALS:
        if key.endswith(suffix):
            return dec
    return None


def _round_value(x, dec: int | None):
    if isinstance(x, bool) or not isinstance(x, float):
        try:
            import numpy as np

            if isinstance(x, np.floating):
                x = float(x)
            else:
                return x
        except ImportError:  # pragma: no cover - numpy is a core dependency
            return x
    if not math.isfinite(x):
        return x
    return round(x, dec) if dec is not None else _round_sig(x)


def rounded(obj, dec: int | None = None):
    """``obj`` (dicts, lists, numbers) with every float rounded to its meaningful precision: by the unit
    suffix of its key (``_m``, ``_L``, ``_deg``, ``_s``, ``_kn`` ...), or by a sibling ``"unit"`` key for a
    criterion's ``value`` and ``limit``; other floats to six significant figures."""
    if isinstance(obj, dict):
        unit_dec = _UNIT_DECIMALS.get(obj.get("unit")) if isinstance(obj.get("unit"), str) else None
        out = {}
        for k, v in obj.items():
            d = _decimals_for(k) if isinstance(k, str) else None
            if d is None and k in ("value", "limit"):
                d = unit_dec
            out[k] = rounded(v, d)
        return out
    if isinstance(obj, (list, tuple)):
        return [rounded(v, dec) for v in obj]
    return _round_value(obj, dec)
