"""Vessel: the composition of a ship's components, and its equations of motion.

A vessel is the sum of its components' forces: hull (Abkowitz or MMG), propeller (thrust through the
thrust-deduction factor), rudder (MMG, Son & Nomoto or hull delta-terms), windage and mean wave drift, plus
any forces a user plugs in from Python (``F_ext``). The rigid body with added mass is solved in 3 DOF
(surge, sway, yaw), or in 4 DOF with roll on a ship with a ``[roll]`` table (:mod:`vessel_gym.physics.roll`),
on velocities through the water, so a uniform current only adds to the kinematics (Fossen 2011, Property
10.1 for an irrotational constant current):

    M nu_r' + C nu_r = tau_hull + tau_prop + tau_rudder + tau_wind + tau_waves + tau_ext,
    eta' = R(psi) nu_r + V_current,

with C nu_r, R(psi) and the velocities over ground and of the air from :mod:`vessel_gym.physics.kinematics`.

:func:`pack` turns a :class:`~vessel_gym.physics.shipfile.Ship` into the parameter row read by the compiled
kernel; :func:`derivatives` is the one source of the equations used by every integrator, the environments,
the manoeuvres, the captive (PMM) mode and the UDP server.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from vessel_gym.physics import crossflow
from vessel_gym.physics import layout as lo
from vessel_gym.physics.atmosphere import blendermann_wind_loads
from vessel_gym.physics.hull import drift_angle, hull_forces_at_depth
from vessel_gym.physics.kinematics import (
    add_coriolis_forces,
    ground_velocity,
    ground_velocity_body,
    relative_wind,
)
from vessel_gym.physics.params import (
    ABKOWITZ,
    BODY,
    ENGINE,
    HULL,
    LARGE_DRIFT,
    MMG,
    NP,
    PROPELLER,
    ROLL,
    RUDDER,
    STEERING_GEAR,
    TRANSMISSION,
    WAVE_DRIFT,
    WINDAGE,
    put,
    put_keys,
)
from vessel_gym.physics.propeller4q import table_code
from vessel_gym.physics.propulsion import (
    effective_wake,
    shaft_acceleration,
    shaft_rate,
    thrust_torque,
)
from vessel_gym.physics.roll import pack_roll, roll_forces
from vessel_gym.physics.seastate import drift_coefficient_table, drift_speed_table, wave_drift_forces_at_speed
from vessel_gym.physics.sections import AbkowitzHull, MMGHull
from vessel_gym.physics.shallow_water import thrust_deduction
from vessel_gym.physics.shipchecks import abkowitz_term
from vessel_gym.physics.shipfile import Ship, UserHull
from vessel_gym.physics.sonnomoto import son_nomoto_rudder_forces, son_nomoto_wake
from vessel_gym.physics.steering import mmg_rudder_forces_beta, steering_gear_rate
from vessel_gym.physics.units import DEG, RPM


def mass_matrix(ship: Ship) -> np.ndarray:
    """3x3 mass matrix M = M_RB + M_A about the origin (midship), SI units."""
    m = ship.mass_kg
    xG = ship.particulars.x_G_m
    Iz = ship.I_zG_kgm2 + m * xG * xG  # about the origin (parallel axes)
    L = ship.particulars.L_m
    rho = ship.particulars.rho_kg_m3
    h = ship.hull
    if isinstance(h, UserHull):  # the user's hull adds its own (components.compose)
        return np.array([[m, 0.0, 0.0], [0.0, m, xG * m], [0.0, xG * m, Iz]])
    if isinstance(h, MMGHull):
        d = ship.particulars.T_m
        mx = h.m_x * 0.5 * rho * L * L * d
        my = h.m_y * 0.5 * rho * L * L * d
        Jz = h.J_z * 0.5 * rho * L**4 * d
        # Yasukawa & Yoshimura (2015) eq. 4
        return np.array([[m + mx, 0.0, 0.0], [0.0, m + my, xG * m], [0.0, xG * m, Iz + Jz]])
    f = (0.5 if h.normalisation == "half_rho_L2_U2" else 1.0) * rho
    dv = h.derivatives
    X_udot = dv.get("X_udot", 0.0) * f * L**3
    Y_vdot = dv.get("Y_vdot", 0.0) * f * L**3
    Y_rdot = dv.get("Y_rdot", 0.0) * f * L**4
    N_vdot = dv.get("N_vdot", 0.0) * f * L**4
    N_rdot = dv.get("N_rdot", 0.0) * f * L**5
    return np.array(
        [[m - X_udot, 0.0, 0.0], [0.0, m - Y_vdot, m * xG - Y_rdot], [0.0, m * xG - N_vdot, Iz - N_rdot]]
    )


def _pack_terms(P: np.ndarray, derivs: dict) -> None:
    """Abkowitz terms merged by monomial (ABKOWITZ.monomials): one row (e_u, e_v, e_r, e_d, c_X, c_Y, c_N) per
    distinct monomial, in the order of first appearance in the ship file."""
    column = {"X": 4, "Y": 5, "N": 6}
    monomials: dict[tuple[int, int, int, int], list[float]] = {}
    for name, value in derivs.items():
        term = abkowitz_term(name)
        if term is None or value == 0.0:
            continue
        eq, *exponents = term
        row = monomials.setdefault(tuple(exponents), [*exponents, 0.0, 0.0, 0.0])
        row[column[eq]] += value  # two names of one term (Y_vr, Y_rv) add, as two terms would
    if len(monomials) > lo.MAX_MONOMIALS:
        raise ValueError(f"more than {lo.MAX_MONOMIALS} distinct Abkowitz monomials")
    for k, row in enumerate(monomials.values()):
        P[ABKOWITZ.monomials + lo.ABK_STRIDE * k : ABKOWITZ.monomials + lo.ABK_STRIDE * (k + 1)] = row
    P[ABKOWITZ.n_monomials] = len(monomials)


def _pack_body(P: np.ndarray, ship: Ship, M: np.ndarray) -> None:
    """params.BODY: the [particulars] keys, the mass, the mass matrix and the Coriolis coefficients of the hull
    model's equations."""
    pt = ship.particulars
    m, xG = ship.mass_kg, pt.x_G_m
    Minv = np.linalg.inv(M[1:, 1:])
    h = ship.hull
    if isinstance(h, MMGHull):
        my = h.m_y * 0.5 * pt.rho_kg_m3 * pt.L_m**2 * pt.T_m
        mx = h.m_x * 0.5 * pt.rho_kg_m3 * pt.L_m**2 * pt.T_m
        # Yasukawa & Yoshimura (2015) eq. 4: (m+m_y) v r + x_G m r^2 ; (m+m_x) u r ; x_G m u r
        coriolis = (m + my, xG * m, m + mx, xG * m)
    elif isinstance(h, UserHull) or h.coriolis == "separate":
        # a user's hull: the rigid body's Coriolis terms stay (components.compose.remove_hull); an Abkowitz
        # hull with separate Coriolis terms, seed eq. 10: m(u' - v r - x_G r^2), m(v' + u r + x_G r'),
        # I_z r' + m x_G (v' + u r)
        coriolis = (m, m * xG, m, m * xG)
    else:
        coriolis = (0.0, 0.0, 0.0, 0.0)  # in the Abkowitz derivatives
    put_keys(P, BODY, pt)
    put(P, BODY, m=m, m11=M[0, 0], Minv22=Minv[0, 0], Minv23=Minv[0, 1], Minv32=Minv[1, 0], Minv33=Minv[1, 1])
    put(P, BODY, **dict(zip(("CX_vr", "CX_rr", "CY_ur", "CN_ur"), coriolis)))


