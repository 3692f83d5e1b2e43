"""Plane polygon geometry in local metres (north, east) for validating scenario files.

Plain Python: run once per load. The per-step contact, clearance and range-beam queries of the
environments are compiled (:mod:`vessel_gym.envs.kernels`).
"""

from __future__ import annotations

from collections.abc import Sequence

Point = tuple[float, float]


def _orient(a: Point, b: Point, c: Point) -> float:
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def _on_segment(a: Point, b: Point, p: Point) -> bool:
    return min(a[0], b[0]) <= p[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= p[1] <= max(a[1], b[1])


def segments_intersect(a: Point, b: Point, c: Point, d: Point) -> bool:
    """True if closed segments ab and cd share a point (touching counts)."""
    o1, o2, o3, o4 = _orient(a, b, c), _orient(a, b, d), _orient(c, d, a), _orient(c, d, b)
    if ((o1 > 0 > o2) or (o1 < 0 < o2)) and ((o3 > 0 > o4) or (o3 < 0 < o4)):
        return True
    return (
        (o1 == 0 and _on_segment(a, b, c))
        or (o2 == 0 and _on_segment(a, b, d))
        or (o3 == 0 and _on_segment(c, d, a))
        or (o4 == 0 and _on_segment(c, d, b))
    )


def signed_area(poly: Sequence[Point]) -> float:
    """Shoelace area, m^2 (positive when the vertices run counter-clockwise in the north-east plane)."""
    n = len(poly)
    return 0.5 * sum(poly[i][0] * poly[(i + 1) % n][1] - poly[(i + 1) % n][0] * poly[i][1] for i in range(n))


def centroid(poly: Sequence[Point]) -> Point:
    """Area centroid of a simple polygon."""
    a = signed_area(poly)
    n = len(poly)
    cx = cy = 0.0
    for i in range(n):
        x0, y0 = poly[i]
        x1, y1 = poly[(i + 1) % n]
        w = x0 * y1 - x1 * y0
        cx += (x0 + x1) * w
        cy += (y0 + y1) * w
    return (cx / (6.0 * a), cy / (6.0 * a))


def self_intersection(poly: Sequence[Point]) -> tuple[int, int] | None:
    """Indices (i, j) of the first pair of non-adjacent edges that meet, or None for a simple polygon."""
    n = len(poly)
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        for j in range(i + 1, n):
            if j == i or (j + 1) % n == i or j == (i + 1) % n:
                continue
            if segments_intersect(a, b, poly[j], poly[(j + 1) % n]):
                return (i, j)
    return None


def point_in_polygon(p: Point, poly: Sequence[Point]) -> bool:
    """Crossing-number test (a point on the boundary may fall either way)."""
    x, y = p
    inside = False
    n = len(poly)
    for i in range(n):
        x0, y0 = poly[i]
        x1, y1 = poly[(i + 1) % n]
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside


def polygons_overlap(p: Sequence[Point], q: Sequence[Point]) -> bool:
    """True if two simple polygons share any point (edges cross or one contains the other)."""
    for i in range(len(p)):
        for j in range(len(q)):
            if segments_intersect(p[i], p[(i + 1) % len(p)], q[j], q[(j + 1) % len(q)]):
                return True
    return point_in_polygon(p[0], q) or point_in_polygon(q[0], p)


def hull_outline(L_m: float, B_m: float) -> list[Point]:
    """Waterline outline in body axes (x forward, y starboard), m: pointed bow, parallel body, square stern."""
    return [
        (0.5 * L_m, 0.0),
        (0.3 * L_m, 0.5 * B_m),
        (-0.5 * L_m, 0.5 * B_m),
        (-0.5 * L_m, -0.5 * B_m),
        (0.3 * L_m, -0.5 * B_m),
    ]
