"""Plane polygon geometry in local metres (north, east) for validating scenario files.

Plain Python: run once per load; the polygon checks are O(n log n) sweeps, so a chart with
thousands of vertices per polygon loads in well under a second. The per-step contact, clearance and range-beam queries of the
environments are compiled (:mod:`vessel_gym.envs.tasks.chart`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

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


def _first_meeting(
    segs: Sequence[tuple[Point, Point]], exempt: Callable[[int, int], bool]
) -> tuple[int, int] | None:
    """A pair (i, j) of segments that share a point, or None; pairs with ``exempt(i, j)`` are not counted.

    Shamos & Hoey (1976) sweep, O(n log n) comparisons: events are the segments' end points in lexicographic
    order; the segments cut by the sweep are kept sorted from bottom to top, and a new neighbour pair is
    tested whenever a segment enters or leaves. The leftmost meeting point of any two segments is found
    before the sweep passes it (its two segments are neighbours just before it), so the sweep stops there
    and the order is never needed past a meeting. Touching counts as meeting. Exempt pairs may only meet
    at a common end point (adjacent edges of one simple polygon; the two polygons' own edges in an overlap
    test); they are ordered by direction there. Precondition: no two non-exempt segments share an end point
    (the callers test for common vertices first, by sorting or hashing), since segments ending at a point
    leave the sweep before those starting there enter.
    """
    n = len(segs)
    lft: list[Point] = []
    rgt: list[Point] = []
    for a, b in segs:
        lo_, hi_ = (a, b) if a <= b else (b, a)
        lft.append(lo_)
        rgt.append(hi_)
    # (x, y, dx, dy) of each segment from its left end, for the orientation test of the inner loops
    geom = [(a[0], a[1], b[0] - a[0], b[1] - a[1]) for a, b in zip(lft, rgt)]
    # removals (0) before insertions (1) at the same point: an edge ending where its neighbour begins
    events = sorted([(rgt[i], 0, i) for i in range(n)] + [(lft[i], 1, i) for i in range(n)])
    status: list[int] = []  # segments cut by the sweep, bottom to top

    def meet(i: int, j: int) -> bool:
        if exempt(i, j):
            return False
        return segments_intersect(lft[i], rgt[i], lft[j], rgt[j])

    def side(t: int, px: float, py: float) -> float:  # > 0: p above segment t, < 0: below, 0: on it
        ax, ay, dx, dy = geom[t]
        return dx * (py - ay) - dy * (px - ax)  # _orient(lft[t], rgt[t], p)

    for p, kind, s in events:
        px, py = p
        if kind == 1:
            lo_, hi_ = 0, len(status)
            while lo_ < hi_:
                mid = (lo_ + hi_) // 2
                t = status[mid]
                ax, ay, dx, dy = geom[t]
                o = dx * (py - ay) - dy * (px - ax)  # side(t, px, py), inlined: the sweep's inner loop
                if o == 0.0:  # p lies on t
                    if not exempt(s, t) or p != lft[t]:
                        return (min(s, t), max(s, t))
                    o = _orient(p, rgt[t], rgt[s])  # both start at p: order by direction
                    if o == 0.0:  # collinear and overlapping
                        return (min(s, t), max(s, t))
                if o > 0.0:
                    lo_ = mid + 1
                else:
                    hi_ = mid
            status.insert(lo_, s)
            for k in (lo_ - 1, lo_ + 1):
                if 0 <= k < len(status) and meet(s, status[k]):
                    return (min(s, status[k]), max(s, status[k]))
        else:
            lo_, hi_ = 0, len(status)
            while lo_ < hi_:  # first segment that p is not above
                mid = (lo_ + hi_) // 2
                ax, ay, dx, dy = geom[status[mid]]
                if dx * (py - ay) - dy * (px - ax) > 0.0:  # side(), inlined
                    lo_ = mid + 1
                else:
                    hi_ = mid
            k = lo_
            pos = -1
            while k < len(status) and side(status[k], px, py) == 0.0:  # every active segment through p
                t = status[k]
                if t == s:
                    pos = k
                elif not exempt(s, t):
                    return (min(s, t), max(s, t))
                k += 1
            if pos < 0:  # pragma: no cover - the order is consistent until a meeting is found
                pos = status.index(s)
            del status[pos]
            if 0 < pos < len(status) and meet(status[pos - 1], status[pos]):
                return (min(status[pos - 1], status[pos]), max(status[pos - 1], status[pos]))
    return None


def repeated_vertex(poly: Sequence[Point]) -> tuple[int, int] | None:
    """Indices (i, j), i < j, of two equal vertices, or None (sorting: O(n log n))."""
    order = sorted(range(len(poly)), key=lambda i: poly[i])
    for a, b in zip(order, order[1:]):
        if poly[a] == poly[b]:
            return (min(a, b), max(a, b))
    return None


def self_intersection(poly: Sequence[Point]) -> tuple[int, int] | None:
    """Indices (i, j) of two non-adjacent edges that meet (edge i runs from vertex i to i + 1), or None
    for a simple polygon. A repeated vertex counts: the edges leaving both copies meet there.
    O(n log n) (:func:`_first_meeting`)."""
    n = len(poly)
    rep = repeated_vertex(poly)
    if rep is not None:
        return rep
    if n < 4:
        return None
    segs = [(poly[i], poly[(i + 1) % n]) for i in range(n)]
    return _first_meeting(segs, lambda i, j: abs(i - j) in (1, n - 1))


def point_in_polygon(p: Point, poly: Sequence[Point]) -> bool:
    """Crossing-number test (a point on the boundary may fall either way); vectorised over the edges."""
    x, y = p
    v = np.asarray(poly, dtype=float).reshape(-1, 2)
    x0, y0 = v[:, 0], v[:, 1]
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    crosses = (y0 > y) != (y1 > y)  # the edge spans the horizontal through p (never a horizontal edge)
    x0, y0, x1, y1 = x0[crosses], y0[crosses], x1[crosses], y1[crosses]
    return bool(np.count_nonzero(x < x0 + (y - y0) * (x1 - x0) / (y1 - y0)) % 2)


def segment_meets_polygon(a: Point, b: Point, poly: Sequence[Point]) -> bool:
    """True if segment ab shares a point with an edge of ``poly``. Edges whose bounding box misses the
    segment's are skipped in one vectorised pass; the rest are tested exactly (:func:`segments_intersect`)."""
    v = np.asarray(poly, dtype=float).reshape(-1, 2)
    w = np.roll(v, -1, axis=0)
    lo_, hi_ = np.minimum(v, w), np.maximum(v, w)
    near = (
        (hi_[:, 0] >= min(a[0], b[0]))
        & (lo_[:, 0] <= max(a[0], b[0]))
        & (hi_[:, 1] >= min(a[1], b[1]))
        & (lo_[:, 1] <= max(a[1], b[1]))
    )
    n = len(poly)
    return any(segments_intersect(a, b, poly[i], poly[(i + 1) % n]) for i in np.flatnonzero(near).tolist())


def _bbox(poly: Sequence[Point]) -> tuple[float, float, float, float]:
    xs = [p[0] for p in poly]
    ys = [p[1] for p in poly]
    return (min(xs), max(xs), min(ys), max(ys))


def polygons_overlap(p: Sequence[Point], q: Sequence[Point]) -> bool:
    """True if two simple polygons share any point (edges meet or one contains the other).

    O((n + m) log(n + m)): one sweep over the edges of both (:func:`_first_meeting`), the edges of one
    polygon exempt from each other (each polygon is simple)."""
    bp, bq = _bbox(p), _bbox(q)
    if bp[1] < bq[0] or bq[1] < bp[0] or bp[3] < bq[2] or bq[3] < bp[2]:
        return False
    if not set(map(tuple, p)).isdisjoint(map(tuple, q)):  # a common vertex (the sweep's precondition)
        return True
    n = len(p)
    segs = [(p[i], p[(i + 1) % n]) for i in range(n)] + [(q[j], q[(j + 1) % len(q)]) for j in range(len(q))]
    if _first_meeting(segs, lambda i, j: (i < n) == (j < n)) is not None:
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