def _pack_hull(P: np.ndarray, ship: Ship) -> None:
    """params.HULL and the record of its model, params.MMG or params.ABKOWITZ, from the [hull] table."""
    h, rho = ship.hull, ship.particulars.rho_kg_m3
    put(P, HULL, r_prime_max=h.r_prime_max, U_min=h.U_min_m_s)
    if isinstance(h, MMGHull):
        put(P, HULL, kind=lo.HULL_MMG)
        put_keys(P, MMG, h)
    elif isinstance(h, UserHull):
        put(P, HULL, kind=lo.HULL_NONE)  # no built-in hull (components.compose)
    else:
        assert isinstance(h, AbkowitzHull)
        put(P, HULL, kind=lo.HULL_ABKOWITZ)
        put_keys(P, ABKOWITZ, h)
        put(
            P,
            ABKOWITZ,
            force_norm=(0.5 if h.normalisation == "half_rho_L2_U2" else 1.0) * rho,
            R_res=h.resistance_N / h.resistance_speed_m_s**2,
        )
        _pack_terms(P, h.derivatives)


def _pack_propulsion(P: np.ndarray, ship: Ship) -> None:
    """params.PROPELLER, TRANSMISSION and ENGINE from the [propeller], [transmission] and [engine] tables;
    without a propeller a neutral drive (unit ratios, a monotone map) that is never read."""
    pr = ship.propeller
    if pr is None:
        put(P, TRANSMISSION, gear_ratio=1.0, efficiency=1.0, I_shaft=1.0)
        put(P, ENGINE, n_e_rated=1.0, map_speed=np.arange(lo.MAP_NS), map_fuel=np.arange(lo.MAP_NF))
        return
    put_keys(P, PROPELLER, pr)
    wake = lo.WAKE_SON_NOMOTO if pr.wake_model == "son_nomoto" else lo.WAKE_MMG
    put(P, PROPELLER, on=1.0, four_quadrant=table_code(pr.four_quadrant), wake_kind=wake)
    eng, tr = ship.engine, ship.transmission
    n_e = eng.rated_rpm * RPM
    Q_rated = eng.rated_power_kW * 1e3 / (2.0 * math.pi * n_e)
    put_keys(P, TRANSMISSION, tr)
    put(
        P,
        TRANSMISSION,
        I_shaft=tr.shaft_inertia_kgm2 + tr.gear_ratio**2 * eng.inertia_kgm2,
        Q_friction=tr.friction_torque_fraction * Q_rated * tr.gear_ratio,
        clutch_min_rev=tr.clutch_min_rpm * RPM,
    )
    put_keys(P, ENGINE, eng)
    put(
        P,
        ENGINE,
        n_e_rated=n_e,
        Q_e_rated=Q_rated,
        map_speed=eng.torque_map_speed,
        map_fuel=eng.torque_map_fuel,
        map_torque=eng.torque_map,
        reversing=lo.REVERSING_DIRECT_AIR if eng.reversing == "direct_air_start" else lo.REVERSING_CLUTCH,
        air_brake_rev=eng.air_brake_rpm_fraction * n_e,
        firing_rev=eng.firing_rpm_fraction * n_e,
        Q_air=eng.starting_air_torque_fraction * Q_rated,
    )


