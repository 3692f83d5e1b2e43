"""Running OpenFOAM applications: environment, logs, progress, failure messages.

Debian's OpenFOAM v1912 needs only ``WM_PROJECT_DIR=/usr/share/openfoam`` (its ``etc/bashrc``
cannot be sourced); every application's output goes to ``log.<app>`` in its case.
"""

from __future__ import annotations

import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from .errors import CfdError

DEFAULT_PROJECT_DIR = "/usr/share/openfoam"
REQUIRED_APPS = (
    "blockMesh",
    "surfaceFeatureExtract",
    "snappyHexMesh",
    "checkMesh",
    "simpleFoam",
    "pimpleFoam",
)
PARALLEL_APPS = ("decomposePar", "reconstructPar", "reconstructParMesh", "mpirun")

_TIME = re.compile(rb"^Time = ([-+0-9.eE]+)\s*$", re.M)
_COURANT = re.compile(rb"Courant Number mean: \S+ max: ([-+0-9.eE]+|nan|inf)")


def foam_env() -> dict[str, str]:
    """Process environment for OpenFOAM: ``WM_PROJECT_DIR`` set if missing, numbers in C locale."""
    env = dict(os.environ)
    env.setdefault("WM_PROJECT_DIR", DEFAULT_PROJECT_DIR)
    env["LC_ALL"] = "C"
    return env


def check_openfoam(parallel: bool = False) -> None:
    """Raise :class:`CfdError` naming what is missing if OpenFOAM cannot run here."""
    apps = REQUIRED_APPS + (PARALLEL_APPS if parallel else ())
    missing = [a for a in apps if shutil.which(a) is None]
    if missing:
        raise CfdError(
            "OpenFOAM check",
            f"not found on PATH: {', '.join(missing)} (install with: apt-get install openfoam)",
        )
    etc = Path(foam_env()["WM_PROJECT_DIR"]) / "etc" / "controlDict"
    if not etc.is_file():
        raise CfdError(
            "OpenFOAM check",
            f"{etc} is missing: set WM_PROJECT_DIR to the OpenFOAM installation "
            f"(Debian: {DEFAULT_PROJECT_DIR})",
        )


def mpi_available() -> bool:
    """True if MPI-parallel runs are possible (mpirun and the decomposition tools)."""
    return all(shutil.which(a) for a in PARALLEL_APPS)


def openfoam_available() -> bool:
    """True if the OpenFOAM applications used by the tool are installed."""
    try:
        check_openfoam()
    except CfdError:
        return False
    return True


class Progress:
    """Thread-safe progress lines on a stream: ``[elapsed] step: message``."""

    def __init__(self, stream=None, interval_s: float = 10.0, quiet: bool = False) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.interval_s = interval_s
        self.quiet = quiet
        self.t0 = time.monotonic()
        self._lock = threading.Lock()

    def __getstate__(self) -> dict:
        """Sent to a Ray task without stream and lock: there it writes to the task's stderr (Ray forwards it)."""
        return {k: v for k, v in self.__dict__.items() if k not in ("stream", "_lock")}

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state, stream=sys.stderr, _lock=threading.Lock())

    def __call__(self, step: str, message: str) -> None:
        if self.quiet:
            return
        with self._lock:
            print(f"[{time.monotonic() - self.t0:7.1f} s] {step}: {message}", file=self.stream, flush=True)


def _tail(path: Path, nbytes: int = 65536) -> bytes:
    try:
        with open(path, "rb") as fh:
            fh.seek(0, os.SEEK_END)
            size = fh.tell()
            fh.seek(max(0, size - nbytes))
            return fh.read()
    except OSError:
        return b""


def failure_reason(log: Path) -> str:
    """The most telling line of a failed OpenFOAM log (FATAL message, FPE, ...)."""
    text = _tail(log, 200_000).decode(errors="replace")
    lines = [line for line in text.splitlines() if line.strip()]
    for i, line in enumerate(lines):
        if "FOAM FATAL" in line:
            detail = [s.strip() for s in lines[i + 1 : i + 6] if s.strip()]
            return (line.strip().removeprefix("-->").strip() + ": " + " ".join(detail[:2]))[:300]
    for key in ("sigFpe::sigHandler", "Floating point exception", "Segmentation fault"):
        for line in reversed(lines):
            if key in line and "trapping" not in line:
                return f"floating point exception (the solution diverged): {line.strip()}"[:300]
    return (lines[-1].strip() if lines else "no output")[:300]


# Set by stop_all(): every running application's process group is terminated and no new one starts.
STOP = threading.Event()
TERMINATE_GRACE_S = 5.0  # s between SIGTERM and SIGKILL of an application's process group


