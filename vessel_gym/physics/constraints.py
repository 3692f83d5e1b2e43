"""Motion constraints: captive (prescribed) motion, the virtual planar motion mechanism (PMM).

A captive model does not integrate its equations of motion: the rig prescribes u, v, r and their rates, and
measures the hydrodynamic forces. Here the rig runs on any ship file through the same component functions as
the free-running simulation, so the tests a towing tank (or ``vessel-cfd``) performs can be repeated on the
model itself: steady tow, static drift, pure sway, pure yaw (ITTC Recommended Procedure 7.5-02-06-02, captive model test).

Measured hydrodynamic force = component forces (hull, and optionally rudder and propeller) at the prescribed
velocities + the added-mass inertia and added-mass Coriolis reactions, i.e. everything except the rigid body's
own inertia m(u' - v r - x_G r^2) etc.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.kinematics import added_mass_coriolis_forces
from vessel_gym.physics.shipfile import Ship, load_ship
from vessel_gym.physics.vessel import N_OUT, forces, mass_matrix, pack


@dataclass(frozen=True)
class CaptiveRecord:
    """Prescribed motion and measured hydrodynamic loads (SI; body axes at midship)."""

    t: np.ndarray
    y: np.ndarray  # lateral position of the midship point (pure sway), m
    psi: np.ndarray  # heading (pure yaw), rad
    u: np.ndarray
    v: np.ndarray
    r: np.ndarray
    udot: np.ndarray
    vdot: np.ndarray
    rdot: np.ndarray
    X: np.ndarray
    Y: np.ndarray
    N: np.ndarray


def captive_forces(
    ship: str | Ship,
    u,
    v,
    r,
    udot=0.0,
    vdot=0.0,
    rdot=0.0,
    delta=0.0,
    rev=0.0,
    include: tuple[str, ...] = ("hull",),
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hydrodynamic (X, Y, N) on a captive ship for arrays of prescribed motion.

    ``include`` selects the components measured: "hull" (bare hull incl. added mass), "rudder", "propeller".
    """
    s = load_ship(ship)
    if s.components:  # a user's component is a force on a batch of states, not a measured captive force
        raise ValueError(
            f"{s.path or s.name}: captive tests of a ship with its own components are not supported yet "
            f"({', '.join(e.model for e in s.components)})"
        )
    P = pack(s)
    u, v, r, udot, vdot, rdot, delta, rev = np.broadcast_arrays(
        *(np.asarray(a, dtype=float) for a in (u, v, r, udot, vdot, rdot, delta, rev))
    )
    M = mass_matrix(s)
    m, xG = s.mass_kg, s.particulars.x_G_m
    Iz = s.I_zG_kgm2 + m * xG * xG
    MA = M - np.array([[m, 0.0, 0.0], [0.0, m, m * xG], [0.0, m * xG, Iz]])
    out = np.zeros(N_OUT)
    X = np.zeros(u.shape)
    Y = np.zeros(u.shape)
    N = np.zeros(u.shape)
    x = np.zeros(lo.NX)
    inp = np.zeros(lo.NU)
    env = np.zeros(lo.NE)
    for i in np.ndindex(u.shape):
        x[lo.X_U], x[lo.X_V], x[lo.X_R], x[lo.X_DELTA], x[lo.X_REV] = u[i], v[i], r[i], delta[i], rev[i]
        f = forces(P, x, inp, env, out)
        Xi = Yi = Ni = 0.0
        if "hull" in include:
            Xi += f[0]
            Yi += f[1]
            Ni += f[2]
            # added-mass Coriolis: the part of the kernel's C(nu) nu beyond the rigid body's
            XA, YA, NA = added_mass_coriolis_forces(P, u[i], v[i], r[i])
            Xi += XA
            Yi += YA
            Ni += NA
            acc = np.array([udot[i], vdot[i], rdot[i]])
            reac = -MA @ acc
            Xi += reac[0]
            Yi += reac[1]
            Ni += reac[2]
        if "rudder" in include:
            Xi += f[4]
            Yi += f[5]
            Ni += f[6]
        if "propeller" in include:
            Xi += f[3]
        X[i], Y[i], N[i] = Xi, Yi, Ni
    return X, Y, N


def static_drift(ship: str | Ship, speed_m_s: float, drift_deg) -> CaptiveRecord:
    """Oblique tow at drift angles beta (deg, MMG convention beta = atan(-v/u): beta > 0 moves the ship towards port of its heading, v = -U sin beta)."""
    b = np.radians(np.atleast_1d(np.asarray(drift_deg, dtype=float)))
    u, v = speed_m_s * np.cos(b), -speed_m_s * np.sin(b)
    z = np.zeros_like(b)
    X, Y, N = captive_forces(ship, u, v, z)
    return CaptiveRecord(z, z, z, u, v, z, z, z, z, X, Y, N)


def pure_sway(
    ship: str | Ship,
    speed_m_s: float,
    amplitude_m: float,
    period_s: float,
    cycles: float = 1.0,
    samples_per_cycle: int = 64,
) -> CaptiveRecord:
    """Pure sway: lateral position y = y0 sin(w t), heading fixed; v = y0 w cos(w t), v' = -y0 w^2 sin(w t)."""
    w = 2.0 * math.pi / period_s
    t = np.linspace(0.0, cycles * period_s, int(cycles * samples_per_cycle), endpoint=False)
    v = amplitude_m * w * np.cos(w * t)
    vdot = -amplitude_m * w * w * np.sin(w * t)
    u = np.full_like(t, speed_m_s)
    z = np.zeros_like(t)
    X, Y, N = captive_forces(ship, u, v, z, z, vdot, z)
    return CaptiveRecord(t, amplitude_m * np.sin(w * t), z, u, v, z, z, vdot, z, X, Y, N)


def pure_yaw(
    ship: str | Ship,
    speed_m_s: float,
    yaw_amplitude_deg: float,
    period_s: float,
    cycles: float = 1.0,
    samples_per_cycle: int = 64,
) -> CaptiveRecord:
    """Pure yaw: heading psi = psi0 sin(w t) with the midship point on the sinusoidal path so that v = 0;
    r = psi0 w cos(w t), r' = -psi0 w^2 sin(w t)."""
    w = 2.0 * math.pi / period_s
    psi0 = math.radians(yaw_amplitude_deg)
    t = np.linspace(0.0, cycles * period_s, int(cycles * samples_per_cycle), endpoint=False)
    r = psi0 * w * np.cos(w * t)
    rdot = -psi0 * w * w * np.sin(w * t)
    u = np.full_like(t, speed_m_s)
    z = np.zeros_like(t)
    X, Y, N = captive_forces(ship, u, z, r, z, z, rdot)
    return CaptiveRecord(t, z, psi0 * np.sin(w * t), u, z, r, z, z, rdot, X, Y, N)
