"""Bad scenario files never crash: unreadable files and ships are one line naming the file with exit 2, and
the polygon checks are O(n log n), so detailed charts load quickly and crossing polygons are still refused."""

from __future__ import annotations

import math
import os
import random
import re
import time
from pathlib import Path

import pytest

from vessel_gym.cli import main
from vessel_gym.scenarios import ScenarioError, load_scenario
from vessel_gym.scenarios import geometry as geo
from vessel_gym.scenarios.scenario import MAX_SCENARIO_FILE_BYTES, SCENARIO_DIR

HARBOUR = (SCENARIO_DIR / "harbour.toml").read_text()


def _write(tmp_path: Path, text: str, name: str = "port.toml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def _with_ship(tmp_path: Path, ship: str) -> Path:
    assert 'ship = "kvlcc2_l7"' in HARBOUR
    return _write(tmp_path, HARBOUR.replace('ship = "kvlcc2_l7"', f'ship = "{ship}"', 1))


def _load_error(path: Path) -> str:
    t0 = time.monotonic()
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    assert time.monotonic() - t0 < 10.0, "a bad file must fail at once, not hang"
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith(str(path)), msg
    return msg


def _star(n: int, centre: tuple[float, float], r_in: float, r_out: float) -> list[tuple[float, float]]:
    """A star with n vertices alternating between the inner and the outer radius (a simple polygon)."""
    return [
        (
            centre[0] + (r_out if i % 2 else r_in) * math.cos(2.0 * math.pi * i / n),
            centre[1] + (r_out if i % 2 else r_in) * math.sin(2.0 * math.pi * i / n),
        )
        for i in range(n)
    ]


def _comb(n: int, north0: float, east0: float) -> list[tuple[float, float]]:
    """A comb (zig-zag top edge, straight bottom) with n vertices, 10 m wide, 4 m deep teeth."""
    k = n - 2
    top = [(north0 + 4.0 * (i % 2), east0 + 10.0 * i / (k - 1)) for i in range(k)]
    return [*top, (north0 - 2.0, east0 + 10.0), (north0 - 2.0, east0)]


def _with_island(tmp_path: Path, pts: list[tuple[float, float]]) -> Path:
    body = ", ".join(f"[{a!r}, {b!r}]" for a, b in pts)
    return _write(tmp_path, HARBOUR + f'\n[[land]]\nname = "rocks"\npoints = [{body}]\n')


# ------------------------------------------------------------------------------------------- unreadable
@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")
def test_ship_dev_zero_is_refused_unread(tmp_path):
    path = _with_ship(tmp_path, "/dev/zero")
    msg = _load_error(path)
    assert "ship: /dev/zero: not a regular file" in msg


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes")
def test_ship_pipe_does_not_hang(tmp_path):
    """``ship = "/dev/stdin"`` on a terminal, or any FIFO without a writer, would block; it is refused."""
    os.mkfifo(tmp_path / "pipe.toml")
    path = _with_ship(tmp_path, "pipe.toml")
    msg = _load_error(path)
    assert "pipe.toml: not a regular file" in msg


@pytest.mark.skipif(not Path("/dev/stdin").exists(), reason="no /dev/stdin")
def test_play_with_ship_dev_stdin_exits_2(tmp_path, capsys):
    """The ``vessel-gym play`` load path: one line on stderr, exit 2, before any window opens."""
    path = _with_ship(tmp_path, "/dev/stdin")
    t0 = time.monotonic()
    code = main(["play", str(path)])
    assert time.monotonic() - t0 < 10.0
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err and "Traceback" not in err
    assert str(path) in err and "/dev/stdin" in err


def test_scenario_directory_and_size_bound(tmp_path):
    d = tmp_path / "charts.toml"
    d.mkdir()
    assert "is a directory" in _load_error(d)
    big = _write(tmp_path, HARBOUR + "#" * MAX_SCENARIO_FILE_BYTES + "\n", "big.toml")
    assert "larger than the limit of 4 MiB" in _load_error(big)


def test_scenario_invalid_utf8_names_the_file(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(HARBOUR.replace('name = "harbour"', 'name = "K\xf8ge"').encode("latin-1"))
    assert "not UTF-8" in _load_error(path)


def test_scenario_huge_integer_and_deep_nesting(tmp_path):
    big = _write(tmp_path, HARBOUR.replace("water_depth_m = 2.0", "water_depth_m = " + "9" * 400), "a.toml")
    assert re.search(r"water_depth_m: an integer of 400 digits is too large", _load_error(big))
    deep = _write(
        tmp_path, HARBOUR.replace("water_depth_m = 2.0", "water_depth_m = " + "[" * 10**5), "b.toml"
    )
    assert "nested too deeply" in _load_error(deep)


def test_repeated_vertex_is_named(tmp_path):
    pts = [(-40.0, 40.0), (-40.0, 50.0), (-30.0, 50.0), (-40.0, 50.0), (-30.0, 40.0)]
    msg = _load_error(_with_island(tmp_path, pts))
    assert "land[3] 'rocks' points[3]: repeats vertex 1" in msg


# ------------------------------------------------------------------------------------------- polygons
@pytest.mark.parametrize("shape", ["star", "comb"])
def test_8000_vertex_land_polygon_loads_quickly(tmp_path, shape):
    """Measured about 0.5 s per load on a 2-core machine (it was 93 s with the all-pairs check); the bound
    leaves room for a loaded CI runner."""
    pts = _star(8000, (-40.0, 45.0), 8.0, 12.0) if shape == "star" else _comb(8000, -40.0, 40.0)
    path = _with_island(tmp_path, pts)
    t0 = time.perf_counter()
    sc = load_scenario(path)
    elapsed = time.perf_counter() - t0
    assert len(sc.land[-1].points) == 8000
    assert elapsed < 3.0, f"{elapsed:.2f} s"


@pytest.mark.parametrize("shape", ["star", "comb"])
def test_8000_vertex_self_intersecting_polygon_is_refused(tmp_path, shape):
    pts = _star(8000, (-40.0, 45.0), 8.0, 12.0) if shape == "star" else _comb(8000, -40.0, 40.0)
    pts[100], pts[4100] = pts[4100], pts[100]  # two far-apart vertices swapped: edges cross the shape
    t0 = time.perf_counter()
    msg = _load_error(_with_island(tmp_path, pts))
    assert time.perf_counter() - t0 < 3.0
    assert re.search(
        r"land\[3\] 'rocks' points: polygon is self-intersecting \(edges \d+ and \d+ meet\)", msg
    )


def _all_pairs_self_intersection(poly):
    """Reference: every pair of non-adjacent edges (O(n^2)); a repeated vertex counts as a meeting."""
    n = len(poly)
    if len(set(poly)) < n:
        return True
    for i in range(n):
        for j in range(i + 2, n):
            if (j + 1) % n == i:
                continue
            if geo.segments_intersect(poly[i], poly[(i + 1) % n], poly[j], poly[(j + 1) % n]):
                return True
    return False


def _all_pairs_overlap(p, q):
    for i in range(len(p)):
        for j in range(len(q)):
            if geo.segments_intersect(p[i], p[(i + 1) % len(p)], q[j], q[(j + 1) % len(q)]):
                return True
    return geo.point_in_polygon(p[0], q) or geo.point_in_polygon(q[0], p)


def test_sweep_agrees_with_all_pairs_on_degenerate_polygons():
    """Vertices on a small integer grid make every degenerate case common: collinear and overlapping
    edges, vertical edges, a vertex on another edge, equal coordinates. The sweep must agree with the
    all-pairs reference on every one."""
    rng = random.Random(20261201)
    simple = []
    for _ in range(4000):
        k = rng.choice((2, 3, 4, 6, 20))
        poly = [(float(rng.randint(0, k)), float(rng.randint(0, k))) for _ in range(rng.randint(3, 9))]
        expected = _all_pairs_self_intersection(poly)
        assert (geo.self_intersection(poly) is not None) == expected, poly
        if not expected and len(poly) <= 6 and abs(geo.signed_area(poly)) > 0.0:
            simple.append(poly)
    assert len(simple) > 300
    for _ in range(4000):
        p, q = rng.choice(simple), rng.choice(simple)
        assert geo.polygons_overlap(p, q) == _all_pairs_overlap(p, q), (p, q)


def test_overlap_with_a_detailed_polygon_is_fast():
    star = _star(8000, (0.0, 0.0), 300.0, 1000.0)
    t0 = time.perf_counter()
    assert geo.polygons_overlap([(0.0, 0.0), (10.0, 0.0), (10.0, 10.0)], star)  # contained
    assert geo.polygons_overlap([(250.0, -5.0), (350.0, -5.0), (350.0, 5.0)], star)  # edges cross
    assert not geo.polygons_overlap([(2000.0, 0.0), (2010.0, 0.0), (2010.0, 10.0)], star)  # apart
    assert time.perf_counter() - t0 < 3.0


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")
def test_serve_with_ship_dev_zero_exits_2(tmp_path, capsys):
    """The ``vessel-gym serve`` load path: the scenario is loaded before any socket is opened."""
    path = _with_ship(tmp_path, "/dev/zero")
    code = main(["serve", str(path), "--duration", "1"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err and "Traceback" not in err
    assert str(path) in err and "/dev/zero: not a regular file" in err
