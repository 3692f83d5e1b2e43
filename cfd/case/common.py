"""What every OpenFOAM case of a study shares: the hull patch, numerics, decomposition, forces output.

fvSchemes and fvSolution (steady SIMPLEC or transient PIMPLE), decomposeParDict, the forces and y+ function
objects, transport and turbulence properties, copying the finished mesh into a case, and asking a running
solver to stop.
"""

from __future__ import annotations

import os
import re
import shutil
import time
from pathlib import Path
from typing import Any

from .. import foamdict
from ..foamdict import Words

HULL_PATCH = "hull"


def decompose_dict(n: int) -> dict[str, Any]:
    # scotch/metis are stub libraries in Debian's v1912; hierarchical always works
    return {
        "numberOfSubdomains": n,
        "method": "hierarchical",
        "hierarchicalCoeffs": {"n": (n, 1, 1), "order": "xyz"},
        "coeffs": {"n": (n, 1, 1), "order": "xyz"},
    }


TIME_SCHEMES = ("backward", "Euler")


def write_schemes(system: Path, steady: bool, time_scheme: str = "backward") -> None:
    """fvSchemes: second order in space for U, k and ω (linearUpwind on a cell-limited gradient), and for
    transient cases ``time_scheme`` (``backward``: second-order, three time levels; ``Euler``: first order)."""
    if time_scheme not in TIME_SCHEMES:
        raise ValueError(f"time scheme must be one of {TIME_SCHEMES} (got {time_scheme!r})")
    # steady SIMPLE: 'bounded' removes the continuity error term (div(phi) != 0 until converged)
    bounded = "bounded " if steady else ""
    foamdict.write(
        system / "fvSchemes",
        {
            "ddtSchemes": {"default": "steadyState" if steady else time_scheme},
            "gradSchemes": {
                "default": "Gauss linear",
                "grad(U)": "cellLimited Gauss linear 1",
                # limited so the linearUpwind extrapolation of k and ω cannot make them negative
                "limitedGrad": "cellLimited Gauss linear 1",
            },
            "divSchemes": {
                "default": "none",
                "div(phi,U)": f"{bounded}Gauss linearUpwind grad(U)",
                "div(phi,k)": f"{bounded}Gauss linearUpwind limitedGrad",
                "div(phi,omega)": f"{bounded}Gauss linearUpwind limitedGrad",
                "div((nuEff*dev2(T(grad(U)))))": "Gauss linear",
            },
            "laplacianSchemes": {"default": "Gauss linear limited corrected 0.5"},
            "interpolationSchemes": {"default": "linear"},
            "snGradSchemes": {"default": "limited corrected 0.5"},
            "wallDist": {"method": "meshWave"},
        },
    )


def write_solution(system: Path, steady: bool, residual_p: float = 1e-5) -> None:
    solvers: dict[str, Any] = {
        "p": {"solver": "GAMG", "smoother": "GaussSeidel", "tolerance": 1e-7, "relTol": 0.05},
        "(U|k|omega)": {
            "solver": "smoothSolver",
            "smoother": "symGaussSeidel",
            "tolerance": 1e-8,
            "relTol": 0.1,
        },
    }
    if steady:
        algo = {
            "SIMPLE": {
                "nNonOrthogonalCorrectors": 0,
                "consistent": True,
                "residualControl": {"p": residual_p, "U": residual_p / 10, '"(k|omega)"': residual_p},
            }
        }
        # U 0.7, k and omega 0.5: with 0.9 / 0.7 the drift cases of the Wigley quick start (grading 1) fell
        # into a limit cycle of SIMPLE (a 24-iteration oscillation of N of 0.15 % about a value 0.4 % off
        # the steady one) and never converged in 500 iterations; with these they converge to constant forces
        # (residualControl) in 95-156 iterations (docs/cfd.md, "Convergence of the steady cases")
        relax = {"equations": {"U": 0.7, '".*"': 0.5}}
    else:
        solvers["(p|pcorr)Final"] = {
            "solver": "GAMG",
            "smoother": "GaussSeidel",
            "tolerance": 1e-7,
            "relTol": 0,
        }
        solvers["(U|k|omega)Final"] = {
            "solver": "smoothSolver",
            "smoother": "symGaussSeidel",
            "tolerance": 1e-8,
            "relTol": 0,
        }
        algo = {
            "PIMPLE": {
                "momentumPredictor": True,
                "nOuterCorrectors": 2,
                "nCorrectors": 2,
                "nNonOrthogonalCorrectors": 0,
                "correctPhi": False,
            }
        }
        relax = {"equations": {'".*"': 1}}
    quoted = {(f'"{k}"' if "|" in k else k): v for k, v in solvers.items()}
    foamdict.write(system / "fvSolution", {"solvers": quoted, **algo, "relaxationFactors": relax})


def function_objects(rho: float, write_yplus: bool) -> dict[str, Any]:
    fo: dict[str, Any] = {
        "forces": {
            "type": "forces",
            "libs": ['"libforces.so"'],
            "writeControl": "timeStep",
            "writeInterval": 1,
            "patches": [HULL_PATCH],
            "rho": "rhoInf",
            "rhoInf": rho,
            "CofR": (0, 0, 0),
            "log": False,
        }
    }
    if write_yplus:
        fo["yPlus"] = {"type": "yPlus", "libs": ['"libfieldFunctionObjects.so"'], "writeControl": "writeTime"}
    return fo


def write_constant(case: Path, nu: float) -> None:
    const = case / "constant"
    foamdict.write(
        const / "transportProperties", {"transportModel": "Newtonian", "nu": Words("[0 2 -1 0 0 0 0]", nu)}
    )
    foamdict.write(
        const / "turbulenceProperties",
        {"simulationType": "RAS", "RAS": {"RASModel": "kOmegaSST", "turbulence": True, "printCoeffs": True}},
    )


def symmetry_plane() -> dict[str, Any]:
    return {"type": "symmetryPlane"}


def link_mesh(case: Path, mesh_case: Path) -> None:
    """Copy the finished polyMesh into a case (cases must not share it: moving meshes write to it)."""
    dst = case / "constant" / "polyMesh"
    if dst.exists():
        shutil.rmtree(dst)
    shutil.copytree(mesh_case / "constant" / "polyMesh", dst)


# s: OpenFOAM's default ``fileModificationSkew`` (etc/controlDict). With runTimeModifiable and
# timeStamp checking, a solver re-reads a file only when its mtime is newer than the mtime it last
# read by more than this skew, so an edit made within 10 s of writing the case was never seen.
FILE_MODIFICATION_SKEW_S = 10.0


def make_stoppable(case: Path) -> None:
    """Backdate the case's controlDict so that request_stop()'s edit is newer by more than the skew."""
    path = case / "system" / "controlDict"
    old = time.time() - 6.0 * FILE_MODIFICATION_SKEW_S
    os.utime(path, (old, old))


def request_stop(case: Path) -> bool:
    """Ask a running solver to write its fields and stop (``stopAt writeNow``); False if already asked.

    The case must have been written with make_stoppable(), or the solver may not notice the edit.
    """
    path = case / "system" / "controlDict"
    text = path.read_text()
    new = re.sub(r"^(stopAt\s+)endTime;", r"\1writeNow;", text, count=1, flags=re.M)
    if new == text:
        return False
    path.write_text(new)
    now = time.time()
    os.utime(path, (now, now))
    return True
