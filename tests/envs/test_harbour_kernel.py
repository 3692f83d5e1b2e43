"""Harbour task kernel: the threaded driver matches the serial one; the observation follows the environment
the physics uses; the chart query's contact cases, and its beams and clearance against a brute-force
reference."""

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym  # noqa: F401
from vessel_gym.envs.task import observation_features
from vessel_gym.envs.tasks import chart, harbour_kernel
from vessel_gym.physics.environment import CALM, Environment
from vessel_gym.physics.units import KNOT_M_S


def test_threaded_harbour_kernel_matches_serial():
    n = harbour_kernel.PARALLEL_MIN_SHIPS
    threaded = gym.make_vec(
        "vessel_gym/HarbourApproach-v2", num_envs=n, vectorization_mode="vector_entry_point"
    )
    serial = gym.make_vec(
        "vessel_gym/HarbourApproach-v2", num_envs=n, vectorization_mode="vector_entry_point"
    )
    assert threaded.unwrapped.task.kernel is harbour_kernel.harbour_update_parallel
    serial.unwrapped.task.kernel = harbour_kernel.harbour_update
    o1, _ = threaded.reset(seed=5)
    o2, _ = serial.reset(seed=5)
    assert np.array_equal(o1, o2)
    threaded.action_space.seed(2)
    for _ in range(40):
        a = threaded.action_space.sample()
        r1 = threaded.step(a)
        r2 = serial.step(a)
        for x, y in zip(r1[:4], r2[:4]):
            assert np.array_equal(x, y)
        assert np.array_equal(r1[4]["min_clearance_m"], r2[4]["min_clearance_m"])


def test_observation_follows_set_environment():
    """A current and a wind set after reset reach the observation: speed over ground and apparent wind as the
    physics and the bridge see them (the task once kept copies of the environment from reset and reported
    0.708 m/s over ground here, the bridge 0.651 m/s)."""
    env = gym.make("vessel_gym/HarbourApproach-v2", observation_type="physical")
    env.reset(seed=0, options={"environment": CALM})
    task = env.unwrapped.task
    sim = task.sim
    sim.set_environment(Environment(current_speed_m_s=0.5, current_to_deg=90.0, wind_speed_m_s=2.0))
    obs, _r, _term, _trunc, info = env.step(np.zeros(2, dtype=np.float32))
    names = [f.name for f in observation_features(task)]
    reading = sim.bridge(0)
    sog = reading.sog_kn * KNOT_M_S
    # over ground = through the water rotated to north/east + the current (0.5 m/s towards east)
    psi, u, v = sim.heading[0], sim.u[0], sim.v[0]
    expected = np.hypot(u * np.cos(psi) - v * np.sin(psi), u * np.sin(psi) + v * np.cos(psi) + 0.5)
    assert sog == pytest.approx(expected, rel=1e-12)
    assert abs(sog - np.hypot(u, v)) > 0.05  # the current changes it (0.651 against 0.708 m/s)
    assert info["speed_over_ground_m_s"] == pytest.approx(sog, rel=1e-12)
    assert obs[names.index("sog")] == pytest.approx(sog, rel=1e-6)  # float32 observation
    wind = reading.wind_rel_speed_kn * KNOT_M_S
    assert obs[names.index("wind_speed")] == pytest.approx(wind, rel=1e-6)
    gamma = np.radians(reading.wind_rel_angle_deg)
    assert obs[names.index("wind_angle_sin")] == pytest.approx(np.sin(gamma), abs=1e-6)
    assert obs[names.index("wind_angle_cos")] == pytest.approx(np.cos(gamma), abs=1e-6)


def test_chart_query_contact_cases():
    """Contact when outlines cross, when the hull lies wholly in a polygon, and when a small rock lies wholly
    under the hull (no outline crossing in the last two)."""
    hull = np.array([(3.5, 0.0), (2.1, 0.6), (-3.5, 0.6), (-3.5, -0.6), (2.1, -0.6)])  # 7 m x 1.2 m
    beam_dirs = np.array([(1.0, 0.0), (0.0, 1.0)])
    scratch = (np.empty(2), np.empty(5), np.empty(5), np.empty((2, 2)))

    def query(polygon, n0=0.0, e0=0.0):
        edges, polys, pbox = chart.chart_tables([(1, polygon)])
        b, hn, he, bw = scratch
        return chart.chart_query(n0, e0, 0.0, hull, edges, polys, pbox, beam_dirs, 50.0, b, hn, he, bw)

    rock = [(-0.2, -0.2), (0.2, -0.2), (0.2, 0.2), (-0.2, 0.2)]
    assert query(rock)[0] == chart.CONTACT  # wholly under the hull
    island = [(-20.0, -20.0), (20.0, -20.0), (20.0, 20.0), (-20.0, 20.0)]
    assert query(island)[0] == chart.CONTACT  # hull wholly inside
    assert query(island, n0=22.0)[0] == chart.CONTACT  # bow over the edge: outlines cross
    flag, clearance = query(island, n0=30.0)
    assert flag == chart.OK and clearance == pytest.approx(30.0 - 3.5 - 20.0)


