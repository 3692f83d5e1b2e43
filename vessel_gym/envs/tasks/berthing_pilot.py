"""The Berthing task's classical pilot: a dynamic-positioning style controller on surge, sway and yaw.

It works from the observation only (the berth-frame errors and velocities over ground, the rate of turn) and
from the ship's particulars and actuators as a pilot knows them (mass, PIANC added mass, thruster and tug
positions and ratings, the engine's dead-slow speed). Two legs, as berthing is taught (e.g. PIANC WG33 2002
section 4.2.3 on approach velocities; Hensen 2003 on the approach to a berth):

1. to the approach point, ``approach_offset_L`` ship lengths off the berth, square to the quay: a speed over
   ground that falls with the distance to go as a constant deceleration would, sqrt(2 a d), at most
   ``approach_speed_m_s``; heading along the track while far, turning parallel to the quay over the last
   ship lengths;
2. from the approach point sideways onto the fenders: a lateral speed that falls with the distance off,
   ``lateral_gain`` x distance, between ``lateral_speed_m_s`` and ``contact_speed_m_s`` (below the PIANC
   design velocity of the ship's displacement), holding the place along the quay and the berth's heading;
   alongside, a small push keeps the ship on the fenders.

A ship on tugs (``stop_first``) is berthed as a VLCC is: no sway control while it makes way, stopped and
parallel at the approach point, then sideways at most 0.1 m/s, falling linearly from one beam off to half the
PIANC velocity at first contact.

The controller: desired body-frame velocities over ground (u_d, v_d) and a heading reference; PI on the
velocity errors times the ship's surge and sway masses (with added mass), PD on heading through a rate
reference and the yaw inertia; the force demands are allocated to the engine (surge: ahead / astern, dead
slow as its least step, stop below half of that), and to the thrusters or tugs (sway and yaw, the two-unit
solution of Y = sum F_j, N = sum x_j F_j); the rudder steers while the ship has way on.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from vessel_gym.envs.policies import HelmPolicy
from vessel_gym.physics.components.azimuth import AzimuthThruster
from vessel_gym.physics.components.fenders import added_mass_coefficient
from vessel_gym.physics.components.thrusters import TunnelThruster


class BerthingPilot(HelmPolicy):
    """DP-style berthing pilot (module docstring); ``__call__(obs)`` -> action, rows of a batch kept apart."""

    def __init__(
        self,
        env: Any,
        approach_speed_m_s: float = 1.5,
        decel_m_s2: float = 0.004,
        lateral_speed_m_s: float = 0.25,
        lateral_gain: float = 0.01,
        contact_speed_m_s: float = 0.04,
        press_fraction: float = 0.05,
        stop_first: bool | None = None,
    ) -> None:
        super().__init__(env)
        task = env.unwrapped.task
        pt = task.ship.particulars
        m = task.ship.mass_kg
        self.M_u = 1.1 * m  # kg: surge mass with a typical 10 % added mass
        self.M_v = added_mass_coefficient(pt.T_m, pt.B_m) * m  # kg: PIANC's sway mass
        self.I_z = 1.2 * m * (0.25 * pt.L_m) ** 2  # kg m^2: k_zz = 0.25 L, 20 % added inertia
        self.off_A = task.config.approach_offset_L * pt.L_m  # m
        self.V_max, self.a, self.V_lat, self.k_lat = (
            approach_speed_m_s,
            decel_m_s2,
            lateral_speed_m_s,
            lateral_gain,
        )
        self.V_c = contact_speed_m_s
        # the water side of the berth seen from the berthed heading: +1 starboard (port side to the quay)
        self.s_w = 1.0 if task.berth.side == "port" else -1.0
        # lateral units: position, largest side force, thruster (o|o|) or tug (linear)
        self.units = []
        lag = 0.0
        for c in task.assist:
            lag = max(lag, c.params.time_constant_s)
            if isinstance(c, TunnelThruster):
                self.units.append((c.params.x_m, c.T_max, True))
            elif isinstance(c, AzimuthThruster):
                # athwartships ('side' order): thrust ~ rpm^2, as a tunnel thruster's
                self.units.append((c.params.x_m, (1.0 - c.params.thrust_deduction) * c.T_max, True))
            else:
                self.units.append((c.params.x_m, c.F_max * c.direction[1], False))
        #: sway and yaw loop time constant, s: ten seconds, or twice the lag of the slowest thruster or tug
        self.T_lat = max(10.0, 2.0 * lag)
        # the yaw rate it asks for: at most what half the units' yaw moment holds against the yaw damping
        N_max = sum(abs(u[0] * u[1]) for u in self.units)
        self.r_max = min(0.01, 0.5 * N_max / (self.I_z / 12.0)) if self.units else 0.01
        prop = task.ship.propeller
        rho = pt.rho_kg_m3
        self.K_prop = rho * prop.D_m**4 * prop.k_0 * (1.0 - prop.t_P) if prop is not None else 1e3  # N s^2
        rt = task.helm.rev_table[0]
        self.n_ahead, self.n_astern, self.n_slow = float(rt[8]), float(-rt[0]), float(rt[5])  # rev/s
        # the deceleration of the speed profile: at most what dead slow astern gives the ship (about 60 % of the
        # ahead thrust at that rpm)
        self.a = min(self.a, 0.6 * self.K_prop * self.n_slow**2 / self.M_u)
        self.a_lat = 0.3 * sum(abs(u[1]) for u in self.units) / self.M_v if self.units else 0.0  # m/s^2
        # the sideways leg's top speed: at most half of what a_lat reaches over the approach offset
        self.V_lat = min(self.V_lat, 0.5 * math.sqrt(self.a_lat * self.off_A))
        # touch at no more than half the PIANC design velocity of the task
        self.V_c = min(self.V_c, 0.5 * task.v_limit)
        self.press = press_fraction * sum(abs(u[1]) for u in self.units) / max(len(self.units), 1)
        #: stop at the approach point before going sideways (default: when the lateral units are tugs, as a
        #: VLCC berths): arrive there below a tenth of the sideways speed, no sway control while under way
        #: (tugs cannot push a ship making way), and the sideways leg at most 0.1 m/s
        tugs = any(not u[2] for u in self.units)
        self.stop_first = tugs if stop_first is None else stop_first
        self.arrive = 0.25
        if self.stop_first:
            self.V_lat = min(self.V_lat, 0.1)
            # the sideways speed falls linearly from V_lat one beam off to the contact speed
            self.k_lat = min(self.k_lat, self.V_lat / pt.B_m)
            self.arrive = 0.01
            # the yaw rate: what half the units' moment reaches in two loop times (a ship at rest has little
            # yaw damping)
            self.r_max = min(0.01, 0.5 * N_max / self.I_z * 2.0 * self.T_lat) if self.units else 0.01
        self.final: np.ndarray | bool = False
        self.I = np.zeros(3)

    def reset(self, mask: np.ndarray | None = None) -> None:
        if mask is None:
            self.final = False
            self.I = np.zeros(3)
        else:
            self.final = np.where(mask, False, self.final)
            self.I = np.where(np.asarray(mask)[..., None], 0.0, self.I)

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        g = lambda name: np.asarray(self.get(obs, name), dtype=float)  # noqa: E731
        ea, eo, h, va, vo, r = (
            g("along_error"),
            g("off_error"),
            g("berth_heading_error"),
            g("vg_along"),
            g("vg_off"),
            g("r"),
        )
        L, dt = self.L, self.dt
        sog = np.hypot(va, vo)
        final = self.final | (
            (np.abs(ea) < 0.1 * L)
            & (np.abs(eo - self.off_A) < 0.1 * L)
            & (np.abs(h) < 0.1)
            & (sog < self.arrive)
        )
        self.final = final
        # desired ground velocity in the berth frame (along, off)
        to = np.where(final, 0.0, self.off_A)
        da, do = ea, eo - to
        dist = np.maximum(np.hypot(da, do), 1e-6)
        V = np.minimum(self.V_max, np.sqrt(2.0 * self.a * dist))
        va_d = np.where(final, -np.clip(0.03 * ea, -0.15, 0.15), -V * da / dist)
        # the lateral speed falls with the distance off, and no faster than a third of the units' side force
        # can take off (a_lat), to the contact speed
        lateral = np.minimum(self.k_lat * eo, np.sqrt(self.a_lat * np.maximum(eo, 0.0)))
        lateral = np.clip(lateral + self.V_c, self.V_c, self.V_lat)
        touching = eo <= 0.02
        vo_d = np.where(final, np.where(touching, 0.0, -lateral), -V * do / dist)
        # heading reference, relative to the berth's: along the track while far, parallel by one length off
        chi = np.arctan2(self.s_w * vo_d, va_d)
        w = np.where(final, 0.0, np.clip((dist - L) / L, 0.0, 1.0))
        h_d = w * chi
        # body-frame desired and actual velocities over ground
        c, s = np.cos(h), np.sin(h)
        x_d, y_d = va_d, self.s_w * vo_d
        u_d, v_d = c * x_d + s * y_d, -s * x_d + c * y_d
        x_g, y_g = va, self.s_w * vo
        u_g, v_g = c * x_g + s * y_g, -s * x_g + c * y_g
        if self.stop_first:
            # sideways no faster than half the units' side force can take off over the distance to go, and
            # no sway control while the ship makes way (above about 1 kn)
            v_max = np.minimum(np.sqrt(self.a_lat * dist), 2.0 * self.V_lat)
            v_d = np.where(final, v_d, np.where(sog < 0.5, np.clip(v_d, -v_max, v_max), v_g))
        e_h = (h - h_d + math.pi) % (2.0 * math.pi) - math.pi
        # heading loop: a third as fast as the rate loop under it when the units are slow (tugs)
        k_h = 1.0 / (3.0 * self.T_lat) if self.stop_first else 5.0 * self.r_max  # 1/s
        r_d = np.clip(-k_h * e_h, -self.r_max, self.r_max)
        err = np.stack([u_d - u_g, v_d - v_g, r_d - r], axis=-1)
        gains = np.array([1.0 / 30.0, 1.0 / self.T_lat, 1.0 / self.T_lat])
        inertia = np.array([self.M_u, self.M_v, self.I_z])
        # damping feed-forward: the free-decay time constants of a ship of this kind (surge, sway, yaw)
        damping = inertia / np.array([90.0, 45.0, 12.0])
        if self.stop_first:
            # stopped off the berth the hull's sway and yaw damping is quadratic cross-flow drag, tens of kN at
            # 0.1 m/s for a VLCC against the 45 s linear decay's MN: the PI terms carry it
            damping = damping * np.array([1.0, 0.0, 0.0])
        limit = np.array([0.3, 0.3, 0.3]) * np.array(
            [self.K_prop * self.n_slow**2, self.press / 0.05, self.press * L]
        )
        self.I = np.clip(self.I + inertia * gains**2 * 0.5 * err * dt, -limit, limit)
        F = inertia * gains * err + self.I + damping * np.stack([u_d, v_d, r_d], axis=-1)
        X, Y, N = F[..., 0], F[..., 1], F[..., 2]
        Y = Y + np.where(final & touching, -self.s_w * self.press, 0.0)
        # engine: surge force from the propeller, thrust K n^2 (astern about 60 % of it); dead slow its least
        n = np.sqrt(np.abs(X) / (self.K_prop * np.where(X >= 0.0, 1.0, 0.6)))
        slow = np.abs(X) > 0.5 * self.K_prop * self.n_slow**2
        n = np.where(n >= self.n_slow, n, np.where(slow, self.n_slow, 0.0))
        engine = np.where(X >= 0.0, n / self.n_ahead, -n / self.n_astern)
        # lateral units: side force and yaw moment
        orders = []
        if len(self.units) >= 2:
            (x1, F1, t1), (x2, F2, t2) = self.units[0], self.units[1]
            Y1 = (N - x2 * Y) / (x1 - x2)
            Y2 = Y - Y1
            for Yj, Fj, tj in ((Y1, F1, t1), (Y2, F2, t2)):
                f = np.clip(Yj / Fj, -1.0, 1.0)
                orders.append(np.sign(f) * np.sqrt(np.abs(f)) if tj else f)
            orders += [np.zeros_like(X)] * (len(self.units) - 2)
        elif self.units:
            x1, F1, t1 = self.units[0]
            f = np.clip(Y / F1, -1.0, 1.0)
            orders.append(np.sign(f) * np.sqrt(np.abs(f)) if t1 else f)
        # rudder: steers with way on
        way = np.clip((u_g - 0.3) / 0.5, 0.0, 1.0)
        rudder = way * np.clip(-1.5 * e_h - 20.0 * r, -self.rudder_limit_rad, self.rudder_limit_rad)
        cols = [np.clip(rudder / self.rudder_limit_rad, -1.0, 1.0), np.clip(engine, -1.0, 1.0)] + orders
        return np.stack(cols, axis=-1).astype(np.float32)
