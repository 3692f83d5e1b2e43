"""UdpLinkWrapper: helm takeover over real loopback sockets, failsafe and hand-back, action types, cost."""

from __future__ import annotations

import json
import math
import time

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym.envs  # noqa: F401  (registers the ids)
from vessel_gym.net.link import LinkConfig, UdpLink
from vessel_gym.net.wrapper import UdpLinkWrapper

from .helpers import Peer

IDS = ("vessel_gym/ZigZag-v1", "vessel_gym/TurningCircle-v0", "vessel_gym/HarbourApproach-v2")
SETTLE_S = 0.005
DT = 0.25  # control interval of every env here, s


class Clock:
    """Injected link clock: one control interval per tick."""

    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t

    def tick(self, dt: float = DT) -> None:
        self.t += dt


def _wrap(env_id="vessel_gym/HarbourApproach-v2", clock=None, link_kw=None, make_kw=None, **kw):
    cfg = {"json_bind": ("127.0.0.1", 0), "nmea_destinations": [], **(link_kw or {})}
    env = gym.make(env_id, **(make_kw or {}))
    kw.setdefault("clock", clock if clock is not None else Clock())
    return UdpLinkWrapper(env, cfg, **kw)


def _pump(env):
    """Let the wrapper's link run once at the wrapper's clock (for a client's handshake)."""
    return lambda: env.link.service(env._clock(), env._own_reading)


def _helm_peer(peers, env, rate=None) -> Peer:
    peer = peers()
    peer.join(env.link.json_address, _pump(env), "helm", rate)
    return peer


def _order(peer, env, seq, rudder, telegraph=None, rpm=None) -> None:
    peer.helm(env.link.json_address, seq, rudder, telegraph=telegraph, rpm=rpm)
    time.sleep(SETTLE_S)


