"""The whole pipeline with OpenFOAM on a Wigley hull at grading 1 (ULTRA COARSE), checked against
Clarke, Gedling & Hine (1983), Trans. RINA 125, 45-68 (regressions as printed in Fossen's Handbook).

About 2 min on two free cores with the earlier numerical defaults (108 s measured; 13.6k cells), 10 min on
one shared core with the current ones (prism layers, backward time at Courant 1; 15.1k cells). Tow at two
speeds, static drift at 3, 6 and 9 deg, one pure sway and one pure yaw run of three periods at omega' = pi.
Skipped only when OpenFOAM is not installed.
"""

from __future__ import annotations

import time

import pytest

from cfd.clarke import clarke83
from cfd.config import build_study
from cfd.pipeline import Pipeline
from cfd.runner import Progress, openfoam_available, read_boundary

pytestmark = [
    pytest.mark.openfoam,
    pytest.mark.slow,
    pytest.mark.skipif(
        not openfoam_available(), reason="OpenFOAM (Debian package openfoam) is not installed"
    ),
]

L, B, T = 1.0, 0.1, 0.0625


@pytest.fixture(scope="module")
def wigley_result(tmp_path_factory):
    out = tmp_path_factory.mktemp("wigley")
    study = build_study(
        {
            "hull": "wigley",
            "lpp": L,
            "bwl": B,
            "tm": T,
            "grading": 1,
            "tests": "all",
            "out": str(out),
            "procs": 2,
            "speeds": "0.8,1.0",
            "pmm_speed": 1.0,
            "drift_deg": "3,6,9",
            "sway_period": 2.0,
            "sway_amplitude": "0.03",
            "yaw_period": 2.0,
            "yaw_deg": "5",
            "rho": 1000.0,
            "nu": 1e-6,
        }
    )
    t0 = time.monotonic()
    result = Pipeline(study, Progress(interval_s=30.0)).run()
    return result, time.monotonic() - t0, out


def test_mesh_is_ok_and_has_the_hull(wigley_result):
    result, _, out = wigley_result
    mesh = result.provenance["mesh"]
    assert mesh["checkMesh_ok"] is True
    assert mesh["cells"] > 5000
    hull = read_boundary(out / "cases" / "mesh")["hull"]
    assert hull["type"] == "wall" and int(hull["nFaces"]) > 100


def test_linear_derivatives_against_clarke_1983(wigley_result):
    result, wall, _ = wigley_result
    d = result.derivatives
    assert result.normalisation == "rho_L2_U2"
    clarke = clarke83(L, B, T, 4.0 / 9.0, "rho_L2_U2")
    assert d["Y_v"] < 0 and d["N_v"] < 0 and d["Y_r"] > 0 and d["N_r"] < 0 and d["Y_vdot"] < 0
    ratios = {k: d[k] / clarke[k] for k in ("Y_v", "N_v", "Y_r", "N_r", "Y_vdot")}
    print(
        f"\nWigley grading 1, wall time {wall:.0f} s; CFD / Clarke (1983): "
        + ", ".join(f"{k} {v:.3f}" for k, v in ratios.items())
    )
    for k, ratio in ratios.items():
        assert 0.65 <= ratio <= 1.35, f"{k}: CFD {d[k]:.5g} vs Clarke {clarke[k]:.5g}"


def test_resistance_is_friction_plus_a_small_form_effect(wigley_result):
    result, _, _ = wigley_result
    tow = result.provenance["tests"]["tow"]
    ratio = [ct / cf for ct, cf in zip(tow["C_T"], tow["C_F_ITTC57"], strict=True)]
    # double body: no wave resistance; 1 + k of a slender Wigley is close to 1
    assert all(0.95 < r < 1.2 for r in ratio), ratio
    assert all(tow["converged"])


def test_ship_file_loads_in_the_simulator(wigley_result):
    result, _, _ = wigley_result
    from vessel_gym.physics.shipfile import load_ship

    ship = load_ship(result.ship_file)
    assert ship.hull.model == "abkowitz" and ship.hull.derivatives["Y_v"] == pytest.approx(
        result.derivatives["Y_v"]
    )
    assert (result.report_dir / "summary.md").is_file()
