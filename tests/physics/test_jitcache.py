"""The kernel cache is keyed by a hash of the sources: a change anywhere a kernel reads compiles afresh, old
machine code is never loaded, and importing the package deletes nothing."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import vessel_gym
from vessel_gym.physics import jitcache

PACKAGE = Path(vessel_gym.__file__).resolve().parent

# A kernel in one file that reads a constant from another: numba's own per-file stamp would not notice a change
# of the constant and would load the stale machine code.
PROBE_CONST = "K = {k}  # 1, a probe constant read by a kernel in another file\n"
PROBE_KERNEL = """
from numba import njit

from vessel_gym.physics import _probe_const


@njit(cache=True)
def probe():
    return _probe_const.K
"""
RUN = "from vessel_gym.physics._probe_kernel import probe; print(probe())"


@pytest.fixture
def package_copy(tmp_path: Path) -> Path:
    """A copy of the package's sources (no caches) with a probe kernel, importable from ``tmp_path``."""
    shutil.copytree(PACKAGE, tmp_path / "vessel_gym", ignore=shutil.ignore_patterns("__pycache__"))
    (tmp_path / "vessel_gym/physics/_probe_const.py").write_text(PROBE_CONST.format(k=1.0))
    (tmp_path / "vessel_gym/physics/_probe_kernel.py").write_text(PROBE_KERNEL)
    return tmp_path


def _run(root: Path, cache_dir: Path | None = None) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env["PYTHONPATH"] = str(root)
    env[jitcache.NOTICE_ENV] = "1"  # stderr is a pipe here
    if cache_dir is not None:
        env["NUMBA_CACHE_DIR"] = str(cache_dir)
    proc = subprocess.run(
        [sys.executable, "-c", RUN], cwd=root, env=env, capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    return proc


def _cache_files(root: Path) -> set[Path]:
    return {p for p in root.rglob("*") if p.suffix in (".nbi", ".nbc")}


def test_changed_constant_in_another_file_recompiles_and_deletes_nothing(package_copy: Path):
    first = _run(package_copy)
    assert first.stdout.strip() == "1.0"
    assert jitcache.COMPILE_NOTICE in first.stderr
    files = _cache_files(package_copy / "vessel_gym/__pycache__")
    assert files, "the probe kernel was not cached beside the sources"

    warm = _run(package_copy)
    assert warm.stdout.strip() == "1.0"
    assert jitcache.COMPILE_NOTICE not in warm.stderr  # loaded from the cache, nothing compiled

    (package_copy / "vessel_gym/physics/_probe_const.py").write_text(PROBE_CONST.format(k=2.0))
    changed = _run(package_copy)
    assert changed.stdout.strip() == "2.0"  # the stale machine code (returning 1.0) was not loaded
    assert jitcache.COMPILE_NOTICE in changed.stderr
    after = _cache_files(package_copy / "vessel_gym/__pycache__")
    assert files <= after and len(after) > len(files)  # the old cache is still there, the new one beside it
    dirs = {
        p.name for p in (package_copy / "vessel_gym/__pycache__").iterdir() if p.name.startswith("numba-")
    }
    assert len(dirs) == 2


def test_user_cache_dir_is_respected(package_copy: Path, tmp_path: Path):
    cache = tmp_path / "numba-cache"
    assert _run(package_copy, cache).stdout.strip() == "1.0"
    (hashed,) = [p for p in cache.iterdir() if p.name.startswith("vessel_gym-")]
    assert _cache_files(hashed / "physics")
    assert not (package_copy / "vessel_gym/__pycache__").exists() or not _cache_files(
        package_copy / "vessel_gym/__pycache__"
    )


def test_hash_covers_every_kernel_source():
    sources = {p.relative_to(PACKAGE).as_posix() for p in jitcache.kernel_sources()}
    assert {"physics/layout.py", "physics/vessel.py", "physics/integrate.py", "envs/tasks/zigzag.py"} <= sources
    assert jitcache.SOURCE_HASH == jitcache.source_hash()


def test_functions_outside_the_package_keep_numbas_locators():
    def elsewhere():
        return 1

    assert jitcache.SourceHashCacheLocator.from_function(elsewhere, __file__) is None


def test_notice_printed_on_a_terminal_logged_elsewhere_or_as_asked(monkeypatch):
    class Tty:
        def __init__(self, tty: bool):
            self.tty = tty

        def isatty(self) -> bool:
            return self.tty

    monkeypatch.delenv(jitcache.NOTICE_ENV, raising=False)
    monkeypatch.setattr("sys.stderr", Tty(True))
    assert jitcache._notice_route() == "print"
    monkeypatch.setattr("sys.stderr", Tty(False))
    assert jitcache._notice_route() == "log"
    monkeypatch.setenv(jitcache.NOTICE_ENV, "1")
    assert jitcache._notice_route() == "print"
    monkeypatch.setenv(jitcache.NOTICE_ENV, "0")
    monkeypatch.setattr("sys.stderr", Tty(True))
    assert jitcache._notice_route() is None


PROBE_TWO = """
from numba import njit


@njit(cache=True)
def other():
    return 2.0
"""


def test_redirected_cold_start_says_so_once_on_stderr(package_copy: Path, tmp_path: Path):
    """Outside a terminal (stderr a pipe, no logging set up, as for a redirected command or a log file), the first
    compilation is one line on stderr, through the vessel_gym logger; two kernels compiled: still one line."""
    (package_copy / "vessel_gym/physics/_probe_two.py").write_text(PROBE_TWO)
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_") and k != jitcache.NOTICE_ENV}
    env["PYTHONPATH"] = str(package_copy)
    env["NUMBA_CACHE_DIR"] = str(tmp_path / "cache")
    code = RUN + "\nfrom vessel_gym.physics._probe_two import other; print(other())"
    proc = subprocess.run(
        [sys.executable, "-c", code], cwd=package_copy, env=env, capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["1.0", "2.0"]
    assert proc.stderr.splitlines() == [jitcache.COMPILE_NOTICE]
    # a program that sets up logging receives it as a record of the vessel_gym logger
    logged = subprocess.run(
        [
            sys.executable,
            "-c",
            "import logging; logging.basicConfig(format='LOG %(name)s %(message)s')\n" + code,
        ],
        cwd=package_copy,
        env={**env, "NUMBA_CACHE_DIR": str(tmp_path / "cache2")},
        capture_output=True,
        text=True,
    )
    assert logged.stderr.splitlines() == [f"LOG vessel_gym {jitcache.COMPILE_NOTICE}"], logged.stderr