def _agent_action(env):
    space = env.action_space
    if isinstance(space, gym.spaces.Box):
        return np.zeros(space.shape, dtype=np.float32)
    if isinstance(space, gym.spaces.Discrete):
        return np.int64(space.n // 2)
    return (space.nvec // 2).astype(np.int64)


def _rudder_order_deg(env) -> float:
    return math.degrees(float(env.unwrapped.sim.rudder_order[0]))


def _rpm_order(env) -> float:
    return float(env.unwrapped.sim.rev_order[0]) * 60.0


# -- takeover ---------------------------------------------------------------------------------------------------


def test_json_helm_order_moves_rudder_within_one_control_interval(peers):
    clock = Clock()
    env = _wrap(clock=clock)
    try:
        _obs, info = env.reset(seed=0)
        assert info["helm"] == "agent"
        a = np.array([0.5, 0.8], dtype=np.float32)  # the agent: 17.5 deg starboard
        clock.tick()
        env.step(a)
        assert _rudder_order_deg(env) == pytest.approx(17.5, abs=1e-4)
        peer = _helm_peer(peers, env)
        _order(peer, env, 1, -12.0, telegraph=2)  # SLOW AHEAD
        clock.tick()
        _obs, _r, _te, _tr, info = env.step(a)  # the next step already carries the order
        assert info["helm"] == "human"
        assert _rudder_order_deg(env) == pytest.approx(-12.0, abs=1e-4)
        slow_ahead = env.unwrapped.sim.telegraph_rev(2, 0) * 60.0
        assert _rpm_order(env) == pytest.approx(slow_ahead, rel=1e-5)
        # the panel is welcomed with the ship's limits
        welcome = [m for m in peer.messages("welcome")]
        assert welcome and welcome[0]["max_rudder_deg"] == pytest.approx(35.0)
        assert welcome[0]["max_rpm"] == pytest.approx(720.0)
        # and the panel sees its order in the state
        clock.tick()
        env.step(a)
        time.sleep(SETTLE_S)
        states = peer.messages("state")
        assert states and states[-1]["rudder_order_deg"] == pytest.approx(-12.0, abs=1e-3)
        assert states[-1]["telegraph"] == 2 and states[-1]["helm_ok"] is True
        assert env.steps_by == {"agent": 1, "human": 2, "failsafe": 0}
    finally:
        env.close()


def test_failsafe_after_one_second_of_silence_then_agent_gets_helm_back(peers):
    clock = Clock()
    env = _wrap(clock=clock, link_kw={"failsafe": "midships_stop"}, agent_resume_s=2.0)
    try:
        env.reset(seed=0)
        peer = _helm_peer(peers, env)
        agent = np.array([-0.4, 0.6], dtype=np.float32)
        _order(peer, env, 1, 20.0, telegraph=4)
        who = []
        for _ in range(5):  # the order arrives at the first step (t = 0.25 s), then the panel is silent
            clock.tick()
            who.append(env.step(agent)[4]["helm"])
        assert who == ["human"] * 5  # up to 1 s of silence (t = 1.25 s) the order holds
        assert _rudder_order_deg(env) == pytest.approx(20.0, abs=1e-4)
        clock.tick()  # more than 1 s of silence: the failsafe applies (midships, STOP)
        info = env.step(agent)[4]
        assert info["helm"] == "failsafe" and env.helm_state.failsafe and not env.helm_state.helm_ok
        assert _rudder_order_deg(env) == pytest.approx(0.0, abs=1e-6) and _rpm_order(env) == 0.0
        for _ in range(7):  # failsafe for agent_resume_s = 2 s
            clock.tick()
            assert env.step(agent)[4]["helm"] == "failsafe"
        clock.tick()
        assert env.step(agent)[4]["helm"] == "agent"
        assert _rudder_order_deg(env) == pytest.approx(-14.0, abs=1e-4)
        # a panel that commands again takes the helm back at once (after 3.5 s of silence it re-registers)
        peer.join(env.link.json_address, _pump(env), "helm")
        _order(peer, env, 1, 5.0, telegraph=1)
        clock.tick()
        assert env.step(agent)[4]["helm"] == "human"
        assert _rudder_order_deg(env) == pytest.approx(5.0, abs=1e-4)
    finally:
        env.close()


def test_hold_failsafe_keeps_orders_and_none_never_resumes(peers):
    clock = Clock()
    env = _wrap(clock=clock, agent_resume_s=None)
    try:
        env.reset(seed=0)
        peer = _helm_peer(peers, env)
        _order(peer, env, 1, -25.0, telegraph=3)
        agent = np.zeros(2, dtype=np.float32)
        for _ in range(40):  # 10 s, the panel silent after its first order
            clock.tick()
            info = env.step(agent)[4]
        assert info["helm"] == "failsafe"
        assert _rudder_order_deg(env) == pytest.approx(-25.0, abs=1e-4)  # "hold"
    finally:
        env.close()


def test_takeover_never_ignores_the_human_but_still_publishes(peers):
    clock = Clock()
    env = _wrap(clock=clock, takeover="never")
    try:
        env.reset(seed=0)
        peer = _helm_peer(peers, env)
        _order(peer, env, 1, -30.0, telegraph=-4)
        agent = np.array([0.2, 1.0], dtype=np.float32)
        for _ in range(3):
            clock.tick()
            info = env.step(agent)[4]
        assert info["helm"] == "agent"
        assert _rudder_order_deg(env) == pytest.approx(7.0, abs=1e-4)
        assert _rpm_order(env) == pytest.approx(720.0, rel=1e-5)
        assert env.helm_state.helm_ok  # the link itself accepted the panel
        assert peer.messages("state")
        assert env.steps_by["human"] == 0
    finally:
        env.close()


def test_close_hands_the_helm_back_to_the_simulation(peers):
    clock = Clock()
    env = _wrap(clock=clock)
    sim = env.unwrapped.sim
    try:
        env.reset(seed=0)
        peer = _helm_peer(peers, env)
        _order(peer, env, 1, 15.0, telegraph=1)
        clock.tick()
        assert env.step(np.zeros(2, dtype=np.float32))[4]["helm"] == "human"
    finally:
        env.close()
    sim.set_helm(rudder_order_rad=-0.1, k=0)  # whoever drives the simulation next has the helm
    assert float(sim.rudder_order[0]) == -0.1


# -- every env and action type ----------------------------------------------------------------------------------


@pytest.mark.parametrize("env_id", IDS)
@pytest.mark.parametrize("action_type", ["continuous", "discrete"])
@pytest.mark.parametrize("engine", [False, True])
def test_human_orders_in_every_env_and_action_type(peers, env_id, action_type, engine):
    clock = Clock()
    env = _wrap(env_id, clock=clock, make_kw={"action_type": action_type, "engine_control": engine})
    try:
        env.reset(seed=1)
        base = env.unwrapped
        peer = _helm_peer(peers, env)
        _order(peer, env, 1, -12.0, rpm=-260.0)
        clock.tick()
        _obs, _r, _te, _tr, info = env.step(_agent_action(env))
        assert info["helm"] == "human"
        rev_table = base.task.helm.rev_table[0] * 60.0  # rpm of telegraph -4..4
        # the panel's orders reach the physics as given, whatever the agent's action type (a discrete agent
        # offers -35, -20, -10, -5, 0, ... deg and telegraph steps only)
        assert _rudder_order_deg(env) == pytest.approx(-12.0, abs=1e-9)
        assert _rpm_order(env) == pytest.approx(-260.0, rel=1e-12)
        # the panel is shown the telegraph step nearest its rpm order: SLOW ASTERN (-300 rpm)
        clock.tick()
        env.step(_agent_action(env))
        time.sleep(SETTLE_S)
        assert peer.messages("state")[-1]["telegraph"] == -2
        assert _rudder_order_deg(env) == pytest.approx(-12.0, abs=1e-9)  # the agent's action did not win
        # a telegraph order
        _order(peer, env, 2, 3.0, telegraph=3)
        clock.tick()
        env.step(_agent_action(env))
        assert _rpm_order(env) == pytest.approx(rev_table[7], rel=1e-5)
        # a reset re-solves the steady approach; the human's orders apply again at the next step
        env.reset(seed=2)
        clock.tick()
        assert env.step(_agent_action(env))[4]["helm"] == "human"
        assert _rpm_order(env) == pytest.approx(rev_table[7], rel=1e-5)
    finally:
        env.close()


# -- cost -------------------------------------------------------------------------------------------------------


class _Counting:
    def __init__(self, sim) -> None:
        self.calls = 0
        self._bridge = sim.bridge

    def __call__(self, *a, **kw):
        self.calls += 1
        return self._bridge(*a, **kw)


@pytest.mark.parametrize("env_id", IDS)
def test_no_peers_and_nmea_off_compute_no_readings(peers, env_id):
    clock = Clock()
    env = _wrap(env_id, clock=clock)
    try:
        sim = env.unwrapped.sim
        counting = sim.bridge = _Counting(sim)
        tr = env.traffic
        if tr is not None:
            tr_counting = tr.sim.bridge = _Counting(tr.sim)
        env.reset(seed=0)
        for _ in range(50):
            clock.tick()
            _o, _r, term, trunc, _i = env.step(_agent_action(env))
            if term or trunc:
                env.reset()
        assert counting.calls == 0
        if tr is not None:
            assert tr_counting.calls == 0 and tr.steps == 0  # traffic nobody sees is not simulated
        # a viewer makes the readings flow, at its rate
        viewer = peers()
        viewer.join(env.link.json_address, _pump(env), "viewer", 2.0)  # one state (and reading) at once
        for _ in range(8):  # 2 s at 2 Hz
            clock.tick()
            env.step(_agent_action(env))
        time.sleep(SETTLE_S)
        states = viewer.messages("state")
        assert 4 <= len(states) <= 5
        assert counting.calls == len(states)  # one reading per state sent: none while the viewer is not due
    finally:
        env.close()


def test_service_is_throttled_on_a_fast_wall_clock():
    env = _wrap(clock="wall", min_service_interval_s=0.05)
    calls = []
    service = env.link.service
    env.link.service = lambda *a, **kw: calls.append(1) or service(*a, **kw)
    try:
        env.reset(seed=0)
        t0 = time.monotonic()
        n = 0
        while time.monotonic() - t0 < 0.2:
            env.step(np.zeros(2, dtype=np.float32))
            n += 1
        assert n > 20 and 2 <= len(calls) <= 7  # reset + about one per 50 ms
    finally:
        env.close()


# -- traffic ----------------------------------------------------------------------------------------------------


def test_harbour_traffic_reaches_viewers_as_targets(peers):
    clock = Clock()
    env = _wrap(clock=clock, make_kw={"control_interval_s": 0.25})  # 40 steps: 10 s
    try:
        assert env.traffic is not None and env.traffic.n == 2
        env.reset(seed=0)
        viewer = peers()
        viewer.join(env.link.json_address, _pump(env), "viewer", 4.0)
        viewer.messages()  # the state of the handshake (without targets: the pump sends none)
        for k in range(40):  # 10 s
            if k % 4 == 3:  # keep-alive every second
                viewer.hello(env.link.json_address, "viewer", 4.0)
                time.sleep(SETTLE_S)
            clock.tick()
            env.step(np.zeros(2, dtype=np.float32))
        time.sleep(SETTLE_S)
        states = viewer.messages("state")
        assert len(states) == 40
        names = [t["name"] for t in states[-1]["targets"]]
        assert names == ["KVLCC2 LOOP", "KVLCC2 PIER"]
        loop = states[-1]["targets"][0]
        assert states[-1]["t_s"] - states[0]["t_s"] == pytest.approx(9.75, abs=1e-6)
        # the loop ship left (-20, 0) eastbound at 1.5 kn: it moved about 7 m in 9.75 s
        assert loop["y_m"] == pytest.approx(1.5 * 0.5144 * 9.75, abs=1.0)
        assert env.traffic.steps == 39  # caught up to the published step only
        assert env.reset()[1]["helm"] == "agent" and env.traffic.steps == 0
    finally:
        env.close()


def test_nmea_stream_carries_own_ship_and_ais(peers):
    clock = Clock()
    sink = peers()
    env = _wrap(clock=clock, link_kw={"nmea_destinations": [sink.address], "nmea_rate_hz": 2.0})
    try:
        env.reset(seed=0)
        for _ in range(8):
            clock.tick()
            env.step(np.zeros(2, dtype=np.float32))
        text = b"".join(sink.raw(SETTLE_S)).decode()
        assert "$GPRMC" in text and "$IIHDT" in text
        assert text.count("!AIVDM,1,1") >= 2 and "!AIVDM,2,1" in text  # type 1 for both, type 5 static
    finally:
        env.close()


# -- arguments --------------------------------------------------------------------------------------------------


def test_bad_arguments_raise_value_error():
    env = gym.make("vessel_gym/ZigZag-v1")
    with pytest.raises(ValueError, match="takeover"):
        UdpLinkWrapper(env, {"json_bind": ("127.0.0.1", 0)}, takeover="sometimes")
    with pytest.raises(ValueError, match="agent_resume_s"):
        UdpLinkWrapper(env, {"json_bind": ("127.0.0.1", 0)}, agent_resume_s=-1.0)
    with pytest.raises(ValueError, match="unknown LinkConfig"):
        UdpLinkWrapper(env, {"json_bnd": ("127.0.0.1", 0)})
    with pytest.raises(ValueError, match="clock"):
        UdpLinkWrapper(env, {"json_bind": ("127.0.0.1", 0)}, clock="lunar")
    with pytest.raises(ValueError, match="vessel-gym environment"):
        UdpLinkWrapper(gym.make("CartPole-v1"), {"json_bind": ("127.0.0.1", 0)})
    link = UdpLink(LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=()))
    with pytest.raises(ValueError, match="either config or link"):
        UdpLinkWrapper(env, {"json_bind": ("127.0.0.1", 0)}, link=link)
    wrapped = UdpLinkWrapper(env, link=link)  # a given link is used, and left open on close
    wrapped.close()
    assert not link._closed
    link.close()


def test_sim_clock_runs_link_in_simulated_time(peers):
    env = _wrap("vessel_gym/ZigZag-v1", clock="sim")
    try:
        env.reset(seed=0)
        viewer = peers()
        viewer.join(env.link.json_address, _pump(env), "viewer", 1.0)
        viewer.messages()
        for k in range(40):  # 10 simulated seconds, in a few wall-clock milliseconds
            if k % 4 == 3:  # keep-alive every simulated second
                viewer.hello(env.link.json_address, "viewer", 1.0)
                time.sleep(SETTLE_S)
            env.step(np.zeros(1, dtype=np.float32))
        time.sleep(SETTLE_S)
        ts = [m["t_s"] for m in viewer.messages("state")]
        assert 9 <= len(ts) <= 11 and json.dumps(ts)
    finally:
        env.close()
