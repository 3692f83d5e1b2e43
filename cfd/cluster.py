"""Running a study's cases on a SLURM cluster: one job-array task per case, MPI across nodes.

``vessel-cfd slurm --cases OUT/cases`` takes the cases a study has written but not finished (no done
marker, and forces short of the endTime), writes each one's ``system/decomposeParDict`` for the cluster's
processor count, and writes ``OUT/slurm/cases.txt`` (one case a line: folder, application) and ``OUT/slurm/run_cases.sbatch``, a job
array whose task k runs line k: decomposePar, ``mpirun --hostfile`` over the nodes SLURM gave it (the
hostfile made from ``scontrol show hostnames``), reconstructPar.

Decomposition by mesh size: hierarchical (a fixed split along x) below :data:`SCOTCH_CELLS`, where the
refinement boxes are small next to the domain and load balance does not matter much; scotch (graph
partitioning, balanced and with small processor boundaries) above. Debian's OpenFOAM package ships only a
stub scotch library, so the local runs of :mod:`cfd.pipeline` stay hierarchical; cluster builds have scotch.
"""

from __future__ import annotations

import re
import shlex
from pathlib import Path
from typing import Any

from . import foamdict
from .case.common import decompose_dict
from .errors import InputError
from .postprocess import end_time, has_run_to_end, read_forces

SCOTCH_CELLS = 1_000_000  # cells; from here on the mesh is decomposed with scotch
DONE = "vessel-cfd.done.json"  # the pipeline's marker of a finished case


def decomposition(cells: int, n: int) -> dict[str, Any]:
    """decomposeParDict for ``n`` subdomains of a mesh of ``cells`` cells (method chosen by mesh size)."""
    if cells >= SCOTCH_CELLS:
        return {"numberOfSubdomains": n, "method": "scotch"}
    return decompose_dict(n)


def pending_cases(cases: Path) -> list[tuple[Path, str]]:
    """Written but unfinished solver cases of a study's ``cases`` folder: (folder, application)."""
    out = []
    for case in sorted(p for p in cases.iterdir() if p.is_dir() and not p.name.startswith("mesh")):
        control = case / "system" / "controlDict"
        if (case / DONE).is_file() or not control.is_file():
            continue
        # a free-surface tow writes no done marker: it is finished when its forces reach its endTime
        if (case / "postProcessing" / "forces").is_dir() and has_run_to_end(
            read_forces(case), end_time(case)
        ):
            continue
        m = re.search(r"^\s*application\s+(\w+)\s*;", control.read_text(), re.M)
        if m:
            out.append((case, m.group(1)))
    return out


def write_slurm(
    cases: Path,
    *,
    cells: int,
    nodes: int = 1,
    tasks_per_node: int = 32,
    time_limit: str = "04:00:00",
    partition: str | None = None,
    account: str | None = None,
) -> Path:
    """Write the job array for the pending cases of ``cases``; return the sbatch script's path."""
    if not cases.is_dir():
        raise InputError("cases", f"{cases} is not a study's cases folder")
    if not (1 <= nodes <= 1000 and 1 <= tasks_per_node <= 1024):
        raise InputError(
            "nodes", f"nodes in [1, 1000] and tasks_per_node in [1, 1024] (got {nodes}, {tasks_per_node})"
        )
    if not re.fullmatch(r"(\d+-)?\d{1,3}:\d\d:\d\d", time_limit):
        raise InputError("time", f"SLURM time limit as [D-]HH:MM:SS (got {time_limit!r})")
    pending = pending_cases(cases)
    if not pending:
        raise InputError("cases", f"{cases} holds no written, unfinished case")
    n = nodes * tasks_per_node
    for case, _ in pending:
        foamdict.write(case / "system" / "decomposeParDict", decomposition(cells, n))
    slurm = cases.parent / "slurm"
    slurm.mkdir(exist_ok=True)
    (slurm / "cases.txt").write_text("".join(f"{case.resolve()} {app}\n" for case, app in pending))
    head = [
        "#!/bin/bash",
        "#SBATCH --job-name=vessel-cfd",
        f"#SBATCH --array=0-{len(pending) - 1}",
        f"#SBATCH --nodes={nodes}",
        f"#SBATCH --ntasks-per-node={tasks_per_node}",
        f"#SBATCH --time={time_limit}",
        "#SBATCH --output=slurm-%A_%a.out",
    ]
    head += [f"#SBATCH --partition={partition}"] if partition else []
    head += [f"#SBATCH --account={account}"] if account else []
    body = f"""
# One study case per array task ({len(pending)} cases, {cells} cells, {decomposition(cells, n)["method"]}
# decomposition into {n} subdomains); written by vessel-cfd.
set -euo pipefail
export WM_PROJECT_DIR="${{WM_PROJECT_DIR:-/usr/share/openfoam}}"
LIST={shlex.quote(str((slurm / "cases.txt").resolve()))}
read -r CASE APP < <(sed -n "$((SLURM_ARRAY_TASK_ID + 1))p" "$LIST")
cd "$CASE"
HOSTFILE="$CASE/hostfile.$SLURM_JOB_ID"
scontrol show hostnames "$SLURM_JOB_NODELIST" | awk -v n="$SLURM_NTASKS_PER_NODE" '{{print $1 " slots=" n}}' > "$HOSTFILE"
if [ "$APP" = interFoam ]; then  # free-surface tow: water below the waterline first
    rm -rf 0 && cp -r 0.orig 0 && setFields > log.setFields 2>&1
fi
decomposePar -force > log.decomposePar 2>&1
mpirun -np "$SLURM_NTASKS" --hostfile "$HOSTFILE" "$APP" -parallel > "log.$APP" 2>&1
reconstructPar -latestTime > log.reconstructPar 2>&1
rm -rf processor* "$HOSTFILE"
"""
    script = slurm / "run_cases.sbatch"
    script.write_text("\n".join(head) + "\n" + body)
    script.chmod(0o755)
    return script
