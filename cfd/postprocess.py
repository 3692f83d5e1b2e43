"""Read OpenFOAM force output and convert it to standard body axes.

OpenFOAM's ``forces`` function object reports, per iteration or time step, the force and moment
on the hull in the case frame (x forward, y to port, z up) about the fixed point ``CofR = (0 0 0)``.
The standard ship axes are x forward, y starboard, z down, so

    X = Fx,  Y = −Fy,  N = −Mz,  v = −v_case,  r = −r_case,  ψ = −ψ_case.

For a moving hull the moment is first taken about the hull's current origin (0, y, 0):
Mz' = Mz + y·Fx, and forces are rotated by −ψ_case into hull axes.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .errors import CfdError

_NUM = r"[-+0-9.eE]+|nan|-?inf"
_ROW = re.compile(rf"^\s*({_NUM})\s+\(\s*({_NUM})\s+({_NUM})\s+({_NUM})\s*\)")


@dataclass(frozen=True)
class ForceHistory:
    """Total force (N) and moment (N·m) in the case frame about the origin, per time/iteration."""

    t: np.ndarray
    F: np.ndarray  # (n, 3)
    M: np.ndarray  # (n, 3)


def _read_table(path: Path) -> tuple[np.ndarray, np.ndarray]:
    t, v = [], []
    for line in path.read_text().splitlines():
        if line.startswith("#"):
            continue
        m = _ROW.match(line)
        if m:
            t.append(float(m.group(1)))
            v.append([float(m.group(i)) for i in (2, 3, 4)])
    return np.array(t), np.array(v).reshape(-1, 3)


def read_forces(case: Path) -> ForceHistory:
    """Forces and moments written by the ``forces`` function object of a case.

    Several start-time folders or ``force_0.dat`` files (restarts) are merged; a later file wins
    where times overlap.
    """
    root = case / "postProcessing" / "forces"
    force_files = sorted(root.glob("*/force*.dat"), key=lambda p: (float(p.parent.name), p.name))
    if not force_files:
        raise CfdError(f"forces ({case.name})", f"no force output in {root}", case)
    ts, Fs, Ms = [], [], []
    for ff in force_files:
        mf = ff.with_name(ff.name.replace("force", "moment"))
        t, F = _read_table(ff)
        tm, M = _read_table(mf) if mf.exists() else (t, np.full_like(F, np.nan))
        n = min(len(t), len(tm))
        ts.append(t[:n])
        Fs.append(F[:n])
        Ms.append(M[:n])
    t = np.concatenate(ts)
    F, M = np.concatenate(Fs), np.concatenate(Ms)
    # keep the last occurrence of each time
    _, idx = np.unique(t[::-1], return_index=True)
    keep = np.sort(len(t) - 1 - idx)
    return ForceHistory(t[keep], F[keep], M[keep])


@dataclass(frozen=True)
class SteadyForces:
    """Converged steady forces in standard body axes, and how steady they were."""

    X: float
    Y: float
    N: float
    iterations: int
    band: dict  # (max − min) over the averaging window, per force
    K: float = 0.0  # roll moment Mx about the case origin's x-axis (the still waterline), N·m (cfd.heel)
    Fy: float = 0.0  # case-frame side force (= −Y), for moving K to another axis height


def steady_forces(history: ForceHistory, window: float = 0.1) -> SteadyForces:
    """Mean over the last ``window`` fraction of iterations (at least 1), in standard axes.

    Non-finite values come through as NaN; the caller reports them with the case's name and log."""
    n = len(history.t)
    if n == 0:
        raise CfdError("forces", "empty force history (the solver wrote no iteration)")
    k = max(1, int(math.ceil(window * n)))
    X = history.F[-k:, 0]
    Y = -history.F[-k:, 1]
    N = -history.M[-k:, 2]
    return SteadyForces(
        float(X.mean()),
        float(Y.mean()),
        float(N.mean()),
        int(history.t[-1]),
        {"X": float(np.ptp(X)), "Y": float(np.ptp(Y)), "N": float(np.ptp(N))},
        float(history.M[-k:, 0].mean()),
        float(history.F[-k:, 1].mean()),
    )


def body_forces(history: ForceHistory, y_case: np.ndarray, psi_case: np.ndarray) -> tuple[np.ndarray, ...]:
    """X, Y, N (standard body axes, about the moving hull origin) of a moving-mesh run.

    ``y_case`` and ``psi_case`` are the hull's lateral position (m, to port) and heading (rad, CCW)
    in the case frame at the times of ``history``.
    """
    Fx, Fy = history.F[:, 0], history.F[:, 1]
    Mz = history.M[:, 2] + y_case * Fx
    c, s = np.cos(psi_case), np.sin(psi_case)
    Fxb = c * Fx + s * Fy
    Fyb = -s * Fx + c * Fy
    return Fxb, -Fyb, -Mz


def forces_settled(
    history: ForceHistory, L: float, *, tol: float = 2e-3, window: int = 50, min_iterations: int = 100
) -> bool:
    """True when X, Y and N have stayed within a band over the last ``window`` iterations.

    Band limits: tol·F for X and Y, tol·0.1·L·F for N, where F = max(|X|, |Y|) averaged over the
    window. Used to stop steady runs whose residuals stall above residualControl while the
    forces no longer change.
    """
    n = len(history.t)
    if n < max(min_iterations, window):
        return False
    F = history.F[-window:]
    M = history.M[-window:]
    if not (np.all(np.isfinite(F)) and np.all(np.isfinite(M))):
        return False
    scale = max(abs(F[:, 0].mean()), abs(F[:, 1].mean()))
    if scale == 0.0:
        return False
    return bool(
        np.ptp(F[:, 0]) <= tol * scale
        and np.ptp(F[:, 1]) <= tol * scale
        and np.ptp(M[:, 2]) <= tol * 0.1 * L * scale
    )


def read_yplus(case: Path, patch: str = "hull") -> tuple[float, float, float] | None:
    """(min, max, mean) y+ on ``patch`` at the last time the ``yPlus`` function object wrote, or None."""
    files = sorted((case / "postProcessing" / "yPlus").glob("*/yPlus.dat"))
    if not files:
        return None
    rows = [r.split() for r in files[-1].read_text().splitlines() if r and not r.startswith("#")]
    rows = [r for r in rows if len(r) >= 5 and r[1] == patch]
    if not rows:
        return None
    try:
        lo, hi, mean = (float(x) for x in rows[-1][2:5])
    except ValueError:
        return None
    return lo, hi, mean


def end_time(case: Path) -> float | None:
    """The endTime a case was written for (its controlDict's: iterations of a steady or LTS solver, seconds
    of a transient one); None if unreadable."""
    control = case / "system" / "controlDict"
    m = re.search(r"^endTime\s+([-+\d.eE]+);", control.read_text(), re.M) if control.is_file() else None
    try:
        return float(m.group(1)) if m else None
    except ValueError:
        return None


def has_run_to_end(forces: ForceHistory, end: float | None) -> bool:
    """The one rule for a finished run: its forces reach the endTime it was written for (within a millionth,
    the rounding of a transient run's written times). A mean over a running case's last window is no
    result, and a queue that ran a finished case again would redo its work."""
    return end is not None and float(forces.t[-1]) >= end - 1e-6 * max(1.0, abs(end))
