"""The records a study passes between its stages: one OpenFOAM case (:class:`Job`) and the finished study
(:class:`FinishedStudy`).

:mod:`cfd.pipeline` makes and runs the jobs; :mod:`cfd.analysis` and :mod:`cfd.report` read a
:class:`FinishedStudy` and nothing else of the pipeline, so the data flows one way: pipeline -> analysis ->
report.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .case import MeshSpec
from .config import Study
from .geometry import PlacedHull


@dataclass
class Job:
    """One OpenFOAM case of the study."""

    name: str
    kind: str  # mesh, tow, drift, sway, yaw
    label: str
    key: dict[str, Any]
    action: Callable[[Job, Path, int], dict[str, Any]]
    params: dict[str, Any] = field(default_factory=dict)  # what the case imposes (speed, angle, motion)
    summary: dict[str, Any] = field(default_factory=dict)  # what it gave (forces, cells, ...)


@dataclass(frozen=True)
class FinishedStudy:
    """Everything the fits and the report need from a study whose cases have all run.

    ``cases`` is the folder holding one case folder per job (named ``job.name``) and ``hull.stl``;
    ``wall_s`` the wall time of each job by name, and of the whole run as ``"total"``, in seconds.
    """

    study: Study
    hull: PlacedHull
    spec: MeshSpec
    jobs: Mapping[str, Job]
    cases: Path
    wall_s: Mapping[str, float]

    @property
    def out(self) -> Path:
        """The study's output folder (ship file and report)."""
        return Path(self.study.out)
