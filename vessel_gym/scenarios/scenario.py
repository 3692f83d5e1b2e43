"""Scenario files: harbour geometry, start and goal regions, ship and weather ranges as data.

A scenario is one TOML file, loaded strictly by the schema loader shared with ship files (unknown keys,
wrong types and out-of-range values are one-line errors naming the file and the key) and then checked
geometrically: polygons must be simple (not self-intersecting), the goal and start regions must be in
navigable water inside the chart bounds. Coordinates are local metres about the geodetic reference point:
``[north, east]`` pairs. Format reference: docs/scenarios.md.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from vessel_gym.physics.components.fenders import FenderParams
from vessel_gym.physics.components.tug import TugParams
from vessel_gym.physics.schema import SpecError, build, builtin_names, param, read_toml, resolve_data_path
from vessel_gym.physics.shipfile import Ship, load_ship
from vessel_gym.scenarios import geometry as geo

SCENARIO_DIR = Path(__file__).parent

#: size bound of a scenario file, bytes: room for charts of some 100,000 vertices (the built-in harbour is
#: under 10 kB); larger files are refused unread
MAX_SCENARIO_FILE_BYTES = 4 << 20

#: obstacle kinds in the order used by the compiled kernels and the renderer
HARD_KINDS = ("land", "breakwater", "quay")


class ScenarioError(SpecError):
    """A scenario file is invalid; the message is one line naming the file and the key."""


@dataclass(frozen=True, kw_only=True)
class Area:
    """A named polygon (land, breakwater, quay)."""

    name: str = param("", doc="label shown on the chart and in messages")
    points: tuple[tuple[float, ...], ...] = param(
        unit="m", lo=-1e6, hi=1e6, doc="vertices [[north, east], ...], at least 3, not self-intersecting"
    )


@dataclass(frozen=True, kw_only=True)
class DepthArea:
    """A polygon of uniform charted depth; shallower than the ship's draught means grounding."""

    name: str = param("", doc="label")
    depth_m: float = param(unit="m", lo=0.0, hi=1e4, doc="charted depth inside the polygon")
    points: tuple[tuple[float, ...], ...] = param(
        unit="m", lo=-1e6, hi=1e6, doc="vertices [[north, east], ...]"
    )


@dataclass(frozen=True, kw_only=True)
class StartRegion:
    """Where episodes start: the midship point uniformly inside ``points``, heading and speed uniform."""

    points: tuple[tuple[float, ...], ...] = param(unit="m", lo=-1e6, hi=1e6, doc="polygon of start positions")
    heading_deg: tuple[float, ...] = param(unit="deg", lo=-360.0, hi=360.0, doc="[min, max] heading")
    speed_m_s: tuple[float, ...] = param(unit="m/s", lo=0.0, hi=30.0, doc="[min, max] steady approach speed")


@dataclass(frozen=True, kw_only=True)
class GoalRegion:
    """Berth or turning basin: success = midship inside ``points``, slow, heading in tolerance."""

    points: tuple[tuple[float, ...], ...] = param(unit="m", lo=-1e6, hi=1e6, doc="goal polygon")
    point_m: tuple[float, ...] | None = param(
        None, unit="m", lo=-1e6, hi=1e6, doc="[north, east] reference point (default: polygon centroid)"
    )
    heading_deg: float = param(0.0, unit="deg", lo=-360.0, hi=360.0, doc="required heading")
    heading_tolerance_deg: float = param(180.0, unit="deg", lo=0.0, hi=180.0, doc="180: any heading")
    max_speed_m_s: float = param(unit="m/s", lo=0.0, hi=10.0, doc="speed over ground below which it counts")


