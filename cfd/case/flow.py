"""Double-body flow cases: the free stream (:class:`FlowSpec`), the 0/ fields, the steady simpleFoam case.

A steady case is a straight tow or a static drift, by the inflow direction; the drift cases
(:func:`start_fields`) and the PMM cases (:mod:`cfd.case.pmm`) start from the converged tow's fields.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

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


def write_steady_case(
    case: Path,
    mesh_case: Path,
    flow: FlowSpec,
    iterations: int,
    procs: int = 1,
    start: tuple[Path, FlowSpec] | None = None,
) -> str:
    """Double-body simpleFoam case (tow or static drift by inflow direction) on the finished mesh.

    ``start``: a time directory of a converged case on the same mesh and its flow; the internal fields
    start from it (:func:`start_fields`) instead of the uniform free stream. Returns how the fields
    started: ``"uniform"`` or ``"from <case name>"``."""
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
            # ASCII: the drift cases start from the tow's fields, read back by start_fields()
            "writeFormat": "ascii",
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
    started = "uniform"
    if start is not None and start_fields(case / "0", start[0], start[1], flow):
        started = f"from {start[0].parent.name}"
    make_stoppable(case)
    return started


_INTERNAL = re.compile(
    r"^internalField\s+(?:uniform\s+(?P<u>\([^)]*\)|[-+0-9.eE]+)\s*;"
    r"|nonuniform\s+List<(?P<t>scalar|vector)>\s*(?P<n>\d+)\s*\()",
    re.M,
)


def read_internal_field(path: Path) -> np.ndarray | None:
    """The internal field of an ASCII OpenFOAM field file: shape (n,) or (n, 3), or (1,)/(1, 3) when it is
    uniform; None when the file is binary, missing or not understood."""
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError):
        return None
    m = _INTERNAL.search(text)
    if m is None or re.search(r"format\s+binary", text[: m.start()]):
        return None
    if m.group("u") is not None:
        vals = np.array(m.group("u").strip("()").split(), dtype=float)
        return vals.reshape(1, -1) if len(vals) == 3 else vals
    n, vector = int(m.group("n")), m.group("t") == "vector"
    end = text.find(";", m.end())
    body = text[m.end() : end].replace("(", " ").replace(")", " ").split()
    try:
        vals = np.array(body, dtype=float)
    except ValueError:
        return None
    if len(vals) != (3 * n if vector else n):
        return None
    return vals.reshape(n, 3) if vector else vals


def _internal_text(values: np.ndarray) -> str:
    if values.ndim == 2:
        if len(values) == 1:
            return "uniform ({:.10g} {:.10g} {:.10g})".format(*values[0])
        rows = "\n".join(f"({a:.10g} {b:.10g} {c:.10g})" for a, b, c in values)
        return f"nonuniform List<vector>\n{len(values)}\n(\n{rows}\n)"
    if len(values) == 1:
        return f"uniform {values[0]:.10g}"
    rows = "\n".join(f"{v:.10g}" for v in values)
    return f"nonuniform List<scalar>\n{len(values)}\n(\n{rows}\n)"


def start_fields(zero: Path, start_dir: Path, start_flow: FlowSpec, flow: FlowSpec) -> bool:
    """Put the converged internal fields of ``start_dir`` (same mesh, free stream ``start_flow``) into the
    uniform 0/ fields of ``zero`` (free stream ``flow``); the boundary conditions stay those of ``flow``.

    Velocity is rotated about z by the change of inflow angle and scaled with the speed; p scales with U²,
    k with U², omega and nut with U (the same flow at another Reynolds number, to first order). A drift case
    started this way begins with the hull's boundary layer and wake in place, turned to the new inflow, and
    SIMPLE only has to adjust the cross flow. False (nothing changed) when a start field cannot be read.
    """
    r = flow.U / start_flow.U
    b = math.radians(flow.beta_deg - start_flow.beta_deg)
    rot = np.array([[math.cos(b), -math.sin(b), 0.0], [math.sin(b), math.cos(b), 0.0], [0.0, 0.0, 1.0]])
    scale = {"U": r, "p": r * r, "k": r * r, "omega": r, "nut": r}
    fields = {}
    for name in scale:
        values = read_internal_field(start_dir / name)
        if values is None:
            return False
        fields[name] = rot @ values.T * r if name == "U" else values * scale[name]
    fields["U"] = fields["U"].T
    for name, values in fields.items():
        path = zero / name
        entry = f"internalField   {_internal_text(values)};"
        text = re.sub(r"^internalField\s+[^;]*;", lambda _, e=entry: e, path.read_text(), count=1, flags=re.M)
        path.write_text(text)
    return True
