"""Static heel with OpenFOAM: a heeled tow and an upright drift of the Wigley hull at grading 1 without prism
layers (the coarsest set-up that runs), one core. Two meshes (upright, heeled 10 deg) and three simpleFoam
runs, about 1-2 min. Skipped only when OpenFOAM is not installed.

What the signs must be, and why (standard axes, K about the still waterline, z_G = 0):
* upright drift: the lateral force Y opposing the sway acts below the waterline (near half draught for a
  Wigley), so K = -z Y with z > 0 down: K and Y of opposite sign, |K| / |Y| between 0.3 T and 0.7 T;
* K_v > 0 follows (Y_v < 0);
* heeled tow: the heel-induced side force is a pressure force on the thin underwater body, whose surface
  normals are nearly horizontal, so K ~ -integral of z dY again: K and Y of opposite sign, |K| < T |Y|;
  and by d'Alembert (a fore-aft symmetric body, no net side force in potential flow) that Y is small
  against the drift's: below 10 % of it.
"""

from __future__ import annotations

import math
import time

import pytest

from cfd.config import build_study
from cfd.pipeline import Pipeline
from cfd.runner import Progress, openfoam_available

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

pytestmark = [
    pytest.mark.openfoam,
    pytest.mark.slow,
    pytest.mark.skipif(
        not openfoam_available(), reason="OpenFOAM (Debian package openfoam) is not installed"
    ),
]

L, B, T = 1.0, 0.1, 0.0625


@pytest.fixture(scope="module")
def heel_result(tmp_path_factory):
    out = tmp_path_factory.mktemp("wigley_heel")
    study = build_study(
        {
            "hull": "wigley",
            "lpp": L,
            "bwl": B,
            "tm": T,
            "grading": 1,
            "layers": False,
            "max_iterations": 300,
            "tests": "tow,drift,heel",
            "out": str(out),
            "procs": 1,
            "pmm_speed": 1.0,
            "speeds": "1.0",
            "drift_deg": "6",
            "heel_deg": "10",
            "heel_drift_deg": 0.0,
            "GM": 0.01,
            "k_xx": 0.04,
            "rho": 1000.0,
            "nu": 1e-6,
            "scale_to": "cfd",
        }
    )
    t0 = time.monotonic()
    result = Pipeline(study, Progress(interval_s=30.0), plots=False).run()
    return result, time.monotonic() - t0, out


def test_heeled_tow_and_drift_give_roll_moments_of_the_expected_sign(heel_result):
    result, wall, out = heel_result
    heel = result.provenance["heel"]
    pts = {p["case"]: p for p in heel["points"]}
    drift = pts["drift_b06.00"]
    tow = pts["heel_p10.00_b+00.00"]
    print(f"\nWigley static heel, grading 1, no layers: wall {wall:.0f} s; points {pts}; fit {heel['derivatives']}")
    assert drift["Y"] > 0.0 and drift["K"] < 0.0  # v < 0 (to port), Y to starboard, heels to port
    assert 0.3 * T < -drift["K"] / drift["Y"] < 0.7 * T
    assert heel["derivatives"]["K_v"] > 0.0
    assert all(math.isfinite(tow[k]) for k in ("Y", "N", "K"))
    assert tow["K"] * tow["Y"] < 0.0 and abs(tow["K"]) < T * abs(tow["Y"])
    assert abs(tow["Y"]) < 0.1 * abs(drift["Y"])
    upright = pts["tow_U1.0000"]
    assert abs(tow["K"]) > 10.0 * abs(upright["K"])  # the heel, not the noise of the upright tow
    ship = tomllib.loads(result.ship_file.read_text())
    assert ship["roll"]["derivatives"]["K_phi"] == pytest.approx(heel["derivatives"]["K_phi"])
