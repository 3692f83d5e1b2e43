"""Runaway detection: a vessel whose state a ship cannot physically reach is stopped and flagged, with why."""

from __future__ import annotations

import math

from numba import njit

from vessel_gym.physics import layout as lo
from vessel_gym.physics.roll import HEEL_RANGE_DEG
from vessel_gym.physics.shipfile import Ship

# Runaway detection: a state a ship cannot physically reach means the model left its valid range, even when
# every number is finite. The IMO test speed is at least 90 % of the speed at 85 % MCR (MSC.137(76) §4.2.1),
# so by the cube law of power the speed at full power is U_full = U_test / 0.9 / 0.85^(1/3) = 1.172 U_test.
FULL_POWER_SPEED_FACTOR = 1.0 / (0.9 * 0.85 ** (1.0 / 3.0))  # U_full / U_test, -
RUNAWAY_SPEED_FACTOR = 3.0  # speed through the water / U_full, -
# rate of turn as r' = r L / U_full: a steady turn has r' = 2 L / D, about 0.7 for the KVLCC2 at 35 deg rudder
# (steady diameter about 3 L) and less at the reduced speed in the turn, so |r'| = 2 at full-power speed is
# beyond a ship under its own power or pushed by tugs
RUNAWAY_RATE_PRIME = 2.0  # -
# the governor holds rated speed, and the overspeed trip acts at no more than 1.2 x rated (IACS UR M3)
RUNAWAY_SHAFT_FACTOR = 1.5  # |shaft speed| / rated shaft speed, -
# heel of a 4-DOF ship beyond the roll model's range (roll.HEEL_RANGE_DEG): the run stops there rather than
# report a capsize the model cannot describe
RUNAWAY_HEEL_DEG = HEEL_RANGE_DEG  # deg
RUNAWAY_OK, RUNAWAY_NONFINITE, RUNAWAY_SPEED, RUNAWAY_RATE, RUNAWAY_SHAFT, RUNAWAY_HEEL = 0, 1, 2, 3, 4, 5
_HEEL_MAX = math.radians(RUNAWAY_HEEL_DEG)  # rad


@njit(cache=True)
def flag_runaway(X, ship_index, limits, alive, why):
    """Mark dead every alive vessel whose speed through the water, rate of turn, shaft speed or heel is beyond its
    ship's bounds ``limits[ship] = (U_max m/s, r_max rad/s, n_max rev/s)``, with the reason in ``why``
    (RUNAWAY_*); a vessel the integrator stopped on a non-finite state gets RUNAWAY_NONFINITE. The state is
    kept as it was when flagged. Returns the number of vessels alive."""
    count = 0
    for b in range(X.shape[0]):
        if not alive[b]:
            if why[b] == RUNAWAY_OK:
                why[b] = RUNAWAY_NONFINITE
            continue
        lim = limits[ship_index[b]]
        u = X[b, lo.X_U]
        v = X[b, lo.X_V]
        code = RUNAWAY_OK
        if u * u + v * v > lim[0] * lim[0]:
            code = RUNAWAY_SPEED
        elif abs(X[b, lo.X_R]) > lim[1]:
            code = RUNAWAY_RATE
        elif abs(X[b, lo.X_REV]) > lim[2]:
            code = RUNAWAY_SHAFT
        elif abs(X[b, lo.X_PHI]) > _HEEL_MAX:  # 0 on a 3-DOF ship
            code = RUNAWAY_HEEL
        why[b] = code
        if code == RUNAWAY_OK:
            count += 1
        else:
            alive[b] = False
    return count


def runaway_limits(ship: Ship) -> tuple[float, float, float]:
    """(U_max m/s, r_max rad/s, n_max rev/s) beyond which a vessel of ``ship`` is flagged as run away."""
    U_full = FULL_POWER_SPEED_FACTOR * ship.test_speed_m_s
    U_max = RUNAWAY_SPEED_FACTOR * U_full
    r_max = RUNAWAY_RATE_PRIME * U_full / ship.particulars.L_m
    n_max = math.inf
    if ship.engine is not None:
        gear = ship.transmission.gear_ratio if ship.transmission is not None else 1.0
        n_max = RUNAWAY_SHAFT_FACTOR * ship.engine.rated_rpm / gear / 60.0
    return U_max, r_max, n_max
