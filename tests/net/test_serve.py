"""``serve()``: a scenario live on the UDP link, against real loopback sockets."""

from __future__ import annotations

import io
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from vessel_gym import cli
from vessel_gym.net import protocol as P
from vessel_gym.net.clients import ServerConnection
from vessel_gym.net.serve import outcome_line, serve
from vessel_gym.physics.schema import SpecError

from .helpers import Peer, free_udp_port

ROOT = Path(__file__).resolve().parents[2]


class _Server:
    """serve() on a thread, its output collected; ``address`` read from the banner."""

    def __init__(self, scenario: str = "harbour", **kw) -> None:
        self.scenario = scenario
        self.out = io.StringIO()
        self.err = io.StringIO()
        kw.setdefault("err", self.err)
        self.result: list[object] = []
        kw.setdefault("json_bind", ("127.0.0.1", 0))
        kw.setdefault("nmea", [])
        self.thread = threading.Thread(target=self._run, kwargs=kw, daemon=True)
        self.thread.start()

    def _run(self, **kw) -> None:
        try:
            self.result.append(serve(self.scenario, out=self.out, **kw))
        except BaseException as exc:  # pragma: no cover - reported by the test
            self.result.append(exc)

    def address(self, timeout_s: float = 30.0) -> tuple[str, int]:
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            m = re.search(r"listening on ([\d.]+):(\d+)", self.out.getvalue())
            if m:
                return (m.group(1), int(m.group(2)))
            if self.result:
                raise AssertionError(f"serve ended early: {self.result[0]!r}")
            time.sleep(0.01)
        raise AssertionError("serve printed no JSON address")

    def join(self, timeout_s: float = 30.0) -> object:
        self.thread.join(timeout_s)
        assert not self.thread.is_alive(), "serve did not stop"
        return self.result[0]


def test_serve_publishes_state_with_traffic_and_nmea_with_ais(peers):
    nmea_sink = peers()
    listen_only = peers()
    srv = _Server(
        nmea=[nmea_sink.address],
        listen_only=[listen_only.address],
        time_factor=20.0,
        duration_s=2.0,
        seed=0,
    )
    server = srv.address()
    viewer = peers()
    states: list[dict] = []
    welcome = []
    t0 = time.monotonic()
    while srv.thread.is_alive() and time.monotonic() - t0 < 10.0:
        viewer.hello(server, "viewer", 20.0, name="test viewer")  # echoes the cookie of the last welcome
        time.sleep(0.1)
        for m in viewer.messages():
            (states if m["type"] == "state" else welcome).append(m)
    assert srv.join() == 0
    assert welcome and welcome[0]["type"] == "welcome" and welcome[0]["max_rpm"] == pytest.approx(720.0)
    assert len(states) >= 10
    last = states[-1]
    assert [t["name"] for t in last["targets"]] == ["KVLCC2 LOOP", "KVLCC2 PIER"]
    assert last["helm_ok"] is False
    # about 20 simulated seconds per wall-clock second
    span_sim = last["t_s"] - states[0]["t_s"]
    assert 10.0 < span_sim < 45.0
    nmea = b"".join(nmea_sink.raw()).decode()
    assert "$GPRMC" in nmea and "!AIVDM" in nmea
    assert listen_only.messages("state")  # the listen-only viewer got state without a hello
    text = srv.out.getvalue()
    assert f"sending to {nmea_sink.address[0]}:{nmea_sink.address[1]}" in text
    assert f"listen-only viewers: {listen_only.address[0]}:{listen_only.address[1]}" in text
    assert "traffic: 2 ship(s): KVLCC2 LOOP, KVLCC2 PIER" in text
    assert "stopped after" in text.splitlines()[-1]


def test_episode_end_prints_one_line_outcome_and_restarts():
    srv = _Server(time_factor=100.0, duration_s=1.0, max_episode_steps=20, seed=1)
    assert srv.join() == 0
    lines = [ln for ln in srv.out.getvalue().splitlines() if ln.startswith("episode ")]
    assert len(lines) >= 2
    # HarbourApproach-v3: 20 control steps of L / U_T / 6 = 0.99 s (kvlcc2_l7)
    assert re.match(r"episode 1: time limit at t = 19\.8 s, path \d+ m, .*; helm: agent 100%$", lines[0])
    assert lines[1].startswith("episode 2: ")


