"""The ship file's tables of the built-in components: one frozen dataclass per table, each key a
``schema.param(unit=, lo=, hi=, doc=)``.

This is the one home of a built-in parameter's name, unit, range and meaning. The loader checks a ship file
against these dataclasses (:mod:`vessel_gym.physics.shipfile`), docs/ship-file.md lists them, and the compiled
model's record of each component kind is derived from them (:mod:`vessel_gym.physics.params`: every number key
of a table becomes a field of its record, under the key's name, with the key's unit and doc). The tables live in
a module of their own, importing only the schema, because :mod:`~vessel_gym.physics.params` is imported by every
equation module and the ship-file loader imports equation modules (their cross-key checks): the records can be
derived from the tables only if the tables sit below both.
"""

from __future__ import annotations

from dataclasses import dataclass

from vessel_gym.physics.propeller4q import TABLE_NAMES
from vessel_gym.physics.schema import param


@dataclass(frozen=True, kw_only=True)
class Particulars:
    L_m: float = param(unit="m", lo=1.0, hi=500.0, doc="length between perpendiculars")
    B_m: float = param(unit="m", lo=0.1, hi=100.0, doc="moulded beam")
    T_m: float = param(unit="m", lo=0.02, hi=40.0, doc="mean draught")
    test_speed_kn: float = param(
        unit="kn", lo=0.5, hi=50.0, doc="IMO MSC.137(76) test speed (approach speed)"
    )
    mass_kg: float | None = param(None, unit="kg", lo=1.0, hi=1e9, doc="mass (or give displacement_m3)")
    displacement_m3: float | None = param(
        None, unit="m^3", lo=1e-3, hi=1e6, doc="displaced volume (mass = rho * volume)"
    )
    x_G_m: float = param(0.0, unit="m", lo=-100.0, hi=100.0, doc="centre of gravity forward of midship")
    k_zz_m: float | None = param(None, unit="m", lo=0.01, hi=200.0, doc="yaw radius of gyration about G")
    I_zG_kgm2: float | None = param(
        None, unit="kg m^2", lo=1e-6, hi=1e14, doc="yaw moment of inertia about G (or k_zz_m)"
    )
    rho_kg_m3: float = param(1025.0, unit="kg/m^3", lo=990.0, hi=1035.0, doc="water density")
    C_b: float | None = param(None, unit="-", lo=0.3, hi=0.95, doc="block coefficient (informative)")
    origin: str = param("midship", choices=("midship",), doc="body-axes origin")



@dataclass(frozen=True, kw_only=True)
class AbkowitzHull:
    model: str = param(choices=("abkowitz",))
    normalisation: str = param(
        "half_rho_L2_U2",
        choices=("half_rho_L2_U2", "rho_L2_U2"),
        doc="prime system: forces / (1/2 rho L^2 U^2) (SNAME) or / (rho L^2 U^2) (seed eq. 5-6)",
    )
    U_ref_m_s: float = param(
        0.0,
        unit="m/s",
        lo=0.0,
        hi=30.0,
        doc="reference speed; > 0: u-terms use the perturbation (u - U_ref)/U",
    )
    coriolis: str = param(
        "separate",
        choices=("separate", "in_derivatives"),
        doc="'in_derivatives' when Y_r, N_r, X_vr already contain the rigid-body m u r terms",
    )
    resistance_N: float = param(
        0.0, unit="N", lo=0.0, hi=1e8, doc="resistance at resistance_speed_m_s, R = c u|u|"
    )
    resistance_speed_m_s: float = param(1.0, unit="m/s", lo=0.01, hi=30.0)
    cross_flow_Cd: float = param(
        0.0,
        unit="-",
        lo=0.0,
        hi=2.0,
        doc="2-D cross-flow drag coefficient (0: none); nonlinear sway-yaw damping",
    )
    r_prime_max: float = param(2.0, unit="-", lo=0.1, hi=10.0, doc="clip of r' in the polynomial (low speed)")
    U_min_m_s: float = param(0.05, unit="m/s", lo=1e-4, hi=2.0, doc="nondimensionalising speed floor")
    derivatives: dict = param(doc="named derivatives, e.g. Y_vvr = -0.379 (see docs/ship-file.md)")



