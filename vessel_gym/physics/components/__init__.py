"""The component contract: what a subsystem of a vessel declares, and how a user's own one is found.

A component fills one **slot** of a vessel (:data:`SLOTS`), reads its parameters from one ship-file table
(keys with unit, range and source), may own states of the integrated state row, contributes named forces
(X, Y, N at midship, body axes) and is one function. The built-in components are declared in
:mod:`~vessel_gym.physics.components.registry` (their compiled equations stay where they are);
:mod:`~vessel_gym.physics.components.compose` checks a composition (a replaced slot loses everything its
built-in contributed, a slot is filled once) and names the forces. docs/components.md has worked examples.

This module stays light (no kernels): the ship-file loader imports it to resolve ``model`` import paths.
"""

from __future__ import annotations

import importlib
import re
from abc import ABC, abstractmethod
from typing import Any, ClassVar, NamedTuple

import numpy as np

#: the slots of a vessel; "extra" takes any number of added components (thrusters, tugs, fenders)
SLOTS = (
    "hull",
    "propeller",
    "engine",
    "governor",
    "transmission",
    "shaft",
    "steering_gear",
    "rudder",
    "windage",
    "wave_drift",
    "current",
    "extra",
)
EXTRA = "extra"

# module.path:Attribute, each part a Python identifier
_IMPORT_PATH = re.compile(r"^[A-Za-z_]\w*(\.[A-Za-z_]\w*)*:[A-Za-z_]\w*(\.[A-Za-z_]\w*)*$")


class ForceRecord(NamedTuple):
    """Forces of one component on every vessel: X (N, surge), Y (N, sway), N (N m, yaw) at midship."""

    X: np.ndarray
    Y: np.ndarray
    N: np.ndarray


class Component(ABC):
    """Base class of a user's component written in plain Python (duck typing works too: any object with
    ``forces(sim, x)``; its slot is then ``getattr(obj, "slot", "extra")``).

    Class attributes declare the contract:

    * ``slot``: one of :data:`SLOTS` ("extra" for an added component such as a bow thruster),
    * ``Params``: a frozen dataclass whose fields are made with :func:`vessel_gym.physics.schema.param`
      (unit, range, doc): the keys of the component's ship-file table, checked on loading like every built-in
      table; None takes the table as a plain dict,
    * ``states``: names of state-row entries the component owns. User components own none yet: the state row
      (:data:`vessel_gym.physics.layout.STATE_NAMES`) is integrated by the compiled kernel, so the engine,
      governor, shaft and steering gear are not replaceable (``replace=`` says so).

    A component built from a ship file is constructed as ``cls(ship, params)``. ``forces(sim, x)`` returns
    (N, 3) X, Y, N for the batch of states ``x`` (N, NX), evaluated once per integration stage. A hull
    replacing the built-in one also gives ``added_mass()``: its 3x3 added-mass matrix M_A (kg, kg m,
    kg m^2) about midship, added to the rigid body's (the built-in hull's added mass leaves with it).
    """

    slot: ClassVar[str] = EXTRA
    Params: ClassVar[type | None] = None
    states: ClassVar[tuple[str, ...]] = ()

    def __init__(self, ship: Any = None, params: Any = None) -> None:
        self.ship, self.params = ship, params

    @property
    def name(self) -> str:
        return type(self).__name__

    @abstractmethod
    def forces(self, sim: Any, x: np.ndarray) -> np.ndarray:
        """(N, 3) forces X (N), Y (N), N (N m) at midship, body axes, for the stage states ``x`` (N, NX)."""


def slot_of(component: Any) -> str:
    """The slot a component fills ("extra" when it declares none)."""
    return getattr(component, "slot", EXTRA)


def name_of(component: Any) -> str:
    """The name of a component's forces (its ``name``, else its class name)."""
    name = getattr(component, "name", None)
    return name if isinstance(name, str) and name else type(component).__name__


def import_model(path: Any, where: str) -> type:
    """The class named by an import path ``"package.module:Class"``; raises ValueError naming ``where``
    (file and key) when the path is malformed, the module cannot be imported or has no such class."""
    if not isinstance(path, str) or not _IMPORT_PATH.match(path):
        raise ValueError(f"{where}: {path!r} is not an import path 'package.module:Class'")
    module_name, attr = path.split(":")
    try:
        obj: Any = importlib.import_module(module_name)
    except ImportError as exc:
        raise ValueError(f"{where}: cannot import module {module_name!r} ({exc})") from None
    except Exception as exc:  # noqa: BLE001 - a user module failing at import: one line, not a traceback
        raise ValueError(f"{where}: importing {module_name!r} failed ({type(exc).__name__}: {exc})") from None
    for part in attr.split("."):
        if not hasattr(obj, part):
            raise ValueError(f"{where}: module {module_name!r} has no {attr!r}")
        obj = getattr(obj, part)
    if not isinstance(obj, type) or not callable(getattr(obj, "forces", None)):
        raise ValueError(f"{where}: {path!r} is not a component class (a class with forces(sim, x))")
    return obj
