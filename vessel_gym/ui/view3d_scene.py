"""The 3D viewer's scene: what it draws and how (geometry in the scene frame, the sea surface, colours).

Scene frame: x east, y north, z up, m, origin at the scenario's reference point. What is drawn but not in the
protocol is stated where it is chosen (freeboard, superstructure, heights of land above the water).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from vessel_gym.scenarios.geometry import signed_area
from vessel_gym.ui.chart import depth_colour

CAMERAS = ("chase", "bridge", "top-down", "harbour", "free")
TELEGRAPH_NAMES = {
    -4: "FULL ASTERN",
    -3: "HALF ASTERN",
    -2: "SLOW ASTERN",
    -1: "DEAD SLOW ASTERN",
    0: "STOP",
    1: "DEAD SLOW AHEAD",
    2: "SLOW AHEAD",
    3: "HALF AHEAD",
    4: "FULL AHEAD",
}
G_M_S2 = 9.80665  # standard gravity, m/s^2
SEA_CELLS = 48  # sea grid resolution per side
#: the chase camera: eye this many ship lengths astern and above the ship, looking at a point this far ahead
CHASE_ASTERN_L, CHASE_ABOVE_L, CHASE_AHEAD_L = 2.2, 0.9, 0.8
# Drawing choices (not in the protocol): freeboard as a fraction of the draught (a laden tanker's is about half),
# height of the deckhouse as a fraction of the beam, heights above the water of land, breakwaters and quays (m,
# as multiples of the own ship's draught so that model-scale and full-scale scenes both look right).
FREEBOARD_T = 0.5
DECKHOUSE_B = 0.45
RELIEF_T = {"land": 3.0, "breakwater": 2.0, "quay": 1.5}

COLOURS = {
    "land": (200, 186, 140),
    "breakwater": (140, 140, 140),
    "quay": (105, 105, 112),
    "own": (200, 40, 30),
    "deckhouse": (235, 235, 235),
    "traffic": (230, 140, 0),
    "goal": (40, 170, 60),
    "start": (90, 90, 160),
    "track": (30, 30, 120),
    "sea": (40, 110, 170),
    "wind": (80, 150, 255),
    "current": (60, 200, 120),
    "route": (120, 60, 160),
}


# ---------------------------------------------------------------------------------------------------------------
# Geometry


def triangulate(poly: Sequence[Sequence[float]]) -> list[tuple[int, int, int]]:
    """Ear-clipping triangulation of a simple polygon (either orientation); indices into ``poly``."""
    pts = [(float(p[0]), float(p[1])) for p in poly]
    n = len(pts)
    if n < 3:
        return []
    idx = list(range(n))
    if signed_area(pts) < 0.0:
        idx.reverse()  # counter-clockwise from here on

    def cross(o: int, a: int, b: int) -> float:
        return (pts[a][0] - pts[o][0]) * (pts[b][1] - pts[o][1]) - (pts[a][1] - pts[o][1]) * (
            pts[b][0] - pts[o][0]
        )

    def inside(p: int, a: int, b: int, c: int) -> bool:
        return cross(a, b, p) >= 0.0 and cross(b, c, p) >= 0.0 and cross(c, a, p) >= 0.0

    out: list[tuple[int, int, int]] = []
    guard = 0
    while len(idx) > 3 and guard < 10 * n * n:
        guard += 1
        m = len(idx)
        for i in range(m):
            a, b, c = idx[i - 1], idx[i], idx[(i + 1) % m]
            if cross(a, b, c) <= 0.0:
                continue  # reflex corner
            if any(inside(p, a, b, c) for p in idx if p not in (a, b, c)):
                continue
            out.append((a, b, c))
            del idx[i]
            break
        else:  # degenerate (collinear) rest: fan it
            break
    out += [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]
    return out


def prism(poly_xy: Sequence[Sequence[float]], z0: float, z1: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and faces of ``poly_xy`` (scene x, y) extruded from z0 to z1 (top, bottom and walls)."""
    p = np.asarray(poly_xy, dtype=np.float64).reshape(-1, 2)
    n = len(p)
    verts = np.vstack([np.column_stack([p, np.full(n, z1)]), np.column_stack([p, np.full(n, z0)])])
    faces = []
    for a, b, c in triangulate(p):
        faces.append((a, b, c))
        faces.append((n + a, n + c, n + b))
    for i in range(n):
        j = (i + 1) % n
        faces.append((i, n + i, n + j))
        faces.append((i, n + j, j))
    return verts.astype(np.float32), np.asarray(faces, dtype=np.uint32)


