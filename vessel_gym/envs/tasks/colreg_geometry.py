"""The geometry of an encounter between two ships: the contact of their hull outlines (the chart's pointed-bow
outline, ``vessel_gym.scenarios.geometry.hull_outline``), the closest point of approach, relative bearings and the COLREG situation (rules 13-15) of a target at detection.

Frames (docs/colreg.md, "Frame convention"): earth-fixed x north, y east; heading psi clockwise from north;
body x forward, y starboard. A *relative bearing* is measured clockwise from the own ship's bow, in [0, 2 pi):
a target fine on the starboard bow has a small positive bearing, sin(bearing) > 0 to starboard.
Plain Python on scalars: an encounter has a handful of ships.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from vessel_gym.control.angles import wrap_pi
from vessel_gym.physics.kinematics import body_point_to_earth
from vessel_gym.scenarios.geometry import Point, polygons_overlap

#: the situations of a target for the own ship, as classified at detection (rules 13-15, 17)
SAFE, HEAD_ON, OVERTAKING, GIVE_WAY, STAND_ON, OVERTAKEN = range(6)
SITUATIONS = ("safe", "head_on", "overtaking", "give_way", "stand_on", "overtaken")
#: situations in which the own ship keeps out of the way (rules 13, 14, 15); in the others it stands on (17)
GIVE_WAY_ROLES = (HEAD_ON, OVERTAKING, GIVE_WAY)
STAND_ON_ROLES = (STAND_ON, OVERTAKEN)

#: rule 13(b): overtaking is coming up from more than 22.5 deg abaft the beam, i.e. within 67.5 deg of the stern
ABAFT_BEAM = math.radians(112.5)  # rad, relative bearing where the stern sector starts
#: rule 14: "reciprocal or nearly reciprocal courses", each ship seeing the other ahead ("masthead lights in
#: line or nearly in line"); the half-width is a choice (the rule gives no number), 6 deg as widely used
HEAD_ON_HALF_WIDTH = math.radians(6.0)  # rad


def place(outline: Sequence[Point], n: float, e: float, psi: float) -> list[Point]:
    """A body-frame outline (``vessel_gym.scenarios.geometry.hull_outline``) on the chart (north, east, m) for a
    ship with its midship point at (``n``, ``e``) heading ``psi`` (rad)."""
    c, s = math.cos(psi), math.sin(psi)
    return [body_point_to_earth(n, e, c, s, x, y) for x, y in outline]


def hulls_touch(a: Sequence[Point], b: Sequence[Point]) -> bool:
    """Whether two hull outlines on the chart touch: they share a point (edges meet or one contains the
    other, ``vessel_gym.scenarios.geometry.polygons_overlap``)."""
    return polygons_overlap(a, b)


def cpa(pn: float, pe: float, wn: float, we: float) -> tuple[float, float]:
    """(DCPA, m; TCPA, s) of a target at relative position (``pn``, ``pe``) (target - own, m) moving with
    relative velocity (``wn``, ``we``) (target - own, m/s), both keeping course and speed. An opening
    target (TCPA < 0) has its closest point behind it: DCPA is then the present range."""
    w2 = wn * wn + we * we
    t = -(pn * wn + pe * we) / w2 if w2 > 1e-12 else 0.0
    if t <= 0.0:
        return math.hypot(pn, pe), t
    return math.hypot(pn + wn * t, pe + we * t), t


def relative_bearing(pn: float, pe: float, psi: float) -> float:
    """Bearing of the relative position (``pn``, ``pe``) from a bow heading ``psi``, clockwise, in [0, 2 pi)."""
    return (math.atan2(pe, pn) - psi) % (2.0 * math.pi)


def classify(pn: float, pe: float, psi_o: float, psi_t: float, closing: bool) -> int:
    """The situation of a target (relative position (``pn``, ``pe``) = target - own, m; headings ``psi_o``
    own, ``psi_t`` target, rad) for the own ship, given that there is a risk of collision (``closing``:
    the target approaches within the risk distance; otherwise SAFE).

    Overtaking (rule 13): the own ship bears more than 22.5 deg abaft the target's beam; overtaken: the target
    bears so from the own ship. Head-on (rule 14): each bears within HEAD_ON_HALF_WIDTH of the other's bow.
    Crossing (rule 15): the ship that has the other on its starboard side gives way; else it stands on.
    """
    if not closing:
        return SAFE
    beta = relative_bearing(pn, pe, psi_o)  # the target seen from the own ship
    alpha = relative_bearing(-pn, -pe, psi_t)  # the own ship seen from the target
    if ABAFT_BEAM < alpha < 2.0 * math.pi - ABAFT_BEAM:
        return OVERTAKING
    if ABAFT_BEAM < beta < 2.0 * math.pi - ABAFT_BEAM:
        return OVERTAKEN
    if abs(wrap_pi(beta)) <= HEAD_ON_HALF_WIDTH and abs(wrap_pi(alpha)) <= HEAD_ON_HALF_WIDTH:
        return HEAD_ON
    return GIVE_WAY if beta < math.pi else STAND_ON


#: rays cast per sector of the range-sensor sweep (the sector reports their smallest range)
RAYS_PER_SECTOR = 5


def sweep_bearings(sectors: int) -> np.ndarray:
    """Relative bearings (rad, clockwise from the bow) of the sweep's rays, sector by sector: sector i is
    centred on i x 360 / ``sectors`` deg (sector 0 dead ahead) and its RAYS_PER_SECTOR rays spread evenly over
    its width."""
    w = 2.0 * math.pi / sectors
    offsets = (np.arange(RAYS_PER_SECTOR) + 0.5) / RAYS_PER_SECTOR * w - 0.5 * w
    return (np.arange(sectors)[:, None] * w + offsets[None, :]).ravel()


def polygon_edges(polys: Sequence[Sequence[Point]]) -> np.ndarray:
    """The edges of closed polygons as rows (a_n, a_e, b_n, b_e), m."""
    rows = [(*p[i], *p[(i + 1) % len(p)]) for p in polys for i in range(len(p))]
    return np.array(rows, dtype=np.float64).reshape(-1, 4)


def sweep(
    n: float, e: float, psi: float, bearings: np.ndarray, edges: np.ndarray, max_range: float
) -> np.ndarray:
    """Range (m) along each ray from (``n``, ``e``) at relative ``bearings`` (rad, from the bow ``psi``) to the
    nearest of ``edges`` (rows a_n, a_e, b_n, b_e; land, shoals and hull outlines), ``max_range`` where a ray
    meets none within it. Ray-segment intersection: o + t d = a + s (b - a), t >= 0, 0 <= s <= 1."""
    out = np.full(len(bearings), max_range)
    if not len(edges):
        return out
    c = psi + bearings
    dn, de = np.cos(c)[:, None], np.sin(c)[:, None]
    an, ae = edges[:, 0] - n, edges[:, 1] - e  # a - o
    sn, se = edges[:, 2] - edges[:, 0], edges[:, 3] - edges[:, 1]  # b - a
    denom = dn * se - de * sn  # cross(d, b - a)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (an * se - ae * sn) / denom  # cross(a - o, b - a) / denom
        s = (an * de - ae * dn) / denom  # cross(a - o, d) / denom
    hit = (np.abs(denom) > 1e-12) & (t >= 0.0) & (s >= 0.0) & (s <= 1.0)
    return np.minimum(np.where(hit, t, max_range).min(axis=1), max_range)


def sector_minima(ranges: np.ndarray, sectors: int) -> np.ndarray:
    """The smallest range of each sector's rays (``sweep`` over ``sweep_bearings(sectors)``)."""
    return ranges.reshape(sectors, RAYS_PER_SECTOR).min(axis=1)
