"""Array layouts shared by the compiled kernels and the Python side.

Every vessel in a batch is described by three rows:

* a **state** row ``x`` (integrated),
* an **input** row (helm: rudder order, shaft-speed order),
* an **environment** row (wind, current, waves, air density as seen by that vessel),

plus a **parameter** row ``P`` packed from its ship file (:func:`vessel_gym.physics.vessel.pack`).
The indices below are module-level integer constants so that numba folds them at compile time.
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
# [roll] table (P_ROLL_ON), held at exactly 0 on a 3-DOF ship (roll.py)
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
F_Q_SHAFT = 3  # drive torque at the propeller shaft of a user's engine, N m (read where P_ENGINE_EXT)
F_DELTA_RATE = 4  # rudder rate of a user's steering gear, rad/s (read where P_SG_EXT)
NF = 5

# --- parameter row P[k, :] -------------------------------------------------------------------------------------
# Filled by vessel.pack(); names follow the literature. Grouped by component.
_names: list[str] = []


def _field(name: str, size: int = 1) -> int:
    i = len(_names)
    _names.extend([name] if size == 1 else [f"{name}[{j}]" for j in range(size)])
    return i


# particulars and rigid body
P_L = _field("L")  # length between perpendiculars, m
P_B = _field("B")  # beam, m
P_T = _field("T")  # mean draught, m
P_RHO = _field("rho")  # water density, kg/m^3
P_MASS = _field("m")  # mass, kg
P_XG = _field("x_G")  # centre of gravity forward of the origin, m
# mass matrix (rigid body + added mass), inverted once at pack time; M = [[m11,0,0],[0,m22,m23],[0,m32,m33]]
P_M11 = _field("m11")
P_MI22 = _field("Minv22")
P_MI23 = _field("Minv23")
P_MI32 = _field("Minv32")
P_MI33 = _field("Minv33")
# Coriolis/centripetal coefficients on the right-hand side:  X += CX_VR v r + CX_RR r^2 ; Y -= CY_UR u r ; N -= CN_UR u r
P_CX_VR = _field("CX_vr")
P_CX_RR = _field("CX_rr")
P_CY_UR = _field("CY_ur")
P_CN_UR = _field("CN_ur")

# hull model selector and common hull parameters
HULL_NONE = 0  # no built-in hull forces (a user hull is plugged in from Python)
HULL_ABKOWITZ = 1
HULL_MMG = 2
P_HULL_KIND = _field("hull_kind")
P_HULL_FNORM = _field("hull_force_norm")  # 1/2 (SNAME prime) or 1 (seed eq. 5-6), times rho
P_HULL_UREF = _field("U_ref")  # Abkowitz reference speed for u-perturbation terms, m/s (0: u' = u/U)
P_HULL_RES = _field("R_res")  # Abkowitz added resistance coefficient R/u|u|, N s^2/m^2
P_HULL_CD = _field("cross_flow_Cd")  # 2-D cross-flow drag coefficient of the hull sections, -
P_RP_MAX = _field("r_prime_max")  # clip of r' in nonlinear terms at low speed, - (see hull.py)
P_U_MIN = _field("U_min")  # speed below which nondimensional hull terms are faded out, m/s

# Abkowitz polynomial terms merged by monomial u'^e_u v'^e_v r'^e_r delta^e_d: a count and MAX_MONOMIALS x
# (e_u, e_v, e_r, e_d, c_X, c_Y, c_N), so that a monomial shared by X, Y and N (e.g. Y_vvr, N_vvr) is
# evaluated once; a coefficient is 0 where the equation has no such term
MAX_MONOMIALS = 80
ABK_STRIDE = 7
P_ABK_NM = _field("abk_n_monomials")
P_ABK_M = _field("abk_monomials", ABK_STRIDE * MAX_MONOMIALS)

# MMG hull (Yasukawa & Yoshimura 2015, eq. 8-10), nondimensional on 1/2 rho L d U^2 (1/2 rho L^2 d U^2 for N)
P_MMG_R0 = _field("R_0")
P_MMG_XVV = _field("X_vv")
P_MMG_XVR = _field("X_vr")
P_MMG_XRR = _field("X_rr")
P_MMG_XVVVV = _field("X_vvvv")
P_MMG_YV = _field("Y_v")
P_MMG_YR = _field("Y_r")
P_MMG_YVVV = _field("Y_vvv")
P_MMG_YVVR = _field("Y_vvr")
P_MMG_YVRR = _field("Y_vrr")
P_MMG_YRRR = _field("Y_rrr")
P_MMG_NV = _field("N_v")
P_MMG_NR = _field("N_r")
P_MMG_NVVV = _field("N_vvv")
P_MMG_NVVR = _field("N_vvr")
P_MMG_NVRR = _field("N_vrr")
P_MMG_NRRR = _field("N_rrr")
# MMG hull at any drift angle (physics/crossflow.py, ship-file table [large_drift]): Yoshimura, Nakao &
# Ishibashi (2009) cross-flow model, blended with the polynomial above outside its fitted range; 0: off
P_XF_ON = _field("large_drift_on")
P_XF_CD = _field("C_D")  # cross-flow drag coefficient of the hull at 90 deg drift, on 1/2 rho L d, -
P_XF_CRY = _field("C_rY")  # yaw-rate factor of the cross flow in the sway force, -
P_XF_CRN = _field("C_rN")  # yaw-rate factor of the cross flow in the yaw moment, -
P_XF_R0A = _field("R_0_astern")  # straight-astern resistance coefficient, on 1/2 rho L d u^2, -
P_XF_BETA1 = _field("mmg_drift_max")  # flow angle up to which the MMG polynomial is used alone, rad
P_XF_BETA2 = _field("cross_flow_drift_min")  # flow angle from which the cross-flow model is used alone, rad
P_XF_RP1 = _field("mmg_r_prime_max")  # |r'| up to which the MMG polynomial is used alone, -
P_XF_RP2 = _field("cross_flow_r_prime_min")  # |r'| from which the cross-flow model is used alone, -
# the model's linear terms on 1/2 rho L d U^2 (L for N), filled by crossflow.pack: the MMG set's, or converted
# from an Abkowitz set; and the Coriolis terms an Abkowitz hull's equations leave to the hull forces
P_XF_R0 = _field("xf_R_0")  # straight-ahead resistance coefficient, -
P_XF_XVR = _field("xf_X_vr")
P_XF_YV = _field("xf_Y_v")
P_XF_YR = _field("xf_Y_r")
P_XF_NV = _field("xf_N_v")
P_XF_NR = _field("xf_N_r")
P_XF_CXRR = _field("xf_C_X_rr")  # x_G m r^2 surge term not in the equations of motion, kg m
P_XF_CNUR = _field("xf_C_N_ur")  # -x_G m u r yaw term not in the equations of motion, kg m
P_XF_UP1 = _field("polynomial_u_prime_max")  # |u'| up to which an Abkowitz polynomial is used alone, -
P_XF_UP2 = _field("cross_flow_u_prime_min")  # |u'| from which the cross-flow model is used alone, -
# bounds of the polynomial's range for the test without square root, atan2 or division
# (crossflow.inside_polynomial_range), each shortened by the factor 1 - 1e-9: tan(P_XF_BETA1), P_XF_RP1^2, P_XF_UP1^2
P_XF_TANB1 = _field("tan_mmg_drift_max")
P_XF_RP1_SQ = _field("mmg_r_prime_max_squared")
P_XF_UP1_SQ = _field("polynomial_u_prime_max_squared")

# propeller (open water K_T, K_Q quadratics in J; wake, thrust deduction; MMG wake change in manoeuvres)
P_PROP_ON = _field("has_propeller")
P_DP = _field("D_P")
P_KT0 = _field("k_0")
P_KT1 = _field("k_1")
P_KT2 = _field("k_2")
P_KQ0 = _field("q_0")
P_KQ1 = _field("q_1")
P_KQ2 = _field("q_2")
P_WP0 = _field("w_P0")
P_TP = _field("t_P")
P_XP = _field("x_P_prime")
P_C1 = _field("C_1")
P_C2P = _field("C_2_plus")
P_C2M = _field("C_2_minus")
P_AST_KT = _field("astern_kt_ratio")  # astern bollard K_T / ahead bollard K_T, -
P_AST_KQ = _field("astern_kq_ratio")  # astern bollard K_Q / ahead bollard K_Q, -
P_AST_SLOPE = _field("astern_inflow_slope")  # d(C_T*)/d(u_a/|n|D) in quadrant 4 relative to k_0, -
P_PROP_4Q = _field("four_quadrant")  # four-quadrant table code, propeller4q.TABLE_NAMES index + 1 (0: none)

# rudder
RUDDER_DERIVATIVES = 0  # rudder forces are in the hull derivatives (delta terms)
RUDDER_MMG = 1
P_RUD_KIND = _field("rudder_kind")
P_AR = _field("A_R")
P_HR = _field("H_R")
P_TR = _field("t_R")
P_AH = _field("a_H")
P_XHP = _field("x_H_prime")
P_XRP = _field("x_R_prime")
P_GRM = _field("gamma_R_minus")
P_GRP = _field("gamma_R_plus")
P_LRP = _field("l_R_prime")
P_EPS = _field("epsilon")
P_KAPPA = _field("kappa")
P_FALPHA = _field("f_alpha")
P_ETA = _field("eta")

# steering gear
P_DMAX = _field("delta_max")  # rad
P_DRATE = _field("delta_rate_max")  # rad/s
P_DTAU = _field("delta_time_constant")  # s

# transmission, engine, governor, shaft
P_GEAR = _field("gear_ratio")  # engine rev / propeller rev, -
P_ETA_GEAR = _field("eta_gear")  # transmission efficiency, -
P_I_SHAFT = _field("I_shaft")  # propeller + entrained water + shafting + i^2 engine inertia, kg m^2
P_Q_FRIC = _field("Q_friction")  # shaft friction torque at rated speed, N m (scaled linearly with speed)
P_ENG_NRATED = _field("n_e_rated")  # engine rated speed, rev/s
P_ENG_QRATED = _field("Q_e_rated")  # engine rated torque (MCR torque), N m
MAP_NS = 8  # engine torque map: speed breakpoints
MAP_NF = 6  # engine torque map: fuel-index breakpoints
P_MAP_S = _field("map_speed", MAP_NS)  # engine speed / rated, -
P_MAP_F = _field("map_fuel", MAP_NF)  # fuel index, -
P_MAP_Q = _field("map_torque", MAP_NS * MAP_NF)  # torque / rated torque, -, row-major [speed, fuel]
P_GOV_KP = _field("governor_Kp")  # fuel index per unit relative speed error, -
P_GOV_KI = _field("governor_Ki")  # fuel index per (unit relative speed error * s), 1/s
P_ENG_ASTERN = _field("astern_torque_ratio")  # astern torque / ahead torque, -
P_CLUTCH_MIN = _field("clutch_min_rev")  # |order| below this (rev/s of propeller) = clutch out

# windage (Blendermann 1994)
P_WIND_ON = _field("has_windage")
P_AFW = _field("A_FW")  # frontal projected area, m^2
P_ALW = _field("A_LW")  # lateral projected area, m^2
P_SL = _field("s_L")  # centre of lateral area forward of the origin, m
P_CDT = _field("CD_t")
P_CDL0 = _field("CD_l_AF_0")
P_CDLPI = _field("CD_l_AF_pi")
P_BDELTA = _field("blendermann_delta")
P_BKAPPA = _field("blendermann_kappa")

# mean wave drift: nondimensional X, Y, N coefficients tabulated over the encounter angle (seastate.py)
WAVE_NA = 73  # 0..360 deg in 5 deg steps
P_WAVE_ON = _field("has_wave_drift")
P_WAVE_TAB = _field("wave_drift_table", 3 * WAVE_NA)
# the forward-speed term of the same formula, per unit 2 omega_0 U / g (seastate.drift_speed_table)
P_WAVE_TAB_U = _field("wave_drift_speed_table", 3 * WAVE_NA)

# engine reversing (propulsion.py): a clutch/gearbox (or ideal) drive, or a direct-reversing two-stroke diesel
# started and braked on starting air
REVERSING_CLUTCH = 0
REVERSING_DIRECT_AIR = 1
P_REV_KIND = _field("reversing")
P_REV_TIME = _field("reversal_time")  # time to shift the reversing gear from one direction to the other, s
P_REV_AIR = _field("air_brake_rev")  # engine speed below which starting air may be applied, rev/s
P_REV_FIRE = _field("firing_rev")  # engine speed in the ordered direction at which fuel is admitted, rev/s
P_REV_QAIR = _field("Q_air")  # engine torque of the starting air, N m

# slots taken over by a user's component written in Python (components.compose): the built-in's equations
# stay in the kernel and read these flags (1: the component drives that part of the state)
P_ENGINE_EXT = _field("engine_by_component")  # shaft drive torque from F_ext[3]; governor, reversing gear held
P_SG_EXT = _field("steering_gear_by_component")  # rudder rate from the component, integrated by the method

# rudder of Son & Nomoto (1982) (sonnomoto.py): the flow angle at the rudder from a polynomial in v', r'
# (their eq. for v_R), the propeller race from momentum theory; A_R, a_H, x'_H, x'_R, epsilon, kappa and f_alpha
# are the MMG fields above
RUDDER_SON_NOMOTO = 2
P_SN_GAMMA = _field("gamma_R")  # flow-straightening factor of the sway velocity at the rudder, -
P_SN_CRR = _field("c_Rr")  # v'_R per r', -
P_SN_CRRRR = _field("c_Rrrr")  # v'_R per r'^3, -
P_SN_CRRRV = _field("c_Rrrv")  # v'_R per r'^2 v', -
P_SN_CRX = _field("c_RX")  # rudder drag X_R = c_RX F_N sin(delta), -
# propeller inflow of Son & Nomoto (1982): 1 - w = 1 - w_P0 + tau ((v' + x'_P r')^2 + c_pv v' + c_pr r')
WAKE_MMG = 0
WAKE_SON_NOMOTO = 1
P_WAKE_KIND = _field("wake_kind")
P_SN_TAU = _field("tau_P")  # -
P_SN_CPV = _field("c_pv")  # -
P_SN_CPR = _field("c_pr")  # -

# roll, the optional fourth degree of freedom (roll.py); every field 0 on a 3-DOF ship
P_ROLL_ON = _field("has_roll")
# inverse of the 3x3 mass matrix over (v, r, p) with rigid body and added mass, row-major (pack time)
P_ROLL_MINV = _field("roll_Minv", 9)
P_ROLL_GM = _field("rho_g_nabla_GM")  # hydrostatic restoring rho g nabla GM, N m/rad (times sin phi)
# righting-lever curve GZ(phi) where the ship file gives one (replaces GM sin phi): a count, the heel
# breakpoints (rad, from 0, increasing) and GZ there (m); the restoring is rho g nabla GZ(|phi|) sign(phi)
MAX_GZ_POINTS = 16
P_ROLL_MG = _field("rho_g_nabla")  # N
P_ROLL_GZ_N = _field("GZ_points")
P_ROLL_GZ_PHI = _field("GZ_heel", MAX_GZ_POINTS)
P_ROLL_GZ = _field("GZ", MAX_GZ_POINTS)
P_ROLL_KP1 = _field("K_p_linear")  # linear roll damping, N m s/rad
P_ROLL_KP2 = _field("K_p_quadratic")  # quadratic roll damping, N m s^2/rad^2
P_ROLL_ZR = _field("z_R")  # rudder's centre of effort below the roll axis (through G), m
# shaft torque reaction on the hull, K = P_ROLL_QSIGN Q_P: -1 right-handed propeller, +1 left-handed, 0 off
P_ROLL_QSIGN = _field("propeller_torque_sign")
# hull roll terms in the SNAME prime system (1/2 rho L^2 U^2, times L for K and N), merged by monomial
# u'^a v'^b r'^c p'^d phi^e: a count and MAX_ROLL_MONOMIALS x (a, b, c, d, e, c_X, c_Y, c_K, c_N)
MAX_ROLL_MONOMIALS = 40
ROLL_STRIDE = 9
P_ROLL_NM = _field("roll_n_monomials")
P_ROLL_M = _field("roll_monomials", ROLL_STRIDE * MAX_ROLL_MONOMIALS)

NP = len(_names)
PARAM_NAMES = tuple(_names)
