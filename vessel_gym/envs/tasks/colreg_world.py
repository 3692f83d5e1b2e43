"""The encounters' bookkeeping of CollisionAvoidance: which vessels of the simulation share an encounter and
which are in it now (:class:`World`), the own ships as the helm sees them (:class:`OwnShips`), and the scripted
targets' rule-following helm (:func:`steer_targets`)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from vessel_gym.control.angles import wrap_pi
from vessel_gym.envs.tasks.colreg_ais import AisReceiver
from vessel_gym.envs.tasks.colreg_geometry import GIVE_WAY_ROLES, classify, cpa, polygon_edges
from vessel_gym.physics.simulation import Simulation
from vessel_gym.scenarios.geometry import hull_outline


class OwnShips:
    """The own ships of a simulation (its first ``n`` vessels) as the helm sees them: actions reach them only,
    and the targets keep the orders they started with (constant-velocity targets)."""

    def __init__(self, sim: Simulation, n: int) -> None:
        self.sim_ = sim
        self.n = n
        self.ships = sim.ships
        self.ship_index = sim.ship_index[:n]

    def ship(self, k: int = 0) -> Any:
        return self.sim_.ship(k)

    def telegraph_rev(self, telegraph: Any, k: int | None = None) -> np.ndarray:
        return (
            self.sim_.telegraph_rev(telegraph)[: self.n]
            if k is None
            else self.sim_.telegraph_rev(telegraph, k)
        )

    def set_helm(self, rudder_order_rad: Any = None, rev_order: Any = None, k: Any = None) -> None:
        self.sim_.set_helm(rudder_order_rad, rev_order, k=slice(0, self.n) if k is None else k)


class World:
    """Which vessels of the simulation share an encounter and which are in it now.

    Own ship k (vessel k) is in encounter ``world_of[k]`` at slot ``slot_of[k]``; encounter w's vessels by slot
    are ``members[w]``: its ``agents`` own ships, then its ``max_targets`` target slots (vessels after the own
    ships). ``active[j]``: vessel j takes part (a target slot an encounter leaves empty, or a ship whose episode
    ended, does not)."""

    def __init__(self, n: int, agents: int, targets: int, L: float, B: float, observed: int) -> None:
        worlds = n // agents
        self.agents = agents
        self.targets = targets
        self.members = [
            [w * agents + s for s in range(agents)] + [n + w * targets + j for j in range(targets)]
            for w in range(worlds)
        ]
        self.world_of = [k // agents for k in range(n)]
        self.slot_of = [k % agents for k in range(n)]
        self.active = np.zeros(n + worlds * targets, dtype=np.bool_)
        self.outline = hull_outline(L, B)
        self.length = L
        self.reach = math.hypot(L, B)  # m: centres farther apart than this cannot touch
        self.slots_observed = observed
        self.course = np.zeros(n + worlds * targets)  # rad, each ship's course at the start
        # restricted waters (set by the task): the polygons a hull must not reach (land, and depth areas
        # shallower than the draught plus the under-keel margin) with their boxes, and all their edges
        self.obstacles: list[tuple[list, tuple[float, float, float, float]]] = []
        self.edges = np.zeros((0, 4))
        # the range-sensor sweep: its rays' relative bearings (rad; empty: no sweep) and sectors
        self.sensors = 0
        self.bearings = np.zeros(0)
        self.ais: AisReceiver | None = None  # targets as received over AIS (None: the truth)

    def set_waters(self, polys: list) -> None:
        """The obstacles of restricted waters: polygons of (north, east) points, m."""
        self.obstacles = [
            (p, (min(q[0] for q in p), max(q[0] for q in p), min(q[1] for q in p), max(q[1] for q in p)))
            for p in polys
        ]
        self.edges = polygon_edges(polys)


def steer_targets(sim: Simulation, world: World, law: tuple) -> None:
    """Rudder orders of the scripted targets that keep the rules: a target that must give way to an own ship of
    its encounter (head-on, crossing with the own ship on its starboard side, overtaking it) alters ``law``'s
    turn to starboard of its start course once the TCPA is below ``law``'s threshold, and back after the CPA;
    otherwise it holds its start course (a stand-on target keeps course, rule 17(a)(i))."""
    Kp, Kd, limit, turn, react, risk = law
    north, east, psi, r = sim.north, sim.east, sim.heading, sim.r
    vn, ve = sim.ground_velocity()
    for members in world.members:
        own = [j for j in members[: world.agents] if world.active[j]]
        for j in members[world.agents :]:
            if not world.active[j]:
                continue
            ref = world.course[j]
            for o in own:
                pn, pe = north[o] - north[j], east[o] - east[j]
                dcpa, tcpa = cpa(pn, pe, vn[o] - vn[j], ve[o] - ve[j])
                role = classify(pn, pe, psi[j], psi[o], dcpa < risk and tcpa > 0.0)
                if role in GIVE_WAY_ROLES and tcpa < react:
                    ref = world.course[j] + turn
            e = wrap_pi(ref - psi[j])
            sim.set_helm(rudder_order_rad=min(max(Kp * e - Kd * r[j], -limit), limit), k=j)
