"""Running applications (with stand-in executables), failure messages, log and force parsing."""

from __future__ import annotations

import io
import math
import os
import stat
from pathlib import Path

import numpy as np
import pytest

from cfd.case import request_stop
from cfd.errors import CfdError
from cfd.postprocess import ForceHistory, body_forces, forces_settled, read_forces, steady_forces
from cfd.runner import Progress, check_openfoam, parse_check_mesh, read_boundary, run_app


def _script(bindir: Path, name: str, body: str) -> None:
    path = bindir / name
    path.write_text("#!/bin/sh\n" + body)
    path.chmod(path.stat().st_mode | stat.S_IEXEC)


@pytest.fixture
def bindir(tmp_path, monkeypatch):
    d = tmp_path / "bin"
    d.mkdir()
    monkeypatch.setenv("PATH", f"{d}{os.pathsep}{os.environ['PATH']}")
    return d


def test_fatal_error_is_one_line_with_step_and_log(tmp_path, bindir):
    _script(
        bindir,
        "simpleFoam",
        'echo "Time = 1"\necho "--> FOAM FATAL ERROR: "\n'
        'echo "Cannot find patchField entry for hull"\nexit 1\n',
    )
    with pytest.raises(CfdError) as err:
        run_app(["simpleFoam"], tmp_path, "simpleFoam (tow U=1 m/s)")
    msg = str(err.value)
    assert msg.startswith("simpleFoam (tow U=1 m/s) failed:")
    assert "Cannot find patchField entry for hull" in msg and "exited with code 1" in msg
    assert "\n" not in msg and err.value.log == tmp_path / "log.simpleFoam"


def test_divergence_stops_the_run(tmp_path, bindir):
    _script(
        bindir,
        "pimpleFoam",
        'i=0\nwhile true; do i=$((i+1)); echo "Time = $i"\n'
        'echo "Courant Number mean: 5 max: 1e+05"; sleep 0.05; done\n',
    )
    stream = io.StringIO()
    with pytest.raises(CfdError, match="diverged: Courant number"):
        run_app(
            ["pimpleFoam"],
            tmp_path,
            "pimpleFoam (sway)",
            progress=Progress(stream, interval_s=0.3),
            end_time=10.0,
        )


def test_progress_reports_time_and_ticks(tmp_path, bindir):
    _script(bindir, "simpleFoam", 'for i in 1 2 3 4 5 6 7 8; do echo "Time = $i"; sleep 0.3; done\n')
    stream = io.StringIO()
    ticks = []
    run_app(
        ["simpleFoam"],
        tmp_path,
        "tow",
        progress=Progress(stream, interval_s=0.5),
        end_time=8,
        on_tick=lambda: ticks.append(1),
    )
    text = stream.getvalue()
    assert "tow: simpleFoam time" in text and "/8 (" in text and "elapsed" in text
    assert ticks  # called every 2 s


def test_missing_openfoam_is_named(monkeypatch, tmp_path):
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(CfdError) as err:
        check_openfoam()
    assert "apt-get install openfoam" in str(err.value) and "blockMesh" in str(err.value)
    with pytest.raises(CfdError, match="not found on PATH"):
        run_app(["blockMesh"], tmp_path, "blockMesh (mesh)")


def test_request_stop_edits_control_dict(tmp_path):
    (tmp_path / "system").mkdir()
    (tmp_path / "system" / "controlDict").write_text("application simpleFoam;\nstopAt          endTime;\n")
    assert request_stop(tmp_path)
    assert "stopAt          writeNow;" in (tmp_path / "system" / "controlDict").read_text()
    assert not request_stop(tmp_path)


