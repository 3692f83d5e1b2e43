"""The free-surface (VOF) straight tow: an interFoam case with local time stepping, in the set-up of the
DTCHull tutorial of OpenFOAM, on a half domain (the tow is symmetric about the centreplane).

The hull is fixed at its design draught and trim (no sinkage or trim), the water flows past it at −U, and
air fills the domain up to 0.5 Lpp above the waterline. The mesh follows the double-body mesh of
:mod:`cfd.case.sizing` (background cells, Table-2 boxes, wake cylinder, hull level, prism layers) with the
boxes mirrored above the waterline and two bands refining the free surface over the Kelvin wedge.

The forces function object integrates the hull patch of the half domain; :func:`resistance_from_half`
doubles it. The STL must be closed and reach above the waterline (a deck, or topsides cut by the domain
top); a knife edge at the waterline, as on a double body, leaves slivers of air cells at the hull.
"""

from __future__ import annotations

import dataclasses
import math
import shutil
from pathlib import Path
from typing import Any

from .. import foamdict
from ..foamdict import Named, Words
from .common import HULL_PATCH, decompose_dict, link_mesh, write_solution
from .flow import FlowSpec
from .mesh import MESH_QUALITY, SURFACE_FEATURES, _snappy, block_mesh_dict
from .sizing import Box, MeshSpec

AIR_HEIGHT = 0.5  # Lpp of air above the waterline (the DTCHull tutorial: about 0.7 Lpp)
# Free-surface bands: the Kelvin wedge (half angle 19.47 deg) from the bow reaches |y| = 1.06 L at the
# outlet 3 L behind it, so the bands span y >= -KELVIN_WIDTH L. The bow wave rises about U^2 / 2g, which is
# 0.024 L for the DTC at Fn 0.218 (0.14 m at 1.668 m/s): the inner band (hull level - 1) covers +-0.03 L,
# the outer one (hull level - 2) +-0.06 L.
KELVIN_WIDTH = 1.1
BAND_INNER = 0.03
BAND_OUTER = 0.06
AHEAD_OF_BOW = 0.5  # Lpp of free-surface refinement ahead of the bow
AIR = {"nu": 1.48e-5, "rho": 1.0}  # air at 15 deg C (m2/s, kg/m3), as in the DTCHull tutorial
G = 9.81  # m/s2
# A stopped run continues from its last written iteration (startFrom latestTime), so the cases write every
# RESTART_EVERY iterations (every quarter of a shorter run), keeping only the latest: a run stopped at the
# end of a 150-minute slot loses at most that many (about 4 min of grid 1 of the DTC's grid study on 2
# processors, and an estimated 12 min of grid 2).
RESTART_EVERY = 250


def free_surface_spec(spec: MeshSpec, half: bool = True) -> MeshSpec:
    """The double-body mesh spec turned into the VOF one: half domain (y <= 0), air above the waterline,
    the refinement boxes mirrored above it, and the free-surface bands."""
    L, h0 = spec.L, spec.h0
    n_up = max(1, math.ceil(round(AIR_HEIGHT * L / h0, 9)))
    n_half = max(1, math.ceil(round(-spec.lo[1] / h0, 9)))
    lo = (spec.lo[0], -n_half * h0, spec.lo[2])
    hi = (spec.hi[0], 0.0 if half else n_half * h0, n_up * h0)
    boxes = [dataclasses.replace(b, hi=(b.hi[0], b.hi[1], -b.lo[2])) for b in spec.boxes]
    x_band = (lo[0], min(hi[0], (0.5 + AHEAD_OF_BOW) * L))
    for name, height, level in (
        ("freeSurfaceOuter", BAND_OUTER, spec.hull_level - 2),
        ("freeSurfaceInner", BAND_INNER, spec.hull_level - 1),
    ):
        if level >= 1:
            boxes.append(
                Box(name, (x_band[0], -KELVIN_WIDTH * L, -height * L), (x_band[1], h0, height * L), level)
            )
    location = (
        lo[0] + 0.71234 * (hi[0] - lo[0]) + 0.0123 * h0,
        lo[1] + 0.08234 * (hi[1] - lo[1]) + 0.0123 * h0,
        lo[2] + 0.31234 * (0.0 - lo[2]) - 0.0123 * h0,
    )
    wakes = tuple(w for w in spec.wakes if w.beta_deg == 0.0)
    cells = (spec.cells[0], n_half * (1 if half else 2), spec.cells[2] + n_up)
    return dataclasses.replace(
        spec, lo=lo, hi=hi, cells=cells, boxes=tuple(boxes), location=location, wakes=wakes
    )


