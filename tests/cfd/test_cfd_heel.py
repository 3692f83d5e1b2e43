"""Static heel without OpenFOAM: the heeled hull, the roll fit, the [roll] table of the ship file."""

from __future__ import annotations

import hashlib
import math

import numpy as np
import pytest
from cfd_fake_foam import TRUE_PRIME, TRUE_ROLL, FakeFoam, fake_environment
from test_cfd_pipeline import run, study

from cfd.config import TESTS, build_study, parse_tests
from cfd.errors import InputError
from cfd.geometry import hydrostatics, read_stl, wigley_hull
from cfd.heel import check_freeboard, fit_roll, heel_triangles, roll_about_G

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

HEEL = {"tests": "tow,drift,heel", "heel_deg": "10", "heel_drift_deg": 6.0, "GM": 0.02, "k_xx": 0.04}


def test_heel_turns_starboard_down_about_the_waterline():
    tris = wigley_hull(1.0, 0.1, 0.0625)
    h = heel_triangles(tris, 10.0)
    pts, hp = tris.reshape(-1, 3), h.reshape(-1, 3)
    stbd_wl = np.argmin(pts[:, 1] + np.abs(pts[:, 2]))  # widest starboard point on the waterline
    assert pts[stbd_wl, 2] == pytest.approx(0.0, abs=1e-9)
    assert hp[stbd_wl, 2] == pytest.approx(-math.sin(math.radians(10.0)) * -pts[stbd_wl, 1], rel=1e-9)
    assert np.allclose(hp[:, 0], pts[:, 0])  # about the x-axis: x unchanged
    assert np.allclose(np.linalg.norm(hp[:, 1:], axis=1), np.linalg.norm(pts[:, 1:], axis=1))
    # a rigid rotation: the closed double body keeps its volume
    assert hydrostatics(h).volume_m3 == pytest.approx(hydrostatics(tris).volume_m3, rel=1e-9)


def test_roll_moment_moves_to_G_with_the_side_force():
    # G 0.1 m above the waterline, a side force of 2 N to port in the case frame (Fy = +2, Y = -2):
    # M_G = M_O + (O - G) x F, x component 0 - (-0.1)(2) = +0.2 N m
    assert roll_about_G(0.5, 2.0, 0.1) == pytest.approx(0.7)


def test_fit_needs_upright_drift_and_heel():
    with pytest.raises(ValueError, match="upright drift and heeled"):
        fit_roll([{"v": 0.1, "phi": 0.0, "Y": 1.0, "N": 1.0, "K": 1.0}], U=1.0, L=1.0, rho=1000.0)


def test_tests_heel_is_optional_and_needs_drift_and_a_roll_table(tmp_path):
    assert parse_tests("all") == TESTS and "heel" not in TESTS
    assert parse_tests("all,heel") == (*TESTS, "heel")
    with pytest.raises(InputError, match="needs 'drift'"):
        study(tmp_path, **{**HEEL, "tests": "tow,heel"})
    with pytest.raises(InputError, match="GM"):
        study(tmp_path, **{**HEEL, "GM": ""})
    with pytest.raises(InputError, match="heel_deg"):
        study(tmp_path, **{**HEEL, "heel_deg": "45"})


