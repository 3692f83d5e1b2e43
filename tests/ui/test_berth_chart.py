"""The berth on the chart (vessel_gym.ui.chart, BerthingTask.overlay): the quay face, the fenders coloured by
the share of their rating used, the berthed pose, in the full chart and the magnified inset; real pygame
rendering, headless."""

import os

import gymnasium as gym
import numpy as np
import pytest

import vessel_gym  # noqa: F401  (registers the ids)
from vessel_gym.ui.chart import BERTH_TARGET, QUAY_FACE, fender_colour, task_renderer

pytest.importorskip("pygame")
os.environ.setdefault("SDL_VIDEODRIVER", "dummy")


def _frame(env, renderer):
    task = env.unwrapped.task
    return task, renderer.draw(task.sim, 0, [], overlay=task.overlay(0))


def _near(frame, xy, colour, r=2):
    x, y = int(round(xy[0])), int(round(xy[1]))
    patch = frame[max(y - r, 0) : y + r + 1, max(x - r, 0) : x + r + 1].reshape(-1, 3)
    return bool((np.abs(patch.astype(int) - colour).max(axis=1) <= 2).any())


def test_fender_colour_runs_from_unused_to_overload():
    assert fender_colour(0.0) == (245, 245, 245)
    assert fender_colour(0.01)[1] == 200 and fender_colour(0.01)[0] < 10  # green
    assert fender_colour(0.5) == (255, 200, 40)  # yellow
    assert fender_colour(1.0) == (255, 0, 40)  # red at the rating
    assert fender_colour(1.2) == (230, 0, 200)  # beyond it


def test_the_quay_fenders_and_berthed_pose_are_drawn_in_chart_and_inset():
    env = gym.make("vessel_gym/Berthing-v0")
    env.reset(seed=0)
    task = env.unwrapped.task
    r = task_renderer(task, "rgb_array")
    task, frame = _frame(env, r)
    assert frame.shape == (600, 800, 3)
    berth = task.overlay(0)["berth"]
    # the quay face: its middle on the full chart
    (n0, e0), (n1, e1) = berth["quay_m"]
    assert _near(frame, r.to_screen(0.5 * (n0 + n1), 0.5 * (e0 + e1)), QUAY_FACE)
    # in the inset: every fender unused (white), the quay face between them, the berthed pose's outline
    x0, y0, w, h = r.inset_rect
    L = task.L
    nc, ec, _psi = berth["target"]
    s = w / (1.5 * L)

    def inset(n, e):
        return (x0 + w / 2 + (e - ec) * s, y0 + h / 2 - (n - nc) * s)

    faces = np.array(berth["fender_face_m"])
    bases = np.array(berth["fender_base_m"])
    for f, b in zip(faces, bases):
        assert _near(frame, inset(*(0.5 * (f + b))), fender_colour(0.0), r=1)
    gap = 0.5 * (faces[0] + faces[1]) - 0.5 * np.array(task.fenders.to_water) * 0.8  # between two fenders
    assert _near(frame, inset(*gap), QUAY_FACE)
    assert (np.abs(frame[y0 : y0 + h, x0 : x0 + w].astype(int) - BERTH_TARGET).max(axis=2) == 0).sum() > 50
    # a panel row of the berth
    assert "contact" in [label for label, _ in task.overlay(0)["rows"]]
    r.close()
    env.close()


def test_a_fender_past_its_rating_turns_magenta_and_a_compressed_one_coloured():
    env = gym.make("vessel_gym/Berthing-v0")
    env.reset(seed=0)
    task = env.unwrapped.task
    task.fender_energy_kJ[0, 2] = 1.5 * task.E_rated / 1e3  # fender 2 overloaded
    task.fender_energy_kJ[0, 0] = 0.5 * task.E_rated / 1e3  # fender 0 at half its rating
    r = task_renderer(task, "rgb_array")
    task, frame = _frame(env, r)
    berth = task.overlay(0)["berth"]
    assert berth["fender_load"][2] == pytest.approx(1.5) and berth["fender_load"][0] == pytest.approx(0.5)
    x0, y0, w, h = r.inset_rect
    inset = frame[y0 : y0 + h, x0 : x0 + w].astype(int)
    for colour in (fender_colour(1.5), fender_colour(0.5)):
        assert (np.abs(inset - colour).max(axis=2) == 0).sum() >= 9  # a fender's square, at least 3 x 3 px
    # on the full chart too (at least 3 px)
    f2 = 0.5 * (np.array(berth["fender_face_m"][2]) + np.array(berth["fender_base_m"][2]))
    assert _near(frame, r.to_screen(*f2), fender_colour(1.5), r=3)
    r.close()
    env.close()


def test_the_environments_own_render_draws_the_berth():
    env = gym.make("vessel_gym/Berthing-v0", render_mode="rgb_array")
    env.reset(seed=1)
    frame = env.render()
    r = env.unwrapped._renderer
    x0, y0, w, h = r.inset_rect
    inset = frame[y0 : y0 + h, x0 : x0 + w].astype(int)
    assert (np.abs(inset - fender_colour(0.0)).max(axis=2) == 0).sum() >= 5 * 9  # five unused fenders
    assert (np.abs(inset - QUAY_FACE).max(axis=2) == 0).sum() > w  # the quay face across the inset
    env.close()
