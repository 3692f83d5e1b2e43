"""Scripted traffic: the other ships of a scenario, each following its route with a heading autopilot.

:class:`Traffic` holds every ``[[traffic]]`` ship of a scenario in one batched
:class:`~vessel_gym.physics.simulation.Simulation` that is stepped alongside the own ship, one control interval
at a time. Each ship steers by line-of-sight guidance on the leg between its previous and its next waypoint
(look-ahead ``lookahead_L`` ship lengths, Fossen 2011 §10.3.2) with a :class:`~vessel_gym.control.PidAutopilot`
whose gains come from the ship's Nomoto model at its route speed (pole placement at ``bandwidth_UL`` U/L);
the shaft-speed order is the one that holds that speed in calm water. A waypoint counts as reached within
``accept_L`` ship lengths or once the ship is abeam of it. At the last waypoint a ship either starts again at
the first (``at_end = "loop"``) or puts the rudder amidships and goes slow astern until it lies stopped in the
water, then orders STOP (``"stop"``). A ship with speed 0 and no route lies still.

Traffic ships move in calm water (no wind, current or waves) and do not interact with the own ship or the
chart: contact with traffic and grounding of traffic are not modelled.

:meth:`Traffic.targets` gives the ships as :class:`~vessel_gym.net.protocol.Target` (JSON ``targets``, and AIS
for ships with an MMSI). :meth:`Traffic.lazy_targets` defers the simulation: nothing is computed until a
consumer reads the targets, and the traffic then catches up to the requested step, so traffic nobody
watches costs nothing.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from vessel_gym.control import (
    PidAutopilot,
    leg_frame,
    los_heading,
    nomoto_pid_gains,
    waypoint_reached,
    wrap_pi_upper,
)
from vessel_gym.net.ais import NAV_MOORED, NAV_UNDER_WAY_ENGINE
from vessel_gym.net.protocol import Target
from vessel_gym.physics.shipfile import Ship, load_ship
from vessel_gym.physics.simulation import Simulation, steps_for
from vessel_gym.physics.steady import SimulationError
from vessel_gym.physics.units import DEG, KNOT_M_S
from vessel_gym.scenarios.scenario import Scenario, ScenarioError, TrafficShip

#: guidance defaults, in ship lengths, and the heading loop's natural frequency in U/L
LOOKAHEAD_L = 3.0
ACCEPT_L = 1.5
BANDWIDTH_UL = 2.0
#: speed through the water below which a ship at the end of its route counts as stopped, m/s
STOPPED_M_S = 0.02


def _ship_path(ship: str, base_dir: str | None) -> str:
    if (ship.endswith(".toml") or "/" in ship) and base_dir and not Path(ship).is_absolute():
        return str(Path(base_dir) / ship)
    return ship


class Traffic:
    """The traffic ships of a scenario, simulated together (see the module docstring).

    Args:
        ships: the ``[[traffic]]`` entries.
        dt_s: physics step, s; ``control_interval_s`` the autopilot's interval, s (a whole multiple of dt_s).
        reference_latlon_deg: geodetic reference of local north/east (the scenario's).
        base_dir: directory for relative ship file paths (the scenario file's).
        first_id: ``Target.id`` of the first ship (the others follow in order).
        lookahead_L, accept_L: line-of-sight look-ahead distance and waypoint acceptance radius, ship lengths.
        bandwidth_UL: natural frequency of the closed heading loop, in units of U/L (U the route speed).
        where: prefix of error messages (the scenario file).

    Raises :class:`~vessel_gym.scenarios.ScenarioError` (one line naming the entry) if a ship cannot be
    loaded or cannot make its speed.
    """

    def __init__(
        self,
        ships: Sequence[TrafficShip],
        *,
        dt_s: float = 0.05,
        control_interval_s: float = 0.25,
        reference_latlon_deg: tuple[float, float] = (0.0, 0.0),
        base_dir: str | None = None,
        first_id: int = 1,
        lookahead_L: float = LOOKAHEAD_L,
        accept_L: float = ACCEPT_L,
        bandwidth_UL: float = BANDWIDTH_UL,
        where: str = "traffic",
    ) -> None:
        if not ships:
            raise ValueError("Traffic needs at least one ship")
        self.specs = tuple(ships)
        self.n = len(self.specs)
        self.dt_s = float(dt_s)
        self.control_interval_s = float(control_interval_s)
        self.nsub = steps_for(control_interval_s, dt_s)
        loaded: dict[str, Ship] = {}
        index = []
        for i, spec in enumerate(self.specs):
            path = _ship_path(spec.ship, base_dir)
            if path not in loaded:
                try:
                    loaded[path] = load_ship(path)
                except ValueError as exc:
                    raise ScenarioError(f"{where} traffic[{i}] {spec.name!r} ship: {exc}") from None
            index.append(list(loaded).index(path))
        self.sim = Simulation(
            list(loaded.values()),
            n=self.n,
            ship_index=index,
            dt=dt_s,
            reference_latlon_deg=(float(reference_latlon_deg[0]), float(reference_latlon_deg[1])),
        )
        self.ships = [self.sim.ship(k) for k in range(self.n)]
        self.L = np.array([s.particulars.L_m for s in self.ships])
        self.lookahead = lookahead_L * self.L
        self.accept = accept_L * self.L
        self.speed_m_s = np.array([s.speed_kn * KNOT_M_S for s in self.specs])
        self.routes = [np.array(s.route_m, dtype=np.float64).reshape(-1, 2) for s in self.specs]
        self.loop = [s.at_end == "loop" for s in self.specs]
        self.ids = [first_id + k for k in range(self.n)]
        self.autopilots: list[PidAutopilot | None] = []
        for spec, ship in zip(self.specs, self.ships):
            if len(spec.route_m) and spec.speed_kn > 0.0:
                U = spec.speed_kn * KNOT_M_S
                gains = nomoto_pid_gains(ship, U, omega_n=bandwidth_UL * U / ship.particulars.L_m)
                self.autopilots.append(PidAutopilot(gains, ship.steering_gear.max_angle_deg * DEG))
            else:
                self.autopilots.append(None)
        self._rev_table = np.stack([self.sim.telegraph_rev(t) for t in range(-4, 5)], axis=1)  # (n, 9) rev/s
        self._where = where
        self._start: tuple[np.ndarray, np.ndarray] | None = None
        self.reset()

    @classmethod
    def from_scenario(
        cls, scenario: Scenario, dt_s: float = 0.05, control_interval_s: float = 0.25, **kw
    ) -> Traffic | None:
        """The scenario's traffic, or None if it has none."""
        if not scenario.traffic:
            return None
        return cls(
            scenario.traffic,
            dt_s=dt_s,
            control_interval_s=control_interval_s,
            reference_latlon_deg=(scenario.reference_latlon_deg[0], scenario.reference_latlon_deg[1]),
            base_dir=str(Path(scenario.path).parent) if scenario.path else None,
            where=scenario.path or scenario.name,
            **kw,
        )

    # --- simulation ---------------------------------------------------------------------------------------------

    def reset(self) -> None:
        """Every ship back to its start pose and speed (steady approach), first waypoint, step 0."""
        sim = self.sim
        if self._start is None:  # the steady approach is solved once; later resets copy it
            for k, spec in enumerate(self.specs):
                try:
                    sim.reset(
                        speed_m_s=float(self.speed_m_s[k]),
                        heading_deg=spec.heading_deg,
                        x_m=spec.start_m[0],
                        y_m=spec.start_m[1],
                        k=k,
                    )
                except SimulationError as exc:
                    raise ScenarioError(f"{self._where} traffic[{k}] {spec.name!r} speed_kn: {exc}") from None
                if spec.speed_kn == 0.0:
                    sim.set_helm(rudder_order_rad=0.0, rev_order=0.0, k=k)
            self._start = (sim.state.copy(), sim.inputs.copy())
        sim.state[:] = self._start[0]
        sim.inputs[:] = self._start[1]
        sim.alive[:] = True
        sim.t = 0.0
        self.wp = np.zeros(self.n, dtype=np.int64)  # index of the waypoint steered for
        self.prev = np.array([s.start_m[:2] for s in self.specs], dtype=np.float64)  # start of the leg
        self.stopped = np.array([ap is None for ap in self.autopilots])
        self.heading_ref = sim.heading.copy()
        self.cross_track = np.zeros(self.n)
        for ap in self.autopilots:
            if ap is not None:
                ap.reset()
        self.steps = 0
        self._cache: tuple[int, list[Target]] | None = None

    def _guidance(self, k: int, north: float, east: float) -> float:
        """Desired heading (rad) of ship k by line of sight on its current leg; advances the waypoint."""
        route = self.routes[k]
        last = len(route) - 1
        for _ in range(len(route) + 1):
            p0, p1 = self.prev[k], route[self.wp[k]]
            alpha, along, cross, leg = leg_frame(p0[0], p0[1], p1[0], p1[1], north, east)
            reached = waypoint_reached(north, east, p1[0], p1[1], self.accept[k]) or along > leg
            if not reached:
                break
            if self.wp[k] == last and not self.loop[k]:
                self.stopped[k] = True
                self.sim.set_helm(rudder_order_rad=0.0, k=k)
                return float(self.sim.heading[k])
            self.prev[k] = p1
            self.wp[k] = 0 if self.wp[k] == last else self.wp[k] + 1
        self.cross_track[k] = cross
        return los_heading(alpha, cross, self.lookahead[k])

    def step(self, n: int = 1) -> None:
        """Advance ``n`` control intervals: autopilot orders, then ``nsub`` physics steps each."""
        sim = self.sim
        dt = self.control_interval_s
        for _ in range(n):
            north, east = sim.north.tolist(), sim.east.tolist()
            heading, r = sim.heading.tolist(), sim.r.tolist()
            for k, ap in enumerate(self.autopilots):
                if ap is None:
                    continue
                if not self.stopped[k]:
                    ref = self._guidance(k, north[k], east[k])
                if self.stopped[k]:  # end of the route: astern until stopped in the water, then STOP
                    moving = float(sim.u[k]) > STOPPED_M_S
                    sim.set_helm(rev_order=float(self._rev_table[k, 2]) if moving else 0.0, k=k)
                    continue
                self.heading_ref[k] = ref
                sim.set_helm(rudder_order_rad=ap.order(heading[k], r[k], ref, dt), k=k)
            sim.step(self.nsub)
            self.steps += 1

    def advance_to(self, step: int) -> None:
        """Step until ``step`` control intervals have passed since :meth:`reset` (never backwards)."""
        if step > self.steps:
            self.step(step - self.steps)

    # --- readings ------------------------------------------------------------------------------------------------

    def heading_error_deg(self) -> np.ndarray:
        """Heading minus the line-of-sight heading of each ship, deg in (-180, 180] (0 for stopped ships)."""
        err = [wrap_pi_upper(float(h - ref)) for h, ref in zip(self.sim.heading, self.heading_ref)]
        return np.where(self.stopped, 0.0, np.degrees(err))

    def _telegraph(self, k: int) -> int:
        rev = float(self.sim.rev_order[k])
        if rev == 0.0:
            return 0
        return int(np.argmin(np.abs(self._rev_table[k] - rev))) - 4

    def targets(self) -> list[Target]:
        """The ships now, as link targets (computed once per step)."""
        if self._cache is not None and self._cache[0] == self.steps:
            return self._cache[1]
        out = []
        for k, (spec, ship) in enumerate(zip(self.specs, self.ships)):
            still = self.autopilots[k] is None and spec.speed_kn == 0.0
            out.append(
                Target(
                    id=self.ids[k],
                    name=spec.name,
                    reading=self.sim.bridge(k, self._telegraph(k)),
                    length_m=ship.particulars.L_m,
                    beam_m=ship.particulars.B_m,
                    mmsi=spec.mmsi,
                    call_sign=spec.call_sign,
                    ship_type=spec.ship_type,
                    draught_m=ship.particulars.T_m,
                    destination=spec.destination,
                    nav_status=NAV_MOORED if still else NAV_UNDER_WAY_ENGINE,
                )
            )
        self._cache = (self.steps, out)
        return out

    def lazy_targets(self, step: int) -> LazyTargets:
        """Targets at control step ``step`` that are simulated and computed only when read."""
        return LazyTargets(self, step)


class LazyTargets(Sequence[Target]):
    """A sequence of the traffic's targets at one step, resolved on first read (length needs no simulation)."""

    __slots__ = ("_traffic", "_step", "_items")

    def __init__(self, traffic: Traffic, step: int) -> None:
        self._traffic = traffic
        self._step = step
        self._items: list[Target] | None = None

    def _resolve(self) -> list[Target]:
        if self._items is None:
            self._traffic.advance_to(self._step)
            self._items = self._traffic.targets()
        return self._items

    def __len__(self) -> int:
        return self._traffic.n

    def __getitem__(self, i):  # type: ignore[override]
        return self._resolve()[i]

    def __iter__(self) -> Iterator[Target]:
        return iter(self._resolve())


__all__ = ["ACCEPT_L", "BANDWIDTH_UL", "LOOKAHEAD_L", "LazyTargets", "Traffic"]
