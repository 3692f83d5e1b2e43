"""The traffic and berthing tasks live: ``serve --env`` for CollisionAvoidance (targets as state targets, AIS and
viewer ships; the COLREG debrief per encounter) and Berthing (thruster and tug orders on the helm, echoed in the
state, reaching the thrusters; the berthing debrief), and the protocol's ``assist`` field."""

from __future__ import annotations

import json
import time

import gymnasium as gym
import numpy as np
import pytest

from vessel_gym.net import protocol as P
from vessel_gym.net.link_config import LinkConfig
from vessel_gym.net.wrapper import UdpLinkWrapper, assist_units, link_limits
from vessel_gym.physics.components.thrusters import TunnelThruster

from .test_serve import _Server

UNITS = (P.AssistUnit("bow_thruster", "thruster"), P.AssistUnit("stern_thruster", "thruster"))
LIMITS = P.Limits(max_rudder_deg=35.0, max_rpm=200.0, assist=UNITS)


def _helm(**extra) -> bytes:
    return json.dumps(
        {"v": 1, "type": "helm", "seq": 5, "rudder_order_deg": 3.0, "telegraph": 1, **extra}
    ).encode()


# --- protocol ------------------------------------------------------------------------------------------------


def test_helm_assist_orders_are_parsed_and_default_to_zero():
    cmd = P.parse_datagram(_helm(assist=[0.5, -1]), LIMITS)
    assert cmd.assist == (0.5, -1.0)
    assert P.parse_datagram(_helm(), LIMITS).assist == (0.0, 0.0)  # a full order: no thruster order is 0
    assert P.parse_datagram(_helm(), P.Limits()).assist == ()  # a ship without thrusters: as before
    roundtrip = P.parse_datagram(P.encode_helm(7, -4.0, telegraph=-2, assist=[0.25, 1.0]), LIMITS)
    assert roundtrip.assist == (0.25, 1.0) and roundtrip.telegraph == -2


@pytest.mark.parametrize(
    "assist, says",
    [
        ([0.5, 1.5], "assist[1] = 1.5 is outside -1..1"),
        ([-1.0001, 0.0], "assist[0] = -1.0001 is outside -1..1"),
        ([0.1, 0.2, 0.3], "assist has 3 orders; the ship has 2 thrusters/tugs"),
        ([0.1], "assist has 1 orders; the ship has 2 thrusters/tugs"),
        (list(range(40)), "too_complex"),
        ([True, 0.0], "assist[0] must be a number"),
        (["0.5", 0.0], "assist[0] must be a number"),
        ([[0.5], 0.0], "assist[0] must be a number"),
        ({"bow": 0.5}, "assist must be a list of numbers"),
        ("full", "assist must be a list of numbers"),
        (1e400, "non_finite"),
    ],
)
def test_bad_assist_orders_are_rejected_with_one_line(assist, says):
    data = _helm(assist=assist) if assist != 1e400 else _helm().replace(b"}", b',"assist":[1e400,0]}')
    if says == "too_complex":  # 40 brackets: refused before parsing
        data = _helm(assist=[[0]] * 40)
    with pytest.raises(P.ProtocolError) as info:
        P.parse_datagram(data, LIMITS)
    assert says in str(info.value) and "\n" not in str(info.value)


def test_assist_orders_for_a_ship_without_thrusters_are_rejected():
    with pytest.raises(P.ProtocolError, match="the ship has 0 thrusters/tugs"):
        P.parse_datagram(_helm(assist=[0.5]), P.Limits())


def test_an_oversized_helm_is_rejected_unread():
    with pytest.raises(P.ProtocolError, match="oversize"):
        P.parse_datagram(_helm(assist=[0.5, 0.5], pad="x" * 3000), LIMITS)


