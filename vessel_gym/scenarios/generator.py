"""Seeded procedural harbours: entrance width and position, breakwater layout, basin, pier and shoal.

``generate_harbour(seed)`` draws one layout from ``numpy.random.default_rng(seed)`` and returns a
:class:`~vessel_gym.scenarios.Scenario` built and checked by the same schema and geometric checks as a
scenario file (:func:`~vessel_gym.scenarios.scenario.validate`), so a generated harbour is as valid as a
built-in one. Sizes are in ship lengths L of the scenario's ship, so the same seed gives the same layout
in ship lengths for any ship.

Seeds are split so that layouts used for evaluation are never seen in training: ``TRAIN_SEEDS`` for
training, ``EVAL_SEEDS`` (disjoint) held out for evaluation only (docs/scenarios.md).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from vessel_gym.physics.schema import SpecError, build
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.scenarios.scenario import Scenario, ScenarioError, validate

#: generator seeds of the training layouts
TRAIN_SEEDS = range(0, 1_000_000)
#: generator seeds of the held-out evaluation layouts (disjoint from TRAIN_SEEDS)
EVAL_SEEDS = range(1_000_000, 1_100_000)
SPLITS = {"train": TRAIN_SEEDS, "eval": EVAL_SEEDS}

#: breakwater layouts: arms in one line, arms angled so their heads point into the harbour (north), or out
LAYOUTS = ("straight", "angled_in", "angled_out")


def split_seed(split: str, index: int = 0) -> int:
    """The ``index``-th generator seed of ``split`` ("train" or "eval")."""
    if split not in SPLITS:
        raise ScenarioError(f"layout_split: expected one of {sorted(SPLITS)}, got {split!r}")
    seeds = SPLITS[split]
    if not 0 <= index < len(seeds):
        raise ScenarioError(f"layout index: expected 0..{len(seeds) - 1}, got {index}")
    return seeds[index]


def seed_split(seed: int) -> str:
    """The split a generator seed belongs to; raises ScenarioError for a seed in neither."""
    for name, seeds in SPLITS.items():
        if seed in seeds:
            return name
    raise ScenarioError(
        f"layout_seed: {seed} is in neither split (train {TRAIN_SEEDS.start}..{TRAIN_SEEDS.stop - 1}, "
        f"eval {EVAL_SEEDS.start}..{EVAL_SEEDS.stop - 1})"
    )


def _rect(n0: float, n1: float, e0: float, e1: float) -> list[list[float]]:
    return [[n0, e0], [n1, e0], [n1, e1], [n0, e1]]


def harbour_table(seed: int, ship: str = "kvlcc2_l7") -> dict[str, Any]:
    """The scenario table (as a scenario file would hold it) of generated layout ``seed``."""
    rng = np.random.default_rng(seed)
    s = load_ship(ship)
    L = s.particulars.L_m
    U = s.test_speed_m_s
    r = lambda v: round(float(v), 3)  # noqa: E731 - millimetre coordinates keep the tables readable

    # chart: open water south of the breakwater line (north = 0), basin to the north (sizes in L)
    Hb = rng.uniform(6.5, 9.0) * L  # basin half width: shores at east = -Hb, +Hb
    Nb = rng.uniform(9.0, 12.0) * L  # north quay face
    n_min, n_max, e_min, e_max = -20.0 * L, Nb + 2.0 * L, -14.0 * L, 14.0 * L
    W = rng.uniform(2.0, 3.5) * L  # entrance width (the v0 harbour: 2.4 L)
    ce = rng.uniform(-3.0, 3.0) * L  # entrance centre, east
    layout = LAYOUTS[int(rng.integers(len(LAYOUTS)))]
    tip = {"straight": 0.0, "angled_in": rng.uniform(0.8, 2.0), "angled_out": -rng.uniform(0.8, 2.0)}[layout]
    tip *= L
    th = 0.2 * L  # breakwater half thickness
    ge = rng.uniform(-2.5, 2.5) * L  # goal centre, east
    gn = Nb - 2.5 * L  # goal centre, north
    land = [
        # the coast recedes south of the breakwaters, leaving open water for the approach
        {
            "name": "west shore",
            "points": [[n_min, e_min], [n_max, e_min], [n_max, -Hb], [0.0, -Hb], [n_min, -12.0 * L]],
        },
        {
            "name": "east shore",
            "points": [[n_min, e_max], [n_min, 12.0 * L], [0.0, Hb], [n_max, Hb], [n_max, e_max]],
        },
        {"name": "north shore", "points": _rect(Nb + 0.6 * L, n_max, -Hb - L, Hb + L)},
    ]
    bw = [
        {
            "name": "west breakwater",
            "points": [[-th, -Hb - L], [th, -Hb - L], [tip + th, ce - W / 2], [tip - th, ce - W / 2]],
        },
        {
            "name": "east breakwater",
            "points": [[-th, Hb + L], [tip - th, ce + W / 2], [tip + th, ce + W / 2], [th, Hb + L]],
        },
    ]
    quay = [{"name": "north quay", "points": _rect(Nb, Nb + 0.6 * L, -0.7 * Hb, 0.7 * Hb)}]
    # a pier from one shore, ending 2 L short of the track (entrance -> goal) so the basin stays navigable
    side = 1.0 if rng.random() < 0.5 else -1.0
    pn = rng.uniform(0.35, 0.6) * Nb
    if side < 0:
        tip_e = min(ce, ge) - 2.0 * L
        length = tip_e + Hb
    else:
        tip_e = max(ce, ge) + 2.0 * L
        length = Hb - tip_e
    length = min(length, rng.uniform(2.5, 5.0) * L)
    if length >= 1.5 * L:
        root = side * Hb
        quay.append(
            {
                "name": "pier",
                "points": _rect(pn - 0.4 * L, pn + 0.4 * L, *sorted((root, root - side * length))),
            }
        )
    # a shoal (shallower than the draught) on the other side, inside the basin and clear of the track
    depth = [
        {"name": "harbour basin", "depth_m": r(2.6 * s.particulars.T_m), "points": _rect(th, Nb, -Hb, Hb)}
    ]
    sn0 = rng.uniform(0.15, 0.3) * Nb
    sn1 = sn0 + rng.uniform(1.5, 3.0) * L
    if side < 0:
        e_in = max(ce, ge) + 2.0 * L
        e_out = Hb
    else:
        e_in = min(ce, ge) - 2.0 * L
        e_out = -Hb
    if abs(e_out - e_in) >= 1.0 * L:
        lo_e, hi_e = sorted((e_in, e_out))
        depth.append(
            {"name": "shoal", "depth_m": r(0.6 * s.particulars.T_m), "points": _rect(sn0, sn1, lo_e, hi_e)}
        )
    table: dict[str, Any] = {
        "name": f"procedural-{seed}",
        "description": (
            f"Generated harbour (seed {seed}): {layout} breakwaters, entrance {W / L:.1f} L wide at "
            f"{ce / L:+.1f} L east, basin {2 * Hb / L:.1f} L x {Nb / L:.1f} L."
        ),
        "ship": ship,
        "reference_latlon_deg": [54.33, 10.15],
        "water_depth_m": r(4.3 * s.particulars.T_m),
        "bounds_m": [r(n_min), r(n_max), r(e_min), r(e_max)],
        "route_m": [[r(-4.0 * L), r(ce)], [r(max(tip, 0.0) + 3.0 * L), r(ce)]],
        "land": land,
        "breakwater": bw,
        "quay": quay,
        "depth_area": depth,
        "start": {
            "points": _rect(-17.0 * L, -11.0 * L, ce - 4.0 * L, ce + 4.0 * L),
            "heading_deg": [-30.0, 30.0],
            "speed_m_s": [r(0.6 * U), r(U)],
        },
        "goal": {
            "points": _rect(gn - L, gn + L, ge - 1.4 * L, ge + 1.4 * L),
            "point_m": [r(gn), r(ge)],
            "heading_deg": 0.0,
            "heading_tolerance_deg": 30.0,
            "max_speed_m_s": r(0.1 * U),
        },
        # Froude-scaled from full scale (x sqrt(L / 320 m), the KVLCC2): wind 0-10 m/s (Beaufort 5; a loaded
        # VLCC creeping at the goal speed cannot hold her heading unassisted in much more), current 0-0.5 m/s
        "weather": {
            "wind_speed_m_s": [0.0, r(10.0 * (L / 320.0) ** 0.5)],
            "current_speed_m_s": [0.0, r(0.5 * (L / 320.0) ** 0.5)],
        },
    }
    for poly in land + bw + quay + depth:
        poly["points"] = [[r(a), r(b)] for a, b in poly["points"]]
    for key in ("start", "goal"):
        table[key]["points"] = [[r(a), r(b)] for a, b in table[key]["points"]]
    return table


def generate_harbour(seed: int, ship: str = "kvlcc2_l7") -> Scenario:
    """Generated harbour ``seed`` for ``ship``, built and validated as a scenario file would be."""
    where = f"procedural harbour (seed {seed})"
    try:
        sc = build(Scenario, harbour_table(seed, ship), where)
    except ScenarioError:
        raise
    except SpecError as exc:
        raise ScenarioError(str(exc)) from None
    validate(sc, where)
    return sc
