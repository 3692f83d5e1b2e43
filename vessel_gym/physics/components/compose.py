"""Composing a vessel from built-in and user components: checked replacement, one component per slot, and the
forces named by component.

The built-ins live in the parameter row ``P`` of the compiled kernel (:func:`vessel_gym.physics.vessel.pack`);
replacing a slot switches off everything its built-in contributes there:

* ``hull``: the hull forces and its added mass (the mass matrix falls back to the rigid body's, plus the
  replacing hull's ``added_mass()``), and the added-mass Coriolis terms (only the rigid body's, Fossen 2011
  eq. 6.43 with the origin at midship, remain; the replacing hull's forces carry its own). On a ship whose
  rudder is in the hull's delta terms, the rudder leaves with the hull.
* ``rudder``: the MMG rudder, and the hull's delta terms (Y_d, N_d, Y_vvd, ...) of a derivative rudder.
* ``windage``, ``wave_drift``: their loads.
* ``engine``: the engine's torque map, its governor (the governor integrator state) and reversing gear, and its
  rotating inertia on the shaft; the replacing :class:`~vessel_gym.physics.components.Engine` drives the shaft
  with its own torque and brings its own inertia (``shaft_inertia_kgm2()``) and states.
* ``steering_gear``: the built-in gear and its exact solution over a step; the replacing
  :class:`~vessel_gym.physics.components.SteeringGear` gives the rudder rate, integrated by the method.

The governor is part of the engine (its gains are ``[engine]`` keys): replace the engine. The propeller, shaft and
transmission are not replaceable yet (the shaft's equation and the propeller's torque on it live in the compiled
kernel); ``current`` is kinematics, not a force. Asking for them raises a one-line ValueError.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import EXTRA, SLOTS, ForceRecord, name_of, slot_of
from vessel_gym.physics.components.registry import BUILTINS, builtin
from vessel_gym.physics.params import (
    ABKOWITZ,
    BODY,
    ENGINE,
    HULL,
    PROPELLER,
    RUDDER,
    STEERING_GEAR,
    TRANSMISSION,
    WAVE_DRIFT,
    WINDAGE,
)
from vessel_gym.physics.shipfile import Ship

#: replace= names kept from before the slots were named
ALIASES = {"wind": "windage", "waves": "wave_drift"}
#: slots whose built-in a Python component cannot replace yet, and why
NOT_REPLACEABLE = {
    "propeller": "its torque on the shaft and its thrust are one compiled model with the shaft-speed state",
    "governor": "the governor is part of the engine (its gains are [engine] keys): replace 'engine' with an "
    "Engine component that governs itself",
    "transmission": "it couples the engine to the shaft-speed state integrated by the compiled kernel; an Engine "
    "component delivers its torque at the propeller shaft, through its own gearbox",
    "shaft": "its speed is a state of the compiled kernel, driven by the engine (replace 'engine')",
    "current": "the current is kinematics (velocities through the water), not a force",
}
REPLACEABLE = ("hull", "rudder", "windage", "wave_drift", "engine", "steering_gear")
#: slots whose component drives a state of the vessel instead of (or besides) a force, and the method it gives
STATE_DRIVERS = {"engine": "shaft_torque", "steering_gear": "rudder_rate"}

def delta_monomials(P: np.ndarray) -> np.ndarray:
    """Indices of the Abkowitz monomials of row ``P`` that contain the rudder angle (e_d > 0)."""
    rows = P[ABKOWITZ.monomials : ABKOWITZ.monomials + lo.ABK_STRIDE * lo.MAX_MONOMIALS].reshape(
        lo.MAX_MONOMIALS, lo.ABK_STRIDE
    )
    used = np.arange(lo.MAX_MONOMIALS) < int(P[ABKOWITZ.n_monomials])
    return np.flatnonzero(used & (rows[:, 3] > 0) & np.any(rows[:, 4:] != 0.0, axis=1))


def builtin_slots(P: np.ndarray) -> dict[str, str]:
    """The slots the built-ins of row ``P`` fill: slot -> name of the built-in (registry.BUILTINS)."""
    filled = {"current": "current"}
    if P[STEERING_GEAR.by_component] == 0.0:
        filled["steering_gear"] = "steering_gear"
    kind = int(P[HULL.kind])
    if kind == lo.HULL_ABKOWITZ:
        filled["hull"] = "abkowitz_hull"
    elif kind == lo.HULL_MMG:
        filled["hull"] = "mmg_hull"
    if P[RUDDER.kind] == lo.RUDDER_MMG:
        filled["rudder"] = "mmg_rudder"
    elif kind == lo.HULL_ABKOWITZ and len(delta_monomials(P)):
        filled["rudder"] = "derivative_rudder"
    if P[PROPELLER.on] > 0.0:
        for slot in ("propeller", "transmission", "shaft"):
            filled[slot] = slot
        if P[ENGINE.by_component] == 0.0:
            filled["engine"] = filled["governor"] = "engine"
    if P[WINDAGE.on] > 0.0:
        filled["windage"] = "windage"
    if P[WAVE_DRIFT.on] > 0.0:
        filled["wave_drift"] = "wave_drift"
    return filled


def slot_name(name: str) -> str:
    """A ``replace=`` name as a slot (``wind``, ``waves`` are kept as aliases); ValueError if not replaceable."""
    slot = ALIASES.get(name, name)
    if slot in NOT_REPLACEABLE:
        raise ValueError(f"replace: {name!r} is not yet supported: {NOT_REPLACEABLE[slot]}")
    if slot not in REPLACEABLE:
        raise ValueError(f"replace: {name!r} is not one of {', '.join(REPLACEABLE + tuple(ALIASES))}")
    return slot


def rigid_body_matrix(ship: Ship) -> np.ndarray:
    """M_RB about midship (kg, kg m, kg m^2), 3 DOF, centre of gravity x_G forward of midship."""
    m, xG = ship.mass_kg, ship.particulars.x_G_m
    Iz = ship.I_zG_kgm2 + m * xG * xG  # about the origin (parallel axes), as vessel.mass_matrix
    return np.array([[m, 0.0, 0.0], [0.0, m, m * xG], [0.0, m * xG, Iz]])


def set_mass(P: np.ndarray, M: np.ndarray) -> None:
    """Store the mass matrix M (3x3) in row ``P`` as the kernel reads it (M11 and the inverse sway-yaw block)."""
    P[BODY.m11] = M[0, 0]
    Minv = np.linalg.inv(M[1:, 1:])
    P[BODY.Minv22], P[BODY.Minv23], P[BODY.Minv32], P[BODY.Minv33] = Minv[0, 0], Minv[0, 1], Minv[1, 0], Minv[1, 1]


def remove_hull(P: np.ndarray, ship: Ship) -> None:
    """Switch off the built-in hull of row ``P``: its forces, added mass and added-mass Coriolis terms."""
    m, xG = ship.mass_kg, ship.particulars.x_G_m
    P[HULL.kind] = lo.HULL_NONE
    set_mass(P, rigid_body_matrix(ship))
    # -C_RB(nu) nu about midship: X + m (v r + x_G r^2), Y - m u r, N - m x_G u r
    P[BODY.CX_vr], P[BODY.CX_rr], P[BODY.CY_ur], P[BODY.CN_ur] = m, m * xG, m, m * xG


def remove_rudder(P: np.ndarray) -> None:
    """Switch off the built-in rudder of row ``P``: the MMG rudder and the hull's delta terms."""
    P[RUDDER.kind] = lo.RUDDER_DERIVATIVES
    for k in delta_monomials(P):
        start = ABKOWITZ.monomials + lo.ABK_STRIDE * k
        P[start + 4 : start + 7] = 0.0  # c_X, c_Y, c_N of the monomial; its exponents stay (a zero term)


