"""The harbour chart as the compiled task reads it: contact, grounding, clearance and range beams of a ship among
chart polygons (:func:`chart_query` over the tables of :func:`chart_tables`), the outcome flags of an episode, and
the charted depth under each ship (:func:`chart_depth` over the tables of :func:`depth_tables`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from vessel_gym.envs.declare import columns
from vessel_gym.physics.kinematics import body_point_to_earth, body_to_earth
from vessel_gym.physics.shallow_water import set_charted_depth
from vessel_gym.scenarios import Scenario

#: outcome of a HarbourApproach step (flags as integers in the kernels, names in ``info["outcome"]``)
OUTCOME = columns(
    "running", "success", "contact", "grounding", "out_of_bounds", "diverged", typename="Outcome"
)
OUTCOMES = OUTCOME._fields
OK = OUTCOME.running
SUCCESS = OUTCOME.success
CONTACT = OUTCOME.contact
GROUNDING = OUTCOME.grounding
OUT_OF_BOUNDS = OUTCOME.out_of_bounds
DIVERGED = OUTCOME.diverged


# Helpers that take arrays are inlined where they are called (inline="always"): a call to a compiled function
# with array arguments keeps numba from pruning the caller's reference counts, an atomic increment and
# decrement per array per call (the chart query paid 16 of them per ship).
@njit(cache=True)
def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


@njit(cache=True)
def _seg_intersect(ax, ay, bx, by, cx, cy, dx, dy):
    d1 = _cross(bx - ax, by - ay, cx - ax, cy - ay)
    d2 = _cross(bx - ax, by - ay, dx - ax, dy - ay)
    d3 = _cross(dx - cx, dy - cy, ax - cx, ay - cy)
    d4 = _cross(dx - cx, dy - cy, bx - cx, by - cy)
    return ((d1 > 0.0) != (d2 > 0.0)) and ((d3 > 0.0) != (d4 > 0.0))


@njit(cache=True)
def _point_seg_dist2(px, py, ax, ay, bx, by):
    """Squared distance from point p to segment ab, m^2 (callers take one sqrt of the minimum)."""
    ex = bx - ax
    ey = by - ay
    ll = ex * ex + ey * ey
    t = 0.0 if ll == 0.0 else ((px - ax) * ex + (py - ay) * ey) / ll
    t = min(max(t, 0.0), 1.0)  # min/max, not branches: which end clamps varies from call to call
    qx = ax + t * ex - px
    qy = ay + t * ey - py
    return qx * qx + qy * qy


@njit(cache=True, inline="always")
def inside_polygon(px, py, xs, ys, start, count):
    """Point (px, py) inside the polygon of vertices (xs, ys)[start : start + count] (even-odd rule)."""
    inside = False
    x0 = xs[start + count - 1]  # each edge runs from the previous vertex (no modulo per vertex)
    y0 = ys[start + count - 1]
    for i in range(start, start + count):
        x1 = xs[i]
        y1 = ys[i]
        if (y0 > py) != (y1 > py) and px < x0 + (py - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
        x0 = x1
        y0 = y1
    return inside


def chart_tables(polygons: list[tuple[int, list]]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The chart as :func:`chart_query` reads it, from (kind, [(north, east), ...]) polygons (kind 1 hard
    obstacle, 2 shoal): three arrays, because every array argument of a compiled call costs a little.

    ``edges`` (n_vertices, 6): vertex (north, east), then the bounding box (n min, n max, e min, e max) of
    the edge from it to the next vertex of its polygon; ``polys`` (n_polygons, 4) int: first vertex row,
    vertex count, kind, orientation (+1 if the vertices run anticlockwise in (north, east) axes, i.e. the
    interior lies left of each edge, else -1); ``pbox`` (n_polygons, 4): each polygon's bounding box.
    """
    verts = np.array([p for _k, pts in polygons for p in pts], dtype=np.float64).reshape(-1, 2)
    count = np.array([len(pts) for _k, pts in polygons], dtype=np.int64)
    start = np.concatenate([[0], np.cumsum(count)[:-1]]).astype(np.int64) if polygons else count
    kind = np.array([k for k, _p in polygons], dtype=np.int64)
    polys = np.stack([start, count, kind, np.ones_like(count)], axis=1)
    edges = np.zeros((verts.shape[0], 6))
    pbox = np.zeros((len(polygons), 4))
    for q, (st, cnt) in enumerate(zip(start, count)):
        a = verts[st : st + cnt]
        b = np.roll(a, -1, axis=0)
        edges[st : st + cnt, 0:2] = a
        edges[st : st + cnt, 2] = np.minimum(a[:, 0], b[:, 0])
        edges[st : st + cnt, 3] = np.maximum(a[:, 0], b[:, 0])
        edges[st : st + cnt, 4] = np.minimum(a[:, 1], b[:, 1])
        edges[st : st + cnt, 5] = np.maximum(a[:, 1], b[:, 1])
        pbox[q] = a[:, 0].min(), a[:, 0].max(), a[:, 1].min(), a[:, 1].max()
        area2 = float(np.sum(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]))  # shoelace: twice the signed area
        polys[q, 3] = 1 if area2 > 0.0 else -1
    return edges, polys.reshape(-1, 4), pbox