@dataclass(frozen=True, kw_only=True)
class Weather:
    """Uniform ranges ``[min, max]`` drawn once per episode (wind from, current towards, waves from)."""

    wind_speed_m_s: tuple[float, ...] = param((0.0, 0.0), unit="m/s", lo=0.0, hi=60.0)
    wind_from_deg: tuple[float, ...] = param((0.0, 360.0), unit="deg", lo=-360.0, hi=360.0)
    current_speed_m_s: tuple[float, ...] = param((0.0, 0.0), unit="m/s", lo=0.0, hi=6.0)
    current_to_deg: tuple[float, ...] = param((0.0, 360.0), unit="deg", lo=-360.0, hi=360.0)
    Hs_m: tuple[float, ...] = param((0.0, 0.0), unit="m", lo=0.0, hi=16.0)
    Tp_s: tuple[float, ...] = param((8.0, 8.0), unit="s", lo=1.0, hi=25.0)
    wave_from_deg: tuple[float, ...] = param((0.0, 360.0), unit="deg", lo=-360.0, hi=360.0)


@dataclass(frozen=True, kw_only=True)
class TrafficShip:
    """Another ship following a route (``vessel_gym.scenarios.traffic``); contact with it is not modelled."""

    name: str = param(doc="ship name (AIS: 20 characters, upper-cased)")
    ship: str = param("kvlcc2_l7", doc="built-in ship name or ship file path (relative to this file)")
    mmsi: int | None = param(
        None, lo=1, hi=999_999_999, doc="AIS MMSI (9 digits); without one no AIS is sent"
    )
    start_m: tuple[float, ...] = param(unit="m", lo=-1e6, hi=1e6, doc="[north, east] start of midship")
    heading_deg: float = param(0.0, unit="deg", lo=-360.0, hi=360.0, doc="start heading")
    speed_kn: float = param(
        unit="kn", lo=0.0, hi=40.0, doc="steady speed through the water; 0 with no route: lying still"
    )
    route_m: tuple[tuple[float, ...], ...] = param(
        (), unit="m", lo=-1e6, hi=1e6, doc="waypoints [[north, east], ...] steered for in turn"
    )
    at_end: str = param(
        "loop",
        choices=("loop", "stop"),
        doc="after the last waypoint: loop to the first, or come to a stop (astern, then STOP)",
    )
    call_sign: str = param("", doc="AIS call sign (7 characters)")
    destination: str = param("", doc="AIS destination (20 characters)")
    ship_type: int = param(70, lo=0, hi=99, doc="AIS ship type code (70 cargo, 80 tanker, ...)")


@dataclass(frozen=True, kw_only=True)
class Berth:
    """A berth on a quay: the quay face, its fenders, the ship's side to it (docs/berthing.md)."""

    name: str = param(doc="berth name (the Berthing task's ``berth`` key)")
    quay_m: tuple[tuple[float, ...], ...] = param(
        unit="m",
        lo=-1e6,
        hi=1e6,
        doc="the quay face (wall) along the berth: [[north, east], [north, east]]; "
        "the ship lies heading from the first point to the second",
    )
    side: str = param("port", choices=("port", "starboard"), doc="the ship's side to the quay")
    fenders_m: tuple[float, ...] = param(
        unit="m", lo=0.0, hi=1e5, doc="fender positions along the face from its first point"
    )
    fender: FenderParams = param(FenderParams(), doc="[berth.fender] the fender type (components.fenders)")
    position_m: float | None = param(
        None,
        unit="m",
        lo=0.0,
        hi=1e5,
        doc="midship's place along the face (default: the middle of the fenders)",
    )
    tugs: tuple[TugParams, ...] = param((), doc="[[berth.tugs]] tugs assisting the ship at this berth")

    @property
    def direction(self) -> tuple[float, float]:
        """Unit vector [north, east] of the face, first point to second (the berthed ship's heading)."""
        (n0, e0), (n1, e1) = self.quay_m[0], self.quay_m[1]
        d = math.hypot(n1 - n0, e1 - e0)
        return ((n1 - n0) / d, (e1 - e0) / d)

    @property
    def heading_deg(self) -> float:
        """The berthed ship's heading, deg."""
        a = self.direction
        return math.degrees(math.atan2(a[1], a[0]))

    def to_water(self) -> tuple[float, float]:
        """Unit normal [north, east] of the face pointing into the water (away from the ship's side)."""
        a, s = self.direction, (1.0 if self.side == "starboard" else -1.0)
        return (s * a[1], -s * a[0])

    def berthed_point(self, half_beam_m: float) -> tuple[float, float]:
        """[north, east] of midship lying alongside the unloaded fenders."""
        along = (
            self.position_m
            if self.position_m is not None
            else 0.5 * (min(self.fenders_m) + max(self.fenders_m))
        )
        a, w = self.direction, self.to_water()
        off = self.fender.height_m + half_beam_m
        n0, e0 = self.quay_m[0]
        return (n0 + along * a[0] + off * w[0], e0 + along * a[1] + off * w[1])


