"""Planar-motion-mechanism cases: the prescribed sway/yaw motion and its moving-mesh pimpleFoam case."""

from __future__ import annotations

import math
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import foamdict
from .common import (
    decompose_dict,
    function_objects,
    link_mesh,
    write_constant,
    write_schemes,
    write_solution,
)
from .flow import FlowSpec


def ramp(t: np.ndarray, t_ramp: float) -> np.ndarray:
    """Half-cosine start ramp from 0 to 1 over ``t_ramp`` seconds."""
    s = np.clip(np.asarray(t, dtype=float) / t_ramp, 0.0, 1.0) if t_ramp > 0 else np.ones_like(t)
    return 0.5 * (1.0 - np.cos(np.pi * s))


@dataclass(frozen=True)
class Motion:
    """Planar PMM motion of the hull in the carriage frame (case-frame axes: y to port, yaw CCW).

    y(t) = y0·ramp(t)·sin(ωt). Pure sway: ψ = 0. Pure yaw: ψ = atan(ẏ/U), so the hull stays tangent
    to its path and v = 0 in body axes.
    """

    kind: str  # "sway" or "yaw"
    y0: float  # lateral amplitude (m)
    omega: float  # rad/s
    U: float
    t_ramp: float

    def y(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return self.y0 * ramp(t, self.t_ramp) * np.sin(self.omega * t)

    def y_dot(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        s = ramp(t, self.t_ramp)
        if self.t_ramp > 0:
            ds = np.where(
                t < self.t_ramp,
                0.5 * np.pi / self.t_ramp * np.sin(np.pi * np.clip(t / self.t_ramp, 0, 1)),
                0.0,
            )
        else:
            ds = np.zeros_like(t)
        return self.y0 * (ds * np.sin(self.omega * t) + s * self.omega * np.cos(self.omega * t))

    def psi(self, t: np.ndarray) -> np.ndarray:
        if self.kind == "sway":
            return np.zeros_like(np.asarray(t, dtype=float))
        return np.arctan2(self.y_dot(t), self.U)


def motion_table(motion: Motion, t_end: float, dt: float) -> str:
    """``tabulated6DoFMotion`` table: one entry per time step, extended past ``t_end``
    (the solver stops with an error once time passes the last entry)."""
    n = int(math.ceil((1.05 * t_end + 0.1) / dt)) + 2
    t = np.arange(n) * dt
    y, psi = motion.y(t), np.degrees(motion.psi(t))
    rows = [f"({ti:.10g} ((0 {yi:.12g} 0) (0 0 {pi:.12g})))" for ti, yi, pi in zip(t, y, psi, strict=True)]
    return f"{n}\n(\n" + "\n".join(rows) + "\n)\n"


def write_pmm_case(
    case: Path,
    mesh_case: Path,
    start_dir: Path,
    flow: FlowSpec,
    motion: Motion,
    t_end: float,
    dt: float,
    procs: int = 1,
    time_scheme: str = "backward",
) -> None:
    """pimpleFoam case with a rigidly moving mesh (solidBody, tabulated6DoFMotion), started from the
    converged straight-tow fields in ``start_dir`` (a time directory of the tow case); ``time_scheme`` is
    the ddt scheme (``backward``, second order, or ``Euler``)."""
    case.mkdir(parents=True, exist_ok=True)
    link_mesh(case, mesh_case)
    write_constant(case, flow.nu)
    zero = case / "0"
    if zero.exists():
        shutil.rmtree(zero)
    zero.mkdir()
    for name in ("U", "p", "k", "omega", "nut"):
        shutil.copyfile(start_dir / name, zero / name)
    const = case / "constant"
    (const / "6DoF.dat").write_text(motion_table(motion, t_end, dt))
    foamdict.write(
        const / "dynamicMeshDict",
        {
            "dynamicFvMesh": "dynamicMotionSolverFvMesh",
            "motionSolverLibs": ['"libfvMotionSolvers.so"'],
            "motionSolver": "solidBody",
            "solidBodyMotionFunction": "tabulated6DoFMotion",
            "tabulated6DoFMotionCoeffs": {"CofG": (0, 0, 0), "timeDataFileName": '"<constant>/6DoF.dat"'},
        },
    )
    system = case / "system"
    n_steps = int(round(t_end / dt))
    foamdict.write(
        system / "controlDict",
        {
            "application": "pimpleFoam",
            "startFrom": "startTime",
            "startTime": 0,
            "stopAt": "endTime",
            "endTime": n_steps * dt,
            "deltaT": dt,
            "writeControl": "timeStep",
            "writeInterval": n_steps,
            "purgeWrite": 1,
            "writeFormat": "binary",
            "writePrecision": 10,
            "writeCompression": False,
            "timeFormat": "general",
            "timePrecision": 10,
            "runTimeModifiable": False,
            "adjustTimeStep": False,
            "functions": function_objects(flow.rho, write_yplus=True),
        },
    )
    write_schemes(system, steady=False, time_scheme=time_scheme)
    write_solution(system, steady=False)
    foamdict.write(system / "decomposeParDict", decompose_dict(procs))
