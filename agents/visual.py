"""Pictures of evaluated episodes: chart frames (PNG), a video (animated GIF or MP4), the trajectory plot.

* :class:`Recorder` wraps an environment during evaluation and keeps each episode's track (midship north,
  east in m, read from the simulation after every step) and, with ``frames_dir``, writes the chart the
  environment renders (``render_mode="rgb_array"``) every ``frame_every`` steps as
  ``<frames_dir>/ep<i>_<step>.png``. It does not change what the agent sees or does.
* :func:`write_video`: ``.gif`` with Pillow (a dependency of matplotlib, so always there with the ``plot``
  extra); ``.mp4`` with imageio + imageio-ffmpeg when they are installed (``pip install imageio
  imageio-ffmpeg``), else a :class:`agents.common.UsageError` naming them.
* :func:`plot_trajectories`: every episode's track on the environment's chart (the scenario's land,
  breakwaters, quays and goal for HarbourApproach; open water otherwise), north up, metres, equal axes.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from agents.common import UsageError

VIDEO_SUFFIXES = (".gif", ".mp4")


def check_video_path(path: str | Path) -> Path:
    """``UsageError`` unless ``path`` ends in a supported suffix and an MP4 writer exists if needed."""
    p = Path(path)
    if p.suffix.lower() not in VIDEO_SUFFIXES:
        raise UsageError(f"--video {p}: expected a file ending in {' or '.join(VIDEO_SUFFIXES)}")
    if p.suffix.lower() == ".mp4":
        try:
            import imageio.v2  # noqa: F401
            import imageio_ffmpeg  # noqa: F401
        except ImportError:
            raise UsageError(
                f"--video {p}: MP4 needs imageio and imageio-ffmpeg (pip install imageio imageio-ffmpeg); "
                "a .gif needs nothing more"
            ) from None
    return p


def _import_gym_wrapper() -> type:
    import gymnasium as gym

    return gym.Wrapper


class Recorder(_import_gym_wrapper()):  # type: ignore[misc]
    """Keeps the track of every episode; with ``frames_dir`` saves chart frames, with ``keep_frames`` keeps
    them in memory (``frames``, for a video)."""

    def __init__(
        self,
        env: Any,
        frames_dir: str | Path | None = None,
        frame_every: int = 1,
        keep_frames: bool = False,
        max_kept: int = 2000,
    ) -> None:
        super().__init__(env)
        self.tracks: list[list[tuple[float, float]]] = []
        self.frames_dir = Path(frames_dir) if frames_dir is not None else None
        self.frame_every = max(int(frame_every), 1)
        self.keep_frames = keep_frames
        self.max_kept = max_kept  # memory cap: 800x600 RGB is 1.4 MB a frame
        self.frames: list[np.ndarray] = []
        self.frame_files: list[Path] = []
        self._step = 0
        if self.frames_dir is not None:
            self.frames_dir.mkdir(parents=True, exist_ok=True)

    def _position(self) -> tuple[float, float]:
        sim = self.env.unwrapped.sim
        return float(sim.north[0]), float(sim.east[0])

    def _frame(self) -> None:
        if self.frames_dir is None and not self.keep_frames:
            return
        if self._step % self.frame_every:
            return
        img = self.env.render()
        if img is None:
            return
        if self.frames_dir is not None:
            from PIL import Image

            f = self.frames_dir / f"ep{len(self.tracks) - 1:03d}_{self._step:05d}.png"
            Image.fromarray(np.asarray(img, dtype=np.uint8)).save(f)
            self.frame_files.append(f)
        if self.keep_frames and len(self.frames) < self.max_kept:
            self.frames.append(np.asarray(img, dtype=np.uint8).copy())

    def reset(self, **kwargs: Any) -> Any:
        out = self.env.reset(**kwargs)
        self.tracks.append([self._position()])
        self._step = 0
        self._frame()
        return out

    def step(self, action: Any) -> Any:
        out = self.env.step(action)
        self._step += 1
        self.tracks[-1].append(self._position())
        self._frame()
        return out


def write_video(frames: list[np.ndarray], path: str | Path, fps: float) -> Path:
    """Animated GIF (Pillow) or MP4 (imageio-ffmpeg) of ``frames`` at ``fps`` frames per second."""
    p = check_video_path(path)
    if not frames:
        raise UsageError(f"--video {p}: no frames were rendered")
    p.parent.mkdir(parents=True, exist_ok=True)
    if p.suffix.lower() == ".gif":
        from PIL import Image

        imgs = [Image.fromarray(f) for f in frames]
        # GIF frame durations are whole hundredths of a second
        imgs[0].save(p, save_all=True, append_images=imgs[1:], duration=max(int(1000.0 / fps), 20), loop=0)
    else:
        import imageio.v2 as imageio

        imageio.mimwrite(p, frames, fps=fps)
    return p


def _chart(ax: Any, env: Any) -> None:
    """The scenario's hard obstacles and goal (HarbourApproach), else nothing (open water)."""
    from matplotlib.patches import Polygon

    sc = getattr(getattr(env.unwrapped, "task", None), "scenario", None)
    if sc is None:
        return
    colours = {"land": "#d9c9a3", "breakwater": "#8c8c8c", "quay": "#a0522d"}
    for kind, _name, pts in sc.hard_obstacles():
        xy = [(e, n) for n, e in pts]  # plot east right, north up
        ax.add_patch(Polygon(xy, closed=True, facecolor=colours.get(kind, "grey"), edgecolor="k", lw=0.5))
    goal = getattr(sc, "goal", None)
    if goal is not None and getattr(goal, "points", None):
        xy = [(p[1], p[0]) for p in goal.points]
        ax.add_patch(Polygon(xy, closed=True, facecolor="#9be59b", edgecolor="g", alpha=0.6, label="goal"))


def plot_trajectories(
    tracks: list[list[tuple[float, float]]],
    env: Any,
    path: str | Path,
    title: str = "",
    labels: list[str] | None = None,
) -> Path:
    """PNG of the episodes' tracks (east right, north up, m) on the environment's chart."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 6))
    try:
        _chart(ax, env)
        for i, tr in enumerate(tracks):
            a = np.asarray(tr, dtype=float)
            label = labels[i] if labels is not None and i < len(labels) else None
            (line,) = ax.plot(a[:, 1], a[:, 0], lw=1.0, label=label)
            ax.plot(a[0, 1], a[0, 0], "o", ms=3, color=line.get_color())
        ax.set_aspect("equal", adjustable="datalim")
        ax.autoscale_view()
        ax.set_xlabel("east (m)")
        ax.set_ylabel("north (m)")
        ax.set_title(title, fontsize=9)
        ax.grid(True, lw=0.3)
        if labels and len(tracks) <= 12:
            ax.legend(fontsize=7, loc="best")
        p = Path(path)
        p.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(p, dpi=110, bbox_inches="tight")
    finally:
        plt.close(fig)
    return p


__all__ = ["VIDEO_SUFFIXES", "Recorder", "check_video_path", "plot_trajectories", "write_video"]
