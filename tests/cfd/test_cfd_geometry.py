"""Hull STL generation, I/O, placement and hydrostatics."""

from __future__ import annotations

import gzip
from collections import Counter

import numpy as np
import pytest

from cfd.errors import InputError
from cfd.geometry import clip_below, hydrostatics, place_hull, read_stl, wigley_hull, write_stl

L, B, T = 1.0, 0.1, 0.0625


@pytest.fixture(scope="module")
def wigley():
    return wigley_hull(L, B, T)


def test_wigley_is_closed_and_outward(wigley):
    edges = Counter()
    key = {}
    for tri in wigley:
        ids = [key.setdefault(tuple(np.round(p, 12)), len(key)) for p in tri]
        for a, b in ((0, 1), (1, 2), (2, 0)):
            edges[tuple(sorted((ids[a], ids[b])))] += 1
    assert set(edges.values()) == {2}  # every edge shared by exactly two triangles
    area = 0.5 * np.cross(wigley[:, 1] - wigley[:, 0], wigley[:, 2] - wigley[:, 0])
    centroid = wigley.mean(axis=1)
    assert np.all(area[:, 1] * centroid[:, 1] > 0)  # normals point away from the centre plane
    on_plane = np.all(np.abs(wigley[:, :, 1]) < 1e-15, axis=1)
    assert not on_plane.any()  # no flat triangles on y = 0


def test_wigley_hydrostatics_against_analytic(wigley):
    h = hydrostatics(wigley)
    assert h.volume_m3 == pytest.approx(4 / 9 * L * B * T, rel=0.01)  # C_B = 4/9
    # wetted surface of the Wigley below the waterline, numerical integral of the exact surface
    x = np.linspace(-0.5, 0.5, 801)
    z = np.linspace(-T, 0, 401)
    X, Z = np.meshgrid(x, z, indexing="ij")
    dydx = B / 2 * (-8 * X / L**2) * (1 - (Z / T) ** 2)
    dydz = B / 2 * (1 - (2 * X / L) ** 2) * (-2 * Z / T**2)
    S = 2 * np.trapezoid(np.trapezoid(np.sqrt(1 + dydx**2 + dydz**2), z, axis=1), x)
    assert h.wetted_area_m2 == pytest.approx(S, rel=0.01)
    assert h.lcb_m == pytest.approx(0.0, abs=1e-3)
    assert (h.lwl_m, h.bwl_m, h.draught_m) == pytest.approx((L, B, T))


def test_clip_keeps_only_the_part_below():
    tri = np.array([[[0.0, 0, -1], [1, 0, 1], [0, 1, 1]]])
    part = clip_below(tri, 0.0)
    assert part.shape == (1, 3, 3) and np.all(part[:, :, 2] <= 1e-12)
    two = clip_below(np.array([[[0.0, 0, -1], [1, 0, -1], [0, 1, 1]]]), 0.0)
    assert two.shape == (2, 3, 3)


@pytest.mark.parametrize("fmt", ["ascii", "binary", "gz"])
def test_stl_round_trip(tmp_path, wigley, fmt):
    path = write_stl(tmp_path / "h.stl", wigley)
    if fmt == "binary":
        rec = np.zeros(len(wigley), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
        rec["v"] = wigley
        path.write_bytes(b"\0" * 80 + np.uint32(len(wigley)).tobytes() + rec.tobytes())
    if fmt == "gz":
        gz = tmp_path / "h.stl.gz"
        gz.write_bytes(gzip.compress(path.read_bytes()))
        path = gz
    back = read_stl(path)
    assert back == pytest.approx(wigley, abs=1e-6)
    if fmt == "ascii":
        assert path.read_text().startswith("solid hull")


def test_read_stl_errors(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        read_stl(tmp_path / "missing.stl")
    bad = tmp_path / "bad.stl"
    bad.write_bytes(b"solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n")
    with pytest.raises(InputError, match="ASCII STL"):
        read_stl(bad)


def test_place_hull_moves_mirrors_and_checks(wigley):
    # the input: stern at x = 0, keel at z = 0, starboard half only (y <= 0)
    moved = wigley + np.array([0.5, 0.0, T])
    half = moved[np.all(moved[:, :, 1] <= 1e-12, axis=1)]
    placed = place_hull(half, L, B, T)
    assert placed.mirrored
    assert placed.shift_m == pytest.approx((-0.5, 0.0, -T))
    assert placed.hydro.volume_m3 == pytest.approx(hydrostatics(wigley).volume_m3, rel=1e-6)
    with pytest.raises(InputError, match="lpp"):
        place_hull(moved * 1000.0, L, B, T)  # millimetres
    with pytest.raises(InputError, match="tm"):
        place_hull(moved, L, B, 2 * T)  # no freeboard
    with pytest.raises(InputError, match="bwl"):
        place_hull(moved, L, 2 * B, T)


def test_a_hole_below_the_waterline_is_refused_before_meshing(wigley):
    from cfd.geometry import check_surface

    moved = wigley + np.array([0.5, 0.0, T])  # keel at z = 0, waterline at z = T, deck at 2T
    assert check_surface(wigley).closed
    centroid_z = moved[:, :, 2].mean(axis=1)
    wet = np.flatnonzero(centroid_z < 0.5 * T)
    holed = np.delete(moved, wet[len(wet) // 2], axis=0)  # one triangle missing under water
    check = check_surface(holed - np.array([0.0, 0.0, T]))
    assert check.open_edges == 3 and check.non_manifold_edges == 0
    with pytest.raises(InputError, match="not closed below the waterline: 3 open") as exc:
        place_hull(holed, L, B, T)
    assert "\n" not in str(exc.value)
    dry = np.flatnonzero(centroid_z > 1.5 * T)
    place_hull(np.delete(moved, dry[0], axis=0), L, B, T)  # a hole in the dry part is cut away: accepted
    doubled = np.concatenate([moved, moved[wet[:1]]])  # a third triangle on an edge
    with pytest.raises(InputError, match="non-manifold"):
        place_hull(doubled, L, B, T)
