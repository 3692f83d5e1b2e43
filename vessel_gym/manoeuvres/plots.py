"""Plots of manoeuvres with their IMO MSC.137(76) limits and verdicts drawn on them (matplotlib; install the
'plot' extra). Distances are in ship lengths L, times in seconds, angles in degrees.

Each ``figure_*`` function builds one figure from trial results and the criteria they are evidence for
(:mod:`vessel_gym.manoeuvres.imo`); an empty criteria list draws the trial without limits and says why. The
drawing style they share is :mod:`~vessel_gym.manoeuvres.plot_style`; the heel figure of a ship with roll,
:func:`~vessel_gym.manoeuvres.plots_roll.figure_roll`, lives in :mod:`~vessel_gym.manoeuvres.plots_roll`.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from vessel_gym.manoeuvres.imo import (
    STOPPING_LARGE_SHIP_LIMIT_L,
    STOPPING_LIMIT_L,
    Criterion,
    ImoReport,
    criteria_for,
)
from vessel_gym.manoeuvres.plot_style import (  # noqa: F401  (the style's names: their old home)
    FAIL_COLOUR,
    LIMIT_COLOUR,
    NO_LIMIT,
    PASS_COLOUR,
    SIDE_STYLE,
    _limit_hline,
    _limit_vline,
    _nice_ticks,
    _plt,
    _side,
    _verdict_box,
    _verdict_lines,
)
from vessel_gym.manoeuvres.plots_roll import ROLL_PLOTS, figure_roll
from vessel_gym.manoeuvres.trials import InitialTurning, PullOut, Stopping, TurningCircle, ZigZag
from vessel_gym.physics.units import KNOT_M_S

# the plot files of an IMO report, in report order (file stem -> title)
REPORT_PLOTS = {
    "turning_circle": "Turning circle",
    "initial_turning": "Initial turning",
    "zigzag_10": "10/10 zig-zag",
    "zigzag_20": "20/20 zig-zag",
    "stopping": "Full-astern stopping",
    "pull_out": "Pull-out",
}


def report_plot_names(ship) -> dict[str, str]:
    """The plot files of ``ship``'s IMO report (file stem -> title): :data:`REPORT_PLOTS`, and
    :data:`ROLL_PLOTS` for a ship with roll."""
    return {**REPORT_PLOTS, **(ROLL_PLOTS if ship is not None and ship.roll is not None else {})}


def _path_L(tr: dict, L: float) -> np.ndarray:
    d = np.hypot(np.diff(tr["x"]), np.diff(tr["y"]))
    return np.concatenate([[0.0], np.cumsum(d)]) / L


def figure_turning(trials: Sequence[TurningCircle], criteria: Sequence[Criterion], title: str):
    """Turning tracks (transfer right, advance up, in L) with advance and tactical-diameter marks; with
    criteria, the 4.5 L advance and 5 L tactical-diameter limits and the verdicts."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8.0, 6.0))
    ext, low = 1.0, -1.0
    for tc in trials:
        side = _side(tc.rudder_deg)
        colour, style = SIDE_STYLE[side]
        L, sg = tc.L_m, np.sign(tc.rudder_deg)
        tr = tc.track.arrays()
        ax.plot(
            tr["y"] / L, tr["x"] / L, style, color=colour, label=f"{side}, {tc.rudder_deg:+.0f} deg rudder"
        )
        a, t, td = tc.advance_m / L, sg * tc.transfer_m / L, sg * tc.tactical_diameter_m / L
        # advance: along the original course to the 90 deg point; tactical diameter: across at 180 deg
        ax.plot([t, t], [0.0, a], ":", color=colour, lw=1.0)
        ax.plot([t], [a], "o", color=colour, ms=5)
        ax.annotate(
            f"advance {a:.2f} L",
            (t, a / 2),
            xytext=(4 * sg, 0),
            textcoords="offset points",
            ha="left" if sg > 0 else "right",
            va="center",
            fontsize=8,
            color=colour,
        )
        p180 = tc.track.at_heading(np.pi)
        y180 = p180[1] / L if p180 else 0.0
        ax.annotate("", (td, y180), (0.0, y180), arrowprops=dict(arrowstyle="<->", color=colour, lw=1.0))
        ax.text(td / 2, y180, f"TD {abs(td):.2f} L", ha="center", va="bottom", fontsize=8, color=colour)
        ext = max(ext, float(np.max(np.abs(tr["y"]))) / L, float(np.max(np.abs(tr["x"]))) / L)
        low = min(low, float(np.floor(np.min(tr["x"]) / L - 0.5)))
    if criteria:
        lim_a = next((c.limit for c in criteria if c.name == "advance"), None)
        lim_td = next((c.limit for c in criteria if c.name == "tactical_diameter"), None)
        if lim_a is not None:
            _limit_hline(ax, lim_a, f"advance limit {lim_a:g} L", lw=1.0)
            ext = max(ext, lim_a)
        if lim_td is not None:
            ax.axvline(-lim_td, color=LIMIT_COLOUR, lw=1.0, ls="-.")  # the port turn's limit, unlabelled
            _limit_vline(ax, lim_td, -0.5, f"TD limit {lim_td:g} L", lw=1.0, va="bottom")
            ext = max(ext, lim_td)
    ext = float(np.ceil(ext + 0.5))
    ax.set_xlim(-ext, ext)
    ax.set_ylim(low, ext)
    ax.set_aspect("equal")
    _nice_ticks(ax)
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.axvline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("transfer y / L (starboard +)")
    ax.set_ylabel("advance x / L (original course up)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower left", fontsize=8)
    _verdict_box(ax, criteria, "upper right")
    ax.set_title(title)
    return fig


