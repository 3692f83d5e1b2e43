"""Standard manoeuvres with the IMO MSC.137(76) definitions (Annex §4; MSC/Circ.1053).

Every trial starts from a steady straight approach at the requested speed (rpm solved for equilibrium,
zero yaw rate) on heading 0 (north) at the origin; the first execute is given at t = 0. Distances are those
of the midship point (the body origin). Where a trial cannot reach its defining event within its time limit
it raises :class:`ManoeuvreIncomplete` instead of reporting a number.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from vessel_gym.control.turning import (
    ADVANCE_HEADING_RAD,
    TACTICAL_HEADING_RAD,
    at_crossing,
    course_axes,
    crossing_fraction,
)
from vessel_gym.control.zigzag import OVERSHOOT_IMO, OvershootTracker
from vessel_gym.manoeuvres.helms import TurnHelm, ZigZagHelm
from vessel_gym.physics import layout as lo
from vessel_gym.physics.bridge import Telegraph
from vessel_gym.physics.environment import CALM, Environment
from vessel_gym.physics.shipfile import Ship, load_ship
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.units import DEG, KNOT_M_S


class ManoeuvreIncomplete(RuntimeError):
    """The manoeuvre's defining event was not reached (e.g. the ship never turned 180 deg)."""


class ManoeuvreDiverged(ManoeuvreIncomplete):
    """The simulation ran away (non-finite or physically impossible state, :meth:`Simulation.divergence`):
    the run is not scored. ``reason`` is that sentence, ``t_s`` the time it was detected."""

    def __init__(self, reason: str, t_s: float) -> None:
        super().__init__(f"the simulation diverged at t = {t_s:.1f} s: {reason}")
        self.reason = reason
        self.t_s = t_s


class Track:
    """Time histories of a trial (SI, radians; heading unwrapped, relative to the original course).

    Rows are recorded as copies of the state; the named arrays (x along the original course, y to
    starboard of it, psi, u, v, r, delta, delta_c, rpm) are built on first access after the run.
    """

    _NAMES = {
        "x": lo.X_N,
        "y": lo.X_E,
        "psi": lo.X_PSI,
        "u": lo.X_U,
        "v": lo.X_V,
        "r": lo.X_R,
        "delta": lo.X_DELTA,
        "phi": lo.X_PHI,  # heel, rad, starboard side down (0 throughout on a 3-DOF ship)
    }

    def __init__(self) -> None:
        self._t: list[float] = []
        self._rows: list[np.ndarray] = []
        self._dc: list[float] = []
        self._cache: dict[str, np.ndarray] = {}

    def append(self, sim: Simulation) -> None:
        self._t.append(sim.t)
        self._rows.append(sim.state[0].copy())
        self._dc.append(sim.inputs[0, lo.U_DELTA_C])
        self._cache = {}

    def _arr(self, name: str) -> np.ndarray:
        if name not in self._cache:
            rows = np.asarray(self._rows)
            self._cache = {k: rows[:, i] for k, i in self._NAMES.items()}
            self._cache["t"] = np.asarray(self._t)
            self._cache["delta_c"] = np.asarray(self._dc)
            self._cache["rpm"] = rows[:, lo.X_REV] * 60.0
        return self._cache[name]

    def __getattr__(self, name: str) -> np.ndarray:
        if name in ("t", "delta_c", "rpm") or name in Track._NAMES:
            return self._arr(name)
        raise AttributeError(name)

    def arrays(self) -> dict[str, np.ndarray]:
        return {k: self._arr(k) for k in ("t", *Track._NAMES, "delta_c", "rpm")}

    def at_heading(self, change_rad: float) -> tuple[float, float, float] | None:
        """(t, x, y) when |heading change| first reaches ``change_rad`` (linear interpolation), else None."""
        psi = np.abs(np.asarray(self.psi))
        idx = np.nonzero(psi >= change_rad)[0]
        if idx.size == 0:
            return None
        i = int(idx[0])
        if i == 0:
            return self.t[0], self.x[0], self.y[0]
        f = crossing_fraction(psi[i - 1], psi[i], change_rad)
        lerp = lambda a: at_crossing(a[i - 1], a[i], f)  # noqa: E731
        return lerp(self.t), lerp(self.x), lerp(self.y)

    def path_length(self, upto: int | None = None) -> float:
        x = self.x[:upto]
        y = self.y[:upto]
        return float(np.hypot(np.diff(x), np.diff(y)).sum())