def remove_engine(P: np.ndarray, ship: Ship) -> None:
    """Switch off the built-in engine of row ``P``: its drive torque, governor and reversing gear (the kernel
    takes the shaft's drive torque from the replacing engine) and its inertia on the shaft."""
    P[ENGINE.by_component] = 1.0
    P[TRANSMISSION.I_shaft] = ship.transmission.shaft_inertia_kgm2


def _shaft_inertia(component: Any, where: str) -> float:
    fn = getattr(component, "shaft_inertia_kgm2", None)
    I_e = fn() if callable(fn) else None
    if not isinstance(I_e, (int, float)) or not np.isfinite(I_e) or I_e < 0.0:
        raise ValueError(
            f"{where}: engine component {name_of(component)} needs shaft_inertia_kgm2() returning its rotating "
            "inertia referred to the propeller shaft, kg m^2 >= 0 (the built-in engine's leaves with it)"
        )
    return float(I_e)


def _state_driver(component: Any, slot: str, where: str) -> None:
    method = STATE_DRIVERS[slot]
    if not callable(getattr(component, method, None)):
        raise ValueError(
            f"{where}: {name_of(component)} fills slot {slot!r} but has no {method}(sim, x, s) "
            f"(subclass components.{'Engine' if slot == 'engine' else 'SteeringGear'})"
        )


def _added_mass(component: Any, where: str) -> np.ndarray:
    fn = getattr(component, "added_mass", None)
    if not callable(fn):
        raise ValueError(
            f"{where}: hull component {name_of(component)} has no added_mass(); a hull brings its added mass "
            "(the built-in hull's goes with it): return M_A, 3x3 in kg, kg m, kg m^2 about midship (zeros if none)"
        )
    M_A = np.asarray(fn(), dtype=float)
    if M_A.shape != (3, 3) or not np.all(np.isfinite(M_A)):
        raise ValueError(f"{where}: {name_of(component)}.added_mass() must return a finite 3x3 array")
    return M_A


