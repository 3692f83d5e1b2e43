"""Checks of a ship file's tables beyond each key's own range: Abkowitz derivative names and sizes, the
engine's torque map and telegraph, and magnitudes checked against the ship itself (mass against the hull's
volume, inertias against mass, propeller and power).

Format reference: docs/ship-file.md ("Plausibility checks"). :mod:`vessel_gym.physics.shipfile` reads the
file, builds its tables (dataclasses) and calls these checks with them; the checks take the tables as they
come (``Any``) so that this module does not import the one that calls it.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from typing import Any

from vessel_gym.physics.schema import SpecError, as_float

# Abkowitz coefficient names: force letter, "_", optional bias marker 0, then the motion variables whose
# product multiplies the coefficient (u, v, r and d for the rudder angle delta), e.g. Y_vvr, N_uud, Y_0uu.
_ABK_TERM = re.compile(r"^([XYN])_(0?)([uvrd]*)$")
_ABK_ACCEL = {"X_udot", "Y_vdot", "Y_rdot", "N_vdot", "N_rdot"}

# Plausibility bands derived from the ship itself (docs/ship-file.md, "Plausibility checks"):
#: mass / (rho L B T C_b): displacement from the block coefficient, allowing for appendages, shell plating and
#: L_pp versus waterline length (a few per cent each) with a wide margin; a wrong unit or digit is far outside.
MASS_CB_FACTOR = 1.2
#: mass / (rho L B T) without C_b: the implied block coefficient, fine yacht hull to box barge
CB_IMPLIED = (0.35, 1.0)
#: yaw radius of gyration / L: merchant hulls lie near 0.2-0.3 L (0.25 L is the usual estimate, e.g.
#: Yasukawa & Yoshimura 2015 for KVLCC2; the Mariner's published I_z gives 0.22 L); the band adds 0.05 L each side.
KZZ_OVER_L = (0.15, 0.35)
#: shaft inertia / (rho_water D^5): a solid bronze disc of diameter D and thickness D/10 gives about 0.08; real
#: propellers with shafting and entrained water 0.005-0.015, light model propellers ~4e-4.
SHAFT_INERTIA_RHO_D5 = (1e-5, 1.0)
#: engine run-up time I omega^2 / P, s (twice the rotor's kinetic energy at rated speed over rated power):
#: diesels ~1-10 s, a geared steam turbine ~40 s (Mariner); beyond this band a digit or unit is wrong.
ENGINE_RUNUP_S = (1e-3, 300.0)
#: torque / rated torque without fuel: friction and pumping losses drag the engine, bounded like
#: [transmission] friction_torque_fraction
NO_FUEL_TORQUE_MIN = -0.3


class ShipFileError(SpecError):
    """A ship file is invalid; the message names the file and the key."""


def abkowitz_term(name: str) -> tuple[str, int, int, int, int] | None:
    """Parse a derivative name: 'Y_vvr' -> ('Y', e_u, e_v, e_r, e_d) = ('Y', 0, 2, 1, 0); None if not a term."""
    m = _ABK_TERM.match(name)
    if not m or (not m.group(2) and not m.group(3)):
        return None
    vars_ = m.group(3)
    return (m.group(1), vars_.count("u"), vars_.count("v"), vars_.count("r"), vars_.count("d"))


def check_abkowitz(derivatives: Mapping[str, Any], where: str) -> None:
    """Each of [hull] derivatives is a finite number with a known name, powers up to 4 and a plausible size."""
    for key, value in derivatives.items():
        w = f"{where} [hull.derivatives] {key}"
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ShipFileError(f"{w}: expected a finite number, got {type(value).__name__}")
        if not math.isfinite(as_float(value, w)):
            raise ShipFileError(f"{w}: expected a finite number, got {value!r}")
        if key in _ABK_ACCEL:
            continue
        term = abkowitz_term(key)
        if term is None:
            raise ShipFileError(
                f"{w}: not a derivative name (expected e.g. X_uu, Y_vvr, N_0u, Y_d or one of "
                f"{', '.join(sorted(_ABK_ACCEL))})"
            )
        if max(term[1:]) > 4:
            raise ShipFileError(f"{w}: powers above 4 are not supported")
        if abs(value) > 10.0:
            raise ShipFileError(f"{w}: |{value:g}| > 10 is not a plausible nondimensional derivative")


def check_engine(eng: Any, where: str) -> None:
    """An [engine] table (``sections.Engine``): the torque map's axes, shape and monotony, the telegraph and
    the air-start fractions."""
    from vessel_gym.physics import layout as lo

    if len(eng.torque_map_speed) != lo.MAP_NS:
        raise ShipFileError(f"{where} [engine] torque_map_speed: needs {lo.MAP_NS} values")
    if len(eng.torque_map_fuel) != lo.MAP_NF:
        raise ShipFileError(f"{where} [engine] torque_map_fuel: needs {lo.MAP_NF} values")
    for name, seq in (("torque_map_speed", eng.torque_map_speed), ("torque_map_fuel", eng.torque_map_fuel)):
        if any(b <= a for a, b in zip(seq, seq[1:])):
            raise ShipFileError(f"{where} [engine] {name}: values must increase strictly")
    if len(eng.torque_map) != lo.MAP_NS or any(len(row) != lo.MAP_NF for row in eng.torque_map):
        raise ShipFileError(f"{where} [engine] torque_map: needs {lo.MAP_NS} rows of {lo.MAP_NF} values")
    fuel0 = [j for j, f in enumerate(eng.torque_map_fuel) if f == 0.0]
    for i, row in enumerate(eng.torque_map):
        w = f"{where} [engine] torque_map[{i}]"
        for j, q in enumerate(row):
            lo_q = NO_FUEL_TORQUE_MIN if j in fuel0 else 0.0
            hi_q = 0.0 if j in fuel0 else math.inf
            if not lo_q <= q <= hi_q:
                what = "without fuel" if j in fuel0 else f"at fuel index {eng.torque_map_fuel[j]:g}"
                raise ShipFileError(
                    f"{w}[{j}]: torque {q:g} {what} is outside [{lo_q:g}, {hi_q:g}] x rated torque"
                )
        if any(b < a for a, b in zip(row, row[1:])):
            raise ShipFileError(f"{w}: torque must not decrease with more fuel, got {list(row)}")
        if row[-1] <= 0.0:
            raise ShipFileError(f"{w}: torque at the highest fuel index must be > 0, got {row[-1]:g}")
    if len(eng.telegraph_rpm) != 9:
        raise ShipFileError(f"{where} [engine] telegraph_rpm: needs 9 values (full astern .. full ahead)")
    t = eng.telegraph_rpm
    if t[4] != 0.0 or any(b <= a for a, b in zip(t, t[1:])):
        raise ShipFileError(f"{where} [engine] telegraph_rpm: must increase, with stop (5th value) = 0")
    if eng.reversing == "direct_air_start" and eng.firing_rpm_fraction >= eng.air_brake_rpm_fraction:
        raise ShipFileError(
            f"{where} [engine] firing_rpm_fraction: {eng.firing_rpm_fraction:g} must be below "
            f"air_brake_rpm_fraction ({eng.air_brake_rpm_fraction:g})"
        )


def _outside(x: float, band: tuple[float, float]) -> bool:
    return not band[0] <= x <= band[1]


def check_plausible(parts: dict[str, Any], where: str) -> None:
    """Checks of magnitudes against the ship itself: mass against the hull's volume, yaw inertia against
    mass L^2, shaft inertia against the propeller, engine inertia against its power (bands above)."""
    p = parts["particulars"]
    key = "mass_kg" if p.mass_kg is not None else "displacement_m3"
    mass = p.mass_kg if p.mass_kg is not None else p.rho_kg_m3 * p.displacement_m3
    box = p.rho_kg_m3 * p.L_m * p.B_m * p.T_m  # kg, mass of the L x B x T box of water
    w = f"{where} [particulars] {key}"
    if p.C_b is not None:
        lo_m, hi_m = box * p.C_b / MASS_CB_FACTOR, box * p.C_b * MASS_CB_FACTOR
        if not lo_m <= mass <= hi_m:
            raise ShipFileError(
                f"{w}: mass {mass:.4g} kg is outside [{lo_m:.4g}, {hi_m:.4g}] kg, "
                f"rho L B T C_b within a factor {MASS_CB_FACTOR:g}"
            )
    elif _outside(mass / box, CB_IMPLIED):
        raise ShipFileError(
            f"{w}: mass {mass:.4g} kg is outside [{CB_IMPLIED[0] * box:.4g}, {CB_IMPLIED[1] * box:.4g}] kg, "
            f"rho L B T x [{CB_IMPLIED[0]:g}, {CB_IMPLIED[1]:g}] (give C_b for a tighter check)"
        )
    if p.k_zz_m is not None:
        k, key = p.k_zz_m, "k_zz_m"
    else:
        k, key = math.sqrt(p.I_zG_kgm2 / mass), "I_zG_kgm2"
    if _outside(k / p.L_m, KZZ_OVER_L):
        raise ShipFileError(
            f"{where} [particulars] {key}: yaw radius of gyration {k:.4g} m = {k / p.L_m:.3g} L is outside "
            f"[{KZZ_OVER_L[0]:g}, {KZZ_OVER_L[1]:g}] L"
        )
    prop, eng, tr = parts.get("propeller"), parts.get("engine"), parts.get("transmission")
    if prop is not None and tr is not None:
        ref = p.rho_kg_m3 * prop.D_m**5  # kg m^2
        if _outside(tr.shaft_inertia_kgm2 / ref, SHAFT_INERTIA_RHO_D5):
            lo_i, hi_i = (f * ref for f in SHAFT_INERTIA_RHO_D5)
            raise ShipFileError(
                f"{where} [transmission] shaft_inertia_kgm2: {tr.shaft_inertia_kgm2:.4g} kg m^2 is outside "
                f"[{lo_i:.3g}, {hi_i:.3g}] kg m^2, rho D^5 x [{SHAFT_INERTIA_RHO_D5[0]:g}, "
                f"{SHAFT_INERTIA_RHO_D5[1]:g}] for the propeller's D_m = {prop.D_m:g} m"
            )
    if eng is not None:
        omega = eng.rated_rpm * 2.0 * math.pi / 60.0  # rad/s
        power = eng.rated_power_kW * 1e3  # W
        if _outside(eng.inertia_kgm2 * omega**2 / power, ENGINE_RUNUP_S):
            lo_i, hi_i = (t * power / omega**2 for t in ENGINE_RUNUP_S)
            raise ShipFileError(
                f"{where} [engine] inertia_kgm2: {eng.inertia_kgm2:.4g} kg m^2 is outside [{lo_i:.3g}, "
                f"{hi_i:.3g}] kg m^2, a run-up time I omega^2 / P within [{ENGINE_RUNUP_S[0]:g}, "
                f"{ENGINE_RUNUP_S[1]:g}] s at the rated power and rpm"
            )
