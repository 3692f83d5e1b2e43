"""What a simulation's vessels read out: the named quantities of the state (speeds, heading, rudder, shaft),
the forces, the engine's and the bridge's instruments, and why a vessel stopped integrating.

A mixin of :class:`~vessel_gym.physics.simulation.Simulation`: it reads the simulation's rows ``state``
(N, NX), ``inputs`` (N, NU) and ``env`` (N, NE) of ``n`` vessels indexed by ``ship_index`` into the parameter
rows ``Ps``; it never writes them.
"""

from __future__ import annotations

import math

import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.bridge import BridgeReading
from vessel_gym.physics.environment import wrap_deg
from vessel_gym.physics.geodesy import local_to_latlon
from vessel_gym.physics.integrate import forces_batch
from vessel_gym.physics.kinematics import ground_velocity, speed_over_ground
from vessel_gym.physics.params import ENGINE, PROPELLER, ROLL
from vessel_gym.physics.runaway import (
    RUNAWAY_HEEL,
    RUNAWAY_HEEL_DEG,
    RUNAWAY_OK,
    RUNAWAY_RATE,
    RUNAWAY_RATE_PRIME,
    RUNAWAY_SHAFT,
    RUNAWAY_SHAFT_FACTOR,
    RUNAWAY_SPEED,
    RUNAWAY_SPEED_FACTOR,
)
from vessel_gym.physics.units import DEG, KNOT_M_S
from vessel_gym.physics.vessel import FORCE_NAMES, N_OUT, forces


