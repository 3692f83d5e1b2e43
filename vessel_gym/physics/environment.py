"""Environment & Atmosphere and Sea-State as one value object per vessel: wind, air, current, waves.

Directions at the edge are in degrees: wind *from* (meteorological), current *towards* (oceanographic),
waves *from*. Inside they become the environment row of the kernel (layout.E_*), in SI and radians.
The water depth (default infinite: deep water, no correction) enters the row as the draught-to-depth ratio
T/h that the shallow-water corrections read (:mod:`vessel_gym.physics.shallow_water`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit

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

#: the fields of an Environment, in declaration order (the columns of :func:`environment_values`)
FIELDS = tuple(f.name for f in dataclasses.fields(Environment))


def environment_values(values: dict, m: int) -> np.ndarray:
    """(m, len(FIELDS)) field values of m environments: ``values`` (field name -> scalar or array of m), the
    other fields at their defaults; each checked against its range as ``Environment(...)`` checks it."""
    values = dict(values)
    out = np.empty((m, len(FIELDS)))
    for j, f in enumerate(dataclasses.fields(Environment)):
        v = np.broadcast_to(np.asarray(values.pop(f.name, f.default), dtype=float), (m,))
        lo_, hi_ = f.metadata.get("lo"), f.metadata.get("hi")
        if f.name == "depth_m":
            bad = ~(v > 0.0)
        else:
            bad = ~np.isfinite(v) | (v < (-math.inf if lo_ is None else lo_)) | (v > (math.inf if hi_ is None else hi_))
        if bad.any():  # Environment's own message names the first bad value
            Environment(**{f.name: float(v[np.argmax(bad)])})
            raise SpecError(f"Environment {f.name}: {float(v[np.argmax(bad)])!r} is out of range")
        out[:, j] = v
    if values:
        raise TypeError(f"unknown Environment field(s) {sorted(values)}")
    return out


@njit(cache=True)
def _earth_velocities(e):
    """The current's and the air's (north, east) velocities of rows ``e`` from their speeds and directions."""
    for k in range(e.shape[0]):
        e[k, lo.E_CUR_N], e[k, lo.E_CUR_E] = current_earth(e[k, lo.E_CUR_SPEED], e[k, lo.E_CUR_TO])
        e[k, lo.E_WIND_N], e[k, lo.E_WIND_E] = air_velocity_earth(e[k, lo.E_WIND_SPEED], e[k, lo.E_WIND_FROM])


def environment_rows(vals: np.ndarray, L_m: float, T_m: float) -> np.ndarray:
    """(m, NE) kernel rows of the environments with field values ``vals`` (:func:`environment_values`) for a
    ship of length L_m and draught T_m: each the row ``Environment(...).row(L_m, T_m)`` gives, to the bit
    (the same operations, over arrays; the wave integrals per environment with waves)."""
    F = {name: vals[:, j] for j, name in enumerate(FIELDS)}
    e = np.zeros((len(vals), lo.NE))
    e[:, lo.E_WIND_SPEED] = F["wind_speed_m_s"]
    e[:, lo.E_WIND_FROM] = F["wind_from_deg"] * DEG
    e[:, lo.E_CUR_SPEED] = F["current_speed_m_s"]
    e[:, lo.E_CUR_TO] = F["current_to_deg"] * DEG
    pt = vals[:, [FIELDS.index("air_pressure_pa"), FIELDS.index("air_temperature_k")]]
    if (pt == pt[:1]).all():  # one air for all (the usual case): no sort of the rows
        air, which = pt[:1], np.zeros(len(pt), dtype=np.int64)
    else:
        air, which = np.unique(pt, axis=0, return_inverse=True)
    e[:, lo.E_RHO_AIR] = np.array([air_density(p, t) for p, t in air.tolist()])[which.reshape(-1)]
    e[:, lo.E_HS] = F["Hs_m"]
    e[:, lo.E_TP] = F["Tp_s"]
    e[:, lo.E_WAVE_FROM] = F["wave_from_deg"] * DEG
    for k in np.flatnonzero(F["Hs_m"] > 0).tolist():
        Hs, Tp = float(F["Hs_m"][k]), float(F["Tp_s"][k])
        e[k, lo.E_ZETA2] = effective_zeta2(Hs, Tp, L_m, T_m)
        e[k, lo.E_OMEGA_ZETA2] = effective_omega_zeta2(Hs, Tp, L_m, T_m)
    _earth_velocities(e)
    depth = F["depth_m"]
    for d in np.unique(depth).tolist():
        try:
            e[depth == d, lo.E_T_OVER_H] = depth_ratio(d, T_m)
        except ValueError as exc:
            raise SpecError(f"Environment {exc}") from None
    return e


class EnvironmentList(Sequence):
    """The vessels' environments: the Environment object of each vessel set one at a time, and for the vessels
    set in a batch (:meth:`set_values`) their field values, made into an Environment when asked for (an
    object per vessel costs ~0.5 kB and ~10 us to make; a batch of 262144 vessels keeps 80 B each)."""

    def __init__(self, environment: Environment, n: int) -> None:
        self._objs: list[Environment | None] = [environment] * n
        self._vals: np.ndarray | None = None  # (n, len(FIELDS)) field values, rows of batched vessels

    def __len__(self) -> int:
        return len(self._objs)

    def __getitem__(self, k):  # type: ignore[override]
        if isinstance(k, slice):
            return [self[i] for i in range(*k.indices(len(self)))]
        env = self._objs[k]
        if env is None:
            return Environment(**dict(zip(FIELDS, self._vals[k].tolist())))
        return env

    def __setitem__(self, k, value) -> None:
        self._objs[k] = value

    def set_values(self, idx: np.ndarray, vals: np.ndarray) -> None:
        """Vessels ``idx`` get the environments of field values ``vals`` (m, len(FIELDS))."""
        if self._vals is None:
            self._vals = np.zeros((len(self._objs), len(FIELDS)))
        self._vals[idx] = vals
        objs = self._objs
        for k in np.asarray(idx).tolist():
            objs[k] = None


def wrap_deg(angle_deg: float) -> float:
    """Angle in [0, 360) (of an array: elementwise, the same numbers)."""
    if isinstance(angle_deg, np.ndarray):
        a = np.fmod(angle_deg, 360.0)
        return np.where(a < 0, a + 360.0, a)
    a = math.fmod(angle_deg, 360.0)
    return a + 360.0 if a < 0 else a
