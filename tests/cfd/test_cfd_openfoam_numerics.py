"""The default numerics with OpenFOAM: prism layers are added and give the y+ they were sized for, and a
pure-sway run with the backward scheme and the wake cylinders runs to its end.

A Wigley hull (L = 1 m, Re = 1e6) at grading 1: mesh with layers (about 15k cells, 6 s), one straight tow
(about 140 SIMPLE iterations, 15 s) and a short pure sway (1.5 periods of 0.5 s, 60 steps, about 25 s) on one
core. The sway is too short for the periodicity check, so the study itself is not asserted to be verified.
"""

from __future__ import annotations

import math

import pytest

from cfd.config import build_study
from cfd.pipeline import Pipeline
from cfd.postprocess import read_forces
from cfd.runner import Progress, openfoam_available, parse_layers

pytestmark = [
    pytest.mark.openfoam,
    pytest.mark.slow,
    pytest.mark.skipif(
        not openfoam_available(), reason="OpenFOAM (Debian package openfoam) is not installed"
    ),
]


@pytest.fixture(scope="module")
def layered(tmp_path_factory):
    out = tmp_path_factory.mktemp("layered")
    study = build_study(
        {
            "hull": "wigley",
            "lpp": 1.0,
            "bwl": 0.1,
            "tm": 0.0625,
            "grading": 1,
            "tests": "tow,sway",
            "out": str(out),
            "speeds": "1.0",
            "sway_period": 0.5,
            "sway_amplitude": "0.01",
            "cycles": 1.5,
            "fit_cycles": 1,
            "rho": 1000.0,
            "nu": 1e-6,
        }
    )
    assert study.layers and study.wake and study.time_scheme == "backward"  # the defaults under test
    return Pipeline(study, Progress(interval_s=30.0), plots=False).run(), out / "cases"


def test_layers_are_added_and_hit_the_yplus_target(layered):
    result, cases = layered
    layers = parse_layers(cases / "mesh" / "log.snappyHexMesh")["hull"]
    assert layers["layers"] >= 1.5 and layers["thickness_pct"] >= 50.0
    gate = result.verification
    assert {c["name"]: c["passed"] for c in gate["study"]}["prism layers"] is True
    tow = {c["name"]: c for c in gate["cases"]["tow_U1.0000"]}
    # without layers this mesh gives a mean y+ of about 300; the layers are sized for 150
    assert tow["y+ at the layer target"]["passed"] and 100 < tow["y+"]["value"]["mean"] < 200
    assert tow["converged before the iteration cap"]["passed"] and tow["force settling"]["passed"]
    snappy = (cases / "mesh" / "system" / "snappyHexMeshDict").read_text()
    assert "wake_p00" in snappy and "wake_m05" in snappy and "wake_p05" in snappy  # sway path angle 7.2 deg


def test_the_backward_sway_runs_to_its_end(layered):
    result, cases = layered
    sway = cases / "sway_a0.01000"
    assert "backward" in (sway / "system" / "fvSchemes").read_text()
    log = (sway / "log.pimpleFoam").read_text()
    assert log.rstrip().endswith("End")
    h = read_forces(sway)
    assert h.t[-1] == pytest.approx(0.75, rel=1e-6) and all(math.isfinite(v) for v in h.F.ravel())
    co = {c["name"]: c for c in result.verification["cases"]["sway_a0.01000"]}["Courant number"]
    assert co["passed"]
    # the hydrodynamic sway added mass of a slender body is negative (it resists the acceleration)
    assert result.derivatives["Y_vdot"] < 0
