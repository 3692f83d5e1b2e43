"""Array layouts shared by the compiled kernels and the Python side.

Every vessel in a batch is described by three rows:

* a **state** row ``x`` (integrated),
* an **input** row (helm: rudder order, shaft-speed order),
* an **environment** row (wind, current, waves, air density as seen by that vessel),

plus a **parameter** row ``P`` packed from its ship file (:func:`vessel_gym.physics.vessel.pack`), made of one
named record per component kind (:mod:`vessel_gym.physics.params`). The indices below are module-level integer
constants so that numba folds them at compile time.
"""

from __future__ import annotations

# --- state x[k, :] -------------------------------------------------------------------------------------------
X_U = 0  # surge velocity through the water, m/s (body x, forward)
X_V = 1  # sway velocity through the water at the body origin (midship), m/s (body y, starboard)
X_R = 2  # yaw rate, rad/s (positive turning to starboard)
X_N = 3  # north position of the body origin, m (earth x)
X_E = 4  # east position of the body origin, m (earth y)
X_PSI = 5  # heading, rad (clockwise from north); not wrapped while integrating
X_DELTA = 6  # actual rudder angle, rad (positive to starboard)
X_REV = 7  # propeller shaft speed, rev/s (negative astern)
X_GOV = 8  # speed-governor integrator state, fuel-index units (-)
# position of a direct-reversing engine's reversing gear (fuel-pump cams and starting-air distributor), -:
# +1 set for ahead, -1 for astern, in between while shifting (propulsion.direct_reversing_drive); unused (0)
# by a clutch or ideal drive
X_CAM = 9
# the fourth degree of freedom, appended so that no column above moves; integrated only on a ship with a
# [roll] table (params.ROLL.on), held at exactly 0 on a 3-DOF ship (roll.py)
X_PHI = 10  # roll (heel) angle, rad (positive starboard side down)
X_P = 11  # roll rate, rad/s
NX = 12
NX_3DOF = X_PHI  # the states a 3-DOF kernel integrates (integrate.drivers): every column before the roll states

STATE_NAMES = ("u", "v", "r", "x", "y", "psi", "delta", "n", "governor", "reversing_gear", "phi", "p")

# --- input u[k, :] ---------------------------------------------------------------------------------------------
U_DELTA_C = 0  # rudder order, rad
U_REV_C = 1  # propeller shaft-speed order, rev/s (sign selects ahead/astern clutch; 0 = clutch out)
NU = 2

# --- environment e[k, :] ---------------------------------------------------------------------------------------
E_WIND_SPEED = 0  # true wind speed at 10 m, m/s
E_WIND_FROM = 1  # true wind direction, rad, meteorological "from", clockwise from north
E_CUR_SPEED = 2  # current speed, m/s
E_CUR_TO = 3  # current direction, rad, oceanographic "towards", clockwise from north
E_RHO_AIR = 4  # air density, kg/m^3 (from pressure and temperature, see atmosphere.py)
E_HS = 5  # significant wave height, m (0: calm)
E_TP = 6  # peak period, s
E_WAVE_FROM = 7  # mean wave direction, rad, "from", clockwise from north
E_ZETA2 = 8  # effective squared wave amplitude for mean drift, m^2 (seastate.effective_zeta2)
# the same current and wind as velocity components, so that the kernels need no sin/cos of a constant direction
E_CUR_N = 9  # current velocity, north, m/s (seastate.current_earth)
E_CUR_E = 10  # current velocity, east, m/s
E_WIND_N = 11  # air velocity, north, m/s (atmosphere.air_velocity_earth: it blows towards wind_from + pi)
E_WIND_E = 12  # air velocity, east, m/s
# draught-to-depth ratio T/h of the water under the ship, -: 0 in deep water (infinite depth), the default, so
# that a row of zeros is deep water (shallow_water.py, environment.Environment.depth_m)
E_T_OVER_H = 13
E_OMEGA_ZETA2 = 14  # effective omega_0 zeta_a^2 of the sea for the forward-speed drift term, m^2 rad/s
NE = 15

# --- what a user's Python components give the kernel per vessel, F[k, :] -------------------------------------------
F_X = 0  # surge force at midship, N (their sum; F_ext's first three entries)
F_Y = 1  # sway force at midship, N
F_N = 2  # yaw moment about midship, N m
F_Q_SHAFT = 3  # drive torque at the propeller shaft of a user's engine, N m (read where params.ENGINE.by_component)
F_DELTA_RATE = 4  # rudder rate of a user's steering gear, rad/s (read where params.STEERING_GEAR.by_component)
NF = 5

# --- parameter row P[k, :] -------------------------------------------------------------------------------------
# The parameters are one named record per component kind (params.py: fields with units, offsets folded into the
# kernels as constants), filled by vessel.pack(). Here: the codes stored in the records' selector fields and the
# sizes of their tables.

# params.HULL.kind
HULL_NONE = 0  # no built-in hull forces (a user hull is plugged in from Python)
HULL_ABKOWITZ = 1
HULL_MMG = 2
# params.ABKOWITZ.monomials: at most MAX_MONOMIALS rows of (e_u, e_v, e_r, e_d, c_X, c_Y, c_N)
MAX_MONOMIALS = 80
ABK_STRIDE = 7
# params.RUDDER.kind
RUDDER_DERIVATIVES = 0  # rudder forces are in the hull derivatives (delta terms)
RUDDER_MMG = 1
RUDDER_SON_NOMOTO = 2  # Son & Nomoto (1982), sonnomoto.py
# params.PROPELLER.wake_kind
WAKE_MMG = 0
WAKE_SON_NOMOTO = 1  # 1 - w = 1 - w_P0 + tau ((v' + x'_P r')^2 + c_pv v' + c_pr r'), Son & Nomoto (1982)
# params.ENGINE.map_*: the engine torque map's speed and fuel-index breakpoints
MAP_NS = 8
MAP_NF = 6
# params.WAVE_DRIFT tables: 0..360 deg in 5 deg steps
WAVE_NA = 73
# params.ENGINE.reversing: a clutch/gearbox (or ideal) drive, or a direct-reversing two-stroke diesel started
# and braked on starting air (propulsion.py)
REVERSING_CLUTCH = 0
REVERSING_DIRECT_AIR = 1
# params.ROLL: points of the righting-lever curve; monomial rows of (a, b, c, d, e, c_X, c_Y, c_K, c_N)
MAX_GZ_POINTS = 16
MAX_ROLL_MONOMIALS = 40
ROLL_STRIDE = 9
