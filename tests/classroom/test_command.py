"""``vessel-gym classroom``: bad input is one line and exit code 2; a class runs, prints its address and the
instructor's code once, and writes its debrief; with a certificate it serves https and wss only."""

from __future__ import annotations

import json
import os
import re
import shutil
import ssl
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from vessel_gym import cli

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["classroom", "nosuch"], "unknown scenario"),
        (["classroom", "harbour", "--ships", "0"], "--ships"),
        (["classroom", "harbour", "--ships", "17"], "--ships"),
        (["classroom", "harbour", "--bind", "0.0.0.0:0"], "--allow-lan"),
        (["classroom", "harbour", "--bind", "192.0.2.1:8090"], "--allow-lan"),
        (["classroom", "harbour", "--bind", "localhost:8090"], "not an IP address"),
        (["classroom", "harbour", "--bind", "127.0.0.1"], "--bind"),
        (["classroom", "harbour", "--tls-cert", "c.pem"], "go together"),
        (
            ["classroom", "harbour", "--tls-cert", "/nonexistent.pem", "--tls-key", "/nonexistent.key"],
            "--tls",
        ),
        (["classroom", "harbour", "--time-factor", "nan"], "--time-factor"),
        (["classroom"], "scenario"),
        (["classroom", "harbour", "--ships", "2", "--pilots", "3"], "--pilots"),
        (["classroom", "supply_base", "--ships", "16", "--bind", "127.0.0.1:0"], "give fewer ships"),
    ],
)
def test_bad_input_is_one_line_and_exit_code_2(argv, says, capsys):
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and says in err, err


def test_a_class_runs_prints_its_codes_once_and_writes_its_debrief(tmp_path):
    env = {**os.environ, "PYTHONPATH": f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    cmd = [sys.executable, "-m", "vessel_gym.cli", "classroom", "harbour", "--ships", "2", "--bind",
           "127.0.0.1:0", "--duration", "15", "--seed", "4", "--out", str(tmp_path)]  # fmt: skip
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        url = proc.stdout.readline()
        code_line = proc.stdout.readline()
        found = re.search(r"open (http://127\.0\.0\.1:(\d+)/)", url)
        assert found, url
        code = re.search(r"instructor code (\S+)", code_line).group(1)
        port = found.group(2)
        with urllib.request.urlopen(found.group(1), timeout=10) as r:
            assert b"Join the class" in r.read()
        from websockets.sync.client import connect

        with connect(f"ws://127.0.0.1:{port}/ws", origin=f"http://127.0.0.1:{port}") as ws:
            ws.send(json.dumps({"type": "join", "code": code}))
            while True:
                m = json.loads(ws.recv(timeout=10))
                if m["type"] == "state":
                    break
            helm = [s["code"] for s in m["class"]]
        out, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
        proc.wait()
    assert proc.returncode == 0, err
    written = list(tmp_path.glob("classroom_harbour_*.html"))
    assert len(written) == 1
    page = written[0].read_text()
    assert "<svg" in page and "Class debrief" in page
    printed = url + code_line + out + err
    assert printed.count(code) == 1 and not any(c in printed for c in helm)
    assert not any(c in page for c in [code, *helm])
    assert "joins=1" in out


@pytest.mark.skipif(shutil.which("openssl") is None, reason="needs the openssl command")
def test_with_a_certificate_it_serves_https_and_wss_only(room, tmp_path):
    cert, key = tmp_path / "cert.pem", tmp_path / "key.pem"
    subprocess.run(
        ["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1", "-subj", "/CN=127.0.0.1",
         "-addext", "subjectAltName=IP:127.0.0.1", "-keyout", str(key), "-out", str(cert)],
        check=True, capture_output=True,
    )  # fmt: skip
    from vessel_gym.classroom import command

    args = command.argparse.Namespace(tls_cert=str(cert), tls_key=str(key))
    server_ctx = command._tls(args)
    r = room(ships=1, tls=server_ctx)
    client_ctx = ssl.create_default_context(cafile=str(cert))
    with urllib.request.urlopen(f"https://127.0.0.1:{r.port}/", context=client_ctx, timeout=10) as resp:
        assert b"Join the class" in resp.read()
    from websockets.exceptions import InvalidStatus
    from websockets.sync.client import connect

    url = f"wss://127.0.0.1:{r.port}/ws"
    with connect(url, origin=f"https://127.0.0.1:{r.port}", ssl=client_ctx) as ws:
        ws.send(json.dumps({"type": "join", "code": r.codes.spectator}))
        assert json.loads(ws.recv(timeout=10))["role"] == "spectator"
    with pytest.raises(InvalidStatus):  # an http page's origin is another origin
        connect(url, origin=f"http://127.0.0.1:{r.port}", ssl=client_ctx)
    with pytest.raises(Exception):  # noqa: B017 - plain http to a TLS port fails in the handshake
        urllib.request.urlopen(f"http://127.0.0.1:{r.port}/", timeout=5).read()
    time.sleep(0.1)


_NUMBER = st.one_of(
    st.integers(-(10**6), 10**6).map(str),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["", "nan", "-inf", "1e400", "abc", "-0", "16", "17", "0"]),
)
_ADDRESS = st.one_of(
    st.builds(
        lambda h, p: f"{h}:{p}",
        st.sampled_from(["127.0.0.1", "0.0.0.0", "localhost", "::1", "[::1]", "", "1.2.3", "a:b", "8.8.8.8"]),
        st.one_of(_NUMBER, st.sampled_from(["0", "70000"])),
    ),
    st.text(max_size=12),
)
_PATHISH = st.sampled_from(["/dev/null", "/", ".", "nosuch.pem", "/etc/passwd", "sub/dir/", "\0"])
_OPTIONS = {
    "--ships": _NUMBER,
    "--pilots": _NUMBER,
    "--bind": _ADDRESS,
    "--allow-lan": None,
    "--host-name": st.text(max_size=12),
    "--tls-cert": _PATHISH,
    "--tls-key": _PATHISH,
    "--time-factor": _NUMBER,
    "--duration": _NUMBER,
    "--seed": _NUMBER,
    "--out": _PATHISH,
}


@st.composite
def _argv(draw) -> list[str]:
    argv = ["classroom"]
    if draw(st.integers(0, 5)):
        argv.append(
            draw(st.one_of(st.sampled_from(["harbour", "nosuch", "HARBOUR"]), _PATHISH, st.text(max_size=8)))
        )
    for opt in draw(st.lists(st.sampled_from(sorted(_OPTIONS)), max_size=5)):
        argv.append(opt)
        if _OPTIONS[opt] is not None:
            argv.append(draw(_OPTIONS[opt]))
    return argv


@settings(
    max_examples=200,
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(argv=_argv())
def test_random_options_end_in_one_line_or_a_class(argv, monkeypatch, tmp_path, capsys):
    """Every check runs for real; the class itself is replaced by an immediate exit once they have passed."""
    from vessel_gym.classroom import harbour

    def no_class(*args, **kwargs):
        raise cli.UsageError("fuzz: the class replaced")

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(harbour, "ClassHarbour", no_class)
    t = time.perf_counter()
    try:
        code = cli.main(argv)
    except SystemExit as exc:  # --help
        code = exc.code
    out, err = capsys.readouterr()
    assert code in (0, 2), (argv, code, err)
    assert "Traceback" not in err and "Traceback" not in out, (argv, err)
    if code:
        assert err.count("\n") == 1 or "usage:" in err, (argv, err)
    assert time.perf_counter() - t < 10.0, argv
