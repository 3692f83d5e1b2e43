"""Berthing in play (vessel_gym.ui.play_berthing): thruster and tug keys reaching the ship and shown on the
panel, the berthing debrief (contact speed against PIANC's limit, energy per fender against its rating, the
reason of the outcome), headless with real pygame rendering."""

import os

import numpy as np
import pytest

from vessel_gym.envs.debrief import berthing_score
from vessel_gym.ui.play import play
from vessel_gym.ui.play_berthing import BerthingConsole

pygame = pytest.importorskip("pygame")
os.environ.setdefault("SDL_VIDEODRIVER", "dummy")


def test_thruster_keys_push_the_bow_and_the_debrief_is_written(tmp_path):
    d = play(
        env_id="vessel_gym/Berthing-v0",
        seed=0,
        realtime=False,
        max_steps=30,
        out_dir=tmp_path,
        weather=False,
        keys=[(0, "x")] * 4 + [(0, "c")] * 4 + [(20, "escape")],
    )
    assert d.outcome == "quit" and d.steps == 20 and d.scenario == "supply_base"
    assert d.berth == "supply quay 1" and d.contact_speed_m_s == 0.0
    assert d.contact_speed_limit_m_s == pytest.approx(0.110, abs=0.001)
    assert len(d.fender_energy_kJ) == 5 and d.fender_rated_energy_kJ == pytest.approx(187.6, abs=0.1)
    # full bow thruster to starboard and full stern thruster to port for 40 s: effort near 1 (mean order^2)
    assert 0.9 < d.assist_effort <= 1.0
    assert "no contact (PIANC limit 0.110 m/s)" in d.summary()
    img = pygame.surfarray.array3d(pygame.image.load(d.track_png))
    assert img.shape[:2] == (800, 600) and img.std() > 10.0


def test_bow_and_stern_thrusters_turn_the_ship_their_way():
    def heading_change(keys):
        c = BerthingConsole("vessel_gym/Berthing-v0", {"weather": False})
        c.reset(0)
        k0 = {"x": pygame.K_x, "z": pygame.K_z, "c": pygame.K_c, "v": pygame.K_v}
        for name in keys:
            c.key(pygame, k0[name])
        psi0 = float(c.env.sim.heading[0])
        for _ in range(20):
            c.env.step(c.action())
        rows = dict(c.overlay()["rows"])
        c.env.close()
        return (float(c.env.sim.heading[0]) - psi0 + np.pi) % (2 * np.pi) - np.pi, rows

    # bow to starboard and stern to port: a turn to starboard; the reverse to port
    stbd, rows = heading_change(["x"] * 4 + ["c"] * 4)
    port, _ = heading_change(["z"] * 4 + ["v"] * 4)
    assert stbd > 0.02 and port < -0.02
    # the panel shows each order with what the thruster delivers: after 40 s, 3 s lag, the full thrust
    assert rows["bow_thruster z/x"] == "+1.00 (+1.00)" and rows["stern_thrust c/v"] == "-1.00 (-1.00)"


def test_tug_keys_order_the_tanker_tugs_and_the_panel_shows_their_pull():
    c = BerthingConsole("vessel_gym/BerthingTanker-v0", {"weather": False})
    c.reset(0)
    c.key(pygame, pygame.K_x)
    c.key(pygame, pygame.K_v)
    c.key(pygame, pygame.K_v)
    assert c.action()[2:].tolist() == [0.25, 0.5]
    for _ in range(5):  # 30 s: one time constant of the tugs
        c.env.step(c.action())
    got = c.delivered()
    c.env.close()
    # a first-order lag: (1 - e^-1) of the order after one time constant, along the tug's line
    assert got == pytest.approx([0.25 * (1 - np.exp(-1)), 0.5 * (1 - np.exp(-1))], rel=0.02)
    c.key(pygame, pygame.K_b)
    assert not c.action()[2:].any()


def _drift(console, v0):
    """The ship parallel 0.5 m off the fenders, drifting onto them at ``v0`` with no orders; to the end."""
    task = console.task
    console.reset(0)
    sim = task.sim
    n0, e0 = task.berthed + 0.5 * task.to_water
    sim.set_environments(np.array([0]), wind_speed_m_s=0.0, current_speed_m_s=0.0)
    sim.reset(speed_m_s=0.0, heading_deg=task.berth.heading_deg, x_m=float(n0), y_m=float(e0), k=0)
    sim.state[0, 0:3] = 0.0
    sim.state[0, 1] = -v0  # port side to
    console.engine = 0
    for steps in range(1, 301):
        _o, _r, term, _t, info = console.env.step(console.action())
        if term:
            return console.debrief(str(info["outcome"]), steps, 0, info, [])
    raise AssertionError("no end")