def _next_vertex(polys):
    """Row of each edge's end vertex in the chart tables (the polygons close on their first vertex)."""
    return np.concatenate([st + (np.arange(cnt) + 1) % cnt for st, cnt, _kind, _orient in polys])


def _brute_force_chart(task, n0, e0, psi, beam_dirs):
    """Reference for :func:`chart.chart_query` without any culling: every beam against every chart edge (the ray
    o + t d meets a + s (b - a) at t = (a - o) x e / (d x e), s = (a - o) x d / (d x e)), and the clearance as
    the smallest distance between a vertex of one outline and an edge of the other, capped at the range."""
    c, s = np.cos(psi), np.sin(psi)
    a = task.edges[:, :2]
    b = a[_next_vertex(task.polys)]
    e = b - a
    w = a - (n0, e0)
    d = np.stack([c * beam_dirs[:, 0] - s * beam_dirs[:, 1], s * beam_dirs[:, 0] + c * beam_dirs[:, 1]], 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]  # (beam, edge)
        t = (w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0])[None, :] / den
        sp = (w[None, :, 0] * d[:, None, 1] - w[None, :, 1] * d[:, None, 0]) / den
    hit = (den != 0.0) & (t >= 0.0) & (sp >= 0.0) & (sp <= 1.0)
    beams = np.minimum(np.where(hit, t, np.inf).min(axis=1), task.beam_range)

    def point_seg(p, a, b):  # distances between points p (n, 2) and segments a b (m, 2), (n, m)
        e = b - a
        tt = np.clip(((p[:, None, :] - a[None]) * e[None]).sum(2) / (e * e).sum(1)[None], 0.0, 1.0)
        q = a[None] + tt[..., None] * e[None] - p[:, None, :]
        return np.sqrt((q * q).sum(2))

    x, y = task.hull[:, 0], task.hull[:, 1]
    hull = np.stack([n0 + c * x - s * y, e0 + s * x + c * y], 1)
    hull_next = np.roll(hull, -1, axis=0)
    clearance = min(point_seg(hull, a, b).min(), point_seg(a, hull, hull_next).min(), task.beam_range)
    return beams, clearance


def test_chart_query_matches_brute_force():
    """Range beams and clearance of the culled chart query against every beam x every edge, over random poses
    in the built-in harbour chart: open water, inside polygons, and close to edges and vertices (1 um to 10 m);
    with the task's beam fan and with an irregular one."""
    task = gym.make("vessel_gym/HarbourApproach-v2").unwrapped.task
    tables = (task.hull, task.edges, task.polys, task.pbox)
    R = task.beam_range
    rng = np.random.default_rng(7)
    verts = task.edges[:, :2]
    nxt = _next_vertex(task.polys)
    n = 400
    k = rng.integers(0, len(verts), n)
    offset = 10.0 ** rng.uniform(-6.0, 1.0, (n, 1)) * rng.normal(size=(n, 2))
    n_min, n_max, e_min, e_max = task.scenario.bounds_m
    points = np.concatenate(
        [
            np.column_stack([rng.uniform(n_min, n_max, n), rng.uniform(e_min, e_max, n)]),  # water and land
            verts[k] + rng.uniform(0.0, 1.0, (n, 1)) * (verts[nxt[k]] - verts[k]) + offset,  # near edges
            verts[k] + offset,  # near vertices
        ]
    )
    headings = rng.uniform(-np.pi, np.pi, len(points))
    irregular = rng.normal(size=(7, 2))
    irregular /= np.linalg.norm(irregular, axis=1, keepdims=True)
    n_clear = 0
    for beam_dirs in (task.beam_dirs, irregular):
        nb = len(beam_dirs)
        beams, bw = np.empty(nb), np.empty((2, nb))
        hn, he = np.empty(len(task.hull)), np.empty(len(task.hull))
        for (n0, e0), psi in zip(points, headings):
            flag, clearance = chart.chart_query(n0, e0, psi, *tables, beam_dirs, R, beams, hn, he, bw)
            ref_beams, ref_clearance = _brute_force_chart(task, n0, e0, psi, beam_dirs)
            np.testing.assert_allclose(beams, ref_beams, rtol=0.0, atol=1e-9, err_msg=f"pose {(n0, e0, psi)}")
            if flag == chart.OK:
                n_clear += 1
                assert abs(clearance - ref_clearance) <= 1e-9, (n0, e0, psi, clearance, ref_clearance)
            else:
                assert clearance == 0.0  # contact or grounding
    assert n_clear > 0.15 * 2 * len(points)  # not vacuous: about a fifth of the poses are clear of the chart