class Stopped(CfdError):
    """An application was stopped because the study was interrupted (Ctrl-C or SIGTERM)."""


def stop_all() -> None:
    """Ask every running :func:`run_app` (in any thread) to terminate its application and return."""
    STOP.set()


def _terminate_group(proc: subprocess.Popen) -> None:
    """SIGTERM to the application's whole process group (mpirun and its ranks too), SIGKILL after a grace."""
    if proc.poll() is not None:
        return
    try:
        os.killpg(proc.pid, signal.SIGTERM)
        proc.wait(timeout=TERMINATE_GRACE_S)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


def run_app(
    argv: Sequence[str],
    case: Path,
    step: str,
    *,
    procs: int = 1,
    progress: Callable[[str, str], None] | None = None,
    end_time: float | None = None,
    max_courant: float = 50.0,
    log_name: str | None = None,
    on_tick: Callable[[], None] | None = None,
) -> Path:
    """Run one OpenFOAM application in ``case`` (MPI-parallel if ``procs`` > 1), logging to ``log.<app>``.

    ``on_tick`` is called every 2 s while the application runs (e.g. to stop a converged run).
    Progress (time/iteration, elapsed) is reported every ``progress.interval_s``. A transient run whose
    Courant number exceeds ``max_courant`` is stopped as diverged. Raises :class:`CfdError` naming
    ``step`` and the log file on any failure.
    """
    app = argv[0]
    log = case / (log_name or f"log.{app}")
    cmd = list(argv)
    if procs > 1:
        mpi = ["mpirun", "-np", str(procs), "--oversubscribe"]
        if hasattr(os, "geteuid") and os.geteuid() == 0:
            mpi.insert(1, "--allow-run-as-root")
        cmd = [*mpi, *cmd, "-parallel"]
    if STOP.is_set():
        raise Stopped(step, "not started: the study was interrupted")
    if shutil.which(cmd[0]) is None:
        raise CfdError(step, f"{cmd[0]} not found on PATH (install with: apt-get install openfoam)")
    t0 = time.monotonic()
    interval = getattr(progress, "interval_s", 10.0)
    last_report = last_tick = t0
    diverged = ""
    with open(log, "wb") as fh:
        # its own session and process group, so that stopping it reaches mpirun's ranks as well
        proc = subprocess.Popen(
            cmd, cwd=case, stdout=fh, stderr=subprocess.STDOUT, env=foam_env(), start_new_session=True
        )
        try:
            while proc.poll() is None:
                time.sleep(0.25)
                if STOP.is_set():
                    _terminate_group(proc)
                    raise Stopped(step, f"{app} stopped: the study was interrupted", log)
                now = time.monotonic()
                if on_tick is not None and now - last_tick >= 2.0:
                    last_tick = now
                    on_tick()
                if now - last_report < interval:
                    continue
                last_report = now
                tail = _tail(log)
                times = _TIME.findall(tail)
                co = _COURANT.findall(tail)
                if co:
                    c = float(co[-1]) if co[-1] not in (b"nan", b"inf") else float("inf")
                    if not c <= max_courant:
                        diverged = f"Courant number {c:.3g} > {max_courant:g}"
                        _terminate_group(proc)
                        break
                if progress is not None:
                    where = f"time {float(times[-1]):.6g}" if times else "running"
                    if times and end_time:
                        where += f"/{end_time:.6g} ({100.0 * float(times[-1]) / end_time:.0f} %)"
                    progress(step, f"{app} {where}, elapsed {now - t0:.0f} s")
        finally:
            _terminate_group(proc)
            rc = proc.wait()
    if diverged:
        raise CfdError(step, f"{app} diverged: {diverged}", log)
    if rc != 0:
        raise CfdError(step, f"{app} exited with code {rc}: {failure_reason(log)}", log)
    return log


# ---------------------------------------------------------------------------------- checkMesh / boundary
_BOUNDARY_ENTRY = re.compile(r"^\s*(\w+)\s*\{([^}]*)\}", re.M)


def read_boundary(case: Path) -> dict[str, dict[str, str]]:
    """Patches of ``constant/polyMesh/boundary``: name -> {"type", "nFaces", "startFace"}."""
    path = case / "constant" / "polyMesh" / "boundary"
    if not path.is_file():
        return {}
    text = path.read_text()
    body = text[text.find("(", text.find("}")) + 1 :] if "FoamFile" in text else text
    out = {}
    for name, inner in _BOUNDARY_ENTRY.findall(body):
        fields = dict(re.findall(r"(\w+)\s+([^;]+);", inner))
        out[name] = fields
    return out


