"""The encounters of CollisionAvoidance: the 22 Imazu cases and a seeded generator that works back from a
situation type, DCPA and TCPA.

An encounter is the own ship's start (origin, heading 0, test speed) and its targets, each a start position
(north, east, m), heading (rad) and speed (m/s), all keeping course and speed (constant-velocity targets).

**Imazu (1987).** H. Imazu, "Research on collision avoidance manoeuvre" (in Japanese), 1987: 22 encounters of
one own ship with one to three targets, the standard benchmark set of ship collision avoidance. The
definitions here follow the encoding by Sawada, Sato and Majima (2021), "Automatic ship collision avoidance
using deep reinforcement learning with LSTM in continuous action spaces", J. Mar. Sci. Technol. 26, 509-524,
as published in the open-source TUD_RL environments (github.com/MarWaltz/TUD_RL,
``tud_rl/envs/_envs/MMG_Imazu.py``: "the 22 ship encounter situations of Imazu (1987) as detailed in Sawada et
al. (2021)"): the own ship steers north; every target is on a collision course, all ships reaching the same
point at the same time TCPA; the targets the own ship overtakes run at the encoding's shaft-speed ratio 0.7 /
1.8 of the others, here 0.4 of the speed. That encoding makes cases 5 and 8, and 15 and 22, the same (the
original figures differ in the targets' offsets, which it does not carry). Scaled to the own ship: it
reaches the meeting point after ``tcpa_L`` of its lengths at its test speed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vessel_gym.envs.tasks.colreg_geometry import (
    GIVE_WAY,
    HEAD_ON,
    OVERTAKING,
    STAND_ON,
    classify,
    cpa,
)

#: target headings of each Imazu case, deg (own ship heading 0); a heading marked "s" is a slow target
IMAZU: dict[int, tuple[str, ...]] = {
    1: ("180",),
    2: ("270",),
    3: ("0s",),
    4: ("45",),
    5: ("180", "270"),
    6: ("350", "315"),
    7: ("0s", "315"),
    8: ("180", "270"),
    9: ("330", "270"),
    10: ("270", "15"),
    11: ("90", "330"),
    12: ("180", "315", "350"),
    13: ("180", "10", "45"),
    14: ("350", "315", "270"),
    15: ("0s", "315", "270"),
    16: ("45", "90", "270"),
    17: ("0s", "10", "315"),
    18: ("225", "345", "330"),
    19: ("15", "345", "225"),
    20: ("0s", "345", "270"),
    21: ("345", "15", "270"),
    22: ("0s", "315", "270"),
}
#: speed of a slow (overtaken) Imazu target as a fraction of the own ship's: the encoding's 0.7 / 1.8 shaft speed
SLOW = 0.4
#: the situation types the generator draws, with their ranges of target course relative to the own ship's
#: (deg) and target speed as a fraction of the own ship's; the classification of the drawn start must agree
#: (rules 13-15, colreg_geometry.classify). A target faster than the own ship (overtaken) is not generated:
#: the steady start of the same ship above its test speed is beyond its engine.
GENERATED = {
    "head_on": (HEAD_ON, (174.0, 186.0), (0.5, 1.0)),
    "overtaking": (OVERTAKING, (-20.0, 20.0), (0.2, 0.6)),
    "give_way": (GIVE_WAY, (190.0, 340.0), (0.5, 1.0)),
    "stand_on": (STAND_ON, (20.0, 170.0), (0.5, 1.0)),
}


@dataclass(frozen=True)
class Target:
    """A target's start: position (north, east, m), heading (rad), speed (m/s) and the situation the
    encounter was drawn as (``SITUATIONS`` index; Imazu: classified from the start)."""

    n: float
    e: float
    psi: float
    speed: float
    situation: int


@dataclass(frozen=True)
class Encounter:
    """An encounter: its name (``imazu:12``, ``generated:head_on``), the own ship's start (origin, heading 0,
    ``speed`` m/s), its targets and the CPA each was planned with (DCPA m, TCPA s, own and target keeping
    course and speed)."""

    name: str
    speed: float
    targets: tuple[Target, ...]
    planned_cpa: tuple[tuple[float, float], ...]
    goal: tuple[float, float] | None = None  # the own ship's goal (north, east, m); None: ahead on its course


def planned_cpa(t_n: float, t_e: float, psi: float, speed: float, own_speed: float) -> tuple[float, float]:
    """(DCPA m, TCPA s) of a target at (``t_n``, ``t_e``) m on ``psi`` rad at ``speed`` m/s from the own ship at
    the origin heading north at ``own_speed`` m/s, both keeping course and speed."""
    return cpa(t_n, t_e, speed * math.cos(psi) - own_speed, speed * math.sin(psi))


def imazu(
    case: int, L: float, U: float, tcpa_L: float, rng: np.random.Generator, jitter: tuple[float, float]
) -> Encounter:
    """Imazu case ``case`` (1..22) for an own ship of length ``L`` (m) and speed ``U`` (m/s) reaching the
    meeting point after ``tcpa_L`` lengths. ``jitter`` (heading deg, speed fraction): each target's heading and
    speed drawn uniformly within +- these of the case's (zero: the case exactly, no draw); the start is still
    worked back from the meeting point, so a jittered target meets the own ship near it."""
    if case not in IMAZU:
        raise ValueError(f"Imazu case {case} does not exist (1..22)")
    T = tcpa_L * L / U  # s to the meeting point
    meet_n = U * T  # the own ship starts at the origin heading north
    targets, planned = [], []
    for code in IMAZU[case]:
        heading = math.radians(float(code.rstrip("s")))
        speed = U * (SLOW if code.endswith("s") else 1.0)
        dh, ds = jitter
        if dh > 0.0 or ds > 0.0:
            heading += math.radians(rng.uniform(-dh, dh))
            speed *= 1.0 + rng.uniform(-ds, ds)
        n = meet_n - speed * math.cos(heading) * T
        e = -speed * math.sin(heading) * T
        d, t = planned_cpa(n, e, heading, speed, U)
        targets.append(Target(n, e, heading, speed, classify(n, e, 0.0, heading, True)))
        planned.append((d, t))
    return Encounter(f"imazu:{case}", U, tuple(targets), tuple(planned))


def generate(
    situations: tuple[str, ...],
    dcpa_m: tuple[float, ...],
    tcpa_s: tuple[float, ...],
    U: float,
    rng: np.random.Generator,
    tries: int = 200,
) -> Encounter:
    """An encounter worked back from each target's situation type (``GENERATED`` key), DCPA (m, >= 0) and
    TCPA (s, > 0): the target's course and speed are drawn from the type's ranges, the side of the passing
    (DCPA to port or starboard of the relative track) at random, and its start is the point from which,
    both ships keeping course and speed, it passes at that DCPA after that TCPA. A start whose situation
    (classified as the task does) is not the one asked is drawn again (at most ``tries`` times, then
    ValueError). The planned CPA is computed again from the start (it equals the one asked to rounding)."""
    targets, planned = [], []
    for name, d, t in zip(situations, dcpa_m, tcpa_s):
        if name not in GENERATED:
            raise ValueError(f"no generated situation {name!r} (have: {', '.join(GENERATED)})")
        want, course, speed_ratio = GENERATED[name]
        for _ in range(tries):
            psi = math.radians(rng.uniform(*course))
            speed = U * rng.uniform(*speed_ratio)
            side = 1.0 if rng.random() < 0.5 else -1.0
            wn, we = speed * math.cos(psi) - U, speed * math.sin(psi)  # target - own, m/s
            w = math.hypot(wn, we)
            if w < 1e-6:
                continue
            # at the CPA the relative position is normal to the relative velocity, DCPA long
            cn, ce = -we / w * d * side, wn / w * d * side
            n, e = cn - wn * t, ce - we * t
            if classify(n, e, 0.0, psi, True) == want:
                targets.append(Target(n, e, psi, speed, want))
                planned.append(planned_cpa(n, e, psi, speed, U))
                break
        else:
            raise ValueError(f"no {name} start found for DCPA {d:g} m, TCPA {t:g} s in {tries} draws")
    label = "+".join(situations)
    return Encounter(f"generated:{label}", U, tuple(targets), tuple(planned))


#: the traffic of a two-lane scheme (``lanes``): per type, the target's course relative to the own ship's
#: (deg), its speed as a fraction of the own ship's and its lateral offset from the own ship's track line
#: (ship lengths; ``opposing``: about the opposite lane's centre line)
LANES = {
    "overtaking": (0.0, (0.3, 0.5), (-0.5, 0.5)),  # a slow ship ahead in the own lane
    "opposing": (180.0, (0.5, 1.0), (-1.5, 1.5)),  # a ship in the opposite lane, on the reciprocal course
}


def lanes(
    types: tuple[str, ...],
    tcpa_s: tuple[float, ...],
    U: float,
    L: float,
    opposite_m: float,
    rng: np.random.Generator,
    spread: float = 1.0,
) -> Encounter:
    """Traffic in a two-lane scheme: the own ship at the origin heading north in its lane at ``U`` m/s; per
    target of ``types`` (``LANES`` key) a ship in the own lane ahead (``overtaking``) or in the opposite lane,
    whose centre line is ``opposite_m`` m to port, on the reciprocal course (``opposing``), with its course,
    speed and lateral offset drawn from the type's ranges (the offset's times ``spread``) and its start where it comes abeam of the own ship
    (both keeping course and speed) after ``tcpa_s`` s."""
    targets, planned = [], []
    for name, t in zip(types, tcpa_s):
        if name not in LANES:
            raise ValueError(f"no lane traffic {name!r} (have: {', '.join(LANES)})")
        course, speed_ratio, offset_L = LANES[name]
        psi = math.radians(course)
        speed = U * rng.uniform(*speed_ratio)
        e = spread * rng.uniform(*offset_L) * L - (opposite_m if name == "opposing" else 0.0)
        n = (U - speed * math.cos(psi)) * t  # closing speed along the lanes x time to come abeam
        d, tc = planned_cpa(n, e, psi, speed, U)
        targets.append(Target(n, e, psi, speed, classify(n, e, 0.0, psi, True)))
        planned.append((d, tc))
    return Encounter("lanes:" + "+".join(types), U, tuple(targets), tuple(planned))