def compose(
    ship: Ship, P: np.ndarray, components: Sequence[Any], replace: Iterable[str], where: str = "Simulation"
) -> np.ndarray:
    """Row ``P`` of ``ship`` with the built-ins of the ``replace`` slots switched off, after checking that each
    slot is filled once: raises ValueError (one line naming ``where``) for an unknown or unsupported slot, a
    component in a slot a built-in still fills, two components in one slot, or a hull without added mass."""
    P = P.copy()
    try:
        slots = [slot_name(name) for name in replace]
    except ValueError as exc:  # the one line names the file or caller, as every other refusal here
        raise ValueError(f"{where}: {exc}") from None
    if "hull" in slots:
        remove_hull(P, ship)
    if "rudder" in slots:
        remove_rudder(P)
    if "windage" in slots:
        P[WINDAGE.on] = 0.0
    if "wave_drift" in slots:
        P[WAVE_DRIFT.on] = 0.0
    if "engine" in slots:
        if P[PROPELLER.on] == 0.0:
            raise ValueError(f"{where}: replace=['engine']: the ship has no propeller and engine to replace")
        remove_engine(P, ship)
    if "steering_gear" in slots:
        P[STEERING_GEAR.by_component] = 1.0
    filled = builtin_slots(P)
    taken: dict[str, str] = {}
    for c in components:
        slot = slot_of(c)
        if slot not in SLOTS:
            raise ValueError(
                f"{where}: component {name_of(c)} has slot {slot!r}, not one of {', '.join(SLOTS)}"
            )
        if slot == EXTRA:
            continue
        if slot in NOT_REPLACEABLE:
            raise ValueError(
                f"{where}: a component in slot {slot!r} is not yet supported: {NOT_REPLACEABLE[slot]}"
            )
        if slot in taken:
            raise ValueError(f"{where}: slot {slot!r} is filled twice ({taken[slot]} and {name_of(c)})")
        if slot in filled:
            raise ValueError(
                f"{where}: {name_of(c)} fills slot {slot!r}, which the ship's {filled[slot]} fills; "
                f"replace it (replace=[{slot!r}]; in a ship file's [[components]] replace = true) or use slot 'extra'"
            )
        if slot == "engine" and P[ENGINE.by_component] == 0.0:
            raise ValueError(f"{where}: {name_of(c)}: the ship has no propeller shaft for an engine to drive")
        taken[slot] = name_of(c)
        if slot == "hull":
            M = rigid_body_matrix(ship) + _added_mass(c, where)
            set_mass(P, M)
        if slot in STATE_DRIVERS:
            _state_driver(c, slot, where)
        if slot == "engine":
            P[TRANSMISSION.I_shaft] += _shaft_inertia(c, where)
    needs = {
        "hull": "a component with slot = 'hull' and added_mass() (the built-in hull's added mass leaves with it)",
        "engine": "an Engine component (the shaft would turn with no drive torque)",
        "steering_gear": "a SteeringGear component (the rudder would not move)",
    }
    for slot, what in needs.items():
        if slot in slots and slot not in taken:
            raise ValueError(f"{where}: replace=[{slot!r}] needs {what}")
    return P


def named_forces(sim: Any, x: np.ndarray | None = None) -> dict[str, ForceRecord]:
    """The forces of every component on every vessel of ``sim`` at the states ``x`` (default: its state),
    by component name: the built-ins present (registry names, from the kernel's force terms) and the user
    components (their names). Their sum plus the rigid body's Coriolis terms is the right-hand side of
    M nu' = tau."""
    from vessel_gym.physics.integrate import forces_batch
    from vessel_gym.physics.vessel import FORCE_NAMES, N_OUT

    x = sim.state if x is None else x
    out = np.zeros((sim.n, N_OUT))
    forces_batch(sim.Ps, sim.ship_index, x, sim.inputs, sim.env, out)
    column = {name: i for i, name in enumerate(FORCE_NAMES)}
    present = [builtin_slots(P) for P in sim.Ps]
    record: dict[str, ForceRecord] = {}
    for spec in BUILTINS:
        if spec.name == "derivative_rudder" or not any(spec.forces):
            continue  # the delta terms are part of X_H, Y_H, N_H; no force of its own
        on = np.array([spec.name in present[si].values() for si in sim.ship_index])
        if not on.any():
            continue
        cols = [out[:, column[f]] if f else np.zeros(sim.n) for f in spec.forces]
        record[spec.name] = ForceRecord(*(np.where(on, c, 0.0) for c in cols))
    for name, F in sim.component_forces(x):
        record[name] = ForceRecord(F[:, 0], F[:, 1], F[:, 2])
    return record


__all__ = ["builtin", "compose", "named_forces", "builtin_slots", "slot_name"]
