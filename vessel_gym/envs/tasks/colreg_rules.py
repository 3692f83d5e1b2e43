"""COLREG scores of an encounter: what the own ship did about each target, judged by rules 8 and 13-17.

Every (own ship, target) pair keeps a record (:data:`R` columns of a row) from the step the target is
detected as a risk of collision (its situation fixed then, :func:`~.colreg_geometry.classify`) until the
episode ends: the own ship's course and speed at detection, its first course alteration of at least
``action_deg`` (time, side, TCPA then), its largest alterations to either side, the closest range and whether
it was then ahead of the target, and, for a stand-on role, how far it left its course and speed while the
range was above ``release_range_L`` and the CPA ahead. :func:`pair_checks` turns a record into the rule checks that apply:

| check | applies to | passes when |
|---|---|---|
| ``early`` | head-on, crossing give-way, overtaking | the action begins with TCPA >= ``early_tcpa_fraction`` x TCPA at detection (rules 8(a), 16) |
| ``substantial`` | same | the alteration to the action's side reaches ``substantial_deg`` (rule 8(b), "readily apparent") |
| ``starboard`` | head-on, crossing give-way | the first alteration is to starboard (rules 14(a), 15 with 8) |
| ``not_ahead`` | crossing give-way | at the closest range the own ship is abaft the target's beam (rule 15: not crossing ahead) |
| ``stand_on`` | crossing stand-on, being overtaken | course within ``stand_on_tolerance_deg`` and speed within ``stand_on_speed_fraction`` until the range is below ``release_range_L`` (rule 17(a)(i)) |
| ``no_port`` | crossing stand-on | an alteration, if any, is not to port (rule 17(c): the target is on the own port side) |

A give-way role without any alteration fails ``early``, ``substantial`` and ``starboard``. A pair violates the
rules when any of its checks fails.
"""

from __future__ import annotations

import math

import numpy as np

from vessel_gym.control.angles import wrap_pi
from vessel_gym.envs.declare import columns
from vessel_gym.envs.tasks.colreg_columns import CHECKS, SC, P
from vessel_gym.envs.tasks.colreg_geometry import (
    GIVE_WAY,
    GIVE_WAY_ROLES,
    HEAD_ON,
    SAFE,
    STAND_ON,
    STAND_ON_ROLES,
)

#: the columns of a pair's record (NaN: not yet)
R = columns(
    "situation",  # SITUATIONS index, fixed at detection (SAFE until then)
    "t_detect",  # s
    "psi_detect",  # rad, own heading at detection
    "U_detect",  # m/s, own speed at detection
    "tcpa_detect",  # s
    "t_action",  # s, first alteration of at least action_deg from psi_detect
    "action_side",  # +1 starboard, -1 port
    "action_tcpa",  # s, TCPA to this target at the action
    "max_stbd",  # rad, largest alteration to starboard of psi_detect
    "max_port",  # rad, largest alteration to port
    "min_range",  # m, closest centre distance since detection
    "ahead_at_cpa",  # 1: own ship forward of the target's beam at the closest range
    "stand_on_dev",  # rad, largest |alteration| while the range was above the release range
    "stand_on_speed_dev",  # largest |speed change| / U_detect then
    "released",  # 1 once the range has fallen below the release range (or the CPA has passed)
    typename="PairRecord",
)


def new_record(row: np.ndarray) -> None:
    """Clear a pair's record: not detected yet."""
    row[:] = math.nan
    row[R.situation] = SAFE


def detect(row: np.ndarray, situation: int, t: float, psi: float, U: float, rng: float, tcpa: float) -> None:
    """The target is detected as a risk in ``situation`` at time ``t`` (s), the own ship on ``psi`` (rad) at
    ``U`` (m/s), range ``rng`` (m), TCPA ``tcpa`` (s)."""
    row[R.situation] = situation
    row[R.t_detect] = t
    row[R.psi_detect] = psi
    row[R.U_detect] = U
    row[R.tcpa_detect] = tcpa
    row[R.max_stbd] = 0.0
    row[R.max_port] = 0.0
    row[R.min_range] = rng
    row[R.ahead_at_cpa] = 0.0
    row[R.stand_on_dev] = 0.0
    row[R.stand_on_speed_dev] = 0.0
    row[R.released] = 0.0


