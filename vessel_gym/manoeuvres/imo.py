"""IMO Standards for Ship Manoeuvrability, Res. MSC.137(76) (2002): criteria, evaluation and report.

Criteria (Annex §5.3): advance <= 4.5 L and tactical diameter <= 5 L in the 35 deg turning test (or the
maximum rudder angle permissible at the test speed); initial turning: no more than 2.5 L travelled by the
time the heading has changed 10 deg with 10 deg rudder; 10/10 zig-zag first overshoot <= 10 deg if
L/V < 10 s, <= 20 deg if L/V >= 30 s, else (5 + 1/2 L/V) deg; second overshoot <= 25 / 40 /
(17.5 + 0.75 L/V) deg on the same ranges; 20/20 zig-zag first overshoot <= 25 deg; full-astern stopping
track reach <= 15 L (Administrations may accept up to 20 L for large ships; the 15 L limit is reported).
All trials to port and starboard at the test speed in deep, calm water.

The pull-out test (MSC/Circ.1053 §3.4.4, Burcher 1972) has no IMO limit; the report runs it on request as
evidence of course stability.

Optional, for ships with roll only: the heel in a turn against the Intact Stability Code's guidance, 2008 IS
Code (Res. MSC.267(85)) Part A §3.1.3: for passenger ships the angle of heel on account of turning should not
exceed 10 deg. The Code estimates that heel from a steady-turn heeling moment; a simulation has the heel itself,
so the criterion is the largest |heel| of the 35 deg turning test to each side (the transient outward heel
exceeds the steady one, so this is the stricter reading). The limit is the caller's (``heel_limit_deg``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from vessel_gym.manoeuvres.trials import (
    InitialTurning,
    ManoeuvreDiverged,
    ManoeuvreIncomplete,
    Stopping,
    TurningCircle,
    ZigZag,
    initial_turning,
    pull_out,
    stopping,
    turning_circle,
    zigzag,
)
from vessel_gym.physics.environment import CALM, Environment
from vessel_gym.physics.plausibility import Finding, check_ship, impossible
from vessel_gym.physics.shipfile import Ship, load_ship
from vessel_gym.physics.units import DEG, KNOT_M_S
from vessel_gym.physics.vessel import mass_matrix


def zigzag10_limits(L_over_V_s: float) -> tuple[float, float]:
    """(first, second) overshoot limits of the 10/10 zig-zag, deg, MSC.137(76) §5.3.3.1-2."""
    if L_over_V_s < 10.0:
        return 10.0, 25.0
    if L_over_V_s >= 30.0:
        return 20.0, 40.0
    return 5.0 + 0.5 * L_over_V_s, 17.5 + 0.75 * L_over_V_s


#: said with every report run in shallow water: the standards' limits are for deep, unrestricted water
SHALLOW_NOTE = (
    "MSC.137(76) criteria apply to deep unrestricted water (MSC/Circ.1053: trials in depths above 4 T); "
    "shallow-water results are shown against them for comparison only"
)
ADVANCE_LIMIT_L = 4.5  # MSC.137(76) §5.3.1
TACTICAL_DIAMETER_LIMIT_L = 5.0  # MSC.137(76) §5.3.1
INITIAL_TURNING_LIMIT_L = 2.5  # MSC.137(76) §5.3.2
ZIGZAG20_FIRST_LIMIT_DEG = 25.0  # MSC.137(76) §5.3.3.3
STOPPING_LIMIT_L = 15.0  # MSC.137(76) §5.3.4
STOPPING_LARGE_SHIP_LIMIT_L = 20.0  # §5.3.4: the most an Administration may accept for large displacement
IS_CODE_PASSENGER_HEEL_LIMIT_DEG = (
    10.0  # 2008 IS Code Part A §3.1.3: heel on account of turning, passenger ships
)
IS_CODE_HEEL_REF = "2008 IS Code (MSC.267(85)) Part A §3.1.3"
#: a turn, a zig-zag or a crash stop at constant or reduced power only adds drag (drift, yaw, rudder, astern
#: thrust), so the speed through the water and the kinetic energy never rise above the approach's; every
#: built-in ship stays at or below 1.0000 of it. The 1 % allows for the approach's rpm, solved numerically.
SPEED_RISE_ALLOWANCE = 0.01
#: the heading change (rad) beyond which a trial's turning direction is read (clear of rounding at t = 0)
DIRECTION_READ_RAD = 1.0 * DEG


@dataclass
class Criterion:
    name: str
    side: str  # "starboard" | "port" | "ahead"
    value: float | None
    limit: float
    unit: str
    note: str = ""
    # the run ran away (non-finite or physically impossible state): never scored, ``note`` says why
    diverged: bool = False
    # the trial did what no ship can (:func:`implausibility`): never scored, this says why
    implausible: str = ""

    @property
    def passed(self) -> bool:
        if self.diverged or self.implausible:
            return False
        return bool(self.value is not None and self.value <= self.limit)

    @property
    def verdict(self) -> str:
        """One of "diverged", "implausible", "pass" or "fail"."""
        if self.diverged:
            return "diverged"
        if self.implausible:
            return "implausible"
        return "pass" if self.passed else "fail"

    def to_dict(self) -> dict:
        d = {
            "name": self.name,
            "side": self.side,
            "value": None if self.value is None else float(self.value),
            "limit": self.limit,
            "unit": self.unit,
            "pass": self.passed,
            "verdict": self.verdict,
        }
        if self.note:
            d["note"] = self.note
        if self.implausible:
            d["implausible"] = self.implausible
        return d


@dataclass
class ImoReport:
    ship: str
    L_m: float
    V_kn: float
    criteria: list[Criterion]
    trials: dict = field(default_factory=dict, repr=False)
    spec: Ship | None = field(default=None, repr=False)
    depth_m: float = math.inf  # water depth of the trials, m (inf: deep water)
    # the ship file's checks (physics.plausibility) run before the trials
    findings: list[Finding] = field(default_factory=list, repr=False)

    @property
    def L_over_V_s(self) -> float:
        return self.L_m / (self.V_kn * KNOT_M_S)

    @property
    def passed(self) -> bool:
        return not self.implausible_reasons and all(c.passed for c in self.criteria)

    @property
    def diverged(self) -> bool:
        """Some trial ran away, so the report cannot pass (the command exits with 1)."""
        return any(c.diverged for c in self.criteria)

    @property
    def implausible_reasons(self) -> list[str]:
        """Why no ship could do what this one did (ship file or trials), one sentence each; the report
        then cannot pass (the command exits with 1)."""
        ship = [
            f"{f.quantity}: {f.value:.4g}, expected {f.expected} ({f.note})"
            for f in impossible(self.findings)
        ]
        trials = dict.fromkeys(c.implausible for c in self.criteria if c.implausible)
        return ship + list(trials)

    @property
    def verdict(self) -> str:
        if self.diverged:
            return "DIVERGED"
        if self.implausible_reasons:
            return "IMPLAUSIBLE"
        return "PASS" if self.passed else "FAIL"

    def criteria_named(self, name: str) -> list[Criterion]:
        return [c for c in self.criteria if c.name == name]

    def to_dict(self) -> dict:
        d = {
            "ship": self.ship,
            "L_m": self.L_m,
            "V_kn": self.V_kn,
            "L_over_V_s": self.L_over_V_s,
            "criteria": [c.to_dict() for c in self.criteria],
            "pass": self.passed,
            "verdict": self.verdict,
        }
        if "pull_out" in self.trials:
            d["pull_out"] = self.trials["pull_out"].to_dict()
        if math.isfinite(self.depth_m):
            d["depth_m"] = self.depth_m
            d["depth_note"] = SHALLOW_NOTE
        if self.implausible_reasons:
            d["implausible"] = self.implausible_reasons
        return d

    def table(self) -> str:
        """The report as a fixed-width text table."""
        lines = [
            f"IMO MSC.137(76) manoeuvring criteria - {self.ship}",
            f"L = {self.L_m:.2f} m, test speed V = {self.V_kn:.2f} kn, L/V = {self.L_over_V_s:.2f} s",
            *([f"water depth {self.depth_m:g} m: {SHALLOW_NOTE}"] if math.isfinite(self.depth_m) else []),
            "",
            f"{'criterion':<28}{'side':<11}{'value':>9}{'limit':>9}  {'unit':<5}{'result':>12}",
            "-" * 76,
        ]
        for c in self.criteria:
            val = "   n/a" if c.value is None else f"{c.value:9.2f}"
            lines.append(
                f"{c.name:<28}{c.side:<11}{val:>9}{c.limit:9.2f}  {c.unit:<5}"
                f"{c.verdict.upper():>12}" + (f"  ({c.note})" if c.note else "")
            )
        lines.append("-" * 76)
        lines += [f"implausible: {why}" for why in self.implausible_reasons]
        lines.append(f"overall: {self.verdict}")
        cfd = cfd_uncertainty_line(self.spec)
        return "\n".join(lines + ([cfd] if cfd else []))


# the linear derivatives: one motion variable after the force's letter (Y_v, N_r, Y_vdot, ...)
_LINEAR = {"u", "v", "r", "p", "phi", "udot", "vdot", "rdot", "pdot"}


def cfd_uncertainty_line(spec: Ship | None) -> str:
    """"Derived from CFD, ±x %" for a ship file whose derivatives come with a grid study's uncertainty
    (``[source.provenance.grid_uncertainty]``, written by ``vessel-cfd study``): x is the largest relative
    uncertainty of the linear derivatives (those that decide course stability and the turning circle), each
    derivative listed after it. Empty for other ship files."""
    prov = spec.source.provenance if spec is not None else {}
    table = prov.get("grid_uncertainty") if isinstance(prov, dict) else None
    if not isinstance(table, dict):
        return ""
    rel = {k: v.get("relative") for k, v in table.items() if isinstance(v, dict) and k != "R_T_N"}
    known = {k: float(v) for k, v in rel.items() if isinstance(v, (int, float))}
    linear = [v for k, v in known.items() if k.partition("_")[2] in _LINEAR]
    if not linear:
        return "Derived from CFD; no grid uncertainty of the linear derivatives could be estimated."
    line = f"Derived from CFD, ±{100 * max(linear):.1f} % (largest grid uncertainty of the linear derivatives, GCI; "
    line += ", ".join(f"{k} ±{100 * v:.1f} %" for k, v in known.items())
    unknown = [k for k in rel if k not in known]
    return line + (f"; none for {', '.join(unknown)} (divergent)" if unknown else "") + ")."


def implausibility(trial, ship: Ship, label: str) -> str:
    """Why a trial's result is physically impossible, or "" if it is not: the speed (or, in the stopping
    test, the kinetic energy) rising above the approach's by more than :data:`SPEED_RISE_ALLOWANCE`, or the
    ship turning against its rudder. ``label`` names the trial in the sentence."""
    tr = trial.track
    u, v, r = (np.asarray(a) for a in (tr.u, tr.v, tr.r))
    U = np.hypot(u, v)
    rise = float(U.max() / U[0]) if U[0] > 0.0 else 1.0
    if rise > 1.0 + SPEED_RISE_ALLOWANCE:
        return f"{label}: the speed rose to {rise:.2f}x the approach speed with no more power"
    if isinstance(trial, Stopping):
        M = mass_matrix(ship)
        nu = np.column_stack([u, v, r])
        energy = 0.5 * np.einsum("ti,ij,tj->t", nu, M, nu)  # J, rigid body and added mass
        gain = float(energy.max() / energy[0])
        if gain > 1.0 + SPEED_RISE_ALLOWANCE:
            return f"{label}: the kinetic energy rose to {gain:.2f}x the approach's with the engine astern"
    rudder = getattr(trial, "rudder_deg", 0.0)
    psi = np.asarray(tr.psi)
    turned = np.nonzero(np.abs(psi) > DIRECTION_READ_RAD)[0]
    if rudder and turned.size and math.copysign(1.0, psi[turned[0]]) != math.copysign(1.0, rudder):
        wrong = "port" if rudder > 0 else "starboard"
        return f"{label}: the ship turned to {wrong} with the rudder to {_side(rudder)}"
    return ""


def _judged(criteria: list[Criterion], trial, ship: Ship, label: str) -> list[Criterion]:
    """``criteria`` of ``trial``, each marked implausible if the trial is (:func:`implausibility`)."""
    why = implausibility(trial, ship, label.replace("_", " "))
    for c in criteria:
        c.implausible = why
    return criteria


def _side(rudder_deg: float) -> str:
    return "starboard" if rudder_deg > 0 else "port"


def turning_criteria(tc: TurningCircle) -> list[Criterion]:
    """Advance and tactical diameter of a 35 deg (or maximum-rudder) turning test, MSC.137(76) §5.3.1."""
    L, side = tc.L_m, _side(tc.rudder_deg)
    return [
        Criterion("advance", side, tc.advance_m / L, ADVANCE_LIMIT_L, "L"),
        Criterion("tactical_diameter", side, tc.tactical_diameter_m / L, TACTICAL_DIAMETER_LIMIT_L, "L"),
    ]


def initial_turning_criteria(it: InitialTurning) -> list[Criterion]:
    """Distance travelled to a 10 deg heading change with 10 deg rudder, MSC.137(76) §5.3.2."""
    side = _side(it.rudder_deg)
    return [Criterion("initial_turning", side, it.distance_m / it.L_m, INITIAL_TURNING_LIMIT_L, "L")]


def zigzag_limits(angle_deg: float, L_over_V_s: float) -> tuple[float, ...]:
    """Overshoot limits (deg) of the 10/10 (first, second) or 20/20 (first) zig-zag, MSC.137(76) §5.3.3."""
    if angle_deg == 10.0:
        return zigzag10_limits(L_over_V_s)
    if angle_deg == 20.0:
        return (ZIGZAG20_FIRST_LIMIT_DEG,)
    raise ValueError(
        f"MSC.137(76) sets overshoot limits for 10/10 and 20/20 zig-zags only, not {angle_deg:g}"
    )


def zigzag_criteria(z: ZigZag, L_over_V_s: float) -> list[Criterion]:
    """The overshoot criteria of a 10/10 or 20/20 zig-zag (MSC.137(76) §5.3.3)."""
    angle = abs(z.rudder_deg)
    names = [f"zigzag_{angle:.0f}_first_overshoot", f"zigzag_{angle:.0f}_second_overshoot"]
    out = []
    for k, (nm, lim) in enumerate(zip(names, zigzag_limits(angle, L_over_V_s))):
        val = z.overshoot_deg[k] if k < len(z.overshoot_deg) else None
        out.append(
            Criterion(nm, _side(z.rudder_deg), val, lim, "deg", "" if val is not None else "not reached")
        )
    return out


def stopping_criteria(st: Stopping) -> list[Criterion]:
    """Track reach of the full-astern stopping test, MSC.137(76) §5.3.4."""
    reach = st.track_reach_m / st.L_m
    note = ""
    if STOPPING_LIMIT_L < reach <= STOPPING_LARGE_SHIP_LIMIT_L:
        note = "within the 20 L an Administration may accept for ships of large displacement"
    return [Criterion("stopping_track_reach", "ahead", reach, STOPPING_LIMIT_L, "L", note)]


def heel_criteria(tc: TurningCircle, limit_deg: float) -> list[Criterion]:
    """The largest |heel| of a 35 deg turning test against ``limit_deg`` (the IS Code's heel-in-turn
    guidance, see the module text); empty for a 3-DOF ship, which has no heel."""
    if tc.max_heel_deg is None:
        return []
    side = _side(tc.rudder_deg)
    return [Criterion("heel_in_turn", side, abs(tc.max_heel_deg), limit_deg, "deg", IS_CODE_HEEL_REF)]


def criteria_for(result, ship: str | Ship) -> list[Criterion]:
    """The MSC.137(76) criteria a single trial result is evidence for: empty unless the trial was run in the
    standard's condition (test speed; 35 deg or the maximum rudder for turning, 10 deg for initial turning,
    10/10 or 20/20 zig-zag). A trial that did what no ship can (:func:`implausibility`) marks them
    implausible, as in the IMO report."""
    s = load_ship(ship)
    V = s.particulars.test_speed_kn
    if abs(getattr(result, "speed_kn", V) - V) > 1e-6 * V:
        return []
    rudder = abs(getattr(result, "rudder_deg", 0.0))
    side = _side(getattr(result, "rudder_deg", 1.0))
    if isinstance(result, TurningCircle) and rudder == min(35.0, s.steering_gear.max_angle_deg):
        return _judged(turning_criteria(result), result, s, f"turning_{side}")
    if isinstance(result, InitialTurning) and rudder == 10.0:
        return _judged(initial_turning_criteria(result), result, s, f"initial_turning_{side}")
    if isinstance(result, ZigZag) and rudder == result.heading_deg and rudder in (10.0, 20.0):
        LV = s.particulars.L_m / (V * KNOT_M_S)
        return _judged(zigzag_criteria(result, LV), result, s, f"zigzag_{rudder:.0f}_{side}")
    if isinstance(result, Stopping):
        return _judged(stopping_criteria(result), result, s, "stopping")
    return []


def _missing(name: str, side: str, limit: float, unit: str, exc: ManoeuvreIncomplete) -> Criterion:
    """The criterion of a trial that gave no value; a run that diverged says so and is never scored."""
    return Criterion(name, side, None, limit, unit, str(exc), isinstance(exc, ManoeuvreDiverged))


def imo_report(
    ship: str | Ship,
    with_pull_out: bool = False,
    environment: Environment = CALM,
    heel_limit_deg: float | None = None,
) -> ImoReport:
    """Run every MSC.137(76) trial to both sides at the ship's test speed and evaluate the criteria;
    ``with_pull_out`` adds the pull-out test (no IMO limit) to the report's trials. Every trial runs in
    ``environment`` (default calm deep water); a finite ``depth_m`` there runs them in shallow water.
    ``heel_limit_deg`` adds the heel-in-turn criterion (IS Code guidance, see the module text) for a ship with
    roll; a 3-DOF ship with a heel limit is refused (ValueError)."""
    s = load_ship(ship)
    if heel_limit_deg is not None:
        if s.roll is None:
            raise ValueError(
                f"ship {s.name!r} has no roll (no [roll] table): no heel to hold to a heel limit"
            )
        if not 0.0 < heel_limit_deg < 90.0:
            raise ValueError(f"heel limit {heel_limit_deg:g} deg: allowed 0 < limit < 90")
    findings = check_ship(s)  # the ship file's signs, energy and rudder, before any trial
    env = environment
    L = s.particulars.L_m
    V = s.particulars.test_speed_kn
    LV = L / (V * KNOT_M_S)
    turn_rudder = min(35.0, s.steering_gear.max_angle_deg)
    crit: list[Criterion] = []
    heel: list[Criterion] = []  # listed after the MSC.137(76) criteria
    trials: dict = {}
    sides = (("starboard", 1.0), ("port", -1.0))

    for side, sg in sides:
        try:
            tc = turning_circle(s, sg * turn_rudder, until_deg=360.0, environment=env)
            trials[f"turning_{side}"] = tc
            crit += _judged(turning_criteria(tc), tc, s, f"turning_{side}")
            if heel_limit_deg is not None:
                heel += _judged(heel_criteria(tc, heel_limit_deg), tc, s, f"turning_{side}")
        except ManoeuvreIncomplete as exc:
            crit.append(_missing("advance", side, ADVANCE_LIMIT_L, "L", exc))
            crit.append(_missing("tactical_diameter", side, TACTICAL_DIAMETER_LIMIT_L, "L", exc))
            if heel_limit_deg is not None:
                heel.append(_missing("heel_in_turn", side, heel_limit_deg, "deg", exc))
    for side, sg in sides:
        try:
            it = initial_turning(s, sg * 10.0, environment=env)
            trials[f"initial_turning_{side}"] = it
            crit += _judged(initial_turning_criteria(it), it, s, f"initial_turning_{side}")
        except ManoeuvreIncomplete as exc:
            crit.append(_missing("initial_turning", side, INITIAL_TURNING_LIMIT_L, "L", exc))
    for angle in (10.0, 20.0):
        limits = zigzag_limits(angle, LV)
        for side, sg in sides:
            try:
                z = zigzag(s, sg * angle, angle, n_overshoots=len(limits), environment=env)
                trials[f"zigzag_{angle:.0f}_{side}"] = z
                crit += _judged(zigzag_criteria(z, LV), z, s, f"zigzag_{angle:.0f}_{side}")
            except ManoeuvreIncomplete as exc:
                names = [f"zigzag_{angle:.0f}_first_overshoot", f"zigzag_{angle:.0f}_second_overshoot"]
                for nm, lim in zip(names, limits):
                    crit.append(_missing(nm, side, lim, "deg", exc))
    try:
        st = stopping(s, environment=env)
        trials["stopping"] = st
        crit += _judged(stopping_criteria(st), st, s, "stopping")
    except ManoeuvreIncomplete as exc:
        crit.append(_missing("stopping_track_reach", "ahead", STOPPING_LIMIT_L, "L", exc))
    if with_pull_out:
        try:
            trials["pull_out"] = pull_out(s, environment=env)
        except ManoeuvreIncomplete:
            pass  # no criterion depends on it; the report says the trial is missing
    return ImoReport(s.name, L, V, crit + heel, trials, s, environment.depth_m, findings)