def _heel_extreme(ship: Ship, track: Track) -> tuple[float | None, float | None]:
    """(heel at the instant of the largest |heel|, deg, signed as phi: + starboard side down; that time, s),
    or (None, None) for a 3-DOF ship, which has no heel."""
    if ship.roll is None:
        return None, None
    phi = np.asarray(track.phi)
    i = int(np.argmax(np.abs(phi)))
    return math.degrees(float(phi[i])), float(track.t[i])


def _heel_keys(d: dict, **heel: float | None) -> dict:
    """``d`` with the heel entries that exist (a 3-DOF ship's result has none)."""
    d.update({k: v for k, v in heel.items() if v is not None})
    return d


def trial_dt(ship: Ship, speed_m_s: float) -> float:
    """Physics step for a trial: L/V / 400 (a turn of the ship takes several L/V), at most 0.1 s,
    rounded down to 1, 2 or 5 x 10^k s so that reported times are exact multiples."""
    target = min(0.1, ship.particulars.L_m / max(speed_m_s, 0.1) / 400.0)
    exp = math.floor(math.log10(target))
    for m in (5.0, 2.0, 1.0):
        if m * 10.0**exp <= target:
            return m * 10.0**exp
    return 10.0**exp


#: the slowest approach a trial accepts, as a fraction of the ship's test speed. The hull's derivatives come
#: from captive tests near the service speed, and the rudder's and hull's forces scale with U^2: at a tenth of
#: the test speed they are 1 % of the tested ones, and a trial's time limit (tens of L/V) grows to days of
#: simulated time (a 35 deg turn of kvlcc2 at 0.1 kn: 55 s of computing for a ship that never turns 180 deg).
MIN_SPEED_FRACTION = 0.1


def _start(ship: str | Ship, speed_kn: float | None, environment: Environment, dt: float | None):
    s = load_ship(ship)
    speed = s.test_speed_m_s if speed_kn is None else speed_kn * KNOT_M_S
    if not (speed > 0.0 and math.isfinite(speed)):
        raise ValueError(f"speed must be positive, got {speed_kn} kn")
    slowest = MIN_SPEED_FRACTION * s.particulars.test_speed_kn
    if speed / KNOT_M_S < slowest * (1.0 - 1e-9):
        raise ValueError(
            f"speed {speed / KNOT_M_S:g} kn is below {slowest:.3g} kn, a tenth of {s.name}'s test speed "
            f"{s.particulars.test_speed_kn:g} kn: outside the range its manoeuvring model was measured for"
        )
    sim = Simulation(s, dt=dt or trial_dt(s, speed), environment=environment)
    sim.reset(speed_m_s=speed)
    return s, sim, speed


def _run(
    sim: Simulation,
    track: Track,
    helm: Callable[[float], float] | None,
    done: Callable[[], bool],
    max_time_s: float,
) -> bool:
    track.append(sim)
    while sim.t < max_time_s - 1e-9:
        if helm is not None:
            sim.set_helm(rudder_order_rad=helm(float(sim.heading[0])))
        if sim.step(1) == 0:
            raise ManoeuvreDiverged(sim.divergence(0) or "the state became non-finite", sim.t)
        track.append(sim)
        if done():
            return True
    return False


