"""SLURM job-array scripts for a study's cases: one case per task, MPI over a hostfile, decomposition by
mesh size; the scripts are checked with bash -n."""

from __future__ import annotations

import shutil
import subprocess

import pytest
from cfd_fake_foam import FakeFoam, fake_environment
from test_cfd_pipeline import study

from cfd.cli import main
from cfd.cluster import SCOTCH_CELLS, decomposition, pending_cases
from cfd.pipeline import DONE, Pipeline
from cfd.runner import Progress


@pytest.fixture
def cases(tmp_path, monkeypatch):
    """A study whose mesh and tow finished and whose two drift cases were written but not run."""
    fake_environment(monkeypatch, FakeFoam(fail_app="simpleFoam"))
    s = study(tmp_path, tests="tow", speeds="1.0")
    with pytest.raises(Exception, match="fake failure"):
        Pipeline(s, Progress(quiet=True), plots=False).run()
    root = s.out / "cases"
    for name in ("drift_b04.00", "drift_b08.00"):
        shutil.copytree(root / "tow_U1.0000", root / name)
    (root / "drift_b08.00" / DONE).write_text("{}")  # finished: not in the array
    return root


def test_a_case_whose_forces_reached_its_end_time_is_not_pending(cases):
    """A free-surface tow writes no done marker: run to its endTime it is finished, short of it pending."""
    import numpy as np
    from cfd_fake_foam import _forces_table

    from cfd.postprocess import end_time

    for name, share in (("vof_U1.6680", 1.0), ("vof_U1.5350", 0.5)):
        case = cases / name
        shutil.copytree(cases / "tow_U1.0000", case)
        end = end_time(case)
        assert end is not None and end >= 2
        t = np.arange(1.0, share * end + 1.0)
        d = case / "postProcessing" / "forces" / "0"
        d.mkdir(parents=True)
        ftxt, mtxt = _forces_table(t, np.ones((len(t), 3)), np.zeros((len(t), 3)))
        (d / "force.dat").write_text(ftxt)
        (d / "moment.dat").write_text(mtxt)
    assert [c.name for c, _ in pending_cases(cases)] == ["drift_b04.00", "tow_U1.0000", "vof_U1.5350"]


def test_decomposition_by_mesh_size():
    assert decomposition(50_000, 64)["method"] == "hierarchical"
    assert decomposition(SCOTCH_CELLS, 64) == {"numberOfSubdomains": 64, "method": "scotch"}


def test_job_array_script_runs_one_case_per_task_over_a_hostfile(cases, capsys):
    assert [(c.name, app) for c, app in pending_cases(cases)] == [
        ("drift_b04.00", "simpleFoam"),
        ("tow_U1.0000", "simpleFoam"),
    ]
    assert main(["slurm", "--cases", str(cases), "--nodes", "2", "--tasks-per-node", "16"]) == 0
    script = cases.parent / "slurm" / "run_cases.sbatch"
    assert f"sbatch {script}" in capsys.readouterr().out
    text = script.read_text()
    assert "#SBATCH --array=0-1" in text and "#SBATCH --nodes=2" in text and "--ntasks-per-node=16" in text
    assert 'mpirun -np "$SLURM_NTASKS" --hostfile "$HOSTFILE" "$APP" -parallel' in text
    assert "scontrol show hostnames" in text and "hierarchical" in text
    # a free-surface (interFoam) case gets its water (0.orig, setFields) before it is decomposed
    assert (
        text.index('if [ "$APP" = interFoam ]') < text.index("setFields") < text.index("decomposePar -force")
    )
    lines = (cases.parent / "slurm" / "cases.txt").read_text().splitlines()
    assert lines[0].endswith("drift_b04.00 simpleFoam") and len(lines) == 2
    decomp = (cases / "drift_b04.00" / "system" / "decomposeParDict").read_text()
    assert "numberOfSubdomains 32;" in decomp and "hierarchical" in decomp
    assert subprocess.run(["bash", "-n", str(script)], capture_output=True).returncode == 0


def test_bad_cluster_input_is_one_line_and_exit_2(cases, tmp_path, capsys):
    assert main(["slurm", "--cases", str(cases), "--time", "4h"]) == 2
    assert "time: SLURM time limit" in capsys.readouterr().err
    assert main(["slurm", "--cases", str(tmp_path / "nowhere")]) == 2
    assert main(["slurm", "--cases", str(cases), "--nodes", "0"]) == 2