@njit(cache=True, inline="always")
def _box_gap2(n0, n1, e0, e1, table, row, col):
    """Squared distance between the box [n0, n1] x [e0, e1] and the box (n min, n max, e min, e max) in
    ``table[row, col : col + 4]``, m^2 (read in place: a row view would cost a reference count)."""
    gn = max(table[row, col] - n1, n0 - table[row, col + 1], 0.0)
    ge = max(table[row, col + 2] - e1, e0 - table[row, col + 3], 0.0)
    return gn * gn + ge * ge


@njit(cache=True)
def _reach2(cull2, rh):
    """Squared distance from the midship point beyond which an edge cannot come within sqrt(cull2) of a hull
    of radius ``rh`` about that point, m^2; widened by 1e-9 relative so that rounding never skips an edge
    that holds the minimum."""
    r = (math.sqrt(cull2) + rh) * (1.0 + 1e-9)
    return r * r


@njit(cache=True, error_model="numpy")
def chart_query(n0, e0, psi, hull, edges, polys, pbox, beam_dirs, beam_range, beams, hn, he, bw):
    """Contact, grounding, clearance and range beams of one ship at (n0, e0, psi) among chart polygons.

    ``hull``: outline in body axes (x forward, y starboard), m. ``edges``, ``polys``, ``pbox``: the chart
    (:func:`chart_tables`).
    ``beam_dirs``: (n_beams, 2) unit vectors of the beams in body axes (x forward, y starboard).
    Fills ``beams`` (m, capped at ``beam_range``) measured from the midship point; returns
    (outcome flag OK/CONTACT/GROUNDING, clearance m = distance hull outline to the nearest polygon edge).
    ``hn``, ``he``: scratch arrays of the hull's length; ``bw``: scratch of shape (2, n_beams). Compiled
    with numpy's floating-point error model: a division by zero gives inf or nan (no exception check in the
    beam loop, so that it vectorises).

    The beams go first, then contact and clearance. Polygons and edges whose bounding box is farther than
    the beam range (beams) or than the clearance found so far are skipped: the distance to a box bounds the
    distance to what is inside it. The nearest beam hit t bounds the clearance from above by t + the hull's
    radius about the midship point (the hit lies on an edge, every hull vertex within that radius of the
    midship point), so that the clearance pass skips, from its start, the polygons and edges farther than
    that, and gives the vertex-to-segment distances only to the few edges near the nearest one. Skipping only
    what cannot be nearer, the results are those of testing every edge.
    """
    c = math.cos(psi)
    s = math.sin(psi)
    nh = hull.shape[0]
    hb0 = hb1 = hb2 = hb3 = 0.0  # the hull's box
    rh2 = 0.0  # squared radius of the hull about the midship point
    for i in range(nh):
        x = hull[i, 0]
        y = hull[i, 1]
        hn[i], he[i] = body_point_to_earth(n0, e0, c, s, x, y)
        if i == 0:
            hb0 = hb1 = hn[0]
            hb2 = hb3 = he[0]
        hb0 = min(hb0, hn[i])  # min/max, not branches: which vertex is extreme depends on the heading
        hb1 = max(hb1, hn[i])
        hb2 = min(hb2, he[i])
        hb3 = max(hb3, he[i])
        rh2 = max(rh2, x * x + y * y)
    rh = math.sqrt(rh2)
    nb = beams.shape[0]
    for j in range(nb):
        x = beam_dirs[j, 0]
        y = beam_dirs[j, 1]
        beams[j] = beam_range
        bw[0, j], bw[1, j] = body_to_earth(c, s, x, y)  # beam direction (north, east)
    npoly = polys.shape[0]
    vn = edges[:, 0]
    ve = edges[:, 1]
    range2 = beam_range * beam_range

    # Range beams from the midship point o. A ray from outside a polygon meets it first on an edge that faces
    # o (it enters there), so edges that face away are skipped, unless o is inside this polygon (aground or
    # in contact).
    for q in range(npoly):
        pgap2 = _box_gap2(n0, n0, e0, e0, pbox, q, 0)
        if pgap2 >= range2:
            continue
        st = polys[q, 0]
        cnt = polys[q, 1]
        orient = polys[q, 3]
        inside = pgap2 == 0.0 and inside_polygon(n0, e0, vn, ve, st, cnt)
        r = st + cnt - 1  # edge r -> m (its box is in row r): the closing edge first, no modulo per edge
        for m in range(st, st + cnt):
            ax = vn[r]
            ay = ve[r]
            ex = vn[m] - ax
            ey = ve[m] - ay
            aon = ax - n0
            aoe = ay - e0
            tn = _cross(aon, aoe, ex, ey)  # o is on the interior side of the edge's line if orient * tn > 0
            if (inside or orient * tn <= 0.0) and _box_gap2(n0, n0, e0, e0, edges, r, 2) < range2:
                for j in range(nb):
                    # ray o + t d meets a + s e at t = (a - o) x e / (d x e), s = (a - o) x d / (d x e);
                    # 0 <= s <= 1 is tested on the numerator against the denominator (sign-aware), so one
                    # division per beam. Branch-free so that the beams run in SIMD lanes: d x e = 0 gives
                    # inf or nan (no hit); fmin, not a conditional store, because a conditional store
                    # vectorises to a masked store, slow and not forwarded to the next edge's loads.
                    dn = bw[0, j]
                    de = bw[1, j]
                    den = _cross(dn, de, ex, ey)
                    t = tn / den
                    sn = _cross(aon, aoe, dn, de)
                    sn = sn if den > 0.0 else -sn
                    hit = (t >= 0.0) & (sn >= 0.0) & (sn <= abs(den))
                    beams[j] = np.fmin(beams[j], t if hit else np.inf)
            r = m

    # contact and clearance
    flag = OK
    clear2 = range2  # squared clearance so far
    bmin = beam_range
    for j in range(nb):
        bmin = min(bmin, beams[j])
    near = (bmin + rh) * (1.0 + 1e-9)  # every hull vertex is at most this far from the nearest hit (if any)
    cull2 = min(clear2, near * near)  # the clearance is at most this: farther polygons and edges are skipped
    reach2 = _reach2(cull2, rh)
    for q in range(npoly):
        st = polys[q, 0]
        cnt = polys[q, 1]
        gap2 = _box_gap2(hb0, hb1, hb2, hb3, pbox, q, 0)
        if gap2 == 0.0:  # the boxes overlap: does the hull touch the polygon?
            hit = False
            r = st + cnt - 1
            for m in range(st, st + cnt):
                if _box_gap2(hb0, hb1, hb2, hb3, edges, r, 2) == 0.0:  # else it cannot cross the hull
                    i2 = nh - 1
                    for i in range(nh):
                        if _seg_intersect(hn[i2], he[i2], hn[i], he[i], vn[r], ve[r], vn[m], ve[m]):
                            hit = True
                            break
                        i2 = i
                    if hit:
                        break
                r = m
            # no crossing: each outline lies wholly inside or wholly outside the other
            hit = (
                hit
                or inside_polygon(hn[0], he[0], vn, ve, st, cnt)
                or inside_polygon(vn[st], ve[st], hn, he, 0, nh)
            )
            if hit:
                clear2 = cull2 = 0.0
                if polys[q, 2] == 1:
                    flag = CONTACT
                elif flag == OK:
                    flag = GROUNDING
        if gap2 < cull2:  # (cull2 <= clear2: the box test of testing every edge is included)
            r = st + cnt - 1
            for m in range(st, st + cnt):
                ax = vn[r]
                ay = ve[r]
                bx = vn[m]
                by = ve[m]
                # an edge farther than reach from o is farther than sqrt(cull2) from the hull
                if (
                    _box_gap2(hb0, hb1, hb2, hb3, edges, r, 2) < cull2
                    and _point_seg_dist2(n0, e0, ax, ay, bx, by) <= reach2
                ):
                    # the distance between the outlines is that between a vertex of one and an edge of the
                    # other; vertex a's distances to the hull's edges only if a is within reach
                    near_a = (ax - n0) * (ax - n0) + (ay - e0) * (ay - e0) <= reach2
                    i2 = nh - 1
                    for i in range(nh):
                        clear2 = min(clear2, _point_seg_dist2(hn[i], he[i], ax, ay, bx, by))
                        if near_a:
                            clear2 = min(clear2, _point_seg_dist2(ax, ay, hn[i2], he[i2], hn[i], he[i]))
                        i2 = i
                    if clear2 < cull2:
                        cull2 = clear2
                        reach2 = _reach2(cull2, rh)
                r = m
    return flag, math.sqrt(clear2)