def resistance_from_half(fx_half_N: float) -> float:
    """Total resistance (N) of the whole hull from the x force on the half hull of the half domain."""
    return -2.0 * fx_half_N


def _block_mesh(fs: MeshSpec) -> dict[str, Any]:
    bm = block_mesh_dict(fs)
    bm["boundary"] = [
        Named("inlet", {"type": "patch", "faces": [(1, 2, 6, 5)]}),  # ahead of the bow (+x)
        Named("outlet", {"type": "patch", "faces": [(0, 4, 7, 3)]}),
        Named("side", {"type": "symmetryPlane", "faces": [(0, 1, 5, 4)]}),
        Named("midPlane", {"type": "symmetryPlane", "faces": [(3, 7, 6, 2)]}),  # the centreplane y = 0
        Named("bottom", {"type": "symmetryPlane", "faces": [(0, 3, 2, 1)]}),
        Named("atmosphere", {"type": "patch", "faces": [(4, 5, 6, 7)]}),
    ]
    return bm


def write_free_surface_mesh(case: Path, fs: MeshSpec, stl: Path, procs: int = 1) -> None:
    """blockMesh, surfaceFeatureExtract and snappyHexMesh dictionaries of the VOF mesh (spec from
    :func:`free_surface_spec`)."""
    system, tri = case / "system", case / "constant" / "triSurface"
    tri.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(stl, tri / "hull.stl")
    foamdict.write(system / "blockMeshDict", _block_mesh(fs))
    foamdict.write(system / "surfaceFeatureExtractDict", SURFACE_FEATURES)
    snappy = _snappy(fs)
    # Castellated hull: every snapped hull mesh we tried (feature snapping on or off, tighter tolerances,
    # prism layers) blew up within 10-30 interFoam iterations in v1912 (also single-phase, also without
    # gravity, also with Euler at Co 0.2), while pimpleFoam ran on the same snapped mesh and interFoam on the
    # castellated one: the stair-stepped surface is what runs here. The DTCHull tutorial's own snapped,
    # layered mesh blows up the same way on this build, and so do prism layers on the castellated hull
    # (cfd/studies/dtc_snapped_probe/). It adds roughness-like drag that shrinks with the cell size;
    # docs/cfd.md says so next to every free-surface number.
    snappy["snap"] = False
    snappy["addLayers"] = False
    foamdict.write(system / "snappyHexMeshDict", snappy)
    foamdict.write(system / "meshQualityDict", MESH_QUALITY)
    foamdict.write(system / "decomposeParDict", decompose_dict(procs))
    _schemes(system)
    write_solution(system, steady=True)  # snappyHexMesh reads fvSolution; the solver's is written later


