"""Bridge & Navigation: what an operator sees, in the units of the bridge.

The Bridge is the top-level part that turns simulation state into instrument readings (GNSS position,
gyro heading, log speed, rate-of-turn indicator, rudder angle indicator, tachometer, anemometer). Everything
downstream that shows the ship to a person (HUD, NMEA, JSON state, debrief) reads a :class:`BridgeReading`.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass


class Telegraph(enum.IntEnum):
    """Engine-order telegraph steps, full astern (-4) to full ahead (+4)."""

    FULL_ASTERN = -4
    HALF_ASTERN = -3
    SLOW_ASTERN = -2
    DEAD_SLOW_ASTERN = -1
    STOP = 0
    DEAD_SLOW_AHEAD = 1
    SLOW_AHEAD = 2
    HALF_AHEAD = 3
    FULL_AHEAD = 4


@dataclass(frozen=True)
class BridgeReading:
    """One ship's instrument readings at one instant (edge units: deg, kn, rpm, deg/min).

    Angles are true (from north, clockwise); ``rot_dpm`` > 0 and ``rudder_deg`` > 0 mean turning / rudder to
    starboard. Wind angles are relative to the bow (apparent) or to north (true), both "from".
    """

    t_s: float  # simulation time, s
    x_m: float  # north of the reference point, m
    y_m: float  # east of the reference point, m
    lat_deg: float  # WGS-84 latitude, deg (north positive)
    lon_deg: float  # WGS-84 longitude, deg (east positive)
    hdg_deg: float  # true heading, deg [0, 360)
    cog_deg: float  # course over ground, deg [0, 360)
    sog_kn: float  # speed over ground, kn
    stw_kn: float  # longitudinal speed through water, kn (negative astern)
    stw_transverse_kn: float  # transverse speed through water, kn (positive to starboard)
    rot_dpm: float  # rate of turn, deg/min (positive to starboard)
    rudder_deg: float  # actual rudder angle, deg (positive to starboard)
    rudder_order_deg: float  # rudder order, deg
    rpm: float  # propeller shaft speed, rev/min (negative astern)
    telegraph: int  # engine order, Telegraph step -4..4
    wind_rel_angle_deg: float  # apparent wind angle from the bow, deg [0, 360)
    wind_rel_speed_kn: float  # apparent wind speed, kn
    wind_true_dir_deg: float  # true wind direction (from), deg [0, 360)
    wind_true_speed_kn: float  # true wind speed, kn
    depth_m: float | None = None  # water depth under the keel reference, m (None: deep/unknown)
    # heel (roll) angle and roll rate, deg and deg/s, positive starboard side down / rolling to starboard;
    # None on a 3-DOF ship, which has no roll
    roll_deg: float | None = None
    roll_rate_dps: float | None = None
