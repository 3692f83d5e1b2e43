"""The heel figure of a ship with roll: heel against time in the turning circles and zig-zags, with the heel
criterion's limit and verdict drawn on the turning panel (matplotlib; install the 'plot' extra)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from vessel_gym.manoeuvres.imo import Criterion
from vessel_gym.manoeuvres.plot_style import SIDE_STYLE, _limit_hline, _nice_ticks, _plt, _side, _verdict_box
from vessel_gym.manoeuvres.trials import TurningCircle

# the plot a ship with roll adds to its report (file stem -> title)
ROLL_PLOTS = {"roll": "Heel"}


def figure_roll(panels: Sequence[tuple[str, Sequence]], criteria: Sequence[Criterion], title: str):
    """Heel against time, one panel per ``(name, trials)`` (turning circles, zig-zags), both sides; with
    heel criteria (``heel_in_turn``), the limit drawn at +-limit on the turning panel and the verdicts."""
    plt = _plt()
    fig, axes = plt.subplots(len(panels), 1, figsize=(9.0, 2.8 * len(panels)), squeeze=False)
    for ax, (name, trials) in zip(axes[:, 0], panels):
        for tr in trials:
            side = _side(tr.rudder_deg)
            colour, ls = SIDE_STYLE[side]
            a = tr.track.arrays()
            ax.plot(a["t"], np.degrees(a["phi"]), ls, color=colour, label=f"to {side}")
        if isinstance(trials[0], TurningCircle) and criteria:
            lim = criteria[0].limit
            for y in (lim, -lim):
                _limit_hline(ax, y, f"heel limit {lim:g} deg", 1.1)
            _verdict_box(ax, criteria, "lower right")
        ax.axhline(0.0, color="0.5", lw=0.6, ls=":")
        _nice_ticks(ax)
        ax.set_ylabel("heel (deg, stbd down +)")
        ax.set_xlabel("time (s)")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right", fontsize=7.5, frameon=False)
        ax.set_title(name, fontsize=9, loc="left")
    fig.suptitle(title)
    return fig
