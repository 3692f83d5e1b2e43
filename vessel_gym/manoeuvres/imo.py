"""IMO Standards for Ship Manoeuvrability, Res. MSC.137(76) (2002): criteria, evaluation and report.

Criteria (Annex §5.3): advance <= 4.5 L and tactical diameter <= 5 L in the 35 deg turning test (or the
maximum rudder angle permissible at the test speed); initial turning: no more than 2.5 L travelled by the
time the heading has changed 10 deg with 10 deg rudder; 10/10 zig-zag first overshoot <= 10 deg if
L/V < 10 s, <= 20 deg if L/V >= 30 s, else (5 + 1/2 L/V) deg; second overshoot <= 25 / 40 /
(17.5 + 0.75 L/V) deg on the same ranges; 20/20 zig-zag first overshoot <= 25 deg; full-astern stopping
track reach <= 15 L (Administrations may accept up to 20 L for large ships; the 15 L limit is reported).
All trials to port and starboard at the test speed in deep, calm water.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from vessel_gym.manoeuvres.trials import (
    ManoeuvreIncomplete,
    initial_turning,
    stopping,
    turning_circle,
    zigzag,
)
from vessel_gym.physics.shipfile import Ship, load_ship
from vessel_gym.physics.units import KNOT_M_S


def zigzag10_limits(L_over_V_s: float) -> tuple[float, float]:
    """(first, second) overshoot limits of the 10/10 zig-zag, deg, MSC.137(76) §5.3.3.1-2."""
    if L_over_V_s < 10.0:
        return 10.0, 25.0
    if L_over_V_s >= 30.0:
        return 20.0, 40.0
    return 5.0 + 0.5 * L_over_V_s, 17.5 + 0.75 * L_over_V_s


@dataclass
class Criterion:
    name: str
    side: str  # "starboard" | "port" | "ahead"
    value: float | None
    limit: float
    unit: str
    note: str = ""

    @property
    def passed(self) -> bool:
        return bool(self.value is not None and self.value <= self.limit)

    def to_dict(self) -> dict:
        d = {
            "name": self.name,
            "side": self.side,
            "value": None if self.value is None else float(self.value),
            "limit": self.limit,
            "unit": self.unit,
            "pass": self.passed,
        }
        if self.note:
            d["note"] = self.note
        return d


@dataclass
class ImoReport:
    ship: str
    L_m: float
    V_kn: float
    criteria: list[Criterion]
    trials: dict = field(default_factory=dict, repr=False)

    @property
    def L_over_V_s(self) -> float:
        return self.L_m / (self.V_kn * KNOT_M_S)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.criteria)

    def to_dict(self) -> dict:
        return {
            "ship": self.ship,
            "L_m": self.L_m,
            "V_kn": self.V_kn,
            "L_over_V_s": self.L_over_V_s,
            "criteria": [c.to_dict() for c in self.criteria],
            "pass": self.passed,
        }

    def table(self) -> str:
        """The report as a fixed-width text table."""
        lines = [
            f"IMO MSC.137(76) manoeuvring criteria - {self.ship}",
            f"L = {self.L_m:.2f} m, test speed V = {self.V_kn:.2f} kn, L/V = {self.L_over_V_s:.2f} s",
            "",
            f"{'criterion':<28}{'side':<11}{'value':>9}{'limit':>9}  {'unit':<5}{'result':>7}",
            "-" * 71,
        ]
        for c in self.criteria:
            val = "   n/a" if c.value is None else f"{c.value:9.2f}"
            lines.append(
                f"{c.name:<28}{c.side:<11}{val:>9}{c.limit:9.2f}  {c.unit:<5}"
                f"{'PASS' if c.passed else 'FAIL':>7}" + (f"  ({c.note})" if c.note else "")
            )
        lines.append("-" * 71)
        lines.append(f"overall: {'PASS' if self.passed else 'FAIL'}")
        return "\n".join(lines)


def imo_report(ship: str | Ship) -> ImoReport:
    """Run every MSC.137(76) trial to both sides at the ship's test speed and evaluate the criteria."""
    s = load_ship(ship)
    L = s.particulars.L_m
    V = s.particulars.test_speed_kn
    LV = L / (V * KNOT_M_S)
    os1, os2 = zigzag10_limits(LV)
    turn_rudder = min(35.0, s.steering_gear.max_angle_deg)
    crit: list[Criterion] = []
    trials: dict = {}
    sides = (("starboard", 1.0), ("port", -1.0))

    for side, sg in sides:
        try:
            tc = turning_circle(s, sg * turn_rudder, until_deg=360.0)
            trials[f"turning_{side}"] = tc
            crit.append(Criterion("advance", side, tc.advance_m / L, 4.5, "L"))
            crit.append(Criterion("tactical_diameter", side, tc.tactical_diameter_m / L, 5.0, "L"))
        except ManoeuvreIncomplete as exc:
            crit.append(Criterion("advance", side, None, 4.5, "L", str(exc)))
            crit.append(Criterion("tactical_diameter", side, None, 5.0, "L", str(exc)))
    for side, sg in sides:
        try:
            it = initial_turning(s, sg * 10.0)
            trials[f"initial_turning_{side}"] = it
            crit.append(Criterion("initial_turning", side, it.distance_m / L, 2.5, "L"))
        except ManoeuvreIncomplete as exc:
            crit.append(Criterion("initial_turning", side, None, 2.5, "L", str(exc)))
    for angle, limits in ((10.0, (os1, os2)), (20.0, (25.0,))):
        for side, sg in sides:
            names = [f"zigzag_{angle:.0f}_first_overshoot", f"zigzag_{angle:.0f}_second_overshoot"][
                : len(limits)
            ]
            try:
                z = zigzag(s, sg * angle, angle, n_overshoots=len(limits))
                trials[f"zigzag_{angle:.0f}_{side}"] = z
                for k, (nm, lim) in enumerate(zip(names, limits)):
                    val = z.overshoot_deg[k] if k < len(z.overshoot_deg) else None
                    crit.append(
                        Criterion(nm, side, val, lim, "deg", "" if val is not None else "not reached")
                    )
            except ManoeuvreIncomplete as exc:
                for nm, lim in zip(names, limits):
                    crit.append(Criterion(nm, side, None, lim, "deg", str(exc)))
    try:
        st = stopping(s)
        trials["stopping"] = st
        crit.append(Criterion("stopping_track_reach", "ahead", st.track_reach_m / L, 15.0, "L"))
    except ManoeuvreIncomplete as exc:
        crit.append(Criterion("stopping_track_reach", "ahead", None, 15.0, "L", str(exc)))
    return ImoReport(s.name, L, V, crit, trials)