def figure_zigzag(trials: Sequence[ZigZag], criteria: Sequence[Criterion], title: str):
    """Heading and rudder against time, one panel per first-execute side, each overshoot annotated; with
    criteria, the heading each overshoot may reach (execute heading + limit) and the verdicts."""
    plt = _plt()
    n = max(len(trials), 1)
    fig, axes = plt.subplots(n, 1, figsize=(9.0, 3.6 * n), sharex=True, squeeze=False)
    ordinal = ("1st", "2nd", "3rd", "4th", "5th", "6th")
    for ax, z in zip(axes[:, 0], trials):
        side = _side(z.rudder_deg)
        colour, _ = SIDE_STYLE[side]
        tr = z.track.arrays()
        sg = float(np.sign(z.rudder_deg))
        ax.plot(tr["t"], np.degrees(tr["psi"]), "-", color=colour, label="heading change")
        ax.plot(tr["t"], np.degrees(tr["delta"]), "-", color="0.45", lw=0.9, label="rudder angle")
        h = z.heading_deg
        for yv in (h, -h):
            ax.axhline(yv, color="0.5", lw=0.6, ls=":")
        mine = [c for c in criteria if c.side == side]
        t_end = float(tr["t"][-1])
        for k, (os_deg, t_os) in enumerate(zip(z.overshoot_deg, z.overshoot_time_s)):
            # the k-th overshoot swings beyond the execute heading on the side of the (k+1)-th rudder order
            s_k = sg if k % 2 == 0 else -sg
            peak = s_k * (h + os_deg)
            ax.plot([t_os], [peak], "o", color=colour, ms=4)
            ax.annotate(
                f"{ordinal[k] if k < len(ordinal) else k + 1} overshoot {os_deg:.2f} deg",
                (t_os, peak),
                xytext=(0, 6 * s_k),
                textcoords="offset points",
                fontsize=8,
                ha="right" if t_os > 0.85 * t_end else "center",  # the last extreme ends the record
                va="bottom" if s_k > 0 else "top",
                color=colour,
            )
            if k < len(mine):
                # the heading this overshoot may reach, drawn from its execute to its extreme
                lim_heading = s_k * (h + mine[k].limit)
                t0 = z.execute_time_s[k + 1] if k + 1 < len(z.execute_time_s) else t_os
                t1 = t_os + 0.5 * (t_os - t0)
                ax.plot([t0, t1], [lim_heading, lim_heading], "-.", color=LIMIT_COLOUR, lw=1.1)
                ax.annotate(
                    f"{ordinal[k]} overshoot limit {mine[k].limit:.1f} deg",
                    (t0, lim_heading),
                    xytext=(0, 3 * s_k),
                    textcoords="offset points",
                    color=LIMIT_COLOUR,
                    fontsize=7.5,
                    ha="left",
                    va="bottom" if s_k > 0 else "top",
                )
        span = h + max([c.limit for c in mine] + list(z.overshoot_deg) + [abs(z.rudder_deg) - h, 0.0])
        ax.set_ylim(-1.35 * span, 1.35 * span)
        _nice_ticks(ax)
        ax.set_ylabel("deg (starboard +)")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="lower right", bbox_to_anchor=(1.0, 1.0), ncols=2, fontsize=7.5, frameon=False)
        ax.set_title(f"{abs(z.rudder_deg):g}/{h:g} zig-zag, first execute to {side}", fontsize=9, loc="left")
        # the second overshoot (the later, right-hand extreme) lies above on a port-first panel: the box
        # then goes to the upper left, which the heading trace leaves empty when it first swings to port
        _verdict_box(ax, mine, "upper right" if sg > 0 else "upper left")
    axes[-1, 0].set_xlabel("time (s)")
    fig.suptitle(title)
    return fig