def chart_to_scene(points: Sequence[Sequence[float]]) -> np.ndarray:
    """Chart points [north, east] (m) to scene [x east, y north]."""
    a = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    return a[:, ::-1].copy()


def body_to_scene(outline: Sequence[Sequence[float]]) -> np.ndarray:
    """Body outline [x forward, y starboard] to the ship node's frame [x starboard, y forward] (heading 0)."""
    return chart_to_scene(outline)


def heading_wxyz(hdg_deg: float) -> tuple[float, float, float, float]:
    """Quaternion of a heading (clockwise from north) as a rotation about the scene's z (up) axis."""
    half = -0.5 * math.radians(hdg_deg)
    return (math.cos(half), 0.0, 0.0, math.sin(half))


def attitude_wxyz(hdg_deg: float, roll_deg: float = 0.0) -> tuple[float, float, float, float]:
    """Quaternion of heading and heel: the heel (roll, + = starboard side down) about the ship frame's forward
    axis (+y), then the heading about the scene's z (up) axis. A right-handed turn about +y lowers +x, the
    starboard side, so the heel angle is the rotation angle. The ship frame's origin is on the waterline, so the
    hull heels about it (the drawing's roll axis; the model's is at its centre of gravity)."""
    yw, _, _, yz = heading_wxyz(hdg_deg)
    half = 0.5 * math.radians(roll_deg)
    rw, ry = math.cos(half), math.sin(half)
    # Hamilton product (yw, 0, 0, yz) * (rw, 0, ry, 0)
    return (yw * rw, -yz * ry, yw * ry, yz * rw)


@dataclass
class Mesh:
    """A triangle mesh of the scene: vertices (n, 3) float32 m, faces (m, 3) uint32, colour RGB 0-255."""

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    colour: tuple[int, int, int]
    opacity: float = 1.0

    def as_json(self) -> dict:
        """For a page that draws it itself: rounded to the millimetre, flat lists."""
        return {
            "name": self.name,
            "v": np.round(self.vertices.astype(np.float64), 3).ravel().tolist(),
            "f": self.faces.astype(np.int64).ravel().tolist(),
            "rgb": list(self.colour),
            "opacity": self.opacity,
        }


@dataclass
class HarbourGeometry:
    """The harbour of a ``scenario`` message in the scene frame: its extent (x min, x max, y min, y max, m),
    open-water depth (m), the meshes (sea bed, land, breakwaters, quays, depth slabs, the goal's area), the
    outlines drawn as lines (goal, start: (name, (k, 2, 3) segments, colour)) and the goal's heading arrow."""

    extent: tuple[float, float, float, float]
    depth_m: float
    meshes: list[Mesh] = field(default_factory=list)
    rings: list[tuple[str, np.ndarray, tuple[int, int, int]]] = field(default_factory=list)
    goal_arrow: np.ndarray | None = None  # (2, 3): tail, tip


