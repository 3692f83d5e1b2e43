"""Double-body flow cases: the free stream (:class:`FlowSpec`), the 0/ fields, the steady simpleFoam case.

A steady case is a straight tow or a static drift, by the inflow direction; the PMM cases
(:mod:`cfd.case.pmm`) start from the converged tow's fields.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .. import foamdict
from ..foamdict import Words
from .common import (
    HULL_PATCH,
    decompose_dict,
    function_objects,
    link_mesh,
    make_stoppable,
    symmetry_plane,
    write_constant,
    write_schemes,
    write_solution,
)


@dataclass(frozen=True)
class FlowSpec:
    """Free stream and water for one case (case frame)."""

    U: float  # speed (m/s)
    beta_deg: float = 0.0  # inflow angle: the ship moves with U(cos β, sin β) in the case frame
    rho: float = 999.1
    nu: float = 1.1386e-6
    intensity: float = 0.01  # free-stream turbulence intensity
    viscosity_ratio: float = 10.0  # ν_t / ν in the free stream

    @property
    def u_inf(self) -> tuple[float, float, float]:
        b = math.radians(self.beta_deg)
        return (-self.U * math.cos(b), -self.U * math.sin(b), 0.0)

    @property
    def k(self) -> float:
        return 1.5 * (self.intensity * self.U) ** 2

    @property
    def omega(self) -> float:
        return self.k / (self.viscosity_ratio * self.nu)


def _field(dims: str, internal: Any, boundary: dict[str, Any], foam_class: str = "volScalarField") -> tuple:
    return {"dimensions": dims, "internalField": internal, "boundaryField": boundary}, foam_class


def flow_fields(flow: FlowSpec) -> dict[str, tuple[dict, str]]:
    """0/ fields for a double-body case: freestream far field, wall functions on the hull."""
    U = flow.u_inf
    k, w, nut0 = flow.k, flow.omega, flow.k / flow.omega
    sym = {"bottom": symmetry_plane(), "waterline": symmetry_plane()}
    return {
        "U": _field(
            "[0 1 -1 0 0 0 0]",
            Words("uniform", U),
            {
                "farfield": {
                    "type": "freestreamVelocity",
                    "freestreamValue": Words("uniform", U),
                    "value": Words("uniform", U),
                },
                # equals noSlip on a fixed mesh; follows the wall on a moving one
                HULL_PATCH: {"type": "movingWallVelocity", "value": Words("uniform", (0, 0, 0))},
                **sym,
            },
            "volVectorField",
        ),
        "p": _field(
            "[0 2 -2 0 0 0 0]",
            Words("uniform", 0),
            {
                "farfield": {
                    "type": "freestreamPressure",
                    "freestreamValue": Words("uniform", 0),
                    "value": Words("uniform", 0),
                },
                HULL_PATCH: {"type": "zeroGradient"},
                **sym,
            },
        ),
        "k": _field(
            "[0 2 -2 0 0 0 0]",
            Words("uniform", k),
            {
                "farfield": {
                    "type": "inletOutlet",
                    "inletValue": Words("uniform", k),
                    "value": Words("uniform", k),
                },
                HULL_PATCH: {"type": "kqRWallFunction", "value": Words("uniform", k)},
                **sym,
            },
        ),
        "omega": _field(
            "[0 0 -1 0 0 0 0]",
            Words("uniform", w),
            {
                "farfield": {
                    "type": "inletOutlet",
                    "inletValue": Words("uniform", w),
                    "value": Words("uniform", w),
                },
                HULL_PATCH: {"type": "omegaWallFunction", "value": Words("uniform", w)},
                **sym,
            },
        ),
        "nut": _field(
            "[0 2 -1 0 0 0 0]",
            Words("uniform", nut0),
            {
                "farfield": {"type": "calculated", "value": Words("uniform", nut0)},
                HULL_PATCH: {"type": "nutUSpaldingWallFunction", "value": Words("uniform", 0)},
                **sym,
            },
        ),
    }


def write_steady_case(case: Path, mesh_case: Path, flow: FlowSpec, iterations: int, procs: int = 1) -> None:
    """Double-body simpleFoam case (tow or static drift by inflow direction) on the finished mesh."""
    case.mkdir(parents=True, exist_ok=True)
    link_mesh(case, mesh_case)
    write_constant(case, flow.nu)
    system = case / "system"
    foamdict.write(
        system / "controlDict",
        {
            "application": "simpleFoam",
            "startFrom": "startTime",
            "startTime": 0,
            "stopAt": "endTime",
            "endTime": iterations,
            "deltaT": 1,
            "writeControl": "timeStep",
            "writeInterval": iterations,
            "purgeWrite": 1,
            "writeFormat": "binary",
            "writePrecision": 10,
            "writeCompression": False,
            "timeFormat": "general",
            "timePrecision": 8,
            "runTimeModifiable": True,  # request_stop() ends a run whose forces have settled
            "functions": function_objects(flow.rho, write_yplus=True),
        },
    )
    write_schemes(system, steady=True)
    write_solution(system, steady=True)
    foamdict.write(system / "decomposeParDict", decompose_dict(procs))
    for name, (body, cls) in flow_fields(flow).items():
        foamdict.write(case / "0" / name, body, foam_class=cls)
    make_stoppable(case)
