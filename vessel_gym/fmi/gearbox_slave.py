"""A ship's geared plant with friction clutches as an FMI 2.0 co-simulation slave (pythonfmu): the script a
gearbox FMU made by :func:`vessel_gym.fmi.export.build_gearbox_fmu` carries.

The equations are vessel-gym's :func:`vessel_gym.physics.components.gearbox.gearbox_drive` (non-reversible
diesel, PI governor, reversing gear with a Karnopp stick-slip clutch per direction) with the parameters of the
ship file in the FMU's resources (``ship.toml``, whose engine slot is the ``ReversingGearbox`` component). Inputs
the shaft speed, the order and the propeller's load torque Q_P + Q_f (the clutch's locked torque is the torque
that keeps engine and shaft together, which depends on it); output the drive torque at the propeller shaft.
Its states (engine speed, governor integrator, clutch pressure) are integrated inside the FMU with RK4, the
inputs held over each communication step (internal steps of at most ``max_step``).

``hold_torque`` (parameter, N m at the propeller shaft) starts the plant steady: clutch applied and locked, the
engine at i |n|, the governor holding that torque, as ``ReversingGearbox.steady_states`` does.
"""

from __future__ import annotations

import math
import os

import numpy as np
from pythonfmu import Fmi2Slave
from pythonfmu.enums import Fmi2Status

from vessel_gym.fmi.slave_vars import register_real

#: (name, causality, unit, description)
VARIABLES = (
    ("hold_torque", "parameter", "N.m", "drive torque at the propeller shaft to start steady with (0: idle)"),
    ("max_step", "parameter", "s", "largest internal integration step"),
    ("shaft_speed", "input", "1/s", "propeller shaft speed, rev/s, negative astern"),
    ("rev_order", "input", "1/s", "shaft-speed order, rev/s, negative astern"),
    ("load_torque", "input", "N.m", "propeller and shafting torque on the shaft, Q_P + Q_f"),
    ("shaft_torque", "output", "N.m", "drive torque at the propeller shaft"),
    ("engine_speed", "output", "1/s", "engine speed, rev/s (engine side)"),
    ("clutch", "output", "1", "applied fraction of the ahead (+) or astern (-) clutch's pressure"),
)


class VesselGymGearbox(Fmi2Slave):
    """vessel-gym's reversing-gear plant (engine, governor, clutches) of the ship in resources/ship.toml."""

    author = "vessel-gym"
    description = "vessel-gym geared plant with friction clutches (resources/ship.toml)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.hold_torque, self.max_step = 0.0, 0.05
        self.shaft_speed = self.rev_order = self.load_torque = 0.0
        self.z = np.zeros(3)  # engine speed rev/s, governor integrator, clutch
        self.P = self.C = None
        for name, kind, _, doc in VARIABLES:
            getter = (lambda n=name: self._output(n)) if kind == "output" else None
            register_real(self, name, kind, doc, getter=getter)

    def exit_initialization_mode(self):
        from vessel_gym.physics.components.compose import remove_engine
        from vessel_gym.physics.components.gearbox import C_DT, C_IDLE_REV, ReversingGearbox
        from vessel_gym.physics.params import TRANSMISSION
        from vessel_gym.physics.propulsion import clutch_direction
        from vessel_gym.physics.shipfile import load_ship
        from vessel_gym.physics.steady import fuel_index_for
        from vessel_gym.physics.vessel import pack

        ship = load_ship(os.path.join(self.resources, "ship.toml"))
        entry = next((e for e in ship.components if e.slot == "engine" and e.cls is ReversingGearbox), None)
        plant = ReversingGearbox(ship, entry.params if entry is not None else None)
        self.P = pack(ship)
        remove_engine(self.P, ship)  # the shaft's inertia without the engine's (it is behind the clutch)
        self.C = plant.constants.copy()
        self.C[C_DT] = self.max_step
        P = self.P
        d = clutch_direction(P, self.rev_order)
        i_g, eta = P[TRANSMISSION.gear_ratio], P[TRANSMISSION.efficiency]
        if d == 0.0 or self.hold_torque == 0.0:
            n_E, Q_E, d = self.C[C_IDLE_REV], 0.0, 0.0  # declutched, idling unloaded
        else:
            n_E, Q_E = d * i_g * self.shaft_speed, d * self.hold_torque / (eta * i_g)
        self.z = np.array([n_E, fuel_index_for(P, n_E, Q_E), d])

    def _drive(self, z):
        from vessel_gym.physics.components.gearbox import gearbox_drive

        return gearbox_drive(
            self.P, self.C, self.shaft_speed, z[0], z[1], z[2], self.rev_order, self.load_torque
        )

    def _output(self, name):
        if self.P is None:
            return 0.0
        if name == "shaft_torque":
            return float(self._drive(self.z)[0])
        return float(self.z[0] if name == "engine_speed" else self.z[2])

    def do_step(self, current_time, step_size):
        from vessel_gym.physics.components.gearbox import C_DT

        if not (step_size > 0.0 and self.max_step > 0.0):
            self.log(
                f"step {step_size:g} s, max_step {self.max_step:g} s: both must be > 0", Fmi2Status.error
            )
            return False
        k = max(1, math.ceil(step_size / self.max_step - 1e-9))
        h = step_size / k
        # the plant's numerical time constants are at least the integration step (as in the ship's integrator)
        self.C[C_DT] = h
        z = self.z.copy()

        def rate(zz):
            out = self._drive(zz)
            return np.array([out[1], out[2], out[3]])

        for _ in range(k):  # RK4 with the inputs held (co-simulation: zero-order hold)
            k1 = rate(z)
            k2 = rate(z + 0.5 * h * k1)
            k3 = rate(z + 0.5 * h * k2)
            k4 = rate(z + h * k3)
            z = z + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        if not np.all(np.isfinite(z)):
            self.log(f"plant states diverged before t = {current_time + step_size:g} s", Fmi2Status.error)
            return False
        self.z = z
        return True