def test_human_helm_takes_over_from_the_agent(peers):
    srv = _Server(time_factor=10.0, duration_s=1.5, seed=0)
    server = srv.address()
    panel = peers()
    panel.join(server, lambda: time.sleep(0.05), "helm", 20.0)
    seq = 0
    got = []
    t0 = time.monotonic()
    while srv.thread.is_alive() and time.monotonic() - t0 < 10.0:
        seq += 1
        panel.helm(server, seq, -20.0, telegraph=1)
        time.sleep(0.05)
        got += panel.messages("state")
    assert srv.join() == 0
    late = [s for s in got if s["helm_ok"]]
    assert late and late[-1]["rudder_order_deg"] == pytest.approx(-20.0, abs=1e-3)
    assert late[-1]["telegraph"] == 1
    assert "helm takeovers 1" in srv.out.getvalue()


def test_helm_changes_are_one_line_each_on_stderr(peers):
    srv = _Server(time_factor=10.0, duration_s=4.0, seed=0)
    server = srv.address()
    a, b = peers(), peers()
    a.join(server, lambda: time.sleep(0.05), "helm", 20.0, name="panel-A")
    b.join(server, lambda: time.sleep(0.05), "helm", 20.0, name="panel-B")
    for seq in range(1, 11):  # A steers for 0.5 s, then falls silent
        a.helm(server, seq, -10.0, telegraph=1)
        time.sleep(0.05)
    time.sleep(1.3)  # the 1 s watchdog releases A
    for seq in range(1, 11):
        b.hello(server, "helm", 20.0, name="panel-B")
        b.helm(server, seq, 10.0, telegraph=2)
        time.sleep(0.05)
    b.hello(server, "viewer", 20.0, name="panel-B")  # B gives the helm back
    assert srv.join() == 0
    lines = srv.err.getvalue().splitlines()
    pa, pb = f"'panel-A' (127.0.0.1:{a.address[1]})", f"'panel-B' (127.0.0.1:{b.address[1]})"
    assert lines == [
        f"vessel-gym serve: helm taken by {pa} from the agent",
        f"vessel-gym serve: helm released by {pa} (no command for the watchdog time); failsafe 'hold', "
        "then the agent after 5 s",
        f"vessel-gym serve: helm taken by {pb} from the failsafe after {pa}",
        f"vessel-gym serve: helm released by {pb} (went back to watching); failsafe 'hold', "
        "then the agent after 5 s",
    ]


def test_token_keeps_out_clients_without_it(peers):
    srv = _Server(time_factor=10.0, duration_s=1.5, seed=0, token="klärung")
    server = srv.address()
    assert "token required" in srv.out.getvalue()
    outsider = peers()
    for _ in range(5):
        outsider.send(server, P.encode_hello("viewer", 20.0, token="klärun"))
        time.sleep(0.05)
    member = peers()
    member.join(server, lambda: time.sleep(0.05), "viewer", 20.0, token="klärung")
    time.sleep(0.3)
    assert srv.join() == 0
    assert outsider.raw() == [] and member.messages("state")


@pytest.mark.slow
def test_real_time_clients_get_state_at_their_rate():
    """At time factor 1 the link ticks every 10 ms: a 20 Hz and a 50 Hz viewer get their rates (loosely, on a
    shared machine), with t_s stepping by less than the 0.25 s control interval."""
    srv = _Server(time_factor=1.0, duration_s=4.0, seed=0)
    server = srv.address()
    conns = {rate: ServerConnection(server, "viewer", rate) for rate in (20.0, 50.0)}
    try:
        t0 = time.monotonic()
        counted: dict[float, list] = {rate: [] for rate in conns}
        while time.monotonic() - t0 < 2.5:
            now = time.monotonic()
            for rate, c in conns.items():
                c.keepalive(now)
                before = c.states_received
                c.poll(now)
                if c.states_received > before and now - t0 > 1.0:  # the last 1.5 s, after joining
                    counted[rate].append(c.state["t_s"])
            time.sleep(0.002)
    finally:
        for c in conns.values():
            c.close()
    assert srv.join() == 0
    assert len(counted[20.0]) >= 15  # >= 10 per real second
    assert len(counted[50.0]) >= 30
    steps = np.diff(counted[50.0])
    assert np.median(steps) < 0.1  # the physics moved between states, not once per control step