@dataclass(frozen=True, kw_only=True)
class MMGHull:
    model: str = param(choices=("mmg",))
    m_x: float = param(unit="-", lo=0.0, hi=1.0, doc="surge added mass / (1/2 rho L^2 d)")
    m_y: float = param(unit="-", lo=0.0, hi=2.0, doc="sway added mass / (1/2 rho L^2 d)")
    J_z: float = param(unit="-", lo=0.0, hi=0.2, doc="yaw added inertia / (1/2 rho L^4 d)")
    R_0: float = param(unit="-", lo=0.0, hi=0.2)
    X_vv: float = param(unit="-", lo=-5, hi=5)
    X_vr: float = param(unit="-", lo=-5, hi=5)
    X_rr: float = param(unit="-", lo=-5, hi=5)
    X_vvvv: float = param(unit="-", lo=-10, hi=10)
    Y_v: float = param(unit="-", lo=-5, hi=0)
    Y_r: float = param(unit="-", lo=-5, hi=5)
    Y_vvv: float = param(unit="-", lo=-20, hi=20)
    Y_vvr: float = param(unit="-", lo=-20, hi=20)
    Y_vrr: float = param(unit="-", lo=-20, hi=20)
    Y_rrr: float = param(unit="-", lo=-20, hi=20)
    N_v: float = param(unit="-", lo=-5, hi=5)
    N_r: float = param(unit="-", lo=-5, hi=0)
    N_vvv: float = param(unit="-", lo=-20, hi=20)
    N_vvr: float = param(unit="-", lo=-20, hi=20)
    N_vrr: float = param(unit="-", lo=-20, hi=20)
    N_rrr: float = param(unit="-", lo=-20, hi=20)
    r_prime_max: float = param(2.0, unit="-", lo=0.1, hi=10.0)
    U_min_m_s: float = param(0.05, unit="m/s", lo=1e-4, hi=2.0)



@dataclass(frozen=True, kw_only=True)
class Propeller:
    D_m: float = param(unit="m", lo=0.01, hi=15.0, doc="propeller diameter D_P")
    k_0: float = param(unit="-", lo=0.0, hi=1.0, doc="K_T = k_0 + k_1 J + k_2 J^2")
    k_1: float = param(unit="-", lo=-2.0, hi=0.5)
    k_2: float = param(unit="-", lo=-2.0, hi=0.5)
    q_0: float = param(unit="-", lo=0.0, hi=0.2, doc="K_Q = q_0 + q_1 J + q_2 J^2")
    q_1: float = param(unit="-", lo=-0.5, hi=0.1)
    q_2: float = param(unit="-", lo=-0.5, hi=0.1)
    w_P0: float = param(unit="-", lo=0.0, hi=0.7, doc="wake fraction in straight running")
    t_P: float = param(unit="-", lo=0.0, hi=0.5, doc="thrust deduction factor")
    x_P_prime: float = param(-0.5, unit="-", lo=-0.7, hi=0.0, doc="propeller position / L")
    C_1: float = param(0.0, unit="-", lo=0.0, hi=10.0, doc="MMG wake change in manoeuvres (0: none)")
    C_2_plus: float = param(1.0, unit="-", lo=0.0, hi=5.0)
    C_2_minus: float = param(1.0, unit="-", lo=0.0, hi=5.0)
    astern_kt_ratio: float = param(
        0.7, unit="-", lo=0.1, hi=1.5, doc="astern bollard K_T / ahead bollard K_T"
    )
    astern_kq_ratio: float = param(
        0.8, unit="-", lo=0.1, hi=1.5, doc="astern bollard K_Q / ahead bollard K_Q"
    )
    astern_inflow_slope: float = param(
        0.5, unit="-", lo=0.0, hi=3.0, doc="growth of astern thrust with ahead inflow (quadrant 4)"
    )
    four_quadrant: str = param(
        "",
        choices=("",) + TABLE_NAMES,
        doc="published Wageningen four-quadrant curves outside quadrant 1 ('': the astern_* approximation)",
    )
    wake_model: str = param(
        "mmg",
        choices=("mmg", "son_nomoto"),
        doc="wake in manoeuvres: MMG C_1, C_2 or Son & Nomoto (1982) tau_P, c_pv, c_pr (sonnomoto.py)",
    )
    tau_P: float = param(0.0, unit="-", lo=0.0, hi=5.0, doc="Son & Nomoto wake change with drift and yaw")
    c_pv: float = param(0.0, unit="-", lo=-1.0, hi=1.0, doc="Son & Nomoto wake change per v'")
    c_pr: float = param(0.0, unit="-", lo=-1.0, hi=1.0, doc="Son & Nomoto wake change per r'")



