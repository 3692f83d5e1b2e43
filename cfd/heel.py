"""Static heel: the heeled double-body hull, the roll-derivative fit and the ship file's [roll] table.

Heel is a rotation of the hull by phi about the x-axis through the still waterline at midship (the case
frame's x-axis; positive phi: starboard down, port up, the same angle as the standard z-down axes' roll).
The mesh is cut at the waterline plane z = 0, a symmetry plane: what the flow sees is the heeled underwater
body mirrored about the still waterline. The part of the hull that the heel immerses is what the STL has
above the waterline: for the Wigley (built as a double body) the mirror image of the underwater body next to
the waterline, for a wall-sided waterline the true topside to first order in phi (docs/cfd.md, "Static
heel"); an STL with topsides is heeled as it is, one without enough of them is refused. No sinkage or trim
follows the heel, and the free surface is absent (double body).

Forces are measured as in every steady case (:mod:`cfd.postprocess`), plus the roll moment
K = Mx (case frame; the x-axis is common to both frames), taken about the axis through G:
K_G = Mx + z_G Fy (G at height z_G above the waterline; Fy = -Y).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .errors import InputError

#: the heel-mesh case name for an angle in degrees
MESH_NAME = "mesh_heel{:05.2f}"
#: the static-heel options of ``vessel-cfd run`` (cfd.cli), keys of a study file with underscores
RUN_OPTIONS: tuple[tuple[str, str], ...] = (
    ("heel-deg", "static-heel angles (deg, starboard down, 0-30) of tests heel; one mesh each"),
    ("heel-drift-deg", "drift angle of the heeled drift runs, at + and - (deg; 0: heeled tows only)"),
    ("z-G", "height of G above the still waterline (m, model scale): the axis of the roll moment K"),
    ("GM", "GM (m, model scale) for a new [roll] table when the template has none"),
    ("k-xx", "roll radius of gyration (m, model scale) for a new [roll] table when the template has none"),
)


def heel_triangles(tris: np.ndarray, phi_deg: float) -> np.ndarray:
    """The hull's triangles (n, 3, 3), case frame, rotated by ``phi_deg`` about the x-axis through the
    origin (midship, still waterline). Positive: starboard (y < 0) down."""
    c, s = math.cos(math.radians(phi_deg)), math.sin(math.radians(phi_deg))
    R = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return np.asarray(tris, dtype=float) @ R.T


def check_freeboard(tris: np.ndarray, bwl: float, phi_deg: float) -> None:
    """Refuse a heel that would immerse more than the STL has above the waterline: the waterline's edge
    goes (B/2) tan(phi) down, so the hull must reach that high above z = 0 (the Wigley, a double body,
    reaches T)."""
    top = float(np.max(np.asarray(tris)[..., 2]))
    need = 0.5 * bwl * math.tan(math.radians(phi_deg))
    if top < need:
        raise InputError(
            "heel_deg",
            f"{phi_deg:g} deg immerses the hull up to {need:.4g} m above the waterline, but the STL ends "
            f"{top:.4g} m above it; give an STL with topsides (or a smaller heel)",
        )


def roll_about_G(Mx: float, Fy: float, z_G: float) -> float:
    """Roll moment (N m, standard axes) about the axis through G from the case-frame moment about the
    waterline axis: M_G = M_O + (O - G) x F, whose x component is Mx + z_G Fy."""
    return Mx + z_G * Fy


def fit_roll(
    points: Sequence[Mapping[str, float]], *, U: float, L: float, rho: float
) -> tuple[dict[str, float], dict[str, float]]:
    """Least-squares roll terms (SNAME prime, ½ rho L^2 U^2 and ½ rho L^3 U^2) from steady points.

    Each point has v (m/s, standard axes), phi (rad) and Y (N), N (N m), K (N m, about G). The model of each
    force is F' = F_v v' + F_vvv v'^3 + F_phi phi + F_vvphi v'^2 phi + F_vphiphi v' phi^2, the terms the
    port-starboard symmetry allows (F(-v, -phi) = -F): F_vvv only with two or more upright drift angles, the
    cross terms only with heeled drift runs. Returns (roll-table terms, rms residual of each force, prime):
    every K term, and the Y and N terms with phi (Y_v, N_v belong to the hull table)."""
    v = np.array([p["v"] for p in points]) / U
    phi = np.array([p["phi"] for p in points])
    upright = {round(abs(x), 9) for x, f in zip(v, phi) if f == 0.0 and x != 0.0}
    if not upright or not np.any(phi != 0.0):
        raise ValueError("the roll fit needs upright drift and heeled runs")
    cols = {"v": v, "phi": phi}
    if len(upright) >= 2:
        cols["vvv"] = v**3
    if np.any((phi != 0.0) & (v != 0.0)):
        cols["vvphi"] = v**2 * phi
        cols["vphiphi"] = v * phi**2
    A = np.column_stack(list(cols.values()))
    if np.linalg.matrix_rank(A) < A.shape[1]:
        raise ValueError(f"the roll fit's points do not determine the terms {', '.join(cols)}")
    q = 0.5 * rho * U**2
    out: dict[str, float] = {}
    rms: dict[str, float] = {}
    for force, scale in (("Y", q * L**2), ("N", q * L**3), ("K", q * L**3)):
        b = np.array([p[force] for p in points]) / scale
        c, *_ = np.linalg.lstsq(A, b, rcond=None)
        rms[force] = float(np.sqrt(np.mean((A @ c - b) ** 2)))
        for term, value in zip(cols, c):
            if force == "K" or "phi" in term:
                out[f"{force}_{term}"] = float(value)
    return out, rms


def roll_table(
    template: Mapping[str, Any], derivatives: Mapping[str, float], *, GM_m: float, I_xG_kgm2: float
) -> dict[str, Any]:
    """The ship file's [roll] table: the template's (its other roll terms kept, the CFD's replacing theirs)
    or a new one from GM and the roll inertia."""
    roll = dict(template.get("roll", {}))
    if not roll:
        roll = {"GM_m": GM_m, "I_xG_kgm2": I_xG_kgm2}
    roll["derivatives"] = {**dict(roll.get("derivatives", {})), **derivatives}
    return roll


def heel_points(jobs: Mapping[str, Any], U: float, z_G: float) -> list[dict[str, float]]:
    """The steady points of the roll fit from a study's finished jobs (cfd.jobs.Job): the base tow and the
    upright drifts at ``U`` (phi = 0) and every heeled tow and drift. Standard axes: v = -U sin(beta_case),
    Y = -Fy, N = -Mz, K about G."""
    out = []
    for job in jobs.values():
        if job.kind not in ("tow", "drift", "heel") or not math.isclose(job.params.get("U", -1.0), U):
            continue
        sm = job.summary
        out.append(
            {
                "case": job.name,
                "v": -U * math.sin(math.radians(job.params["beta"])),
                "phi": math.radians(job.params.get("phi", 0.0)),
                "Y": float(sm["Y_N"]),
                "N": float(sm["N_Nm"]),
                "K": roll_about_G(float(sm["K_Nm"]), float(sm["Fy_case_N"]), z_G),
            }
        )
    return out


def roll_results(
    jobs: Mapping[str, Any],
    template: Mapping[str, Any],
    particulars: Mapping[str, float],
    study: Any,
    lam: float,
) -> tuple[dict[str, Any], dict[str, Any]]:
    """The [roll] table and its provenance for a study with tests "heel": the fit of :func:`fit_roll` on the
    study's points; GM and k_xx (model scale) scaled by ``lam`` when the template has no [roll]."""
    points = heel_points(jobs, study.U_ref, study.z_G)
    derivs, rms = fit_roll(points, U=study.U_ref, L=study.lpp, rho=study.rho)
    mass = float(particulars["displacement_m3"]) * float(particulars["rho_kg_m3"])
    table = roll_table(template, derivs, GM_m=study.GM * lam, I_xG_kgm2=mass * (study.k_xx * lam) ** 2)
    provenance = {
        "method": "double-body static heel (heeled tow, heeled drift at +/- heel_drift_deg) and upright drift; "
        "hull heeled about the still waterline at midship, mirrored about it; K about G at z_G above the waterline",
        "z_G_model_m": study.z_G,
        "points": points,
        "fit_rms_prime": rms,
        "derivatives": derivs,
        "roll_table_from": "template" if "roll" in template else "study GM and k_xx",
    }
    return table, provenance


def summary_lines(heel: Mapping[str, Any]) -> list[str]:
    """The static-heel section of the report's summary.md (empty without heel runs)."""
    if not heel:
        return []
    lines = [
        "",
        "## Static heel (roll terms, SNAME prime, K about G)",
        "",
        "| case | v (m/s) | phi (deg) | Y (N) | N (N m) | K (N m) |",
        "|---|---|---|---|---|---|",
    ]
    for p in heel["points"]:
        lines.append(
            f"| {p['case']} | {p['v']:.4g} | {math.degrees(p['phi']):.3g} | {p['Y']:.4g} | {p['N']:.4g} | {p['K']:.4g} |"
        )
    lines += ["", ", ".join(f"{k} = {v:.4g}" for k, v in heel["derivatives"].items())]
    return lines
