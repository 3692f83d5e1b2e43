"""The class debrief: one self-contained HTML file with the chart and every track (SVG), a row per student,
and each student's own track and figures.

Each student's run is scored as ``vessel-gym play`` scores one (:func:`vessel_gym.ui.play.score`, rows of
:class:`vessel_gym.ui.play.Debrief`), with one change a shared harbour needs: the clearance that counts is the
least of the clearance to land and quays and the closest approach to another ship's hull, and a contact with
another ship is a contact. Added rows: the closest approach to another ship, what the contact was with, the
rudder effort (sum of the changes of rudder order), the telegraph orders given and the mean rudder angle.
"""

from __future__ import annotations

import html
import math
import time
from typing import Any

from vessel_gym.classroom.harbour import ClassHarbour, ShipRecord
from vessel_gym.ui.play import Debrief, score

#: track colours, one per ship (16 distinct hues)
COLOURS = (
    "#e6194b", "#3cb44b", "#4363d8", "#f58231", "#911eb4", "#42d4f4", "#f032e6", "#9a6324",
    "#469990", "#800000", "#808000", "#000075", "#e6beff", "#aaffc3", "#ffd8b1", "#a9a9a9",
)  # fmt: skip


def student_debrief(h: ClassHarbour, k: int) -> Debrief:
    """Ship ``k``'s run as a play debrief (module doc: the clearance includes other ships)."""
    rec: ShipRecord = h.records[k]
    info = rec.info
    outcome = rec.outcome if rec.outcome != "running" else "time_limit"
    clearance = min(float(info.get("min_clearance_m", math.inf)), rec.min_ship_distance_m)
    time_s = float(info.get("time_s", 0.0))
    final_distance = float(info.get("distance_to_goal_m", rec.start_distance_m))
    return Debrief(
        scenario=h.scenario.name,
        outcome=rec.outcome,
        time_s=time_s,
        steps=int(h.steps[k]),
        min_clearance_m=clearance,
        contacts=rec.contacts,
        path_m=float(info.get("path_m", 0.0)),
        start_distance_m=rec.start_distance_m,
        final_distance_m=final_distance,
        final_speed_m_s=float(info.get("speed_over_ground_m_s", math.nan)),
        final_heading_error_deg=float(info.get("heading_error_deg", math.nan)),
        score=score(outcome, time_s, clearance, rec.start_distance_m, final_distance, h.L, h.task.U_T),
        track=list(rec.track),
    )


def extra_rows(h: ClassHarbour, k: int) -> list[tuple[str, str]]:
    rec = h.records[k]
    mean_rudder = rec.rudder_abs_sum_deg / rec.samples if rec.samples else 0.0
    closest = "-" if not math.isfinite(rec.min_ship_distance_m) else f"{rec.min_ship_distance_m:.2f} m"
    return [
        ("closest approach to a ship", closest),
        ("contact with", rec.contact_with or "-"),
        ("rudder effort", f"{rec.rudder_effort_deg:.0f} deg of orders, mean |rudder| {mean_rudder:.1f} deg"),
        ("engine orders", f"{rec.engine_changes}"),
    ]


