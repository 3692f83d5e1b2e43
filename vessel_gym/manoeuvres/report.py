"""The IMO MSC.137(76) report as one self-contained HTML file: the ship's particulars and source, the criteria
table with values, limits and verdicts, and every manoeuvre plot embedded as a base64 PNG (no external
resources, so the file can be mailed or printed as it is)."""

from __future__ import annotations

import base64
import datetime as _dt
import html
import re
import textwrap
from pathlib import Path

from vessel_gym.manoeuvres.imo import ImoReport, cfd_uncertainty_line
from vessel_gym.manoeuvres.plots import report_plot_names, report_pngs

_CSS = """
body { font-family: "DejaVu Sans", Helvetica, Arial, sans-serif; max-width: 60em; margin: 2em auto;
       color: #222; line-height: 1.4; padding: 0 1em; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; }
h2 { font-size: 1.2em; border-bottom: 1px solid #ccc; padding-bottom: 0.2em; margin-top: 1.6em; }
table { border-collapse: collapse; margin: 0.6em 0; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
th { background: #f0f0f0; }
.PASS { color: #fff; background: #1a7f37; font-weight: bold; text-align: center; }
.FAIL { color: #fff; background: #c62828; font-weight: bold; text-align: center; }
.DIVERGED { color: #fff; background: #6a1b9a; font-weight: bold; text-align: center; }
.IMPLAUSIBLE { color: #fff; background: #e65100; font-weight: bold; text-align: center; }
.overall { font-size: 1.1em; padding: 0.3em 0.8em; display: inline-block; }
.note { color: #555; font-size: 0.9em; }
figure { margin: 1em 0; page-break-inside: avoid; }
figure img { max-width: 100%; height: auto; border: 1px solid #ddd; }
figcaption { font-size: 0.9em; color: #444; }
pre { white-space: pre-wrap; font-size: 0.85em; background: #f7f7f7; padding: 0.6em; }
"""

_CRITERION_TEXT = {
    "advance": "Advance, 35 deg turning test (§5.3.1)",
    "tactical_diameter": "Tactical diameter, 35 deg turning test (§5.3.1)",
    "initial_turning": "Distance to 10 deg heading change, 10 deg rudder (§5.3.2)",
    "zigzag_10_first_overshoot": "10/10 zig-zag, first overshoot (§5.3.3.1)",
    "zigzag_10_second_overshoot": "10/10 zig-zag, second overshoot (§5.3.3.2)",
    "zigzag_20_first_overshoot": "20/20 zig-zag, first overshoot (§5.3.3.3)",
    "stopping_track_reach": "Track reach, full-astern stopping test (§5.3.4)",
    "heel_in_turn": "Largest heel, 35 deg turning test (2008 IS Code Part A §3.1.3 guidance)",
}

_CAPTIONS = {
    "turning_circle": "Turning tracks to both sides with the advance (at 90 deg heading change) and tactical "
    "diameter (at 180 deg) marked; dash-dotted: the 4.5 L advance and 5 L tactical-diameter limits.",
    "initial_turning": "Heading change against distance travelled with 10 deg rudder; the criterion is the "
    "distance at 10 deg heading change (limit 2.5 L).",
    "zigzag_10": "Heading and rudder angle of the 10/10 zig-zag to both sides; dash-dotted: the heading each "
    "overshoot may reach (execute heading + limit; the limits depend on L/V, §5.3.3).",
    "zigzag_20": "Heading and rudder angle of the 20/20 zig-zag to both sides; dash-dotted: the heading the "
    "first overshoot may reach (limit 25 deg).",
    "stopping": "Full-astern stopping: track (head reach along the original course) with the 15 L limit and "
    "the 20 L an Administration may accept for ships of large displacement; surge speed and shaft speed.",
    "pull_out": "Pull-out test from both sides (MSC/Circ.1053 §3.4.4; Burcher 1972): rate of turn after the "
    "rudder is returned to midships. No IMO limit; converging rates indicate course stability.",
    "roll": "Heel (positive: starboard side down) against time in the 35 deg turning test and the zig-zags, "
    "both sides; dash-dotted, when a heel limit was asked for: that limit (2008 IS Code Part A §3.1.3 "
    "guidance, 10 deg for passenger ships).",
}


