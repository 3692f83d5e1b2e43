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

Rule 9 (narrow channels) is scored per control step by :func:`narrow_channel` (time in breach, as rule 10 is).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from vessel_gym.control.angles import wrap_pi
from vessel_gym.envs.declare import columns
from vessel_gym.envs.tasks.colreg_columns import CHECKS, SC, P
from vessel_gym.envs.tasks.colreg_geometry import (
    GIVE_WAY,
    GIVE_WAY_ROLES,
    HEAD_ON,
    OVERTAKING,
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


#: the rule 9 breaches :func:`narrow_channel` reports, in its order
RULE9 = ("port_side", "crossing", "close_overtake")


def narrow_channel(
    offset: float,
    heading_off: float,
    others: list[tuple[float, float, float, float, float, int]],
    half_m: float,
    along_rad: float,
    risk_m: float,
    pass_m: float,
) -> tuple[bool, bool, bool]:
    """Which parts of COLREG Rule 9 (narrow channels) the own ship breaches at this moment, as
    (``port_side``, ``crossing``, ``close_overtake``) (:data:`RULE9`).

    The channel is straight: ``offset`` (m) is the own ship's midship point to starboard of the channel's centre
    line as seen looking along the channel's direction, ``heading_off`` (rad) its heading less that direction;
    the channel reaches ``half_m`` to either side of the centre line. A ship heads *along* the channel when its
    heading is within ``along_rad`` of the direction or of its reciprocal. ``others``: per other ship
    (offset m, heading_off rad, DCPA m, TCPA s, range m, the own ship's situation towards it, a
    :data:`~.colreg_geometry.SITUATIONS` index).

    * ``port_side``, 9(a): "A vessel proceeding along the course of a narrow channel or fairway shall keep as
      near to the outer limit of the channel or fairway which lies on her starboard side as is safe and
      practicable." Breached while the own ship, in the channel and heading along it, has its midship point
      on the half of the channel to its port side (measured: the half, a weaker reading of "as near to the
      outer limit ... as is safe and practicable", which the model cannot judge).
    * ``crossing``, 9(d): "A vessel shall not cross a narrow channel or fairway if such crossing impedes the
      passage of a vessel which can safely navigate only within such channel or fairway." Breached while the
      own ship, in the channel, heads across it (not along) and a ship in the channel heading along it has
      a risk of collision with it (DCPA below ``risk_m``, TCPA > 0): its crossing impedes that ship.
    * ``close_overtake``, 9(e)(i): "In a narrow channel or fairway when overtaking can take place only if the
      vessel to be overtaken has to take action to permit safe passing, the vessel intending to overtake
      shall indicate her intention by sounding the appropriate signal ... The vessel to be overtaken shall,
      if in agreement, ... take steps to permit safe passing." The model has no sound signals, so no such
      agreement can be had: breached while the own ship, overtaking a ship in the channel (rule 13), is
      closer to it than ``pass_m`` centre to centre (our reading: a pass that close needs the overtaken
      ship's room). 9(e)(ii) keeps rule 13 (scored by :func:`pair_checks`).

    Rules 9(b) and (c) (small, sailing and fishing vessels) do not apply to the simulated ships; 9(f) and
    (g) (bends, anchoring) have nothing to score in a straight channel where nobody anchors.
    """
    if abs(offset) > half_m:  # outside the channel: rule 9 does not speak of it
        return False, False, False
    ahead = abs(heading_off) <= along_rad
    back = abs(heading_off) >= math.pi - along_rad
    port_side = (ahead and offset < 0.0) or (back and offset > 0.0)
    crossing = False
    close = False
    for o_off, o_head, dcpa, tcpa, rng, situation in others:
        if abs(o_off) > half_m:
            continue
        o_along = abs(o_head) <= along_rad or abs(o_head) >= math.pi - along_rad
        if not (ahead or back) and o_along and dcpa < risk_m and tcpa > 0.0:
            crossing = True
        if situation == OVERTAKING and rng < pass_m:
            close = True
    return port_side, crossing, close


def episode_metrics(infos: list, terminated: bool) -> dict[str, Any]:
    """An episode's outcome and COLREG scores from its last ``info``: success and collision (0/1), the
    closest range (m, ship lengths), path ratio, rudder reversals, the COLREG score, whether a pair violated
    a rule, the mean reaction delay (s; NaN without an alteration) and each check's pass fraction (NaN where
    it never applied)."""
    last = infos[-1]
    out: dict[str, Any] = {
        "success": float(last["success"]),
        "collision": float(last["collision"]),
        "grounding": float(last["grounding"]),
        "min_separation_m": last["min_separation_m"],
        "min_separation_L": last["min_separation_L"],
        "path_ratio": last["path_ratio"],
        "rudder_reversals": last["rudder_reversals"],
        "colreg_score": last["colreg_score"] if last["colreg_checks"] else math.nan,
        "colreg_violation": float(last["colreg_violations"] > 0),
        "reaction_delay_s": last["reaction_delay_s"] if last["reaction_delay_s"] >= 0.0 else math.nan,
    }
    for c in CHECKS:
        n = last["colreg_applied"][c]
        out[f"{c}_ok"] = last["colreg_passed"][c] / n if n else math.nan
    if last.get("tss_scored"):  # rule 10 in a traffic-separation scheme
        times = [last["tss_zone_s"], last["tss_wrong_lane_s"], last["tss_against_flow_s"]]
        out["tss_zone_s"], out["tss_wrong_lane_s"], out["tss_against_flow_s"] = times
        out["rule10_violation"] = float(any(t > 0.0 for t in times))
    if last.get("channel_scored"):  # rule 9 in a narrow channel
        times = [last[f"rule9_{b}_s"] for b in RULE9]
        out.update({f"rule9_{b}_s": t for b, t in zip(RULE9, times)})
        out["rule9_violation"] = float(any(t > 0.0 for t in times))
    return out