@dataclass(frozen=True)
class TurningCircle:
    ship: str
    rudder_deg: float
    speed_kn: float
    L_m: float
    advance_m: float
    transfer_m: float
    tactical_diameter_m: float
    steady_diameter_m: float | None
    time_to_90_s: float
    time_to_180_s: float
    final_speed_kn: float
    track: Track = field(repr=False, compare=False)
    # 4-DOF ships only (None otherwise), signed as phi (+ starboard side down): the heel at its largest
    # magnitude and when, and the mean heel of the steady turn (heading change 360..720 deg)
    max_heel_deg: float | None = None
    max_heel_time_s: float | None = None
    steady_heel_deg: float | None = None

    def to_dict(self) -> dict:
        L = self.L_m
        d = {
            "ship": self.ship,
            "rudder_deg": self.rudder_deg,
            "speed_kn": self.speed_kn,
            "L_m": L,
            "advance_L": self.advance_m / L,
            "transfer_L": self.transfer_m / L,
            "tactical_diameter_L": self.tactical_diameter_m / L,
            "steady_diameter_L": None if self.steady_diameter_m is None else self.steady_diameter_m / L,
            "advance_m": self.advance_m,
            "transfer_m": self.transfer_m,
            "tactical_diameter_m": self.tactical_diameter_m,
            "steady_diameter_m": self.steady_diameter_m,
            "time_to_90_s": self.time_to_90_s,
            "time_to_180_s": self.time_to_180_s,
            "final_speed_kn": self.final_speed_kn,
        }
        return _heel_keys(
            d,
            max_heel_deg=self.max_heel_deg,
            max_heel_time_s=self.max_heel_time_s,
            steady_heel_deg=self.steady_heel_deg,
        )


def _fit_circle(x: np.ndarray, y: np.ndarray) -> float:
    """Diameter of the least-squares circle through points (Kasa fit)."""
    A = np.column_stack([x, y, np.ones_like(x)])
    b = x * x + y * y
    c, *_ = np.linalg.lstsq(A, b, rcond=None)
    xc, yc = c[0] / 2.0, c[1] / 2.0
    return 2.0 * math.sqrt(c[2] + xc * xc + yc * yc)


def turning_circle(
    ship: str | Ship,
    rudder_deg: float = 35.0,
    speed_kn: float | None = None,
    environment: Environment = CALM,
    dt: float | None = None,
    max_time_s: float | None = None,
    until_deg: float = 720.0,
) -> TurningCircle:
    """Turning circle (MSC.137(76) §4.2.2): rudder order at t = 0, held; positive rudder = starboard.

    Advance: distance along the original course at a 90 deg heading change; transfer: perpendicular to it
    at 90 deg; tactical diameter: perpendicular at 180 deg; steady diameter: least-squares circle through
    the track between 360 and 720 deg (None if the ship does not turn 720 deg within the time limit, or
    when ``until_deg`` < 720 stops the run earlier).
    """
    if until_deg < 180.0:
        raise ValueError("until_deg must be at least 180")
    if rudder_deg == 0.0 or not math.isfinite(rudder_deg):
        raise ValueError(f"rudder must be a nonzero angle, got {rudder_deg}")
    s, sim, speed = _start(ship, speed_kn, environment, dt)
    dmax = s.steering_gear.max_angle_deg
    if abs(rudder_deg) > dmax:
        raise ValueError(f"rudder {rudder_deg:g} deg exceeds the steering gear's {dmax:g} deg")
    L = s.particulars.L_m
    limit = max_time_s or 60.0 * L / speed
    track = Track()
    helm = TurnHelm(rudder_deg * DEG)
    _run(sim, track, helm.order, lambda: abs(sim.heading[0]) >= until_deg * DEG, limit)
    p90 = track.at_heading(ADVANCE_HEADING_RAD)
    p180 = track.at_heading(TACTICAL_HEADING_RAD)
    if p90 is None or p180 is None:
        reached = math.degrees(max(abs(p) for p in track.psi))
        raise ManoeuvreIncomplete(
            f"{s.name}: heading changed only {reached:.1f} deg in {limit:.0f} s "
            f"with {rudder_deg:g} deg rudder (the turn needs 180 deg)"
        )
    psi = np.abs(np.asarray(track.psi))
    sel = (psi >= 2 * math.pi) & (psi <= 4 * math.pi)
    steady = (
        _fit_circle(np.asarray(track.x)[sel], np.asarray(track.y)[sel]) if psi[-1] >= 4 * math.pi else None
    )
    final_u = math.hypot(track.u[-1], track.v[-1])
    max_heel, max_heel_t = _heel_extreme(s, track)
    steady_heel = None
    if s.roll is not None and psi[-1] >= 4 * math.pi:
        steady_heel = math.degrees(float(np.mean(np.asarray(track.phi)[sel])))
    # the trial starts on heading 0 at the origin: x, y are already along and across the original course
    advance, transfer = course_axes(0.0, 0.0, 0.0, p90[1], p90[2])
    return TurningCircle(
        s.name,
        rudder_deg,
        speed / KNOT_M_S,
        L,
        advance,
        abs(transfer),
        abs(course_axes(0.0, 0.0, 0.0, p180[1], p180[2])[1]),
        steady,
        p90[0],
        p180[0],
        final_u / KNOT_M_S,
        track,
        max_heel,
        max_heel_t,
        steady_heel,
    )