def _schemes(system: Path) -> None:
    # the DTCHull tutorial's schemes: LTS pseudo-time, vanLeer + interface compression for alpha
    foamdict.write(
        system / "fvSchemes",
        {
            "ddtSchemes": {"default": "localEuler"},
            "gradSchemes": {"default": "Gauss linear", "limitedGrad": "cellLimited Gauss linear 1"},
            "divSchemes": {
                "div(rhoPhi,U)": "Gauss linearUpwind grad(U)",
                "div(U)": "Gauss linear",
                "div(phi,alpha)": "Gauss vanLeer",
                "div(phirb,alpha)": "Gauss linear",
                "div(phi,k)": "Gauss linearUpwind limitedGrad",
                "div(phi,omega)": "Gauss linearUpwind limitedGrad",
                "div(((rho*nuEff)*dev2(T(grad(U)))))": "Gauss linear",
            },
            "laplacianSchemes": {"default": "Gauss linear limited corrected 0.5"},
            "interpolationSchemes": {"default": "linear"},
            "snGradSchemes": {"default": "limited corrected 0.5"},
            "wallDist": {"method": "meshWave"},
        },
    )


def _solution(system: Path) -> None:
    foamdict.write(
        system / "fvSolution",
        {
            "solvers": {
                '"alpha.water.*"': {
                    "nAlphaCorr": 1,
                    "nAlphaSubCycles": 1,
                    "cAlpha": 1,
                    "MULESCorr": True,
                    "nLimiterIter": 5,
                    "solver": "smoothSolver",
                    "smoother": "symGaussSeidel",
                    "tolerance": 1e-8,
                    "relTol": 0,
                },
                '"pcorr.*"': {"solver": "GAMG", "smoother": "DIC", "tolerance": 1e-5, "relTol": 0},
                '"p_rgh.*"': {"solver": "GAMG", "smoother": "DIC", "tolerance": 1e-7, "relTol": 0.01},
                '"(U|k|omega).*"': {
                    "solver": "smoothSolver",
                    "smoother": "symGaussSeidel",
                    "nSweeps": 1,
                    "tolerance": 1e-7,
                    "relTol": 0.1,
                },
            },
            "PIMPLE": {
                "momentumPredictor": False,
                "nOuterCorrectors": 1,
                "nCorrectors": 2,
                "nNonOrthogonalCorrectors": 0,
                # local time step: Courant 10 in the flow, 5 at the interface, smoothed and damped in time
                "maxCo": 10,
                "maxAlphaCo": 5,
                "rDeltaTSmoothingCoeff": 0.05,
                "rDeltaTDampingCoeff": 0.5,
                "nAlphaSpreadIter": 0,
                "nAlphaSweepIter": 0,
                "maxDeltaT": 1,
            },
            "relaxationFactors": {"equations": {'".*"': 1}},
        },
    )


def _fields(flow: FlowSpec) -> dict[str, tuple[str, Any, str, dict[str, Any]]]:
    """0.orig fields, with the DTCHull tutorial's boundary conditions: the outflow keeps the inflow's mean
    water velocity (outletPhaseMeanVelocity) and lets the water level follow (variableHeightFlowRate); the
    atmosphere is open at zero total pressure."""
    U = (-flow.U, 0.0, 0.0)
    k, w = flow.k, flow.omega
    in_out = {"type": "inletOutlet", "inletValue": Words("uniform", 0), "value": Words("uniform", 0)}

    def turb(v: float, wall: str) -> dict[str, Any]:
        io = {"type": "inletOutlet", "inletValue": Words("uniform", v), "value": Words("uniform", v)}
        return {
            "inlet": {"type": "fixedValue", "value": Words("uniform", v)},
            "outlet": io,
            "atmosphere": io,
            HULL_PATCH: {"type": wall, "value": Words("uniform", v)},
        }

    return {
        # the inlet's water below z = 0 is set by setFields (boxToFace)
        "alpha.water": (
            "[0 0 0 0 0 0 0]",
            0,
            "volScalarField",
            {
                "inlet": {"type": "fixedValue", "value": Words("uniform", 0)},
                "outlet": {"type": "variableHeightFlowRate", "lowerBound": 0, "upperBound": 1},
                "atmosphere": in_out,
                HULL_PATCH: {"type": "zeroGradient"},
            },
        ),
        "U": (
            "[0 1 -1 0 0 0 0]",
            U,
            "volVectorField",
            {
                "inlet": {"type": "fixedValue", "value": Words("uniform", U)},
                "outlet": {
                    "type": "outletPhaseMeanVelocity",
                    "Umean": flow.U,
                    "alpha": "alpha.water",
                    "value": Words("uniform", U),
                },
                "atmosphere": {"type": "pressureInletOutletVelocity", "value": Words("uniform", (0, 0, 0))},
                HULL_PATCH: {"type": "noSlip"},
            },
        ),
        "p_rgh": (
            "[1 -1 -2 0 0 0 0]",
            0,
            "volScalarField",
            {
                "inlet": {"type": "fixedFluxPressure", "value": Words("uniform", 0)},
                "outlet": {"type": "zeroGradient"},
                "atmosphere": {"type": "totalPressure", "p0": Words("uniform", 0)},
                HULL_PATCH: {"type": "fixedFluxPressure", "value": Words("uniform", 0)},
            },
        ),
        "k": ("[0 2 -2 0 0 0 0]", k, "volScalarField", turb(k, "kqRWallFunction")),
        "omega": ("[0 0 -1 0 0 0 0]", w, "volScalarField", turb(w, "omegaWallFunction")),
        "nut": (
            "[0 2 -1 0 0 0 0]",
            0,
            "volScalarField",
            {
                "inlet": {"type": "fixedValue", "value": Words("uniform", 0)},
                "outlet": {"type": "zeroGradient"},
                "atmosphere": {"type": "zeroGradient"},
                HULL_PATCH: {"type": "nutUSpaldingWallFunction", "value": Words("uniform", 0)},
            },
        ),
    }