#: a page of the project's documentation named by its path in the repository (ship files' notes do that)
_DOC_PATH = re.compile(r"\bdocs/([\w-]+)\.md\b")


def readable_refs(text: str) -> str:
    """``docs/physics.md`` -> ``the vessel-gym documentation, page "physics"``: the report's reader has the
    report, not the repository, and finds a page of the documentation by its name."""
    return _DOC_PATH.sub(lambda m: f'the vessel-gym documentation, page "{m.group(1)}"', text)


def _e(x) -> str:
    return html.escape(readable_refs(str(x)))


def _particulars_rows(report: ImoReport) -> list[tuple[str, str]]:
    rows = [("ship", report.ship), ("length between perpendiculars L", f"{report.L_m:.2f} m")]
    s = report.spec
    if s is not None:
        p = s.particulars
        rows += [("beam B", f"{p.B_m:.2f} m"), ("draught T", f"{p.T_m:.2f} m")]
        if p.displacement_m3 is not None:
            rows.append(("displacement volume", f"{p.displacement_m3:,.1f} m³"))
        rows.append(("mass", f"{s.mass_kg / 1000.0:,.1f} t"))
        if p.C_b is not None:
            rows.append(("block coefficient C_B", f"{p.C_b:.3f}"))
        rows.append(("centre of gravity x_G (forward of midship)", f"{p.x_G_m:.2f} m"))
        rows.append(("hull model", s.hull.model))
        rows.append(
            (
                "rudder: maximum angle, rate",
                f"{s.steering_gear.max_angle_deg:g} deg, {s.steering_gear.max_rate_deg_s:g} deg/s",
            )
        )
        if s.engine is not None:
            rows.append(("engine MCR", f"{s.engine.rated_power_kW:,.0f} kW at {s.engine.rated_rpm:g} rpm"))
        if s.path:
            from vessel_gym.physics.shipfile import SHIP_DIR

            builtin = Path(s.path).resolve().parent == SHIP_DIR.resolve()
            rows.append(("ship file", f"built-in {Path(s.path).name}" if builtin else s.path))
    rows += [
        ("test speed V", f"{report.V_kn:.2f} kn"),
        ("L/V", f"{report.L_over_V_s:.2f} s"),
    ]
    return rows


