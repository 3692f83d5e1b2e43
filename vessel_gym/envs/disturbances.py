"""Wind, current and waves for the open-water tasks, drawn per episode from ranges by the reset seed.

The draw becomes the vessel's :class:`~vessel_gym.physics.environment.Environment` in the simulation
(``Simulation.set_environment``) before the steady approach is solved, so the physics applies it (wind on
the ship's windage, current through the relative velocity, mean wave drift) and the ship starts in
equilibrium in it; the task keeps no copy. Directions are relative to the episode's original course:
wind and waves *from* (0 = from ahead, 90 = from starboard), current *towards* (0 = with the ship,
90 = setting her to starboard), so a range means the same to the ship whatever course the episode draws.

A disturbance whose speed or height range is [0, 0] (the default) draws nothing: the random stream of the
episode, and so every episode, is exactly that of calm water.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.envs.config import OpenWaterConfig
from vessel_gym.envs.task import _uniform
from vessel_gym.physics.environment import Environment, wrap_deg
from vessel_gym.physics.schema import SpecError, check_ranges, param
from vessel_gym.physics.shipfile import Ship, builtin_ships, load_ship
from vessel_gym.physics.simulation import Simulation

DISTURBANCE_RANGES = (
    "wind_speed_m_s",
    "wind_from_rel_deg",
    "current_speed_m_s",
    "current_to_rel_deg",
    "Hs_m",
    "Tp_s",
    "wave_from_rel_deg",
)


@dataclass(frozen=True, kw_only=True)
class DisturbedOpenWaterConfig(OpenWaterConfig):
    """Open-water settings with wind, current and waves (each a [min, max] range drawn per episode)."""

    wind_speed_m_s: tuple[float, ...] = param(
        (0.0, 0.0), unit="m/s", lo=0.0, hi=60.0, doc="[min, max] true wind speed at 10 m (needs [windage])"
    )
    wind_from_rel_deg: tuple[float, ...] = param(
        (0.0, 360.0),
        unit="deg",
        lo=-360.0,
        hi=360.0,
        doc="[min, max] wind from, relative to the original course",
    )
    current_speed_m_s: tuple[float, ...] = param(
        (0.0, 0.0), unit="m/s", lo=0.0, hi=6.0, doc="[min, max] current speed"
    )
    current_to_rel_deg: tuple[float, ...] = param(
        (0.0, 360.0),
        unit="deg",
        lo=-360.0,
        hi=360.0,
        doc="[min, max] current towards, relative to the original course",
    )
    Hs_m: tuple[float, ...] = param(
        (0.0, 0.0), unit="m", lo=0.0, hi=16.0, doc="[min, max] significant wave height (needs [wave_drift])"
    )
    Tp_s: tuple[float, ...] = param(
        (8.0, 8.0), unit="s", lo=1.0, hi=25.0, doc="[min, max] spectral peak period"
    )
    wave_from_rel_deg: tuple[float, ...] = param(
        (0.0, 360.0),
        unit="deg",
        lo=-360.0,
        hi=360.0,
        doc="[min, max] waves from, relative to the original course",
    )


class Disturbances:
    """Draws a vessel's wind, current and waves for an episode and sets them in the simulation.

    Raises SpecError at construction for a range that is not [min, max], and for wind or waves on a ship
    whose file has no ``[windage]`` or ``[wave_drift]`` table (they would exert no force on it).
    """

    def __init__(self, config: DisturbedOpenWaterConfig, ship: Ship, where: str) -> None:
        check_ranges(config, DISTURBANCE_RANGES, where)
        self.c = config
        self.wind = config.wind_speed_m_s[1] > 0.0
        self.current = config.current_speed_m_s[1] > 0.0
        self.waves = config.Hs_m[1] > 0.0
        for on, table, key in ((self.wind, "windage", "wind_speed_m_s"), (self.waves, "wave_drift", "Hs_m")):
            if on and getattr(ship, table) is None:
                having = [n for n in builtin_ships() if getattr(load_ship(n), table) is not None]
                raise SpecError(
                    f"{where} {key}: ship {ship.name!r} has no [{table}] table, so it would exert no force; "
                    f"use a ship with one (built in: {', '.join(having)}) or set {key} = [0, 0]"
                )
        self.active = self.wind or self.current or self.waves

    def draw(self, rng: Any, course_deg: Any) -> Environment:
        """This episode's environment for a ship whose original course is ``course_deg`` (compass)."""
        return Environment(**self.draw_values(rng, course_deg))

    def draw_values(self, rng: Any, course_deg: Any) -> dict[str, Any]:
        """The drawn ``Environment`` keywords: floats from a numpy Generator, arrays over the vessels from
        :class:`~vessel_gym.envs.generators.BatchDraws` (each vessel drawing what a lone reset draws)."""
        c = self.c
        kw: dict[str, Any] = {}
        if self.wind:
            kw["wind_speed_m_s"] = _uniform(rng, c.wind_speed_m_s)
            kw["wind_from_deg"] = wrap_deg(course_deg + _uniform(rng, c.wind_from_rel_deg))
        if self.current:
            kw["current_speed_m_s"] = _uniform(rng, c.current_speed_m_s)
            kw["current_to_deg"] = wrap_deg(course_deg + _uniform(rng, c.current_to_rel_deg))
        if self.waves:
            kw["Hs_m"] = _uniform(rng, c.Hs_m)
            kw["Tp_s"] = _uniform(rng, c.Tp_s)
            kw["wave_from_deg"] = wrap_deg(course_deg + _uniform(rng, c.wave_from_rel_deg))
        return kw

    def apply(self, sim: Simulation, k: Any, rng: Any, course_deg: Any) -> None:
        """Set vessel k's environment for a new episode (nothing, and no draw, when all are calm); ``k`` an
        index array: those vessels' (``rng`` their draws, ``course_deg`` a scalar or an array over them)."""
        if not self.active:
            return
        if np.ndim(k) == 0:
            sim.set_environment(self.draw(rng, course_deg), k)
            return
        sim.set_environments(k, **self.draw_values(rng, course_deg))


__all__ = ["DISTURBANCE_RANGES", "DisturbedOpenWaterConfig", "Disturbances"]