def figure_initial_turning(trials: Sequence[InitialTurning], criteria: Sequence[Criterion], title: str):
    """Heading change against distance travelled (L) to the 10 deg mark, and heading and rudder against time;
    with criteria, the 2.5 L limit and the verdicts."""
    plt = _plt()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10.0, 4.2))
    for it in trials:
        side = _side(it.rudder_deg)
        colour, style = SIDE_STYLE[side]
        tr = it.track.arrays()
        s = _path_L(tr, it.L_m)
        psi = np.degrees(np.abs(tr["psi"]))
        d = it.distance_m / it.L_m
        a1.plot(s, psi, style, color=colour, label=f"{side}, {it.rudder_deg:+.0f} deg rudder")
        a1.plot([d], [10.0], "o", color=colour, ms=5)
        above = side == "port"
        a1.annotate(
            f"{side} {d:.2f} L",
            (d, 10.0),
            xytext=(-6 if above else 6, 8 if above else -8),
            textcoords="offset points",
            ha="right" if above else "left",
            va="bottom" if above else "top",
            fontsize=8,
            color=colour,
        )
        a2.plot(tr["t"], psi, style, color=colour, label=f"|heading change|, {side}")
        a2.plot(
            tr["t"],
            np.degrees(np.abs(tr["delta"])),
            style,
            color="0.45",
            lw=0.9,
            label=f"|rudder angle|, {side}",
        )
    a1.axhline(10.0, color="0.5", lw=0.7, ls=":")
    xmax = max([it.distance_m / it.L_m for it in trials] + [1.0])
    lim = next((c.limit for c in criteria), None)
    if lim is not None:
        _limit_vline(a1, lim, 13.5, f"limit {lim:g} L ", lw=1.1, va="top")
        xmax = max(xmax, lim)
    a1.set_xlim(0.0, 1.15 * xmax)
    a1.set_ylim(0.0, 14.0)
    a1.set_xlabel("distance travelled / L")
    a1.set_ylabel("heading change (deg)")
    a1.legend(loc="upper left", fontsize=8)
    _verdict_box(a1, criteria, "lower right")
    a2.axhline(10.0, color="0.5", lw=0.7, ls=":")
    a2.set_ylim(0.0, 14.0)
    a2.set_xlabel("time (s)")
    a2.set_ylabel("deg")
    a2.legend(loc="upper left", fontsize=7, ncols=2)
    for ax in (a1, a2):
        _nice_ticks(ax)
        ax.grid(True, alpha=0.3)
    fig.suptitle(title)
    return fig


