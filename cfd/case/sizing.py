"""Mesh sizing: the domain, the seed report's Table-2 refinement boxes, surface levels, boundary layers.

All lengths in the case frame of :mod:`cfd.geometry` (x forward, y to port, z up, origin at midship in the
waterplane). :class:`MeshSpec` holds everything the mesh and flow cases need to know about the mesh.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..friction import wall_distance

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
# Cells of one level between two refinement levels (snappyHexMesh nCellsBetweenLevels) at cell_scale 1; a
# finer family member has proportionally more, so the transitions keep their physical width.
CELLS_BETWEEN_LEVELS = 3


@dataclass(frozen=True)
class Box:
    name: str
    lo: tuple[float, float, float]
    hi: tuple[float, float, float]
    level: int


@dataclass(frozen=True)
class Wake:
    """A cylindrical refinement region along the wake of one inflow angle (snappyHexMesh searchableCylinder).

    The axis runs from midship on the waterplane downstream along the inflow direction, so at a drift angle
    β it passes the stern at y = −(L/2) tan β, where the leeward bilge vortices leave the hull.
    """

    name: str
    beta_deg: float  # inflow angle of the case frame (U∞ ∝ (−cos β, −sin β, 0))
    point1: tuple[float, float, float]
    point2: tuple[float, float, float]
    radius: float
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
    yplus_target: float = 0.0  # y+ the first layer was sized for (0: no layers)
    wakes: tuple[Wake, ...] = ()
    cells_between_levels: int = CELLS_BETWEEN_LEVELS  # snappyHexMesh's buffer between two levels

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
    wake_deg: tuple[float, ...] = (),
    cell_scale: float = 1.0,
) -> MeshSpec:
    """Background mesh, Table-2 boxes and surface levels for a hull of Lpp L, breadth B, draught T.

    ``sizing="grading"``: background cells of L/8; the hull surface at level
    :func:`hull_level_for`; Table-2 box k (6 = innermost) at level hull_level − 1 − (6 − k), boxes
    of level < 1 dropped (grading 5 uses the seed's full six-box scheme).
    ``sizing="yplus"``: the seed's rule — hull cells as high as the y⁺ wall cell (2 × wall distance,
    aspect ratio 1) and background cell = that size × 2^levels. Expect very large meshes.
    ``cell_scale`` (grading sizing) multiplies the background cell, hence every cell, leaving the levels,
    the regions' extents and the physical width of the transitions between levels (the buffer of
    :data:`CELLS_BETWEEN_LEVELS` cells grows as the cells shrink) as they are: meshes with cell_scale 1, 1/√2
    and 1/2 are a systematically refined family with refinement ratio √2 (a grid study's grids), which the
    grading's level steps are not.
    """
    if not 0.0 < cell_scale <= 4.0:
        raise ValueError(f"cell_scale must be in (0, 4], got {cell_scale}")
    H = hull_level_for(grading, L, T)
    y_wall = wall_distance(U, L, nu, yplus)
    if sizing == "yplus":
        h0 = 2.0 * y_wall * 2**H
    else:
        h0 = L / BACKGROUND_CELLS_PER_L * cell_scale
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
        L,
        B,
        T,
        grading,
        h0,
        tuple(lo),
        tuple(hi),
        tuple(cells),
        H,
        tuple(boxes),
        location,
        n_layers,
        t1,
        yplus_target=yplus if n_layers else 0.0,
        wakes=wake_regions(L, B, T, H, wake_deg),
        cells_between_levels=max(1, round(CELLS_BETWEEN_LEVELS / cell_scale)),
    )


# The wake cylinder reaches WAKE_LENGTH behind the stern (in Lpp), about where the double-body wake of a
# slender hull has spread to the coarse background cells; its radius clears the draught and the half
# breadth by WAKE_CLEARANCE Lpp, the clearance of the seed's innermost Table-2 box to the DTC's side.
WAKE_LENGTH = 1.0
WAKE_CLEARANCE = 0.05
# Cylinders are laid in a fan every WAKE_STEP_DEG from 0 to the largest angle (rounded up): neighbours
# 5 deg apart overlap to about 2 L behind midship (2 R / tan 5 deg with R ~ 0.1 L), so every angle in the fan
# has its wake inside refined cells, and a new angle inside the fan does not change the mesh (resume).
WAKE_STEP_DEG = 5.0


def wake_regions(L: float, B: float, T: float, hull_level: int, angles_deg: tuple[float, ...]) -> tuple:
    """The :class:`Wake` fan covering the inflow angles ``angles_deg`` (deg, case frame; the sign gives the
    side): one cylinder every :data:`WAKE_STEP_DEG` from 0 to each angle rounded up, at the level of the
    second innermost Table-2 box (hull level − 2, at least 1). No angles, no wake regions."""
    fan: set[float] = set()
    for a in angles_deg:
        n = math.ceil(abs(a) / WAKE_STEP_DEG - 1e-9)
        fan |= {math.copysign(k * WAKE_STEP_DEG, a) if k else 0.0 for k in range(n + 1)}
    out = []
    radius = max(T, 0.5 * B) + WAKE_CLEARANCE * L
    reach = (0.5 + WAKE_LENGTH) * L  # from midship to WAKE_LENGTH behind the stern
    for beta in sorted(fan):
        b = math.radians(beta)
        p2 = (-reach * math.cos(b), -reach * math.sin(b), 0.0)
        name = f"wake_{'m' if beta < 0 else 'p'}{abs(beta):02.0f}"
        out.append(Wake(name, beta, (0.0, 0.0, 0.0), p2, radius, max(1, hull_level - 2)))
    return tuple(out)


def pmm_time_step(spec: MeshSpec, U: float, period: float, courant: float = 1.0) -> float:
    """Time step with the given Courant number on the hull cells, dividing the period into whole steps."""
    dt = courant * spec.h_hull / U
    n = max(40, math.ceil(period / dt))
    return period / n


def cell_count_estimate(spec: MeshSpec) -> int:
    """Rough cell count (for a warning before meshing): background + boxes + hull surface band."""
    n = float(np.prod(spec.cells))
    vol_cell0 = spec.h0**3
    for b in spec.boxes:
        vol = float(np.prod(np.subtract(b.hi, b.lo)))
        vol = min(vol, float(np.prod(np.subtract(spec.hi, spec.lo))))
        n += vol / vol_cell0 * (8**b.level - 8 ** (b.level - 1))
    for w in spec.wakes:  # the half below the waterplane, at its own level over the background
        vol = 0.5 * math.pi * w.radius**2 * math.dist(w.point1, w.point2)
        n += vol / vol_cell0 * (8**w.level - 1)
    # hull band: about 3 cell layers around a surface of area ~ 2 L (B + 2T)
    area = 2.0 * spec.L * (spec.B + 2.0 * spec.T) * 0.7
    n += 3.0 * area / spec.h_hull**2
    return int(n)
