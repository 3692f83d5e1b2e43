"""The one way the slave scripts (:mod:`~vessel_gym.fmi.ship_slave`, :mod:`~vessel_gym.fmi.engine_slave`,
:mod:`~vessel_gym.fmi.gear_slave`, :mod:`~vessel_gym.fmi.gearbox_slave`) declare their real variables: a
parameter is fixed at initialisation, an input continuous, an output continuous and calculated by the slave.
The scripts run inside their FMU on a host with vessel-gym installed, so they import this module like the
physics.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from pythonfmu import Fmi2Causality, Fmi2Variability, Real
from pythonfmu.enums import Fmi2Initial

KINDS = ("parameter", "input", "output")


def register_real(
    slave: Any,
    name: str,
    kind: str,
    doc: str,
    getter: Callable[[], float] | None = None,
    setter: Callable[[float], None] | None = None,
) -> None:
    """Register the real variable ``name`` of causality ``kind`` (one of :data:`KINDS`) on ``slave``."""
    if kind == "output":
        slave.register_variable(
            Real(
                name,
                causality=Fmi2Causality.output,
                variability=Fmi2Variability.continuous,
                initial=Fmi2Initial.calculated,
                description=doc,
                getter=getter,
            )
        )
    elif kind == "parameter":
        slave.register_variable(
            Real(name, causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed, description=doc)
        )
    elif kind == "input":
        slave.register_variable(
            Real(
                name,
                causality=Fmi2Causality.input,
                variability=Fmi2Variability.continuous,
                description=doc,
                setter=setter,
            )
        )
    else:
        raise ValueError(f"variable {name!r}: kind {kind!r}, expected one of {', '.join(KINDS)}")