def test_welcome_names_the_units_and_state_echoes_orders_and_fender_loads():
    from .helpers import make_reading

    welcome = json.loads(P.encode_welcome(1, "helm", 20.0, True, LIMITS, 1.0, 3.0, "hold", "c", "s"))
    assert welcome["assist"] == [
        {"name": "bow_thruster", "kind": "thruster"},
        {"name": "stern_thruster", "kind": "thruster"},
    ]
    assert "assist" not in json.loads(P.encode_welcome(1, "helm", 20.0, True, P.Limits(), 1.0, 3.0, "hold"))
    extras = P.StateExtras((P.AssistReading("bow_thruster", "thruster", 1.0, 0.4567),), (0.1234, 1.2))
    (state,) = P.encode_state(3, make_reading(), True, extras=extras)
    msg = json.loads(state)
    assert msg["assist"] == [{"name": "bow_thruster", "kind": "thruster", "order": 1.0, "delivered": 0.457}]
    assert msg["fender_load"] == [0.123, 1.2]
    (plain,) = P.encode_state(3, make_reading(), True)
    assert "assist" not in json.loads(plain) and "fender_load" not in json.loads(plain)


def test_midships_stop_failsafe_stops_the_thrusters_too():
    from vessel_gym.net.helm_owner import HelmOwner

    owner = HelmOwner("midships_stop")
    owner.command(0.0, ("127.0.0.1", 1), "p", P.HelmCommand(1, 10.0, telegraph=2, assist=(0.5, -0.5)))
    assert owner.state.assist == (0.5, -0.5)
    owner.release(2.0, "watchdog")
    assert owner.state.assist == (0.0, 0.0) and owner.state.rudder_order_deg == 0.0
    hold = HelmOwner("hold")
    hold.command(0.0, ("127.0.0.1", 1), "p", P.HelmCommand(1, 10.0, telegraph=2, assist=(0.5, -0.5)))
    hold.release(2.0, "watchdog")
    assert hold.state.assist == (0.5, -0.5)


# --- the helm reaches the thrusters --------------------------------------------------------------------------


def test_panel_thruster_order_reaches_the_thruster_and_the_agent_gets_it_back(peers):
    """A panel's bow-thruster order, not the agent's, drives the bow thruster while the panel holds the helm:
    its side force builds up to T_max x the forward-speed loss (momentum theory, thrusters.py); after the panel
    says bye and the failsafe time passes, the agent's order (0) returns."""
    env = gym.make("vessel_gym/Berthing-v0")
    assert [(u.name, u.kind) for u in assist_units(env)] == [
        ("bow_thruster", "thruster"),
        ("stern_thruster", "thruster"),
    ]
    assert link_limits(env).assist == assist_units(env)
    t = [0.0]
    w = UdpLinkWrapper(
        env,
        LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=()),
        clock=lambda: t[0],
        agent_resume_s=2.0,
    )
    try:
        task = env.unwrapped.task
        bow = next(c for c in task.assist if isinstance(c, TunnelThruster) and c.name == "bow_thruster")
        w.reset(seed=3)
        server = w.link.json_address
        panel = peers()
        panel.join(server, lambda: w.service(), "helm", 20.0)
        zero = np.zeros(env.action_space.shape, dtype=np.float32)
        seq = 0
        for _ in range(8):  # 16 s: over five time constants of the 3 s thrust lag
            seq += 1
            panel.send(server, P.encode_helm(seq, 0.0, telegraph=0, session=panel.session, assist=[1.0, 0.0]))
            time.sleep(0.005)
            t[0] += 0.1
            w.step(zero)
        assert w.steered_by == "human"
        assert bow.orders(1)[0] == 1.0
        sim = env.unwrapped.sim
        z = sim.component_states[:1][:, task.assist_states[task.assist.index(bow)]]
        assert float(bow.delivered(z)[0]) > 0.99  # 1 - exp(-16 s / 3 s) of the ordered thrust
        X, Y, N = bow.forces(sim, sim.state[:1], z)[0]  # the force the physics sums, N and N m
        # T_max times the forward-speed loss, which is never below 0.48 (Brix's curve, SPEED_LOSS)
        assert 0.48 * bow.T_max <= Y <= bow.T_max and X == 0.0
        assert Y == pytest.approx(bow.side_force(sim.u[0], 1.0), rel=0.02)
        assert N == pytest.approx(bow.params.x_m * Y) and bow.params.x_m > 0.0  # forward: turns to starboard
        states = panel.messages("state")
        echoed = [s for s in states if "assist" in s]
        assert (
            echoed and echoed[-1]["assist"][0]["order"] == 1.0 and echoed[-1]["assist"][0]["delivered"] > 0.5
        )
        assert "fender_load" in echoed[-1] and len(echoed[-1]["fender_load"]) == len(task.berth.fenders_m)
        panel.bye(server)
        for _ in range(40):  # the failsafe holds, then the agent steers again
            t[0] += 0.1
            w.step(zero)
        assert w.steered_by == "agent" and bow.orders(1)[0] == 0.0
    finally:
        w.close()


