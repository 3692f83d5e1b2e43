"""Classical heading autopilot: PID with gains from the ship's Nomoto model.

Pole placement on Nomoto's first-order model T r' + r = K delta (Fossen 2011, Handbook of Marine Craft
Hydrodynamics and Motion Control, §15.2.7 / eq. 15.110-15.112): with natural frequency omega_n and relative
damping zeta of the closed heading loop,

    K_p = T omega_n^2 / K,   K_d = (2 zeta omega_n T - 1) / K,   K_i = omega_n K_p / 10.

The default omega_n is a fraction of the ship's speed-scaled bandwidth: omega_n = 0.6 U / L rad/s (about one
heading oscillation in ten ship lengths), zeta = 0.9; both are arguments. For a course-unstable ship (T < 0)
the same formulas hold with the unstable pole placed by K_d.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from vessel_gym.physics.linear import Nomoto, nomoto
from vessel_gym.physics.shipfile import Ship, load_ship


def wrap_pi(angle_rad: float) -> float:
    """Angle in (-pi, pi]."""
    a = math.fmod(angle_rad + math.pi, 2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi


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


class PidAutopilot:
    """Heading-hold / course-changing PID: rudder order (rad) from heading error and yaw rate.

    delta = -(K_p e + K_i int e dt + K_d r) with e = wrap(psi - psi_ref); the derivative acts on the measured
    yaw rate (no derivative kick on set-point changes). Anti-windup by conditional integration: the error is
    integrated only while |e| is below ``integrate_below_rad`` (a large course change is done by P and D; the
    integral trims the steady heading error of wind, current and hull asymmetry).
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
        e = wrap_pi(heading_rad - heading_ref_rad)
        if g.K_i > 0.0 and abs(e) < self.integrate_below_rad:
            lim = self.max_rudder_rad / g.K_i
            self.integral = min(max(self.integral + e * dt_s, -lim), lim)
        delta = -(g.K_p * e + g.K_i * self.integral + g.K_d * yaw_rate_rad_s)
        return min(max(delta, -self.max_rudder_rad), self.max_rudder_rad)
