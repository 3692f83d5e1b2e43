"""Trained agents on some ships of the class (``--agent``): the shipped HarbourApproach agent steers its ship
with the helm it was trained on, toward the goal, beside the students; an agent that does not fit is one line
and exit code 2."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from vessel_gym import cli
from vessel_gym.classroom.harbour import ClassHarbour

ROOT = Path(__file__).resolve().parents[2]
V3 = ROOT / "agents/trained/ppo_HarbourApproach-v3_seed0.zip"

pytest.importorskip("stable_baselines3")


def test_an_agent_ship_sails_toward_its_goal_with_its_smooth_helm():
    h = ClassHarbour("harbour", 2, seed=2, agent=str(V3), agents=1)
    assert h.names == ["Ship 1", "Agent 2"] and h.agent_ships.tolist() == [1]
    assert type(h.agent.helm).__name__ == "LagHelm" and h.agent.every == 4  # 0.99 s / 0.25 s
    d0 = [r.info["distance_to_goal_m"] for r in h.records]
    orders = []
    while h.t_s < 60.0 and h.live[1]:
        h.order(0, 0.0, 0)  # the student stops and waits
        h.step()
        orders.append(math.degrees(float(h.sim.rudder_order[1])))
    d1 = [r.info["distance_to_goal_m"] for r in h.records]
    assert h.live[1] and d0[1] - d1[1] > 40.0, (d0, d1)  # about 1 m/s made good toward the goal
    # the agent's orders, not the students' 5 degree steps: the lag's, changing once per second at most
    steps = np.abs(np.diff(orders))
    assert np.any(np.abs(np.array(orders) / 5.0 - np.round(np.array(orders) / 5.0)) > 0.05)
    moved = np.flatnonzero(steps > 1e-9)
    assert len(moved) > 5 and np.all(np.diff(moved) % 4 == 0)
    assert steps.max() <= 0.25 * 15.8 * 0.99 + 1e-6  # the rate cap: a quarter of the gear's 15.8 deg/s


def test_an_agent_ship_alone_arrives():
    h = ClassHarbour("harbour", 1, seed=2, agent=str(V3), agents=1)
    while h.live[0] and h.t_s < 400.0:
        h.step()
    assert h.records[0].outcome == "success", h.records[0].outcome


@pytest.mark.parametrize(
    ("extra", "says"),
    [
        (["--agents", "1"], "--agents needs --agent"),
        (["--agent", str(V3), "--agents", "2", "--pilots", "1"], "more than --ships"),
        (["--agent", "/nonexistent/agent.zip"], "no such agent"),
        (
            ["--agent", str(ROOT / "agents/trained/ppo_CollisionAvoidance-v0_seed0.zip")],
            "HarbourApproach agent",
        ),
    ],
)
def test_an_agent_that_does_not_fit_is_one_line_and_exit_code_2(extra, says, capsys):
    argv = ["classroom", "harbour", "--ships", "2", "--bind", "127.0.0.1:0", *extra]
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and says in err, err


def test_a_broken_agent_file_or_sidecar_is_one_line(tmp_path, capsys):
    bad = tmp_path / "ppo_HarbourApproach-v3_seed9.zip"
    bad.write_bytes(b"not a zip")
    argv = ["classroom", "harbour", "--ships", "2", "--bind", "127.0.0.1:0", "--agent", str(bad)]
    assert cli.main(argv) == 2  # no sidecar
    assert "sidecar" in capsys.readouterr().err
    shutil.copyfile(V3.with_suffix(".json"), bad.with_suffix(".json"))
    assert cli.main(argv) == 2  # the sidecar fits, the file does not load
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "cannot load" in err, err
    meta = json.loads(V3.with_suffix(".json").read_text())
    bad.with_suffix(".json").write_text(json.dumps({**meta, "env_id": "vessel_gym/ZigZag-v1"}))
    shutil.copyfile(V3, bad)
    assert cli.main(argv) == 2  # a sound file trained on another task
    assert "trained on 'vessel_gym/ZigZag-v1'" in capsys.readouterr().err