# --- serve --env -----------------------------------------------------------------------------------------------


def test_serve_collision_avoidance_sends_targets_as_state_ais_and_viewer_ships_and_debriefs(peers):
    """The encounter's target ships reach a viewer (state targets, v2 particulars) and a chartplotter (AIS);
    each episode ends with the outcome line and the per-encounter COLREG debrief."""
    nmea_sink = peers()
    srv = _Server(
        None,
        env="vessel_gym/CollisionAvoidance-v0",
        nmea=[nmea_sink.address],
        time_factor=100.0,
        duration_s=4.0,
        seed=1,
        max_episode_steps=8,
    )
    server = srv.address(timeout_s=300.0)
    viewer = peers()
    states, particulars = [], []
    t0 = time.monotonic()
    while srv.thread.is_alive() and time.monotonic() - t0 < 20.0:
        viewer.send(
            server, P.encode_hello("viewer", 20.0, "v", cookie=viewer.cookie, session=viewer.session, proto=2)
        )
        time.sleep(0.1)
        for m in viewer.messages():
            if m["type"] == "state":
                states.append(m)
            elif m["type"] == "particulars":
                particulars.append(m)
    assert srv.join() == 0
    out = srv.out.getvalue()
    assert "vessel_gym/CollisionAvoidance-v0: open sea, ship kvlcc2_full" in out
    with_targets = [s for s in states if s["targets"]]
    assert with_targets, "no state carried the target ships"
    names = {t["name"] for s in with_targets for t in s["targets"]}
    assert names <= {"target 1", "target 2", "target 3"} and names
    t = with_targets[-1]["targets"][0]
    assert t["length_m"] == pytest.approx(320.0, rel=0.01) and isinstance(t["sog_kn"], float)
    assert {p["name"] for p in particulars if not p["own"]} >= names  # drawn by the 3D viewer as ships
    nmea = b"".join(nmea_sink.raw()).decode()
    assert "!AIVDM" in nmea and "$GPRMC" in nmea
    lines = out.splitlines()
    ends = [i for i, line in enumerate(lines) if line.startswith("episode ")]
    assert ends, out
    assert "COLREG score" in lines[ends[0]] and "min separation" in lines[ends[0]]
    assert lines[ends[0] + 1].startswith("COLREG debrief: imazu:")
    debrief = lines[ends[0] + 2 : ends[0] + 6]
    assert any(line.strip().startswith("target 1:") for line in debrief), debrief


def test_colreg_debrief_scores_are_the_tasks_own():
    """The debrief's per-encounter checks add up to the episode's info (one home: colreg_rules)."""
    from vessel_gym.envs.debrief import colreg_debrief, encounter_scores
    from vessel_gym.envs.tasks.colreg_encounters import IMAZU
    from vessel_gym.policy import load_policy

    env = gym.make("vessel_gym/CollisionAvoidance-v0")
    pilot = load_policy("pid", env)
    obs, info = env.reset(seed=4, options={"scenario": "imazu:12"})
    for _ in range(120):
        obs, _r, term, trunc, info = env.step(pilot(obs))
        if term or trunc:
            break
    task = env.unwrapped.task
    scores = encounter_scores(task)
    assert len(scores) == len(IMAZU[12])  # one per target of the case
    assert sum(len(s.checks) for s in scores) == info["colreg_checks"]
    assert sum(s.violation for s in scores) == info["colreg_violations"]
    passed = sum(sum(s.checks.values()) for s in scores)
    assert passed / max(info["colreg_checks"], 1) == pytest.approx(
        info["colreg_score"] if info["colreg_checks"] else 0.0
    )
    lines = colreg_debrief(task, info, str(info["outcome"]))
    assert lines[0].startswith("COLREG debrief: imazu:12") and len(lines) == len(scores) + 2
    env.close()