def harbour_geometry(scene: Mapping, L: float, T: float) -> HarbourGeometry:
    """What the 3D views build of a ``scenario`` message (protocol v2: ``bounds_m``, ``water_depth_m``,
    ``features``) for an own ship of length ``L`` and draught ``T`` (m): land, breakwaters and quays extruded
    from below the deepest bed to RELIEF_T draughts above the water, depth areas as slabs of the sea bed in the
    chart's depth shading, the goal and start outlines and the goal's area and heading."""
    bounds = scene.get("bounds_m")
    if isinstance(bounds, list) and len(bounds) == 4 and all(isinstance(b, (int, float)) for b in bounds):
        n0, n1, e0, e1 = bounds
        extent = (float(e0), float(e1), float(n0), float(n1))
    else:
        s = 40.0 * L
        extent = (-s, s, -s, s)
    depth = float(scene.get("water_depth_m") or 10.0 * T)
    geo = HarbourGeometry(extent, depth)
    x0, x1, y0, y1 = extent
    pad = 0.25 * max(x1 - x0, y1 - y0)
    features = [f for f in scene.get("features") or [] if isinstance(f, Mapping)]
    bed = prism(
        [(x0 - pad, y0 - pad), (x1 + pad, y0 - pad), (x1 + pad, y1 + pad), (x0 - pad, y1 + pad)],
        -depth - 0.05,
        -depth,
    )
    deepest = max([depth] + [float(f.get("depth_m") or 0.0) for f in features])
    geo.meshes.append(Mesh("/chart/seabed", *bed, depth_colour(depth, T, deepest)))
    for f in features:
        pts = f.get("points") or []
        if len(pts) < 3:
            continue
        xy = chart_to_scene(pts)
        kind = f.get("kind")
        name = f"/chart/{kind}_{f.get('id', 0)}"
        if kind in RELIEF_T:
            geo.meshes.append(Mesh(name, *prism(xy, -deepest - 0.1, RELIEF_T[kind] * T), COLOURS[kind]))
        elif kind == "depth":
            # A slab of the sea bed at the charted depth, in the chart's depth shading (sand where it is
            # shallower than the own ship's draught); deeper pockets show as steps of the open-water bed.
            d = float(f.get("depth_m") or 0.0)
            top = -min(d, depth) + 0.01 * T
            geo.meshes.append(Mesh(name, *prism(xy, top - 0.02 * T, top), depth_colour(d, T, deepest)))
        elif kind in ("goal", "start"):
            ring = np.column_stack([xy, np.full(len(xy), 0.05 * T)])
            geo.rings.append((name, np.stack([ring, np.roll(ring, -1, axis=0)], axis=1), COLOURS[kind]))
            if kind == "goal":
                geo.meshes.append(Mesh(name + "_area", *prism(xy, 0.0, 0.02 * T), COLOURS["goal"], 0.35))
                gp, hd = f.get("point_m"), f.get("heading_deg")
                if isinstance(gp, list) and len(gp) == 2 and isinstance(hd, (int, float)):
                    gx, gy, r = gp[1], gp[0], 0.6 * L
                    tip = (gx + r * math.sin(math.radians(hd)), gy + r * math.cos(math.radians(hd)))
                    geo.goal_arrow = np.array([[gx, gy, 0.3 * T], [tip[0], tip[1], 0.3 * T]])
    return geo