def report_html(report: ImoReport, pngs: dict[str, bytes] | None = None) -> str:
    """The report as one self-contained HTML document (plots embedded as base64 PNG; ``pngs``: the plots
    already rendered by :func:`~vessel_gym.manoeuvres.plots.report_pngs`)."""
    s = report.spec
    verdict = report.verdict
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>IMO MSC.137(76) manoeuvring report - {_e(report.ship)}</title>",
        f"<style>{_CSS}</style></head><body>",
        f"<h1>IMO manoeuvring standards, Res. MSC.137(76): {_e(report.ship)}</h1>",
        f'<p>Overall: <span class="overall {verdict}">{verdict}</span> '
        f'<span class="note">({sum(c.passed for c in report.criteria)} of {len(report.criteria)} criteria '
        "met; simulated trials in deep, calm water at the test speed, both sides)</span></p>",
    ]
    cfd = cfd_uncertainty_line(report.spec)
    if cfd:
        parts.append(f'<p class="note">{_e(cfd)}</p>')
    if report.implausible_reasons:
        parts.append(
            "<h2>Not a possible ship</h2><p>No criterion is scored in a trial that no ship could run:</p><ul>"
        )
        parts += [f"<li>{_e(why)}</li>" for why in report.implausible_reasons]
        parts.append("</ul>")
    parts.append("<h2>Ship particulars</h2><table>")
    parts += [f"<tr><th>{_e(k)}</th><td>{_e(v)}</td></tr>" for k, v in _particulars_rows(report)]
    parts.append("</table>")
    if s is not None:
        parts.append("<h2>Source of the parameter set</h2>")
        parts.append(f"<p>{_e(s.source.citation)}</p>")
        if s.source.sign_convention:
            parts.append(f'<p class="note">Sign convention: {_e(s.source.sign_convention)}</p>')
        if s.source.notes.strip():
            parts.append(f"<h3>Notes on the parameter set</h3><pre>{_e(s.source.notes.strip())}</pre>")
    parts += [
        "<h2>Criteria</h2>",
        "<table><tr><th>criterion</th><th>side</th><th>value</th><th>limit</th><th>unit</th>"
        "<th>result</th><th>note</th></tr>",
    ]
    for c in report.criteria:
        val = "n/a" if c.value is None else f"{c.value:.2f}"
        res = c.verdict.upper()
        parts.append(
            f"<tr><td>{_e(_CRITERION_TEXT.get(c.name, c.name))}</td><td>{_e(c.side)}</td>"
            f'<td class="num">{val}</td><td class="num">&le; {c.limit:.2f}</td><td>{_e(c.unit)}</td>'
            f'<td class="{res}">{res}</td><td class="note">{_e(c.note or c.implausible)}</td></tr>'
        )
    parts.append("</table>")
    parts.append(
        '<p class="note">Limits (MSC.137(76) §5.3): advance 4.5 L and tactical diameter 5 L; initial turning '
        "2.5 L; 10/10 zig-zag first overshoot 10 deg for L/V &lt; 10 s, 20 deg for L/V &ge; 30 s, "
        "(5 + L/V / 2) deg between; second overshoot 25 / 40 / (17.5 + 0.75 L/V) deg on the same ranges; "
        "20/20 zig-zag first overshoot 25 deg; stopping track reach 15 L (an Administration may accept up "
        f"to 20 L for ships of large displacement). With L/V = {report.L_over_V_s:.2f} s here.</p>"
    )
    heel = report.criteria_named("heel_in_turn")
    if heel:
        parts.append(
            '<p class="note">Heel in a turn (2008 IS Code, Res. MSC.267(85), Part A §3.1.3: for passenger ships '
            "the angle of heel on account of turning should not exceed 10 deg; the Code estimates it from a "
            "steady-turn heeling moment): here the largest simulated heel of the 35 deg turning test, held "
            f"to the {heel[0].limit:g} deg asked for.</p>"
        )
    parts.append("<h2>Manoeuvres</h2>")
    pngs = report_pngs(report) if pngs is None else pngs
    plot_names = report_plot_names(s)
    for stem, png in pngs.items():
        b64 = base64.b64encode(png).decode("ascii")
        parts.append(
            f'<figure><img alt="{_e(plot_names[stem])}" src="data:image/png;base64,{b64}">'
            f"<figcaption><b>{_e(plot_names[stem])}.</b> {_e(_CAPTIONS[stem])}</figcaption></figure>"
        )
    missing = [title for k, title in plot_names.items() if k not in pngs]
    if missing:
        parts.append(
            f'<p class="note">Not completed (see the notes in the criteria table): '
            f"{_e(', '.join(missing))}.</p>"
        )
    stamp = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    parts.append(f'<p class="note">Written by vessel-gym on {stamp}.</p></body></html>')
    return "\n".join(parts)


def summary_text(report: ImoReport, width: int = 86) -> str:
    """Particulars, source and the criteria table as plain text (the first page of the PDF report)."""
    lines = [f"{k:<44}{v}" for k, v in _particulars_rows(report)]
    if report.spec is not None:
        lines += ["", "source:"] + textwrap.wrap(
            report.spec.source.citation, width, initial_indent="  ", subsequent_indent="  "
        )
    cfd = cfd_uncertainty_line(report.spec)
    if cfd:
        lines += [""] + textwrap.wrap(cfd, width)
    lines += ["", report.table()]
    return "\n".join(lines)


def report_name(ship_name: str, suffix: str = ".html") -> str:
    """Default file name of a ship's report: ``imo_<ship>.html`` (see :func:`vessel_gym.outputs.safe_name`)."""
    from vessel_gym.outputs import safe_name

    return f"imo_{safe_name(ship_name)}{suffix}"


def write_report(
    report: ImoReport, path: str | Path, force: bool = False, pngs: dict[str, bytes] | None = None
) -> Path:
    """Write the HTML report (or, for a ``.pdf`` path, the summary page and plots as one PDF) to ``path``;
    an existing file is not replaced unless ``force``. ``pngs`` as for :func:`report_html`."""
    from vessel_gym.manoeuvres.plots import report_pdf_bytes
    from vessel_gym.outputs import write_new

    path = Path(path)
    if path.suffix.lower() == ".pdf":
        return write_new(path, report_pdf_bytes(report, summary_text(report)), force)
    return write_new(path, report_html(report, pngs).encode("utf-8"), force)
