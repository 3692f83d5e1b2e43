"""A ship's own engine and governor as an FMI 2.0 co-simulation slave (pythonfmu): the script an engine FMU
made by :func:`vessel_gym.fmi.export.build_engine_fmu` carries.

The equations are vessel-gym's built-in plant, :func:`vessel_gym.physics.propulsion.engine_drive` (torque
map, PI governor with anti-windup, clutch or direct-reversing gear) with the parameters of the ship file in
the FMU's resources (``ship.toml``). It is the engine of that ship as another simulator would see it: inputs
the shaft speed and the order, output the drive torque at the propeller shaft, its own states (governor
integrator, reversing gear) integrated inside the FMU with the inputs held over each communication step
(RK4, internal steps of at most ``max_step``). The output is a direct function of the inputs and the states
(direct feedthrough): read after setting the inputs, it is the torque at that instant.

``hold_torque`` (parameter, N m at the propeller shaft) starts the engine steady: the governor integrator
holding that torque at the initial shaft speed, as vessel-gym's own steady approach does.
"""

from __future__ import annotations

import math
import os

from pythonfmu import Fmi2Slave
from pythonfmu.enums import Fmi2Status

from vessel_gym.fmi.slave_vars import register_real

#: (name, causality, unit, description)
VARIABLES = (
    ("hold_torque", "parameter", "N.m", "drive torque at the propeller shaft to start steady with (0: idle)"),
    ("max_step", "parameter", "s", "largest internal integration step"),
    ("shaft_speed", "input", "1/s", "propeller shaft speed, rev/s, negative astern"),
    ("rev_order", "input", "1/s", "shaft-speed order, rev/s, negative astern"),
    ("shaft_torque", "output", "N.m", "drive torque at the propeller shaft"),
    ("fuel_index", "output", "1", "governor fuel index"),
)


class VesselGymEngine(Fmi2Slave):
    """vessel-gym's engine + governor of the ship in resources/ship.toml."""

    author = "vessel-gym"
    description = "vessel-gym engine and speed governor (resources/ship.toml)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.hold_torque, self.max_step = 0.0, 0.05
        self.shaft_speed = self.rev_order = 0.0
        self.gov, self.cam, self.P = 0.0, 1.0, None
        for name, kind, _, doc in VARIABLES:
            getter = (lambda n=name: self._drive()[0 if n == "shaft_torque" else 1]) if kind == "output" else None
            register_real(self, name, kind, doc, getter=getter)

    def exit_initialization_mode(self):
        from vessel_gym.physics.params import TRANSMISSION
        from vessel_gym.physics.propulsion import clutch_direction
        from vessel_gym.physics.shipfile import load_ship
        from vessel_gym.physics.steady import fuel_index_for
        from vessel_gym.physics.vessel import pack

        self.P = pack(load_ship(os.path.join(self.resources, "ship.toml")))
        P = self.P
        d = clutch_direction(P, self.rev_order)
        self.cam = (
            d if d != 0.0 else 1.0
        )  # the reversing gear set the way of the order (a direct-reversing plant)
        self.gov = 0.0
        if self.hold_torque > 0.0 and d != 0.0:
            # the steady approach's rule (physics.steady): fuel whose engine torque holds the shaft
            n_e = abs(P[TRANSMISSION.gear_ratio] * self.shaft_speed)
            self.gov = fuel_index_for(P, n_e, self.hold_torque / (P[TRANSMISSION.efficiency] * P[TRANSMISSION.gear_ratio]))

    def _drive(self, gov=None, cam=None):
        """(drive torque N m, fuel index, d gov/dt, d cam/dt) at the inputs and the states (or ``gov``, ``cam``)."""
        if self.P is None:
            return 0.0, 0.0, 0.0, 0.0
        from vessel_gym.physics.propulsion import engine_drive

        g = self.gov if gov is None else gov
        c = self.cam if cam is None else cam
        Q, dcam, dgov, fuel, _n_e, _Q_e, _phase = engine_drive(self.P, self.shaft_speed, c, g, self.rev_order)
        return Q, fuel, dgov, dcam

    def do_step(self, current_time, step_size):
        if not (step_size > 0.0 and self.max_step > 0.0):
            self.log(
                f"step {step_size:g} s, max_step {self.max_step:g} s: both must be > 0", Fmi2Status.error
            )
            return False
        k = max(1, math.ceil(step_size / self.max_step - 1e-9))
        h = step_size / k
        g, c = self.gov, self.cam
        for _ in range(k):  # RK4 with the inputs held (co-simulation: zero-order hold)
            _, _, g1, c1 = self._drive(g, c)
            _, _, g2, c2 = self._drive(g + 0.5 * h * g1, c + 0.5 * h * c1)
            _, _, g3, c3 = self._drive(g + 0.5 * h * g2, c + 0.5 * h * c2)
            _, _, g4, c4 = self._drive(g + h * g3, c + h * c3)
            g += h / 6.0 * (g1 + 2.0 * g2 + 2.0 * g3 + g4)
            c += h / 6.0 * (c1 + 2.0 * c2 + 2.0 * c3 + c4)
        if not (math.isfinite(g) and math.isfinite(c)):
            self.log(f"engine states diverged before t = {current_time + step_size:g} s", Fmi2Status.error)
            return False
        self.gov, self.cam = g, c
        return True
