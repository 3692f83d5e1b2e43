"""OpenFOAM case generation: mesh, steady double-body tow/drift, moving-mesh PMM, free surface.

All lengths in the case frame of :mod:`cfd.geometry` (x forward, y to port, z up, origin at
midship in the waterplane). Dictionaries are written with :mod:`cfd.foamdict`; the values come
from :class:`MeshSpec` and :class:`FlowSpec`, so the generated text is reproducible and testable.
"""

from __future__ import annotations

import math
import re
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from . import foamdict
from .foamdict import Named, Words

HULL_PATCH = "hull"

# Seed report Table 2: refinement boxes in multiples of Lpp, x from the aft perpendicular, y from
# the centreline (the DTC's half breadth is 0.0719 Lpp; boxes keep their clearance to the hull).
TABLE2 = (
    (1, -1.673, 1.673, -1.004),
    (2, -0.873, 1.506, -0.502),
    (3, -0.502, 1.339, -0.251),
    (4, -0.335, 1.171, -0.167),
    (5, -0.167, 1.088, -0.100),
    (6, -0.084, 1.046, -0.092),
)
TABLE2_HALF_BREADTH = 0.859 / (2 * 5.976)

# Domain in multiples of Lpp about midship (1.5 Lpp ahead of the bow, 2.5 Lpp behind the stern, 1.5 Lpp
# to each side, 1 Lpp deep), enclosing the seed's outermost box with 0.5-0.8 Lpp to spare.
DOMAIN = ((-3.0, 2.0), (-1.5, 1.5), (-1.0, 0.0))
BACKGROUND_CELLS_PER_L = 8


# ---------------------------------------------------------------------------------- physics helpers
def skin_friction_flat_plate(re: float) -> float:
    """Schlichting's turbulent flat-plate skin friction C_f = (2 log10 Re − 0.65)^−2.3 (local, at x = L)."""
    return (2.0 * math.log10(re) - 0.65) ** -2.3


def wall_distance(U_m_s: float, L_m: float, nu_m2_s: float, yplus: float) -> float:
    """Distance (m) of the first cell centre from the wall for a target y+ (flat plate of length L).

    u_τ = U √(C_f/2), y = y⁺ ν / u_τ — the seed report's method (boundary layer developing over Lpp).
    """
    cf = skin_friction_flat_plate(U_m_s * L_m / nu_m2_s)
    u_tau = U_m_s * math.sqrt(0.5 * cf)
    return yplus * nu_m2_s / u_tau


def ittc57(re: float) -> float:
    """ITTC-1957 model-ship correlation line C_F = 0.075 / (log10 Re − 2)²."""
    return 0.075 / (math.log10(re) - 2.0) ** 2


# ---------------------------------------------------------------------------------- mesh spec
@dataclass(frozen=True)
class Box:
    name: str
    lo: tuple[float, float, float]
    hi: tuple[float, float, float]
    level: int


@dataclass(frozen=True)
class MeshSpec:
    """Everything blockMesh and snappyHexMesh need, derived from the hull and the grading."""

    L: float
    B: float
    T: float
    grading: int
    h0: float  # background cell size (m)
    lo: tuple[float, float, float]
    hi: tuple[float, float, float]
    cells: tuple[int, int, int]
    hull_level: int
    boxes: tuple[Box, ...]
    location: tuple[float, float, float]
    n_layers: int = 0
    first_layer_m: float = 0.0
    expansion: float = 1.2

    @property
    def h_hull(self) -> float:
        """Cell size on the hull surface (m)."""
        return self.h0 / 2**self.hull_level


def hull_level_for(grading: int, L: float, T: float) -> int:
    """Refinement level of the hull surface: at least 4 cells across the draught at grading 1,
    one more level (half the cell size) per grading step."""
    # surface cell h0 / 2^H <= T / 4 with h0 = L / 8  <=>  H >= log2(L / 2T)
    base = max(3, math.ceil(math.log2(L / (2.0 * T)) - 1e-9))
    return base + grading - 1