@njit(cache=True)
def poses_clear(n0, e0, psi, xs, ys, hull, edges, polys, pbox, beam_dirs, beam_range):
    """Per candidate pose j: inside the polygon (xs, ys) (a start region) and clear of the chart (its
    :func:`chart_query` outcome OK), for many candidates in one call (the start rejection of a batch reset)."""
    m = n0.shape[0]
    ok = np.zeros(m, dtype=np.bool_)
    beams = np.empty(beam_dirs.shape[0])
    hn = np.empty(hull.shape[0])
    he = np.empty(hull.shape[0])
    bw = np.empty((2, beam_dirs.shape[0]))
    for j in range(m):
        if inside_polygon(n0[j], e0[j], xs, ys, 0, xs.shape[0]):
            flag, _c = chart_query(
                n0[j], e0[j], psi[j], hull, edges, polys, pbox, beam_dirs, beam_range, beams, hn, he, bw
            )
            ok[j] = flag == OK
    return ok


def depth_tables(scenario: Scenario) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The chart's depth areas as :func:`chart_depth` reads them, shallowest first (so that the first area
    containing a point is the shallowest, :meth:`Scenario.depth_at`'s rule): ``verts`` (n_vertices, 2)
    (north, east) m; ``areas`` (n_areas, 2) int: first vertex row, vertex count; ``area`` (n_areas, 5): depth m,
    then the bounding box (north min, north max, east min, east max) m."""
    ds = sorted(scenario.depth_area, key=lambda d: d.depth_m)  # stable: equal depths keep the file's order
    pts = [np.array([(p[0], p[1]) for p in d.points], dtype=np.float64).reshape(-1, 2) for d in ds]
    verts = np.concatenate(pts) if pts else np.zeros((0, 2))
    count = np.array([len(a) for a in pts], dtype=np.int64)
    start = np.concatenate([[0], np.cumsum(count)[:-1]]).astype(np.int64) if pts else count
    areas = np.stack([start, count], axis=1).reshape(-1, 2)
    area = np.array(
        [(d.depth_m, a[:, 0].min(), a[:, 0].max(), a[:, 1].min(), a[:, 1].max()) for d, a in zip(ds, pts)],
        dtype=np.float64,
    ).reshape(-1, 5)
    return verts, areas, area


@njit(cache=True)
def chart_depth(north, east, verts, areas, area, water_depth, T, depth, env):
    """For each vessel k: ``depth[k]`` the charted depth (m) under its midship point (``north[k]``,
    ``east[k]``): the first (shallowest) depth area containing it, else ``water_depth``; and that depth in the
    physics' environment row ``env[k]`` for a ship of draught ``T`` (m), by
    :func:`~vessel_gym.physics.shallow_water.set_charted_depth`: the Taimuri et al. (2020) corrections hold for
    h/T >= 1.2, so water between the draught and 1.2 T acts as h/T = 1.2, as does a point over a shoal (the
    task's grounding rule ends that episode)."""
    xs = verts[:, 0]
    ys = verts[:, 1]
    for k in range(north.shape[0]):
        n = north[k]
        e = east[k]
        h = water_depth
        for a in range(areas.shape[0]):
            if area[a, 1] <= n <= area[a, 2] and area[a, 3] <= e <= area[a, 4]:
                if inside_polygon(n, e, xs, ys, areas[a, 0], areas[a, 1]):
                    h = area[a, 0]
                    break
        depth[k] = h
        set_charted_depth(env, k, h, T)