def test_serve_berthing_takes_thruster_orders_from_the_helm_and_debriefs(peers):
    """A helm panel on a served Berthing-v0 orders the bow thruster; the state echoes the order and the thrust
    it delivers; the episode ends with the berthing debrief (contact speed, energy per fender vs rating)."""
    srv = _Server(
        None,
        env="vessel_gym/Berthing-v0",
        time_factor=20.0,
        duration_s=3.0,
        seed=2,
        max_episode_steps=20,
    )
    server = srv.address(timeout_s=300.0)
    panel = peers()
    panel.join(server, lambda: time.sleep(0.05), "helm", 20.0)
    welcome = []
    seq = 0
    got = []
    t0 = time.monotonic()
    while srv.thread.is_alive() and time.monotonic() - t0 < 15.0:
        seq += 1
        panel.send(server, P.encode_helm(seq, 0.0, telegraph=0, session=panel.session, assist=[0.8, 0.0]))
        time.sleep(0.05)
        for m in panel.messages():
            (got if m["type"] == "state" else welcome).append(m)
    assert srv.join() == 0
    out = srv.out.getvalue()
    assert "thrusters/tugs on the helm: bow_thruster (thruster), stern_thruster (thruster)" in out
    mine = [s for s in got if s["helm_ok"]]
    assert mine and mine[-1]["assist"][0]["order"] == pytest.approx(0.8)
    assert mine[-1]["assist"][0]["delivered"] > 0.3  # thrust 0.64 T_max ordered, lagging 3 s
    assert mine[-1]["assist"][1]["order"] == 0.0
    assert len(mine[-1]["fender_load"]) == 5
    assert "helm takeovers 1" in out
    lines = out.splitlines()
    ends = [i for i, line in enumerate(lines) if line.startswith("episode ")]
    assert ends and "fender max" in lines[ends[0]] and "contact" in lines[ends[0]]
    assert lines[ends[0] + 1] == "berthing debrief:"
    block = "\n".join(lines[ends[0] + 1 : ends[0] + 10])
    assert "contact speed" in block and "kJ rated" in block and "PIANC limit" in block


