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

import contextlib
import importlib
import io
import os
import re
import sys
from abc import ABC, abstractmethod
from collections.abc import Iterator
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

#: the setting that lets ship files name code outside vessel-gym's own components (docs/components.md,
#: "Code from ship files"): a ship file is data a user may have downloaded, and importing a module runs it
ALLOW_CODE_ENV = "VESSEL_GYM_ALLOW_CODE"
#: import paths below this package are vessel-gym's own components, always allowed
TRUSTED_PACKAGE = "vessel_gym.physics.components"
_code_allowed = False


def allow_code(enabled: bool = True) -> None:
    """Let ship files loaded from now on in this process name components in any importable module
    (``--allow-code`` on the command line, or ``VESSEL_GYM_ALLOW_CODE=1``)."""
    global _code_allowed
    _code_allowed = bool(enabled)


def code_allowed() -> bool:
    """Whether ship files may name code outside :data:`TRUSTED_PACKAGE` (:func:`allow_code` or the env)."""
    return _code_allowed or os.environ.get(ALLOW_CODE_ENV, "").strip() not in ("", "0")


# module.path:Attribute, each part a Python identifier
_IMPORT_PATH = re.compile(r"^[A-Za-z_]\w*(\.[A-Za-z_]\w*)*:[A-Za-z_]\w*(\.[A-Za-z_]\w*)*$")


class ForceRecord(NamedTuple):
    """Forces of one component on every vessel: X (N, surge), Y (N, sway), N (N m, yaw) at midship."""

    X: np.ndarray
    Y: np.ndarray
    N: np.ndarray


class State(NamedTuple):
    """A state a component owns and the integrator integrates with the vessel's: its name, unit and the value
    a reset starts from (a component may solve its steady value instead, ``Engine.steady_states``)."""

    name: str
    unit: str
    initial: float = 0.0
    doc: str = ""


class Component(ABC):
    """Base class of a user's component written in plain Python (duck typing works too: any object with
    ``forces(sim, x)``; its slot is then ``getattr(obj, "slot", "extra")``).

    Class attributes declare the contract:

    * ``slot``: one of :data:`SLOTS` ("extra" for an added component such as a bow thruster),
    * ``Params``: a frozen dataclass whose fields are made with :func:`vessel_gym.physics.schema.param`
      (unit, range, doc): the keys of the component's ship-file table, checked on loading like every built-in
      table; None takes the table as a plain dict,
    * ``states``: the :class:`State` entries the component owns (name, unit, initial value). The integrator
      integrates them with the vessel's state, stage by stage with the same method, from the rates the
      component's ``rates(sim, x, s)`` returns ((N, k), in the order of ``states``). Every method of a
      component that owns states receives them as a third argument ``s`` (N, k): ``forces(sim, x, s)``,
      ``rates(sim, x, s)``, and an engine's ``shaft_torque`` or a steering gear's ``rudder_rate``.

    A component built from a ship file is constructed as ``cls(ship, params)``. ``forces(sim, x)`` returns
    (N, 3) X, Y, N for the batch of states ``x`` (N, NX), evaluated once per integration stage. A hull
    replacing the built-in one also gives ``added_mass()``: its 3x3 added-mass matrix M_A (kg, kg m,
    kg m^2) about midship, added to the rigid body's (the built-in hull's added mass leaves with it). The
    engine and the steering gear drive states of the vessel rather than forces: subclass :class:`Engine` or
    :class:`SteeringGear`.
    """

    slot: ClassVar[str] = EXTRA
    Params: ClassVar[type | None] = None
    states: ClassVar[tuple[State, ...]] = ()

    def __init__(self, ship: Any = None, params: Any = None) -> None:
        self.ship, self.params = ship, params

    @property
    def name(self) -> str:
        return type(self).__name__

    @abstractmethod
    def forces(self, sim: Any, x: np.ndarray) -> np.ndarray:
        """(N, 3) forces X (N), Y (N), N (N m) at midship, body axes, for the stage states ``x`` (N, NX)."""