def write_free_surface_case(
    case: Path,
    spec: MeshSpec,
    stl: Path,
    flow: FlowSpec,
    iterations: int,
    procs: int = 1,
    mesh_case: Path | None = None,
) -> MeshSpec:
    """Write a VOF interFoam straight tow at ``flow.U`` for ``iterations`` LTS iterations.

    ``spec`` is the double-body spec (:func:`~cfd.case.sizing.mesh_spec`); the VOF one is derived from it
    and returned. With ``mesh_case`` (a finished VOF mesh) its polyMesh is copied in; otherwise the case
    holds the meshing dictionaries too and its ``Allrun`` meshes first. ``0.orig`` holds the initial fields;
    ``Allrun`` copies it to ``0`` and runs setFields (water below z = 0) before interFoam, on ``procs``
    MPI processes when ``procs`` > 1; run again, it resumes from the last time written.
    """
    fs = free_surface_spec(spec)
    case.mkdir(parents=True, exist_ok=True)
    if mesh_case is None:
        write_free_surface_mesh(case, fs, stl, procs)
    else:
        link_mesh(case, mesh_case)
    system, const = case / "system", case / "constant"
    foamdict.write(
        system / "controlDict",
        {
            "application": "interFoam",
            "startFrom": "latestTime",
            "startTime": 0,
            "stopAt": "endTime",
            "endTime": iterations,
            "deltaT": 1,
            "writeControl": "timeStep",
            "writeInterval": max(1, min(iterations // 4, RESTART_EVERY)),
            "purgeWrite": 1,
            "writeFormat": "binary",
            "writePrecision": 10,
            "writeCompression": False,
            "timeFormat": "general",
            "runTimeModifiable": True,
            "functions": {
                "forces": {
                    "type": "forces",
                    "libs": ['"libforces.so"'],
                    "writeControl": "timeStep",
                    "writeInterval": 1,
                    "patches": [HULL_PATCH],
                    "rho": "rho",  # interFoam's p is in Pa: integrate it as it is, with the two-phase rho field
                    "CofR": (0, 0, 0),
                    "log": False,
                }
            },
        },
    )
    foamdict.write(
        system / "setFieldsDict",
        {
            "defaultFieldValues": [Words("volScalarFieldValue", "alpha.water", 0)],
            "regions": [
                Named(
                    shape,
                    {
                        "box": Words((-1e9, -1e9, -1e9), (1e9, 1e9, 0)),
                        "fieldValues": [Words("volScalarFieldValue", "alpha.water", 1)],
                    },
                )
                for shape in ("boxToCell", "boxToFace")  # the cells and the inlet faces below z = 0
            ],
        },
    )
    _schemes(system)
    _solution(system)
    foamdict.write(system / "decomposeParDict", decompose_dict(procs))
    foamdict.write(
        const / "g",
        {"dimensions": "[0 1 -2 0 0 0 0]", "value": (0, 0, -G)},
        foam_class="uniformDimensionedVectorField",
    )
    # p_rgh = p - rho g (h - hRef): hRef at the undisturbed waterline z = 0 makes p_rgh = 0 at the surface
    foamdict.write(
        const / "hRef",
        {"dimensions": "[0 1 0 0 0 0 0]", "value": 0},
        foam_class="uniformDimensionedScalarField",
    )
    foamdict.write(
        const / "transportProperties",
        {
            "phases": ["water", "air"],
            "water": {"transportModel": "Newtonian", "nu": flow.nu, "rho": flow.rho},
            "air": {"transportModel": "Newtonian", **AIR},
            "sigma": 0,  # surface tension is negligible at model scale for resistance
        },
    )
    foamdict.write(
        const / "turbulenceProperties",
        {"simulationType": "RAS", "RAS": {"RASModel": "kOmegaSST", "turbulence": True, "printCoeffs": True}},
    )
    sym = {p: {"type": "symmetryPlane"} for p in ("side", "midPlane", "bottom")}
    for name, (dims, internal, cls, bnd) in _fields(flow).items():
        foamdict.write(
            case / "0.orig" / name,
            {
                "dimensions": dims,
                "internalField": Words("uniform", internal),
                "boundaryField": {**bnd, **sym},
            },
            foam_class=cls,
        )
    mesh_steps = (
        "blockMesh > log.blockMesh\nsurfaceFeatureExtract > log.surfaceFeatureExtract\n"
        "snappyHexMesh -overwrite > log.snappyHexMesh\ncheckMesh > log.checkMesh\n"
        if mesh_case is None
        else ""
    )
    # controlDict starts from the latest time, so running Allrun again resumes a stopped tow: a serial one
    # from its last write, a parallel one from its processor folders (or, once reconstructed, from the
    # reconstructed last time, decomposed again). setFields only ever rewrites 0. The log of an earlier part
    # is kept under a number, so that the CPU time of every part is counted (cfd.tank.solver_cpu_s).
    water = "rm -rf 0 && cp -r 0.orig 0\nsetFields > log.setFields\n"
    keep_log = (
        "if [ -f log.interFoam ]; then\n    n=1\n    while [ -f log.interFoam.$n ]; do n=$((n + 1)); done\n"
        "    mv log.interFoam log.interFoam.$n\nfi\n"
    )
    if procs > 1:
        solve = (
            "if [ ! -d processor0 ]; then\n"
            + "".join("    " + line + "\n" for line in water.splitlines())
            + "    decomposePar -force > log.decomposePar\nfi\n"
            + 'ROOT=""\nif [ "$(id -u)" = 0 ]; then ROOT=--allow-run-as-root; fi\n'
            + f"mpirun -np {procs} $ROOT --oversubscribe interFoam -parallel > log.interFoam\n"
            + "reconstructPar -latestTime > log.reconstructPar\nrm -rf processor*\n"
        )
    else:
        solve = water + "interFoam > log.interFoam\n"
    (case / "Allrun").write_text(
        "#!/bin/sh\n# VOF straight tow written by vessel-cfd (docs/cfd.md, section Free surface).\n"
        'set -e\ncd "$(dirname "$0")"\nexport WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam}\n'
        + mesh_steps
        + keep_log
        + solve
    )
    (case / "Allrun").chmod(0o755)
    return fs
