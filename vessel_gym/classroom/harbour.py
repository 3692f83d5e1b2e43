"""One harbour, several own ships: the classroom's simulation.

Every own ship is a vessel of one HarbourApproach task of N vessels, built by
:func:`vessel_gym.parallel_env` (the same task code, reward and outcome as the Gymnasium environment) and stepped
together in one batch. The classroom adds what a class needs beyond the task: the ships see each other (the
pages draw every ship, and contact between two own ships, or an own ship and the scenario's traffic, ends both
runs as a contact), one weather for the whole harbour set live, a ship reset on its own, and the record each
student's debrief is scored from (:mod:`vessel_gym.classroom.debrief`).

Orders are those of ``vessel-gym play``: the rudder in 5 degree steps (:data:`~vessel_gym.ui.play.RUDDER_ORDERS_DEG`)
and the telegraph steps -4 .. 4.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vessel_gym.classroom import MAX_SHIPS
from vessel_gym.envs.task import PHASE_RESET, PHASE_STEP, reset_vessels, vessel_info
from vessel_gym.envs.tasks.colreg_ais import REP_T, AisReceiver
from vessel_gym.envs.tasks.colreg_geometry import cpa, relative_bearing
from vessel_gym.physics.units import KNOT_M_S
from vessel_gym.scenarios.geometry import hull_outline, polygons_overlap
from vessel_gym.ui.play import RUDDER_ORDERS_DEG, TELEGRAPH_STEPS

TASK_ID = "vessel_gym/HarbourApproach-v2"
#: the helm is read this often (s of simulation time): a person's order acts within a quarter second, and the
#: pages see the ships move 4 times a second of simulation time (the task's default, L/U_T/6, is 0.99 s)
CONTROL_INTERVAL_S = 0.25
#: own ships start at least this many ship lengths apart (centre to centre), so nobody starts in contact
START_SPACING_L = 1.2
#: a ship's track is recorded once per this many seconds of simulation time
TRACK_SPACING_S = 1.0
#: other ships listed as a ship's targets (nearest first): what a radar plot of a small harbour shows
MAX_TARGETS = 6
#: the other ships reach a student's page as its ship's AIS receiver has them (``envs.tasks.colreg_ais``): Class A
#: stations (ITU-R M.1371-5 Annex 1 Table 1 rates by speed and turning), SOG and COG rounded to the report's
#: resolution, dead-reckoned between reports; no lost reports and no position error (a harbour of ships a few
#: lengths apart would drown in a GNSS error of 10 m): what the student sees of the others is the report's age
AIS_CLASS = "A"
#: deg/min: a rate of turn above this is "changing course" (the faster reporting rate); CollisionAvoidance's default
AIS_TURNING_DEG_MIN = 5.0
#: a ship's run ends with these outcomes; "contact" covers quays, land, breakwaters, other own ships and traffic
ENDED = ("success", "contact", "grounding", "out_of_bounds", "diverged", "time_limit")


@dataclass
class ShipRecord:
    """What the debrief needs of one ship's current run (times s, distances m, angles deg)."""

    start_distance_m: float = 0.0
    start_t_s: float = 0.0
    outcome: str = "running"
    contact_with: str = ""  # what the contact was with: "land", a ship's name
    contacts: int = 0
    min_ship_distance_m: float = math.inf  # closest approach of the hull to another ship's hull
    rudder_effort_deg: float = 0.0  # sum of |change of rudder order|
    engine_changes: int = 0  # telegraph orders given
    rudder_abs_sum_deg: float = 0.0  # for the mean |rudder angle|
    samples: int = 0
    track: list[tuple[float, float]] = field(default_factory=list)
    info: dict[str, Any] = field(default_factory=dict)  # the task's last info of this ship