def _pack_rudder(P: np.ndarray, ship: Ship) -> None:
    """params.RUDDER from the [rudder] table and params.STEERING_GEAR from [steering_gear]."""
    rd = ship.rudder
    put_keys(P, RUDDER, rd)  # each model's equations read the keys of their own model
    if rd.model == "mmg":
        put(P, RUDDER, kind=lo.RUDDER_MMG, eta=min(ship.propeller.D_m / rd.H_R_m, 1.0))  # eta = D_P / H_R
    elif rd.model == "son_nomoto":
        put(P, RUDDER, kind=lo.RUDDER_SON_NOMOTO)
    else:
        put(P, RUDDER, kind=lo.RUDDER_DERIVATIVES)
    sg = ship.steering_gear
    put_keys(P, STEERING_GEAR, sg)
    put(P, STEERING_GEAR, delta_max=sg.max_angle_deg * DEG, delta_rate_max=sg.max_rate_deg_s * DEG)


def _pack_loads(P: np.ndarray, ship: Ship) -> None:
    """params.WINDAGE from the [windage] table, params.WAVE_DRIFT from [wave_drift] (off without them)."""
    w = ship.windage
    if w is not None:
        put_keys(P, WINDAGE, w)
        put(P, WINDAGE, on=1.0)
    wd = ship.wave_drift
    if wd is not None:
        pt = ship.particulars
        put_keys(P, WAVE_DRIFT, wd)
        put(
            P,
            WAVE_DRIFT,
            on=1.0,
            table=drift_coefficient_table(pt.L_m, pt.B_m, wd.C_wp) * wd.reflection,
            speed_table=drift_speed_table(pt.L_m, pt.B_m, wd.C_wp) * wd.reflection,
        )


