"""The whole ship as an FMI 2.0 co-simulation slave (pythonfmu): the script an exported FMU carries.

:func:`vessel_gym.fmi.export.build_ship_fmu` copies this file into the FMU's resources with the ship file
(``ship.toml``) and the export's settings (``settings.json``: internal step, approach, the approach's
shaft-speed order). The host runs it in its own Python, where vessel-gym must be installed: the FMU carries
the ship's data, not the physics. Each ``doStep`` of H seconds sets the helm and the environment from the
inputs and advances the native :class:`~vessel_gym.physics.simulation.Simulation` H / dt steps of its own
step dt (H must be a whole multiple of dt): at H = dt the FMU's trajectory is the native simulation's.

Angles are radians and speeds SI at the FMU's interface (Modelica's and OSP's convention); the native
environment takes degrees, converted here.
"""

from __future__ import annotations

import json
import math
import os

from pythonfmu import Fmi2Slave
from pythonfmu.enums import Fmi2Status

from vessel_gym.fmi.slave_vars import register_real

#: (name, unit, description) of the inputs, held over a communication step
INPUTS = (
    ("rudder_order", "rad", "rudder order, positive to starboard"),
    (
        "rev_order",
        "1/s",
        "propeller shaft-speed order, rev/s, negative astern; until set, the steady approach's (its start value: "
        "the order of the approach in calm water)",
    ),
    ("wind_speed", "m/s", "true wind speed at 10 m"),
    ("wind_from", "rad", "true wind direction, from, clockwise from north"),
    ("current_speed", "m/s", "current speed"),
    ("current_to", "rad", "current direction, towards, clockwise from north"),
)
#: (name, unit, description) of the outputs, at the end of each communication step
OUTPUTS = (
    ("x", "m", "position north of the start"),
    ("y", "m", "position east of the start"),
    ("heading", "rad", "heading, clockwise from north"),
    ("u", "m/s", "surge speed through the water"),
    ("v", "m/s", "sway speed through the water, positive to starboard"),
    ("r", "rad/s", "rate of turn, positive to starboard"),
    ("rudder_angle", "rad", "rudder angle, positive to starboard"),
    ("shaft_speed", "1/s", "propeller shaft speed, rev/s"),
)
#: (name, unit, description) of the parameters, fixed at initialisation
PARAMETERS = (
    ("dt", "s", "internal physics step (a communication step must be a whole multiple of it)"),
    ("x0", "m", "start position north"),
    ("y0", "m", "start position east"),
    ("heading0", "rad", "start heading (steady straight approach at the ship's IMO test speed)"),
)


class VesselGymShip(Fmi2Slave):
    """A vessel-gym ship (resources/ship.toml) in a steady straight approach at its IMO test speed."""

    author = "vessel-gym"
    description = "vessel-gym ship, 3-DOF manoeuvring model (resources/ship.toml)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        with open(os.path.join(self.resources, "settings.json"), encoding="utf-8") as fh:
            settings = json.load(fh)
        self.sim = None
        self.dt, self.x0, self.y0, self.heading0 = settings["dt"], 0.0, 0.0, 0.0
        self.rudder_order, self.rev_order = 0.0, settings["rev_order"]
        self.wind_speed = self.wind_from = self.current_speed = self.current_to = 0.0
        for name, _, _ in OUTPUTS:
            setattr(self, name, 0.0)
        self._allow_code = bool(settings.get("allow_code", False))
        self._env = None
        for name, _, doc in PARAMETERS:
            register_real(self, name, "parameter", doc)
        self._rev_order_given = False  # until the importer sets it, the order of the approach solved at init
        for name, _, doc in INPUTS:
            register_real(self, name, "input", doc, setter=self._set_rev_order if name == "rev_order" else None)
        for name, _, doc in OUTPUTS:
            register_real(self, name, "output", doc)

    def _set_rev_order(self, value):
        self.rev_order, self._rev_order_given = value, True

    def exit_initialization_mode(self):
        from vessel_gym.physics import components
        from vessel_gym.physics.simulation import Simulation

        if self._allow_code:  # the ship file names code of the exporter's, allowed when the FMU was made
            components.allow_code()
        self.sim = Simulation(os.path.join(self.resources, "ship.toml"), dt=float(self.dt))
        self._set_environment()
        self.sim.reset(heading_deg=math.degrees(self.heading0), x_m=self.x0, y_m=self.y0)
        if not self._rev_order_given:  # the approach in the initial weather, as the native simulation's
            self.rev_order = float(self.sim.rev_order[0])
        self._read_outputs()

    def _set_environment(self):
        from vessel_gym.physics.environment import Environment

        env = (self.wind_speed, self.wind_from, self.current_speed, self.current_to)
        if env == self._env:
            return
        self.sim.set_environment(
            Environment(
                wind_speed_m_s=float(self.wind_speed),
                wind_from_deg=math.degrees(math.remainder(self.wind_from, 2.0 * math.pi)),
                current_speed_m_s=float(self.current_speed),
                current_to_deg=math.degrees(math.remainder(self.current_to, 2.0 * math.pi)),
            )
        )
        self._env = env

    def _read_outputs(self):
        s = self.sim
        self.x, self.y, self.heading = float(s.north[0]), float(s.east[0]), float(s.heading[0])
        self.u, self.v, self.r = float(s.u[0]), float(s.v[0]), float(s.r[0])
        self.rudder_angle, self.shaft_speed = float(s.rudder[0]), float(s.rev[0])

    def do_step(self, current_time, step_size):
        k = round(step_size / self.dt)
        if k < 1 or abs(k * self.dt - step_size) > 1e-9 * max(1.0, step_size):
            self.log(
                f"communication step {step_size:g} s is not a whole multiple of the internal step dt = {self.dt:g} s",
                Fmi2Status.error,
            )
            return False
        try:
            self._set_environment()
            self.sim.set_helm(rudder_order_rad=float(self.rudder_order), rev_order=float(self.rev_order))
            alive = self.sim.step(k)
        except Exception as exc:  # noqa: BLE001 - an input out of range: the importer's log, not a crash
            self.log(f"{type(exc).__name__}: {exc}", Fmi2Status.error)
            return False
        if not alive:
            self.log(
                f"the ship's motion diverged before t = {current_time + step_size:g} s", Fmi2Status.error
            )
            return False
        self._read_outputs()
        return True
