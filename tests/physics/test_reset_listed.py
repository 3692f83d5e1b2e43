"""Simulation.reset of some vessels of a batch with values listed per vessel: with a ship that has components
(the supply ship's thrusters) as without, each listed vessel gets its own heading and position and the others
keep theirs."""

from __future__ import annotations

import numpy as np
import pytest

from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.simulation import Simulation


@pytest.mark.parametrize("ship", ["supply", "kvlcc2_l7"])
def test_reset_of_listed_vessels_sets_each_its_own_pose(ship):
    sim = Simulation(load_ship(ship), n=4)
    sim.reset(speed_m_s=1.0, heading_deg=0.0)
    before = sim.state.copy()
    sim.reset(
        speed_m_s=[1.0, 1.5], heading_deg=[30.0, 120.0], x_m=[10.0, -20.0], y_m=[5.0, 7.0], k=np.array([1, 3])
    )
    assert np.degrees(sim.heading[[1, 3]]) == pytest.approx([30.0, 120.0])
    assert sim.north[[1, 3]] == pytest.approx([10.0, -20.0]) and sim.east[[1, 3]] == pytest.approx([5.0, 7.0])
    assert sim.u[[1, 3]] == pytest.approx([1.0, 1.5], rel=1e-6)
    np.testing.assert_array_equal(sim.state[[0, 2]], before[[0, 2]])
