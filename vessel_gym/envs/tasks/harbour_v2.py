"""HarbourApproach-v2: the v1 task with the harbour physics: the cross-flow hull at large drift (default ship
``kvlcc2_l7_harbour``) and the water depth under each ship read from the scenario's chart.

What differs from v1 (:mod:`vessel_gym.envs.tasks.harbour_v1`): the default ship, and after every task update
(the end of a reset and of a control step) the depth under each midship point, looked up in the chart's depth
areas by :func:`chart_depth`, becomes the draught-to-depth ratio the physics reads for the next control step.
Declaration, reward weights, start and compiled task step are v1's. The environment classes are in
:mod:`vessel_gym.envs.harbour`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from vessel_gym.envs.task import compiled_call
from vessel_gym.envs.tasks.chart import inside_polygon
from vessel_gym.envs.tasks.harbour_v1 import HarbourApproachV1Config, HarbourApproachV1Task
from vessel_gym.physics.schema import SpecError, param
from vessel_gym.physics.shallow_water import check_hull, set_charted_depth
from vessel_gym.scenarios import Scenario


@dataclass(frozen=True, kw_only=True)
class HarbourApproachV2Config(HarbourApproachV1Config):
    """HarbourApproach-v2 configuration (see :class:`~vessel_gym.envs.harbour.HarbourApproachV2Env`)."""

    ship: str | None = param(
        "kvlcc2_l7_harbour",
        doc="ship name or file, MMG hull (default: the L7 model with its estimated windage and the cross-flow "
        "hull at large drift; None: the scenario's ship)",
    )


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


class HarbourApproachV2Task(HarbourApproachV1Task):
    Config = HarbourApproachV2Config
    #: the physics sees the charted depth under each ship (a pilot policy adapts to it: envs.policies)
    depth_from_chart = True

    def __init__(self, config: HarbourApproachV2Config, n: int, scenario: Scenario | None = None) -> None:
        super().__init__(config, n, scenario=scenario)
        try:  # the chart's depth is finite: the ship's hull must be one the corrections are for
            check_hull(self.ship, self.scenario.water_depth_m)
        except ValueError:
            raise SpecError(
                f"HarbourApproach-v2 config ship: {self.ship.name!r} has a {self.ship.hull.model!r} hull; v2 applies "
                "the chart's depth through the shallow-water corrections of the MMG hull (Taimuri et al. 2020): "
                "choose an MMG ship (default kvlcc2_l7_harbour) or HarbourApproach-v1"
            ) from None
        self.depth_verts, self.depth_areas, self.depth_area = depth_tables(self.scenario)
        #: charted depth under each ship's midship point (m), as the physics sees it from the next control
        #: step on (before the clamp to 1.2 T)
        self.depth_m = np.full(n, float(self.scenario.water_depth_m))
        self._draught = float(self.ship.particulars.T_m)
        self._depth_call: tuple | None = None  # chart_depth's compiled code and its arguments, bound once

    def update(self, phase: np.ndarray) -> None:
        """v1's task update, then the depth under every ship for the next control step (:func:`chart_depth`:
        one compiled call over all vessels).

        The depth is read once per control step, not in every physics step within it: over one
        control step (L / U_T / 6: 0.99 s on kvlcc2_l7) the ship moves about a sixth of its length, while the
        shallow-water corrections already take the depth at the midship point for the whole hull, and the
        chart's depth areas change by steps at their edges: a reading per physics step would move where a
        step in depth takes effect by at most a sixth of a ship length."""
        super().update(phase)
        call = self._depth_call
        if call is None:
            sim = self.sim
            # views of the simulation's state: the simulation keeps its arrays (and the task kernel binds them)
            args = (
                sim.north,
                sim.east,
                self.depth_verts,
                self.depth_areas,
                self.depth_area,
                float(self.scenario.water_depth_m),
                self._draught,
                self.depth_m,
                sim.env,
            )
            chart_depth(*args)  # compiles, or loads from the cache, the lookup for these arguments
            self._depth_call = compiled_call(chart_depth, args)
            return
        call[0](*call[1])

    def __getstate__(self) -> dict:
        state = super().__getstate__()
        state["_depth_call"] = None  # compiled code does not pickle; a copy binds its own at its first update
        return state
