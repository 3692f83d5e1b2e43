"""Independent plain-numpy transcription of the right-hand side of Fossen's MSS ``container.m`` (Son & Nomoto
1982 high-speed container ship, revision 2022-07-22), line by line in its own state vector and units, for the
code-to-code validation of the built-in ``container`` ship (tests/physics/test_container.py).

State x = [u v r x y psi p phi delta n] (m/s, m/s, rad/s, m, m, rad, rad/s, rad, rad, rpm); input
ui = [delta_c (rad), n_c (rpm)]. Nothing here imports vessel_gym: the transcription shares no code with the
model it checks. The only departure from container.m is that the rudder limit ``delta_max_deg`` is an
argument (container.m fixes it at 10 deg); its default is container.m's value.

Son, K.H. and Nomoto, K. (1982). On the coupled motion of steering and rolling of a high-speed container
ship. Naval Architecture and Ocean Engineering 20, 73-83 (from J. Soc. Nav. Arch. Japan 150, 1981).
"""

from __future__ import annotations

import math

import numpy as np


def container_rhs(x, ui, delta_max_deg=10.0):
    """xdot of container.m for the state ``x`` (10,) and input ``ui`` (2,). Returns (xdot, U)."""
    L = 175.0  # m
    U = math.sqrt(x[0] ** 2 + x[1] ** 2)  # m/s
    if U <= 0.0 or x[9] <= 0.0:
        raise ValueError("container.m needs U > 0 and n > 0")
    Ddelta_max = 5.0  # deg/s
    n_max = 160.0  # rpm

    delta_c = ui[0]
    n_c = ui[1] / 60.0 * L / U
    u = x[0] / U
    v = x[1] / U
    p = x[6] * L / U
    r = x[2] * L / U
    phi = x[7]
    psi = x[5]
    delta = x[8]
    n = x[9] / 60.0 * L / U

    m, mx, my = 0.00792, 0.000238, 0.007049
    Ix, alphay, lx = 0.0000176, 0.05, 0.0313
    ly, Iz = 0.0313, 0.000456
    Jx, Jz = 0.0000034, 0.000419
    g = 9.81
    nabla = 21222.0
    AR, Delta, D = 33.0376, 1.8219, 6.533
    GM = 0.3 / L
    rho = 1025.0
    t = 0.175
    W = rho * g * nabla / (rho * L**2 * U**2 / 2.0)

    Xuu, Xvr, Xrr, Xphiphi, Xvv = -0.0004226, -0.00311, 0.00020, -0.00020, -0.00386
    Kv, Kr, Kp, Kphi = 0.0003026, -0.000063, -0.0000075, -0.000021
    Kvvv, Krrr, Kvvr, Kvrr = 0.002843, -0.0000462, -0.000588, 0.0010565
    Kvvphi, Kvphiphi, Krrphi, Krphiphi = -0.0012012, -0.0000793, -0.000243, 0.00003569
    Yv, Yr, Yp, Yphi = -0.0116, 0.00242, 0.0, -0.000063
    Yvvv, Yrrr, Yvvr, Yvrr = -0.109, 0.00177, 0.0214, -0.0405
    Yvvphi, Yvphiphi, Yrrphi, Yrphiphi = 0.04605, 0.00304, 0.009325, -0.001368
    Nv, Nr, Np, Nphi = -0.0038545, -0.00222, 0.000213, -0.0001424
    Nvvv, Nrrr, Nvvr, Nvrr = 0.001492, -0.00229, -0.0424, 0.00156
    Nvvphi, Nvphiphi, Nrrphi, Nrphiphi = -0.019058, -0.0053766, -0.0038592, 0.0024195
    kk, epsilon, xR = 0.631, 0.921, -0.5
    wp, tau, xp = 0.184, 1.09, -0.526
    cpv, cpr, ga = 0.0, 0.0, 0.088
    cRr, cRrrr, cRrrv = -0.156, -0.275, 1.96
    cRX, aH, zR = 0.71, 0.237, 0.033
    xH = -0.48

    m11 = m + mx
    m22 = m + my
    m32 = -my * ly
    m42 = my * alphay
    m33 = Ix + Jx
    m44 = Iz + Jz

    if abs(delta_c) >= delta_max_deg * math.pi / 180.0:
        delta_c = math.copysign(delta_max_deg * math.pi / 180.0, delta_c)
    delta_dot = delta_c - delta
    if abs(delta_dot) >= Ddelta_max * math.pi / 180.0:
        delta_dot = math.copysign(Ddelta_max * math.pi / 180.0, delta_dot)

    n_c = n_c * U / L
    n = n * U / L
    if abs(n_c) >= n_max / 60.0:
        n_c = math.copysign(n_max / 60.0, n_c)
    Tm = 5.65 / n if n > 0.3 else 18.83
    n_dot = 1.0 / Tm * (n_c - n) * 60.0

    vR = ga * v + cRr * r + cRrrr * r**3 + cRrrv * r**2 * v
    uP = u * ((1.0 - wp) + tau * ((v + xp * r) ** 2 + cpv * v + cpr * r))
    J = uP * U / (n * D)
    KT = 0.527 - 0.455 * J
    uR = uP * epsilon * math.sqrt(1.0 + 8.0 * kk * KT / (math.pi * J**2))
    alphaR = delta + math.atan(vR / uR)
    FN = -((6.13 * Delta) / (Delta + 2.25)) * (AR / L**2) * (uR**2 + vR**2) * math.sin(alphaR)
    T = 2.0 * rho * D**4 / (U**2 * L**2 * rho) * KT * n * abs(n)

    X = (
        Xuu * u**2 + (1.0 - t) * T + Xvr * v * r + Xvv * v**2 + Xrr * r**2 + Xphiphi * phi**2
        + cRX * FN * math.sin(delta) + (m + my) * v * r
    )
    Y = (
        Yv * v + Yr * r + Yp * p + Yphi * phi + Yvvv * v**3 + Yrrr * r**3 + Yvvr * v**2 * r
        + Yvrr * v * r**2 + Yvvphi * v**2 * phi + Yvphiphi * v * phi**2 + Yrrphi * r**2 * phi
        + Yrphiphi * r * phi**2 + (1.0 + aH) * FN * math.cos(delta) - (m + mx) * u * r
    )
    K = (
        Kv * v + Kr * r + Kp * p + Kphi * phi + Kvvv * v**3 + Krrr * r**3 + Kvvr * v**2 * r
        + Kvrr * v * r**2 + Kvvphi * v**2 * phi + Kvphiphi * v * phi**2 + Krrphi * r**2 * phi
        + Krphiphi * r * phi**2 - (1.0 + aH) * zR * FN * math.cos(delta) + mx * lx * u * r - W * GM * phi
    )
    N = (
        Nv * v + Nr * r + Np * p + Nphi * phi + Nvvv * v**3 + Nrrr * r**3 + Nvvr * v**2 * r
        + Nvrr * v * r**2 + Nvvphi * v**2 * phi + Nvphiphi * v * phi**2 + Nrrphi * r**2 * phi
        + Nrphiphi * r * phi**2 + (xR + aH * xH) * FN * math.cos(delta)
    )

    detM = m22 * m33 * m44 - m32**2 * m44 - m42**2 * m33
    xdot = np.array(
        [
            X * (U**2 / L) / m11,
            -((-m33 * m44 * Y + m32 * m44 * K + m42 * m33 * N) / detM) * (U**2 / L),
            ((-m42 * m33 * Y + m32 * m42 * K + N * m22 * m33 - N * m32**2) / detM) * (U**2 / L**2),
            (math.cos(psi) * u - math.sin(psi) * math.cos(phi) * v) * U,
            (math.sin(psi) * u + math.cos(psi) * math.cos(phi) * v) * U,
            math.cos(phi) * r * (U / L),
            ((-m32 * m44 * Y + K * m22 * m44 - K * m42**2 + m32 * m42 * N) / detM) * (U**2 / L**2),
            p * (U / L),
            delta_dot,
            n_dot,
        ]
    )
    return xdot, U


def rk4(x, ui, dt, delta_max_deg=10.0):
    """One classical Runge-Kutta step of container.m with the input held over the step."""
    k1, _ = container_rhs(x, ui, delta_max_deg)
    k2, _ = container_rhs(x + 0.5 * dt * k1, ui, delta_max_deg)
    k3, _ = container_rhs(x + 0.5 * dt * k2, ui, delta_max_deg)
    k4, _ = container_rhs(x + dt * k3, ui, delta_max_deg)
    return x + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