def chart_svg(h: ClassHarbour, ships: list[int], width_px: int = 640) -> str:
    """The harbour (land and quays grey, shoals tan, goal green, start dashed) and the tracks of ``ships``,
    north up, as an SVG element (1 user unit = 1 m)."""
    n0, n1, e0, e1 = h.scenario.bounds_m
    w, hgt = e1 - e0, n1 - n0
    height_px = int(width_px * hgt / max(w, 1e-9))

    def pts(points: Any) -> str:
        return " ".join(f"{e:.2f},{-n:.2f}" for n, e in points)

    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width_px}" height="{height_px}" '
        f'viewBox="{e0} {-n1} {w} {hgt}" style="background:#cfe3f3">'
    ]
    sc = h.scenario
    for _n, p in sc.shoals(h.T):
        out.append(f'<polygon points="{pts(p)}" fill="#e8d8a8" stroke="none"/>')
    for _kind, _name, p in sc.hard_obstacles():
        out.append(f'<polygon points="{pts(p)}" fill="#9a9a8a" stroke="#555" stroke-width="0.3"/>')
    out.append(
        f'<polygon points="{pts([(p[0], p[1]) for p in sc.goal.points])}" fill="none" stroke="#1a8a1a" '
        'stroke-width="0.6"/>'
    )
    out.append(
        f'<polygon points="{pts([(p[0], p[1]) for p in sc.start.points])}" fill="none" stroke="#555" '
        'stroke-width="0.4" stroke-dasharray="2,2"/>'
    )
    for k in ships:
        track = h.records[k].track
        if not track:
            continue
        c = COLOURS[k % len(COLOURS)]
        out.append(f'<polyline points="{pts(track)}" fill="none" stroke="{c}" stroke-width="0.6"/>')
        (sn, se), (en, ee) = track[0], track[-1]
        out.append(f'<circle cx="{se:.2f}" cy="{-sn:.2f}" r="1.2" fill="{c}"/>')
        out.append(f'<rect x="{ee - 1.2:.2f}" y="{-en - 1.2:.2f}" width="2.4" height="2.4" fill="{c}"/>')
        label = html.escape(h.names[k])
        out.append(f'<text x="{ee + 2:.2f}" y="{-en:.2f}" font-size="4" fill="{c}">{label}</text>')
    out.append("</svg>")
    return "".join(out)


def class_debrief_html(h: ClassHarbour) -> str:
    """The whole class's debrief as one HTML page (module doc)."""
    e = html.escape
    stamp = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    debriefs = [student_debrief(h, k) for k in range(h.n)]
    rows = []
    for k, d in enumerate(debriefs):
        closest = h.records[k].min_ship_distance_m
        rows.append(
            f'<tr><td style="color:{COLOURS[k % len(COLOURS)]}">&#9632;</td><td>{e(h.names[k])}</td>'
            f"<td>{e(d.outcome)}</td><td>{d.time_s:.0f}</td><td>{d.min_clearance_m:.1f}</td>"
            f"<td>{'-' if not math.isfinite(closest) else f'{closest:.1f}'}</td><td>{d.contacts}</td>"
            f"<td>{d.final_speed_m_s:.2f}</td><td>{h.records[k].rudder_effort_deg:.0f}</td>"
            f"<td>{h.records[k].engine_changes}</td><td><b>{d.score:.0f}</b></td></tr>"
        )
    scores = [d.score for d in debriefs]
    parts = [
        "<!doctype html><html><head><meta charset='utf-8'>",
        f"<title>Class debrief: {e(h.scenario.name)}</title>",
        "<style>body{font-family:sans-serif;margin:1.5em}table{border-collapse:collapse}"
        "td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}th{background:#eee}"
        ".student{display:inline-block;vertical-align:top;margin:1em;border:1px solid #ccc;padding:.5em}</style>",
        "</head><body>",
        f"<h1>Class debrief: {e(h.scenario.name)}</h1>",
        f"<p>{h.n} ships, class time {h.t_s:.0f} s, written {stamp}. Class mean score "
        f"{sum(scores) / len(scores):.0f} / 100.</p>",
        chart_svg(h, list(range(h.n)), 800),
        "<h2>Students</h2><table><tr><th></th><th>student</th><th>outcome</th><th>time s</th>"
        "<th>min clearance m</th><th>closest ship m</th><th>contacts</th><th>speed at end m/s</th>"
        "<th>rudder effort deg</th><th>engine orders</th><th>score</th></tr>",
        *rows,
        "</table>",
    ]
    for k, d in enumerate(debriefs):
        items = [(label, value) for label, value in d.items() if label != "track plot"] + extra_rows(h, k)
        table = "".join(f"<tr><th>{e(label)}</th><td>{e(value)}</td></tr>" for label, value in items)
        parts.append(
            f'<div class="student"><h3>{e(h.names[k])}</h3>{chart_svg(h, [k], 360)}<table>{table}</table></div>'
        )
    parts.append("</body></html>")
    return "\n".join(parts)