@dataclass(frozen=True)
class ZigZag:
    ship: str
    rudder_deg: float
    heading_deg: float
    speed_kn: float
    L_m: float
    overshoot_deg: list[float]
    overshoot_time_s: list[float]
    execute_time_s: list[float]
    period_s: float | None
    track: Track = field(repr=False, compare=False)
    # 4-DOF ships only (None otherwise): the heel at its largest magnitude, signed as phi, and when
    max_heel_deg: float | None = None
    max_heel_time_s: float | None = None

    def to_dict(self) -> dict:
        d = {
            "ship": self.ship,
            "rudder_deg": self.rudder_deg,
            "heading_deg": self.heading_deg,
            "speed_kn": self.speed_kn,
            "L_m": self.L_m,
            "overshoot_deg": self.overshoot_deg,
            "overshoot_time_s": self.overshoot_time_s,
            "execute_time_s": self.execute_time_s,
            "period_s": self.period_s,
        }
        return _heel_keys(d, max_heel_deg=self.max_heel_deg, max_heel_time_s=self.max_heel_time_s)


def zigzag(
    ship: str | Ship,
    rudder_deg: float = 10.0,
    heading_deg: float | None = None,
    speed_kn: float | None = None,
    n_overshoots: int = 3,
    environment: Environment = CALM,
    dt: float | None = None,
    max_time_s: float | None = None,
) -> ZigZag:
    """Zig-zag test (MSC.137(76) §4.2.4), first execute to starboard for positive ``rudder_deg``.

    The k-th overshoot angle is the heading excursion beyond the (k+1)-th execute heading, measured at the
    following extreme of heading (where the yaw rate changes sign). The period is the time between the
    2nd and 4th executes (one full oscillation), None when fewer executes happened.
    """
    heading_deg = abs(rudder_deg) if heading_deg is None else heading_deg
    if not (0.0 < heading_deg < 90.0):
        raise ValueError(f"zig-zag heading change must be in (0, 90) deg, got {heading_deg}")
    if rudder_deg == 0.0 or not math.isfinite(rudder_deg):
        raise ValueError(f"rudder must be a nonzero angle, got {rudder_deg}")
    s, sim, speed = _start(ship, speed_kn, environment, dt)
    if abs(rudder_deg) > s.steering_gear.max_angle_deg:
        raise ValueError(
            f"rudder {rudder_deg:g} deg exceeds the steering gear's {s.steering_gear.max_angle_deg:g} deg"
        )
    L = s.particulars.L_m
    limit = max_time_s or 80.0 * L / speed
    helm = ZigZagHelm(rudder_deg * DEG, heading_deg * DEG)
    track = Track()
    exec_times: list[float] = [0.0]
    # deviations from the original course (heading 0); the overshoot is the extreme deviation minus psi
    tracker = OvershootTracker(OVERSHOOT_IMO)

    def helm_order(psi: float) -> float:
        before = helm.side
        order = helm.order(psi)
        if helm.side != before:
            exec_times.append(sim.t)
            # the swing continues towards the side the rudder just left
            tracker.start(before, 0.0, psi, sim.t)
        return order

    def done() -> bool:
        tracker.update(float(sim.heading[0]), float(sim.r[0]), sim.t)
        return len(tracker.overshoots_rad) >= n_overshoots

    complete = _run(sim, track, helm_order, done, limit)
    overs = [math.degrees(p) - heading_deg for p in tracker.overshoots_rad]
    over_t = tracker.times_s
    if not complete and len(overs) < 1:
        raise ManoeuvreIncomplete(
            f"{s.name}: the {abs(rudder_deg):g}/{heading_deg:g} zig-zag reached no overshoot in {limit:.0f} s"
        )
    period = exec_times[3] - exec_times[1] if len(exec_times) >= 4 else None
    return ZigZag(
        s.name, rudder_deg, heading_deg, speed / KNOT_M_S, L, overs, over_t, exec_times, period, track,
        *_heel_extreme(s, track),
    )