@dataclass(frozen=True, kw_only=True)
class Scenario:
    """A harbour scenario (see docs/scenarios.md for the file format)."""

    name: str = param("", doc="scenario name (default: file stem)")
    description: str = param("", doc="one paragraph for people")
    ship: str = param("kvlcc2_l7", doc="built-in ship name or ship file path (relative to this file)")
    reference_latlon_deg: tuple[float, ...] = param(
        (0.0, 0.0), unit="deg", lo=-180.0, hi=180.0, doc="[lat, lon] of the local origin"
    )
    water_depth_m: float = param(unit="m", lo=0.01, hi=1e4, doc="depth outside every depth area")
    bounds_m: tuple[float, ...] = param(
        unit="m", lo=-1e6, hi=1e6, doc="[north_min, north_max, east_min, east_max]: chart and episode area"
    )
    land: tuple[Area, ...] = param((), doc="[[land]] polygons")
    breakwater: tuple[Area, ...] = param((), doc="[[breakwater]] polygons")
    quay: tuple[Area, ...] = param((), doc="[[quay]] polygons")
    depth_area: tuple[DepthArea, ...] = param((), doc="[[depth_area]] polygons")
    route_m: tuple[tuple[float, ...], ...] = param(
        (),
        unit="m",
        lo=-1e6,
        hi=1e6,
        doc="recommended track [[north, east], ...] towards the goal (optional)",
    )
    start: StartRegion = param(doc="[start] table")
    goal: GoalRegion = param(doc="[goal] table")
    weather: Weather = param(Weather(), doc="[weather] table")
    traffic: tuple[TrafficShip, ...] = param((), doc="[[traffic]] other ships following routes (optional)")
    berth: tuple[Berth, ...] = param(
        (), doc="[[berth]] berths with their fenders (optional; docs/berthing.md)"
    )
    path: str = field(default="", init=False, compare=False)

    # --- derived --------------------------------------------------------------------------------------------
    def load_ship(self) -> Ship:
        """The scenario's ship (a relative ship path is taken relative to the scenario file)."""
        s = self.ship
        if (s.endswith(".toml") or "/" in s) and self.path and not Path(s).is_absolute():
            s = str(Path(self.path).parent / s)
        return load_ship(s)

    @property
    def goal_point(self) -> tuple[float, float]:
        """Goal reference point [north, east], m."""
        if self.goal.point_m is not None:
            return (self.goal.point_m[0], self.goal.point_m[1])
        return geo.centroid(_pts(self.goal.points))

    def find_berth(self, name: str | None) -> Berth:
        """The berth of that name (None: the first); ScenarioError naming the berths there are."""
        for b in self.berth:
            if name is None or b.name == name:
                return b
        have = ", ".join(repr(b.name) for b in self.berth) or "none"
        raise ScenarioError(f"{self.path or self.name}: no [[berth]] {name!r} (berths: {have})")

    def hard_obstacles(self) -> list[tuple[str, str, list[tuple[float, float]]]]:
        """(kind, name, points) of every land, breakwater and quay polygon."""
        out = []
        for kind in HARD_KINDS:
            for a in getattr(self, kind):
                out.append((kind, a.name, _pts(a.points)))
        return out

    def depth_at(self, north_m: float, east_m: float) -> float:
        """Charted depth (m) at the point [north, east] (m): the shallowest depth area containing it (where
        areas overlap, the chart's safe reading), else ``water_depth_m``. The physics takes it as the
        :class:`~vessel_gym.physics.environment.Environment`'s ``depth_m`` under the ship's midship point."""
        p = (float(north_m), float(east_m))
        inside = [d.depth_m for d in self.depth_area if geo.point_in_polygon(p, _pts(d.points))]
        return min(inside, default=self.water_depth_m)

    def shoals(self, draught_m: float) -> list[tuple[str, list[tuple[float, float]]]]:
        """(name, points) of depth areas shallower than ``draught_m`` (grounding areas)."""
        return [(d.name, _pts(d.points)) for d in self.depth_area if d.depth_m < draught_m]


