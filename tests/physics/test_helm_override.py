"""Simulation.override_helm: an outside helmsman's orders (SI units) win over set_helm until handed back."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.units import DEG


def test_override_wins_over_set_helm_until_handed_back():
    sim = Simulation("mariner", n=2)
    sim.reset()
    sim.override_helm(1, rudder_order_rad=10 * DEG, rev_order=1.5)
    assert sim.rudder_order[1] == 10 * DEG and sim.rev_order[1] == 1.5  # at once
    sim.set_helm(rudder_order_rad=-5 * DEG, rev_order=0.5)  # the agent's orders, all vessels
    assert sim.rudder_order.tolist() == [-5 * DEG, 10 * DEG]
    assert sim.rev_order.tolist() == [0.5, 1.5]
    sim.set_helm(rudder_order_rad=np.array([1.0, 2.0]) * DEG, k=slice(0, 2))
    assert sim.rudder_order[1] == 10 * DEG
    # hand back: the orders in force stay until set_helm changes them
    sim.override_helm(1)
    assert sim.rudder_order[1] == 10 * DEG and sim.rev_order[1] == 1.5
    sim.set_helm(rudder_order_rad=3 * DEG)
    assert sim.rudder_order.tolist() == [3 * DEG, 3 * DEG] and sim.rev_order[1] == 1.5


def test_an_order_left_none_is_not_overridden():
    sim = Simulation("mariner")
    sim.reset()
    sim.override_helm(0, rudder_order_rad=-20 * DEG)
    sim.set_helm(rudder_order_rad=0.0, rev_order=0.7, k=0)
    assert sim.rudder_order[0] == -20 * DEG and sim.rev_order[0] == 0.7


def test_overridden_vessel_moves_as_if_the_order_were_set():
    # the override is an order like any other: vessel 0 ordered through set_helm, vessel 1 overridden against
    # an opposite set_helm order every step, follow the same path
    sim = Simulation("mariner", n=2)
    sim.reset()
    sim.override_helm(1, rudder_order_rad=15 * DEG)
    for _ in range(200):
        sim.set_helm(rudder_order_rad=np.array([15.0, -15.0]) * DEG)
        sim.step()
    assert sim.heading[0] > 3 * DEG  # 20 s of 15 deg starboard rudder turned it to starboard
    np.testing.assert_array_equal(sim.state[0], sim.state[1])


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"k": 2, "rudder_order_rad": 0.1}, "vessel 2 is not in"),
        ({"k": -1, "rudder_order_rad": 0.1}, "vessel -1 is not in"),
        ({"rudder_order_rad": math.nan}, "rudder_order_rad must be a finite number"),
        ({"rev_order": math.inf}, "rev_order must be a finite number"),
    ],
)
def test_bad_override_raises(kwargs, match):
    sim = Simulation("mariner", n=2)
    with pytest.raises(ValueError, match=match):
        sim.override_helm(**kwargs)