def pack(ship: Ship) -> np.ndarray:
    """The kernel's parameter row for ``ship`` (float64, length params.NP): each component's record
    (:mod:`vessel_gym.physics.params`) built from its ship-file section, written by field name."""
    P = np.zeros(NP)
    M = mass_matrix(ship)
    _pack_body(P, ship, M)
    _pack_hull(P, ship)
    _pack_propulsion(P, ship)
    _pack_rudder(P, ship)
    _pack_loads(P, ship)
    crossflow.pack(P, ship.large_drift)
    if ship.roll is not None:
        pt = ship.particulars
        pack_roll(P, M, ship.roll, ship.mass_kg, pt.L_m, pt.rho_kg_m3)
    return P


def abkowitz_family(Ps: np.ndarray) -> bool:
    """Whether a parameter row (or any row of a batch) uses a model of the Abkowitz family: an Abkowitz
    polynomial hull, the Son & Nomoto (1982) rudder or wake (the container ship's and Mariner's models). A
    kernel for vessels without them is compiled without them (``abk`` None: :func:`derivatives_of`)."""
    P = np.atleast_2d(Ps)
    return bool(
        (P[:, HULL.kind] == lo.HULL_ABKOWITZ).any()
        or (P[:, RUDDER.kind] == lo.RUDDER_SON_NOMOTO).any()
        or (P[:, PROPELLER.wake_kind] == lo.WAKE_SON_NOMOTO).any()
    )


def far_models(Ps: np.ndarray) -> bool:
    """Whether a parameter row (or any row of a batch) uses a model for far from the design point: the
    cross-flow hull at large drift (``[large_drift]``, crossflow.py) or the four-quadrant propeller curves
    (``[propeller] four_quadrant``, propeller4q.py). A kernel for vessels without them is compiled without them
    (``far`` None: :func:`derivatives_of`), about a fifth less to compile for such a ship (docs/performance.md)."""
    P = np.atleast_2d(Ps)
    return bool((P[:, LARGE_DRIFT.on] != 0.0).any() or (P[:, PROPELLER.four_quadrant] != 0.0).any())


# The hot call chain (the integrators' per-vessel loop -> step -> derivatives -> force_terms -> components)
# is compiled without reference counting (numba's `_nrt=False`): these functions allocate nothing and only
# read and write arrays their caller owns, so counting references is pure overhead -- an atomic increment
# and decrement of the parent array for every row view taken and every array passed, ~5-10 % of a step
# (docs/performance.md). A function compiled this way cannot allocate or return an array: `forces`, which
# returns its output row to Python, keeps counting, and the drivers allocate the scratch rows they pass in.
NO_REFCOUNT = {"_nrt": False}