def _pts(points: tuple[tuple[float, ...], ...]) -> list[tuple[float, float]]:
    return [(float(p[0]), float(p[1])) for p in points]


def builtin_scenarios() -> list[str]:
    """Names of the scenario files shipped with vessel-gym."""
    return builtin_names(SCENARIO_DIR)


def resolve_scenario_path(scenario: str | Path) -> Path:
    """A built-in name or a path to a TOML file -> path. Raises ScenarioError naming the choices."""
    return resolve_data_path(scenario, SCENARIO_DIR, "scenario", ScenarioError)


def load_scenario(scenario: str | Path | Scenario) -> Scenario:
    """Load and validate a scenario by built-in name or file path (a :class:`Scenario` passes through)."""
    if isinstance(scenario, Scenario):
        return scenario
    path = resolve_scenario_path(scenario)
    where = str(path)
    try:
        data = read_toml(path, MAX_SCENARIO_FILE_BYTES)
        sc = build(Scenario, data, where)
    except ScenarioError:
        raise
    except SpecError as exc:
        raise ScenarioError(str(exc)) from None
    object.__setattr__(sc, "path", where)
    if not sc.name:
        object.__setattr__(sc, "name", path.stem)
    validate(sc, where)
    return sc


def _check_polygon(points: tuple[tuple[float, ...], ...], where: str) -> list[tuple[float, float]]:
    for i, p in enumerate(points):
        if len(p) != 2:
            raise ScenarioError(f"{where}[{i}]: a point is [north, east], got {len(p)} values")
    pts = _pts(points)
    if len(pts) < 3:
        raise ScenarioError(f"{where}: a polygon needs at least 3 points, got {len(pts)}")
    rep = geo.repeated_vertex(pts)
    if rep is not None:
        raise ScenarioError(f"{where}[{rep[1]}]: repeats vertex {rep[0]} (a polygon visits each point once)")
    hit = geo.self_intersection(pts)
    if hit is not None:
        raise ScenarioError(f"{where}: polygon is self-intersecting (edges {hit[0]} and {hit[1]} meet)")
    if abs(geo.signed_area(pts)) < 1e-9:
        raise ScenarioError(f"{where}: polygon has zero area")
    return pts


def _check_range(rng: tuple[float, ...], where: str) -> None:
    if len(rng) != 2:
        raise ScenarioError(f"{where}: expected [min, max], got {len(rng)} values")
    if rng[0] > rng[1]:
        raise ScenarioError(f"{where}: min {rng[0]:g} > max {rng[1]:g}")


def _label(kind: str, i: int, name: str) -> str:
    return f"{kind}[{i}]" + (f" {name!r}" if name else "")