class Readings:
    """Named quantities and instrument readings of a batch of vessels (see the module docstring)."""

    n: int
    t: float
    state: np.ndarray
    inputs: np.ndarray
    env: np.ndarray
    Ps: np.ndarray
    ship_index: np.ndarray
    alive: np.ndarray
    why_dead: np.ndarray
    environments: list
    reference_latlon_deg: tuple[float, float]
    _runaway_limits: np.ndarray
    _batch: object
    component_states: np.ndarray

    # --- named quantities (tasks ask these, never index raw state) ----------------------------------------
    @property
    def u(self) -> np.ndarray:
        """Surge velocity through the water, m/s."""
        return self.state[:, lo.X_U]

    @property
    def v(self) -> np.ndarray:
        """Sway velocity through the water at midship, m/s (positive starboard)."""
        return self.state[:, lo.X_V]

    @property
    def r(self) -> np.ndarray:
        """Yaw rate, rad/s (positive to starboard)."""
        return self.state[:, lo.X_R]

    @property
    def north(self) -> np.ndarray:
        return self.state[:, lo.X_N]

    @property
    def east(self) -> np.ndarray:
        return self.state[:, lo.X_E]

    @property
    def heading(self) -> np.ndarray:
        """Heading, rad, unwrapped (continuous through a turn)."""
        return self.state[:, lo.X_PSI]

    @property
    def rudder(self) -> np.ndarray:
        """Actual rudder angle, rad."""
        return self.state[:, lo.X_DELTA]

    @property
    def rudder_order(self) -> np.ndarray:
        return self.inputs[:, lo.U_DELTA_C]

    @property
    def rev(self) -> np.ndarray:
        """Propeller shaft speed, rev/s."""
        return self.state[:, lo.X_REV]

    @property
    def rev_order(self) -> np.ndarray:
        return self.inputs[:, lo.U_REV_C]

    @property
    def speed_through_water(self) -> np.ndarray:
        return np.hypot(self.u, self.v)

    def ground_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        """Velocity over ground (north, east), m/s."""
        psi = self.heading
        return ground_velocity(
            self.u, self.v, np.cos(psi), np.sin(psi), self.env[:, lo.E_CUR_N], self.env[:, lo.E_CUR_E]
        )

    def forces(self) -> dict[str, np.ndarray]:
        """Component forces at the current state (N, N m; see vessel.FORCE_NAMES)."""
        out = np.zeros((self.n, N_OUT))
        forces_batch(self.Ps, self.ship_index, self.state, self.inputs, self.env, out)
        return {name: out[:, i] for i, name in enumerate(FORCE_NAMES)}

    def engine(self, k: int = 0) -> dict[str, float]:
        """Engine readings of vessel k: fuel index, engine rpm, torque (N m), shaft power (kW). With a user's
        engine: its torque at the propeller shaft and the power, fuel index and engine rpm NaN (its own)."""
        from vessel_gym.physics.propulsion import engine_drive

        P = self.Ps[self.ship_index[k]]
        if P[PROPELLER.on] == 0.0:
            return {"fuel_index": 0.0, "engine_rpm": 0.0, "torque_Nm": 0.0, "power_kW": 0.0}
        x = self.state[k]
        if P[ENGINE.by_component] > 0.0:  # a user's engine: its torque at the propeller shaft; its fuel unknown here
            q = float(self._batch.shaft_torque(self, self.state, self.component_states)[k])
            return {
                "fuel_index": math.nan,
                "engine_rpm": math.nan,
                "torque_Nm": q,
                "power_kW": 2 * math.pi * x[lo.X_REV] * q / 1e3,
            }
        order = self.rev_order[k]
        _qd, _dc, _di, fuel, n_e, q, _ph = engine_drive(P, x[lo.X_REV], x[lo.X_CAM], x[lo.X_GOV], order)
        return {
            "fuel_index": fuel,
            "engine_rpm": n_e * 60.0,
            "torque_Nm": q,
            "power_kW": 2 * math.pi * n_e * q / 1e3,
        }

    def bridge(self, k: int = 0, telegraph: int = 0) -> BridgeReading:
        """Instrument readings of vessel k (Bridge & Navigation)."""
        out = np.zeros(N_OUT)
        forces(self.Ps[self.ship_index[k]], self.state[k], self.inputs[k], self.env[k], out)  # vessel k only
        f = {"gamma_rw": out[FORCE_NAMES.index("gamma_rw")], "V_rw": out[FORCE_NAMES.index("V_rw")]}
        psi, u, v = float(self.heading[k]), float(self.u[k]), float(self.v[k])
        cur_n, cur_e = float(self.env[k, lo.E_CUR_N]), float(self.env[k, lo.E_CUR_E])
        vn, ve = ground_velocity(u, v, math.cos(psi), math.sin(psi), cur_n, cur_e)
        lat, lon = local_to_latlon(self.north[k], self.east[k], *self.reference_latlon_deg)
        e = self.environments[k]
        x = self.state[k]
        has_roll = self.Ps[self.ship_index[k]][ROLL.on] > 0.0
        return BridgeReading(
            t_s=self.t,
            x_m=float(self.north[k]),
            y_m=float(self.east[k]),
            lat_deg=lat,
            lon_deg=lon,
            hdg_deg=wrap_deg(math.degrees(self.heading[k])),
            cog_deg=wrap_deg(math.degrees(math.atan2(ve, vn))),
            sog_kn=float(speed_over_ground(vn, ve) / KNOT_M_S),
            stw_kn=float(self.u[k] / KNOT_M_S),
            stw_transverse_kn=float(self.v[k] / KNOT_M_S),
            rot_dpm=float(math.degrees(self.r[k]) * 60.0),
            rudder_deg=float(math.degrees(self.rudder[k])),
            rudder_order_deg=float(math.degrees(self.rudder_order[k])),
            rpm=float(self.rev[k] * 60.0),
            telegraph=int(telegraph),
            wind_rel_angle_deg=wrap_deg(math.degrees(f["gamma_rw"])),
            wind_rel_speed_kn=float(f["V_rw"] / KNOT_M_S),
            wind_true_dir_deg=wrap_deg(e.wind_from_deg),
            wind_true_speed_kn=e.wind_speed_m_s / KNOT_M_S,
            roll_deg=float(math.degrees(x[lo.X_PHI])) if has_roll else None,
            roll_rate_dps=float(math.degrees(x[lo.X_P])) if has_roll else None,
        )

    def divergence(self, k: int = 0) -> str | None:
        """Why vessel k stopped integrating, as one sentence with the value and its bound, or None while it
        runs: a non-finite state, or a physically impossible speed, rate of turn or shaft speed."""
        code = int(self.why_dead[k])
        if self.alive[k] and code == RUNAWAY_OK:
            return None
        U_max, r_max, n_max = self._runaway_limits[self.ship_index[k]]
        x = self.state[k]
        if code == RUNAWAY_SPEED:
            return (
                f"speed through the water {math.hypot(x[lo.X_U], x[lo.X_V]) / KNOT_M_S:.4g} kn exceeds "
                f"{U_max / KNOT_M_S:.4g} kn ({RUNAWAY_SPEED_FACTOR:g} x the speed at full power)"
            )
        if code == RUNAWAY_RATE:
            return (
                f"rate of turn {abs(x[lo.X_R]) / DEG:.4g} deg/s exceeds {r_max / DEG:.4g} deg/s "
                f"(r' = {RUNAWAY_RATE_PRIME:g} at the speed at full power)"
            )
        if code == RUNAWAY_SHAFT:
            return (
                f"shaft speed {abs(x[lo.X_REV]) * 60.0:.4g} rpm exceeds {n_max * 60.0:.4g} rpm "
                f"({RUNAWAY_SHAFT_FACTOR:g} x rated)"
            )
        if code == RUNAWAY_HEEL:
            return f"heel {abs(x[lo.X_PHI]) / DEG:.4g} deg exceeds {RUNAWAY_HEEL_DEG:g} deg, the roll model's end"
        return "the state became non-finite"