class Engine(Component):
    """Base of a user's engine (slot ``engine``): the engine with its speed governor (and its own clutch,
    gearbox or reversing gear if it has them) driving the ship's propeller shaft.

    Connections: it reads the shaft speed ``x[:, X_REV]`` (rev/s, negative astern) and the shaft-speed order
    ``sim.rev_order`` (rev/s) and returns the torque it drives the propeller shaft with, ``shaft_torque(sim,
    x, s)`` (N,) in N m at the propeller shaft (after its gearbox, signed like the shaft speed for ahead
    drive). The ship's shaft integrates the shaft speed, 2 pi I dn/dt = Q_drive - Q_P - Q_f
    (:func:`vessel_gym.physics.propulsion.shaft_rate`), with I the ``[transmission]`` shaft inertia plus the
    engine's own rotating inertia referred to the propeller shaft, ``shaft_inertia_kgm2()`` (kg m^2; i^2
    I_engine for a gear ratio i). The built-in engine's torque map, governor (its integrator state) and
    reversing gear leave with it, and its inertia too. The engine's states (a governor integrator, a
    turbocharger lag, ...) are :class:`State` entries with their ``rates``.

    At a reset to a steady approach, ``steady_states(sim, x, Q_hold)`` returns the states (N, k) that hold the
    solved shaft speed ``x[:, X_REV]`` with the drive torque ``Q_hold`` (N,) N m (= Q_P + Q_f); by default
    the states' initial values.
    """

    slot: ClassVar[str] = "engine"

    @abstractmethod
    def shaft_torque(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        """(N,) drive torque at the propeller shaft, N m, at the stage states ``x`` and own states ``s``."""

    @abstractmethod
    def shaft_inertia_kgm2(self) -> float:
        """The engine's rotating inertia referred to the propeller shaft, kg m^2."""

    def rates(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        """(N, k) time derivatives of the engine's own states (no states: an empty array)."""
        return np.zeros((x.shape[0], len(self.states)))

    def steady_states(self, sim: Any, x: np.ndarray, Q_hold: np.ndarray) -> np.ndarray:
        """(N, k) own states of a steady run at the shaft speeds of ``x`` with drive torques ``Q_hold`` N m."""
        return np.tile([st.initial for st in self.states], (x.shape[0], 1)).astype(float)

    def forces(self, sim: Any, x: np.ndarray, s: np.ndarray | None = None) -> np.ndarray:
        """An engine exerts no force on the hull (the propeller's thrust is the propeller's)."""
        return np.zeros((x.shape[0], 3))


class SteeringGear(Component):
    """Base of a user's steering gear (slot ``steering_gear``): moves the rudder towards the helm's order.

    Connections: it reads the rudder angle ``x[:, X_DELTA]`` (rad, positive to starboard) and the order
    ``sim.rudder_order`` (rad) and returns the rudder rate ``rudder_rate(sim, x, s)`` (N,) in rad/s. The
    integrator then integrates the rudder angle with the method (RK4 or Euler) like every other state; the
    built-in gear's exact solution over a step leaves with the built-in. Its own states (a pump's lag, a
    telemotor) are :class:`State` entries with their ``rates``; at a reset they take their initial values.
    """

    slot: ClassVar[str] = "steering_gear"

    @abstractmethod
    def rudder_rate(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        """(N,) rudder rate, rad/s, at the stage states ``x`` and own states ``s``."""

    def rates(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        """(N, k) time derivatives of the steering gear's own states (no states: an empty array)."""
        return np.zeros((x.shape[0], len(self.states)))

    def forces(self, sim: Any, x: np.ndarray, s: np.ndarray | None = None) -> np.ndarray:
        """A steering gear exerts no force on the hull (the rudder's forces are the rudder's)."""
        return np.zeros((x.shape[0], 3))


def states_of(component: Any) -> tuple[State, ...]:
    """The states a component owns (checked: each a :class:`State` with a unique name)."""
    states = tuple(getattr(component, "states", ()) or ())
    names = [getattr(st, "name", None) for st in states]
    if not all(isinstance(st, State) for st in states) or len(set(names)) != len(names):
        raise ValueError(
            f"component {name_of(component)}: states must be State(name, unit, initial) entries with distinct "
            "names"
        )
    return states


def slot_of(component: Any) -> str:
    """The slot a component fills ("extra" when it declares none)."""
    return getattr(component, "slot", EXTRA)


def name_of(component: Any) -> str:
    """The name of a component's forces (its ``name``, else its class name)."""
    name = getattr(component, "name", None)
    return name if isinstance(name, str) and name else type(component).__name__


@contextlib.contextmanager
def _held_output(out: io.StringIO) -> Iterator[None]:
    """Everything written to sys.stdout and sys.stderr, and to file descriptors 1 and 2 (``os.write``, a
    subprocess), while the block runs goes to ``out`` instead."""
    import tempfile

    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    saved: list[tuple[int, int]] = []
    with tempfile.TemporaryFile() as spool:
        try:
            for fd in (1, 2):
                try:
                    saved.append((fd, os.dup(fd)))
                except OSError:  # not open (a daemon): nothing can be written there anyway
                    continue
                os.dup2(spool.fileno(), fd)
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
                yield
        finally:
            for fd, copy in saved:
                os.dup2(copy, fd)
                os.close(copy)
            spool.seek(0)
            out.write(spool.read().decode("utf-8", "replace"))


def import_model(path: Any, where: str) -> type:
    """The class named by an import path ``"package.module:Class"``; raises ValueError naming ``where``
    (file and key) when the path is malformed, the module cannot be imported or has no such class."""
    if not isinstance(path, str) or not _IMPORT_PATH.match(path):
        raise ValueError(f"{where}: {path!r} is not an import path 'package.module:Class'")
    module_name, attr = path.split(":")
    trusted = module_name == TRUSTED_PACKAGE or module_name.startswith(TRUSTED_PACKAGE + ".")
    if not trusted and not code_allowed():
        raise ValueError(
            f"{where}: {path!r} would run the code of module {module_name!r}; allow code from ship files with "
            f"--allow-code, {ALLOW_CODE_ENV}=1 or vessel_gym.physics.components.allow_code()"
        )
    out = io.StringIO()
    try:
        # what the module prints while it imports is held back, and shown on stderr only if it gave the
        # component: a failure is one line, whatever the module wrote or however it tried to exit
        with _held_output(out):
            obj: Any = importlib.import_module(module_name)
    except ImportError as exc:
        raise ValueError(f"{where}: cannot import module {module_name!r} ({exc})") from None
    except BaseException as exc:  # noqa: BLE001 - SystemExit, KeyboardInterrupt ... at import: one line
        raise ValueError(f"{where}: importing {module_name!r} failed ({type(exc).__name__}: {exc})") from None
    for part in attr.split("."):
        if not hasattr(obj, part):
            raise ValueError(f"{where}: module {module_name!r} has no {attr!r}")
        obj = getattr(obj, part)
    if not isinstance(obj, type) or not callable(getattr(obj, "forces", None)):
        raise ValueError(f"{where}: {path!r} is not a component class (a class with forces(sim, x))")
    if out.getvalue():
        sys.stderr.write(out.getvalue())
    return obj