def _docs_client_snippet() -> str:
    text = (ROOT / "docs" / "protocol.md").read_text()
    after = text[text.index("### Your own client") :]
    code = after[after.index("```python\n") + len("```python\n") :]
    return code[: code.index("```")]


@pytest.mark.slow
def test_the_docs_client_snippet_keeps_receiving_past_the_client_timeout():
    srv = _Server(time_factor=1.0, duration_s=12.0, seed=0)
    host, port = srv.address()
    code = _docs_client_snippet()
    assert 'SERVER = ("127.0.0.1", 10120)' in code
    code = code.replace('SERVER = ("127.0.0.1", 10120)', f"SERVER = ({host!r}, {port})")
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    stamps: list[float] = []

    def read() -> None:
        for _line in proc.stdout:
            stamps.append(time.monotonic())

    reader = threading.Thread(target=read, daemon=True)
    t0 = time.monotonic()
    reader.start()
    try:
        time.sleep(6.0)
    finally:
        proc.kill()
        proc.wait(10)
        reader.join(5)
    srv.join()
    late = [t - t0 for t in stamps if t - t0 > 4.5]  # well past the 3 s client timeout
    assert len(stamps) >= 30 and len(late) >= 5, (len(stamps), len(late))


def test_bad_agent_path_and_scenario_are_one_line_errors(tmp_path):
    with pytest.raises(ValueError, match=r"agent '.*nope\.zip'.*no such file") as exc:
        serve("harbour", agent=str(tmp_path / "nope.zip"), json_bind=("127.0.0.1", 0), nmea=[])
    assert "\n" not in str(exc.value)
    with pytest.raises(SpecError, match="unknown scenario") as exc:
        serve("atlantis", json_bind=("127.0.0.1", 0), nmea=[])
    assert "\n" not in str(exc.value)
    with pytest.raises(ValueError, match="time_factor"):
        serve("harbour", time_factor=0.0, nmea=[])


def test_taken_port_is_a_one_line_error(peers):
    taken = peers()
    with pytest.raises(ValueError, match=r"cannot open the UDP link .*127\.0\.0\.1:\d+") as exc:
        serve("harbour", json_bind=taken.address, nmea=[])
    assert "\n" not in str(exc.value)


def test_cli_maps_bad_agent_to_exit_code_2(capsys, tmp_path):
    code = cli.main(
        ["serve", "--agent", str(tmp_path / "missing.zip"), "--json", "127.0.0.1:0", "--nmea", "off"]
    )
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and "missing.zip" in err