# checkMesh "***" findings that make a mesh unusable; the others (skewness, non-orthogonality, aspect
# ratio, ...) are quality warnings that the solvers tolerate in small numbers
_FATAL_CHECK = re.compile(r"negative|zero|open|orient|pyramid|upper triangular|illegal|error", re.I)


def parse_check_mesh(log: Path) -> dict[str, object]:
    """Cell count, quality figures and verdict from a checkMesh log.

    ``ok``: checkMesh's own "Mesh OK."; ``fatal``: findings that make the mesh unusable (negative
    volumes, open cells, wrong orientation, ...); ``warnings``: the other "***" findings.
    """
    text = log.read_text(errors="replace")

    def num(pattern: str) -> float | None:
        m = re.search(pattern, text, re.M)
        return float(m.group(1)) if m else None

    failed = re.search(r"Failed (\d+) mesh checks", text)
    findings = [line.strip().lstrip("*") for line in text.splitlines() if line.strip().startswith("***")]
    return {
        "ok": "Mesh OK." in text,
        "failed_checks": int(failed.group(1)) if failed else 0,
        "fatal": [f for f in findings if _FATAL_CHECK.search(f)],
        "warnings": [f for f in findings if not _FATAL_CHECK.search(f)],
        "cells": int(num(r"^\s*cells:\s+(\d+)") or 0),
        "max_non_orthogonality": num(r"Mesh non-orthogonality Max: ([0-9.eE+-]+)"),
        "max_skewness": num(r"Max skewness = ([0-9.eE+-]+)"),
    }


_LAYER_ROW = re.compile(r"^(\S+)\s+(\d+)\s+([0-9.eE+-]+)\s+([0-9.eE+-]+)\s+([0-9.eE+-]+)\s*$")


def parse_layers(log: Path) -> dict[str, dict[str, float]]:
    """Per patch, the prism layers snappyHexMesh added (its last layer table): faces, mean number of layers,
    overall thickness (m) and that thickness as a percentage of the one asked for. Empty without layers."""
    try:
        text = log.read_text(errors="replace")
    except OSError:
        return {}
    start = text.rfind("overall thickness")
    if start < 0:
        return {}
    rows: dict[str, dict[str, float]] = {}
    for line in text[start:].splitlines()[3:]:
        m = _LAYER_ROW.match(line.strip())
        if not m:
            break
        name, faces, layers, thick, pct = m.groups()
        rows[name] = {
            "faces": int(faces),
            "layers": float(layers),
            "thickness_m": float(thick),
            "thickness_pct": float(pct),
        }
    return rows


_FACE = re.compile(r"(\d+)\(([^)]*)\)")


def _ascii_body(path: Path) -> str | None:
    """The text after the FoamFile header of an ASCII mesh file, or None (binary or unreadable)."""
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError):
        return None
    head_end = text.find("}", text.find("FoamFile")) + 1 if "FoamFile" in text else 0
    if re.search(r"format\s+binary", text[:head_end]):
        return None
    return text[head_end:]


def patch_area(case: Path, patch: dict[str, str]) -> float | None:
    """Area (m²) of one patch of an ASCII ``constant/polyMesh`` (``patch`` as from :func:`read_boundary`),
    summed over fan triangles of each face; None when the mesh is binary or unreadable."""
    poly = case / "constant" / "polyMesh"
    points, faces = _ascii_body(poly / "points"), _ascii_body(poly / "faces")
    try:
        start, n = int(patch["startFace"]), int(patch["nFaces"])
        m = re.search(r"(\d+)\s*\(", points or "")
        if m is None or faces is None:
            return None
        count = int(m.group(1))
        pts = np.array(
            points[m.end() :].replace("(", " ").replace(")", " ").split()[: 3 * count], dtype=float
        )
        pts = pts.reshape(count, 3)
        if "faceCompactList" in faces[:200] or re.match(r"\s*\d+\s*\(\s*\d+\s+\d", faces):
            lists = [b.split() for b in re.findall(r"\d+\s*\(([^)]*)\)", faces)]
            offsets, labels = np.array(lists[0], dtype=int), np.array(lists[1], dtype=int)
            polys = [labels[offsets[i] : offsets[i + 1]] for i in range(start, start + n)]
        else:
            opener = re.search(r"\d+\s*\(", faces)
            if opener is None:
                return None
            polys = []
            for i, fm in enumerate(_FACE.finditer(faces, opener.end())):
                if i >= start + n:
                    break
                if i >= start:
                    polys.append(np.array(fm.group(2).split(), dtype=int))
        if len(polys) != n:
            return None
        area = 0.0
        for f in polys:
            v = pts[f]
            area += 0.5 * float(np.linalg.norm(np.cross(v[1:-1] - v[0], v[2:] - v[0]), axis=1).sum())
        return area
    except (KeyError, ValueError, IndexError):
        return None