@dataclass(frozen=True, kw_only=True)
class Rudder:
    model: str = param(
        choices=("mmg", "derivatives", "son_nomoto"),
        doc="'derivatives': rudder forces are hull delta-terms; 'son_nomoto': Son & Nomoto (1982)",
    )
    A_R_m2: float = param(1.0, unit="m^2", lo=1e-4, hi=500.0)
    H_R_m: float = param(1.0, unit="m", lo=0.01, hi=30.0, doc="rudder span")
    t_R: float = param(0.3, unit="-", lo=0.0, hi=1.0)
    a_H: float = param(0.3, unit="-", lo=0.0, hi=1.5)
    x_H_prime: float = param(-0.45, unit="-", lo=-1.0, hi=0.0)
    x_R_prime: float = param(-0.5, unit="-", lo=-0.7, hi=-0.3)
    gamma_R_minus: float = param(0.4, unit="-", lo=0.0, hi=2.0)
    gamma_R_plus: float = param(0.6, unit="-", lo=0.0, hi=2.0)
    l_R_prime: float = param(-0.7, unit="-", lo=-2.0, hi=0.0)
    epsilon: float = param(1.0, unit="-", lo=0.3, hi=2.0)
    kappa: float = param(0.5, unit="-", lo=0.0, hi=1.5)
    f_alpha: float = param(2.7, unit="1/rad", lo=0.5, hi=7.0)
    # Son & Nomoto (1982) rudder only (sonnomoto.py): v'_R polynomial and drag factor
    gamma_R: float = param(0.0, unit="-", lo=-2.0, hi=2.0, doc="Son & Nomoto: v'_R per v'")
    c_Rr: float = param(0.0, unit="-", lo=-2.0, hi=2.0, doc="Son & Nomoto: v'_R per r'")
    c_Rrrr: float = param(0.0, unit="-", lo=-5.0, hi=5.0, doc="Son & Nomoto: v'_R per r'^3")
    c_Rrrv: float = param(0.0, unit="-", lo=-10.0, hi=10.0, doc="Son & Nomoto: v'_R per r'^2 v'")
    c_RX: float = param(1.0, unit="-", lo=0.0, hi=2.0, doc="Son & Nomoto: X_R = c_RX F_N sin(delta)")



@dataclass(frozen=True, kw_only=True)
class SteeringGear:
    max_angle_deg: float = param(35.0, unit="deg", lo=1.0, hi=70.0)
    max_rate_deg_s: float = param(2.32, unit="deg/s", lo=0.1, hi=60.0)
    time_constant_s: float = param(1.0, unit="s", lo=0.01, hi=20.0)



