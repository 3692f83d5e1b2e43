"""Hull surfaces: STL input/output, the Wigley hull, placement and hydrostatics (pure numpy).

Triangles are arrays of shape ``(n, 3, 3)``: triangle, vertex, coordinate (m).

The *case frame* used for every OpenFOAM case is OpenFOAM's usual one: x forward (bow at +x),
y to port, z up, origin at midship (half-way between the perpendiculars) on the centreline in the
waterplane. Forces are converted to the standard body axes (x forward, y starboard, z down) when
they are read back (see :mod:`cfd.postprocess`).
"""

from __future__ import annotations

import gzip
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .case.sizing import DOMAIN
from .errors import InputError

_VERTEX = re.compile(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)")


# --------------------------------------------------------------------------------------- STL I/O
def read_stl(path: str | Path) -> np.ndarray:
    """Read an ASCII or binary STL file (optionally gzip-compressed) into ``(n, 3, 3)`` triangles."""
    path = Path(path)
    if not path.is_file():
        raise InputError("hull", f"STL file {path} does not exist")
    data = path.read_bytes()
    if data[:2] == b"\x1f\x8b":
        data = gzip.decompress(data)
    head = data[:1024].lstrip()
    tris: np.ndarray
    if head.startswith(b"solid") and b"facet" in data[:4096]:
        verts = np.array(_VERTEX.findall(data), dtype=float)
        if len(verts) == 0 or len(verts) % 3:
            raise InputError("hull", f"{path} is not a valid ASCII STL (vertex count {len(verts)})")
        tris = verts.reshape(-1, 3, 3)
    else:
        if len(data) < 84:
            raise InputError("hull", f"{path} is too short to be an STL file")
        n = int(np.frombuffer(data, dtype="<u4", count=1, offset=80)[0])
        if len(data) < 84 + 50 * n:
            raise InputError("hull", f"{path} is not a valid binary STL ({n} triangles announced)")
        rec = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
        tris = np.frombuffer(data, dtype=rec, count=n, offset=84)["v"].astype(float)
    if not np.all(np.isfinite(tris)):
        raise InputError("hull", f"{path} contains non-finite vertex coordinates")
    return tris


