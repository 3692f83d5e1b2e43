"""OpenFOAM case generation: mesh, steady double-body tow/drift, moving-mesh PMM, free surface.

All lengths in the case frame of :mod:`cfd.geometry` (x forward, y to port, z up, origin at midship in the
waterplane). Dictionaries are written with :mod:`cfd.foamdict`; the values come from :class:`MeshSpec` and
:class:`FlowSpec`, so the generated text is reproducible and testable.

- :mod:`~cfd.case.sizing`: mesh sizing (domain, Table-2 boxes, levels, layers, PMM time step)
- :mod:`~cfd.case.common`: what every case shares (numerics, decomposition, forces output, stop request)
- :mod:`~cfd.case.mesh`: the blockMesh + snappyHexMesh case
- :mod:`~cfd.case.flow`: the free stream, 0/ fields and the steady simpleFoam case
- :mod:`~cfd.case.pmm`: PMM motion and the moving-mesh pimpleFoam case
- :mod:`~cfd.case.free_surface`: the VOF interFoam case (written, not run)
"""

from .common import HULL_PATCH, link_mesh, request_stop
from .flow import FlowSpec, flow_fields, write_steady_case
from .free_surface import write_free_surface_case
from .mesh import MESH_QUALITY, write_mesh_case
from .pmm import Motion, motion_table, ramp, write_pmm_case
from .sizing import TABLE2, Box, MeshSpec, cell_count_estimate, hull_level_for, mesh_spec, pmm_time_step

__all__ = [
    "HULL_PATCH",
    "MESH_QUALITY",
    "TABLE2",
    "Box",
    "FlowSpec",
    "MeshSpec",
    "Motion",
    "cell_count_estimate",
    "flow_fields",
    "hull_level_for",
    "link_mesh",
    "mesh_spec",
    "motion_table",
    "pmm_time_step",
    "ramp",
    "request_stop",
    "write_free_surface_case",
    "write_mesh_case",
    "write_pmm_case",
    "write_steady_case",
]