def mesh_spec(
    L: float,
    B: float,
    T: float,
    grading: int,
    *,
    U: float,
    nu: float,
    layers: bool = False,
    yplus: float = 150.0,
    sizing: str = "grading",
) -> MeshSpec:
    """Background mesh, Table-2 boxes and surface levels for a hull of Lpp L, breadth B, draught T.

    ``sizing="grading"``: background cells of L/8; the hull surface at level
    :func:`hull_level_for`; Table-2 box k (6 = innermost) at level hull_level − 1 − (6 − k), boxes
    of level < 1 dropped (grading 5 uses the seed's full six-box scheme).
    ``sizing="yplus"``: the seed's rule — hull cells as high as the y⁺ wall cell (2 × wall distance,
    aspect ratio 1) and background cell = that size × 2^levels. Expect very large meshes.
    """
    H = hull_level_for(grading, L, T)
    y_wall = wall_distance(U, L, nu, yplus)
    if sizing == "yplus":
        h0 = 2.0 * y_wall * 2**H
    else:
        h0 = L / BACKGROUND_CELLS_PER_L
    lo, hi, cells = [], [], []
    for a, b in DOMAIN:
        n = max(1, math.ceil(round((b - a) * L / h0, 9)))
        if b == 0.0:  # the waterplane stays exactly at z = 0
            lo.append(-n * h0)
            hi.append(0.0)
        else:
            lo.append(a * L)
            hi.append(a * L + n * h0)
        cells.append(n)
    boxes = []
    for k, xmin, xmax, ymin in TABLE2:
        level = H - 1 - (6 - k)
        if level < 1:
            continue
        half = 0.5 * B + (abs(ymin) - TABLE2_HALF_BREADTH) * L
        half = max(half, 0.5 * B + 0.01 * L)
        z_lo = -(T + half - 0.5 * B)
        blo = (max((xmin - 0.5) * L, lo[0]), max(-half, lo[1]), max(z_lo, lo[2]))
        bhi = (min((xmax - 0.5) * L, hi[0]), min(half, hi[1]), hi[2] + h0)
        boxes.append(Box(f"box{k}", blo, bhi, level))
    # a point in the fluid, off every cell face and outside the boxes
    location = (
        lo[0] + 0.71234 * (hi[0] - lo[0]) + 0.0123 * h0,
        lo[1] + 0.91234 * (hi[1] - lo[1]) + 0.0123 * h0,
        lo[2] + 0.31234 * (hi[2] - lo[2]) - 0.0123 * h0,
    )
    n_layers, t1 = 0, 0.0
    if layers:
        t1 = 2.0 * y_wall
        h_hull = h0 / 2**H
        if t1 < 0.8 * h_hull:
            n_layers = max(1, min(20, math.ceil(math.log(0.6 * h_hull / t1) / math.log(1.2)) + 1))
    return MeshSpec(
        L, B, T, grading, h0, tuple(lo), tuple(hi), tuple(cells), H, tuple(boxes), location, n_layers, t1
    )


# ---------------------------------------------------------------------------------- mesh case
def _block_mesh(spec: MeshSpec) -> dict[str, Any]:
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
            "nCellsBetweenLevels": 3,
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