def figure_stopping(st: Stopping, criteria: Sequence[Criterion], title: str):
    """The stopping track (head reach up, lateral deviation across, in L) with the 15 L limit and the 20 L an
    Administration may accept, and speed and shaft rpm against time."""
    plt = _plt()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10.0, 5.0), gridspec_kw=dict(width_ratios=[1, 2]))
    L = st.L_m
    tr = st.track.arrays()
    x, y = tr["x"] / L, tr["y"] / L
    a1.plot(y, x, "-", color=SIDE_STYLE["starboard"][0])
    hr, lat, reach = st.head_reach_m / L, st.lateral_deviation_m / L, st.track_reach_m / L
    a1.plot([lat], [hr], "s", color="k", ms=5)
    a1.annotate(
        f"stopped\nhead reach {hr:.2f} L\ntrack reach {reach:.2f} L\nlateral {lat:+.2f} L",
        (lat, hr),
        xytext=(-6, -6) if lat > 0 else (6, -6),  # on the side away from the drift, inside the axes
        textcoords="offset points",
        fontsize=7.5,
        ha="right" if lat > 0 else "left",
        va="top",
    )
    top = max(hr, reach) + 1.0
    if criteria:
        _limit_hline(a1, STOPPING_LIMIT_L, f"limit {STOPPING_LIMIT_L:g} L", lw=1.1)
        _limit_hline(
            a1, STOPPING_LARGE_SHIP_LIMIT_L, f"{STOPPING_LARGE_SHIP_LIMIT_L:g} L (large ships)", 0.8, ":", 7
        )
        top = max(top, STOPPING_LARGE_SHIP_LIMIT_L + 1.5)
    # a straight stop has almost no lateral extent: keep the across axis at least +-1 L wide so that
    # numerical noise is not magnified into a curve
    half = max(1.0, 1.2 * float(np.max(np.abs(y))))
    a1.set_xlim(-half, half)
    a1.set_ylim(-0.5, top)
    _nice_ticks(a1)
    from matplotlib.ticker import MaxNLocator

    a1.xaxis.set_major_locator(MaxNLocator(nbins=4, steps=[1, 2, 2.5, 5, 10], symmetric=True))
    a1.set_xlabel("lateral y / L (starboard +)")
    a1.set_ylabel("head reach x / L (original course up)")
    a1.grid(True, alpha=0.3)
    a1.set_title("track", fontsize=9)

    speed_kn = tr["u"] / KNOT_M_S
    a2.plot(tr["t"], speed_kn, "-", color=SIDE_STYLE["starboard"][0], label="surge speed (kn)")
    a2.set_xlabel("time (s)")
    a2.set_ylabel("surge speed (kn)", color=SIDE_STYLE["starboard"][0])
    a2.axhline(0.0, color="0.6", lw=0.6)
    a2.axvline(st.time_s, color="k", lw=0.7, ls=":")
    a2.text(
        st.time_s,
        float(np.max(speed_kn)) * 0.5,
        f" stopped at {st.time_s:.0f} s",
        fontsize=8,
        rotation=90,
        ha="right",
        va="center",
    )
    a3 = a2.twinx()
    a3.plot(tr["t"], tr["rpm"], "-", color=SIDE_STYLE["port"][0], label="shaft speed (rpm)")
    a3.set_ylabel("shaft speed (rpm, ahead +)", color=SIDE_STYLE["port"][0])
    a3.axhline(0.0, color=SIDE_STYLE["port"][0], lw=0.5, ls=":")
    _nice_ticks(a2)
    _nice_ticks(a3, x=False)
    a2.grid(True, alpha=0.3)
    h1, l1 = a2.get_legend_handles_labels()
    h2, l2 = a3.get_legend_handles_labels()
    a2.legend(h1 + h2, l1 + l2, loc="upper center", bbox_to_anchor=(0.5, 0.88), fontsize=8)
    a2.set_title("speed and shaft speed", fontsize=9)
    _verdict_box(a2, criteria, "upper right")
    fig.suptitle(title)
    return fig


