"""OpenFOAM case generation: mesh sizing, dictionaries (parsed back with foamlib), PMM motion tables."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cfd import foamdict
from cfd.case import (
    TABLE2,
    FlowSpec,
    Motion,
    cell_count_estimate,
    hull_level_for,
    mesh_spec,
    motion_table,
    pmm_time_step,
    ramp,
    write_free_surface_case,
    write_mesh_case,
    write_pmm_case,
    write_steady_case,
)
from cfd.case.free_surface import resistance_from_half
from cfd.foamdict import Named, Words
from cfd.friction import ittc57, wall_distance
from cfd.geometry import wigley_hull, wigley_hull_with_freeboard, write_stl

L, B, T = 1.0, 0.1, 0.0625


def _parse(path: Path) -> dict:
    foamlib = pytest.importorskip("foamlib")
    return foamlib.FoamFile(path).as_dict()


def _words(value) -> str:
    """A foamlib entry of several words as the text OpenFOAM reads."""
    return " ".join(str(v) for v in value) if isinstance(value, (tuple, list)) else str(value)


def test_foamdict_text_is_parsed_back_by_foamlib(tmp_path):
    entries = {
        "solvers": {'"(U|k)"': {"solver": "smoothSolver", "tolerance": 1e-8}},
        "vertices": [(0, 0, 0), (1.5, 0, -2)],
        "blocks": [Words("hex", tuple(range(8)), (4, 2, 1), "simpleGrading", (1, 1, 1))],
        "boundary": [Named("farfield", {"type": "patch", "faces": [(0, 4, 7, 3)]})],
        "flag": True,
        "internalField": Words("uniform", (1.0, 0.0, 0.0)),
    }
    d = _parse(foamdict.write(tmp_path / "system" / "testDict", entries))
    assert d["solvers"]['"(U|k)"']["tolerance"] == pytest.approx(1e-8)
    assert np.asarray(d["vertices"])[1].tolist() == [1.5, 0, -2]
    assert d["flag"] is True
    with pytest.raises(ValueError, match="non-finite"):
        foamdict.dumps({"x": float("nan")})


def test_mesh_spec_grading_scales_levels_and_boxes():
    levels = [hull_level_for(g, L, T) for g in range(1, 6)]
    assert levels == [3, 4, 5, 6, 7]  # 4 cells across the draught at grading 1, halving per step
    assert hull_level_for(1, 5.976, 0.244) == 4  # the DTC's smaller T/L needs one more level
    s1 = mesh_spec(L, B, T, 1, U=1.0, nu=1e-6)
    s5 = mesh_spec(L, B, T, 5, U=1.0, nu=1e-6)
    assert s1.h0 == pytest.approx(L / 8) and s1.cells == (40, 24, 8)
    assert s1.lo == pytest.approx((-3.0, -1.5, -1.0)) and s1.hi == pytest.approx((2.0, 1.5, 0.0))
    assert [b.name for b in s1.boxes] == ["box5", "box6"] and [b.level for b in s1.boxes] == [1, 2]
    assert [b.level for b in s5.boxes] == [1, 2, 3, 4, 5, 6]  # the seed's full six-level scheme
    box6 = s5.boxes[-1]
    assert box6.lo[0] == pytest.approx((TABLE2[-1][1] - 0.5) * L)  # Table 2 x from the AP, about midship
    assert box6.hi[0] == pytest.approx((TABLE2[-1][2] - 0.5) * L)
    assert box6.hi[1] > B / 2 and box6.lo[2] < -T  # boxes enclose the hull
    assert cell_count_estimate(s5) > 30 * cell_count_estimate(s1)
    x, y, z = s1.location
    assert abs(y) > B and z < -T  # the fluid point is away from the hull


def test_a_grid_family_divides_every_cell_by_the_same_ratio():
    # grid k of a grid study: cell_scale sqrt(2)^-k; every cell size shrinks by the ratio (background, hull
    # and every box, since their levels are unchanged), the regions stay where they are, and the buffer
    # between two levels keeps its physical width (3 cells at scale 1, 6 at scale 1/2)
    family = [mesh_spec(L, B, T, 1, U=1.0, nu=1e-6, cell_scale=math.sqrt(2) ** -k) for k in range(3)]
    for coarse, fine in zip(family, family[1:]):
        assert coarse.h0 / fine.h0 == pytest.approx(math.sqrt(2))
        assert coarse.h_hull / fine.h_hull == pytest.approx(math.sqrt(2))
        assert [b.level for b in fine.boxes] == [b.level for b in coarse.boxes]
        assert [(b.lo[0], b.hi[0], b.lo[1]) for b in fine.boxes] == [
            (b.lo[0], b.hi[0], b.lo[1]) for b in coarse.boxes
        ]
    assert [s.cells_between_levels for s in family] == [3, 4, 6]
    assert family[0] == mesh_spec(L, B, T, 1, U=1.0, nu=1e-6)  # scale 1 is the grading's own mesh
    # the domain is whole background cells: it can only grow, by less than a cell of the coarsest grid
    for s in family[1:]:
        for k in range(3):
            assert family[0].lo[k] - family[0].h0 < s.lo[k] <= family[0].lo[k] + 1e-12
    # the estimate grows by about r^3 = 2.8 per step (the hull band only by r^2)
    ratio = cell_count_estimate(family[1]) / cell_count_estimate(family[0])
    assert 2.0 < ratio < 3.0
    with pytest.raises(ValueError, match="cell_scale"):
        mesh_spec(L, B, T, 1, U=1.0, nu=1e-6, cell_scale=0.0)


def test_wall_distance_and_layers():
    # Re = 9.1e6 (DTC model): the first cell centre for y+ = 150 is a few millimetres off the wall
    y = wall_distance(1.668, 5.976, 1.09e-6, 150.0)
    assert 1e-3 < y < 5e-3
    assert wall_distance(1.668, 5.976, 1.09e-6, 30.0) == pytest.approx(y / 5)
    spec = mesh_spec(5.976, 0.859, 0.244, 3, U=1.668, nu=1.09e-6, layers=True, yplus=30.0)
    assert spec.n_layers >= 1 and spec.first_layer_m == pytest.approx(
        2 * wall_distance(1.668, 5.976, 1.09e-6, 30)
    )
    seed = mesh_spec(5.976, 0.859, 0.244, 1, U=1.668, nu=1.09e-6, sizing="yplus")
    assert seed.h_hull == pytest.approx(
        2 * y
    )  # the seed's rule: hull cell = wall cell, background x 2^levels
    assert ittc57(1e6) == pytest.approx(0.075 / 16)


@pytest.fixture(scope="module")
def mesh_case(tmp_path_factory):
    root = tmp_path_factory.mktemp("cases")
    stl = write_stl(root / "hull.stl", wigley_hull(L, B, T))
    spec = mesh_spec(L, B, T, 1, U=1.0, nu=1e-6, layers=True, yplus=30)
    write_mesh_case(root / "mesh", spec, stl, procs=2)
    poly = root / "mesh" / "constant" / "polyMesh"
    poly.mkdir(parents=True)
    (poly / "boundary").write_text("placeholder\n")
    return root, spec


def test_mesh_dictionaries(mesh_case):
    root, spec = mesh_case
    mesh = root / "mesh"
    bm = _parse(mesh / "system" / "blockMeshDict")
    assert np.asarray(bm["vertices"]).shape == (8, 3)
    assert "hex" in str(bm["blocks"]) and "40" in str(bm["blocks"])
    names = str(bm["boundary"])
    assert all(n in names for n in ("farfield", "bottom", "waterline", "symmetryPlane"))
    sn = _parse(mesh / "system" / "snappyHexMeshDict")
    c = sn["castellatedMeshControls"]
    assert list(c["refinementSurfaces"]["hull"]["level"]) == [spec.hull_level, spec.hull_level]
    assert c["refinementSurfaces"]["hull"]["patchInfo"]["type"] == "wall"
    assert list(c["locationInMesh"]) == pytest.approx(spec.location)
    assert set(c["refinementRegions"]) == {b.name for b in spec.boxes}
    assert sn["addLayers"] is True
    assert sn["addLayersControls"]["layers"]["hull"]["nSurfaceLayers"] == spec.n_layers
    dec = _parse(mesh / "system" / "decomposeParDict")
    assert dec["method"] == "hierarchical" and dec["numberOfSubdomains"] == 2
    assert (mesh / "constant" / "triSurface" / "hull.stl").is_file()
    assert _parse(mesh / "system" / "surfaceFeatureExtractDict")["hull.stl"]["extractFromSurfaceCoeffs"]


def test_steady_case_fields(mesh_case):
    root, _ = mesh_case
    flow = FlowSpec(U=1.2, beta_deg=6.0, rho=1000.0, nu=1e-6)
    case = root / "drift"
    write_steady_case(case, root / "mesh", flow, 300)
    U = _parse(case / "0" / "U")
    ux, uy, uz = U["internalField"]
    assert (ux, uy, uz) == pytest.approx(
        (-1.2 * math.cos(math.radians(6)), -1.2 * math.sin(math.radians(6)), 0)
    )
    assert U["boundaryField"]["farfield"]["type"] == "freestreamVelocity"
    assert U["boundaryField"]["hull"]["type"] == "movingWallVelocity"
    assert U["boundaryField"]["waterline"]["type"] == "symmetryPlane"  # double body
    assert _parse(case / "0" / "p")["boundaryField"]["farfield"]["type"] == "freestreamPressure"
    assert _parse(case / "0" / "nut")["boundaryField"]["hull"]["type"] == "nutUSpaldingWallFunction"
    cd = _parse(case / "system" / "controlDict")
    assert cd["application"] == "simpleFoam" and cd["endTime"] == 300
    f = cd["functions"]["forces"]
    assert list(f["patches"]) == ["hull"] and f["rhoInf"] == 1000 and list(f["CofR"]) == [0, 0, 0]
    sol = _parse(case / "system" / "fvSolution")
    assert sol["SIMPLE"]["consistent"] is True and '"(k|omega)"' in sol["SIMPLE"]["residualControl"]
    assert (case / "constant" / "polyMesh" / "boundary").is_file()
    assert flow.k == pytest.approx(1.5 * (0.01 * 1.2) ** 2) and flow.omega == pytest.approx(flow.k / 1e-5)


def test_pmm_case_and_motion_table(mesh_case):
    root, spec = mesh_case
    start = root / "tow" / "200"
    start.mkdir(parents=True)
    for name in ("U", "p", "k", "omega", "nut"):
        (start / name).write_text(f"{name} placeholder\n")
    period = 2.0
    motion = Motion("yaw", 0.03, 2 * math.pi / period, 1.0, 0.5 * period)
    dt = pmm_time_step(spec, 1.0, period)
    assert period / dt == pytest.approx(round(period / dt))  # whole steps per period
    assert dt * 1.0 / spec.h_hull == pytest.approx(1.0, rel=0.05)  # Courant number on the hull cells
    assert pmm_time_step(spec, 1.0, period, courant=0.5) == pytest.approx(dt / 2, rel=0.05)
    case = root / "yaw"
    write_pmm_case(case, root / "mesh", start, FlowSpec(U=1.0), motion, 3 * period, dt)
    dyn = _parse(case / "constant" / "dynamicMeshDict")
    assert dyn["solidBodyMotionFunction"] == "tabulated6DoFMotion"
    cd = _parse(case / "system" / "controlDict")
    assert cd["application"] == "pimpleFoam" and cd["endTime"] == pytest.approx(3 * period)
    assert (case / "0" / "U").read_text() == "U placeholder\n"
    text = (case / "constant" / "6DoF.dat").read_text()
    n = int(text.split("\n", 1)[0])
    rows = [r for r in text.splitlines()[2:-1]]
    assert len(rows) == n
    t_last = float(rows[-1].strip("(").split()[0])
    assert t_last > 3 * period * 1.05  # the table outlasts endTime (v1912 stops otherwise)


def test_motion_kinematics():
    U, w = 1.5, 2.0
    m = Motion("yaw", 0.05, w, U, 1.0)
    t = np.linspace(0, 8, 8001)
    assert ramp(np.array([0.0, 0.5, 1.0, 2.0]), 1.0) == pytest.approx([0, 0.5, 1, 1])
    ydot = np.gradient(m.y(t), t)
    assert m.y_dot(t)[10:-10] == pytest.approx(ydot[10:-10], abs=1e-4)
    assert m.psi(t) == pytest.approx(np.arctan2(m.y_dot(t), U))  # heading tangent to the path: v = 0
    sway = Motion("sway", 0.05, w, U, 1.0)
    assert np.all(sway.psi(t) == 0)
    assert "((0 0 0) (0 0 0))" in motion_table(sway, 1.0, 0.1).splitlines()[2]


def test_free_surface_case_is_generated(tmp_path):
    stl = write_stl(tmp_path / "hull.stl", wigley_hull_with_freeboard(L, B, T, 0.1))
    spec = mesh_spec(L, B, T, 2, U=1.0, nu=1e-6, layers=True, wake_deg=(0.0, 5.0))
    case = tmp_path / "vof"
    fs = write_free_surface_case(case, spec, stl, FlowSpec(U=1.0, rho=998.8), 1000)
    cd = _parse(case / "system" / "controlDict")
    assert cd["application"] == "interFoam" and cd["endTime"] == 1000
    assert cd["functions"]["forces"]["rho"] == "rho"  # interFoam's p is in Pa: no rhoInf scaling
    assert _parse(case / "system" / "fvSchemes")["ddtSchemes"]["default"] == "localEuler"
    bm = _parse(case / "system" / "blockMeshDict")
    names = str(bm["boundary"])
    assert all(n in names for n in ("inlet", "outlet", "atmosphere", "midPlane", "side", "bottom"))
    v = np.asarray(bm["vertices"])
    assert v[:, 1].max() == 0.0 and v[:, 1].min() < -L  # half domain, the centreplane y = 0 a symmetry plane
    assert v[:, 2].max() >= 0.5 * L  # air above the waterline
    assert fs.hi[1] == 0.0 and fs.cells[1] * 2 == spec.cells[1]
    bands = {b.name: b for b in fs.boxes}
    assert bands["freeSurfaceInner"].level == spec.hull_level - 1 and bands["freeSurfaceInner"].hi[2] > 0
    assert bands["box6"].hi[2] == pytest.approx(-bands["box6"].lo[2])  # boxes mirrored above the waterline
    assert [w.name for w in fs.wakes] == ["wake_p00"]  # a straight tow: only its own wake
    sn = _parse(case / "system" / "snappyHexMeshDict")
    assert sn["snap"] is False and sn["addLayers"] is False  # castellated hull (docs/cfd.md says why)
    regions = [str(r) for r in _parse(case / "system" / "setFieldsDict")["regions"]]
    assert any("boxToFace" in r for r in regions)  # the inlet's water, not only the cells
    assert _parse(case / "constant" / "hRef")["value"] == 0
    U = _parse(case / "0.orig" / "U")
    assert U["boundaryField"]["outlet"]["type"] == "outletPhaseMeanVelocity"
    assert _parse(case / "0.orig" / "p_rgh")["boundaryField"]["atmosphere"]["type"] == "totalPressure"
    for f in ("alpha.water", "U", "p_rgh", "k", "omega", "nut"):
        assert _parse(case / "0.orig" / f)["boundaryField"]["midPlane"]["type"] == "symmetryPlane"
    text = (case / "Allrun").read_text()
    assert text.index("snappyHexMesh") < text.index("setFields") < text.index("\ninterFoam > log.interFoam")
    assert resistance_from_half(-1.5) == 3.0  # both sides of the hull, as a positive resistance


def test_wall_sided_wigley_is_closed_and_has_its_volume():
    from cfd.geometry import check_surface, hydrostatics

    F = 0.05
    tris = wigley_hull_with_freeboard(L, B, T, F)
    surface = check_surface(tris, z_max=10.0)  # every edge, above the waterline too
    assert surface.open_edges == 0 and surface.non_manifold_edges == 0
    # divergence theorem over the closed surface: Wigley 4/9 LBT below, L B F 2/3 (parabolic waterplane) above
    vol = np.einsum("ij,ij->i", tris[:, 0], np.cross(tris[:, 1], tris[:, 2])).sum() / 6.0
    assert vol == pytest.approx(4 / 9 * L * B * T + 2 / 3 * L * B * F, rel=0.01)
    below = hydrostatics(tris)
    assert below.volume_m3 == pytest.approx(4 / 9 * L * B * T, rel=0.01) and below.draught_m == pytest.approx(
        T
    )


def test_numerics_default_to_second_order(mesh_case, tmp_path):
    root, _ = mesh_case
    steady = root / "steady_schemes"
    write_steady_case(steady, root / "mesh", FlowSpec(U=1.0), 100)
    sch = _parse(steady / "system" / "fvSchemes")
    assert sch["ddtSchemes"]["default"] == "steadyState"
    for f in ("k", "omega"):  # second-order convection of the turbulence quantities, limited gradient
        assert _words(sch["divSchemes"][f"div(phi,{f})"]) == "bounded Gauss linearUpwind limitedGrad"
    assert _words(sch["gradSchemes"]["limitedGrad"]) == "cellLimited Gauss linear 1"
    start = root / "tow_for_schemes" / "100"
    start.mkdir(parents=True)
    for name in ("U", "p", "k", "omega", "nut"):
        (start / name).write_text("placeholder\n")
    motion = Motion("sway", 0.02, math.pi, 1.0, 1.0)
    for scheme in ("backward", "Euler"):
        case = root / f"pmm_{scheme}"
        kw = {} if scheme == "backward" else {"time_scheme": "Euler"}  # backward is the default
        write_pmm_case(case, root / "mesh", start, FlowSpec(U=1.0), motion, 4.0, 0.02, **kw)
        sch = _parse(case / "system" / "fvSchemes")
        assert sch["ddtSchemes"]["default"] == scheme
        assert _words(sch["divSchemes"]["div(phi,k)"]) == "Gauss linearUpwind limitedGrad"
    with pytest.raises(ValueError, match="time scheme"):
        write_pmm_case(
            root / "pmm_bad", root / "mesh", start, FlowSpec(U=1.0), motion, 4.0, 0.02, time_scheme="CN"
        )


def test_study_defaults_suit_the_physics(tmp_path):
    from cfd.config import build_study
    from cfd.errors import InputError

    s = build_study({"hull": "wigley", "lpp": 1, "bwl": 0.1, "tm": 0.0625, "out": str(tmp_path)})
    assert s.layers is True and s.yplus == 150.0 and s.wake is True
    assert s.time_scheme == "backward" and s.courant == 1.0
    s = build_study(
        {"hull": "wigley", "lpp": 1, "bwl": 0.1, "tm": 0.0625, "out": str(tmp_path), "courant": "0.5"}
        | {"time_scheme": "Euler", "layers": "false", "wake": "no"}
    )
    assert (s.courant, s.time_scheme, s.layers, s.wake) == (0.5, "Euler", False, False)
    for key, bad in (("courant", "3"), ("courant", "0"), ("time_scheme", "CrankNicolson")):
        with pytest.raises(InputError, match=key):
            build_study(
                {"hull": "wigley", "lpp": 1, "bwl": 0.1, "tm": 0.0625, "out": str(tmp_path), key: bad}
            )


def test_layers_are_sized_for_the_yplus_target():
    # Wigley L = 1 m at Re = 1e6: flat-plate C_f(1e6) = 0.00375, u_tau = 0.0433 m/s, so y+ = 150 puts the
    # first cell centre 3.47 mm off the wall and the first layer is 6.9 mm; growth 1.2 up to 0.6 of the
    # 15.6 mm surface cell takes 3 layers
    spec = mesh_spec(L, B, T, 1, U=1.0, nu=1e-6, layers=True, yplus=150.0)
    assert spec.first_layer_m == pytest.approx(2 * 3.47e-3, rel=0.01)
    assert spec.n_layers == 3 and spec.yplus_target == 150.0
    assert spec.first_layer_m * spec.expansion ** (spec.n_layers - 1) == pytest.approx(
        0.6 * spec.h_hull, rel=0.25
    )
    assert mesh_spec(L, B, T, 1, U=1.0, nu=1e-6).yplus_target == 0.0  # no layers, no target


def test_wake_refinement_follows_the_drift_angle(tmp_path):
    spec = mesh_spec(L, B, T, 2, U=1.0, nu=1e-6, wake_deg=(0.0, 6.0, -3.0))
    # a fan every 5 deg from 0 to each angle rounded up; negative angles (PMM) on the other side
    assert [w.name for w in spec.wakes] == ["wake_m05", "wake_p00", "wake_p05", "wake_p10"]
    w10 = spec.wakes[-1]
    (x1, y1, z1), (x2, y2, z2) = w10.point1, w10.point2
    assert (x1, y1) == (0.0, 0.0) and z1 == z2 == 0.0  # from midship on the waterplane (double body)
    # downstream of an inflow (-cos b, -sin b): the axis leans to -y, past the stern by 1 L
    assert math.degrees(math.atan2(-y2, -x2)) == pytest.approx(10.0)
    assert math.hypot(x2, y2) == pytest.approx(1.5 * L)
    assert w10.radius > T and w10.level == spec.hull_level - 2
    assert mesh_spec(L, B, T, 2, U=1.0, nu=1e-6, wake_deg=(0.0, 4.0)).wakes == spec.wakes[1:3]
    stl = write_stl(tmp_path / "hull.stl", wigley_hull(L, B, T))
    write_mesh_case(tmp_path / "mesh", spec, stl)
    sn = _parse(tmp_path / "mesh" / "system" / "snappyHexMeshDict")
    cyl = sn["geometry"]["wake_p10"]
    assert cyl["type"] == "searchableCylinder" and list(cyl["point2"]) == pytest.approx(w10.point2)
    assert cyl["radius"] == pytest.approx(w10.radius)
    region = sn["castellatedMeshControls"]["refinementRegions"]["wake_p10"]
    assert region["mode"] == "inside" and list(region["levels"][0]) == [1e15, w10.level]
    assert cell_count_estimate(spec) > cell_count_estimate(mesh_spec(L, B, T, 2, U=1.0, nu=1e-6))


def test_a_drift_case_starts_from_the_converged_tow_turned_to_its_inflow(tmp_path):
    from cfd.case.flow import flow_fields, read_internal_field, start_fields

    tow = FlowSpec(U=1.0)
    zero = tmp_path / "0"
    for name, (body, cls) in flow_fields(FlowSpec(U=2.0, beta_deg=90.0)).items():
        foamdict.write(zero / name, body, foam_class=cls)
    done = tmp_path / "tow" / "150"  # three cells of a converged tow, as simpleFoam writes them in ASCII
    done.mkdir(parents=True)
    vec = "internalField   nonuniform List<vector> \n3\n(\n(-1 0 0)\n(-0.5 0.1 0)\n(0 0 0.2)\n)\n;\n"
    (done / "U").write_text("FoamFile { format ascii; class volVectorField; }\n" + vec + "boundaryField {}\n")
    for name, vals in (("p", "0.5 -0.25 0"), ("k", "1e-4 2e-4 3e-4"), ("omega", "10 20 30"), ("nut", "1 2 3")):
        text = f"internalField   nonuniform List<scalar> 3({vals});\nboundaryField {{}}\n"
        (done / name).write_text("FoamFile { format ascii; class volScalarField; }\n" + text)
    assert start_fields(zero, done, tow, FlowSpec(U=2.0, beta_deg=90.0))
    # turned by +90 deg about z (inflow from (-U, 0) to (0, -U)) and doubled with the speed
    U = read_internal_field(zero / "U")
    np.testing.assert_allclose(U, [[0, -2, 0], [-0.2, -1, 0], [0, 0, 0.4]], atol=1e-12)
    np.testing.assert_allclose(read_internal_field(zero / "p"), [2.0, -1.0, 0.0])  # x U^2
    np.testing.assert_allclose(read_internal_field(zero / "omega"), [20, 40, 60])  # x U
    text = (zero / "U").read_text()  # the boundary conditions are the drift case's own
    assert text.count("internalField") == 1 and "freestreamVelocity" in text and "movingWallVelocity" in text
    (done / "k").write_text("FoamFile { format binary; }\ninternalField nonuniform List<scalar> 3(\x00\x01);\n")
    assert not start_fields(zero, done, tow, FlowSpec(U=2.0))  # unreadable (binary): the caller keeps uniform