@dataclass(frozen=True, kw_only=True)
class Engine:
    rated_power_kW: float = param(unit="kW", lo=0.01, hi=2e5, doc="maximum continuous rating (MCR)")
    rated_rpm: float = param(unit="rpm", lo=10.0, hi=10000.0, doc="engine speed at MCR")
    inertia_kgm2: float = param(unit="kg m^2", lo=1e-4, hi=1e7, doc="engine rotating inertia")
    torque_map_speed: tuple[float, ...] = param(
        unit="-", lo=0.0, hi=2.0, doc="engine speed / rated, 8 values"
    )
    torque_map_fuel: tuple[float, ...] = param(unit="-", lo=0.0, hi=1.0, doc="fuel index, 6 values")
    torque_map: tuple[tuple[float, ...], ...] = param(
        unit="-", lo=-1.0, hi=2.0, doc="torque / rated torque, [speed][fuel]"
    )
    astern_torque_ratio: float = param(
        1.0,
        unit="-",
        lo=0.05,
        hi=1.0,
        doc="astern torque / ahead torque (e.g. a steam plant's astern turbine)",
    )
    governor_Kp: float = param(unit="-", lo=0.0, hi=100.0, doc="fuel index per relative speed error")
    governor_Ki: float = param(unit="1/s", lo=0.0, hi=100.0)
    telegraph_rpm: tuple[float, ...] = param(
        unit="rpm", lo=-10000.0, hi=10000.0, doc="propeller rpm for full astern ... stop ... full ahead (9)"
    )
    reversing: str = param(
        "clutch",
        choices=("clutch", "direct_air_start"),
        doc="clutch: ahead/neutral/astern clutch and gearbox (or an ideal drive), instant; direct_air_start: "
        "direct-reversing diesel, fuel off, reversing gear, starting air, fuel astern",
    )
    reversal_time_s: float = param(
        15.0, unit="s", lo=1.0, hi=120.0, doc="direct_air_start: time to shift the reversing gear"
    )
    air_brake_rpm_fraction: float = param(
        0.35,
        unit="-",
        lo=0.05,
        hi=0.6,
        doc="direct_air_start: engine speed / rated below which starting air may be applied",
    )
    firing_rpm_fraction: float = param(
        0.15, unit="-", lo=0.02, hi=0.5, doc="direct_air_start: engine speed / rated at which fuel is admitted"
    )
    starting_air_torque_fraction: float = param(
        0.5, unit="-", lo=0.05, hi=2.0, doc="direct_air_start: starting-air torque / rated torque"
    )



@dataclass(frozen=True, kw_only=True)
class Transmission:
    gear_ratio: float = param(1.0, unit="-", lo=0.05, hi=50.0, doc="engine rev / propeller rev")
    efficiency: float = param(0.98, unit="-", lo=0.5, hi=1.0)
    shaft_inertia_kgm2: float = param(
        unit="kg m^2", lo=1e-6, hi=1e7, doc="propeller + entrained water + shafting"
    )
    friction_torque_fraction: float = param(
        0.02, unit="-", lo=0.0, hi=0.3, doc="shaft friction at rated speed / rated torque"
    )
    clutch_min_rpm: float = param(1.0, unit="rpm", lo=0.0, hi=1000.0, doc="|order| below: clutch out")



@dataclass(frozen=True, kw_only=True)
class Windage:
    A_F_m2: float = param(unit="m^2", lo=0.01, hi=1e4, doc="frontal projected area above water")
    A_L_m2: float = param(unit="m^2", lo=0.01, hi=5e4, doc="lateral projected area above water")
    s_L_m: float = param(0.0, unit="m", lo=-300.0, hi=300.0, doc="centre of A_L forward of midship")
    CD_t: float = param(unit="-", lo=0.1, hi=2.0, doc="Blendermann (1994) Table: transverse drag coefficient")
    CD_l_AF_0: float = param(unit="-", lo=0.1, hi=2.0, doc="longitudinal coefficient, head wind")
    CD_l_AF_pi: float = param(unit="-", lo=0.1, hi=2.0, doc="longitudinal coefficient, stern wind")
    delta: float = param(unit="-", lo=0.0, hi=1.0, doc="cross-force parameter")
    kappa: float = param(1.0, unit="-", lo=0.0, hi=5.0, doc="rolling-moment factor (unused in 3 DOF)")
    ship_type: str = param("", doc="Blendermann ship type the coefficients were taken for")



