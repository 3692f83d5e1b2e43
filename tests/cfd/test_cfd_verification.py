"""The verification gate on the fake-foam double: every check, which derivatives a failure marks
unverified, and the exit code of an unverified run."""

from __future__ import annotations

import json

import pytest
from cfd_fake_foam import FakeFoam, fake_environment
from test_cfd_pipeline import DATA, run, study

from cfd.verification import LIMITS


def _checks(gate, case):
    return {c["name"]: c for c in gate["cases"][case]}


def test_a_clean_study_is_verified_and_reports_every_check(tmp_path, monkeypatch):
    fake = fake_environment(monkeypatch, FakeFoam())
    result = run(study(tmp_path, speeds="1.0", drift_deg="4,8"), fake)
    gate = result.verification
    assert result.verified and gate["failures"] == []
    assert set(gate["cases"]) == {
        "tow_U1.0000",
        "drift_b04.00",
        "drift_b08.00",
        "sway_a0.03000",
        "yaw_p05.00",
    }
    tow = _checks(gate, "tow_U1.0000")
    assert set(tow) == {
        "y+",
        "y+ at the layer target",
        "Reynolds number",
        "k >= 0",
        "converged before the iteration cap",
        "force settling",
    }
    assert tow["y+"]["value"] == {"min": 40.0, "max": 250.0, "mean": 120.0}  # y+ of every case, not only tows
    assert tow["y+ at the layer target"]["value"]["ratio"] == pytest.approx(
        120.0 / 150.0
    )  # default target 150
    assert _checks(gate, "yaw_p05.00")["y+"]["passed"]
    sway = _checks(gate, "sway_a0.03000")
    assert sway["periodicity"]["value"]["Y"] < 1e-3 and sway["Courant number"]["value"] == pytest.approx(
        1.8, 0.01
    )
    area = {c["name"]: c for c in gate["study"]}["hull patch area"]["value"]
    assert area["relative"] == pytest.approx(0.0, abs=1e-9)  # the fake's patch has the STL's wetted area
    layers = {c["name"]: c for c in gate["study"]}["prism layers"]
    assert layers["passed"] and layers["value"]["thickness_fraction"] == pytest.approx(0.8)
    assert set(gate["derivatives"]["Y_v"].split()) == {"verified"}
    assert gate["derivatives"]["X_udot"].startswith("estimate")
    summary = (result.report_dir / "summary.md").read_text()
    assert "## Verification: VERIFIED" in summary and "| sway_a0.03000 | periodicity |" in summary
    saved = json.loads((result.report_dir / "derivatives.json").read_text())
    assert saved["verification"]["verdict"] == "VERIFIED"
    assert "Verification gate: VERIFIED" in result.ship_file.read_text()


@pytest.mark.parametrize(
    ("fake_kw", "study_kw", "failed", "unverified", "verified"),
    [
        (
            {"yplus": (60.0, 3000.0, 450.0)},
            {},
            ("drift_b04.00", "y+"),
            {"Y_v", "Y_r", "Y_vdot", "X_vv"},
            set(),
        ),
        ({"bounding_k_in": "yaw"}, {}, ("yaw_p05.00", "k >= 0"), {"Y_r", "N_rdot"}, {"Y_v", "Y_vdot"}),
        ({"courant": 12.0}, {}, ("sway_a0.03000", "Courant number"), {"Y_vdot", "Y_r"}, {"Y_v", "N_v"}),
        ({"settle": False}, {}, ("drift_b04.00", "force settling"), {"Y_v", "N_v"}, {"Y_vdot", "Y_r"}),
        ({}, {"nu": 1e-5}, ("tow_U1.0000", "Reynolds number"), {"Y_v", "Y_r"}, set()),
        ({}, {"cycles": 2.0, "fit_cycles": 1.0}, ("sway_a0.03000", "periodicity"), {"Y_vdot"}, {"Y_v"}),
        ({"hull_area_factor": 2.0}, {}, ("hull patch area",), {"Y_v", "Y_r", "Y_vdot"}, set()),
        ({"layer_fraction": 0.3}, {}, ("prism layers",), {"Y_v", "Y_r", "Y_vdot"}, set()),
        (  # y+ inside the wall-function range, but far below what the layers were sized for
            {"yplus": (5.0, 60.0, 30.0)},
            {},
            ("drift_b04.00", "y+ at the layer target"),
            {"Y_v", "N_v"},
            set(),
        ),
    ],
)
def test_a_failed_check_marks_the_derivatives_it_feeds(
    tmp_path, monkeypatch, fake_kw, study_kw, failed, unverified, verified
):
    fake = fake_environment(monkeypatch, FakeFoam(**fake_kw))
    result = run(study(tmp_path, speeds="1.0", drift_deg="4,8", **study_kw), fake)
    gate = result.verification
    assert not result.verified
    assert ": ".join(failed) in gate["failures"]
    for k in unverified:
        assert gate["derivatives"][k].startswith("unverified"), k
    for k in verified:
        assert gate["derivatives"][k] == "verified", k
    assert "## Verification: UNVERIFIED" in (result.report_dir / "summary.md").read_text()


def test_the_thresholds_are_the_documented_ones():
    doc = (DATA.parents[2] / "docs" / "cfd.md").read_text()
    for key, value in LIMITS.items():
        assert f"`{key}` = {value:g}" in doc, key


def test_an_unverified_run_exits_3_and_keeps_its_ship_file(tmp_path, monkeypatch, capsys):
    from cfd.cli import EXIT_UNVERIFIED, main

    fake_environment(monkeypatch, FakeFoam(yplus=(60.0, 3000.0, 450.0)))
    out = tmp_path / "o"
    args = ["run", "--hull", "wigley", "--lpp", "1", "--bwl", "0.1", "--tm", "0.0625", "--tests", "tow"]
    args += ["--out", str(out), "--template", str(DATA / "small_ship.toml"), "--scale-to", "cfd", "--quiet"]
    assert main(args) == EXIT_UNVERIFIED == 3
    printed = capsys.readouterr().out
    assert "verification: UNVERIFIED" in printed and "y+" in printed
    assert (out / "ship.toml").is_file() and (out / "report" / "summary.md").is_file()
