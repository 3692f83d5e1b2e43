"""Regenerate the pictures of the README (takes about a minute cold).

    python docs/img/make_images.py docs/img      # replace the committed pictures
    python docs/img/make_images.py               # write them to out/img/ (ignored by git) to compare first

- ``chart_harbour.png``: the pygame chart view (``render_mode="rgb_array"``) of HarbourApproach-v3 (seed 0)
  after 100 control steps (about 100 s) under the PID harbour pilot (``vessel_gym.policy.load_policy("pid", env)``).
- ``imo_turning_circle.png``: the turning-circle plot of ``vessel-gym imo kvlcc2 --plot DIR``.

Both are scaled to 640 px wide to keep the repository small.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("MPLBACKEND", "Agg")

WIDTH_PX = 640  # px, width of the committed pictures
STEPS = 100  # control steps (about 100 s) before the chart is drawn (the ship is under way in the approach channel)


def _save_scaled(surface, path: Path) -> None:
    """Crop uniform white margins (matplotlib's around an equal-aspect plot), scale to WIDTH_PX, save."""
    import numpy as np
    import pygame

    rgb = pygame.surfarray.array3d(surface)  # (width, height, 3)
    ink = np.argwhere((rgb < 250).any(axis=2))
    if len(ink):
        (x0, y0), (x1, y1) = ink.min(axis=0), ink.max(axis=0)
        pad = 8  # px kept around the drawing
        x0, y0 = max(x0 - pad, 0), max(y0 - pad, 0)
        x1, y1 = min(x1 + pad, rgb.shape[0] - 1), min(y1 + pad, rgb.shape[1] - 1)
        surface = surface.subsurface(pygame.Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1))
    w, h = surface.get_size()
    pygame.image.save(pygame.transform.smoothscale(surface, (WIDTH_PX, round(h * WIDTH_PX / w))), str(path))


def chart(out: Path) -> Path:
    import gymnasium as gym
    import pygame

    import vessel_gym  # noqa: F401  (registers the ids)
    from vessel_gym.policy import load_policy

    env = gym.make("vessel_gym/HarbourApproach-v3", render_mode="rgb_array")
    obs, _ = env.reset(seed=0)
    pilot = load_policy("pid", env)
    for _ in range(STEPS):
        obs, _r, term, trunc, _i = env.step(pilot(obs))
        if term or trunc:
            break
    frame = env.render()  # (height, width, 3) uint8
    env.close()
    path = out / "chart_harbour.png"
    _save_scaled(pygame.surfarray.make_surface(frame.swapaxes(0, 1)), path)
    return path


def imo_plot(out: Path) -> Path:
    import pygame

    from vessel_gym.manoeuvres.imo import imo_report
    from vessel_gym.manoeuvres.plots import plot_report

    tmp = Path(tempfile.mkdtemp(prefix="vessel-gym-img-"))
    try:
        files = plot_report(imo_report("kvlcc2"), tmp / "plots")
        src = next((f for f in files if "turning" in Path(f).name), files[0])
        path = out / "imo_turning_circle.png"
        _save_scaled(pygame.image.load(str(src)), path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return path


def main(argv: list[str] | None = None) -> int:
    from vessel_gym.cli_args import OneLineParser

    p = OneLineParser(prog="make_images.py", description="Regenerate the README's pictures.")
    p.add_argument(
        "out",
        nargs="?",
        default="out/img",
        help="directory for the pictures; docs/img replaces the committed ones",
    )
    out = Path(p.parse_args(argv).out)
    out.mkdir(parents=True, exist_ok=True)
    for make in (chart, imo_plot):
        print(make(out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
