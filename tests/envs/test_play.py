"""Keyboard play, headless with scripted key events."""

from __future__ import annotations

import numpy as np
import pytest

from vessel_gym.ui.play import play, score


def test_scripted_play_writes_a_debrief(tmp_path):
    pygame = pytest.importorskip("pygame")
    d = play(
        "harbour",
        seed=1,
        realtime=False,
        max_steps=120,
        out_dir=tmp_path,
        keys=[(0, "up"), (0, "up"), (10, "left"), (30, "space")],
    )
    assert d.steps == 120 and d.outcome == "max_steps"
    assert d.time_s == pytest.approx(120 * 0.99)  # HarbourApproach-v2: L / U_T / 6 of kvlcc2_l7 per step
    assert d.min_clearance_m > 0.0 and d.contacts == 0 and 0.0 <= d.score <= 100.0
    assert "minimum clearance" in d.summary()
    img = pygame.surfarray.array3d(pygame.image.load(d.track_png))
    assert img.shape[:2] == (800, 600) and img.std() > 10.0
    assert len(d.track) == 121


def test_scripted_keys_steer_the_ship():
    left = play("harbour", seed=2, realtime=False, max_steps=60, out_dir=None, keys=[(0, "left")] * 4)
    right = play("harbour", seed=2, realtime=False, max_steps=60, out_dir=None, keys=[(0, "right")] * 4)
    assert np.array(left.track)[-1, 1] < np.array(right.track)[-1, 1]  # port turn ends further west


def test_quit_key_and_score():
    d = play("harbour", seed=0, realtime=False, max_steps=50, out_dir=None, keys=[(5, "escape")])
    assert d.outcome == "quit" and d.steps == 5
    assert score("success", 100.0, 5.0, 100.0, 0.0, 7.0, 1.0) == pytest.approx(100.0)
    assert score("contact", 10.0, 0.0, 100.0, 50.0, 7.0, 1.0) == pytest.approx(10.0)