def test_serve_env_errors_are_one_line(capsys):
    from vessel_gym.cli import main

    assert main(["serve", "--env", "vessel_gym/ZigZag-v1", "--nmea", "off", "--duration", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "serve runs one of" in err and "vessel_gym/Berthing-v0" in err
    assert main(["serve", "harbour", "--env", "vessel_gym/Berthing-v0", "--duration", "1"]) == 2
    assert "not both" in capsys.readouterr().err


def test_pygame_helm_panel_orders_the_thrusters_of_a_berthing_ship():
    """The pygame helm panel learns the units from the welcome, and its z/x keys order the bow thruster of a
    Berthing ship on the link (the environment stepped by the panel's frame hook, in one thread)."""
    pytest.importorskip("pygame")
    from vessel_gym.ui import panels

    env = gym.make("vessel_gym/Berthing-v0")
    w = UdpLinkWrapper(env, LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=()))
    zero = np.zeros(env.action_space.shape, dtype=np.float32)
    task = env.unwrapped.task
    bow = task.assist[0]
    pressed = []
    try:
        w.reset(seed=5)

        def frame(i, panel, conn):
            w.step(zero)
            if i == 5:
                panel.handle_key("t")
            if panel.ready and len(panel.assist) == 2 and not pressed:
                for key in ("x", "x", "c"):
                    panel.handle_key(key)
                pressed.append(i)

        result = panels.run_helm(
            w.link.json_address, name="pilot", max_frames=60, fps=100.0, headless=True, size=(640, 400),
            capture=True, on_frame=frame,
        )  # fmt: skip
        assert pressed and result.owned_helm
        assert result.panel.assist == [0.5, -0.25]
        assert bow.orders(1)[0] == pytest.approx(0.5) and task.assist[1].orders(1)[0] == pytest.approx(-0.25)
        assert len(np.unique(result.last_frame.reshape(-1, 3), axis=0)) > 20
    finally:
        w.close()


def test_the_tankers_tugs_are_its_helm_units_and_take_a_panels_orders(peers):
    env = gym.make("vessel_gym/BerthingTanker-v0")
    assert [(u.name, u.kind) for u in assist_units(env)] == [("bow_tug", "tug"), ("stern_tug", "tug")]
    w = UdpLinkWrapper(env, LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=()))
    try:
        w.reset(seed=1)
        server = w.link.json_address
        panel = peers()
        panel.join(server, lambda: w.service(), "helm", 20.0)
        zero = np.zeros(env.action_space.shape, dtype=np.float32)
        for seq in range(1, 4):
            panel.send(
                server, P.encode_helm(seq, 0.0, telegraph=0, session=panel.session, assist=[-0.5, 1.0])
            )
            time.sleep(0.005)
            w.step(zero)
        tugs = env.unwrapped.task.assist
        assert w.steered_by == "human" and [t.orders(1)[0] for t in tugs] == [-0.5, 1.0]
        welcome = [m for m in panel.messages() if m["type"] == "welcome"]
        assert welcome[-1]["assist"] == [
            {"name": "bow_tug", "kind": "tug"},
            {"name": "stern_tug", "kind": "tug"},
        ]
    finally:
        w.close()


def test_pygame_panel_chart_draws_the_fenders_by_load():
    pytest.importorskip("pygame")
    from vessel_gym.ui import panels
    from vessel_gym.ui.chart import fender_colour

    quad = lambda e: [[20.0, e], [20.0, e + 8.0], [28.0, e + 8.0], [28.0, e]]  # noqa: E731  (north, east), m
    scene = {
        "features": [{"kind": "fender", "points": quad(-30.0)}, {"kind": "fender", "points": quad(30.0)}]
    }
    state = {"x_m": 0.0, "y_m": 0.0, "hdg_deg": 0.0, "fender_load": [0.3, 1.2], "targets": []}
    frame = panels.render_frame_array(state, scene=scene)
    colours = {tuple(c) for c in frame.reshape(-1, 3)}
    assert fender_colour(0.3) in colours and fender_colour(1.2) in colours


# --- serve --target-agent: the targets steered by agents, the own ship on the helm ------------------------------

PPO0 = "agents/trained/ppo_CollisionAvoidance-v0_seed0.zip"


def test_targets_are_own_ships_steered_by_the_agent_from_their_own_observation():
    """OwnShipAmongAgents: every target of the encounter is an own ship whose policy gets its own observation
    (its own route and goal ahead, the served ship in its target list) and whose order reaches its rudder; the
    served ship's orders are the caller's alone."""
    from vessel_gym.multiagent import OwnShipAmongAgents

    seen = []

    class HardStarboard:
        def reset(self):
            pass

        def __call__(self, obs):
            seen.append(obs)
            return np.array([1.0], dtype=np.float32)

    env = OwnShipAmongAgents(
        "vessel_gym/CollisionAvoidance-v0", lambda e: HardStarboard(), observation_type="physical"
    )
    lay = env.observation_layout
    _obs, info = env.reset(seed=0, options={"scenario": "imazu:13", "heading_deg": 0.0})
    task = env.task
    assert task.n == 4 and len(env.penv.driven) == 3 and info["scenario"] == "imazu:13"
    assert env.penv.possible_agents == ["ship_0"]
    for _ in range(3):
        env.step(np.zeros(1, dtype=np.float32))
    sim = task.sim
    assert sim.rudder_order[0] == 0.0 and all(sim.rudder_order[k] > 0.0 for k in (1, 2, 3))
    assert all(sim.r[k] > 0.0 for k in (1, 2, 3))  # swinging to starboard, ship 0 not yet
    assert len(seen) == 9 and all(lay.value(o, "goal_cos") > 0.99 for o in seen[:3])  # their goals ahead
    assert all(lay.value(o, "t0_valid") == 1.0 for o in seen)  # each sees the others
    from vessel_gym.net.batch_targets import BatchTargets

    assert BatchTargets.has_targets(env) and [t.name for t in BatchTargets(env).targets()] == [
        "target 1",
        "target 2",
        "target 3",
    ]


