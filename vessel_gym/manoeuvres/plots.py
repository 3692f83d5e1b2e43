"""Trajectory and time-history plots of manoeuvres (PNG, matplotlib; install the 'plot' extra)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np


def _plt():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the install
        raise RuntimeError("plots need matplotlib: pip install 'vessel-gym[plot]'") from exc
    return plt


def plot_report(report, out_dir: str | Path) -> list[Path]:
    """Write the IMO report's plots into ``out_dir``: turning tracks, zig-zag histories, stopping track."""
    plt = _plt()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    L = report.L_m
    files: list[Path] = []

    fig, ax = plt.subplots(figsize=(6.5, 6.5))
    for key, style in (("turning_starboard", "-"), ("turning_port", "--")):
        tc = report.trials.get(key)
        if tc is None:
            continue
        tr = tc.track.arrays()
        ax.plot(tr["y"] / L, tr["x"] / L, style, label=f"{tc.rudder_deg:+.0f} deg rudder")
        ax.plot([tc.transfer_m / L * math.copysign(1, tc.rudder_deg)], [tc.advance_m / L], "o", ms=4)
    ax.axhline(4.5, color="r", lw=0.8, ls=":", label="advance limit 4.5 L")
    for xlim in (5.0, -5.0):
        ax.axvline(xlim, color="m", lw=0.8, ls=":")
    ax.set_xlabel("transfer y / L (starboard +)")
    ax.set_ylabel("advance x / L")
    ax.set_aspect("equal")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(f"{report.ship}: turning circles at {report.V_kn:.1f} kn (tactical diameter limit 5 L)")
    files.append(out / "turning_circle.png")
    fig.tight_layout()
    fig.savefig(files[-1], dpi=110)
    plt.close(fig)

    for angle in (10, 20):
        fig, ax = plt.subplots(figsize=(8, 4))
        for side, style in (("starboard", "-"), ("port", "--")):
            z = report.trials.get(f"zigzag_{angle}_{side}")
            if z is None:
                continue
            tr = z.track.arrays()
            ax.plot(tr["t"], np.degrees(tr["psi"]), style, label=f"heading, first execute {side}")
            ax.plot(tr["t"], np.degrees(tr["delta"]), style, lw=0.8, label=f"rudder, first execute {side}")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("deg")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
        ax.set_title(f"{report.ship}: {angle}/{angle} zig-zag")
        files.append(out / f"zigzag_{angle}.png")
        fig.tight_layout()
        fig.savefig(files[-1], dpi=110)
        plt.close(fig)

    st = report.trials.get("stopping")
    if st is not None:
        tr = st.track.arrays()
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 4))
        a1.plot(tr["y"] / L, tr["x"] / L)
        a1.set_xlabel("y / L")
        a1.set_ylabel("x / L")
        a1.set_title(f"crash stop: track reach {st.track_reach_m / L:.2f} L")
        a1.grid(True, alpha=0.3)
        a2.plot(tr["t"], tr["u"] / 0.514444, label="surge (kn)")
        a2.plot(tr["t"], tr["rpm"], label="shaft rpm")
        a2.set_xlabel("time (s)")
        a2.grid(True, alpha=0.3)
        a2.legend(fontsize=8)
        files.append(out / "stopping.png")
        fig.tight_layout()
        fig.savefig(files[-1], dpi=110)
        plt.close(fig)
    return files


def plot_track(result, path: str | Path, title: str = "") -> Path:
    """Track (and heading/rudder history) of one manoeuvre result to ``path``."""
    plt = _plt()
    tr = result.track.arrays()
    L = result.L_m
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4.5))
    a1.plot(tr["y"] / L, tr["x"] / L)
    a1.set_aspect("equal")
    a1.set_xlabel("y / L (starboard +)")
    a1.set_ylabel("x / L")
    a1.grid(True, alpha=0.3)
    a2.plot(tr["t"], np.degrees(tr["psi"]), label="heading change (deg)")
    a2.plot(tr["t"], np.degrees(tr["delta"]), label="rudder (deg)")
    a2.set_xlabel("time (s)")
    a2.grid(True, alpha=0.3)
    a2.legend(fontsize=8)
    fig.suptitle(title or result.ship)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