def validate(sc: Scenario, where: str = "scenario") -> None:
    """Geometric and cross-key checks; raises ScenarioError (one line naming file and key)."""
    for kind in HARD_KINDS:
        for i, a in enumerate(getattr(sc, kind)):
            _check_polygon(a.points, f"{where} {_label(kind, i, a.name)} points")
    for i, d in enumerate(sc.depth_area):
        _check_polygon(d.points, f"{where} {_label('depth_area', i, d.name)} points")
    goal = _check_polygon(sc.goal.points, f"{where} goal points")
    start = _check_polygon(sc.start.points, f"{where} start points")
    if len(sc.bounds_m) != 4 or sc.bounds_m[0] >= sc.bounds_m[1] or sc.bounds_m[2] >= sc.bounds_m[3]:
        raise ScenarioError(
            f"{where} bounds_m: expected [north_min, north_max, east_min, east_max], min < max"
        )
    if len(sc.reference_latlon_deg) != 2 or abs(sc.reference_latlon_deg[0]) > 90.0:
        raise ScenarioError(f"{where} reference_latlon_deg: expected [lat, lon] with |lat| <= 90")
    _check_range(sc.start.heading_deg, f"{where} start heading_deg")
    _check_range(sc.start.speed_m_s, f"{where} start speed_m_s")
    for f in dataclasses.fields(Weather):
        _check_range(getattr(sc.weather, f.name), f"{where} weather {f.name}")
    if sc.goal.point_m is not None:
        if len(sc.goal.point_m) != 2:
            raise ScenarioError(f"{where} goal point_m: expected [north, east]")
        if not geo.point_in_polygon((sc.goal.point_m[0], sc.goal.point_m[1]), goal):
            raise ScenarioError(f"{where} goal point_m: not inside the goal polygon")
    try:
        ship = sc.load_ship()
    except SpecError as exc:
        raise ScenarioError(f"{where} ship: {exc}") from None
    n0, n1, e0, e1 = sc.bounds_m
    for key, poly in (("goal", goal), ("start", start)):
        if any(not (n0 <= p[0] <= n1 and e0 <= p[1] <= e1) for p in poly):
            raise ScenarioError(f"{where} {key} points: region extends outside bounds_m")
        for kind, name, obs in sc.hard_obstacles():
            if geo.polygons_overlap(poly, obs):
                raise ScenarioError(f"{where} {key} points: region overlaps {kind} {name!r}")
        for name, obs in sc.shoals(ship.particulars.T_m):
            if geo.polygons_overlap(poly, obs):
                raise ScenarioError(
                    f"{where} {key} points: region overlaps depth area {name!r}, shallower than the "
                    f"draught of {ship.name} ({ship.particulars.T_m:g} m)"
                )
    for i, p in enumerate(sc.route_m):
        if len(p) != 2:
            raise ScenarioError(f"{where} route_m[{i}]: a point is [north, east], got {len(p)} values")
        if not (n0 <= p[0] <= n1 and e0 <= p[1] <= e1):
            raise ScenarioError(f"{where} route_m[{i}]: outside bounds_m")
        for kind, name, obs in sc.hard_obstacles():
            if geo.point_in_polygon((p[0], p[1]), obs):
                raise ScenarioError(f"{where} route_m[{i}]: on {kind} {name!r}")
    _validate_traffic(sc, where, ship)
    _validate_berths(sc, where)
    if sc.start.speed_m_s[0] <= 0.0:
        raise ScenarioError(f"{where} start speed_m_s: the minimum must be > 0 (steady approach)")
    if not math.isfinite(sc.water_depth_m):  # pragma: no cover - schema already rejects
        raise ScenarioError(f"{where} water_depth_m: must be finite")


def _validate_berths(sc: Scenario, where: str) -> None:
    """The ``[[berth]]`` entries: a face of two distinct points, fenders on it, the water side navigable."""
    for i, b in enumerate(sc.berth):
        w = f"{where} {_label('berth', i, b.name)}"
        if len(b.quay_m) != 2 or any(len(p) != 2 for p in b.quay_m):
            raise ScenarioError(f"{w} quay_m: expected [[north, east], [north, east]]")
        length = math.hypot(b.quay_m[1][0] - b.quay_m[0][0], b.quay_m[1][1] - b.quay_m[0][1])
        if length < 1.0:
            raise ScenarioError(f"{w} quay_m: the two points must be apart")
        if len(b.fenders_m) < 2 or max(b.fenders_m) > length:
            raise ScenarioError(f"{w} fenders_m: at least 2 fenders, each within the face's {length:g} m")
        if b.position_m is not None and b.position_m > length:
            raise ScenarioError(f"{w} position_m: beyond the face's {length:g} m")
        wn, we = b.to_water()
        probe = (0.5 * (b.quay_m[0][0] + b.quay_m[1][0]) + 2.0 * b.fender.height_m * wn,
                 0.5 * (b.quay_m[0][1] + b.quay_m[1][1]) + 2.0 * b.fender.height_m * we)  # fmt: skip
        for kind, name, obs in sc.hard_obstacles():
            if geo.point_in_polygon(probe, obs):
                raise ScenarioError(
                    f"{w}: the water side of the face is on {kind} {name!r} (side {b.side!r} the wrong way?)"
                )