def figure_pull_out(po: PullOut, title: str):
    """Rate of turn against time after the starboard and the port turn; the verdict on course stability
    (the two residual rates converge) - the pull-out test has no IMO limit."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(9.0, 4.2))
    for track, side, steady, resid in zip(
        po.tracks, ("starboard", "port"), po.steady_rate_deg_s, po.residual_rate_deg_s
    ):
        colour, style = SIDE_STYLE[side]
        tr = track.arrays()
        ax.plot(
            tr["t"],
            np.degrees(tr["r"]),
            style,
            color=colour,
            label=f"after {side} turn: steady {steady:+.3f}, residual {resid:+.3f} deg/s",
        )
        ordered = np.nonzero(tr["delta_c"] != 0.0)[0]
        if ordered.size and ordered[-1] + 1 < tr["t"].size:
            ax.axvline(tr["t"][ordered[-1] + 1], color="0.5", lw=0.7, ls=":")
    ax.text(
        0.5,
        0.98,
        "rudder to midships at the dotted line",
        transform=ax.transAxes,
        ha="center",
        va="top",
        fontsize=8,
        color="0.35",
    )
    ax.axhline(0.0, color="0.6", lw=0.6)
    ok = po.stable
    verdict = (
        "course stable: the residual rates converge"
        if ok
        else "course unstable: the residual rates stay apart"
    )
    ax.text(
        0.98,
        0.9,
        verdict + "\n(Burcher 1972; no IMO limit)",
        transform=ax.transAxes,
        ha="right",
        va="top",
        fontsize=8,
        color="white",
        bbox=dict(boxstyle="round,pad=0.4", fc=PASS_COLOUR if ok else FAIL_COLOUR, ec="none", alpha=0.9),
    )
    _nice_ticks(ax)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("rate of turn (deg/s, starboard +)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(title)
    return fig


def report_figures(report: ImoReport):
    """``(stem, figure)`` for each of the report's plots whose trials ran (names of
    :func:`report_plot_names`)."""
    t = report.trials
    head = f"{report.ship} at {report.V_kn:.1f} kn (L = {report.L_m:g} m, L/V = {report.L_over_V_s:.1f} s)"
    sides = ("starboard", "port")
    tcs = [t[f"turning_{s}"] for s in sides if f"turning_{s}" in t]
    if tcs:
        crit = report.criteria_named("advance") + report.criteria_named("tactical_diameter")
        yield "turning_circle", figure_turning(tcs, crit, f"Turning circles: {head}")
    its = [t[f"initial_turning_{s}"] for s in sides if f"initial_turning_{s}" in t]
    if its:
        yield (
            "initial_turning",
            figure_initial_turning(
                its, report.criteria_named("initial_turning"), f"Initial turning, 10 deg rudder: {head}"
            ),
        )
    for angle in (10, 20):
        zs = [t[f"zigzag_{angle}_{s}"] for s in sides if f"zigzag_{angle}_{s}" in t]
        if zs:
            crit = [c for c in report.criteria if c.name.startswith(f"zigzag_{angle}_")]
            yield f"zigzag_{angle}", figure_zigzag(zs, crit, f"{angle}/{angle} zig-zag: {head}")
    if "stopping" in t:
        yield (
            "stopping",
            figure_stopping(
                t["stopping"], report.criteria_named("stopping_track_reach"), f"Full-astern stopping: {head}"
            ),
        )
    if "pull_out" in t:
        yield (
            "pull_out",
            figure_pull_out(t["pull_out"], f"Pull-out, {t['pull_out'].rudder_deg:g} deg: {head}"),
        )
    if report.spec is not None and report.spec.roll is not None:
        names = {"turning": "35 deg turning test", "zigzag_10": "10/10 zig-zag", "zigzag_20": "20/20 zig-zag"}
        panels = [(nm, [t[f"{k}_{s}"] for s in sides if f"{k}_{s}" in t]) for k, nm in names.items()]
        panels = [p for p in panels if p[1]]
        if panels:
            crit = report.criteria_named("heel_in_turn")
            yield "roll", figure_roll(panels, crit, f"Heel: {head}")


def figure_for(result, title: str, ship=None):
    """One figure for a single trial result; the IMO limits are drawn when the trial was run in the
    MSC.137(76) condition for ``ship`` (see :func:`vessel_gym.manoeuvres.imo.criteria_for`)."""
    crit = (
        criteria_for(result, ship if ship is not None else result.ship)
        if not isinstance(result, PullOut)
        else []
    )
    if isinstance(result, TurningCircle):
        return figure_turning([result], crit, title)
    if isinstance(result, ZigZag):
        return figure_zigzag([result], crit, title)
    if isinstance(result, InitialTurning):
        return figure_initial_turning([result], crit, title)
    if isinstance(result, Stopping):
        return figure_stopping(result, crit, title)
    if isinstance(result, PullOut):
        return figure_pull_out(result, title)
    raise TypeError(f"no plot for {type(result).__name__}")


def figure_bytes(fig, fmt: str = "png", dpi: int = 110) -> bytes:
    """Render and close ``fig``; the file's bytes in ``fmt`` (png, svg or pdf)."""
    plt = _plt()
    buf = io.BytesIO()
    try:
        fig.tight_layout()
        fig.savefig(buf, format=fmt, dpi=dpi)
    finally:
        plt.close(fig)
    return buf.getvalue()