N_OUT = 20
FORCE_NAMES = (
    "X_H",
    "Y_H",
    "N_H",
    "X_P",
    "X_R",
    "Y_R",
    "N_R",
    "X_W",
    "Y_W",
    "N_W",
    "X_D",
    "Y_D",
    "N_D",
    "thrust",
    "Q_prop",
    "w_P",
    "V_rw",
    "gamma_rw",
    "current_n",
    "current_e",
)
# The forces and flow quantities of one vessel at one state, by name (force_terms): FORCE_NAMES (X, Y in N and N in
# N m of each component, the propeller's thrust N, torque N m and wake fraction, the relative wind m/s and rad, the
# current m/s north and east), then cos and sin of the heading. A named tuple compiles to the plain tuple it was:
# the fields are summed by name at no cost.
VesselForces = namedtuple("VesselForces", (*FORCE_NAMES, "cos_psi", "sin_psi"))


@njit(cache=True, **NO_REFCOUNT)
def force_terms(P, x, env, H, abk, far):
    """All component forces for one vessel at state ``x``, a :data:`VesselForces` record: the N_OUT values of
    :func:`forces` by their names, then cos(psi) and sin(psi) for the kinematics in :func:`derivatives`.

    ``H`` is the draught-to-depth ratio T/h the vessel is in (``env[E_T_OVER_H]``; 0 in deep water). A
    deep-water kernel passes None (integrate.drivers): numba prunes every branch on ``H is None`` before typing,
    so this function and the hull, wake, rudder and thrust-deduction functions it calls are compiled without
    their shallow-water code (each returns its deep-water value for None, as at H = 0: the same results).
    ``abk`` (True or None) likewise leaves out the models of the Abkowitz family (:func:`abkowitz_family`),
    ``far`` (True or None) the cross-flow hull at large drift and the four-quadrant propeller (:func:`far_models`).

    A tuple, not an output array: a store into an array that the compiler cannot prove distinct from ``P``
    and ``x`` would make it load them again (see :func:`derivatives`).
    """
    u = x[lo.X_U]
    v = x[lo.X_V]
    r = x[lo.X_R]
    psi = x[lo.X_PSI]
    delta = x[lo.X_DELTA]
    n = x[lo.X_REV]
    XH, YH, NH = hull_forces_at_depth(P, u, v, r, delta, H, abk, far)
    has_prop = P[PROPELLER.on] > 0.0
    mmg_rudder = P[RUDDER.kind] == lo.RUDDER_MMG
    # one speed and drift angle for wake and rudder; the atan2 only where a model reads beta
    U = math.sqrt(u * u + v * v)
    beta = drift_angle(u, v, U) if mmg_rudder or (has_prop and P[PROPELLER.C_1] != 0.0) else 0.0
    T = 0.0
    Qp = 0.0
    wP = P[PROPELLER.w_P0]
    if has_prop:
        sn_wake = False
        if abk is not None:  # the Son & Nomoto models compiled in only where they may be used (abk)
            if P[PROPELLER.wake_kind] == lo.WAKE_SON_NOMOTO:
                wP = son_nomoto_wake(P, u, v, r)
                sn_wake = True
        if not sn_wake:
            wP = effective_wake(P, U, beta, r, H)
        T, Qp = thrust_torque(P, u * (1.0 - wP), n, far)
    XR = YR = NR = 0.0
    if mmg_rudder:
        XR, YR, NR = mmg_rudder_forces_beta(P, u, U, beta, r, delta, wP, T, H)
    elif abk is not None:
        if P[RUDDER.kind] == lo.RUDDER_SON_NOMOTO:
            XR, YR, NR = son_nomoto_rudder_forces(P, u, v, r, delta, u * (1.0 - wP), T)
    cn = env[lo.E_CUR_N]
    ce = env[lo.E_CUR_E]
    c = math.cos(psi)
    s = math.sin(psi)
    u_g, v_g = ground_velocity_body(u, v, c, s, cn, ce)
    Vrw, gam, cos_gam, sin_gam = relative_wind(u_g, v_g, c, s, env[lo.E_WIND_N], env[lo.E_WIND_E])
    XW, YW, NW = blendermann_wind_loads(P, Vrw, gam, cos_gam, sin_gam, env[lo.E_RHO_AIR])
    XD, YD, ND = wave_drift_forces_at_speed(
        P, env[lo.E_ZETA2], env[lo.E_OMEGA_ZETA2], env[lo.E_WAVE_FROM], psi, u
    )
    XP = (1.0 - thrust_deduction(P, H)) * T
    return VesselForces(XH, YH, NH, XP, XR, YR, NR, XW, YW, NW, XD, YD, ND, T, Qp, wP, Vrw, gam, cn, ce, c, s)


