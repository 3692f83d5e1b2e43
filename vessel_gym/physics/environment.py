"""Environment & Atmosphere and Sea-State as one value object per vessel: wind, air, current, waves.

Directions at the edge are in degrees: wind *from* (meteorological), current *towards* (oceanographic),
waves *from*. Inside they become the environment row of the kernel (layout.E_*), in SI and radians.
The water depth (default infinite: deep water, no correction) enters the row as the draught-to-depth ratio
T/h that the shallow-water corrections read (:mod:`vessel_gym.physics.shallow_water`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.atmosphere import air_density, air_velocity_earth
from vessel_gym.physics.schema import SpecError, check_fields, param
from vessel_gym.physics.seastate import current_earth, effective_omega_zeta2, effective_zeta2
from vessel_gym.physics.shallow_water import depth_ratio
from vessel_gym.physics.units import DEG, P_ISA_PA, T_ISA_K


@dataclass(frozen=True, kw_only=True)
class Environment:
    """Weather, atmosphere and sea state around a vessel (all uniform in space and constant in time)."""

    wind_speed_m_s: float = param(0.0, unit="m/s", lo=0.0, hi=60.0, doc="true wind speed at 10 m")
    wind_from_deg: float = param(0.0, unit="deg", lo=-360.0, hi=360.0, doc="true wind direction, from")
    air_pressure_pa: float = param(P_ISA_PA, unit="Pa", lo=85000.0, hi=110000.0)
    air_temperature_k: float = param(T_ISA_K, unit="K", lo=233.0, hi=323.0)
    current_speed_m_s: float = param(0.0, unit="m/s", lo=0.0, hi=6.0)
    current_to_deg: float = param(0.0, unit="deg", lo=-360.0, hi=360.0, doc="current direction, towards")
    Hs_m: float = param(0.0, unit="m", lo=0.0, hi=16.0, doc="significant wave height")
    Tp_s: float = param(8.0, unit="s", lo=1.0, hi=25.0, doc="spectral peak period")
    wave_from_deg: float = param(0.0, unit="deg", lo=-360.0, hi=360.0, doc="mean wave direction, from")
    # no range in the metadata: infinity (deep water) is the default; checked in __post_init__ and, against
    # the ship's draught, in row()
    depth_m: float = param(math.inf, unit="m", doc="water depth under the ship (inf: deep water)")

    def __post_init__(self) -> None:
        # at construction, so a bad value is named here and not met later as a kernel or engine failure
        check_fields(self, "Environment")
        if (
            isinstance(self.depth_m, bool)
            or not isinstance(self.depth_m, (int, float))
            or not self.depth_m > 0
        ):
            raise SpecError(
                f"Environment depth_m: expected a depth > 0 m or inf (deep water), got {self.depth_m!r}"
            )

    @property
    def rho_air_kg_m3(self) -> float:
        return air_density(self.air_pressure_pa, self.air_temperature_k)

    def row(self, L_m: float, T_m: float) -> np.ndarray:
        """Kernel environment row for a ship of length L_m and draught T_m."""
        e = np.zeros(lo.NE)
        e[lo.E_WIND_SPEED] = self.wind_speed_m_s
        e[lo.E_WIND_FROM] = self.wind_from_deg * DEG
        e[lo.E_CUR_SPEED] = self.current_speed_m_s
        e[lo.E_CUR_TO] = self.current_to_deg * DEG
        e[lo.E_RHO_AIR] = self.rho_air_kg_m3
        e[lo.E_HS] = self.Hs_m
        e[lo.E_TP] = self.Tp_s
        e[lo.E_WAVE_FROM] = self.wave_from_deg * DEG
        e[lo.E_ZETA2] = effective_zeta2(self.Hs_m, self.Tp_s, L_m, T_m) if self.Hs_m > 0 else 0.0
        e[lo.E_OMEGA_ZETA2] = effective_omega_zeta2(self.Hs_m, self.Tp_s, L_m, T_m) if self.Hs_m > 0 else 0.0
        e[lo.E_CUR_N], e[lo.E_CUR_E] = current_earth(e[lo.E_CUR_SPEED], e[lo.E_CUR_TO])
        e[lo.E_WIND_N], e[lo.E_WIND_E] = air_velocity_earth(e[lo.E_WIND_SPEED], e[lo.E_WIND_FROM])
        try:
            e[lo.E_T_OVER_H] = depth_ratio(float(self.depth_m), T_m)
        except ValueError as exc:
            raise SpecError(f"Environment {exc}") from None
        return e


CALM = Environment()


def wrap_deg(angle_deg: float) -> float:
    """Angle in [0, 360)."""
    a = math.fmod(angle_deg, 360.0)
    return a + 360.0 if a < 0 else a