def track(
    row: np.ndarray,
    t: float,
    psi: float,
    U: float,
    rng: float,
    tcpa: float,
    ahead: bool,
    action_rad: float,
    release_m: float,
) -> None:
    """One step of a detected pair: the own ship on ``psi`` at ``U``, the target at range ``rng`` with
    ``tcpa``; ``ahead``: the own ship is forward of the target's beam now; ``action_rad``: the alteration that
    counts as an action; ``release_m``: the range below which a stand-on ship may act (rule 17(a)(ii), (b)):
    its departures from course and speed count until the range first falls below it or the CPA passes."""
    dev = wrap_pi(psi - row[R.psi_detect])
    row[R.max_stbd] = max(row[R.max_stbd], dev)
    row[R.max_port] = max(row[R.max_port], -dev)
    if math.isnan(row[R.t_action]) and abs(dev) >= action_rad:
        row[R.t_action] = t
        row[R.action_side] = 1.0 if dev > 0.0 else -1.0
        row[R.action_tcpa] = tcpa
    if rng < row[R.min_range]:
        row[R.min_range] = rng
        row[R.ahead_at_cpa] = 1.0 if ahead else 0.0
    if rng <= release_m or tcpa <= 0.0:  # rule 17(a)(ii), (b): from here the stand-on ship may act
        row[R.released] = 1.0
    if row[R.released] == 0.0:
        row[R.stand_on_dev] = max(row[R.stand_on_dev], abs(dev))
        du = abs(U - row[R.U_detect]) / max(row[R.U_detect], 1e-9)
        row[R.stand_on_speed_dev] = max(row[R.stand_on_speed_dev], du)


def pair_checks(
    row: np.ndarray, early_fraction: float, substantial_rad: float, stand_on_rad: float, stand_on_speed: float
) -> dict[str, bool]:
    """The checks that apply to a pair's record, each passed or not (empty for a pair never at risk)."""
    sit = int(row[R.situation])
    out: dict[str, bool] = {}
    acted = not math.isnan(row[R.t_action])
    side = row[R.action_side] if acted else 0.0
    if sit in GIVE_WAY_ROLES:
        out["early"] = acted and row[R.action_tcpa] >= early_fraction * row[R.tcpa_detect]
        reach = row[R.max_stbd] if side > 0 else row[R.max_port]
        if sit not in (HEAD_ON, GIVE_WAY):  # overtaking: either side
            reach = max(row[R.max_stbd], row[R.max_port])
        out["substantial"] = acted and reach >= substantial_rad
        if sit in (HEAD_ON, GIVE_WAY):
            out["starboard"] = side > 0
        if sit == GIVE_WAY:
            out["not_ahead"] = row[R.ahead_at_cpa] < 0.5
    elif sit in STAND_ON_ROLES:
        out["stand_on"] = bool(
            row[R.stand_on_dev] <= stand_on_rad and row[R.stand_on_speed_dev] <= stand_on_speed
        )
        if sit == STAND_ON:
            out["no_port"] = side >= 0
    return {k: bool(v) for k, v in out.items()}


def reaction_delay(row: np.ndarray) -> float:
    """Seconds from detection to the first alteration (NaN without either)."""
    return float(row[R.t_action] - row[R.t_detect])


def score_row(pairs: np.ndarray, out: np.ndarray, p: np.ndarray) -> None:
    """A vessel's COLREG scores so far (``out``, columns :data:`~.colreg_columns.SC`) from its pair records
    ``pairs`` (one row per slot of its encounter), the rule thresholds in the parameter row ``p``."""
    out[:] = 0.0
    delays = []
    for row in pairs:
        if row[R.situation] != SAFE and not math.isnan(row[R.t_action]):
            delays.append(reaction_delay(row))
        checks = pair_checks(
            row, p[P.early_fraction], p[P.substantial], p[P.stand_on_course], p[P.stand_on_speed]
        )
        for name, ok in checks.items():
            out[getattr(SC, f"applied_{name}")] += 1.0
            out[getattr(SC, f"passed_{name}")] += float(ok)
        out[SC.violations] += float(not all(checks.values()))
    out[SC.checks] = sum(out[getattr(SC, f"applied_{c}")] for c in CHECKS)
    passed = sum(out[getattr(SC, f"passed_{c}")] for c in CHECKS)
    out[SC.score] = passed / out[SC.checks] if out[SC.checks] else 1.0
    out[SC.delay] = sum(delays) / len(delays) if delays else -1.0