def sea_grid(extent: tuple[float, float, float, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The sea surface's grid over ``extent`` and a quarter of its span around it: x, y (SEA_CELLS + 1)^2 m and
    faces (2 SEA_CELLS^2, 3) uint32."""
    x0, x1, y0, y1 = extent
    pad = 0.25 * max(x1 - x0, y1 - y0)
    gx, gy = np.meshgrid(
        np.linspace(x0 - pad, x1 + pad, SEA_CELLS + 1), np.linspace(y0 - pad, y1 + pad, SEA_CELLS + 1)
    )
    m = SEA_CELLS + 1
    i, j = np.meshgrid(np.arange(SEA_CELLS), np.arange(SEA_CELLS))
    a = (j * m + i).ravel()
    faces = np.concatenate([np.column_stack([a, a + 1, a + m + 1]), np.column_stack([a, a + m + 1, a + m])])
    return gx.ravel(), gy.ravel(), faces.astype(np.uint32)


def ship_meshes(pid: int | str, outline: Sequence[Sequence[float]] | None, L: float, B: float, T: float,
                colour: tuple[int, int, int]) -> list[Mesh]:  # fmt: skip
    """A ship's hull (``outline`` in body axes, or the standard hull outline) and deckhouse, ship frame."""
    from vessel_gym.scenarios.geometry import hull_outline

    (hv, hf), (dv, df) = _ship_meshes(outline or hull_outline(L, B), L, B, T or 0.1 * L)
    return [
        Mesh(f"/ship_{pid}/hull", hv, hf, colour),
        Mesh(f"/ship_{pid}/house", dv, df, COLOURS["deckhouse"]),
    ]


def wave_number(omega: float, depth_m: float) -> float:
    """Wave number k (rad/m) of angular frequency omega (rad/s) in water of depth h: omega^2 = g k tanh(k h)
    (linear wave theory), solved by Newton iteration from the deep-water value."""
    k = omega * omega / G_M_S2
    if not depth_m > 0.0:
        return k
    for _ in range(30):
        th = math.tanh(k * depth_m)
        f = G_M_S2 * k * th - omega * omega
        df = G_M_S2 * (th + k * depth_m * (1.0 - th * th))
        step = f / df
        k -= step
        if abs(step) < 1e-12 * k:
            break
    return k


def sea_components(hs_m: float, tp_s: float, from_deg: float, depth_m: float) -> list[tuple[float, ...]]:
    """The sea state drawn for Hs, Tp and the direction waves come from: two long-crested regular components
    (periods Tp and 0.8 Tp, directions 20 deg apart) whose combined variance gives the significant wave height
    Hs = 4 sigma, each (amplitude m, kx, ky rad/m, omega rad/s, phase rad) with elevation
    a sin(kx x + ky y - omega t + phase). A picture of the sea state, not a spectrum: the physics takes its
    wave forces elsewhere. Calm (Hs 0): none."""
    if not hs_m > 0.0:
        return []
    a = 0.25 * hs_m  # two components of amplitude a: variance a^2 = (Hs / 4)^2
    out = []
    for period, dtheta, phase in ((tp_s, 0.0, 0.0), (0.8 * tp_s, 20.0, 1.3)):
        omega = 2.0 * math.pi / period
        k = wave_number(omega, depth_m)
        to = math.radians(from_deg + 180.0 + dtheta)  # waves travel away from where they come from
        out.append((a, k * math.sin(to), k * math.cos(to), omega, phase))
    return out


def sea_elevation(
    x: np.ndarray, y: np.ndarray, t_s: float, hs_m: float, tp_s: float, from_deg: float, depth_m: float
) -> np.ndarray:
    """Surface elevation (m) at scene points (x, y) and time ``t_s`` of :func:`sea_components`."""
    z = np.zeros_like(x)
    for a, kx, ky, omega, phase in sea_components(hs_m, tp_s, from_deg, depth_m):
        z += a * np.sin(kx * x + ky * y - omega * t_s + phase)
    return z


def _ship_meshes(outline: Sequence[Sequence[float]], L: float, B: float, T: float) -> list[tuple]:
    """Hull prism (waterline outline from -T to the freeboard) and a deckhouse aft, in the ship frame."""
    hull = prism(body_to_scene(outline), -T, FREEBOARD_T * T)
    xs = np.array([-0.5 * L + 0.03 * L, -0.5 * L + 0.15 * L])
    house_outline = [(xs[1], 0.4 * B), (xs[0], 0.4 * B), (xs[0], -0.4 * B), (xs[1], -0.4 * B)]
    house = prism(body_to_scene(house_outline), FREEBOARD_T * T, FREEBOARD_T * T + DECKHOUSE_B * B)
    return [hull, house]
