"""A tiny free-surface (VOF) smoke run with interFoam: the case the DTC validation writes, on a small
wall-sided Wigley hull (L = 1 m, Fn = 0.3), meshed and run for a few LTS iterations.

About 20k cells (half domain), meshing a few seconds and 10 iterations about 1 s each on a shared core.
It checks that the case runs and stays physical (free surface kept, buoyancy and drag of the right size),
not the resistance: that needs thousands of iterations (docs/cfd.md, section Free surface).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from cfd.geometry import wigley_hull_with_freeboard
from cfd.runner import Progress, openfoam_available
from cfd.tank import run_free_surface_tows

pytestmark = [
    pytest.mark.openfoam,
    pytest.mark.slow,
    pytest.mark.skipif(
        not openfoam_available(), reason="OpenFOAM (Debian package openfoam) is not installed"
    ),
]

L, B, T, RHO, G = 1.0, 0.1, 0.0625, 1000.0, 9.81


def test_interfoam_runs_the_free_surface_tow(tmp_path):
    U = 0.3 * math.sqrt(G * L)
    result = run_free_surface_tows(
        wigley_hull_with_freeboard(L, B, T, 0.05),
        lpp=L,
        bwl=B,
        tm=T,
        speeds=(U,),
        out=tmp_path,
        iterations=10,
        rho=RHO,
        nu=1e-6,
        progress=Progress(interval_s=30.0),
    )
    assert 5_000 < result["mesh"]["cells"] < 60_000
    (run,) = result["runs"]
    assert run["iterations"] == 10
    case = tmp_path / "cases" / f"vof_U{U:.4f}"
    log = (case / "log.interFoam").read_text(errors="replace")
    assert log.rstrip().endswith("End")
    last = [line for line in log.splitlines() if line.startswith("Phase-1 volume fraction")][-1]
    lo, hi = (
        float(last.split("Min(alpha.water) = ")[1].split()[0]),
        float(last.split("Max(alpha.water) = ")[1]),
    )
    assert -1e-3 < lo and hi < 1.001  # the free surface is kept sharp and bounded
    # the hull is buoyed by about rho g V / 2 on the half hull (Wigley V = 4/9 L B T), and dragged
    from cfd.postprocess import read_forces

    Fz = read_forces(case).F[-1, 2]
    assert Fz == pytest.approx(RHO * G * 4 / 9 * L * B * T / 2, rel=0.1)
    assert run["R_T_N"] > 0 and math.isfinite(run["R_T_N"])


def test_write_only_meshes_and_leaves_runnable_cases(tmp_path):
    from cfd.cluster import pending_cases

    result = run_free_surface_tows(
        wigley_hull_with_freeboard(L, B, T, 0.05),
        lpp=L,
        bwl=B,
        tm=T,
        speeds=(0.8, 1.0),
        out=tmp_path,
        iterations=10,
        rho=RHO,
        nu=1e-6,
        progress=Progress(quiet=True),
        write_only=True,
    )
    assert result["runs"] == [] and result["mesh"]["cells"] > 5_000
    cases = tmp_path / "cases"
    # the mesh's grading, grid, hull level and hull cell are kept for the report of the cases once run
    # elsewhere (and for a grid study of them)
    assert json.loads((cases / "mesh" / "vof_mesh.json").read_text()) == {
        "grading": 1,
        "grid": 0,
        "hull_level": result["mesh"]["hull_level"],
        "hull_cell_m": pytest.approx(result["mesh"]["hull_cell_m"]),
    }
    assert [(c.name, app) for c, app in pending_cases(cases)] == [
        ("vof_U0.8000", "interFoam"),
        ("vof_U1.0000", "interFoam"),
    ]
    for c, _ in pending_cases(cases):
        assert (c / "constant" / "polyMesh" / "owner").is_file() and (c / "0" / "alpha.water").is_file()
        assert not (c / "log.interFoam").exists() and "interFoam" in (c / "Allrun").read_text()


def test_a_written_parallel_tow_runs_on_two_processes_and_resumes(tmp_path):
    """A case written for 2 processors (``--mode write --procs 2``): its Allrun runs interFoam on both, and
    run again after endTime is raised (as after a stop at a 150-minute slot's end) it continues from the
    last time written instead of starting over."""
    import re
    import subprocess

    run_free_surface_tows(
        wigley_hull_with_freeboard(L, B, T, 0.05),
        lpp=L,
        bwl=B,
        tm=T,
        speeds=(0.9,),
        out=tmp_path,
        iterations=4,
        rho=RHO,
        nu=1e-6,
        procs=2,
        progress=Progress(quiet=True),
        write_only=True,
    )
    case = tmp_path / "cases" / "vof_U0.9000"

    def allrun(argv: list[str], cwd: Path | None = None) -> list[int]:
        subprocess.run(argv, cwd=cwd, check=True, capture_output=True, timeout=600)
        log = (case / "log.interFoam").read_text(errors="replace")
        assert "nProcs : 2" in log and "\nEnd\n" in log
        return [int(t) for t in re.findall(r"^Time = (\d+)$", log, flags=re.M)]

    assert allrun(["sh", str(case / "Allrun")]) == [1, 2, 3, 4]  # from anywhere
    assert (case / "4" / "alpha.water").is_file() and not (case / "processor0").exists()
    control = case / "system" / "controlDict"
    control.write_text(re.sub(r"^endTime\s+4;", "endTime 6;", control.read_text(), flags=re.M))
    assert allrun(["sh", "Allrun"], cwd=case) == [5, 6]  # from the case folder; resumed from time 4
    assert (case / "6" / "U").is_file()
    # the first part's log is kept, so the CPU time counts both parts
    from cfd.tank import solver_cpu_s

    first = (case / "log.interFoam.1").read_text(errors="replace")
    assert re.findall(r"^Time = (\d+)$", first, flags=re.M)[-1] == "4"
    assert solver_cpu_s(case) > float(re.findall(r"^ExecutionTime = ([\d.]+) s", first, flags=re.M)[-1]) * 2
