"""The pipeline without OpenFOAM: frame conversions, fits, ship file, resume, failure messages."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from cfd_fake_foam import C_R, TRUE_PRIME, FakeFoam, fake_environment

from cfd.config import build_study
from cfd.errors import CfdError
from cfd.pipeline import DONE, Pipeline
from cfd.runner import Progress

DATA = Path(__file__).parent / "data"


def study(tmp_path: Path, **over):
    raw = {
        "hull": "wigley",
        "lpp": 1.0,
        "bwl": 0.1,
        "tm": 0.0625,
        "out": str(tmp_path / "out"),
        "grading": 1,
        "tests": "all",
        "speeds": "0.8,1.0,1.2",
        "pmm_speed": 1.0,
        "drift_deg": "3,6,9",
        "sway_period": 2.0,
        "sway_amplitude": "0.03",
        "yaw_period": 2.0,
        "yaw_deg": "5",
        "rho": 1000.0,
        "nu": 1e-6,
        "template": str(DATA / "small_ship.toml"),
        "scale_to": "cfd",
    }
    raw.update(over)
    return build_study(raw)


def run(s, fake, plots=False):
    return Pipeline(s, Progress(quiet=True), plots=plots).run()


@pytest.fixture
def fake(monkeypatch):
    return fake_environment(monkeypatch, FakeFoam())


def test_recovers_the_fake_hull_and_writes_a_loadable_ship_file(tmp_path, fake):
    result = run(study(tmp_path), fake, plots=True)
    d = result.derivatives
    assert result.normalisation == "rho_L2_U2"
    for k in ("Y_v", "N_v", "Y_vvv", "N_vvv", "X_vv"):  # steady: exact
        assert d[k] == pytest.approx(TRUE_PRIME[k], rel=1e-6), k
    for k in ("Y_vdot", "Y_r", "N_r", "N_rdot", "Y_rdot"):  # PMM: finite-difference error of the fake only
        assert d[k] == pytest.approx(TRUE_PRIME[k], rel=0.02), k
    assert d["X_rr"] == pytest.approx(TRUE_PRIME["X_rr"], rel=0.05)
    assert abs(d["N_vdot"] - TRUE_PRIME["N_vdot"]) < 2e-5
    # the fake's resistance is exactly the simulator's u|u| law: nothing left for X_u, X_uu
    assert abs(d["X_u"]) < 1e-9 and abs(d["X_uu"]) < 1e-9
    text = result.ship_file.read_text()
    assert "[hull.derivatives]" in text and "[source.provenance.mesh]" in text
    from vessel_gym.physics.shipfile import load_ship

    ship = load_ship(result.ship_file)
    assert ship.hull.normalisation == "rho_L2_U2" and ship.hull.coriolis == "separate"
    assert ship.hull.resistance_N == pytest.approx(C_R * 1.0**2)
    assert ship.hull.U_ref_m_s == pytest.approx(1.0)
    assert ship.particulars.L_m == pytest.approx(1.0) and ship.particulars.C_b == pytest.approx(
        4 / 9, rel=0.01
    )
    assert ship.particulars.k_zz_m == pytest.approx(0.25)  # the template's k_zz / L (from I_zG and mass)
    assert ship.particulars.I_zG_kgm2 is None  # replaced, not contradicted
    assert ship.steering_gear.max_rate_deg_s == 10.0  # copied from the template
    prov = ship.source.provenance
    assert prov["mesh"]["cells"] == 1234 and prov["derivative_origin"]["Y_vdot"] == "pure sway"
    report = result.report_dir
    for name in (
        "summary.md",
        "derivatives.json",
        "drift_Y_v.png",
        "sway_Y_vdot.png",
        "yaw_N_r.png",
        "tow_resistance.png",
        "convergence_steady.png",
    ):
        assert (report / name).is_file(), name
    dj = json.loads((report / "derivatives.json").read_text())
    assert dj["clarke83"]["Y_v"] < 0


def test_scaled_ship_file_and_half_normalisation(tmp_path, fake):
    s = study(tmp_path, scale_to="template", normalisation="half_rho_L2_U2")
    result = run(s, fake)
    from vessel_gym.physics.shipfile import load_ship

    ship = load_ship(result.ship_file)
    lam = 2.0  # small template: L = 2 m
    assert ship.particulars.L_m == pytest.approx(lam)
    assert ship.particulars.displacement_m3 == pytest.approx(lam**3 * result.provenance["hull"]["volume_m3"])
    assert ship.hull.U_ref_m_s == pytest.approx(math.sqrt(lam))  # Froude scaling
    assert ship.particulars.test_speed_kn == 2.0  # the template's
    assert result.derivatives["Y_v"] == pytest.approx(2 * TRUE_PRIME["Y_v"], rel=1e-6)
    assert result.provenance["scale"]["form_factor_k"] == pytest.approx(
        result.provenance["scale"]["form_factor_k"]
    )
    notes = ship.source.notes
    assert "[rudder], [steering_gear]" in notes and "borrowed unchanged from small-template" in notes
    assert "a ship of L = 2 m" in notes and "scaled by 2 to that length" in notes
    assert result.provenance["borrowed"]["tables"][:2] == ["rudder", "steering_gear"]


def test_an_unscaled_ship_file_says_its_borrowed_tables_were_sized_for_another_ship(tmp_path, fake):
    result = run(study(tmp_path, tests="tow", speeds="1.0"), fake)  # scale_to = cfd, template L = 2 m
    assert "NOT scaled (scale_to = cfd)" in result.borrowed and "2 times as long" in result.borrowed
    assert result.borrowed in result.ship_file.read_text()


def test_resume_skips_finished_cases_and_redoes_changed_ones(tmp_path, monkeypatch):
    first = fake_environment(monkeypatch, FakeFoam())
    s = study(tmp_path)
    run(s, first)
    cases = s.out / "cases"
    names = sorted(p.parent.name for p in cases.glob(f"*/{DONE}"))
    assert names == sorted(
        [
            "mesh",
            "tow_U0.8000",
            "tow_U1.0000",
            "tow_U1.2000",
            "drift_b03.00",
            "drift_b06.00",
            "drift_b09.00",
            "sway_a0.03000",
            "yaw_p05.00",
        ]
    )
    second = fake_environment(monkeypatch, FakeFoam())
    run(s, second)
    assert second.calls == []  # everything resumed
    third = fake_environment(monkeypatch, FakeFoam())
    # 8 deg lies inside the wake fan already refined for 9 deg (cfd.case.sizing.wake_regions): one case
    run(study(tmp_path, drift_deg="3,6,8,9"), third)
    assert {c for _, c in third.calls} == {"drift_b08.00"}
    marker = cases / "tow_U0.8000" / DONE
    marker.write_text(json.dumps({"key": "stale"}))
    fourth = fake_environment(monkeypatch, FakeFoam())
    run(study(tmp_path, drift_deg="3,6,8,9"), fourth)
    assert {c for _, c in fourth.calls} == {"tow_U0.8000"}


def test_a_drift_angle_beyond_the_wake_fan_remeshes(tmp_path, monkeypatch):
    s = study(tmp_path)
    run(s, fake_environment(monkeypatch, FakeFoam()))
    wider = fake_environment(monkeypatch, FakeFoam())
    run(study(tmp_path, drift_deg="3,6,9,12"), wider)  # the wake fan grows from 10 to 15 deg: new mesh
    assert ("snappyHexMesh", "mesh") in wider.calls and ("simpleFoam", "drift_b03.00") in wider.calls
    snappy = (s.out / "cases" / "mesh" / "system" / "snappyHexMeshDict").read_text()
    assert "wake_p15" in snappy and "wake_p20" not in snappy


def test_missing_hull_patch_is_a_clear_error(tmp_path, monkeypatch):
    fake_environment(monkeypatch, FakeFoam(hull_faces=0))
    with pytest.raises(CfdError) as err:
        run(study(tmp_path), None)
    msg = str(err.value)
    assert "snappyHexMesh (mesh)" in msg and "hull" in msg and "log.snappyHexMesh" in msg
    assert "\n" not in msg
    assert not (tmp_path / "out" / "cases" / "mesh" / DONE).exists()


def test_check_mesh_fatal_findings_stop_and_quality_warnings_do_not(tmp_path, monkeypatch):
    fake_environment(monkeypatch, FakeFoam(check_finding="Zero or negative cell volume detected."))
    with pytest.raises(CfdError, match=r"checkMesh \(mesh\) failed: unusable mesh: Zero or negative"):
        run(study(tmp_path, tests="tow"), None)
    fake_environment(monkeypatch, FakeFoam(check_finding="Max skewness = 4.2, 3 highly skew faces detected"))
    result = run(study(tmp_path / "b", tests="tow"), None)
    assert result.provenance["mesh"]["checkMesh_warnings"] == [
        "Max skewness = 4.2, 3 highly skew faces detected"
    ]


def test_divergence_is_reported_and_finished_cases_are_kept(tmp_path, monkeypatch):
    fake_environment(monkeypatch, FakeFoam(nan_in="drift_b06"))
    with pytest.raises(CfdError) as err:
        run(study(tmp_path), None)
    msg = str(err.value)
    assert "drift beta=6 deg" in msg and "diverged" in msg and "\n" not in msg
    cases = tmp_path / "out" / "cases"
    assert (cases / "mesh" / DONE).is_file() and (cases / "tow_U1.0000" / DONE).is_file()
    assert not (cases / "drift_b06.00" / DONE).exists()


def test_solver_crash_names_step_and_log(tmp_path, monkeypatch):
    fake_environment(monkeypatch, FakeFoam(fail_app="pimpleFoam"))
    with pytest.raises(CfdError) as err:
        run(study(tmp_path), None)
    assert err.value.log is not None and err.value.log.name == "log.pimpleFoam"
    assert "FOAM FATAL" in str(err.value)


def test_cli_run_exit_codes(tmp_path, monkeypatch, capsys):
    from cfd.cli import main

    fake_environment(monkeypatch, FakeFoam(hull_faces=0))
    args = [
        "run",
        "--hull",
        "wigley",
        "--lpp",
        "1",
        "--bwl",
        "0.1",
        "--tm",
        "0.0625",
        "--grading",
        "1",
        "--tests",
        "tow",
        "--out",
        str(tmp_path / "o"),
        "--template",
        str(DATA / "small_ship.toml"),
        "--quiet",
    ]
    assert main(args) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "snappyHexMesh (mesh)" in err[0]
    fake_environment(monkeypatch, FakeFoam())
    assert main([*args, "--scale-to", "cfd", "--speeds", "1.0"]) == 0
    out = capsys.readouterr().out
    assert "ship file:" in out and (tmp_path / "o" / "ship.toml").is_file()
    assert "borrowed:  The CFD hull is bare; [rudder]" in out


def test_free_surface_option_writes_a_vof_case_with_topsides(tmp_path, fake):
    from cfd.geometry import check_surface, read_stl

    s = study(tmp_path, tests="tow", speeds="1.0", free_surface="true")
    run(s, fake)
    case = s.out / "cases" / "free_surface_tow"
    assert "interFoam" in (case / "Allrun").read_text() and (case / "0.orig" / "alpha.water").is_file()
    hull = read_stl(case / "constant" / "triSurface" / "hull.stl")
    # the Wigley gets wall-sided topsides and a deck at z = T, closed all round
    assert hull[:, :, 2].max() == pytest.approx(0.0625) and check_surface(hull, z_max=1.0).open_edges == 0
    assert ("interFoam", "free_surface_tow") not in fake.calls  # written, not run