class ClassHarbour:
    """``n`` own ships in the harbour of ``scenario`` (module doc). Not thread-safe: one owner drives it."""

    def __init__(
        self,
        scenario: str,
        n: int,
        seed: int | None = None,
        pilots: int = 0,
        agent: str | None = None,
        agents: int = 0,
    ) -> None:
        import vessel_gym
        from vessel_gym.envs.tasks.harbour import own_ship
        from vessel_gym.scenarios import load_scenario
        from vessel_gym.scenarios.traffic import Traffic

        if not 1 <= n <= MAX_SHIPS:
            raise ValueError(f"ships: expected 1..{MAX_SHIPS}, got {n}")
        if not 0 <= pilots <= n:
            raise ValueError(f"pilots: expected 0..{n} (the number of ships), got {pilots}")
        if not 0 <= agents <= n - pilots or (agents > 0) != (agent is not None):
            raise ValueError(
                f"agents: expected 0..{n - pilots} ships (the ships less the pilots) with an agent"
            )
        sc = load_scenario(scenario)
        self.penv = vessel_gym.parallel_env(
            TASK_ID,
            agents=n,
            scenario=sc,
            action_type="discrete",
            engine_control=True,
            rudder_orders_deg=RUDDER_ORDERS_DEG,
            telegraph_steps=TELEGRAPH_STEPS,
            control_interval_s=CONTROL_INTERVAL_S,
            **own_ship(sc),
        )
        self.task = task = self.penv.task
        self.sim = task.sim
        self.scenario = task.scenario
        self.n = n
        self.dt = float(task.config.control_interval_s)
        self.max_steps = int(task.max_steps)
        self.L = float(task.L)
        self.B = float(task.ship.particulars.B_m)
        self.T = float(task.ship.particulars.T_m)
        self.hull = np.array(hull_outline(self.L, self.B))  # body axes (x forward, y starboard), m
        #: the last ``pilots`` ships are steered by the task's scripted harbour pilot, not by a student
        self.pilot_ships = np.arange(n - pilots, n)
        #: the ``agents`` ships before the pilot ships are steered by a trained agent (classroom.agents)
        self.agent_ships = np.arange(n - pilots - agents, n - pilots)
        students = n - pilots - agents
        self.names = [
            f"Ship {k + 1}" if k < students else f"Agent {k + 1}" if k < n - pilots else f"Pilot {k + 1}"
            for k in range(n)
        ]
        self.pilot = self._make_pilot() if pilots else None
        self.agent = None
        if agents:
            from vessel_gym.classroom.agents import AgentShips

            self.agent = AgentShips(agent, self.scenario, task.layout, self.dt, self.agent_ships)
        self.rudder_i = np.full(n, RUDDER_ORDERS_DEG.index(0.0), dtype=np.int64)
        self.tele_i = np.full(n, TELEGRAPH_STEPS.index(0), dtype=np.int64)
        self.live = np.zeros(n, dtype=np.bool_)
        self.steps = np.zeros(n, dtype=np.int64)  # control steps of each ship's run
        self.records = [ShipRecord() for _ in range(n)]
        self.traffic = Traffic.from_scenario(self.scenario, task.dt, self.dt)
        n_traffic = len(self.traffic.specs) if self.traffic is not None else 0
        #: ship k's receiver: slot j < n is own ship j, slot n + i the scenario's traffic ship i
        self.ais = AisReceiver(n, n + n_traffic, AIS_CLASS, 0.0, 0.0, 0.0, 0.0, AIS_TURNING_DEG_MIN)
        self._ais_rng = np.random.default_rng(seed)
        self._ais_cache: dict[int, tuple[float, list[dict[str, Any]]]] = {}
        self._ais_truth: tuple[float, list[tuple]] = (math.nan, [])
        self.weather: dict[str, float] = {}
        self.t_s = 0.0  # class time, s of simulation
        self.seed = seed
        if self.reset_all(seed):
            # one step compiles the step kernels here, before the class opens, rather than at the first
            # student's first key press (tens of seconds on a fresh cache, with the pages waiting); then the
            # same start again
            self.step()
            self.t_s = 0.0
        if not self.reset_all(seed):
            raise ValueError(
                f"ships: no start for {n} ships {START_SPACING_L:g} ship lengths apart in the start region of "
                f"{self.scenario.name!r} (its ship is {self.L:g} m long): give fewer ships"
            )

    # --- runs -------------------------------------------------------------------------------------------------

    def reset_all(self, seed: int | None = None) -> bool:
        """Every ship to a fresh start (the task's start region, spaced apart), the traffic to its start, the
        class weather from ship 0's draw of the scenario's ranges; False if some ships could not be spaced."""
        self.penv.reset(seed=seed)
        if self.traffic is not None:
            self.traffic.reset()
        spaced = self._space_out(np.arange(self.n))
        e = self.sim.environments[0]
        self.weather = {
            "wind_speed_m_s": float(e.wind_speed_m_s),
            "wind_from_deg": float(e.wind_from_deg),
            "current_speed_m_s": float(e.current_speed_m_s),
            "current_to_deg": float(e.current_to_deg),
        }
        for k in range(self.n):
            self._started(k)
        return spaced

    def reset_ship(self, k: int) -> None:
        """Ship ``k`` to a new start in the start region clear of the others; the others sail on."""
        self._reset(np.array([k]))
        self._space_out(np.array([k]))
        self._started(k)

    def _make_pilot(self) -> Any:
        """The task's registered ``scripted`` pilot (envs.policies.HarbourPilot), reading the observations of
        the pilot ships as one batch, its actions the discrete orders of this helm."""
        from types import SimpleNamespace

        from vessel_gym.envs.registration import declaration

        task = self.task
        base = SimpleNamespace(
            observation_layout=task.layout,
            config=task.config,
            task=task,
            action_space=self.penv.action_space(self.penv.possible_agents[0]),
        )
        return declaration(TASK_ID).pilots["scripted"](SimpleNamespace(unwrapped=base))

    def _steer_pilots(self) -> None:
        if self.pilot is None:
            return
        act = np.asarray(self.pilot(self.task.obs[self.pilot_ships]))
        self.rudder_i[self.pilot_ships] = act[:, 0]
        self.tele_i[self.pilot_ships] = act[:, 1]

    def _reset(self, idx: np.ndarray) -> None:
        reset_vessels(self.task, idx, None)
        phase = np.zeros(self.n, dtype=np.int8)
        phase[idx] = PHASE_RESET
        self.task.update(phase)

    def _space_out(self, movable: np.ndarray) -> bool:
        """Draw again the starts of ``movable`` ships that are within START_SPACING_L of an earlier ship (their
        generators continue, so each draw is new); False if 200 rounds left some too close (they keep their
        last draw)."""
        spacing = START_SPACING_L * self.L
        for _ in range(200):
            north, east = self.sim.north, self.sim.east
            clash = []
            for k in movable.tolist():
                d = np.hypot(north - north[k], east - east[k])
                d[k] = math.inf
                others = np.ones(self.n, dtype=np.bool_) if len(movable) == 1 else np.arange(self.n) < k
                if np.any(d[others] < spacing):
                    clash.append(k)
            if not clash:
                return True
            self._reset(np.array(clash))
        return False

    def _started(self, k: int) -> None:
        sim, task = self.sim, self.task
        self._apply_weather(k)
        rev0 = float(sim.rev_order[k])  # the telegraph step closest to the start's shaft speed (as play does)
        self.tele_i[k] = int(np.argmin(np.abs(task.helm.rev_table[k] - rev0)))
        self.rudder_i[k] = RUDDER_ORDERS_DEG.index(0.0)
        info = vessel_info(task, k)
        self.records[k] = ShipRecord(
            start_distance_m=float(info["distance_to_goal_m"]),
            start_t_s=self.t_s,
            track=[(float(sim.north[k]), float(sim.east[k]))],
            info=info,
        )
        self.live[k] = True
        self.steps[k] = 0
        self.ais.reset(k, self._ais_rng)  # the others are heard afresh: one report each at the next reading
        self._ais_cache.clear()  # a ship moved without a step (a reset while paused): every picture anew
        self._ais_truth = (math.nan, [])
        if self.pilot is not None and k in self.pilot_ships:
            self.pilot.reset(self.pilot_ships == k)  # its waypoints and integral start again
        if self.agent is not None and k in self.agent_ships:
            self.agent.start(k, sim)

    # --- orders and weather ----------------------------------------------------------------------------------

    def order(self, k: int, rudder_deg: float, telegraph: int) -> None:
        """Ship ``k``'s helm: ``rudder_deg`` one of RUDDER_ORDERS_DEG, ``telegraph`` in -4..4 (ValueError
        otherwise); acts at the next control step. An ended run keeps its orders (midships, stop)."""
        if rudder_deg not in RUDDER_ORDERS_DEG:
            lo, hi = RUDDER_ORDERS_DEG[0], RUDDER_ORDERS_DEG[-1]
            raise ValueError(f"rudder: expected {lo:g}..{hi:g} deg in 5 deg steps")
        if telegraph not in TELEGRAPH_STEPS:
            raise ValueError("telegraph: expected an integer -4..4")
        if not self.live[k]:
            return
        ri, ti = RUDDER_ORDERS_DEG.index(float(rudder_deg)), TELEGRAPH_STEPS.index(int(telegraph))
        rec = self.records[k]
        rec.rudder_effort_deg += abs(RUDDER_ORDERS_DEG[ri] - RUDDER_ORDERS_DEG[int(self.rudder_i[k])])
        rec.engine_changes += int(ti != self.tele_i[k])
        self.rudder_i[k], self.tele_i[k] = ri, ti

    def set_weather(self, **fields: float) -> None:
        """Wind and current for every ship now (Environment fields wind_speed_m_s, wind_from_deg,
        current_speed_m_s, current_to_deg); a value out of the Environment's range raises (SpecError)."""
        from vessel_gym.physics.environment import Environment

        new = {**self.weather, **{key: float(v) for key, v in fields.items()}}
        Environment(**new)  # checks every field's range before any ship changes
        self.weather = new
        for k in range(self.n):
            self._apply_weather(k)

    def _apply_weather(self, k: int) -> None:
        if self.weather:
            e = self.sim.environments[k]  # keeps the ship's depth and sea state
            self.sim.set_environment(dataclasses.replace(e, **self.weather), k)

    # --- the step ---------------------------------------------------------------------------------------------

    def step(self) -> list[int]:
        """Every ship and the traffic one control step; returns the ships whose run ended in it."""
        task, sim = self.task, self.sim
        self._steer_pilots()
        rudder = np.where(self.live, self.rudder_i, RUDDER_ORDERS_DEG.index(0.0))
        tele = np.where(self.live, self.tele_i, TELEGRAPH_STEPS.index(0))
        task.helm.apply(np.stack([rudder, tele], axis=1))
        if self.agent is not None:
            self.agent.steer(sim, task.obs, self.steps, self.live)
        sim.step(task.nsub)
        task.update(np.where(self.live, PHASE_STEP, 0).astype(np.int8))
        if self.traffic is not None:
            self.traffic.step()
        self.t_s += self.dt
        ended = []
        live = np.flatnonzero(self.live).tolist()
        for k in live:
            self.steps[k] += 1
            rec = self.records[k]
            rec.info = vessel_info(task, k)
            rec.rudder_abs_sum_deg += abs(math.degrees(float(sim.rudder[k])))
            rec.samples += 1
            if (self.t_s - rec.start_t_s) >= len(rec.track) * TRACK_SPACING_S:
                rec.track.append((float(sim.north[k]), float(sim.east[k])))
            if task.terminated[k]:
                outcome = str(rec.info["outcome"])
                self._end(k, outcome, {"contact": "land or quay", "grounding": "shoal"}.get(outcome, ""))
                ended.append(k)
            elif self.steps[k] >= self.max_steps:
                self._end(k, "time_limit", "")
                ended.append(k)
        for k, other in self._ship_contacts():
            for a, b in ((k, other), (other, k)):
                if isinstance(a, int) and self.live[a]:
                    self._end(a, "contact", b if isinstance(b, str) else self.names[b])
                    ended.append(a)
        return ended

    def _end(self, k: int, outcome: str, with_: str) -> None:
        rec = self.records[k]
        rec.outcome = outcome
        rec.contact_with = with_
        rec.contacts += int(outcome in ("contact", "grounding"))
        rec.track.append((float(self.sim.north[k]), float(self.sim.east[k])))
        self.live[k] = False

    def hulls(self) -> np.ndarray:
        """(n, 5, 2) outlines of the own ships, north and east, m."""
        sim = self.sim
        c, s = np.cos(sim.heading)[:, None], np.sin(sim.heading)[:, None]
        x, y = self.hull[None, :, 0], self.hull[None, :, 1]
        return np.stack([sim.north[:, None] + c * x - s * y, sim.east[:, None] + s * x + c * y], axis=2)

    def _ship_contacts(self) -> list[tuple[int, int | str]]:
        """Pairs in contact among the live own ships (and a live own ship with a traffic ship, by name); the
        records' closest approaches are updated on the way (hull to hull, m)."""
        hulls = [self.hulls()]
        names: list[int | str] = list(range(self.n))
        lengths = [self.L] * self.n
        if self.traffic is not None:
            outlines = []
            for t in self.traffic.targets():
                r = t.reading
                h = math.radians(r.hdg_deg)
                c, s = math.cos(h), math.sin(h)
                body = hull_outline(t.length_m, t.beam_m)
                outlines.append([(r.x_m + c * x - s * y, r.y_m + s * x + c * y) for x, y in body])
                names.append(t.name)
                lengths.append(t.length_m)
            hulls.append(np.array(outlines).reshape(-1, 5, 2))
        allh = np.concatenate(hulls)  # (m, 5, 2): own ships, then traffic
        gap = hull_gaps(allh)
        live = self.live
        m = len(names)
        own_live = np.zeros(m, dtype=np.bool_)
        own_live[: self.n] = live
        gap[~own_live[:, None] & ~own_live[None, :]] = np.inf  # nobody's run to score
        np.fill_diagonal(gap, np.inf)
        centre = allh.mean(axis=1)
        reach = 0.5 * (np.array(lengths)[:, None] + np.array(lengths)[None, :])
        near = np.hypot(*(centre[:, None, :] - centre[None, :, :]).transpose(2, 0, 1)) <= reach
        pairs: list[tuple[int, int | str]] = []
        for i, j in zip(*np.nonzero(np.triu(near & np.isfinite(gap), 1))):
            # hulls of length l lie within l/2 of their centre: only those pairs can meet
            if polygons_overlap([tuple(v) for v in allh[i].tolist()], [tuple(v) for v in allh[j].tolist()]):
                gap[i, j] = gap[j, i] = 0.0
                pairs.append((int(i), names[j]))  # i < j: i is an own ship (they come first)
        for k in np.flatnonzero(live).tolist():
            rec = self.records[k]
            rec.min_ship_distance_m = min(rec.min_ship_distance_m, float(gap[k].min()))
        return pairs

    # --- readings ---------------------------------------------------------------------------------------------

    def conning(self, k: int) -> dict[str, Any]:
        """The conning display of ship ``k``: heading deg, speed over ground kn, ROT deg/min, rudder and its
        order deg, shaft speed rpm, telegraph step, depth under the keel m, the run's timer s, its outcome."""
        b = self.sim.bridge(k, TELEGRAPH_STEPS[int(self.tele_i[k])])
        rec = self.records[k]
        ukc = float(self.task.depth_m[k]) - self.T
        return {
            "heading_deg": _finite(b.hdg_deg),
            "sog_kn": _finite(b.sog_kn),
            "rot_dpm": _finite(b.rot_dpm),
            "rudder_deg": _finite(b.rudder_deg),
            "rudder_order_deg": RUDDER_ORDERS_DEG[int(self.rudder_i[k])],
            "rpm": _finite(b.rpm),
            "telegraph": TELEGRAPH_STEPS[int(self.tele_i[k])],
            "ukc_m": _finite(ukc),
            "timer_s": round(self.t_s - rec.start_t_s, 2),
            "goal_m": _finite(float(rec.info.get("distance_to_goal_m", math.nan))),
            "outcome": rec.outcome,
            "contact_with": rec.contact_with,
        }

    def ais_picture(self, k: int) -> list[dict[str, Any]]:
        """The other ships (own ships and traffic) as ship ``k``'s AIS receiver has them now (``AIS_CLASS``):
        name, north and east m (the last report dead-reckoned to now), SOG m/s and COG deg of that report, its
        age s, length and beam m, and whether it is another student's ship (``own``). Once per step and ship."""
        cached = self._ais_cache.get(k)
        if cached is not None and cached[0] == self.t_s:
            return cached[1]
        if self._ais_truth[0] != self.t_s:  # every ship as it transmits now, once per step
            sim = self.sim
            vn, ve = sim.ground_velocity()
            truth = [(j, self.names[j], float(sim.north[j]), float(sim.east[j]), float(vn[j]), float(ve[j]),
                      float(sim.r[j]), self.L, self.B) for j in range(self.n)]  # fmt: skip
            if self.traffic is not None:
                for i, t in enumerate(self.traffic.targets()):
                    r = t.reading
                    sog, cog = r.sog_kn * KNOT_M_S, math.radians(r.cog_deg)
                    rot = math.radians(r.rot_dpm) / 60.0
                    truth.append((self.n + i, t.name, r.x_m, r.y_m, sog * math.cos(cog), sog * math.sin(cog),
                                  rot, t.length_m, t.beam_m))  # fmt: skip
            self._ais_truth = (self.t_s, [x for x in truth if all(math.isfinite(v) for v in x[2:7])])
        out = []
        for slot, name, n, e, tvn, tve, rot, L, B in self._ais_truth[1]:  # a diverged ship transmits nothing
            if slot == k:
                continue
            # Python floats: rounding numpy scalars costs ten times as much (16 ships: 270 reports a step)
            an, ae, avn, ave = map(float, self.ais.observe(k, slot, self.t_s, n, e, tvn, tve, rot))
            out.append(
                {
                    "name": name,
                    "n": round(an, 3),
                    "e": round(ae, 3),
                    "sog": round(math.hypot(avn, ave), 3),
                    "cog": round(math.degrees(math.atan2(ave, avn)) % 360.0, 1),
                    "vn": avn,
                    "ve": ave,
                    "age_s": round(self.t_s - float(self.ais.rep[k, slot, REP_T]), 2),
                    "L": L,
                    "B": B,
                    "own": slot < self.n,
                }
            )
        self._ais_cache[k] = (self.t_s, out)
        return out

    def targets_for(self, k: int, most: int = MAX_TARGETS) -> list[dict[str, Any]]:
        """The other ships as ship ``k``'s targets from its AIS picture (:meth:`ais_picture`), nearest first (at
        most ``most``): name, range m, relative bearing deg (clockwise from the bow), DCPA m and TCPA s (both
        keeping course and speed; ``envs.tasks.colreg_geometry.cpa``), midship to midship, the report's age s."""
        sim = self.sim
        vn, ve = sim.ground_velocity()
        n0, e0, psi = float(sim.north[k]), float(sim.east[k]), float(sim.heading[k])
        if not (math.isfinite(n0) and math.isfinite(e0) and math.isfinite(psi)):
            return []
        out = []
        for a in self.ais_picture(k):
            pn, pe = a["n"] - n0, a["e"] - e0
            dcpa, tcpa = cpa(pn, pe, a["vn"] - float(vn[k]), a["ve"] - float(ve[k]))
            out.append(
                {
                    "name": a["name"],
                    "range_m": round(math.hypot(pn, pe), 1),
                    "bearing_deg": round(math.degrees(relative_bearing(pn, pe, psi)), 1),
                    "dcpa_m": round(dcpa, 1),
                    "tcpa_s": round(tcpa, 1),
                    "age_s": a["age_s"],
                }
            )
        return sorted(out, key=lambda t: t["range_m"])[:most]

    def ships(self) -> list[dict[str, Any]]:
        """Every own ship for the chart: index, name, north and east m, heading deg, SOG m/s, outcome."""
        sim = self.sim
        sog = np.hypot(*sim.ground_velocity())
        return [
            {
                "k": k,
                "name": self.names[k],
                "n": _finite(float(sim.north[k])),
                "e": _finite(float(sim.east[k])),
                "hdg": _finite(math.degrees(float(sim.heading[k])) % 360.0),
                "sog": _finite(float(sog[k])),
                "outcome": self.records[k].outcome,
            }
            for k in range(self.n)
        ]

    def targets(self) -> list[dict[str, Any]]:
        """The scenario's traffic for the chart: name, north, east m, heading deg, length and beam m."""
        if self.traffic is None:
            return []
        return [
            {
                "name": t.name,
                "n": _finite(t.reading.x_m),
                "e": _finite(t.reading.y_m),
                "hdg": _finite(t.reading.hdg_deg),
                "L": t.length_m,
                "B": t.beam_m,
            }
            for t in self.traffic.targets()
        ]

    def chart(self) -> dict[str, Any]:
        """The harbour for the pages: bounds [n0, n1, e0, e1], hard obstacles and shoals as polygons
        [[north, east], ...], the goal and start regions, the own ship's length and beam (m)."""
        sc = self.scenario
        return {
            "name": sc.name,
            "bounds": list(sc.bounds_m),
            "hard": [[list(p) for p in pts] for _kind, _name, pts in sc.hard_obstacles()],
            "shoals": [[list(p) for p in pts] for _name, pts in sc.shoals(self.T)],
            "goal": [[p[0], p[1]] for p in sc.goal.points],
            "start": [[p[0], p[1]] for p in sc.start.points],
            "L": self.L,
            "B": self.B,
        }


def hull_gaps(hulls: np.ndarray) -> np.ndarray:
    """(m, m) least distances between the outlines ``hulls`` ((m, v, 2), m) from each vertex to the other's
    edges (numpy over all pairs); 0 is not implied for outlines that cross: test those with polygons_overlap."""
    a, b = hulls, np.roll(hulls, -1, axis=1)  # edges a -> b of every outline
    ab = b - a  # (m, v, 2)
    ap = (
        hulls[:, None, :, None, :] - a[None, :, None, :, :]
    )  # (m, m, v, v, 2): vertex of i from edge start of j
    den = np.maximum((ab * ab).sum(axis=2), 1e-12)[None, :, None, :]
    t = np.clip((ap * ab[None, :, None, :, :]).sum(axis=4) / den, 0.0, 1.0)
    d = np.sqrt(((ap - t[..., None] * ab[None, :, None, :, :]) ** 2).sum(axis=4)).min(axis=(2, 3))
    return np.minimum(d, d.T)


def _finite(x: float) -> float | None:
    """JSON has no NaN: a diverged reading is null."""
    return round(float(x), 3) if math.isfinite(x) else None