def test_serve_with_target_agents_lets_a_person_helm_against_them(peers):
    """serve --env CollisionAvoidance-v0 --target-agent <the shipped PPO>: the banner says so; a helm panel takes
    the own ship (its rudder order in the state); the three agent-steered targets go out as state targets, 3D
    viewer ships and AIS; the episode ends with the COLREG debrief."""
    nmea_sink = peers()
    srv = _Server(
        None,
        env="vessel_gym/CollisionAvoidance-v0",
        target_agent=PPO0,
        nmea=[nmea_sink.address],
        time_factor=100.0,
        duration_s=4.0,
        seed=3,
        max_episode_steps=8,
    )
    server = srv.address(timeout_s=300.0)
    panel, viewer = peers(), peers()
    panel.join(server, lambda: time.sleep(0.05), "helm", 20.0)
    states, particulars = [], []
    seq = 0
    t0 = time.monotonic()
    while srv.thread.is_alive() and time.monotonic() - t0 < 20.0:
        seq += 1
        panel.send(server, P.encode_helm(seq, 7.0, telegraph=3, session=panel.session))
        viewer.send(
            server, P.encode_hello("viewer", 20.0, "v", cookie=viewer.cookie, session=viewer.session, proto=2)
        )
        time.sleep(0.05)
        states += [m for m in panel.messages() if m["type"] == "state"]
        particulars += [m for m in viewer.messages() if m["type"] == "particulars"]
    assert srv.join() == 0
    out = srv.out.getvalue()
    assert f"open sea, targets steered by '{PPO0}'" in out and "helm takeovers 1" in out
    mine = [s for s in states if s["helm_ok"]]
    assert mine and mine[-1]["rudder_order_deg"] == pytest.approx(7.0)
    names = {t["name"] for s in states for t in s["targets"]}
    assert names == {"target 1", "target 2", "target 3"}
    assert {p["name"] for p in particulars if not p["own"]} >= names  # drawn by the 3D viewer as ships
    assert "!AIVDM" in b"".join(nmea_sink.raw()).decode()
    lines = out.splitlines()
    ends = [i for i, line in enumerate(lines) if line.startswith("episode ")]
    assert ends and lines[ends[0] + 1].startswith("COLREG debrief: ")
    assert any(line.strip().startswith("target 3:") for line in lines[ends[0] + 2 : ends[0] + 6])


def test_serve_target_agent_errors_are_one_line(capsys):
    from vessel_gym.cli import main

    base = ["serve", "--nmea", "off", "--duration", "1", "--json", "127.0.0.1:0"]
    cases = [
        (["--env", "vessel_gym/CollisionAvoidance-v0", "--target-agent", "nope.zip"], "no such file"),
        (
            ["--env", "vessel_gym/CollisionAvoidance-v0", "--target-agent", "agents/trained/ppo_ZigZagRandom-v1_seed0.zip"],
            "does not match the environment's (49,)",
        ),
        (["--env", "vessel_gym/Berthing-v0", "--target-agent", PPO0], "only the CollisionAvoidance tasks"),
    ]
    for extra, needle in cases:
        assert main(base + extra) == 2, extra
        err = capsys.readouterr().err.strip()
        assert err.count("\n") == 0 and "--target-agent" in err and needle in err, err
