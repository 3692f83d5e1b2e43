"""The built-in components, declared through the component contract.

One row per built-in: its slot, its ship-file table (and the ``model`` value that selects it), the dataclass
of its keys (units, ranges and docs are on the fields), the states it owns, the named forces it contributes
(names of :data:`vessel_gym.physics.vessel.FORCE_NAMES`, in X, Y, N order), its one function and the record
of its parameters the compiled model reads (:mod:`vessel_gym.physics.params`). The
equations themselves stay compiled in their modules; this table describes them, and
:mod:`~vessel_gym.physics.components.compose` reads it to check replacements and to name forces.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from vessel_gym.physics import sections
from vessel_gym.physics.atmosphere import blendermann_wind_loads
from vessel_gym.physics.hull import hull_forces
from vessel_gym.physics.kinematics import ground_velocity
from vessel_gym.physics.propulsion import (
    clutch_direction,
    engine_drive,
    governor,
    propeller_thrust_torque,
    shaft_acceleration,
)
from vessel_gym.physics.seastate import wave_drift_forces
from vessel_gym.physics.steering import mmg_rudder_forces_beta, steering_gear_rate


@dataclass(frozen=True)
class ComponentSpec:
    """A built-in component's declaration."""

    name: str
    slot: str
    table: str  # ship-file table ("" for the environment's current)
    model: str  # the table's ``model`` value that selects it ("" when the table has no model key)
    params: type | None  # dataclass of the table's keys (unit, range, doc on each field)
    states: tuple[str, ...]  # entries of layout.STATE_NAMES the component integrates
    forces: tuple[str, ...]  # X, Y, N names in vessel.FORCE_NAMES ("" where it contributes none)
    function: Callable
    citation: str
    # the kind of its parameter record in the compiled model (params.RECORDS: fields with units, built from
    # the table by vessel.pack); "" where it has none (the current is a row of the environment)
    record: str = ""


BUILTINS: tuple[ComponentSpec, ...] = (
    ComponentSpec(
        "abkowitz_hull",
        "hull",
        "hull",
        "abkowitz",
        sections.AbkowitzHull,
        (),
        ("X_H", "Y_H", "N_H"),
        hull_forces,
        "Abkowitz (1964) polynomial in SNAME (1950) prime variables; added mass from the *_dot derivatives",
        record="abkowitz",
    ),
    ComponentSpec(
        "mmg_hull",
        "hull",
        "hull",
        "mmg",
        sections.MMGHull,
        (),
        ("X_H", "Y_H", "N_H"),
        hull_forces,
        "Yasukawa & Yoshimura (2015), J. Mar. Sci. Technol. 20, eq. 4 and 8-10 (added mass m_x, m_y, J_z)",
        record="mmg_hull",
    ),
    ComponentSpec(
        "propeller",
        "propeller",
        "propeller",
        "",
        sections.Propeller,
        (),
        ("X_P", "", ""),
        propeller_thrust_torque,
        "open-water K_T, K_Q quadratics; wake change Yasukawa & Yoshimura (2015) eq. 15-16; astern quadrants "
        "docs/physics.md",
        record="propeller",
    ),
    ComponentSpec(
        "engine",
        "engine",
        "engine",
        "",
        sections.Engine,
        ("reversing_gear",),  # moves only on a direct-reversing engine ([engine] reversing)
        ("", "", ""),
        engine_drive,
        "torque map (engine speed x fuel index), bilinear, the seed report's engine subsystem; a direct-reversing "
        "two-stroke's reversing sequence (propulsion.direct_reversing_drive)",
        record="engine",
    ),
    ComponentSpec(
        "governor",
        "governor",
        "engine",
        "",
        sections.Engine,
        ("governor",),
        ("", "", ""),
        governor,
        "PI speed governor with conditional-integration anti-windup (keys governor_Kp, governor_Ki)",
        record="engine",
    ),
    ComponentSpec(
        "transmission",
        "transmission",
        "transmission",
        "",
        sections.Transmission,
        (),
        ("", "", ""),
        clutch_direction,
        "gear ratio, efficiency, clutch ahead / neutral / astern (docs/physics.md)",
        record="transmission",
    ),
    ComponentSpec(
        "shaft",
        "shaft",
        "transmission",
        "",
        sections.Transmission,
        ("n",),
        ("", "", ""),
        shaft_acceleration,
        "rigid shafting: 2 pi I dn/dt = s eta_G i Q_E - Q_P - Q_f (propulsion.py)",
        record="transmission",
    ),
    ComponentSpec(
        "steering_gear",
        "steering_gear",
        "steering_gear",
        "",
        sections.SteeringGear,
        ("delta",),
        ("", "", ""),
        steering_gear_rate,
        "rate-limited first-order steering gear (IMO MSC.137(76) trials assume the rate limit)",
        record="steering_gear",
    ),
    ComponentSpec(
        "mmg_rudder",
        "rudder",
        "rudder",
        "mmg",
        sections.Rudder,
        (),
        ("X_R", "Y_R", "N_R"),
        mmg_rudder_forces_beta,
        "Yasukawa & Yoshimura (2015) eq. 20-36",
        record="rudder",
    ),
    ComponentSpec(
        "derivative_rudder",
        "rudder",
        "rudder",
        "derivatives",
        sections.Rudder,
        (),
        ("X_H", "Y_H", "N_H"),  # the hull's delta terms (Y_d, N_d, Y_vvd, ...)
        hull_forces,
        "the hull's Abkowitz delta terms (Abkowitz 1964)",
        record="abkowitz",
    ),
    ComponentSpec(
        "windage",
        "windage",
        "windage",
        "",
        sections.Windage,
        (),
        ("X_W", "Y_W", "N_W"),
        blendermann_wind_loads,
        "Blendermann (1994), as in Fossen (2011) eq. 8.27-8.30",
        record="windage",
    ),
    ComponentSpec(
        "wave_drift",
        "wave_drift",
        "wave_drift",
        "",
        sections.WaveDrift,
        (),
        ("X_D", "Y_D", "N_D"),
        wave_drift_forces,
        "Faltinsen et al. (1980) short-wave asymptotic drift (Faltinsen 1990 eq. 5.40)",
        record="wave_drift",
    ),
    ComponentSpec(
        "current",
        "current",
        "",
        "",
        None,
        (),
        ("", "", ""),
        ground_velocity,
        "uniform irrotational current in the kinematics (Fossen 2011, Property 10.1)",
        record="",
    ),
)


def builtin(name: str) -> ComponentSpec:
    """The declaration of the built-in component ``name``."""
    for spec in BUILTINS:
        if spec.name == name:
            return spec
    raise KeyError(f"no built-in component {name!r} (one of {', '.join(s.name for s in BUILTINS)})")
