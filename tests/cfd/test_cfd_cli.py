"""vessel-cfd command line: input validation (exit 2, one line naming the key), interactive set-up,
study files, the small commands."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import numpy as np
import pytest

from cfd.cli import interactive, main
from cfd.config import build_study, load_study_file
from cfd.errors import InputError

DATA = Path(__file__).parent / "data"
BASE = ["run", "--hull", "wigley", "--lpp", "1", "--bwl", "0.1", "--tm", "0.0625", "--out", "unused"]


def _replace(args, flag, value):
    out = list(args)
    if flag in out:
        out[out.index(flag) + 1] = value
    else:
        out += [flag, value]
    return out


@pytest.mark.parametrize(
    ("flag", "value", "named"),
    [
        ("--lpp", "-1", "lpp"),
        ("--lpp", "abc", "lpp"),
        ("--bwl", "0.9", "bwl"),  # more than Lpp / 2
        ("--tm", "0", "tm"),
        ("--grading", "6", "grading"),
        ("--grading", "2.5", "grading"),
        ("--tests", "tow,spin", "tests"),
        ("--hull", "missing.stl", "hull"),
        ("--hull", str(DATA / "small_ship.toml"), "hull"),  # not an STL
        ("--procs", "0", "procs"),
        ("--speeds", "0.5:0.2:3", "speeds"),  # MAX < MIN
        ("--speeds", "25", "speeds"),
        ("--drift-deg", "45", "drift_deg"),
        ("--sway-amplitude", "0.9", "sway_amplitude"),
        ("--yaw-deg", "-3", "yaw_deg"),
        ("--cycles", "1", "cycles"),
        ("--normalisation", "mmg", "normalisation"),
        ("--template", "nope.toml", "template"),
        ("--layers", "maybe", "layers"),
        ("--pmm-speed", "0.001", "pmm_speed"),  # Reynolds number too low
    ],
)
def test_bad_input_exits_2_with_one_line_naming_the_key(flag, value, named, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(_replace(BASE, flag, value)) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("vessel-cfd: error: ") and named in err[0]


def test_argparse_errors_are_one_line(capsys):
    with pytest.raises(SystemExit) as e:
        main(["run", "--no-such-option", "1"])
    assert e.value.code == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_study_file_and_overrides(tmp_path):
    f = tmp_path / "study.toml"
    f.write_text(
        'hull = "wigley"\nlpp = 2.0\nbwl = 0.2\ntm = 0.125\nout = "runs/w"\ngrading = 2\ntests = ["tow", "yaw"]\n'
        'speeds = "1.0:2.0:3"\nyaw_deg = [3, 6]\ndrift_deg = "0:8:5"\n'
    )
    s = load_study_file(f, {"grading": "3"})
    assert s.out == tmp_path / "runs" / "w"
    assert s.grading == 3 and s.tests == ("tow", "yaw")
    assert s.speeds == (1.0, 1.5, 2.0) and s.pmm_speed == 2.0
    assert s.drift_deg == (2.0, 4.0, 6.0, 8.0)  # 0 is the straight tow, run anyway
    assert s.yaw_period == pytest.approx(3.14159265 * 2.0 / 2.0, rel=1e-6)  # omega' = 2 by default
    bad = tmp_path / "bad.toml"
    bad.write_text('hull = "wigley"\nlpp = 2\nbwl = 0.2\ntm = 0.1\nout = "x"\nspeed = 1\n')
    with pytest.raises(InputError) as err:
        load_study_file(bad)
    assert err.value.key == "speed" and "unknown key" in str(err.value)
    with pytest.raises(InputError, match="not valid TOML"):
        (tmp_path / "broken.toml").write_text("hull = ")
        load_study_file(tmp_path / "broken.toml")


def test_cli_study_option_validates(tmp_path, capsys):
    f = tmp_path / "s.toml"
    f.write_text('hull = "wigley"\nlpp = 1\nbwl = 0.1\ntm = 0.0625\nout = "o"\ngrading = 9\n')
    assert main(["run", "--study", str(f)]) == 2
    assert "grading" in capsys.readouterr().err


def _answers(tmp_path):
    return iter(
        [
            "7",
            "5",  # simulation type: invalid, then full PMM
            "nothere.stl",
            "wigley",
            "-1",
            "1.0",  # Lpp
            "0.1",
            "0.0625",
            "",
            "2",  # processors: meshing (default 1), solving
            "9",
            "1",  # grading
            "0.8,1.0",
            "",  # tow speeds, PMM speed (default: Fn 0.2)
            "2",
            "1",
            "8",
            "4",  # drift: min, max < min (re-asked), max, count
            "2",
            "0.02",
            "0.03",
            "2",  # sway period, amplitude min, max, count
            "",
            "3",
            "3",  # yaw period (default), yaw angle min, max (one case)
            str(tmp_path / "out"),
            str(DATA / "small_ship.toml"),
        ]
    )


def test_interactive_flow_reasks_invalid_answers(capsys, tmp_path):
    answers = _answers(tmp_path)
    study = interactive(read=lambda prompt: next(answers), run=False)
    out = capsys.readouterr().out
    assert "WELCOME TO vessel-cfd" in out and "ULTRA COARSE" in out
    assert out.count("invalid:") == 5  # type, hull, Lpp, grading, drift maximum
    assert study.tests == ("tow", "drift", "sway", "yaw")
    assert study.lpp == 1.0 and study.grading == 1 and study.procs == 2 and study.mesh_procs == 1
    assert study.speeds == (0.8, 1.0) and study.pmm_speed == pytest.approx(0.2 * (9.81) ** 0.5, rel=1e-3)
    assert study.drift_deg == (2.0, 4.0, 6.0, 8.0)
    assert study.sway_amplitude == (0.02, 0.03) and study.sway_period == 2.0
    assert study.yaw_deg == (3.0,)
    assert study.template == DATA / "small_ship.toml"


def test_interactive_end_of_input_is_an_input_error():
    answers = iter(["1"])

    def read(prompt):
        try:
            return next(answers)
        except StopIteration:
            raise EOFError from None

    with pytest.raises(InputError, match="ended"):
        interactive(read=read, run=False)


def test_wigley_and_clarke_commands(tmp_path, capsys):
    out = tmp_path / "w.stl"
    assert main(["wigley", "--lpp", "2", "--bwl", "0.2", "--tm", "0.125", "--out", str(out)]) == 0
    assert out.read_text().startswith("solid hull")
    assert main(["clarke", "--lpp", "1", "--bwl", "0.1", "--tm", "0.0625", "--cb", "0.4444"]) == 0
    text = capsys.readouterr().out
    d = json.loads(text[text.index("{") :])
    assert d["Y_v"] == pytest.approx(-0.01576, abs=1e-5)
    assert main(["clarke", "--lpp", "1", "--bwl", "0.1", "--tm", "0.0625", "--cb", "2"]) == 2


def test_build_study_defaults_scale_with_the_hull():
    s = build_study({"hull": "wigley", "lpp": 4.0, "bwl": 0.4, "tm": 0.25, "out": "x"})
    assert s.speeds == (round(0.2 * (9.81 * 4.0) ** 0.5, 6),)  # Fn 0.2
    assert s.sway_amplitude == (0.1,)  # 0.025 L
    assert s.sway_period == pytest.approx(3.14159265 * 4.0 / s.pmm_speed, rel=1e-6)
    assert s.as_dict()["out"] == str(Path.cwd() / "x")  # relative paths resolve against the cwd


def test_interactive_set_up_saves_its_study_file_without_overwriting(capsys, tmp_path):
    answers = _answers(tmp_path)
    study = interactive(read=lambda prompt: next(answers), run=False)
    for _ in range(2):  # the same study twice: one file
        answers = itertools.chain(_answers(tmp_path), ["n"])
        assert interactive(read=lambda prompt, a=answers: next(a)) == 0
    saved = tmp_path / "out" / "study.toml"
    assert f"Study saved to {saved}" in capsys.readouterr().out
    assert sorted(p.name for p in saved.parent.iterdir()) == ["study.toml"]
    assert load_study_file(saved) == study  # the saved file gives back the same study
    saved.write_text("# the user's own study file\n")
    answers = itertools.chain(_answers(tmp_path), ["n"])
    interactive(read=lambda prompt: next(answers))
    assert saved.read_text() == "# the user's own study file\n"
    assert load_study_file(saved.parent / "study-1.toml") == study


# ------------------------------------------------------------------------------ hulls the tool refuses
def _stl_case(tmp_path, triangles, *extra):
    from cfd.geometry import write_stl

    stl = write_stl(tmp_path / "hull.stl", triangles)
    return ["run", "--hull", str(stl), "--lpp", "1", "--bwl", "0.1", "--tm", "0.0625", "--out", str(tmp_path / "o")]


def _refused(argv, capsys, monkeypatch):
    """Exit 2 with one line, before any OpenFOAM application could start (none is allowed to)."""
    from cfd import pipeline

    def no_foam(*a, **k):
        raise AssertionError("OpenFOAM started for a hull that should have been refused")

    monkeypatch.setattr(pipeline, "run_app", no_foam)
    monkeypatch.setattr(pipeline, "check_openfoam", no_foam)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("vessel-cfd: error: ")
    return err[0]


def _wigley_keel_at_zero():
    from cfd.geometry import wigley_hull

    return wigley_hull(1.0, 0.1, 0.0625) + np.array([0.5, 0.0, 0.0625])  # stern x = 0, keel z = 0, deck 2T


def test_an_stl_with_a_hole_under_water_is_refused_with_the_reason(tmp_path, capsys, monkeypatch):
    tris = _wigley_keel_at_zero()
    wet = np.flatnonzero(tris[:, :, 2].mean(axis=1) < 0.03)
    holed = np.delete(tris, wet[[10, len(wet) // 2]], axis=0)  # two triangles missing under water
    line = _refused(_stl_case(tmp_path, holed), capsys, monkeypatch)
    assert "hull: the STL is not closed below the waterline: 6 open" in line


def test_a_millimetre_hull_with_particulars_in_metres_is_refused_naming_the_unit(tmp_path, capsys, monkeypatch):
    line = _refused(_stl_case(tmp_path, _wigley_keel_at_zero() * 1000.0), capsys, monkeypatch)
    assert "lpp:" in line and "millimetres" in line and "1000 x Lpp" in line


@pytest.mark.parametrize(
    ("z_keel", "named", "reason"),
    [
        (5.0, "z_keel", "whole hull would lie below the domain"),  # waterline above the STL's top
        (0.9, "z_keel", "below the domain's bottom"),  # the STL reaches 0.96 m below the waterline
        (-5.0, "z_keel", "nothing is under water"),  # waterline below the STL's keel
    ],
)
def test_a_hull_outside_the_domain_is_refused_with_the_reason(tmp_path, capsys, monkeypatch, z_keel, named, reason):
    tris = _wigley_keel_at_zero()
    tall = tris.copy()
    tall[:, :, 2] *= 8.0  # a hull 1 m deep: keel z = 0, deck z = 1 m
    argv = _stl_case(tmp_path, tall if z_keel == 0.9 else tris) + ["--z-keel", str(z_keel)]
    line = _refused(argv, capsys, monkeypatch)
    assert f"error: {named}:" in line and reason in line, line