def report_pngs(report: ImoReport) -> dict[str, bytes]:
    """Each of the report's plots rendered once as PNG bytes, by file stem (see :data:`REPORT_PLOTS`)."""
    return {stem: figure_bytes(fig) for stem, fig in report_figures(report)}


def plot_report(
    report: ImoReport,
    out: str | Path,
    force: bool = False,
    pdf: bool | None = None,
    pngs: dict[str, bytes] | None = None,
) -> list[Path]:
    """Write the report's plots: PNGs named after :data:`REPORT_PLOTS` into the directory ``out``, or one
    multipage PDF file ``out`` (``pdf``; default: when ``out`` ends in ``.pdf``). Existing files are not
    replaced unless ``force``. ``pngs``: the plots already rendered by :func:`report_pngs`."""
    from vessel_gym.outputs import write_new

    out = Path(out)
    if pdf if pdf is not None else out.suffix.lower() == ".pdf":
        return [write_new(out, report_pdf_bytes(report), force)]
    pngs = report_pngs(report) if pngs is None else pngs
    return [write_new(out / f"{stem}.png", data, force) for stem, data in pngs.items()]


def report_pdf_bytes(report: ImoReport, summary: str = "") -> bytes:
    """All of the report's plots as one multipage PDF (matplotlib's PdfPages), preceded by an A4 page with
    the ``summary`` text when one is given."""
    from matplotlib.backends.backend_pdf import PdfPages

    plt = _plt()
    buf = io.BytesIO()
    with PdfPages(buf) as pdf:
        if summary:
            fig = plt.figure(figsize=(8.27, 11.69))  # A4 portrait
            fig.text(0.06, 0.96, summary, family="monospace", fontsize=7.2, va="top")
            pdf.savefig(fig)
            plt.close(fig)
        for _stem, fig in report_figures(report):
            fig.tight_layout()
            pdf.savefig(fig)
            plt.close(fig)
    return buf.getvalue()


def plot_track(result, path: str | Path, title: str = "", force: bool = False, ship=None) -> Path:
    """The plot of one trial result (:func:`figure_for`; ``ship`` decides whether IMO limits apply) to
    ``path`` (format from its suffix: png, svg, pdf); an existing file is not replaced unless ``force``."""
    from vessel_gym.outputs import write_new

    path = Path(path)
    fmt = path.suffix.lower().lstrip(".") or "png"
    return write_new(path, figure_bytes(figure_for(result, title or result.ship, ship), fmt), force)