def write_stl(path: str | Path, triangles: np.ndarray, name: str = "hull") -> Path:
    """Write triangles as an ASCII STL with one solid called ``name`` (OpenFOAM reads the name)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tris = np.asarray(triangles, dtype=float)
    normals = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    norm = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.divide(normals, norm, out=np.zeros_like(normals), where=norm > 0)
    parts = [f"solid {name}\n"]
    for nrm, tri in zip(normals, tris, strict=True):
        parts.append(
            f" facet normal {nrm[0]:.7e} {nrm[1]:.7e} {nrm[2]:.7e}\n  outer loop\n"
            + "".join(f"   vertex {p[0]:.9e} {p[1]:.9e} {p[2]:.9e}\n" for p in tri)
            + "  endloop\n endfacet\n"
        )
    parts.append(f"endsolid {name}\n")
    path.write_text("".join(parts))
    return path


# --------------------------------------------------------------------------------------- Wigley
def _clustered(n: int) -> np.ndarray:
    """n points on [-1, 1] clustered towards both ends (sine spacing)."""
    return np.sin(0.5 * np.pi * np.linspace(-1.0, 1.0, n))


def wigley_hull(L: float, B: float, T: float, nx: int = 81, nz: int = 25) -> np.ndarray:
    """Closed parabolic Wigley double body in the case frame.

    The surface is y = ±B/2 (1 − (2x/L)²)(1 − (z/T)²) for x ∈ [−L/2, L/2] and z ∈ [−T, T]: the hull
    below the waterline (z ≤ 0, draught T) mirrored about the waterplane, so that the symmetry plane
    of a double-body case cuts it at z = 0. C_B = 4/9. Normals point outwards; port and starboard
    sheets share their boundary vertices, and no triangle has all three vertices on the boundary
    (that would give flat, coincident triangles on the two sheets).
    """
    if min(L, B, T) <= 0:
        raise InputError("wigley", f"L, B and T must be > 0 m (got {L}, {B}, {T})")
    if nx < 3 or nz < 3:
        raise InputError("wigley", f"grid must be at least 3x3 (got {nx}x{nz})")
    xi = _clustered(nx)
    zeta = _clustered(nz)
    X, Z = np.meshgrid(0.5 * L * xi, T * zeta, indexing="ij")
    half = 0.5 * B * (1.0 - xi[:, None] ** 2) * (1.0 - zeta[None, :] ** 2)
    on_boundary = np.zeros((nx, nz), dtype=bool)
    on_boundary[[0, -1], :] = True
    on_boundary[:, [0, -1]] = True

    points: list[np.ndarray] = []
    index = np.full((2, nx, nz), -1, dtype=int)
    for i in range(nx):
        for j in range(nz):
            if on_boundary[i, j]:
                index[:, i, j] = len(points)
                points.append(np.array([X[i, j], 0.0, Z[i, j]]))
            else:
                for side, sign in enumerate((1.0, -1.0)):
                    index[side, i, j] = len(points)
                    points.append(np.array([X[i, j], sign * half[i, j], Z[i, j]]))
    P = np.array(points)

    tris = []
    for side, sign in enumerate((1.0, -1.0)):
        for i in range(nx - 1):
            for j in range(nz - 1):
                a, b, c, d = (i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)
                options = [((a, b, c), (a, c, d)), ((a, b, d), (b, c, d))]
                for pair in options:
                    if not any(all(on_boundary[q] for q in t) for t in pair):
                        break
                for t in pair:
                    ids = [index[side, q[0], q[1]] for q in t]
                    tri = P[ids]
                    n = np.cross(tri[1] - tri[0], tri[2] - tri[0])
                    if n[1] * sign < 0:
                        tri = tri[[0, 2, 1]]
                    tris.append(tri)
    return np.array(tris)


def wigley_hull_with_freeboard(
    L: float, B: float, T: float, freeboard: float, nx: int = 81, nz: int = 17, nz_above: int = 5
) -> np.ndarray:
    """Closed Wigley hull for free-surface cases: the parabolic hull below the waterline, wall-sided above it
    up to a flat deck at z = ``freeboard`` (case frame, waterline z = 0).

    Below z = 0: y = ±B/2 (1 − (2x/L)²)(1 − (z/T)²), as :func:`wigley_hull`; above: y = ±B/2 (1 − (2x/L)²),
    so the water meets vertical sides (a knife edge above the waterline, as in the double body, leaves
    slivers of air cells at the hull that a VOF solver does not survive). Stem, stern and keel are shared
    by both sides; the deck closes the top. Normals point outwards.
    """
    if min(L, B, T, freeboard) <= 0:
        raise InputError(
            "wigley", f"L, B, T and the freeboard must be > 0 m (got {L}, {B}, {T}, {freeboard})"
        )
    xi = _clustered(nx)
    below = -T * np.cos(0.5 * np.pi * np.linspace(0.0, 1.0, nz))  # keel -> waterline, dense at the keel
    z = np.concatenate([below, np.linspace(0.0, freeboard, nz_above)[1:]])
    nzt = len(z)
    depth = np.clip(z / T, -1.0, 0.0)
    half = 0.5 * B * (1.0 - xi[:, None] ** 2) * (1.0 - depth[None, :] ** 2)
    shared = np.zeros((nx, nzt), dtype=bool)  # on the centreline: stem, stern, keel
    shared[[0, -1], :] = True
    shared[:, 0] = True
    points: list[tuple[float, float, float]] = []
    index = np.full((2, nx, nzt), -1, dtype=int)
    for i in range(nx):
        for j in range(nzt):
            x = 0.5 * L * xi[i]
            if shared[i, j]:
                index[:, i, j] = len(points)
                points.append((x, 0.0, z[j]))
            else:
                for side, sign in enumerate((1.0, -1.0)):
                    index[side, i, j] = len(points)
                    points.append((x, sign * half[i, j], z[j]))
    P = np.array(points)

    def oriented(ids: list[int], axis: int, sign: float) -> np.ndarray | None:
        tri = P[ids]
        n = np.cross(tri[1] - tri[0], tri[2] - tri[0])
        if np.linalg.norm(n) < 1e-14 * L * L:
            return None  # the deck's corner triangles at stem and stern collapse to a line
        return tri[[0, 2, 1]] if n[axis] * sign < 0 else tri

    tris = []
    for side, sign in enumerate((1.0, -1.0)):
        for i in range(nx - 1):
            for j in range(nzt - 1):
                a, b, c, d = (i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)
                for pair in (((a, b, c), (a, c, d)), ((a, b, d), (b, c, d))):
                    if not any(all(shared[q] for q in t) for t in pair):
                        break
                for t in pair:
                    tri = oriented([index[side, q[0], q[1]] for q in t], 1, sign)
                    if tri is not None:
                        tris.append(tri)
    top = nzt - 1
    for i in range(nx - 1):  # the deck: strips between the port and starboard top edges
        p0, p1 = index[0, i, top], index[0, i + 1, top]
        s0, s1 = index[1, i, top], index[1, i + 1, top]
        for ids in ([p0, s0, s1], [p0, s1, p1]):
            tri = oriented(ids, 2, 1.0)
            if tri is not None:
                tris.append(tri)
    return np.array(tris)


# --------------------------------------------------------------------------------------- hydrostatics
def clip_below(triangles: np.ndarray, z0: float = 0.0) -> np.ndarray:
    """Parts of the triangles with z ≤ z0 (orientation kept)."""
    out = []
    for tri in np.asarray(triangles, dtype=float):
        below = tri[:, 2] <= z0
        nb = int(below.sum())
        if nb == 3:
            out.append(tri)
            continue
        if nb == 0:
            continue
        # rotate so that the odd vertex is first, keeping orientation
        k = int(np.flatnonzero(below if nb == 1 else ~below)[0])
        p0, p1, p2 = tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]

        def cut(p: np.ndarray, q: np.ndarray) -> np.ndarray:
            s = (z0 - p[2]) / (q[2] - p[2])
            return p + s * (q - p)

        c01, c02 = cut(p0, p1), cut(p0, p2)
        if nb == 1:
            out.append(np.array([p0, c01, c02]))
        else:
            out.append(np.array([c01, p1, p2]))
            out.append(np.array([c01, p2, c02]))
    return np.array(out).reshape(-1, 3, 3)


@dataclass(frozen=True)
class Hydrostatics:
    """Properties of the hull below the waterplane z = 0 of the case frame (SI units)."""

    volume_m3: float
    wetted_area_m2: float
    lcb_m: float  # x of the centre of buoyancy, forward of midship positive
    lwl_m: float  # waterline length (underwater extent in x)
    bwl_m: float  # largest underwater breadth
    draught_m: float


def hydrostatics(triangles: np.ndarray) -> Hydrostatics:
    """Volume, wetted surface and centre of buoyancy of the part of a closed hull below z = 0.

    The waterplane lid contributes nothing to ∮ z n_z dA, so the open clipped surface suffices.
    Integrals of quadratic functions use the (exact) edge-midpoint rule.
    """
    wet = clip_below(triangles, 0.0)
    if len(wet) == 0:
        raise InputError("hull", "no part of the hull lies below the waterline")
    a = 0.5 * np.cross(wet[:, 1] - wet[:, 0], wet[:, 2] - wet[:, 0])  # area vectors
    area = np.linalg.norm(a, axis=1)
    zc = wet[:, :, 2].mean(axis=1)
    vol = float(np.sum(a[:, 2] * zc))
    mids = 0.5 * (wet + wet[:, [1, 2, 0]])
    xz_mean = np.mean(mids[:, :, 0] * mids[:, :, 2], axis=1)
    mx = float(np.sum(a[:, 2] * xz_mean))
    sign = 1.0 if vol >= 0 else -1.0  # inward normals flip both integrals
    vol, mx = sign * vol, sign * mx
    pts = wet.reshape(-1, 3)
    return Hydrostatics(
        volume_m3=vol,
        wetted_area_m2=float(area.sum()),
        lcb_m=mx / vol if vol > 0 else 0.0,
        lwl_m=float(np.ptp(pts[:, 0])),
        bwl_m=float(np.ptp(pts[:, 1])),
        draught_m=float(-pts[:, 2].min()),
    )


# --------------------------------------------------------------------------------------- surface check
@dataclass(frozen=True)
class SurfaceCheck:
    """Topology of the part of a hull surface that lies below a plane z = ``z_max``.

    An *open* edge belongs to one triangle only (a hole or a gap between patches); a *non-manifold*
    edge to three or more. Either one below the waterline lets snappyHexMesh mesh the inside of the
    hull as well as the outside, and the forces then come from both sides of the skin.
    """

    open_edges: int
    non_manifold_edges: int
    first_defect_m: tuple[float, float, float] | None  # midpoint of one defective edge

    @property
    def closed(self) -> bool:
        return self.open_edges == 0 and self.non_manifold_edges == 0


def check_surface(triangles: np.ndarray, z_max: float = 0.0, tol_m: float | None = None) -> SurfaceCheck:
    """Count open and non-manifold edges with a point below ``z_max`` (vertices merged within ``tol_m``,
    default 10⁻⁶ of the hull's size, since STL files repeat each vertex once per triangle)."""
    tris = np.asarray(triangles, dtype=float)
    pts = tris.reshape(-1, 3)
    if tol_m is None:
        tol_m = 1e-6 * max(float(np.ptp(pts, axis=0).max()), 1e-12)
    _, idx = np.unique(np.round(pts / tol_m).astype(np.int64), axis=0, return_inverse=True)
    idx = idx.reshape(-1, 3)
    edges = np.concatenate([idx[:, [0, 1]], idx[:, [1, 2]], idx[:, [2, 0]]])
    edges.sort(axis=1)
    edges = edges[edges[:, 0] != edges[:, 1]]  # degenerate (sliver) triangles
    uniq, count = np.unique(edges, axis=0, return_counts=True)
    first = np.zeros(len(pts), dtype=np.int64)
    first[idx.ravel()] = np.arange(len(pts))  # one input point per merged vertex
    a, b = pts[first[uniq[:, 0]]], pts[first[uniq[:, 1]]]
    wet = np.minimum(a[:, 2], b[:, 2]) < z_max - tol_m
    open_, multi = wet & (count == 1), wet & (count > 2)
    bad = np.flatnonzero(open_ | multi)
    where = tuple(float(c) for c in 0.5 * (a[bad[0]] + b[bad[0]])) if len(bad) else None
    return SurfaceCheck(int(open_.sum()), int(multi.sum()), where)


# --------------------------------------------------------------------------------------- placement
@dataclass(frozen=True)
class PlacedHull:
    """A hull moved into the case frame, with what was done to it."""

    triangles: np.ndarray
    hydro: Hydrostatics
    shift_m: tuple[float, float, float]  # added to the input coordinates
    mirrored: bool  # a half hull was mirrored about y = 0

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        pts = self.triangles.reshape(-1, 3)
        return pts.min(axis=0), pts.max(axis=0)


def _unit_hint(ratio: float) -> str:
    """A guess at the unit of an STL whose size is ``ratio`` times the particulars given in metres."""
    for factor, unit in ((1000.0, "millimetres"), (100.0, "centimetres"), (25.4, "inches"), (1e-3, "kilometres")):
        if 0.7 * factor <= ratio <= 1.4 * factor:
            return f"the STL looks to be in {unit} while Lpp, Bwl and Tm are in metres: scale it to metres; "
    return "check the STL's units (metres) and "


def place_hull(
    triangles: np.ndarray,
    lpp: float,
    bwl: float,
    tm: float,
    x_ap: float | None = None,
    z_keel: float | None = None,
) -> PlacedHull:
    """Move a hull (bow towards +x, z up, centreline at y = 0) into the case frame.

    ``x_ap`` is the x of the aft perpendicular in the input (default: aft end of the underwater
    hull) and ``z_keel`` the z of the keel (default: lowest point). The waterline is at
    ``z_keel + tm``; midship at ``x_ap + lpp / 2``. A half hull (all y ≥ 0 or all y ≤ 0) is mirrored.
    The checks catch the usual mistakes (millimetres, wrong axis, no freeboard) with a message that
    names the input to fix.
    """
    tris = np.asarray(triangles, dtype=float)
    if tris.ndim != 3 or tris.shape[1:] != (3, 3) or len(tris) < 4:
        raise InputError("hull", "the STL holds fewer than 4 triangles")
    pts = tris.reshape(-1, 3)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    width = hi[1] - lo[1]
    mirrored = False
    if lo[1] >= -1e-6 * max(width, 1e-9) or hi[1] <= 1e-6 * max(width, 1e-9):
        mirror = tris * np.array([1.0, -1.0, 1.0])
        tris = np.concatenate([tris, mirror[:, [0, 2, 1]]])
        mirrored = True
    zk = float(lo[2]) if z_keel is None else float(z_keel)
    z_wl = zk + tm
    key = "tm" if z_keel is None else "z_keel"
    if hi[2] <= z_wl + 1e-3 * tm:
        raise InputError(
            key,
            f"the hull STL must extend above the waterline z = {z_wl:.4g} m (z_keel + tm; the STL's top is "
            f"{hi[2]:.4g} m, so the whole hull would lie below the domain, whose top is the waterline)",
        )
    if lo[2] >= z_wl:
        raise InputError(
            "z_keel",
            f"the hull STL lies wholly above the waterline z = {z_wl:.4g} m (z_keel + tm; the STL's lowest "
            f"point is {lo[2]:.4g} m): nothing is under water",
        )
    # the domain is DOMAIN[2] Lpp deep below the waterline; the keel keeps at least half of it (as tm <= L/2)
    # as water under the hull, or the bottom's symmetry plane sits in the hull's displacement flow
    depth = z_wl - float(lo[2])
    max_depth = -0.5 * DOMAIN[2][0] * lpp
    if depth > max_depth:
        raise InputError(
            key,
            f"the hull reaches {depth:.4g} m below the waterline (z_keel + tm = {z_wl:.4g} m), deeper than "
            f"{max_depth:.4g} m = half the domain's depth of {-DOMAIN[2][0]:g} Lpp: the hull would reach into "
            f"or below the domain's bottom (check z_keel and tm, and that the STL is in metres with z up)",
        )
    under = pts[pts[:, 2] <= z_wl]
    xa = float(under[:, 0].min()) if x_ap is None else float(x_ap)
    shift = (-(xa + 0.5 * lpp), 0.0, -z_wl)
    placed = tris + np.array(shift)
    hydro = hydrostatics(placed)
    ratio = hydro.lwl_m / lpp
    if not 0.8 <= ratio <= 1.3:
        raise InputError(
            "lpp",
            f"underwater length of the STL is {hydro.lwl_m:.4g} m, {ratio:.4g} x Lpp = {lpp:.4g} m "
            f"(allowed 0.8-1.3; {_unit_hint(ratio)}check that the bow points to +x)",
        )
    bratio = hydro.bwl_m / bwl
    if not 0.8 <= bratio <= 1.2:
        raise InputError(
            "bwl",
            f"underwater breadth of the STL is {hydro.bwl_m:.4g} m vs Bwl = {bwl:.4g} m (allowed 0.8-1.2x)",
        )
    surface = check_surface(placed, 0.0)
    if not surface.closed:
        x, y, z = surface.first_defect_m or (0.0, 0.0, 0.0)
        raise InputError(
            "hull",
            f"the STL is not closed below the waterline: {surface.open_edges} open and "
            f"{surface.non_manifold_edges} non-manifold edges (one at x = {x:.4g}, y = {y:.4g}, z = {z:.4g} m "
            "about midship in the waterplane); the mesher would fill the inside of the hull too. "
            "Repair the STL (e.g. surfaceCheck, meshlab) so every edge joins exactly two triangles",
        )
    plo = placed.reshape(-1, 3)[:, 0]
    if plo.min() > -0.3 * lpp or plo.max() < 0.3 * lpp:
        raise InputError("x_ap", f"x_ap = {xa:.4g} m puts midship far from the hull's middle")
    return PlacedHull(placed, hydro, shift, mirrored)