@dataclass(frozen=True)
class InitialTurning:
    ship: str
    rudder_deg: float
    speed_kn: float
    L_m: float
    distance_m: float  # path length of the midship point until the heading has changed 10 deg
    advance_m: float  # distance along the original course at that moment
    time_s: float
    track: Track = field(repr=False, compare=False)

    def to_dict(self) -> dict:
        return {
            "ship": self.ship,
            "rudder_deg": self.rudder_deg,
            "speed_kn": self.speed_kn,
            "L_m": self.L_m,
            "distance_L": self.distance_m / self.L_m,
            "advance_L": self.advance_m / self.L_m,
            "distance_m": self.distance_m,
            "time_s": self.time_s,
        }


def initial_turning(
    ship: str | Ship,
    rudder_deg: float = 10.0,
    speed_kn: float | None = None,
    environment: Environment = CALM,
    dt: float | None = None,
) -> InitialTurning:
    """Initial turning ability (MSC.137(76) §5.3.2): 10 deg rudder; distance travelled until the heading
    has changed 10 deg from the original heading."""
    if rudder_deg == 0.0:
        raise ValueError("rudder must be a nonzero angle")
    s, sim, speed = _start(ship, speed_kn, environment, dt)
    track = Track()
    target = 10.0 * DEG
    if not _run(
        sim,
        track,
        TurnHelm(rudder_deg * DEG).order,
        lambda: abs(sim.heading[0]) >= target,
        40.0 * s.particulars.L_m / speed,
    ):
        raise ManoeuvreIncomplete(f"{s.name}: heading never changed 10 deg with {rudder_deg:g} deg rudder")
    t, x, y = track.at_heading(target)
    psi = np.abs(np.asarray(track.psi))
    i = int(np.nonzero(psi >= target)[0][0])
    dist = track.path_length(i) + math.hypot(x - track.x[i - 1], y - track.y[i - 1])
    return InitialTurning(s.name, rudder_deg, speed / KNOT_M_S, s.particulars.L_m, dist, x, t, track)


@dataclass(frozen=True)
class Stopping:
    ship: str
    speed_kn: float
    L_m: float
    track_reach_m: float
    head_reach_m: float
    lateral_deviation_m: float
    time_s: float
    track: Track = field(repr=False, compare=False)

    def to_dict(self) -> dict:
        L = self.L_m
        return {
            "ship": self.ship,
            "speed_kn": self.speed_kn,
            "L_m": L,
            "track_reach_L": self.track_reach_m / L,
            "head_reach_L": self.head_reach_m / L,
            "lateral_deviation_L": self.lateral_deviation_m / L,
            "track_reach_m": self.track_reach_m,
            "head_reach_m": self.head_reach_m,
            "lateral_deviation_m": self.lateral_deviation_m,
            "time_s": self.time_s,
        }