def test_boundary_and_check_mesh_parsing(tmp_path):
    poly = tmp_path / "constant" / "polyMesh"
    poly.mkdir(parents=True)
    (poly / "boundary").write_text(
        "FoamFile\n{\n    version 2.0;\n    object boundary;\n}\n\n2\n(\n    farfield\n    {\n        type patch;\n"
        "        nFaces 1024;\n        startFace 39744;\n    }\n    hull\n    {\n        type wall;\n"
        "        inGroups 1(wall);\n        nFaces 584;\n        startFace 43488;\n    }\n)\n"
    )
    b = read_boundary(tmp_path)
    assert b["hull"]["nFaces"] == "584" and b["hull"]["type"] == "wall" and set(b) == {"farfield", "hull"}
    log = tmp_path / "log.checkMesh"
    log.write_text(
        "    cells:            13560\n ***Max skewness = 4.1, 4 highly skew faces detected\n"
        "    Mesh non-orthogonality Max: 34.6 average: 6\n\nFailed 1 mesh checks.\n"
    )
    c = parse_check_mesh(log)
    assert c["ok"] is False and c["failed_checks"] == 1 and c["cells"] == 13560
    assert c["max_non_orthogonality"] == 34.6 and c["max_skewness"] == 4.1
    assert c["fatal"] == [] and c["warnings"] == ["Max skewness = 4.1, 4 highly skew faces detected"]
    log.write_text(" ***Zero or negative cell volume detected.  Minimum negative volume: -1e-9\n")
    assert parse_check_mesh(log)["fatal"]


def _write_forces(case: Path, start: str, t, F, M, suffix=""):
    d = case / "postProcessing" / "forces" / start
    d.mkdir(parents=True, exist_ok=True)
    for name, V in (("force", F), ("moment", M)):
        rows = "".join(f"{ti}\t({v[0]} {v[1]} {v[2]})\t(0 0 0)\t(0 0 0)\n" for ti, v in zip(t, V))
        (d / f"{name}{suffix}.dat").write_text(f"# {name}\n# Time (total_x total_y total_z)\n" + rows)


def test_read_forces_merges_restarts_and_converts_axes(tmp_path):
    t1 = np.arange(1.0, 6.0)
    _write_forces(tmp_path, "0", t1, np.tile([-1.0, 2.0, 0], (5, 1)), np.tile([0, 0, 3.0], (5, 1)))
    t2 = np.arange(4.0, 9.0)  # a restart from time 3 rewrites 4 and 5
    _write_forces(tmp_path, "3", t2, np.tile([-2.0, 4.0, 0], (5, 1)), np.tile([0, 0, 6.0], (5, 1)))
    h = read_forces(tmp_path)
    assert h.t.tolist() == [1, 2, 3, 4, 5, 6, 7, 8]
    assert h.F[3, 0] == -2.0  # the later file wins
    s = steady_forces(h, window=0.3)
    assert (s.X, s.Y, s.N) == (-2.0, -4.0, -6.0)  # standard axes: Y = -Fy, N = -Mz
    with pytest.raises(CfdError, match="no force output"):
        read_forces(tmp_path / "empty")


def test_body_forces_rotate_and_shift_the_moment():
    # a hull at y = 0.1 (to port) with heading 10 deg (bow to port), body forces X = -1, Y_std = 2, N_std = 0.5
    psi, y = math.radians(10.0), 0.1
    Fxb, Fyb = -1.0, -2.0  # case-frame body components (y to port)
    Fx = math.cos(psi) * Fxb - math.sin(psi) * Fyb
    Fy = math.sin(psi) * Fxb + math.cos(psi) * Fyb
    Mz = -0.5 - y * Fx  # about the fixed origin
    h = ForceHistory(np.array([1.0]), np.array([[Fx, Fy, 0.0]]), np.array([[0.0, 0.0, Mz]]))
    X, Y, N = body_forces(h, np.array([y]), np.array([psi]))
    assert (X[0], Y[0], N[0]) == pytest.approx((-1.0, 2.0, 0.5))


def test_forces_settled():
    n = 200
    t = np.arange(1.0, n + 1)
    F = np.column_stack([-30 * (1 - np.exp(-t / 20)), 0.5 + 0 * t, 0 * t])
    M = np.column_stack([0 * t, 0 * t, 0.2 + 0 * t])
    assert forces_settled(ForceHistory(t, F, M), 6.0)
    assert not forces_settled(ForceHistory(t[:60], F[:60], M[:60]), 6.0)  # still moving, and too early
    F2 = F.copy()
    F2[-10:, 1] += 1.0  # a side-force jump
    assert not forces_settled(ForceHistory(t, F2, M), 6.0)
