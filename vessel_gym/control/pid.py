"""Classical heading autopilot: PID with gains from the ship's Nomoto model, and the rate-of-turn PI.

Pole placement on Nomoto's first-order model T r' + r = K delta (Fossen 2011, Handbook of Marine Craft
Hydrodynamics and Motion Control, §15.2.7 / eq. 15.110-15.112): with natural frequency omega_n and relative
damping zeta of the closed heading loop,

    K_p = T omega_n^2 / K,   K_d = (2 zeta omega_n T - 1) / K,   K_i = omega_n K_p / 10.

The default omega_n is a fraction of the ship's speed-scaled bandwidth: omega_n = 0.6 U / L rad/s (about one
heading oscillation in ten ship lengths), zeta = 0.9; both are arguments. For a course-unstable ship (T < 0)
the same formulas hold with the unstable pole placed by K_d.

The control law itself is one pair of scalar functions, :func:`pid_integral` and :func:`pid_rudder`
(compiled; ``*_batch`` are the same bodies as numpy ufuncs for batches of vessels). Every autopilot of the
project uses them: :class:`PidAutopilot` (traffic, the heading tests), the environments' baselines
(:class:`vessel_gym.envs.policies.PIDHeadingAutopilot`) and the turning-rate PI
(:class:`vessel_gym.policy.RatePI`, gains :func:`nomoto_rate_pi_gains`).
"""

from __future__ import annotations

import math
import types
from dataclasses import dataclass

from numba import njit, vectorize

from vessel_gym.control.angles import wrap_pi_upper
from vessel_gym.physics.linear import Nomoto, nomoto
from vessel_gym.physics.shipfile import Ship, load_ship


def _pid_integral(integral, e, dt_s, limit, integrate_below):
    """Integral of the error after one interval: e dt added while |e| < ``integrate_below`` (conditional
    integration, the anti-windup of Fossen 2011 §12.2.6), clamped to +-``limit``."""
    if abs(e) < integrate_below:
        return min(max(integral + e * dt_s, -limit), limit)
    return integral


def _pid_rudder(e, integral, r, K_p, K_i, K_d, max_rudder):
    """Rudder order delta = K_p e + K_i int e dt - K_d r, clipped to +-``max_rudder`` (rad).

    e = psi_ref - psi (rad; or a rate error for a PI on the rate of turn); the derivative acts on the
    measured yaw rate r (rad/s), so a set-point change gives no derivative kick.
    """
    d = K_p * e + K_i * integral - K_d * r
    return min(max(d, -max_rudder), max_rudder)


def _ufunc(f):
    """The body of ``f`` as a numpy ufunc, compiled on first use and cached on disk under its own name (numba
    files its cache by function name: the ufunc must not share the scalar version's entry)."""
    g = types.FunctionType(f.__code__, f.__globals__, f.__name__ + "_batch", f.__defaults__, f.__closure__)
    g.__qualname__ = f.__qualname__ + "_batch"
    g.__doc__ = f.__doc__
    return vectorize(cache=True)(g)


pid_integral = njit(cache=True)(_pid_integral)
pid_rudder = njit(cache=True)(_pid_rudder)
#: the same bodies as numpy ufuncs (broadcasting over a batch of vessels)
pid_integral_batch = _ufunc(_pid_integral)
pid_rudder_batch = _ufunc(_pid_rudder)


@dataclass(frozen=True)
class PidGains:
    K_p: float  # rad rudder per rad heading error, -
    K_i: float  # 1/s
    K_d: float  # s
    omega_n: float  # rad/s
    zeta: float  # -
    model: Nomoto


def nomoto_pid_gains(
    ship: str | Ship, speed_m_s: float | None = None, omega_n: float | None = None, zeta: float = 0.9
) -> PidGains:
    """PID gains by pole placement on the ship's first-order Nomoto model at ``speed_m_s``."""
    s = load_ship(ship)
    U = s.test_speed_m_s if speed_m_s is None else speed_m_s
    m = nomoto(s, U)
    wn = 0.6 * U / s.particulars.L_m if omega_n is None else omega_n
    Kp = m.T * wn * wn / m.K
    Kd = (2.0 * zeta * wn * m.T - 1.0) / m.K
    Ki = wn * Kp / 10.0
    return PidGains(Kp, Ki, Kd, wn, zeta, m)


def nomoto_rate_pi_gains(model: Nomoto, omega: float, zeta: float = 1.0) -> tuple[float, float]:
    """(K_p, K_i) of a PI on the rate-of-turn error e = r_c - r, by pole placement on Nomoto's model.

    T r' + r = K delta with delta = K_p e + K_i int e dt gives the closed loop
    T s^2 + (1 + K K_p) s + K K_i = 0; placing it at T (s^2 + 2 zeta omega s + omega^2) gives
    K_p = (2 zeta omega T - 1) / K (-) and K_i = omega^2 T / K (1/s), valid for course-unstable ships
    (T, K < 0) too. ``omega`` in rad/s.
    """
    return (2.0 * zeta * omega * model.T - 1.0) / model.K, omega * omega * model.T / model.K


class PidAutopilot:
    """Heading-hold / course-changing PID: rudder order (rad) from heading error and yaw rate.

    delta = -(K_p e + K_i int e dt + K_d r) with e = wrap(psi - psi_ref); the derivative acts on the measured
    yaw rate (no derivative kick on set-point changes). Anti-windup by conditional integration: the error is
    integrated only while |e| is below ``integrate_below_rad`` (a large course change is done by P and D; the
    integral trims the steady heading error of wind, current and hull asymmetry). ``integral`` is the
    integral of psi - psi_ref, rad s.
    """

    def __init__(
        self, gains: PidGains, max_rudder_rad: float, integrate_below_rad: float = math.radians(5.0)
    ):
        self.gains = gains
        self.max_rudder_rad = max_rudder_rad
        self.integrate_below_rad = integrate_below_rad
        self.integral = 0.0

    @classmethod
    def for_ship(cls, ship: str | Ship, speed_m_s: float | None = None, **kw) -> PidAutopilot:
        s = load_ship(ship)
        return cls(nomoto_pid_gains(s, speed_m_s, **kw), math.radians(s.steering_gear.max_angle_deg))

    def reset(self) -> None:
        self.integral = 0.0

    def order(self, heading_rad: float, yaw_rate_rad_s: float, heading_ref_rad: float, dt_s: float) -> float:
        g = self.gains
        e = wrap_pi_upper(heading_rad - heading_ref_rad)
        # the shared law takes e = psi_ref - psi: negation is exact, so this is the same arithmetic
        below = self.integrate_below_rad if g.K_i > 0.0 else 0.0
        lim = self.max_rudder_rad / g.K_i if g.K_i > 0.0 else 0.0
        self.integral = -pid_integral(-self.integral, -e, dt_s, lim, below)
        return pid_rudder(-e, -self.integral, yaw_rate_rad_s, g.K_p, g.K_i, g.K_d, self.max_rudder_rad)


__all__ = [
    "PidAutopilot",
    "PidGains",
    "nomoto_pid_gains",
    "nomoto_rate_pi_gains",
    "pid_integral",
    "pid_integral_batch",
    "pid_rudder",
    "pid_rudder_batch",
]
