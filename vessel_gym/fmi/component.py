"""FMUs as components of a ship (docs/fmi.md): an FMI 2.0 co-simulation FMU in the engine slot (engine with
its governor) or the steering-gear slot, or as a force component (slot ``extra``: :class:`FmuForce`), chosen
from a ship file's ``[[components]]`` and stepped with fmpy.

A ship file names it like any component (docs/components.md), with the FMU, the map from the slot's
quantities to the FMU's variables (with their units), start values and the communication step::

    [[components]]
    slot = "engine"
    model = "vessel_gym.fmi.component:FmuEngine"
    replace = true
    [components.params]
    path = "diesel.fmu"                 # relative to the ship file
    step_s = 0.1                        # communication step, a whole multiple of the simulation's step
    shaft_inertia_kgm2 = 2.5e5          # the engine's rotating inertia referred to the propeller shaft
    inputs = { shaft_speed = { name = "n", unit = "rpm" }, rev_order = "n_set" }
    outputs = { shaft_torque = { name = "Q", unit = "kN.m" } }
    hold_torque = "Q_start"             # optional: a parameter that starts the FMU steady at this torque
    # optional input load_torque (N m, Q_P + Q_f at t_k): for a plant with a clutch (docs/fmi.md)
    start = { J = 1200.0 }              # optional: start values of parameters and inputs

**Co-simulation.** At each communication point t_k the slot's quantities at t_k are the FMU's inputs, its
outputs are read (an output with direct feedthrough reflects them at once) and held over [t_k, t_k + H]
(zero-order hold) while the ship integrates, and the FMU is stepped to t_k + H. The drive torque therefore
lags the shaft by up to one step H: the error is first order in H (docs/fmi.md, "Tolerances").

**Where the component is in time.** A component is called at every stage of the integrator; it owns one
state, ``clock`` (s since the vessel's reset, rate 1: exact under RK4 and Euler), and communicates at the
first stage of a step (its stage state is the simulation's own state array) once the clock reaches the next
communication point. A reset of a vessel sets its clock to 0: its FMU instance is reset and initialised
again (steady, with ``hold_torque``, at the drive torque the reset's steady approach solved).

**Cost.** One FMU instance per vessel of the simulation (a vector env's batch: N instances; a ship file's
component in a simulation of several ships: one per vessel of every ship), each stepped from Python once
per communication step: about 4 FMI calls per vessel and step, some tens of microseconds for a compiled FMU,
more for one that runs Python (pythonfmu). Loading a ship file with an FMU component runs the FMU's native
code: it needs the consent of ``--allow-code`` like any code a ship file names.
"""

from __future__ import annotations

import math
import shutil
import weakref
from pathlib import Path
from typing import Any

import numpy as np

from vessel_gym.fmi import require
from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import Component, Engine, State, SteeringGear

#: unit names accepted for a slot's quantity and the factor from that unit to the slot's (SI) unit
UNITS = {
    "rev/s": {"rev/s": 1.0, "1/s": 1.0, "Hz": 1.0, "rpm": 1.0 / 60.0, "rad/s": 1.0 / (2.0 * math.pi)},
    "N.m": {"N.m": 1.0, "N m": 1.0, "Nm": 1.0, "kN.m": 1e3, "kNm": 1e3, "MN.m": 1e6},
    "rad": {"rad": 1.0, "deg": math.pi / 180.0},
    "rad/s": {"rad/s": 1.0, "deg/s": math.pi / 180.0},
    "m/s": {"m/s": 1.0, "kn": 1852.0 / 3600.0},
    "m": {"m": 1.0},
    "s": {"s": 1.0},
    "N": {"N": 1.0, "kN": 1e3, "MN": 1e6},
}
#: the time a communication point may be missed by, as a fraction of the step (round-off of the clock)
CLOCK_TOLERANCE = 1e-6


class FmuError(ValueError):
    """An FMU that cannot serve its slot: one line naming the file and, where it is one, the variable."""


class _Port:
    """One slot quantity mapped to an FMU variable: value reference and factor FMU unit -> slot unit."""

    def __init__(self, vr: int, factor: float, name: str) -> None:
        self.vr, self.factor, self.name = vr, factor, name


