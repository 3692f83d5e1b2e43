"""Debriefs of the tasks people drive (``play``, ``serve``): what a run's last ``info`` and the task's records
say, in a person's words. Nothing here judges: the berthing figures are the task's info, the COLREG checks are
:mod:`~vessel_gym.envs.tasks.colreg_rules`' ``pair_checks`` on the task's pair records.

- Berthing: outcome and why, the first contact's speed against PIANC's limit, the energy each fender absorbed
  against its rating, the final pose on the berth, thruster/tug effort and a score (:func:`berthing_debrief`).
- CollisionAvoidance: per encounter (each target of the own ship's encounter) the situation classified at
  detection, the rule checks (rules 8 and 13-17, with the task's thresholds), the reaction delay and the closest
  range; then the episode's figures (:func:`colreg_debrief`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vessel_gym.envs.tasks.berthing import OUTCOMES
from vessel_gym.envs.tasks.colreg_columns import P
from vessel_gym.envs.tasks.colreg_geometry import SAFE, SITUATIONS
from vessel_gym.envs.tasks.colreg_rules import R, pair_checks, reaction_delay


@dataclass
class BerthingDebrief:
    """The result of one berthing run: outcome and why, the first contact's speed against PIANC's limit, the
    energy each fender absorbed against its rating, the final pose on the berth."""

    scenario: str
    berth: str
    outcome: str  # success, fender_overload, contact_speed, contact, grounding, ..., quit, max_steps
    reason: str
    time_s: float
    steps: int
    contact_speed_m_s: float  # 0 if it never touched
    contact_speed_limit_m_s: float
    fender_energy_kJ: list[float]
    fender_rated_energy_kJ: float
    along_error_m: float
    off_error_m: float
    heading_error_deg: float
    assist_effort: float
    start_distance_m: float
    final_distance_m: float
    score: float  # 0..100
    track_png: str | None = None
    track: list[tuple[float, float]] = field(default_factory=list, repr=False)

    @property
    def max_fender_fraction(self) -> float:
        return max(self.fender_energy_kJ, default=0.0) / self.fender_rated_energy_kJ

    def items(self) -> list[tuple[str, str]]:
        """(label, value) rows of the debrief."""
        if self.contact_speed_m_s > 0.0:
            pct = 100.0 * self.contact_speed_m_s / self.contact_speed_limit_m_s
            contact = (
                f"{self.contact_speed_m_s:.3f} m/s, {pct:.0f} % of the PIANC limit "
                f"{self.contact_speed_limit_m_s:.3f} m/s"
            )
        else:
            contact = f"no contact (PIANC limit {self.contact_speed_limit_m_s:.3f} m/s)"
        energies = ", ".join(
            f"{e:.1f} ({100.0 * e / self.fender_rated_energy_kJ:.0f} %)" for e in self.fender_energy_kJ
        )
        rows = [
            ("scenario", f"{self.scenario}, {self.berth}"),
            ("outcome", f"{self.outcome}: {self.reason}"),
            ("time", f"{self.time_s:.1f} s ({self.steps} steps)"),
            ("contact speed", contact),
            ("fender energy", f"kJ of {self.fender_rated_energy_kJ:.0f} kJ rated: {energies}"),
            (
                "on the berth",
                f"{self.off_error_m:+.2f} m off, {self.along_error_m:+.1f} m along, "
                f"heading {self.heading_error_deg:+.1f} deg",
            ),
            ("thruster/tug effort", f"{self.assist_effort:.2f} (mean order^2)"),
            ("score", f"{self.score:.0f} / 100"),
        ]
        return rows + ([("track plot", self.track_png)] if self.track_png else [])

    def summary(self) -> str:
        """Human-readable debrief, one item per line."""
        return "\n".join(f"{label:20s}{value}" for label, value in self.items())


def berthing_score(
    outcome: str, contact_fraction: float, fender_fraction: float, start_m: float, final_m: float
) -> float:
    """Debrief score 0..100. Success: 50 + 25 x (1 - contact speed / PIANC limit) + 25 x (1 - the largest fender
    energy / its rating). Otherwise: 40 x the fraction of the distance to the berth made good, halved after a
    failure (touching too fast, fender overload, contact, grounding)."""
    if outcome == "success":
        return 50.0 + 25.0 * (1.0 - min(contact_fraction, 1.0)) + 25.0 * (1.0 - min(fender_fraction, 1.0))
    made_good = min(max(1.0 - final_m / max(start_m, 1e-9), 0.0), 1.0)
    # the task's failure outcomes (a time limit is none of them)
    failed = outcome in OUTCOMES and outcome not in ("running", "success")
    return 40.0 * made_good * (0.5 if failed else 1.0)


def berthing_reason(outcome: str, info: Mapping[str, Any]) -> str:
    v, lim = float(info["contact_speed_m_s"]), float(info["contact_speed_limit_m_s"])
    e, rated = np.asarray(info["fender_energy_kJ"], dtype=float), float(info["fender_rated_energy_kJ"])
    return {
        "success": "alongside within the tolerances, held",
        "fender_overload": f"fender {int(np.argmax(e)) + 1} absorbed {e.max():.0f} kJ, over its {rated:.0f} kJ",
        "contact_speed": f"first touch at {v:.3f} m/s, over the PIANC limit {lim:.3f} m/s",
        "contact": "the hull touched the quay or an obstacle away from the fenders",
        "grounding": "the hull over water shallower than its draught",
        "out_of_bounds": "left the chart",
        "diverged": "the hull model left its range",
        "quit": "ended by the player",
        "max_steps": "the step limit asked for",
        "time_limit": "not berthed in the time allowed",
    }.get(outcome, outcome)


def berthing_debrief(
    scenario: str,
    berth: str,
    outcome: str,
    steps: int,
    info: Mapping[str, Any],
    start_distance_m: float,
    track: list | None = None,
) -> BerthingDebrief:
    """The debrief of a berthing run that ended with ``outcome`` after ``steps`` steps, from the task's last
    ``info`` and the distance to the berth at the start (m): ``play``'s and ``serve``'s."""
    v, lim = float(info["contact_speed_m_s"]), float(info["contact_speed_limit_m_s"])
    rated = float(info["fender_rated_energy_kJ"])
    energy = [float(e) for e in np.asarray(info["fender_energy_kJ"], dtype=float).ravel()]
    final = float(np.hypot(info["along_error_m"], info["off_error_m"]))
    return BerthingDebrief(
        scenario=scenario,
        berth=berth,
        outcome=outcome,
        reason=berthing_reason(outcome, info),
        time_s=float(info["time_s"]),
        steps=steps,
        contact_speed_m_s=v,
        contact_speed_limit_m_s=lim,
        fender_energy_kJ=energy,
        fender_rated_energy_kJ=rated,
        along_error_m=float(info["along_error_m"]),
        off_error_m=float(info["off_error_m"]),
        heading_error_deg=float(info["heading_error_deg"]),
        assist_effort=float(info["assist_effort"]),
        start_distance_m=start_distance_m,
        final_distance_m=final,
        score=berthing_score(outcome, v / lim, max(energy, default=0.0) / rated, start_distance_m, final),
        track=list(track or []),
    )


#: how each situation reads in the debrief (SITUATIONS order)
SITUATION_TEXT = {
    "safe": "no risk of collision",
    "head_on": "head-on (rule 14)",
    "overtaking": "overtaking (rule 13)",
    "give_way": "crossing, give-way (rules 15, 16)",
    "stand_on": "crossing, stand-on (rule 17)",
    "overtaken": "being overtaken, stand-on (rules 13, 17)",
}


@dataclass(frozen=True)
class EncounterScore:
    """One target's encounter: its situation at detection, each check that applies (passed or not), the
    reaction delay (s, NaN without an action) and the closest centre distance since detection (m)."""

    target: str
    situation: str
    checks: dict[str, bool] = field(default_factory=dict)
    reaction_delay_s: float = math.nan
    min_range_m: float = math.nan

    @property
    def violation(self) -> bool:
        return not all(self.checks.values())

    def line(self, L: float) -> str:
        if self.situation == "safe":
            return f"{self.target}: {SITUATION_TEXT['safe']}"
        checks = ", ".join(f"{k} {'ok' if ok else 'FAILED'}" for k, ok in self.checks.items())
        delay = f"{self.reaction_delay_s:.0f} s" if math.isfinite(self.reaction_delay_s) else "no action"
        verdict = "VIOLATION" if self.violation else "kept the rules"
        return (
            f"{self.target}: {SITUATION_TEXT[self.situation]}: {checks}; reaction {delay}, closest "
            f"{self.min_range_m:.0f} m ({self.min_range_m / L:.1f} L): {verdict}"
        )


def encounter_scores(task: Any, k: int = 0) -> list[EncounterScore]:
    """Own ship k's encounters, one per target slot of its encounter that took part, from the task's pair
    records (read before the next reset clears them)."""
    world = task.world
    members = world.members[world.world_of[k]]
    p = task.p
    out = []
    for slot, j in enumerate(members):
        if j == k or not (slot < world.agents or world.active[j]):  # own ships take part even once they left
            continue
        row = task.pairs[k, slot]
        sit = int(row[R.situation])
        if k == 0:  # the served ship: every other ship is a target, named by its slot as the link names it
            name = f"target {slot}"
        elif slot >= world.agents:
            name = f"target {slot - world.agents + 1}"
        else:
            name = f"own ship {slot + 1}"
        if sit == SAFE:
            out.append(EncounterScore(name, "safe"))
            continue
        checks = pair_checks(
            row, p[P.early_fraction], p[P.substantial], p[P.stand_on_course], p[P.stand_on_speed]
        )
        out.append(
            EncounterScore(name, SITUATIONS[sit], checks, reaction_delay(row), float(row[R.min_range]))
        )
    return out


def colreg_debrief(task: Any, info: Mapping[str, Any], outcome: str) -> list[str]:
    """The debrief lines of own ship 0's run that ended with ``outcome``: the encounter, each target's scores,
    then the episode's COLREG score, minimum separation and path ratio, and in restricted waters the times in
    breach of rule 10 (a traffic-separation scheme) or rule 9 (a narrow channel)."""
    L = task.L
    lines = [f"COLREG debrief: {info.get('scenario', '')}, {outcome}"]
    lines += ["  " + e.line(L) for e in encounter_scores(task, 0)]
    checks = int(info.get("colreg_checks", 0))
    lines.append(
        f"  score {float(info.get('colreg_score', 1.0)):.2f} ({checks} checks, "
        f"{int(info.get('colreg_violations', 0))} encounter(s) in violation); min separation "
        f"{float(info.get('min_separation_m', math.nan)):.0f} m ({float(info.get('min_separation_L', math.nan)):.1f} L); "
        f"path ratio {float(info.get('path_ratio', math.nan)):.2f}"
    )
    g = lambda k: float(info.get(k, 0.0))  # noqa: E731
    if info.get("tss_scored"):  # restricted waters: the times in breach of rules 10 and 9
        lines.append(
            f"  rule 10: {g('tss_zone_s'):.0f} s in the separation zone, {g('tss_wrong_lane_s'):.0f} s in the "
            f"opposite lane, {g('tss_against_flow_s'):.0f} s against the flow"
        )
    if info.get("channel_scored"):
        lines.append(
            f"  rule 9: {g('rule9_port_side_s'):.0f} s on the channel's port half (9(a)), "
            f"{g('rule9_crossing_s'):.0f} s crossing in the way of a ship in it (9(d)), "
            f"{g('rule9_close_overtake_s'):.0f} s overtaking too close (9(e))"
        )
    return lines