def _decompose(n: int) -> dict[str, Any]:
    # scotch/metis are stub libraries in Debian's v1912; hierarchical always works
    return {
        "numberOfSubdomains": n,
        "method": "hierarchical",
        "hierarchicalCoeffs": {"n": (n, 1, 1), "order": "xyz"},
        "coeffs": {"n": (n, 1, 1), "order": "xyz"},
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
    foamdict.write(system / "blockMeshDict", _block_mesh(spec))
    foamdict.write(
        system / "surfaceFeatureExtractDict",
        {
            "hull.stl": {
                "extractionMethod": "extractFromSurface",
                "extractFromSurfaceCoeffs": {"includedAngle": 150},
                "subsetFeatures": {"nonManifoldEdges": False, "openEdges": True},
                "writeObj": False,
            }
        },
    )
    foamdict.write(system / "snappyHexMeshDict", _snappy(spec))
    foamdict.write(system / "meshQualityDict", MESH_QUALITY)
    foamdict.write(system / "decomposeParDict", _decompose(procs))
    _write_schemes(system, steady=True)
    _write_solution(system, steady=True, residual_p=1e-5)


# ---------------------------------------------------------------------------------- flow cases
@dataclass(frozen=True)
class FlowSpec:
    """Free stream and water for one case (case frame)."""

    U: float  # speed (m/s)
    beta_deg: float = 0.0  # inflow angle: the ship moves with U(cos β, sin β) in the case frame
    rho: float = 999.1
    nu: float = 1.1386e-6
    intensity: float = 0.01  # free-stream turbulence intensity
    viscosity_ratio: float = 10.0  # ν_t / ν in the free stream

    @property
    def u_inf(self) -> tuple[float, float, float]:
        b = math.radians(self.beta_deg)
        return (-self.U * math.cos(b), -self.U * math.sin(b), 0.0)

    @property
    def k(self) -> float:
        return 1.5 * (self.intensity * self.U) ** 2

    @property
    def omega(self) -> float:
        return self.k / (self.viscosity_ratio * self.nu)


def _field(dims: str, internal: Any, boundary: dict[str, Any], foam_class: str = "volScalarField") -> tuple:
    return {"dimensions": dims, "internalField": internal, "boundaryField": boundary}, foam_class


def _sym() -> dict[str, Any]:
    return {"type": "symmetryPlane"}


def flow_fields(flow: FlowSpec) -> dict[str, tuple[dict, str]]:
    """0/ fields for a double-body case: freestream far field, wall functions on the hull."""
    U = flow.u_inf
    k, w, nut0 = flow.k, flow.omega, flow.k / flow.omega
    sym = {"bottom": _sym(), "waterline": _sym()}
    return {
        "U": _field(
            "[0 1 -1 0 0 0 0]",
            Words("uniform", U),
            {
                "farfield": {
                    "type": "freestreamVelocity",
                    "freestreamValue": Words("uniform", U),
                    "value": Words("uniform", U),
                },
                # equals noSlip on a fixed mesh; follows the wall on a moving one
                HULL_PATCH: {"type": "movingWallVelocity", "value": Words("uniform", (0, 0, 0))},
                **sym,
            },
            "volVectorField",
        ),
        "p": _field(
            "[0 2 -2 0 0 0 0]",
            Words("uniform", 0),
            {
                "farfield": {
                    "type": "freestreamPressure",
                    "freestreamValue": Words("uniform", 0),
                    "value": Words("uniform", 0),
                },
                HULL_PATCH: {"type": "zeroGradient"},
                **sym,
            },
        ),
        "k": _field(
            "[0 2 -2 0 0 0 0]",
            Words("uniform", k),
            {
                "farfield": {
                    "type": "inletOutlet",
                    "inletValue": Words("uniform", k),
                    "value": Words("uniform", k),
                },
                HULL_PATCH: {"type": "kqRWallFunction", "value": Words("uniform", k)},
                **sym,
            },
        ),
        "omega": _field(
            "[0 0 -1 0 0 0 0]",
            Words("uniform", w),
            {
                "farfield": {
                    "type": "inletOutlet",
                    "inletValue": Words("uniform", w),
                    "value": Words("uniform", w),
                },
                HULL_PATCH: {"type": "omegaWallFunction", "value": Words("uniform", w)},
                **sym,
            },
        ),
        "nut": _field(
            "[0 2 -1 0 0 0 0]",
            Words("uniform", nut0),
            {
                "farfield": {"type": "calculated", "value": Words("uniform", nut0)},
                HULL_PATCH: {"type": "nutUSpaldingWallFunction", "value": Words("uniform", 0)},
                **sym,
            },
        ),
    }


def _write_schemes(system: Path, steady: bool) -> None:
    div_u = "bounded Gauss linearUpwind grad(U)" if steady else "Gauss linearUpwind grad(U)"
    div_t = "bounded Gauss upwind" if steady else "Gauss upwind"
    foamdict.write(
        system / "fvSchemes",
        {
            "ddtSchemes": {"default": "steadyState" if steady else "Euler"},
            "gradSchemes": {"default": "Gauss linear", "grad(U)": "cellLimited Gauss linear 1"},
            "divSchemes": {
                "default": "none",
                "div(phi,U)": div_u,
                "div(phi,k)": div_t,
                "div(phi,omega)": div_t,
                "div((nuEff*dev2(T(grad(U)))))": "Gauss linear",
            },
            "laplacianSchemes": {"default": "Gauss linear limited corrected 0.5"},
            "interpolationSchemes": {"default": "linear"},
            "snGradSchemes": {"default": "limited corrected 0.5"},
            "wallDist": {"method": "meshWave"},
        },
    )


def _write_solution(system: Path, steady: bool, residual_p: float = 1e-5) -> None:
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
        relax = {"equations": {"U": 0.9, '".*"': 0.7}}
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


def _function_objects(rho: float, write_yplus: bool) -> dict[str, Any]:
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


def _write_constant(case: Path, nu: float) -> None:
    const = case / "constant"
    foamdict.write(
        const / "transportProperties", {"transportModel": "Newtonian", "nu": Words("[0 2 -1 0 0 0 0]", nu)}
    )
    foamdict.write(
        const / "turbulenceProperties",
        {"simulationType": "RAS", "RAS": {"RASModel": "kOmegaSST", "turbulence": True, "printCoeffs": True}},
    )


def link_mesh(case: Path, mesh_case: Path) -> None:
    """Copy the finished polyMesh into a case (cases must not share it: moving meshes write to it)."""
    dst = case / "constant" / "polyMesh"
    if dst.exists():
        shutil.rmtree(dst)
    shutil.copytree(mesh_case / "constant" / "polyMesh", dst)


def write_steady_case(case: Path, mesh_case: Path, flow: FlowSpec, iterations: int, procs: int = 1) -> None:
    """Double-body simpleFoam case (tow or static drift by inflow direction) on the finished mesh."""
    case.mkdir(parents=True, exist_ok=True)
    link_mesh(case, mesh_case)
    _write_constant(case, flow.nu)
    system = case / "system"
    foamdict.write(
        system / "controlDict",
        {
            "application": "simpleFoam",
            "startFrom": "startTime",
            "startTime": 0,
            "stopAt": "endTime",
            "endTime": iterations,
            "deltaT": 1,
            "writeControl": "timeStep",
            "writeInterval": iterations,
            "purgeWrite": 1,
            "writeFormat": "binary",
            "writePrecision": 10,
            "writeCompression": False,
            "timeFormat": "general",
            "timePrecision": 8,
            "runTimeModifiable": True,  # request_stop() ends a run whose forces have settled
            "functions": _function_objects(flow.rho, write_yplus=True),
        },
    )
    _write_schemes(system, steady=True)
    _write_solution(system, steady=True)
    foamdict.write(system / "decomposeParDict", _decompose(procs))
    for name, (body, cls) in flow_fields(flow).items():
        foamdict.write(case / "0" / name, body, foam_class=cls)


def request_stop(case: Path) -> bool:
    """Ask a running solver to write its fields and stop (``stopAt writeNow``); False if already asked."""
    path = case / "system" / "controlDict"
    text = path.read_text()
    new = re.sub(r"^(stopAt\s+)endTime;", r"\1writeNow;", text, count=1, flags=re.M)
    if new == text:
        return False
    path.write_text(new)
    return True


# ---------------------------------------------------------------------------------- PMM motion
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
) -> None:
    """pimpleFoam case with a rigidly moving mesh (solidBody, tabulated6DoFMotion), started from the
    converged straight-tow fields in ``start_dir`` (a time directory of the tow case)."""
    case.mkdir(parents=True, exist_ok=True)
    link_mesh(case, mesh_case)
    _write_constant(case, flow.nu)
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
            "functions": _function_objects(flow.rho, write_yplus=False),
        },
    )
    _write_schemes(system, steady=False)
    _write_solution(system, steady=False)
    foamdict.write(system / "decomposeParDict", _decompose(procs))


