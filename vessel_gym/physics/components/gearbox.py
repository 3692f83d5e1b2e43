"""A geared plant that reverses through its gearbox: a non-reversible medium-speed diesel driving a fixed-pitch
propeller through a reversing reduction gear with one hydraulically applied multi-disc friction clutch per
direction (ahead, astern).

The engine always turns the same way; ahead or astern is chosen by which clutch is applied. A reversal is the
sequence a bridge control system runs on such a plant (docs/physics.md, "Engine reversal"): the engine is
brought to idle and the clutch of the old direction released at once; the propeller, no longer driven, slows
in the ship's wake towards its windmilling speed; the clutch of the new direction is applied only once the
engine is down to its shifting speed and the propeller turns against the new direction slower than the
engagement limit; it fills over its engagement time, slipping while its torque capacity cannot yet hold the
engine and propeller together (the slip stops the windmilling propeller and pulls the engine down), and locks;
the governor then raises the engine to the ordered speed.

States (the component contract's :class:`~vessel_gym.physics.components.State` entries):

* ``engine_speed`` n_E (rev/s, engine side, >= 0: the engine does not reverse),
* ``governor`` the PI speed governor's integrator (fuel index, -): the ship's ``[engine]`` gains,
* ``clutch`` c in [-1, 1]: the applied fraction of the ahead (c > 0) or astern (c < 0) clutch's pressure.

Equations (engine side of the clutch; i the gear ratio, eta its efficiency, s = sign c the engaged train):

    2 pi I_E dn_E/dt = Q_E(n_E, f) - Q_c,        shaft: 2 pi I_s dn/dt = s eta i Q_c - Q_P - Q_f,
    slip w = n_E - s i n,   |Q_c| <= Q_cap = |c| k_cap Q_E,rated.

The clutch torque is the friction model of Karnopp (1985, J. Dyn. Syst. Meas. Control 107:100-103): it is the
torque that keeps engine and shaft together (Q_lock, from both equations with dw/dt = 0) as long as that is
within the capacity, otherwise the capacity against the slip. For a fixed integration step the stick is
stabilised: Q_c = clip(Q_lock + K w, -Q_cap, Q_cap) with K chosen so that a residual slip decays with the time
constant ``lock_time_s``, or the physics step if that is longer (the exact stick would need a step far below the
clutch's slip dynamics); the clutch's fill and release end in an exponential approach of the same kind.

The one function is :func:`gearbox_drive` (compiled; runs un-jitted with NUMBA_DISABLE_JIT=1); the component
:class:`ReversingGearbox` evaluates it on the whole batch once per integration stage.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import Engine, State
from vessel_gym.physics.params import ENGINE, TRANSMISSION
from vessel_gym.physics.propulsion import (
    clutch_direction,
    engine_drag_torque,
    engine_torque,
    governor,
    shaft_friction_torque,
)
from vessel_gym.physics.schema import param
from vessel_gym.physics.steady import fuel_index_for
from vessel_gym.physics.units import RPM
from vessel_gym.physics.vessel import force_terms


@dataclass(frozen=True, kw_only=True)
class ReversingGearboxParams:
    """The ship-file keys of the plant (``[[components]] params``); the engine's rating, torque map, inertia and
    governor gains and the gearbox's ratio, efficiency and shaft inertia stay in ``[engine]`` and
    ``[transmission]``."""

    clutch_capacity_ratio: float = param(
        1.5,
        unit="-",
        lo=1.0,
        hi=4.0,
        doc="slipping torque capacity of a fully applied clutch / engine rated torque (>= 1: a clutch that "
        "cannot carry the rated torque slips in service)",
    )
    engagement_time_s: float = param(
        3.0, unit="s", lo=0.2, hi=30.0, doc="time to apply a clutch from released to full pressure"
    )
    release_time_s: float = param(0.5, unit="s", lo=0.05, hi=10.0, doc="time to release a clutch")
    engage_rpm_fraction: float = param(
        0.3,
        unit="-",
        lo=0.0,
        hi=1.0,
        doc="a clutch is applied only while the propeller turns against its direction slower than this "
        "fraction of rated propeller speed",
    )
    shift_rpm_fraction: float = param(
        0.4,
        unit="-",
        lo=0.05,
        hi=1.0,
        doc="... and the engine runs no faster than this fraction of its rated speed",
    )
    idle_rpm_fraction: float = param(
        0.25, unit="-", lo=0.05, hi=0.8, doc="engine idle speed while declutched or reversing / rated speed"
    )
    lock_time_s: float = param(
        0.2,
        unit="s",
        lo=0.01,
        hi=5.0,
        doc="time constant with which a residual clutch slip decays once the clutch holds (stick "
        "stabilisation for a fixed step; a longer physics step takes its place)",
    )


# indices of the plant's constants row C (ReversingGearbox.constants)
C_CAP = 0  # clutch capacity / engine rated torque, -
C_ENGAGE_T = 1  # s
C_RELEASE_T = 2  # s
C_ENGAGE_REV = 3  # propeller speed against the new direction below which a clutch may be applied, rev/s
C_SHIFT_REV = 4  # engine speed at or below which a clutch may be applied, rev/s
C_IDLE_REV = 5  # engine idle speed, rev/s
C_LOCK_T = 6  # s
C_I_E = 7  # engine rotating inertia (engine side), kg m^2
#: the simulation's step, s: the numerical time constants (the clutch's fill tail, the stick) are at least one
#: step, so that RK4 follows them without overshoot at any step the vessel's own dynamics allow (0: exact)
C_DT = 8
NC = 9

#: share of a clutch's fill or release time spent in its final exponential approach, so that the pressure's rate
#: is continuous for RK4 (as the direct-reversing engine's reversing gear, propulsion.CAM_TAU_FRACTION), -
CLUTCH_TAU_FRACTION = 0.1
#: a clutch counts as applied within this much of full pressure, -
CLUTCH_SET = 0.05

# phases, reported by gearbox_drive
PHASE_LOCKED = 0  # the applied clutch holds engine and propeller together
PHASE_SLIPPING = 1  # a clutch is applied but slips at its capacity
PHASE_ENGAGING = 2  # the clutch of the ordered direction is filling
PHASE_WAITING = 3  # declutched: stop ordered, or waiting for the engine and propeller to slow for the shift
PHASE_NAMES = ("locked", "slipping", "engaging", "waiting")

N_RESULT = 9


@njit(cache=True)
def gearbox_drive(P, C, n, n_E, gov, c, n_order, Q_load):
    """Drive torque of the reversing-gear plant and the rates of its states.

    P the ship's parameter row (engine map, governor gains, gear ratio and efficiency, shaft inertia
    ``TRANSMISSION.I_shaft``), C the plant's constants (``C_*``); n the propeller shaft speed (rev/s), n_E the engine
    speed (rev/s), gov the governor integrator, c the clutch state, n_order the shaft-speed order (rev/s, its
    sign the direction, |order| below ``clutch_min_rpm`` a stop), Q_load = Q_P + Q_f the propeller's and
    the shafting's torque on the shaft (N m).

    Returns (Q_drive at the propeller shaft N m, dn_E/dt rev/s^2, d gov/dt 1/s, dc/dt 1/s, fuel index,
    engine torque Q_E N m, clutch torque Q_c N m (engine side), slip rev/s (engine side), phase).
    """
    i_g = P[TRANSMISSION.gear_ratio]
    eta = P[TRANSMISSION.efficiency]
    d = clutch_direction(P, n_order)
    # applied (beyond the last few per cent, which a fixed step may overshoot through 0) in the ordered direction
    along = c * d >= CLUTCH_SET
    # the interlock: a clutch is applied only with the engine near idle and the propeller nearly stopped
    permit = -d * n <= C[C_ENGAGE_REV] and n_E <= C[C_SHIFT_REV]
    target = d if (d != 0.0 and (along or permit)) else 0.0
    filling = target * c >= 0.0 and abs(target) > abs(c)
    T_fill = C[C_ENGAGE_T] if filling else C[C_RELEASE_T]
    rate = 1.0 / T_fill
    dc = max(-rate, min(rate, (target - c) / max(CLUTCH_TAU_FRACTION * T_fill, C[C_DT])))
    # governor: the ordered engine speed once the clutch of the ordered direction is applied, idle otherwise
    n_idle = C[C_IDLE_REV]
    n_Eo = max(i_g * abs(n_order), n_idle) if c * d >= 1.0 - CLUTCH_SET else n_idle
    fuel, dgov, _s, _ne = governor(P, n_E / i_g, gov, n_Eo / i_g)
    Q_E = engine_torque(P, n_E, fuel) if fuel > 0.0 else engine_drag_torque(P, n_E)
    # the clutch (Karnopp stick-slip, stabilised): engine-side torque through the engaged train s
    s = 1.0 if c > 0.0 else (-1.0 if c < 0.0 else 0.0)
    I_E = C[C_I_E]
    I_s = P[TRANSMISSION.I_shaft]
    a = 1.0 / I_E + eta * i_g * i_g / I_s  # 1/(kg m^2): 2 pi x the slip deceleration per unit clutch torque
    Q_cap = abs(c) * C[C_CAP] * P[ENGINE.Q_e_rated]
    slip = n_E - s * i_g * n
    Q_lock = (Q_E / I_E + s * i_g * Q_load / I_s) / a
    Q_hold = Q_lock + 2.0 * math.pi * slip / (max(C[C_LOCK_T], C[C_DT]) * a)
    Q_c = max(-Q_cap, min(Q_cap, Q_hold))
    dn_E = (Q_E - Q_c) / (2.0 * math.pi * I_E)
    if target == 0.0:
        phase = PHASE_WAITING
    elif abs(target - c) > CLUTCH_SET:
        phase = PHASE_ENGAGING
    elif abs(Q_hold) > Q_cap:
        phase = PHASE_SLIPPING
    else:
        phase = PHASE_LOCKED
    return s * eta * i_g * Q_c, dn_E, dgov, dc, fuel, Q_E, Q_c, slip, phase


@njit(cache=True)
def gearbox_batch(Ps, ship_index, x, inp, env, Z, C, out):
    """:func:`gearbox_drive` for every vessel of a batch: states ``x`` (N, NX), inputs, environment rows, the
    plant's states ``Z`` (N, 3) = (n_E, governor, clutch); fills ``out`` (N, N_RESULT). The propeller's torque
    comes from the vessel's own force evaluation (:func:`vessel.force_terms`, the one home of the wake and the
    four-quadrant propeller)."""
    for k in range(x.shape[0]):
        P = Ps[ship_index[k]]
        n = x[k, lo.X_REV]
        f = force_terms(P, x[k], env[k], env[k, lo.E_T_OVER_H], True, True)
        Q_load = f.Q_prop + shaft_friction_torque(P, n)
        q, dn_E, dgov, dc, fuel, Q_E, Q_c, slip, phase = gearbox_drive(
            P, C, n, Z[k, 0], Z[k, 1], Z[k, 2], inp[k, lo.U_REV_C], Q_load
        )
        out[k, 0], out[k, 1], out[k, 2], out[k, 3], out[k, 4] = q, dn_E, dgov, dc, fuel
        out[k, 5], out[k, 6], out[k, 7], out[k, 8] = Q_E, Q_c, slip, phase


class ReversingGearbox(Engine):
    """Non-reversible medium-speed diesel, reversing reduction gear with a friction clutch per direction,
    fixed-pitch propeller (slot ``engine``; it replaces the built-in engine, governor and instant clutch).

    Chosen from a ship file (``supply.toml``)::

        [[components]]
        slot = "engine"
        model = "vessel_gym.physics.components.gearbox:ReversingGearbox"
        replace = true
        params = { clutch_capacity_ratio = 1.5, engagement_time_s = 3.0, ... }

    The telegraph keeps its meaning: an order is a propeller speed (rev/s), its sign the direction the
    gearbox drives in.
    """

    Params = ReversingGearboxParams

    def __init__(self, ship, params=None):
        params = ReversingGearboxParams() if params is None else params
        super().__init__(ship, params)
        eng, tr = ship.engine, ship.transmission
        n_rated = eng.rated_rpm * RPM  # engine, rev/s
        idle = params.idle_rpm_fraction * n_rated
        if idle / tr.gear_ratio <= tr.clutch_min_rpm * RPM:
            raise ValueError(
                f"params idle_rpm_fraction: {params.idle_rpm_fraction} gives an idle "
                f"speed that turns the propeller slower than [transmission] clutch_min_rpm (allowed: above "
                f"{tr.clutch_min_rpm * tr.gear_ratio / eng.rated_rpm:.3g})"
            )
        C = np.zeros(NC)
        C[C_CAP] = params.clutch_capacity_ratio
        C[C_ENGAGE_T], C[C_RELEASE_T] = params.engagement_time_s, params.release_time_s
        C[C_ENGAGE_REV] = params.engage_rpm_fraction * n_rated / tr.gear_ratio
        C[C_SHIFT_REV] = max(params.shift_rpm_fraction, params.idle_rpm_fraction) * n_rated
        C[C_IDLE_REV] = idle
        C[C_LOCK_T] = params.lock_time_s
        C[C_I_E] = eng.inertia_kgm2
        self.constants = C
        self.states = (
            State("engine_speed", "rev/s", idle, "engine speed (engine side; the engine does not reverse)"),
            State("governor", "-", 0.0, "speed-governor integrator, fuel index"),
            State("clutch", "-", 0.0, "applied fraction of the ahead (+) or astern (-) clutch's pressure"),
        )

    def shaft_inertia_kgm2(self) -> float:
        """0: the engine's inertia is behind the clutch, in its own state's equation (the kernel's shaft keeps
        the ``[transmission]`` shaft inertia)."""
        return 0.0

    def evaluate(self, sim, x, s) -> np.ndarray:
        """(N, N_RESULT) of :func:`gearbox_drive` at the stage states ``x`` and plant states ``s``."""
        out = np.empty((x.shape[0], N_RESULT))
        self.constants[C_DT] = sim.dt
        Z = np.ascontiguousarray(s, dtype=float)
        gearbox_batch(sim.Ps, sim.ship_index, np.ascontiguousarray(x), sim.inputs, sim.env, Z, self.constants, out)
        return out

    def shaft_torque(self, sim, x, s):
        return self.evaluate(sim, x, s)[:, 0]

    def rates(self, sim, x, s):
        return self.evaluate(sim, x, s)[:, 1:4]

    def steady_states(self, sim, x, Q_hold):
        """Clutch applied in the order's direction and locked (engine at i |n|), the governor integrator at the
        fuel index whose torque holds ``Q_hold``; a stop order: declutched, engine idling unloaded."""
        Z = np.zeros((x.shape[0], 3))
        for k in range(x.shape[0]):
            P = sim.Ps[sim.ship_index[k]]
            d = clutch_direction(P, sim.inputs[k, lo.U_REV_C])
            i_g, eta = P[TRANSMISSION.gear_ratio], P[TRANSMISSION.efficiency]
            if d == 0.0:
                n_E, Q_E = self.constants[C_IDLE_REV], 0.0
            else:
                n_E, Q_E = d * i_g * x[k, lo.X_REV], d * Q_hold[k] / (eta * i_g)
            Z[k] = (n_E, fuel_index_for(P, n_E, Q_E), d)
        return Z