def test_pipeline_heels_the_mesh_and_recovers_the_roll_terms(tmp_path, monkeypatch):
    fake = fake_environment(monkeypatch, FakeFoam())
    s = study(tmp_path, **HEEL)
    result = run(s, fake)
    cases = s.out / "cases"
    # one heeled mesh, from the hull rotated 10 deg; the heeled tow and the heeled drift at +/- 6 deg on it
    heeled = read_stl(cases / "mesh_heel10.00" / "constant" / "triSurface" / "hull.stl")
    upright = read_stl(cases / "hull.stl")
    assert np.allclose(heeled, heel_triangles(upright, 10.0), atol=1e-6)
    stl = hashlib.sha256((cases / "hull_heel10.00.stl").read_bytes()).hexdigest()
    for b in ("+00.00", "+06.00", "-06.00"):  # the fake's mesh names the STL it was made from
        assert f"hull.stl {stl}" in (cases / f"heel_p10.00_b{b}" / "constant" / "polyMesh" / "points").read_text()
    assert f"hull.stl {stl}" not in (cases / "drift_b06.00" / "constant" / "polyMesh" / "points").read_text()
    ship = tomllib.loads(result.ship_file.read_text())
    got = ship["roll"]["derivatives"]
    assert set(got) == set(TRUE_ROLL)  # every K term, and the Y and N terms with phi only
    for k, v in TRUE_ROLL.items():
        assert got[k] == pytest.approx(v, rel=1e-6, abs=1e-12), k
    # a new [roll] table from the study's GM and k_xx (scale_to = cfd: model scale)
    assert ship["roll"]["GM_m"] == pytest.approx(0.02)
    m = ship["particulars"]["displacement_m3"] * ship["particulars"]["rho_kg_m3"]
    assert ship["roll"]["I_xG_kgm2"] == pytest.approx(m * 0.04**2)
    assert ship["source"]["provenance"]["heel"]["fit_rms_prime"]["K"] < 1e-10
    # the heeled cases pass the verification gate's per-case checks like the upright ones
    gate = result.verification
    assert {"heel_p10.00_b+00.00", "heel_p10.00_b+06.00"} <= set(gate["cases"])
    assert gate["verdict"] == "VERIFIED", gate["failures"]
    summary = (s.out / "report" / "summary.md").read_text()
    assert "## Static heel" in summary and "heel_p10.00_b-06.00" in summary
    from vessel_gym.physics.shipfile import load_ship

    assert load_ship(result.ship_file).roll is not None


def test_roll_terms_are_taken_about_G(tmp_path, monkeypatch):
    fake = fake_environment(monkeypatch, FakeFoam())
    s = study(tmp_path, **HEEL, z_G=0.05)
    got = tomllib.loads(run(s, fake).ship_file.read_text())["roll"]["derivatives"]
    # K'_G = K'_O - (z_G / L) Y' (G above the waterline; Y' in the 1/2 rho prime system of [roll])
    y_v_half = 2.0 * TRUE_PRIME["Y_v"]  # the fake's hull terms are in rho_L2_U2
    assert got["K_v"] == pytest.approx(TRUE_ROLL["K_v"] - 0.05 * y_v_half, rel=1e-6)
    assert got["K_phi"] == pytest.approx(TRUE_ROLL["K_phi"] - 0.05 * TRUE_ROLL["Y_phi"], rel=1e-6)


def test_without_heel_the_ship_file_has_no_roll_table(tmp_path, monkeypatch):
    fake = fake_environment(monkeypatch, FakeFoam())
    s = build_study({**_raw(tmp_path), "tests": "tow,drift"})
    assert "roll" not in tomllib.loads(run(s, fake).ship_file.read_text())


def _raw(tmp_path):
    return {
        "hull": "wigley",
        "lpp": 1.0,
        "bwl": 0.1,
        "tm": 0.0625,
        "out": str(tmp_path / "out"),
        "pmm_speed": 1.0,
        "speeds": "1.0",
        "drift_deg": "3,6",
        "rho": 1000.0,
        "nu": 1e-6,
        "scale_to": "cfd",
        "template": str(__import__("test_cfd_pipeline").DATA / "small_ship.toml"),
    }


def test_resume_keeps_the_heel_cases_and_a_new_angle_meshes_again(tmp_path, monkeypatch):
    run(study(tmp_path, **HEEL), fake_environment(monkeypatch, FakeFoam()))
    again = fake_environment(monkeypatch, FakeFoam())
    run(study(tmp_path, **HEEL), again)
    assert again.calls == []  # every case, the heel mesh too, found done
    other = fake_environment(monkeypatch, FakeFoam())
    run(study(tmp_path, **{**HEEL, "heel_deg": "5"}), other)
    ran = {case for _, case in other.calls}
    assert ran == {"mesh_heel05.00", "heel_p05.00_b+00.00", "heel_p05.00_b+06.00", "heel_p05.00_b-06.00"}


def test_a_hull_without_topsides_is_not_heeled():
    tris = wigley_hull(1.0, 0.1, 0.0625)
    under = tris[np.all(tris[..., 2] <= 1e-12, axis=1)]  # the underwater half only: nothing above z = 0
    check_freeboard(tris, 0.1, 10.0)  # the double body reaches T = 0.0625 m > 0.05 tan 10 deg
    with pytest.raises(InputError, match="heel_deg: 10 deg immerses"):
        check_freeboard(under, 0.1, 10.0)