def pmm_time_step(spec: MeshSpec, U: float, period: float, courant: float = 1.25) -> float:
    """Time step with the given Courant number on the hull cells, dividing the period into whole steps."""
    dt = courant * spec.h_hull / U
    n = max(40, math.ceil(period / dt))
    return period / n


# ---------------------------------------------------------------------------------- free surface
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
    bm = _block_mesh(fs)
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
            "functions": _function_objects(flow.rho, write_yplus=False),
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
    sym = {"sides": {"type": "symmetry"}, "bottom": _sym()}
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


def cell_count_estimate(spec: MeshSpec) -> int:
    """Rough cell count (for a warning before meshing): background + boxes + hull surface band."""
    n = float(np.prod(spec.cells))
    vol_cell0 = spec.h0**3
    for b in spec.boxes:
        vol = float(np.prod(np.subtract(b.hi, b.lo)))
        vol = min(vol, float(np.prod(np.subtract(spec.hi, spec.lo))))
        n += vol / vol_cell0 * (8**b.level - 8 ** (b.level - 1))
    # hull band: about 3 cell layers around a surface of area ~ 2 L (B + 2T)
    area = 2.0 * spec.L * (spec.B + 2.0 * spec.T) * 0.7
    n += 3.0 * area / spec.h_hull**2
    return int(n)
