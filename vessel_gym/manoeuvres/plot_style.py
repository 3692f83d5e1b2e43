"""The drawing style shared by the manoeuvre plots: colours, the verdict box, IMO limit lines, axis ticks, and
matplotlib itself, loaded on first use (install the 'plot' extra)."""

from __future__ import annotations

from collections.abc import Sequence

from vessel_gym.manoeuvres.imo import Criterion

PASS_COLOUR = "#1a7f37"
FAIL_COLOUR = "#c62828"
LIMIT_COLOUR = "#c62828"
SIDE_STYLE = {"starboard": ("#1f5fa8", "-"), "port": ("#d9730d", "--")}
NO_LIMIT = "not run in the MSC.137(76) condition: no IMO limit drawn"


def _plt():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the install
        raise RuntimeError("plots need matplotlib: pip install 'vessel-gym[plot]'") from exc
    return plt


def _nice_ticks(ax, x: bool = True, y: bool = True) -> None:
    from matplotlib.ticker import MaxNLocator

    loc = dict(nbins=8, steps=[1, 2, 2.5, 5, 10])
    if x:
        ax.xaxis.set_major_locator(MaxNLocator(**loc))
    if y:
        ax.yaxis.set_major_locator(MaxNLocator(**loc))


def _verdict_lines(criteria: Sequence[Criterion]) -> list[tuple[str, bool]]:
    """One line per criterion (value against limit, and its verdict: PASS, FAIL, or IMPLAUSIBLE or DIVERGED
    for a trial that is never scored), then why each implausible trial is."""
    out = []
    for c in criteria:
        name = c.name.replace("zigzag_10_", "").replace("zigzag_20_", "").replace("_", " ")
        val = "n/a" if c.value is None else f"{c.value:.2f}"
        op = "vs" if c.value is None else ("<=" if c.value <= c.limit else ">")
        unit = " deg" if c.unit == "deg" else f" {c.unit}"
        out.append((f"{c.side} {name}: {val}{unit} {op} {c.limit:.2f}{unit}  {c.verdict.upper()}", c.passed))
    out += [
        (f"not scored: {why}", False)
        for why in dict.fromkeys(c.implausible for c in criteria if c.implausible)
    ]
    return out


def _verdict_box(ax, criteria: Sequence[Criterion], loc: str = "upper right", extra: str = "") -> None:
    """The verdict of each criterion as a coloured box on ``ax`` (green all pass, red any fail)."""
    if not criteria:
        ax.text(
            0.5, 0.02, NO_LIMIT, transform=ax.transAxes, ha="center", va="bottom", fontsize=7, color="0.35"
        )
        return
    lines = _verdict_lines(criteria)
    ok = all(p for _, p in lines)
    text = "\n".join(t for t, _ in lines) + (f"\n{extra}" if extra else "")
    x, ha = (0.98, "right") if "right" in loc else (0.02, "left")
    y, va = (0.98, "top") if "upper" in loc else (0.02, "bottom")
    ax.text(
        x,
        y,
        text,
        transform=ax.transAxes,
        ha=ha,
        va=va,
        fontsize=7.5,
        family="monospace",
        color="white",
        bbox=dict(boxstyle="round,pad=0.4", fc=PASS_COLOUR if ok else FAIL_COLOUR, ec="none", alpha=0.9),
        zorder=10,
    )


def _limit_hline(ax, y: float, label: str, lw: float, ls: str = "-.", fontsize: float = 8) -> None:
    """A criterion's limit drawn across the axes at ``y``, labelled above the line at x = 0."""
    ax.axhline(y, color=LIMIT_COLOUR, lw=lw, ls=ls)
    ax.text(0.0, y, label, color=LIMIT_COLOUR, fontsize=fontsize, ha="center", va="bottom")


def _limit_vline(ax, x: float, y: float, label: str, lw: float, va: str) -> None:
    """A criterion's limit drawn up the axes at ``x``, labelled along its left side from ``y``."""
    ax.axvline(x, color=LIMIT_COLOUR, lw=lw, ls="-.")
    ax.text(x, y, label, color=LIMIT_COLOUR, fontsize=8, rotation=90, ha="right", va=va)


def _side(rudder_deg: float) -> str:
    return "starboard" if rudder_deg > 0 else "port"
