"""A VOF interFoam straight-tow case with a free surface, written for users to run (never run by the tool)."""

from __future__ import annotations

import math
from pathlib import Path

from .. import foamdict
from ..foamdict import Named, Words
from .common import HULL_PATCH, function_objects, symmetry_plane
from .flow import FlowSpec
from .mesh import block_mesh_dict, write_mesh_case
from .sizing import Box, MeshSpec


def write_free_surface_case(case: Path, spec: MeshSpec, stl: Path, flow: FlowSpec, iterations: int) -> None:
    """Generate (not run) a VOF interFoam straight-tow case in the style of the DTCHull tutorial.

    The domain extends 0.5 Lpp above the waterline with an ``atmosphere`` patch; water below z = 0
    via setFields; local time stepping (LTS). This case is written for users to run and tune; the
    tool never runs it and its results are not validated (see docs/cfd.md).
    """
    L = spec.L
    top = 0.5 * L
    n_up = max(1, math.ceil(top / spec.h0))
    lo, hi = spec.lo, (spec.hi[0], spec.hi[1], n_up * spec.h0)
    fs = MeshSpec(
        spec.L,
        spec.B,
        spec.T,
        spec.grading,
        spec.h0,
        lo,
        hi,
        (spec.cells[0], spec.cells[1], spec.cells[2] + n_up),
        spec.hull_level,
        spec.boxes
        + (
            Box(
                "freeSurface",
                (lo[0], lo[1], -0.25 * spec.T),
                (hi[0], hi[1], 0.25 * spec.T),
                max(1, spec.hull_level - 2),
            ),
        ),
        (spec.location[0], spec.location[1], spec.location[2]),
    )
    write_mesh_case(case, fs, stl)
    bm = block_mesh_dict(fs)
    bm["boundary"] = [
        Named("inlet", {"type": "patch", "faces": [(1, 2, 6, 5)]}),
        Named("outlet", {"type": "patch", "faces": [(0, 4, 7, 3)]}),
        Named("sides", {"type": "symmetry", "faces": [(0, 1, 5, 4), (3, 7, 6, 2)]}),
        Named("bottom", {"type": "symmetryPlane", "faces": [(0, 3, 2, 1)]}),
        Named("atmosphere", {"type": "patch", "faces": [(4, 5, 6, 7)]}),
    ]
    system, const = case / "system", case / "constant"
    foamdict.write(system / "blockMeshDict", bm)
    U = (-flow.U, 0.0, 0.0)
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
            "writeInterval": 100,
            "purgeWrite": 2,
            "writeFormat": "binary",
            "writePrecision": 10,
            "timeFormat": "general",
            "runTimeModifiable": True,
            "functions": function_objects(flow.rho, write_yplus=False),
        },
    )
    foamdict.write(
        system / "setFieldsDict",
        {
            "defaultFieldValues": [Words("volScalarFieldValue", "alpha.water", 0)],
            "regions": [
                Named(
                    "boxToCell",
                    {
                        "box": Words((-1e9, -1e9, -1e9), (1e9, 1e9, 0)),
                        "fieldValues": [Words("volScalarFieldValue", "alpha.water", 1)],
                    },
                )
            ],
        },
    )
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
                "momentumPredictor": True,
                "nOuterCorrectors": 1,
                "nCorrectors": 2,
                "nNonOrthogonalCorrectors": 0,
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
    foamdict.write(
        const / "g",
        {"dimensions": "[0 1 -2 0 0 0 0]", "value": (0, 0, -9.81)},
        foam_class="uniformDimensionedVectorField",
    )
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
            "air": {"transportModel": "Newtonian", "nu": 1.48e-05, "rho": 1},
            "sigma": 0,
        },
    )
    foamdict.write(
        const / "turbulenceProperties",
        {"simulationType": "RAS", "RAS": {"RASModel": "kOmegaSST", "turbulence": True, "printCoeffs": True}},
    )
    k, w = flow.k, flow.omega
    sym = {"sides": {"type": "symmetry"}, "bottom": symmetry_plane()}
    fields = {
        "alpha.water": (
            "[0 0 0 0 0 0 0]",
            0,
            "volScalarField",
            {
                "inlet": {"type": "fixedValue", "value": Words("uniform", 0)},
                "outlet": {"type": "variableHeightFlowRate", "lowerBound": 0, "upperBound": 1},
                "atmosphere": {
                    "type": "inletOutlet",
                    "inletValue": Words("uniform", 0),
                    "value": Words("uniform", 0),
                },
                HULL_PATCH: {"type": "zeroGradient"},
            },
        ),
        "U": (
            "[0 1 -1 0 0 0 0]",
            U,
            "volVectorField",
            {
                "inlet": {"type": "fixedValue", "value": Words("uniform", U)},
                "outlet": {"type": "outletPhaseMeanVelocity", "Umean": flow.U, "alpha": "alpha.water"},
                "atmosphere": {
                    "type": "pressureInletOutletVelocity",
                    "tangentialVelocity": Words("uniform", U),
                    "value": Words("uniform", (0, 0, 0)),
                },
                HULL_PATCH: {"type": "fixedValue", "value": Words("uniform", (0, 0, 0))},
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
        "k": (
            "[0 2 -2 0 0 0 0]",
            k,
            "volScalarField",
            {
                "inlet": {"type": "fixedValue", "value": Words("uniform", k)},
                "outlet": {
                    "type": "inletOutlet",
                    "inletValue": Words("uniform", k),
                    "value": Words("uniform", k),
                },
                "atmosphere": {
                    "type": "inletOutlet",
                    "inletValue": Words("uniform", k),
                    "value": Words("uniform", k),
                },
                HULL_PATCH: {"type": "kqRWallFunction", "value": Words("uniform", k)},
            },
        ),
        "omega": (
            "[0 0 -1 0 0 0 0]",
            w,
            "volScalarField",
            {
                "inlet": {"type": "fixedValue", "value": Words("uniform", w)},
                "outlet": {
                    "type": "inletOutlet",
                    "inletValue": Words("uniform", w),
                    "value": Words("uniform", w),
                },
                "atmosphere": {
                    "type": "inletOutlet",
                    "inletValue": Words("uniform", w),
                    "value": Words("uniform", w),
                },
                HULL_PATCH: {"type": "omegaWallFunction", "value": Words("uniform", w)},
            },
        ),
        "nut": (
            "[0 2 -1 0 0 0 0]",
            0,
            "volScalarField",
            {
                "inlet": {"type": "fixedValue", "value": Words("uniform", 0)},
                "outlet": {"type": "zeroGradient"},
                "atmosphere": {"type": "zeroGradient"},
                HULL_PATCH: {"type": "nutkWallFunction", "value": Words("uniform", 0)},
            },
        ),
    }
    for name, (dims, internal, cls, bnd) in fields.items():
        foamdict.write(
            case / "0.orig" / name,
            {
                "dimensions": dims,
                "internalField": Words("uniform", internal),
                "boundaryField": {**bnd, **sym},
            },
            foam_class=cls,
        )
    (case / "Allrun").write_text(
        "#!/bin/sh\n# VOF straight tow generated by vessel-cfd. NOT validated: see docs/cfd.md.\n"
        'set -e\ncd "${0%/*}"\nexport WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam}\n'
        "blockMesh > log.blockMesh\nsurfaceFeatureExtract > log.surfaceFeatureExtract\n"
        "snappyHexMesh -overwrite > log.snappyHexMesh\nrm -rf 0 && cp -r 0.orig 0\n"
        "setFields > log.setFields\ninterFoam > log.interFoam\n"
    )
    (case / "Allrun").chmod(0o755)
