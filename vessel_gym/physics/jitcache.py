"""Where the compiled kernels are cached, and the notice shown while they compile.

numba caches a kernel's machine code per source file and checks only that file for changes, but our kernels
inline functions and read layout constants from other modules, so a kernel's cache can go stale when only one
of those changes. Instead of deleting cache files when the sources change, the package's kernels are cached in
a directory named by a hash of every source they can depend on (``SOURCE_HASH``): after any change the kernels
look in a new, empty directory and compile afresh; stale machine code is never found, and nothing is deleted.

The directory is, in order of preference: ``$NUMBA_CACHE_DIR/vessel_gym-<hash>`` when the user chose a numba
cache directory; ``vessel_gym/__pycache__/numba-<hash>`` beside the sources when writable; the user's cache
directory (``~/.cache/vessel_gym/numba-<hash>`` on Linux) otherwise. Directories of older sources are left
where they are (each a few MB); they can be removed by hand at any time.

Which sources count: every ``.py`` file under ``vessel_gym/physics`` and ``vessel_gym/envs``, and any other
module of the package that mentions numba. Kernels may inline functions and read module constants only from
these.

numba internals: this is the one module of the package that uses numba's private API -- the cache locator
classes of ``numba.core.caching`` (``_CacheLocator``, ``_SourceFileBackedLocatorMixin``, the locator list of
``CacheImpl``) and the compile events of ``numba.core.event`` -- because numba has no public way to say where a
function's cache lives or to key it by more than its own file. Private names may change in any numba release,
so numba is pinned to the minor versions CI tests (pyproject.toml; the lowest in .ci/constraints-lowest.txt);
``tests/physics/test_jitcache.py`` fails first when a new numba moves them. The rest of the physics uses
numba's public decorators only (``njit``, ``prange``, ``config``).

Compiling the kernels takes tens of seconds on a small machine, so the first compilation in a process says so
once ("vessel-gym: compiling kernels (first run only) ..."); runs that load everything from the cache say
nothing. On a terminal the line is printed on stderr. Anywhere else (a redirected command, a log, Jupyter, a
library call such as ``gymnasium.make``) it is a WARNING of the ``vessel_gym`` logger: without a logging set-up
Python prints it on stderr as the same one line, and a program that configures logging routes or silences it
like any other record. ``VESSEL_GYM_COMPILE_NOTICE=1`` prints it on stderr always (benchmarks), ``=0`` never.
"""

from __future__ import annotations

import hashlib
import logging
import os
import sys
import threading
from pathlib import Path

from numba.core import caching, event
from numba.misc.appdirs import AppDirs

PACKAGE_DIR = Path(__file__).resolve().parent.parent  # vessel_gym/
KERNEL_DIRS = ("physics", "envs")  # subpackages whose every module a kernel may read
COMPILE_NOTICE = "vessel-gym: compiling kernels (first run only) ..."
NOTICE_ENV = "VESSEL_GYM_COMPILE_NOTICE"  # "1": always print the notice, "0": never; unset: print or log it
LOGGER = logging.getLogger("vessel_gym")

# numba >= 0.64 names these without the leading underscore
_CacheImpl = getattr(caching, "CacheImpl", None) or caching._CacheImpl
_CacheLocator = caching._CacheLocator
_SourceFileBackedLocatorMixin = caching._SourceFileBackedLocatorMixin


def kernel_sources(package_dir: Path = PACKAGE_DIR) -> list[Path]:
    """The source files whose content keys the kernel cache (see the module docstring), sorted."""
    files = set()
    for sub in KERNEL_DIRS:
        files.update((package_dir / sub).rglob("*.py"))
    for f in package_dir.rglob("*.py"):
        if f not in files and b"numba" in f.read_bytes():
            files.add(f)
    return sorted(files)


def source_hash(package_dir: Path = PACKAGE_DIR) -> str:
    """sha256 over the kernel sources' paths (relative to the package) and contents, first 16 hex digits."""
    digest = hashlib.sha256()
    for f in kernel_sources(package_dir):
        digest.update(f.relative_to(package_dir).as_posix().encode() + b"\0")
        digest.update(f.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


SOURCE_HASH = source_hash()


def cache_roots() -> list[Path]:
    """Candidate cache directories for this source hash, in order of preference."""
    from numba.core import config

    if config.CACHE_DIR:
        return [Path(config.CACHE_DIR) / f"vessel_gym-{SOURCE_HASH}"]
    user = Path(AppDirs(appname="vessel_gym", appauthor=False).user_cache_dir)
    return [PACKAGE_DIR / "__pycache__" / f"numba-{SOURCE_HASH}", user / f"numba-{SOURCE_HASH}"]


class SourceHashCacheLocator(_SourceFileBackedLocatorMixin, _CacheLocator):
    """numba cache locator for the package's kernels: a per-source-hash directory (module docstring)."""

    def __init__(self, py_func, py_file: str, root: Path):
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        rel = Path(py_file).resolve().parent.relative_to(PACKAGE_DIR)
        self._cache_path = str(root / rel)

    def get_cache_path(self) -> str:
        return self._cache_path

    @classmethod
    def from_function(cls, py_func, py_file):
        try:
            Path(py_file).resolve().relative_to(PACKAGE_DIR)
        except (ValueError, OSError):
            return None  # not ours: numba's own locators decide
        for root in cache_roots():
            self = cls(py_func, py_file, root)
            try:
                self.ensure_cache_path()
            except OSError:
                continue
            return self
        return None  # nowhere writable: numba's locators (or no cache) as for any function


_notice_lock = threading.Lock()
_notice_shown = False


def _notice_route() -> str | None:
    """How the compile notice is given: "print" (stderr), "log" (the vessel_gym logger) or None."""
    choice = os.environ.get(NOTICE_ENV, "")
    if choice == "0":
        return None
    if choice == "1":
        return "print"
    try:
        tty = sys.stderr.isatty()
    except (AttributeError, ValueError):  # replaced or closed stderr
        tty = False
    return "print" if tty else "log"


class _CompileNotice(event.Listener):
    """Gives COMPILE_NOTICE once per process when numba starts compiling one of the package's kernels."""

    def on_start(self, ev):
        global _notice_shown
        if _notice_shown:
            return
        dispatcher = ev.data.get("dispatcher") if isinstance(ev.data, dict) else None
        py_func = getattr(dispatcher, "py_func", None)
        module = getattr(py_func, "__module__", "") or ""
        route = _notice_route() if module.startswith("vessel_gym.") else None
        if route is None:
            return
        with _notice_lock:
            if not _notice_shown:
                _notice_shown = True
                if route == "print":
                    print(COMPILE_NOTICE, file=sys.stderr, flush=True)
                else:
                    LOGGER.warning(COMPILE_NOTICE)

    def on_end(self, ev):
        pass


_listeners: list[_CompileNotice] = []


def install() -> None:
    """Put the locator first in numba's list and listen for compilations (idempotent)."""
    if SourceHashCacheLocator not in _CacheImpl._locator_classes:
        _CacheImpl._locator_classes.insert(0, SourceHashCacheLocator)
    if not any(isinstance(x, _CompileNotice) for x in _listeners):
        listener = _CompileNotice()
        event.register("numba:compile", listener)
        _listeners.append(listener)