@njit(cache=True)
def forces(P, x, inp, env, out):
    """All component forces for one vessel at state ``x``; fills ``out`` (length N_OUT) and returns it.

    out = [X_H, Y_H, N_H, X_P, X_R, Y_R, N_R, X_W, Y_W, N_W, X_D, Y_D, N_D, thrust, Q_prop, w_P,
           V_rw, gamma_rw, cur_n, cur_e]
    """
    f = force_terms(P, x, env, env[lo.E_T_OVER_H], True, True)
    for i in range(N_OUT):
        out[i] = f[i]
    return out




@njit(cache=True, **NO_REFCOUNT)
def derivatives(P, x, inp, env, F_ext, xdot):
    """State derivative of one vessel: fills ``xdot`` (length NX).

    The general form of :func:`derivatives_of`: every part of the model tested at run time.
    """
    derivatives_of(P, x, inp, env, F_ext, xdot, env[lo.E_T_OVER_H], True, True, True, True)


@njit(cache=True, **NO_REFCOUNT)
def derivatives_of(P, x, inp, env, F_ext, xdot, H, roll, ext, abk, far):
    """State derivative of one vessel, :func:`derivatives` compiled for one kind of vessel: fills ``xdot``
    (length NX; on a 3-DOF kernel the roll columns are not written).

    The five last arguments choose what is compiled in; the integrators' drivers pass compile-time
    constants (integrate.drivers), so numba builds one kernel per combination and LLVM drops the parts a
    combination rules out:

    * ``H``, the draught-to-depth ratio T/h: ``env[E_T_OVER_H]``, or None for deep water
      (:func:`force_terms`);
    * ``roll``: True where a vessel may have the fourth degree of freedom (``ROLL.on``, tested at run time),
      None for 3-DOF vessels only (the roll equations are not compiled);
    * ``ext``: True where a user's engine may drive the shaft (``ENGINE.by_component``, tested at run time), False
      for the built-in engine only;
    * ``abk``: True where a vessel may use a model of the Abkowitz family (:func:`abkowitz_family`: an Abkowitz
      hull, the Son & Nomoto rudder or wake; tested at run time), None for vessels without (those models are not
      compiled in: :func:`~vessel_gym.physics.hull.hull_forces_at_depth`, :func:`force_terms`);
    * ``far``: True where a vessel may use the cross-flow hull at large drift or the four-quadrant propeller
      (:func:`far_models`; tested at run time), None for vessels without (not compiled in).

    A False or None flag is only passed for vessels it describes, so every combination gives the results of the
    general form to the bit.

    F_ext = (X, Y, N) added to the right-hand side (user components, captive-rig reactions), and on a vessel
    whose engine is a user's component (``ENGINE.by_component``) a fourth entry, its drive torque at the propeller
    shaft (N m; 0 when F_ext has three entries, as in a force-only balance). The forces
    travel from :func:`force_terms` as a named record (:data:`VesselForces`), not through a scratch row. Every result is computed before the first store into ``xdot``: the compiler cannot rule
    out that ``xdot`` shares memory with ``P`` or ``x``, so a store would make it load them again.
    """
    f = force_terms(P, x, env, H, abk, far)
    u = x[lo.X_U]
    v = x[lo.X_V]
    r = x[lo.X_R]
    X, Y, N = add_coriolis_forces(
        P,
        u,
        v,
        r,
        f.X_H + f.X_P + f.X_R + f.X_W + f.X_D + F_ext[0],
        f.Y_H + f.Y_R + f.Y_W + f.Y_D + F_ext[1],
        f.N_H + f.N_R + f.N_W + f.N_D + F_ext[2],
    )
    vn, ve = ground_velocity(u, v, f.cos_psi, f.sin_psi, f.current_n, f.current_e)
    delta_dot = steering_gear_rate(P, x[lo.X_DELTA], inp[lo.U_DELTA_C])
    ndot = 0.0
    gdot = 0.0
    cdot = 0.0
    if P[PROPELLER.on] > 0.0:
        if ext and P[ENGINE.by_component] > 0.0:
            # a user's engine (components.compose): its drive torque arrives as F_ext[3]; the built-in
            # governor and reversing gear are not part of the vessel (their states hold still)
            Q_drive = F_ext[lo.F_Q_SHAFT] if F_ext.shape[0] > lo.F_Q_SHAFT else 0.0
            ndot = shaft_rate(P, x[lo.X_REV], Q_drive, f.Q_prop)
        else:
            ndot, cdot, gdot, _fuel, _ne, _qe = shaft_acceleration(
                P, x[lo.X_REV], x[lo.X_CAM], x[lo.X_GOV], inp[lo.U_REV_C], f.Q_prop
            )
    phidot = 0.0
    pdot = 0.0
    udot = X / P[BODY.m11]
    vdot = P[BODY.Minv22] * Y + P[BODY.Minv23] * N
    rdot = P[BODY.Minv32] * Y + P[BODY.Minv33] * N
    psidot = r
    # numba prunes a branch on `flag is None` before typing (not one on a literal bool, which LLVM drops only
    # after the branch's callees are compiled): a 3-DOF kernel then compiles no roll equations at all
    if roll is not None:
        if P[ROLL.on] > 0.0:
            # the fourth degree of freedom (roll.py): roll terms of the hull, restoring and damping, the rudder's
            # sway force z_R below the roll axis; the 3x3 mass matrix over (v, r, p) couples sway, yaw and roll
            phi = x[lo.X_PHI]
            p = x[lo.X_P]
            Xr, Yr, Kr, Nr = roll_forces(P, u, v, r, p, phi)
            X += Xr
            Y += Yr
            N += Nr
            K = Kr - P[ROLL.z_R_m] * f.Y_R + P[ROLL.torque_sign] * f.Q_prop  # rudder; shaft torque reaction
            j = ROLL.Minv
            udot = X / P[BODY.m11]
            vdot = P[j] * Y + P[j + 1] * N + P[j + 2] * K
            rdot = P[j + 3] * Y + P[j + 4] * N + P[j + 5] * K
            pdot = P[j + 6] * Y + P[j + 7] * N + P[j + 8] * K
            # Euler-angle kinematics with zero pitch (Fossen 2011 eq. 2.29): the heeled body y-axis spans the
            # horizontal by cos(phi), and the yaw rate about the heeled z-axis turns the heading by r cos(phi)
            cphi = math.cos(phi)
            vn, ve = ground_velocity(u, v * cphi, f.cos_psi, f.sin_psi, f.current_n, f.current_e)
            psidot = r * cphi
            phidot = p
    xdot[lo.X_U] = udot
    xdot[lo.X_V] = vdot
    xdot[lo.X_R] = rdot
    xdot[lo.X_N] = vn
    xdot[lo.X_E] = ve
    xdot[lo.X_PSI] = psidot
    xdot[lo.X_DELTA] = delta_dot
    xdot[lo.X_REV] = ndot
    xdot[lo.X_GOV] = gdot
    xdot[lo.X_CAM] = cdot
    if roll is not None:
        xdot[lo.X_PHI] = phidot
        xdot[lo.X_P] = pdot
