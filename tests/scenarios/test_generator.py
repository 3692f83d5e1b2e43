"""The procedural harbour generator: seeded, every layout passes the scenario loader's checks, disjoint
train and eval seed ranges, layouts that really vary."""

from __future__ import annotations

import pytest

from vessel_gym.scenarios import ScenarioError, validate
from vessel_gym.scenarios.generator import (
    EVAL_SEEDS,
    TRAIN_SEEDS,
    generate_harbour,
    harbour_table,
    seed_split,
    split_seed,
)


def test_same_seed_same_layout_and_layouts_vary():
    assert harbour_table(7) == harbour_table(7)
    widths = set()
    for seed in range(12):
        bw = harbour_table(seed)["breakwater"]
        widths.add(round(bw[1]["points"][1][1] - bw[0]["points"][2][1], 3))  # entrance width, m
    assert len(widths) == 12
    kinds = {harbour_table(s)["description"].split(": ")[1].split(" ")[0] for s in range(30)}
    assert kinds == {"straight", "angled_in", "angled_out"}


@pytest.mark.parametrize("seeds", [range(0, 25), range(EVAL_SEEDS.start, EVAL_SEEDS.start + 25)])
def test_generated_layouts_pass_the_scenario_checks(seeds):
    for seed in seeds:
        sc = generate_harbour(seed)
        validate(sc, f"seed {seed}")  # generate_harbour validates; again to be explicit
        assert sc.route_m and sc.breakwater and sc.quay


def test_splits_are_disjoint_and_checked():
    assert TRAIN_SEEDS.stop <= EVAL_SEEDS.start
    assert seed_split(split_seed("train", 3)) == "train"
    assert seed_split(split_seed("eval", 3)) == "eval"
    with pytest.raises(ScenarioError, match="layout_split"):
        split_seed("test")
    with pytest.raises(ScenarioError, match="layout_seed"):
        seed_split(EVAL_SEEDS.stop)