def stopping(
    ship: str | Ship,
    speed_kn: float | None = None,
    environment: Environment = CALM,
    dt: float | None = None,
    max_time_s: float | None = None,
) -> Stopping:
    """Full-astern stopping test (MSC.137(76) §4.2.3): telegraph full astern at t = 0, rudder midships,
    until the ship is stopped in the water (surge velocity through the water reaches zero).

    Track reach: path length of the midship point; head reach: distance along the original course;
    lateral deviation: perpendicular distance (signed, positive to starboard).
    """
    s, sim, speed = _start(ship, speed_kn, environment, dt)
    if s.engine is None:
        raise ManoeuvreIncomplete(f"{s.name}: a ship without propulsion cannot do a stopping test")
    sim.set_helm(rudder_order_rad=0.0, rev_order=sim.telegraph_rev(int(Telegraph.FULL_ASTERN), 0))
    track = Track()
    limit = max_time_s or 200.0 * s.particulars.L_m / speed
    if not _run(sim, track, None, lambda: sim.u[0] <= 0.0, limit):
        raise ManoeuvreIncomplete(
            f"{s.name}: not stopped in the water after {limit:.0f} s (speed {sim.u[0] / KNOT_M_S:.2f} kn)"
        )
    u = np.asarray(track.u)
    f = u[-2] / (u[-2] - u[-1])  # interpolate the zero crossing of u
    lerp = lambda a: a[-2] + f * (a[-1] - a[-2])  # noqa: E731
    x, y, t = lerp(track.x), lerp(track.y), lerp(track.t)
    reach = track.path_length(len(track.x) - 1) + math.hypot(x - track.x[-2], y - track.y[-2])
    return Stopping(s.name, speed / KNOT_M_S, s.particulars.L_m, reach, x, y, t, track)


@dataclass(frozen=True)
class PullOut:
    ship: str
    rudder_deg: float
    steady_rate_deg_s: tuple[float, float]  # after the starboard and the port turn
    residual_rate_deg_s: tuple[float, float]
    stable: bool
    tracks: tuple[Track, Track] = field(repr=False, compare=False)

    def to_dict(self) -> dict:
        return {
            "ship": self.ship,
            "rudder_deg": self.rudder_deg,
            "steady_rate_deg_s": list(self.steady_rate_deg_s),
            "residual_rate_deg_s": list(self.residual_rate_deg_s),
            "course_stable": self.stable,
        }


def pull_out(
    ship: str | Ship,
    rudder_deg: float = 20.0,
    speed_kn: float | None = None,
    environment: Environment = CALM,
    dt: float | None = None,
) -> PullOut:
    """Pull-out test (Burcher 1972; ITTC 7.5-04-02-01) from both sides: steady turn, then rudder midships.

    For a course-stable ship the rates of turn after the starboard and the port turn decay to the same value
    (zero, or the ship's small neutral rate when the hull is asymmetric); for an unstable ship they stay
    apart. Stable: the two residual rates differ by less than 5 % of the steady rate.
    """
    steady, resid, tracks = [], [], []
    for side in (1.0, -1.0):
        s, sim, speed = _start(ship, speed_kn, environment, dt)
        T_turn = 20.0 * s.particulars.L_m / speed
        track = Track()
        _run(sim, track, TurnHelm(side * rudder_deg * DEG).order, lambda: False, T_turn)
        steady.append(math.degrees(float(sim.r[0])))
        _run(sim, track, TurnHelm(0.0).order, lambda: False, 2.0 * T_turn)
        resid.append(math.degrees(float(sim.r[0])))
        tracks.append(track)
    stable = abs(resid[0] - resid[1]) < 0.05 * 0.5 * (abs(steady[0]) + abs(steady[1]))
    return PullOut(s.name, rudder_deg, tuple(steady), tuple(resid), stable, tuple(tracks))
