"""The front door of ``vessel-gym`` and ``vessel-cfd``: version, help with defaults, one way to name a ship, the
ship list, quiet SIGPIPE, and arguments that must give one line and exit code 2."""

from __future__ import annotations

import subprocess
import sys

import pytest

import vessel_gym
from cfd.cli import main as cfd_main
from vessel_gym import cli
from vessel_gym.cli import main


def run(capsys, *argv, entry=main):
    code = entry(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out.strip() == f"vessel-gym {vessel_gym.__version__}"


def _subparsers(parser):
    import argparse

    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sp in action.choices.items():
                yield name, sp
                yield from ((f"{name} {n}", s) for n, s in _subparsers(sp))


def test_every_option_with_a_default_shows_it_in_help():
    parser = cli.build_parser()
    checked = 0
    for name, sp in _subparsers(parser):
        text = " ".join(sp.format_help().split())
        for action in sp._actions:
            if action.default in (None, False, "==SUPPRESS==") or not action.option_strings:
                continue
            if action.dest == "help" or "default" in (action.help or ""):  # the help says it in words
                continue
            assert f"(default: {action.default})" in text, (name, action.dest)
            checked += 1
    assert checked >= 15


def test_live_commands_help_shows_every_default_and_range():
    """play, serve, helm, view and view3d: every option that takes a value says its default (also when it is
    "none"), and every numeric option its allowed range, in --help."""
    parser = cli.build_parser()
    subs = dict(_subparsers(parser))
    checked = 0
    for name in ("play", "serve", "helm", "view", "view3d"):
        formatter = subs[name]._get_formatter()
        for action in subs[name]._actions:
            if not action.option_strings or action.nargs == 0 or action.dest == "help":
                continue
            opt = action.option_strings[0]
            entry = formatter._expand_help(action)  # the help text as --help prints it
            assert "default" in entry, (name, opt, entry)
            bounds = getattr(action.type, "bounds", None)
            if bounds is not None:
                assert all(b in entry for b in bounds if b != "inf"), (name, opt, entry)
            checked += 1
    assert checked >= 15
    play_help = " ".join(subs["play"].format_help().split())
    assert "--speedup SPEEDUP initial time factor (range: [0.25, 16])" in play_help


def test_cfd_help_shows_defaults():
    from cfd.cli import _parser

    run_parser = dict(_subparsers(_parser()))["run"]
    text = " ".join(run_parser.format_help().split())
    for shown in (
        "--grading GRADING mesh grading",
        "(default: 1)",
        "(default: 999.1)",
        "(default: 2,4,6,8,10)",
    ):
        assert shown in text


@pytest.mark.parametrize(
    "argv",
    [
        ("imo", "kvlcc2", "--ship", "mariner"),  # two different ships
        ("imo",),  # none
        ("manoeuvre", "stopping"),
        ("manoeuvre", "zigzag", "kvlcc2", "--ship", "dtc"),
    ],
)
def test_ship_named_exactly_once(capsys, argv):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and "ship" in err


@pytest.mark.parametrize(
    "form", [("kvlcc2_l7",), ("--ship", "kvlcc2_l7"), ("kvlcc2_l7", "--ship", "kvlcc2_l7")]
)
def test_ship_positional_or_option(capsys, monkeypatch, form):
    from vessel_gym.manoeuvres import trials

    seen = {}

    class Result:
        def to_dict(self):
            return {"ship": seen["ship"]}

    def fake_stopping(ship, speed):
        seen["ship"] = getattr(ship, "name", ship)  # the command may pass the loaded Ship
        return Result()

    monkeypatch.setattr(trials, "stopping", fake_stopping)
    code, out, err = run(capsys, "manoeuvre", "stopping", *form, "--json")
    assert code == 0, err
    assert seen["ship"] == "kvlcc2_l7"


def test_ships_lists_particulars_and_source(capsys):
    import json

    from vessel_gym.physics.shipfile import builtin_ships, load_ship

    code, out, _ = run(capsys, "ships", "--json")
    assert code == 0
    rows = {r["ship"]: r for r in json.loads(out)}
    assert set(rows) == set(builtin_ships())
    kv = rows["kvlcc2"]
    # Yasukawa & Yoshimura (2015) Table 1: KVLCC2 full scale L = 320 m, B = 58 m, d = 20.8 m, volume 312,600 m3
    assert (kv["L_m"], kv["B_m"], kv["T_m"]) == (320.0, 58.0, 20.8)
    assert kv["displacement_t"] == pytest.approx(312600 * 1.025, rel=1e-6)
    assert "Yasukawa" in kv["source"] and kv["test_speed_kn"] == load_ship("kvlcc2").particulars.test_speed_kn
    code, out, _ = run(capsys, "ships")
    assert code == 0
    lines = out.splitlines()
    assert lines[0].split()[:2] == ["ship", "hull"]
    for name in builtin_ships():
        (row,) = [i for i, line in enumerate(lines) if line.split()[:1] == [name]]
        assert lines[row + 1].strip().startswith("source: ")


@pytest.mark.parametrize(
    "argv, needle",
    [
        (("serve", "--seed", "-1"), "--seed"),
        (("play", "--seed", "-1"), "--seed"),
        (("play", "--max-steps", "-5"), "--max-steps"),
        (("manoeuvre", "zigzag", "kvlcc2", "--overshoots", "-1"), "--overshoots"),
        (("helm", "--server", "no.such.host.invalid:10120"), "--server"),
        (("view", "--listen", "8.8.8.8:41122"), "--listen"),
        ((), "no command given"),
        (("--version", "imo"), "--version takes no other arguments"),
        (("imo", "--version"), "--version takes no other arguments"),
    ],
)
def test_bad_arguments_one_line_exit_2(capsys, argv, needle):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and needle in err and "Traceback" not in err


def test_cfd_out_that_cannot_be_created(capsys, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    for out_dir in ("/proc/x", str(blocker / "sub")):
        code, out, err = run(
            capsys,
            "run",
            *("--hull", "wigley", "--lpp", "1", "--bwl", "0.1", "--tm", "0.0625", "--tests", "tow"),
            *("--out", out_dir),
            entry=cfd_main,
        )
        assert code == 2 and len(err.strip().splitlines()) == 1 and "out" in err and out_dir in err


def test_sigpipe_is_quiet():
    """``imo --json | head -c 600``: the reader leaves early; no BrokenPipeError traceback. The report is replaced
    by 200 kB of output (more than a pipe holds), so that the write fails whatever the timing."""
    code = (
        "import sys\n"
        "from vessel_gym import cli\n"
        "cli._cmd_imo = lambda args: print('x' * 200_000) or 0\n"
        "sys.exit(cli.main(['imo', 'kvlcc2', '--json']))\n"
    )
    proc = subprocess.run(
        f'{sys.executable} -c "{code}" | head -c 600 > /dev/null; echo ${{PIPESTATUS[0]}}',
        shell=True,
        executable="/bin/bash",
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert "Traceback" not in proc.stderr and "BrokenPipeError" not in proc.stderr, proc.stderr
    assert proc.stdout.strip() in ("0", "1")


def test_scenarios_each_with_one_line_of_description(capsys):
    from vessel_gym.scenarios import builtin_scenarios

    code, out, _ = run(capsys, "scenarios")
    assert code == 0
    lines = out.splitlines()
    assert [line.split()[0] for line in lines] == builtin_scenarios()
    for line in lines:
        assert len(line.split()) > 5 and line.endswith(".")


def test_ships_example_writes_a_documented_ship_file_that_loads(capsys, tmp_path):
    from vessel_gym.cli_ships import TEMPLATE
    from vessel_gym.physics.shipfile import load_ship

    target = tmp_path / "my_ship.toml"
    code, out, err = run(capsys, "ships", "--example", str(target))
    assert code == 0 and out == "" and str(target) in err
    text = target.read_text()
    ship, template = load_ship(target), load_ship(TEMPLATE)
    assert ship.name == "my_ship" and ship.particulars == template.particulars and ship.hull == template.hull
    assert "docs/ship-file.md" in text and f"vessel-gym imo {target.name}" in text
    # every key of [particulars] and [rudder] carries a comment: the schema's unit/range/meaning or its own
    for table in ("particulars", "rudder"):
        body = text.split(f"[{table}]\n", 1)[1].split("\n\n", 1)[0]
        assert all("#" in line for line in body.splitlines() if "=" in line), body
    assert "L_m = 7.0" in text and "m, [1, 500]: length between perpendiculars" in text
    # an existing file is not replaced without --force
    code, out, err = run(capsys, "ships", "--example", str(target))
    assert code == 2 and len(err.strip().splitlines()) == 1 and "--force" in err
    assert run(capsys, "ships", "--example", str(target), "--force")[0] == 0


def test_play_helm_and_view_without_a_display_say_so_in_one_line(capsys, monkeypatch):
    from vessel_gym.ui import display, panels, play

    assert display.no_display_reason({}, "linux") is not None
    assert display.no_display_reason({"DISPLAY": ":0"}, "linux") is None
    assert display.no_display_reason({"WAYLAND_DISPLAY": "wayland-0"}, "linux") is None
    assert display.no_display_reason({"SDL_VIDEODRIVER": "dummy"}, "linux") is None  # headless on purpose
    assert display.no_display_reason({}, "darwin") is None

    def opened(*a, **kw):
        raise AssertionError("a window was opened")

    monkeypatch.setattr(play, "play", opened)
    monkeypatch.setattr(panels, "run_helm", opened)
    monkeypatch.setattr(panels, "run_viewer", opened)
    monkeypatch.setattr(display.sys, "platform", "linux")
    for var in ("SDL_VIDEODRIVER", "DISPLAY", "WAYLAND_DISPLAY"):
        monkeypatch.delenv(var, raising=False)
    for command in ("play", "helm", "view"):
        code, out, err = run(capsys, command)
        assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, err
        assert err.startswith(f"vessel-gym {command}: no display") and "SDL_VIDEODRIVER=dummy" in err


def test_view_with_no_server_says_so(capsys, monkeypatch):
    import socket

    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:  # a free port nobody serves
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    code, out, err = run(capsys, "view", "--server", f"127.0.0.1:{port}", "--duration", "1")
    assert code == 1 and out == ""
    assert err.strip().splitlines()[-1].startswith(f"vessel-gym view: no state from 127.0.0.1:{port} in ")
    assert "vessel-gym serve" in err


@pytest.mark.parametrize("argv", [("imo", "x\x00.toml"), ("play", "x\x00.toml")])
def test_a_file_name_with_a_nul_is_escaped_in_its_one_line_error(capsys, argv):
    """A NUL (or any control character) in a file name is written as repr writes it, in the error the file
    reader raises as well as on the command line: one line, no raw control character."""
    from vessel_gym.physics.schema import SpecError, read_toml

    with pytest.raises(SpecError) as err:
        read_toml("x\x00.toml")
    assert str(err.value) == "x\\x00.toml: cannot read (embedded null byte)"
    code, out, err_text = run(capsys, *argv)
    assert code == 2 and out == ""
    assert err_text == "vessel-gym: x\\x00.toml: cannot read (embedded null byte)\n"