def _free_all(instances: list) -> None:
    """Terminate and free FMU instances (fmpy's freeInstance also unloads the library: pythonfmu 0.7's FMUs
    abort the process at exit when an instance is freed without it)."""
    for fmu in instances:
        if fmu is None:
            continue
        try:
            fmu.terminate()
        except Exception:  # noqa: BLE001, S110 - an instance that failed: free it all the same
            pass
        try:
            fmu.freeInstance()
        except Exception:  # noqa: BLE001, S110 - nothing more to do at the end of its life
            pass
    instances.clear()


class FmuSlot:
    """What the engine and the steering gear share: the FMU, its ports, one instance per vessel, the
    communication. Subclasses declare ``INPUTS`` and ``OUTPUTS`` (slot quantity -> slot unit)."""

    INPUTS: dict[str, str] = {}
    OUTPUTS: dict[str, str] = {}
    HOLD: str | None = None  # the slot quantity a reset holds steady (unit in OUTPUTS), or None
    OPTIONAL_INPUTS = False  # True: the map names any subset of INPUTS (a force FMU's state inputs)
    OPTIONAL: frozenset[str] = frozenset()  # inputs the map may leave out (the others it must name)
    states = (
        State("clock", "s", 0.0, "time since the vessel's reset (tells the component where a stage is)"),
    )

    def _setup(self, ship: Any, params: Any) -> None:
        require("fmpy")
        from fmpy import extract, platform, read_model_description, supported_platforms

        if not isinstance(params, dict):
            raise FmuError("params: expected a table with path, step_s, inputs, outputs")
        allowed = {"path", "step_s", "inputs", "outputs", "start", "hold_torque", "shaft_inertia_kgm2"}
        unknown = sorted(set(params) - allowed)
        if unknown:
            raise FmuError(f"params: unknown key {unknown[0]!r} (allowed: {', '.join(sorted(allowed))})")
        if "path" not in params or not isinstance(params["path"], str):
            raise FmuError("params path: expected the FMU's file name (relative to the ship file)")
        base = Path(ship.path).parent if getattr(ship, "path", None) else Path.cwd()
        self.path = (base / params["path"]).resolve()
        where = str(self.path)
        if not self.path.is_file():
            raise FmuError(f"{where}: no such FMU")
        step = params.get("step_s")
        if isinstance(step, bool) or not isinstance(step, (int, float)) or not (0.0 < step <= 60.0):
            raise FmuError(
                f"{where}: params step_s: expected a communication step in (0, 60] s, got {step!r}"
            )
        self.step_s = float(step)
        try:
            md = read_model_description(str(self.path), validate=True)
        except Exception as exc:  # noqa: BLE001 - a broken archive or XML: one line
            raise FmuError(f"{where}: not a readable FMU ({type(exc).__name__}: {exc})") from None
        if md.fmiVersion != "2.0":
            raise FmuError(f"{where}: FMI {md.fmiVersion}; only FMI 2.0 co-simulation FMUs are supported")
        if md.coSimulation is None:
            raise FmuError(
                f"{where}: a model-exchange-only FMU; this slot needs an FMI 2.0 co-simulation FMU"
            )
        platforms = supported_platforms(str(self.path))
        if platform not in platforms:
            have = ", ".join(p for p in platforms if p != "c-code") or "none"
            raise FmuError(f"{where}: no binary for this platform {platform} (the FMU has: {have})")
        self.md = md
        self.variables = {v.name: v for v in md.modelVariables}
        inputs = params.get("inputs")
        quantities = self.INPUTS
        if isinstance(inputs, dict):
            quantities = {q: u for q, u in self.INPUTS.items() if q in inputs or q not in self.OPTIONAL}
        self.inputs = self._ports(
            inputs, quantities, "inputs", ("input",), optional=self.OPTIONAL_INPUTS, known=self.INPUTS
        )
        self.outputs = self._ports(params.get("outputs"), self.OUTPUTS, "outputs", ("output",))
        self.hold = None
        if params.get("hold_torque") is not None:
            if self.HOLD is None:
                raise FmuError(f"{where}: params hold_torque: only an engine starts steady at a torque")
            spec = {self.HOLD: params["hold_torque"]}
            self.hold = self._ports(spec, {self.HOLD: self.OUTPUTS[self.HOLD]}, "hold_torque", ("parameter",))
        self.start = []
        start = params.get("start", {})
        if not isinstance(start, dict):
            raise FmuError(f"{where}: params start: expected a table variable = value")
        for name, value in start.items():
            var = self._variable(name, "start")
            if var.causality not in ("parameter", "input") or var.variability == "constant":
                raise FmuError(
                    f"{where}: start {name!r}: causality {var.causality}, not a parameter or input"
                )
            if var.type != "Real" or isinstance(value, bool) or not isinstance(value, (int, float)):
                raise FmuError(f"{where}: start {name!r}: expected a number for a Real variable")
            self.start.append((var.valueReference, float(value)))
        self._last_message = ""
        self._callbacks = self._make_callbacks()
        self._unzipped = extract(str(self.path))
        weakref.finalize(self, shutil.rmtree, self._unzipped, True)
        self._instances: list[Any] = []
        # freed with the component (or at exit): terminated, freed and the library unloaded, instance by instance
        weakref.finalize(self, _free_all, self._instances)
        self._held = np.zeros((0, len(self.outputs)))
        self._t = np.zeros(0)  # each instance's time: the end of its current communication step
        self._hold_value = np.zeros(0)
        self._hold_init = np.zeros(0)
        self._dt_checked: float | None = None
        self._substeps = 1

    # --- the map ---------------------------------------------------------------------------------------------
    def _variable(self, name: Any, key: str) -> Any:
        if not isinstance(name, str) or name not in self.variables:
            raise FmuError(f"{self.path}: {key}: no variable {name!r} in the FMU")
        return self.variables[name]

    def _ports(
        self,
        spec: Any,
        quantities: dict[str, str],
        key: str,
        causalities: tuple,
        optional: bool = False,
        known: dict[str, str] | None = None,
    ) -> dict[str, _Port]:
        where = str(self.path)
        known = quantities if known is None else known
        if not isinstance(spec, dict):
            raise FmuError(f"{where}: params {key}: expected a table {', '.join(quantities)} = variable")
        extra = sorted(set(spec) - set(known))
        if extra:
            raise FmuError(f"{where}: params {key}: {extra[0]!r} is not one of {', '.join(known)}")
        missing = sorted(set(quantities) - set(spec))
        if optional:
            quantities = {q: u for q, u in quantities.items() if q in spec}
            missing = [] if spec else ["(any one)"]
        if missing:
            raise FmuError(f"{where}: params {key}: missing {missing[0]!r} (the slot needs it)")
        ports = {}
        for q, slot_unit in quantities.items():
            entry = spec[q]
            name, unit = (entry.get("name"), entry.get("unit")) if isinstance(entry, dict) else (entry, None)
            var = self._variable(name, f"{key} {q}")
            if var.causality not in causalities:
                raise FmuError(
                    f"{where}: variable {name!r} ({key} {q}) has causality {var.causality}, not {causalities[0]}"
                )
            if var.type != "Real":
                raise FmuError(f"{where}: variable {name!r} ({key} {q}) is {var.type}, not Real")
            declared = var.unit or (var.declaredType.unit if getattr(var, "declaredType", None) else None)
            unit = unit or declared or slot_unit
            factors = UNITS[slot_unit]
            if unit not in factors:
                raise FmuError(
                    f"{where}: variable {name!r} ({key} {q}): unit {unit!r} is not one of {', '.join(factors)}"
                )
            if declared and declared in factors and factors[declared] != factors[unit]:
                raise FmuError(
                    f"{where}: variable {name!r} ({key} {q}) is in {declared!r}, the map says {unit!r}"
                )
            ports[q] = _Port(var.valueReference, factors[unit], name)
        return ports

    # --- the instances ---------------------------------------------------------------------------------------
    def _instance(self, k: int) -> Any:
        from fmpy.fmi2 import FMU2Slave

        fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self._unzipped,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=f"vessel{k}",
        )
        self._fmi(fmu.instantiate, "instantiate", callbacks=self._callbacks, loggingOn=True)
        return fmu

    def _make_callbacks(self) -> Any:
        """FMI callbacks whose logger keeps the FMU's last warning or error (for the one-line message) and
        prints nothing."""
        from ctypes import byref

        from fmpy.fmi2 import (
            calloc,
            fmi2CallbackAllocateMemoryTYPE,
            fmi2CallbackFreeMemoryTYPE,
            fmi2CallbackFunctions,
            fmi2CallbackLoggerTYPE,
            free,
        )

        def logger(component, instance, status, category, message):
            if status >= 1:  # warning, discard, error, fatal
                self._last_message = message.decode("utf-8", "replace").strip().replace("\n", " ")[:300]

        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(logger)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        try:
            from fmpy.logging import addLoggerProxy

            addLoggerProxy(byref(cb))  # formats the FMU's variadic message
        except Exception:  # noqa: BLE001, S110 - without it the messages arrive unformatted
            pass
        return cb

    def _fmi(self, call: Any, what: str, *args: Any, **kw: Any) -> Any:
        """An FMI call; a failure (an exception or a status above warning) is one FmuError naming the file."""
        try:
            status = call(*args, **kw)
        except Exception as exc:  # noqa: BLE001 - fmpy's FMICallException, a missing binary: one line
            raise FmuError(f"{self.path}: {what} failed ({exc}){self._said()}") from None
        if isinstance(status, int) and status > 1:
            label = {2: "discard", 3: "error", 4: "fatal"}.get(status, str(status))
            raise FmuError(f"{self.path}: {what} failed (status {label}){self._said()}")
        return status

    def _said(self) -> str:
        """The FMU's last logged warning or error, as the end of a message ('' if none)."""
        msg, self._last_message = self._last_message, ""
        return f"; the FMU says: {msg}" if msg else ""

    def _grow(self, n: int) -> None:
        while len(self._instances) < n:
            self._instances.append(None)
        if len(self._t) < n:
            self._t = np.resize(self._t, n)
            self._held = np.zeros((n, len(self.outputs)))
            self._hold_value = np.zeros(n)
            self._hold_init = np.full(n, np.nan)

    def _set_inputs(self, fmu: Any, values: dict[str, float], what: str) -> None:
        vrs = [p.vr for p in self.inputs.values()]
        vals = [values[q] / p.factor for q, p in self.inputs.items()]
        self._fmi(
            fmu.setReal, f"{what}: setting {', '.join(p.name for p in self.inputs.values())}", vrs, vals
        )

    def _initialise(self, k: int, values: dict[str, float]) -> None:
        fmu = self._instances[k]
        if fmu is None:
            fmu = self._instances[k] = self._instance(k)
        else:
            self._fmi(fmu.reset, "reset")
        for vr, value in self.start:
            self._fmi(fmu.setReal, "setting start values", [vr], [value])
        if self.hold is not None:
            port = self.hold[self.HOLD]
            self._fmi(fmu.setReal, f"setting {port.name}", [port.vr], [self._hold_value[k] / port.factor])
        self._set_inputs(fmu, values, "initialisation")
        self._fmi(fmu.setupExperiment, "setupExperiment", startTime=0.0)
        self._fmi(fmu.enterInitializationMode, "enterInitializationMode")
        self._fmi(fmu.exitInitializationMode, "exitInitializationMode")
        self._t[k] = 0.0
        self._hold_init[k] = self._hold_value[k]

    def _communicate(self, sim: Any, x: np.ndarray, clock: np.ndarray) -> None:
        """At the first stage of a step: initialise reset vessels' instances, and step every instance whose
        communication point the clock has reached, with the slot's quantities of ``x`` as its inputs."""
        n = x.shape[0]
        self._grow(n)
        if self._dt_checked != sim.dt:
            # the FMU steps at step_s; the slot's quantities are exchanged every max(step_s, dt): one of the two
            # steps must be a whole multiple of the other
            m = max(self.step_s, sim.dt) / min(self.step_s, sim.dt)
            if abs(m - round(m)) > 1e-9 * m:
                raise FmuError(
                    f"{self.path}: params step_s = {self.step_s:g} s and the simulation's step {sim.dt:g} s: one must "
                    "be a whole multiple of the other"
                )
            self._substeps = round(sim.dt / self.step_s) if sim.dt > self.step_s else 1
            self._dt_checked = sim.dt
        tol = CLOCK_TOLERANCE * self.step_s
        values = self._slot_values(sim, x, clock)
        out_vrs = [p.vr for p in self.outputs.values()]
        factors = np.array([p.factor for p in self.outputs.values()])
        for k in range(n):
            vk = {q: float(v[k]) for q, v in values.items()}
            fresh = clock[k] == 0.0 and (self._t[k] > 0.0 or self._hold_init[k] != self._hold_value[k])
            if self._instances[k] is None or fresh:
                self._initialise(k, vk)
            if clock[k] + tol < self._t[k]:
                continue  # inside the communication step: the held outputs stand
            fmu = self._instances[k]
            t = self._t[k]
            self._set_inputs(fmu, vk, f"t = {t:g} s")
            got = self._fmi(fmu.getReal, f"t = {t:g} s: reading outputs", out_vrs)
            self._held[k] = np.asarray(got, dtype=float) * factors
            for j in range(self._substeps):  # (several FMU steps per exchange when step_s < dt)
                tj = t + j * self.step_s
                self._fmi(
                    fmu.doStep,
                    f"doStep at t = {tj:g} s",
                    currentCommunicationPoint=tj,
                    communicationStepSize=self.step_s,
                )
            self._t[k] = t + self._substeps * self.step_s

    def _held_output(self, sim: Any, x: np.ndarray, s: np.ndarray, quantity: str) -> np.ndarray:
        if x is sim.state:  # the first stage of a step (integrate.run_with_components): communicate
            self._communicate(sim, x, s[:, 0])
        elif len(self._instances) < x.shape[0]:  # evaluated before any step (a named-force read-out)
            return np.zeros(x.shape[0])
        return self._held[: x.shape[0], list(self.outputs).index(quantity)]

    def rates(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        return np.ones((x.shape[0], 1))  # the clock

    def _slot_values(self, sim: Any, x: np.ndarray, clock: np.ndarray) -> dict[str, np.ndarray]:
        raise NotImplementedError


class FmuEngine(FmuSlot, Engine):
    """An FMU in the engine slot: the engine with its governor. Inputs ``shaft_speed`` (rev/s, the shaft's
    state) and ``rev_order`` (rev/s, the telegraph's order); output ``shaft_torque`` (N m, drive torque at the
    propeller shaft). Ship-file key ``shaft_inertia_kgm2``: the engine's inertia referred to the shaft."""

    INPUTS = {"shaft_speed": "rev/s", "rev_order": "rev/s", "load_torque": "N.m"}
    OPTIONAL = frozenset({"load_torque"})
    OUTPUTS = {"shaft_torque": "N.m"}
    HOLD = "shaft_torque"
    states = FmuSlot.states

    def __init__(self, ship: Any, params: Any) -> None:
        Engine.__init__(self, ship, params)
        self._setup(ship, params)
        inertia = params.get("shaft_inertia_kgm2")
        if isinstance(inertia, bool) or not isinstance(inertia, (int, float)) or not (0.0 <= inertia < 1e12):
            raise FmuError(
                f"{self.path}: params shaft_inertia_kgm2: expected the engine's inertia referred to the propeller "
                f"shaft, kg m^2 >= 0, got {inertia!r}"
            )
        self.inertia = float(inertia)

    def shaft_inertia_kgm2(self) -> float:
        return self.inertia

    def _slot_values(self, sim: Any, x: np.ndarray, clock: np.ndarray) -> dict[str, np.ndarray]:
        values = {"shaft_speed": x[:, lo.X_REV], "rev_order": sim.rev_order}
        if "load_torque" in self.inputs:
            values["load_torque"] = load_torque(sim, x)
        return values

    def shaft_torque(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        return self._held_output(sim, x, s, "shaft_torque")

    def steady_states(self, sim: Any, x: np.ndarray, Q_hold: np.ndarray) -> np.ndarray:
        self._grow(x.shape[0])
        # the vessels being reset are those with a drive torque to hold (the others get 0 here): their
        # instances start now, from the approach's shaft speed and order (an order given after the reset, a
        # crash stop's, reaches the FMU at the first communication point, as it reaches a built-in engine)
        Q = np.asarray(Q_hold, dtype=float)
        values = self._slot_values(sim, x, np.zeros(x.shape[0]))
        for k in np.flatnonzero(Q != 0.0).tolist():
            self._hold_value[k] = Q[k]
            self._initialise(k, {q: float(v[k]) for q, v in values.items()})
        return np.zeros((x.shape[0], 1))


def load_torque(sim: Any, x: np.ndarray) -> np.ndarray:
    """The propeller's and the shafting's torque on the shaft, Q_P + Q_f (N m), of every vessel at ``x``: what
    ``ReversingGearbox.evaluate`` gives its clutch (``gearbox.gearbox_batch``), from the vessel's own force
    evaluation (the one home of the wake and the four-quadrant propeller)."""
    from vessel_gym.physics.propulsion import shaft_friction_torque
    from vessel_gym.physics.vessel import force_terms

    out = np.empty(x.shape[0])
    for k in range(x.shape[0]):
        P = sim.Ps[sim.ship_index[k]]
        xk = np.ascontiguousarray(x[k], dtype=float)
        f = force_terms(P, xk, sim.env[k], sim.env[k, lo.E_T_OVER_H], True, True)
        out[k] = f.Q_prop + shaft_friction_torque(P, xk[lo.X_REV])
    return out


class FmuSteeringGear(FmuSlot, SteeringGear):
    """An FMU in the steering-gear slot. Inputs ``rudder_angle`` and ``rudder_order`` (rad); output
    ``rudder_rate`` (rad/s), integrated by the ship's integrator (held over each communication step)."""

    INPUTS = {"rudder_angle": "rad", "rudder_order": "rad"}
    OUTPUTS = {"rudder_rate": "rad/s"}
    states = FmuSlot.states

    def __init__(self, ship: Any, params: Any) -> None:
        SteeringGear.__init__(self)
        self.ship, self.params = ship, params
        if isinstance(params, dict) and "shaft_inertia_kgm2" in params:
            raise FmuError("params shaft_inertia_kgm2: a steering gear has no shaft inertia")
        self._setup(ship, params)

    def _slot_values(self, sim: Any, x: np.ndarray, clock: np.ndarray) -> dict[str, np.ndarray]:
        return {"rudder_angle": x[:, lo.X_DELTA], "rudder_order": sim.rudder_order}

    def rudder_rate(self, sim: Any, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        return self._held_output(sim, x, s, "rudder_rate")


#: the state a force FMU may take as inputs: quantity -> (slot unit, column of the state, or None for the clock)
FORCE_INPUTS = {
    "u": ("m/s", lo.X_U),
    "v": ("m/s", lo.X_V),
    "r": ("rad/s", lo.X_R),
    "x": ("m", lo.X_N),
    "y": ("m", lo.X_E),
    "heading": ("rad", lo.X_PSI),
    "rudder_angle": ("rad", lo.X_DELTA),
    "shaft_speed": ("rev/s", lo.X_REV),
    "t": ("s", None),
}


class FmuForce(FmuSlot, Component):
    """An FMU as a force component (slot ``extra``, any number of them): inputs any of :data:`FORCE_INPUTS`
    (the vessel's state through the water, position, heading, rudder angle, shaft speed, and ``t``, s since
    the vessel's reset); outputs ``X``, ``Y`` (N) and ``N`` (N m), body axes at midship, held over each
    communication step like every FMU slot's outputs. The steady approach of a reset does not see the FMU's
    force (it is 0 until the first communication, at t = 0): a force that is not zero in the straight
    approach starts the ship out of its balance."""

    slot = "extra"
    INPUTS = {q: unit for q, (unit, _) in FORCE_INPUTS.items()}
    OUTPUTS = {"X": "N", "Y": "N", "N": "N.m"}
    OPTIONAL_INPUTS = True
    states = FmuSlot.states

    def __init__(self, ship: Any, params: Any) -> None:
        Component.__init__(self, ship, params)
        if isinstance(params, dict) and "shaft_inertia_kgm2" in params:
            raise FmuError("params shaft_inertia_kgm2: a force component has no shaft inertia")
        self._setup(ship, params)

    def _slot_values(self, sim: Any, x: np.ndarray, clock: np.ndarray) -> dict[str, np.ndarray]:
        return {q: (clock if FORCE_INPUTS[q][1] is None else x[:, FORCE_INPUTS[q][1]]) for q in self.inputs}

    def forces(self, sim: Any, x: np.ndarray, s: np.ndarray | None = None) -> np.ndarray:
        if s is not None and x is sim.state:  # the first stage of a step: communicate
            self._communicate(sim, x, s[:, 0])
        elif len(self._instances) < x.shape[0]:  # before any step (the steady approach, a read-out)
            return np.zeros((x.shape[0], 3))
        return self._held[: x.shape[0]].copy()


__all__ = ["FORCE_INPUTS", "FmuEngine", "FmuError", "FmuForce", "FmuSteeringGear", "UNITS", "load_torque"]
