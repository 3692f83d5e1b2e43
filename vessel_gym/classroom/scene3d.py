"""The 3D view of a student's page: the harbour, the ships' hulls and the sea, built by the 3D viewer's scene
code (:mod:`vessel_gym.ui.view3d_scene`: the same land, quays, depth slabs, goal, hull and deckhouse, sea
components and chase camera as ``vessel-gym view3d``) and sent once in the welcome; the page draws them with
WebGL (``scene3d.js``, no library) and moves the ships by the states.

Scene frame: x east, y north, z up, m, origin at the scenario's reference point.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from vessel_gym.net.protocol_v2 import scenario_features
from vessel_gym.ui.view3d_scene import (
    CHASE_ABOVE_L,
    CHASE_AHEAD_L,
    CHASE_ASTERN_L,
    COLOURS,
    FREEBOARD_T,
    harbour_geometry,
    sea_components,
    sea_grid,
    ship_meshes,
)

#: another student's ship in the 3D view: the blue of the chart's other own ships
STUDENT_RGB = (42, 106, 216)
#: sea surface opacity (the sea bed and the depth slabs show through it), as the 3D viewer draws it
SEA_OPACITY = 0.55


def class_scene(harbour: Any) -> dict[str, Any]:
    """The 3D scene of ``harbour`` (a :class:`~vessel_gym.classroom.harbour.ClassHarbour`) for a page: meshes as
    flat lists (vertices m, faces), the goal and start outlines, the hulls of the own ships' type and of each
    traffic ship, the sea grid and its components at the class's sea state, the chase camera's offsets."""
    sc = harbour.scenario
    scene = {
        "bounds_m": list(sc.bounds_m),
        "water_depth_m": sc.water_depth_m,
        "features": [{"id": i, **f} for i, f in enumerate(scenario_features(sc))],
    }
    L, B, T = harbour.L, harbour.B, harbour.T
    geo = harbour_geometry(scene, L, T)
    hulls = {"own": [m.as_json() for m in ship_meshes("own", None, L, B, T, COLOURS["own"])]}
    if harbour.traffic is not None:
        for t in harbour.traffic.targets():
            draught = float(getattr(t, "draught_m", 0.0) or 0.06 * t.length_m)
            meshes = ship_meshes(t.name, None, t.length_m, t.beam_m, draught, COLOURS["traffic"])
            hulls[t.name] = [m.as_json() for m in meshes]
    x, y, faces = sea_grid(geo.extent)
    e = harbour.sim.environments[0]
    return {
        "extent": list(geo.extent),
        "L": L,
        "T": T,
        "meshes": [m.as_json() for m in geo.meshes],
        "rings": [
            {"name": name, "v": np.round(segs, 3).ravel().tolist(), "rgb": list(rgb)}
            for name, segs, rgb in geo.rings
        ],
        "hulls": hulls,
        "rgb": {
            "own": COLOURS["own"],
            "student": STUDENT_RGB,
            "traffic": COLOURS["traffic"],
            "ended": (150,) * 3,
        },
        "sea": {
            "x": np.round(x, 2).tolist(),
            "y": np.round(y, 2).tolist(),
            "f": faces.astype(np.int64).ravel().tolist(),
            "rgb": COLOURS["sea"],
            "opacity": SEA_OPACITY,
            "components": [list(c) for c in sea_components(e.Hs_m, e.Tp_s, e.wave_from_deg, geo.depth_m)],
        },
        "chase_L": [CHASE_ASTERN_L, CHASE_ABOVE_L, CHASE_AHEAD_L],
        "deck_z": FREEBOARD_T * T,
    }