def test_cli_token_option_and_environment(capsys, monkeypatch):
    base = ["serve", "--json", "127.0.0.1:0", "--nmea", "off", "--duration", "0.3", "--time-factor", "10"]
    assert cli.main([*base, "--token", "x" * 129]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--token must be 1-128 characters" in err
    assert cli.main([*base, "--token", "s\u00e9same"]) == 0
    assert "token required" in capsys.readouterr().out
    monkeypatch.setenv("VESSEL_GYM_TOKEN", "")  # empty: no token
    assert cli.main(base) == 0
    assert "token required" not in capsys.readouterr().out
    monkeypatch.setenv("VESSEL_GYM_TOKEN", "from-env")
    assert cli.main(base) == 0
    assert "token required" in capsys.readouterr().out
    for command in ("helm", "view"):
        assert cli.main([command, "--token", ""]) == 2
        assert "--token must be 1-128 characters" in capsys.readouterr().err


def test_outcome_line():
    info = {
        "outcome": "success",
        "time_s": 312.5,
        "path_m": 240.4,
        "min_clearance_m": 3.21,
        "distance_to_goal_m": 1.0,
    }
    line = outcome_line(3, info, False, {"agent": 30, "human": 90, "failsafe": 0})
    assert line == (
        "episode 3: success at t = 312.5 s, path 240 m, min clearance 3.2 m, distance to goal 1.0 m; "
        "helm: agent 25%, human 75%"
    )
    assert "time limit" in outcome_line(1, {**info, "outcome": "running"}, True, {"agent": 1})


@pytest.mark.slow
def test_ctrl_c_ends_cleanly_with_exit_code_0():
    port = free_udp_port()
    proc = subprocess.Popen(
        [sys.executable, "-m", "vessel_gym.cli", "serve", "--json", f"127.0.0.1:{port}", "--nmea", "off"],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        for line in proc.stdout:
            if "Ctrl-C" in line:
                break
        viewer = Peer()
        viewer.join(("127.0.0.1", port), lambda: time.sleep(0.05), "viewer", 10.0)
        time.sleep(0.5)
        assert viewer.messages("state")
        viewer.close()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, err
    assert "stopped after" in out and "Traceback" not in err


_DRIFTING_GEAR = '''
import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import SteeringGear


class DriftingGear(SteeringGear):
    """A failed steering gear: ignores the helm and drives the rudder to starboard at 1 deg/s up to 35 deg."""

    def rudder_rate(self, sim, x, s):
        return np.clip((np.radians(35.0) - x[:, lo.X_DELTA]) / 0.05, 0.0, np.radians(1.0))
'''


def test_serve_runs_the_ship_files_component(peers, tmp_path, monkeypatch):
    """A scenario whose ship file names a user's steering gear: the served rudder angle is the gear's (1 deg/s
    to starboard from the reset, whatever the agent orders), not the helm's."""
    (tmp_path / "served_gear.py").write_text(_DRIFTING_GEAR)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("VESSEL_GYM_ALLOW_CODE", "1")  # these ship files name the test's own modules
    ships = ROOT / "vessel_gym" / "physics" / "data" / "ships"
    ship = tmp_path / "gear_failure.toml"
    ship.write_text(
        (ships / "kvlcc2_l7.toml").read_text()
        + '\n[[components]]\nslot = "steering_gear"\nmodel = "served_gear:DriftingGear"\nreplace = true\n'
    )
    scenario = tmp_path / "harbour_gear.toml"
    text = (ROOT / "vessel_gym" / "scenarios" / "harbour.toml").read_text()
    scenario.write_text(re.sub(r'(?m)^ship = "kvlcc2_l7"$', f'ship = "{ship}"', text, count=1))
    srv = _Server(str(scenario), time_factor=5.0, duration_s=8.0, seed=0)
    server = srv.address(timeout_s=180.0)  # the component path compiles on first use
    viewer = peers()
    states: list[dict] = []
    t0 = time.monotonic()
    while srv.thread.is_alive() and time.monotonic() - t0 < 30.0:
        viewer.hello(server, "viewer", 20.0, name="test viewer")
        time.sleep(0.1)
        states += viewer.messages("state")
    assert srv.join() == 0
    assert len(states) >= 3
    for st in states:  # 1 deg/s from the reset (t = 0), to 0.01 deg (the message's resolution)
        assert st["rudder_deg"] == pytest.approx(min(st["t_s"], 35.0), abs=0.011), st
    assert states[-1]["rudder_deg"] > 2.0
    assert any(st["rudder_order_deg"] != st["rudder_deg"] for st in states)  # the helm is not what moved it


def test_serve_makes_its_env_without_an_upgrade_warning():
    """serve chooses HarbourApproach-v3 itself: the user is not told to upgrade an id they never named."""
    import warnings

    from vessel_gym.net.served import Served
    from vessel_gym.scenarios import load_scenario

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        env = Served(None, load_scenario("harbour")).make({})
    env.close()
    assert not [w for w in caught if "out of date" in str(w.message)], [str(w.message) for w in caught]
