"""Typed, strict environment configuration (the schema loader of ship and scenario files).

Each environment has a frozen config dataclass; subclasses inherit and override defaults. A config is built
from (in order) the class defaults, an optional TOML file or mapping or config instance, and keyword
overrides; nested tables (``reward``) merge key by key. Unknown keys, wrong types and out-of-range values
raise :class:`~vessel_gym.physics.schema.SpecError` with a one-line message naming the key.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

from vessel_gym.physics.schema import SpecError, build, param, read_toml

C = TypeVar("C")

# Reward weights: any sign (a negative weight turns a penalty into a bonus), bounded to catch typos
WEIGHT_RANGE = (-1e3, 1e3)


def weight(default: float, doc: str) -> Any:
    """A reward-weight field: reward = sum of weight x term; ``doc`` says what the term is."""
    return param(default, lo=WEIGHT_RANGE[0], hi=WEIGHT_RANGE[1], doc=doc)


@dataclass(frozen=True, kw_only=True)
class ShipEnvConfig:
    """Settings shared by every vessel-gym environment."""

    ship: str | None = param("kvlcc2_l7", doc="built-in ship name or ship file path")
    dt_s: float | None = param(
        None,
        unit="s",
        lo=1e-4,
        hi=10.0,
        doc="physics step (default: the longest whole fraction of the control interval within 0.7 of the "
        "integrator's stable step for the ship)",
    )
    control_interval_s: float = param(
        0.25, unit="s", lo=1e-4, hi=600.0, doc="time between actions; a whole multiple of dt_s or it raises"
    )
    method: str = param("rk4", choices=("rk4", "euler"), doc="integrator")
    action_type: str = param("continuous", choices=("continuous", "discrete"), doc="action type")
    engine_control: bool = param(False, doc="the agent also gives the engine order")
    rudder_limit_deg: float | None = param(
        None,
        unit="deg",
        lo=1.0,
        hi=70.0,
        doc="continuous: |action| = 1 orders this rudder (default: gear limit)",
    )
    rudder_orders_deg: tuple[float, ...] = param(
        (-35.0, -20.0, -10.0, -5.0, 0.0, 5.0, 10.0, 20.0, 35.0),
        unit="deg",
        lo=-70.0,
        hi=70.0,
        doc="discrete: the helm orders, negative = port",
    )
    telegraph_steps: tuple[int, ...] = param(
        (-4, -3, -2, -1, 0, 1, 2, 3, 4), unit="-", lo=-4, hi=4, doc="discrete: the telegraph steps offered"
    )
    observation_type: str = param(
        "normalized",
        choices=("normalized", "physical"),
        doc="normalized: each feature / its scale in [-1, 1]; physical: SI units clipped to +-scale",
    )


@dataclass(frozen=True, kw_only=True)
class OpenWaterConfig(ShipEnvConfig):
    """Settings shared by the open-water tasks (ZigZag, TurningCircle): the steady approach they start from."""

    approach_speed_m_s: float | None = param(
        None, unit="m/s", lo=0.01, hi=30.0, doc="steady approach speed (default: ship test speed)"
    )
    initial_heading_deg: tuple[float, ...] = param(
        (0.0, 0.0), unit="deg", lo=-360.0, hi=360.0, doc="[min, max] original course"
    )


@dataclass(frozen=True, kw_only=True)
class RollOptionsConfig:
    """The roll options of a task on a ship with roll (a 4-DOF ship such as ``container``); refused on a 3-DOF
    ship. Off by default: the observation, the reward and the ``info`` keys are then those without roll."""

    observe_roll: bool = param(
        False, doc="append roll angle phi / heel_ref and roll rate p / (heel_ref omega_phi) to the observation"
    )
    heel_weight: float = param(
        0.0,
        lo=WEIGHT_RANGE[0],
        hi=WEIGHT_RANGE[1],
        doc="weight of the heel reward term -(phi / heel_ref)^2; 0: no heel term (and no info key)",
    )
    heel_ref_deg: float = param(
        10.0,
        unit="deg",
        lo=0.1,
        hi=40.0,
        doc="heel scale of the roll observation and the heel term (default: the IS Code's heel-in-turn 10 deg)",
    )


def _as_table(value: Any) -> Any:
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: _as_table(getattr(value, f.name)) for f in dataclasses.fields(value) if f.init}
    if isinstance(value, tuple):
        return [_as_table(v) for v in value]
    return value


def _merge(base: dict, over: Mapping) -> dict:
    out = dict(base)
    for k, v in over.items():
        if isinstance(v, Mapping) and isinstance(out.get(k), Mapping):
            out[k] = _merge(out[k], v)
        elif isinstance(v, tuple):
            out[k] = list(v)
        else:
            out[k] = _as_table(v) if dataclasses.is_dataclass(v) else v
    return out


def make_config(
    cls: type[C],
    config: C | Mapping | str | Path | None = None,
    where: str = "",
    base: Mapping | None = None,
    **overrides: Any,
) -> C:
    """Build config ``cls`` from a config instance, mapping or TOML path, plus keyword overrides (strict).

    ``base`` (a preset: values over the class defaults) lies under a mapping or TOML ``config`` and the
    overrides; a config instance is complete and takes no base."""
    where = where or f"{cls.__name__}"
    table: dict = _merge({}, base or {})
    if isinstance(config, (str, Path)):
        where = str(config)
        table = _merge(table, read_toml(Path(config)))
    elif isinstance(config, cls):
        if not overrides:
            return config
        table = _as_table(config)
    elif isinstance(config, Mapping):
        table = _merge(table, config)
    elif config is not None:
        raise SpecError(f"{where}: config must be a {cls.__name__}, a mapping or a TOML path, got {config!r}")
    table = _merge(table, overrides)
    return build(cls, table, where)


def config_fields(cls: type) -> list[dataclasses.Field]:
    """The init fields of a config class (for documentation)."""
    return [f for f in dataclasses.fields(cls) if f.init]