def _validate_traffic(sc: Scenario, where: str, own_ship: Ship) -> None:
    """Checks of the ``[[traffic]]`` entries: ship, start, waypoints and legs in navigable water, MMSIs."""
    n0, n1, e0, e1 = sc.bounds_m
    # arrays once, not per point and leg: the point and leg tests are vectorised over a polygon's edges
    hard = [(kind, name, np.asarray(obs)) for kind, name, obs in sc.hard_obstacles()]
    seen: dict[int, int] = {}
    ships: dict[str, Ship] = {sc.ship: own_ship}
    for i, t in enumerate(sc.traffic):
        label = f"{where} {_label('traffic', i, t.name)}"
        if not t.name.strip():
            raise ScenarioError(f"{where} traffic[{i}] name: must not be empty")
        if t.mmsi is not None:
            if t.mmsi in seen:
                raise ScenarioError(f"{label} mmsi: {t.mmsi} is also used by traffic[{seen[t.mmsi]}]")
            seen[t.mmsi] = i
        if t.ship not in ships:
            s = t.ship
            if (s.endswith(".toml") or "/" in s) and sc.path and not Path(s).is_absolute():
                s = str(Path(sc.path).parent / s)
            try:
                ships[t.ship] = load_ship(s)
            except SpecError as exc:
                raise ScenarioError(f"{label} ship: {exc}") from None
        draught = ships[t.ship].particulars.T_m
        if len(t.start_m) != 2:
            raise ScenarioError(f"{label} start_m: expected [north, east], got {len(t.start_m)} values")
        if t.route_m and t.speed_kn <= 0.0:
            raise ScenarioError(f"{label} speed_kn: must be > 0 for a ship with a route")
        if t.at_end == "loop" and len(t.route_m) == 1:
            raise ScenarioError(f'{label} route_m: a loop needs at least 2 waypoints (or at_end = "stop")')
        for j, p in enumerate(t.route_m):
            if len(p) != 2:
                raise ScenarioError(f"{label} route_m[{j}]: a point is [north, east], got {len(p)} values")
        pts = [("start_m", (float(t.start_m[0]), float(t.start_m[1])))] + [
            (f"route_m[{j}]", (float(p[0]), float(p[1]))) for j, p in enumerate(t.route_m)
        ]
        shoals = [(name, np.asarray(obs)) for name, obs in sc.shoals(draught)]
        for key, p in pts:
            if not (n0 <= p[0] <= n1 and e0 <= p[1] <= e1):
                raise ScenarioError(f"{label} {key}: outside bounds_m")
            for kind, name, obs in hard:
                if geo.point_in_polygon(p, obs):
                    raise ScenarioError(f"{label} {key}: on {kind} {name!r}")
            for name, obs in shoals:
                if geo.point_in_polygon(p, obs):
                    raise ScenarioError(f"{label} {key}: in depth area {name!r}, shallower than the draught")
        legs = [(pts[j][1], pts[j + 1][1], pts[j + 1][0]) for j in range(len(pts) - 1)]
        if t.at_end == "loop" and len(t.route_m) >= 2:
            legs.append((pts[-1][1], pts[1][1], "route_m[0]"))
        for a, b, key in legs:
            for kind, name, obs in hard:
                if geo.segment_meets_polygon(a, b, obs):
                    raise ScenarioError(f"{label} {key}: the leg to it crosses {kind} {name!r}")