def test_the_debrief_of_a_too_fast_touch_names_speed_limit_and_fender_energies():
    c = BerthingConsole("vessel_gym/Berthing-v0", {"weather": False})
    d = _drift(c, 0.3)
    c.env.close()
    assert d.outcome == "contact_speed"
    assert 0.27 < d.contact_speed_m_s < 0.3  # as the task measured it
    assert "over the PIANC limit 0.110 m/s" in d.reason
    rows = dict(d.items())
    assert rows["contact speed"].startswith(f"{d.contact_speed_m_s:.3f} m/s, ")
    assert "% of the PIANC limit 0.110 m/s" in rows["contact speed"]
    assert rows["fender energy"].startswith("kJ of 188 kJ rated: ")
    assert rows["fender energy"].count("%") == 5
    assert d.score < 20.0  # a failure: 40 x distance made good, halved


def test_the_debrief_of_an_overload_names_the_fender():
    c = BerthingConsole("vessel_gym/Berthing-v0", {"weather": False, "pianc_condition": "e"})
    d = _drift(c, 0.55)
    c.env.close()
    j = int(np.argmax(d.fender_energy_kJ))
    assert d.outcome == "fender_overload" and d.max_fender_fraction > 1.0
    assert d.reason.startswith(f"fender {j + 1} absorbed {d.fender_energy_kJ[j]:.0f} kJ, over its 188 kJ")


def test_berthing_score():
    assert berthing_score("success", 0.0, 0.0, 300.0, 0.0) == pytest.approx(100.0)
    assert berthing_score("success", 0.5, 0.2, 300.0, 0.0) == pytest.approx(50.0 + 12.5 + 20.0)
    assert berthing_score("time_limit", 0.0, 0.0, 300.0, 150.0) == pytest.approx(20.0)
    assert berthing_score("contact", 0.0, 0.0, 300.0, 150.0) == pytest.approx(10.0)


def test_a_task_that_is_not_berthing_is_refused():
    with pytest.raises(ValueError, match="not a berthing task"):
        BerthingConsole("vessel_gym/ZigZag-v1", {})


def test_the_command_line_plays_a_berthing_task_and_refuses_another_in_one_line(tmp_path, capsys):
    from vessel_gym.cli import main

    code = main(["play", "--env", "vessel_gym/ZigZag-v1", "--max-steps", "2", "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "not a berthing task" in err
    code = main(
        ["play", "--env", "vessel_gym/Berthing-v0", "--seed", "1", "--max-steps", "2", "--out", str(tmp_path)]
    )
    out = capsys.readouterr().out
    assert code == 0 and "contact speed" in out and "fender energy" in out
    assert (tmp_path / "debrief_supply_base.png").exists()
    # a scenario without a berth: one line, exit 2
    code = main(["play", "harbour", "--env", "vessel_gym/Berthing-v0", "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "[[berth]]" in err


def test_the_debrief_of_a_berthing_by_the_scripted_pilot_is_a_success_within_the_limits():
    from vessel_gym.envs.tasks.berthing_pilot import BerthingPilot

    c = BerthingConsole("vessel_gym/Berthing-v0", {})
    obs, _ = c.env.reset(seed=0)
    c.start_distance = 300.0
    pilot = BerthingPilot(c.env)
    pilot.reset()
    steps, term = 0, False
    while not term and steps < 900:
        obs, _r, term, _t, info = c.env.step(pilot(obs))
        steps += 1
    d = c.debrief(str(info["outcome"]), steps, 0, info, [])
    c.env.close()
    assert d.outcome == "success" and d.reason == "alongside within the tolerances, held"
    assert 0.0 < d.contact_speed_m_s < d.contact_speed_limit_m_s and d.max_fender_fraction < 1.0
    assert d.score == pytest.approx(
        50.0 + 25.0 * (1.0 - d.contact_speed_m_s / 0.110) + 25.0 * (1.0 - d.max_fender_fraction), abs=0.1
    )
    assert abs(d.off_error_m) <= 0.1 and abs(d.heading_error_deg) <= 3.0
