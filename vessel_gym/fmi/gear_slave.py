"""A ship's own steering gear as an FMI 2.0 co-simulation slave (pythonfmu): the script a steering-gear FMU
made by :func:`vessel_gym.fmi.export.build_steering_gear_fmu` carries.

The equation is vessel-gym's built-in gear, :func:`vessel_gym.physics.steering.steering_gear_rate` (a
rate-limited first-order gear, order clipped to the maximum angle), with the parameters of the ship file in the
FMU's resources. Inputs the rudder angle and the order, output the rudder rate, a direct function of the inputs
(no state of its own: the rudder angle is the ship's state, integrated by the ship's integrator).
"""

from __future__ import annotations

import os

from pythonfmu import Fmi2Slave

from vessel_gym.fmi.slave_vars import register_real

#: (name, causality, unit, description)
VARIABLES = (
    ("rudder_angle", "input", "rad", "rudder angle, positive to starboard"),
    ("rudder_order", "input", "rad", "rudder order, positive to starboard"),
    ("rudder_rate", "output", "rad/s", "rudder rate the gear drives"),
)


class VesselGymSteeringGear(Fmi2Slave):
    """vessel-gym's steering gear of the ship in resources/ship.toml."""

    author = "vessel-gym"
    description = "vessel-gym steering gear (resources/ship.toml)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.rudder_angle = self.rudder_order = 0.0
        self.P = None
        for name, kind, _, doc in VARIABLES:
            register_real(self, name, kind, doc, getter=self._rate if kind == "output" else None)

    def exit_initialization_mode(self):
        from vessel_gym.physics.shipfile import load_ship
        from vessel_gym.physics.vessel import pack

        self.P = pack(load_ship(os.path.join(self.resources, "ship.toml")))

    def _rate(self):
        if self.P is None:
            return 0.0
        from vessel_gym.physics.steering import steering_gear_rate

        return float(steering_gear_rate(self.P, self.rudder_angle, self.rudder_order))

    def do_step(self, current_time, step_size):
        return True  # no state of its own