@dataclass(frozen=True, kw_only=True)
class WaveDrift:
    C_wp: float = param(0.85, unit="-", lo=0.5, hi=0.98, doc="waterplane coefficient of the drift waterline")
    reflection: float = param(
        1.0, unit="-", lo=0.0, hi=1.0, doc="short-wave reflection factor (1: wall-sided)"
    )



@dataclass(frozen=True, kw_only=True)
class LargeDrift:
    """Ship-file table ``[large_drift]``: the cross-flow model for an MMG or Abkowitz hull (docs/ship-file.md)."""

    model: str = param("yoshimura_2009", choices=("yoshimura_2009",), doc="Yoshimura, Nakao & Ishibashi (2009)")
    C_D: float = param(unit="-", lo=0.1, hi=2.0, doc="hull cross-flow drag coefficient at 90 deg drift, on 1/2 rho L d")
    C_rY: float = param(unit="-", lo=0.0, hi=5.0, doc="yaw-rate factor of the cross flow in the sway force")
    C_rN: float = param(unit="-", lo=0.0, hi=5.0, doc="yaw-rate factor of the cross flow in the yaw moment")
    R_0_astern: float = param(unit="-", lo=0.0, hi=0.2, doc="resistance coefficient straight astern, like R_0")
    mmg_drift_max_deg: float = param(
        22.0, unit="deg", lo=0.0, hi=60.0, doc="flow angle up to which the MMG polynomial is used unchanged"
    )
    cross_flow_drift_min_deg: float = param(
        35.0, unit="deg", lo=1.0, hi=90.0, doc="flow angle from which the cross-flow model is used alone"
    )
    mmg_r_prime_max: float = param(1.2, unit="-", lo=0.0, hi=5.0, doc="|r'| up to which the MMG polynomial is used")
    cross_flow_r_prime_min: float = param(
        2.4, unit="-", lo=0.1, hi=10.0, doc="|r'| from which the cross-flow model is used alone"
    )
    polynomial_u_prime_max: float = param(
        0.8, unit="-", lo=0.0, hi=1.0, doc="Abkowitz hull with U_ref: |u'| up to which the polynomial is used"
    )
    cross_flow_u_prime_min: float = param(
        1.0, unit="-", lo=0.05, hi=1.0, doc="Abkowitz hull with U_ref: |u'| from which the cross-flow model is used"
    )



@dataclass(frozen=True, kw_only=True)
class Roll:
    """The ``[roll]`` table of a 4-DOF ship."""

    GM_m: float = param(unit="m", lo=0.01, hi=20.0, doc="transverse metacentric height (upright)")
    I_xG_kgm2: float = param(unit="kg m^2", lo=1e-6, hi=1e14, doc="roll moment of inertia about G")
    z_R_m: float = param(
        0.0, unit="m", lo=-30.0, hi=30.0, doc="rudder's centre of effort below G (roll moment -z_R Y_R)"
    )
    GZ_heel_deg: tuple[float, ...] = param(
        (), unit="deg", lo=0.0, hi=90.0, doc="heel breakpoints of a righting-lever curve (0 first, to >= 40)"
    )
    GZ_m: tuple[float, ...] = param((), unit="m", lo=-20.0, hi=20.0, doc="righting lever GZ at GZ_heel_deg")
    propeller_torque_reaction: str = param(
        "none",
        choices=("none", "right_handed", "left_handed"),
        doc="roll moment of the shaft torque on the hull, -Q_P for a right-handed propeller ('none': not modelled)",
    )
    damping_linear_Nms: float = param(
        0.0, unit="N m s/rad", lo=0.0, hi=1e12, doc="linear roll damping besides the hull's K_p"
    )
    damping_quadratic_Nms2: float = param(
        0.0, unit="N m s^2/rad^2", lo=0.0, hi=1e14, doc="quadratic roll damping K_pp p|p|"
    )
    derivatives: dict = param(
        {}, doc="hull roll terms (prime system): K_v, K_vvphi, Y_phi, N_rrphi, K_pdot, ... (docs/ship-file.md)"
    )

