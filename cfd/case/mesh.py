"""The meshing case: blockMesh, surfaceFeatureExtract and snappyHexMesh dictionaries from a :class:`MeshSpec`."""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

from .. import foamdict
from ..foamdict import Named, Words
from .common import HULL_PATCH, decompose_dict, write_schemes, write_solution
from .sizing import MeshSpec

#: surfaceFeatureExtractDict of the hull STL (one home for the double-body and free-surface meshes): edges where
#: the faces meet at less than 150 deg (normals over 30 deg apart) and the open edges are features, so that
#: snappyHexMesh snaps the keel, stem and transom corners instead of rounding them
SURFACE_FEATURES: dict[str, Any] = {
    "hull.stl": {
        "extractionMethod": "extractFromSurface",
        "extractFromSurfaceCoeffs": {"includedAngle": 150},
        "subsetFeatures": {"nonManifoldEdges": False, "openEdges": True},
        "writeObj": False,
    }
}


def block_mesh_dict(spec: MeshSpec) -> dict[str, Any]:
    (x0, y0, z0), (x1, y1, z1) = spec.lo, spec.hi
    verts = [
        (x0, y0, z0),
        (x1, y0, z0),
        (x1, y1, z0),
        (x0, y1, z0),
        (x0, y0, z1),
        (x1, y0, z1),
        (x1, y1, z1),
        (x0, y1, z1),
    ]
    return {
        "scale": 1,
        "vertices": verts,
        "blocks": [Words("hex", tuple(range(8)), spec.cells, "simpleGrading", (1, 1, 1))],
        "edges": [],
        "boundary": [
            Named(
                "farfield",
                {"type": "patch", "faces": [(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2)]},
            ),
            Named("bottom", {"type": "symmetryPlane", "faces": [(0, 3, 2, 1)]}),
            Named("waterline", {"type": "symmetryPlane", "faces": [(4, 5, 6, 7)]}),
        ],
        "mergePatchPairs": [],
    }


MESH_QUALITY = {
    "maxNonOrtho": 65,
    "maxBoundarySkewness": 20,
    "maxInternalSkewness": 4,
    "maxConcave": 80,
    "minVol": 1e-13,
    "minTetQuality": 1e-15,
    "minArea": -1,
    "minTwist": 0.02,
    "minDeterminant": 0.001,
    "minFaceWeight": 0.05,
    "minVolRatio": 0.01,
    "minTriangleTwist": -1,
    "nSmoothScale": 4,
    "errorReduction": 0.75,
    "relaxed": {"maxNonOrtho": 75},
}


def _snappy(spec: MeshSpec) -> dict[str, Any]:
    geometry: dict[str, Any] = {"hull.stl": {"type": "triSurfaceMesh", "name": HULL_PATCH}}
    regions: dict[str, Any] = {}
    for b in spec.boxes:
        geometry[b.name] = {"type": "searchableBox", "min": b.lo, "max": b.hi}
        regions[b.name] = {"mode": "inside", "levels": [(1e15, b.level)]}
    for w in spec.wakes:
        geometry[w.name] = {
            "type": "searchableCylinder",
            "point1": w.point1,
            "point2": w.point2,
            "radius": w.radius,
        }
        regions[w.name] = {"mode": "inside", "levels": [(1e15, w.level)]}
    H = spec.hull_level
    layers = {
        "relativeSizes": False,
        "layers": {HULL_PATCH: {"nSurfaceLayers": spec.n_layers}},
        "expansionRatio": spec.expansion,
        "firstLayerThickness": spec.first_layer_m or 1e-3 * spec.L,
        "minThickness": 0.1 * (spec.first_layer_m or 1e-3 * spec.L),
        "nGrow": 0,
        "featureAngle": 60,
        "slipFeatureAngle": 30,
        "nRelaxIter": 3,
        "nSmoothSurfaceNormals": 1,
        "nSmoothNormals": 3,
        "nSmoothThickness": 10,
        "maxFaceThicknessRatio": 0.5,
        "maxThicknessToMedialRatio": 0.3,
        "minMedianAxisAngle": 90,
        "nBufferCellsNoExtrude": 0,
        "nLayerIter": 50,
    }
    return {
        "castellatedMesh": True,
        "snap": True,
        "addLayers": spec.n_layers > 0,
        "geometry": geometry,
        "castellatedMeshControls": {
            "maxLocalCells": 5_000_000,
            "maxGlobalCells": 50_000_000,
            "minRefinementCells": 10,
            "maxLoadUnbalance": 0.10,
            "nCellsBetweenLevels": spec.cells_between_levels,
            "features": [{"file": '"hull.eMesh"', "level": H}],
            "refinementSurfaces": {HULL_PATCH: {"level": (H, H), "patchInfo": {"type": "wall"}}},
            "resolveFeatureAngle": 30,
            "refinementRegions": regions,
            "locationInMesh": spec.location,
            "allowFreeStandingZoneFaces": True,
        },
        "snapControls": {
            "nSmoothPatch": 3,
            "tolerance": 2.0,
            "nSolveIter": 30,
            "nRelaxIter": 5,
            "nFeatureSnapIter": 10,
            "implicitFeatureSnap": False,
            "explicitFeatureSnap": True,
            "multiRegionFeatureSnap": False,
        },
        "addLayersControls": layers,
        "meshQualityControls": MESH_QUALITY,
        "mergeTolerance": 1e-6,
        "debug": 0,
    }


def write_mesh_case(case: Path, spec: MeshSpec, stl: Path, procs: int = 1) -> None:
    """Write the meshing case: blockMesh, surfaceFeatureExtract and snappyHexMesh dictionaries."""
    system, tri = case / "system", case / "constant" / "triSurface"
    tri.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(stl, tri / "hull.stl")
    foamdict.write(
        system / "controlDict",
        {
            "application": "snappyHexMesh",
            "startFrom": "startTime",
            "startTime": 0,
            "stopAt": "endTime",
            "endTime": 1,
            "deltaT": 1,
            "writeControl": "timeStep",
            "writeInterval": 1,
            "writeFormat": "ascii",
            "writePrecision": 10,
            "runTimeModifiable": False,
        },
    )
    foamdict.write(system / "blockMeshDict", block_mesh_dict(spec))
    foamdict.write(system / "surfaceFeatureExtractDict", SURFACE_FEATURES)
    foamdict.write(system / "snappyHexMeshDict", _snappy(spec))
    foamdict.write(system / "meshQualityDict", MESH_QUALITY)
    foamdict.write(system / "decomposeParDict", decompose_dict(procs))
    write_schemes(system, steady=True)
    write_solution(system, steady=True, residual_p=1e-5)
