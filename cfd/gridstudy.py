"""Grid study: one quantity on three (or two) systematically refined grids -> Richardson extrapolation and
the numerical uncertainty. The numerics are plain Python; :func:`run_grid_study` runs the studies.

Procedure of Celik, Ghia, Roache, Freitas, Coleman & Raad (2008), "Procedure for estimation and reporting
of uncertainty due to discretization in CFD applications", ASME J. Fluids Eng. 130, 078001, which is
Roache's grid convergence index (GCI) with safety factor F_s = 1.25 for three grids; the convergence
condition as in ITTC Recommended Procedure 7.5-03-01-01 (Uncertainty analysis in CFD, verification):

- grids 1 (finest), 2, 3 with representative sizes h1 < h2 < h3 (h = (V/N)^(1/3) in 3-D: the domain is
  the same on every grid, so h ∝ N^(-1/3)), r21 = h2/h1, r32 = h3/h2;
- ε21 = φ2 − φ1, ε32 = φ3 − φ2, convergence ratio R = ε21/ε32:
  0 < R < 1 monotonic convergence, R < 0 oscillatory convergence, R ≥ 1 divergence;
- apparent order p from p = |ln|ε32/ε21| + q(p)| / ln r21, q(p) = ln((r21^p − s)/(r32^p − s)),
  s = sign(ε32/ε21), solved by fixed-point iteration;
- φ_ext = (r21^p φ1 − φ2)/(r21^p − 1), e_a = |(φ1 − φ2)/φ1|, e_ext = |(φ_ext − φ1)/φ_ext|,
  GCI_fine = F_s e_a / (r21^p* − 1) (a fraction of φ1) with p* = min(p, 2), the formal order (Roache);
- oscillatory convergence: U = ½ (max φ − min φ) over the three grids (ITTC 7.5-03-01-01); divergence: no
  uncertainty can be given.

Two grids (:func:`grid_convergence_two`) cannot show the order or the convergence condition, so the order is
assumed, the formal one (p = 2), and the safety factor is Roache's for that case, F_s = 3 (Roache 1998,
Verification and Validation in Computational Science and Engineering, ch. 5; Roache 1994, ASME J. Fluids
Eng. 116:405): GCI_fine = 3 e_a / (r21² − 1), φ_ext = (r21² φ1 − φ2)/(r21² − 1). It is the cheaper,
more conservative variant, for hulls whose third grid costs too much.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

SAFETY_FACTOR = 1.25  # F_s of Roache's GCI for a three-grid study (Celik et al. 2008)
SAFETY_FACTOR_TWO_GRIDS = 3.0  # F_s for two grids, where the order is assumed, not observed (Roache 1998)
TWO_GRIDS = "two grids, order assumed"  # the condition of a two-grid result: none can be judged
# Formal order of the discretisation (second-order convection and gradients). An apparent order above it means
# the grids are not in the asymptotic range (the error terms of different orders still compete), and GCI
# with that order would shrink to nothing: the GCI uses min(p, P_FORMAL), the conservative choice of Roache
# (1998, Verification and Validation in Computational Science and Engineering, ch. 5). Measured on the
# Wigley at gradings 1-3: p = 7.6 (Y_v) and 15 (N_v), whose uncapped GCI were 0.05 % and 0.002 %.
P_FORMAL = 2.0


@dataclass(frozen=True)
class GridConvergence:
    """Result for one quantity; ``phi`` finest first (three grids, or two). Fractions (not %) for e_a, e_ext
    and GCI."""

    phi: tuple[float, ...]
    r21: float
    r32: float | None  # None with two grids
    R: float | None  # convergence ratio ε21/ε32 (None when ε32 = 0, or with two grids)
    # "monotonic", "oscillatory", "divergent", "converged" (no change between grids); with two grids
    # "two grids, order assumed" (no condition can be judged)
    condition: str
    p: float | None = None  # apparent order
    p_gci: float | None = None  # order used in the GCI: min(p, P_FORMAL)
    phi_ext: float | None = None
    e_a: float | None = None
    e_ext: float | None = None
    gci_fine: float | None = None
    uncertainty: float | None = None  # absolute, in the quantity's unit

    def as_dict(self) -> dict[str, object]:
        return {k: v for k, v in self.__dict__.items() if v is not None}


def apparent_order(eps21: float, eps32: float, r21: float, r32: float, tol: float = 1e-10) -> float:
    """Apparent order p of Celik et al. (2008) eq. 3, by fixed-point iteration."""
    s = math.copysign(1.0, eps32 / eps21)
    ratio = math.log(abs(eps32 / eps21))
    p = abs(ratio) / math.log(r21)
    for _ in range(500):
        q = math.log((r21**p - s) / (r32**p - s))
        p_new = abs(ratio + q) / math.log(r21)
        if abs(p_new - p) < tol:
            return p_new
        p = p_new
    raise ValueError("the apparent order did not converge (grids too close or data too irregular)")


def grid_convergence(
    phi: tuple[float, float, float], h: tuple[float, float, float], safety: float = SAFETY_FACTOR
) -> GridConvergence:
    """Richardson extrapolation and GCI of ``phi`` on grids of representative size ``h`` (finest first)."""
    phi1, phi2, phi3 = (float(x) for x in phi)
    h1, h2, h3 = (float(x) for x in h)
    if not 0 < h1 < h2 < h3:
        raise ValueError(f"grid sizes must grow from the finest grid: h = {h}")
    r21, r32 = h2 / h1, h3 / h2
    eps21, eps32 = phi2 - phi1, phi3 - phi2
    if eps21 == 0.0 and eps32 == 0.0:
        return GridConvergence((phi1, phi2, phi3), r21, r32, None, "converged", uncertainty=0.0, phi_ext=phi1)
    R = eps21 / eps32 if eps32 != 0.0 else None
    spread = max(phi1, phi2, phi3) - min(phi1, phi2, phi3)
    if R is not None and R < 0:
        return GridConvergence((phi1, phi2, phi3), r21, r32, R, "oscillatory", uncertainty=0.5 * spread)
    if R is None or R >= 1.0 or eps21 == 0.0:
        return GridConvergence((phi1, phi2, phi3), r21, r32, R, "divergent")
    p = apparent_order(eps21, eps32, r21, r32)
    phi_ext = (r21**p * phi1 - phi2) / (r21**p - 1.0)
    e_a = abs((phi1 - phi2) / phi1)
    e_ext = abs((phi_ext - phi1) / phi_ext)
    p_gci = min(p, P_FORMAL)
    gci = safety * e_a / (r21**p_gci - 1.0)
    return GridConvergence(
        (phi1, phi2, phi3), r21, r32, R, "monotonic", p, p_gci, phi_ext, e_a, e_ext, gci, gci * abs(phi1)
    )


def grid_convergence_two(
    phi: tuple[float, float], h: tuple[float, float], safety: float = SAFETY_FACTOR_TWO_GRIDS
) -> GridConvergence:
    """Roache's two-grid GCI of ``phi`` on grids of size ``h`` (finest first): the formal order assumed, F_s = 3."""
    phi1, phi2 = (float(x) for x in phi)
    h1, h2 = (float(x) for x in h)
    if not 0 < h1 < h2:
        raise ValueError(f"grid sizes must grow from the finest grid: h = {h}")
    if phi1 == 0.0:
        raise ValueError("the finest-grid value is 0, so no relative error can be formed")
    r21 = h2 / h1
    rp = r21**P_FORMAL
    e_a = abs((phi1 - phi2) / phi1)
    phi_ext = (rp * phi1 - phi2) / (rp - 1.0)
    e_ext = abs((phi_ext - phi1) / phi_ext) if phi_ext != 0.0 else None
    gci = safety * e_a / (rp - 1.0)
    return GridConvergence(
        (phi1, phi2), r21, None, None, TWO_GRIDS, None, P_FORMAL, phi_ext, e_a, e_ext, gci, gci * abs(phi1)
    )


def grid_size(cells: int, dimensions: int = 3) -> float:
    """Representative cell size of a grid of ``cells`` cells on a fixed domain, up to a constant: N^(-1/d)."""
    if cells <= 0:
        raise ValueError("a grid needs cells > 0")
    return cells ** (-1.0 / dimensions)


def run_grid_study(study, gradings, progress=None, plots: bool = True) -> dict[str, object]:
    """Run ``study`` at three (or two) gradings (each in ``<out>/grading_<g>/``, resumable as any study), then
    write ``<out>/grid_study.json``, ``grid_study.md`` and ``grid_convergence.png`` for R_T and every
    derivative the CFD gave. Returns the JSON content."""
    import dataclasses  # noqa: PLC0415
    import json  # noqa: PLC0415
    from pathlib import Path  # noqa: PLC0415

    from .pipeline import Pipeline  # noqa: PLC0415 - the numerical part above needs no pipeline

    out = Path(study.out)
    runs = []
    for g in sorted(gradings, reverse=True):  # finest first
        sub = dataclasses.replace(study, grading=g, out=out / f"grading_{g}")
        result = Pipeline(sub, progress, plots=plots).run()
        prov = result.provenance
        tow = prov["tests"]["tow"]
        i = min(range(len(tow["speeds_m_s"])), key=lambda k: abs(tow["speeds_m_s"][k] - study.U_ref))
        values = {"R_T_N": -float(tow["X_N"][i])}
        origin = prov["derivative_origin"]
        for k, v in prov["model_scale_derivatives"].items():
            if origin.get(k, "").startswith(("static drift", "pure")):
                values[k] = float(v)
        runs.append(
            {
                "grading": g,
                "cells": int(prov["mesh"]["cells"]),
                "values": values,
                "verdict": result.verification["verdict"],
            }
        )
    h = tuple(grid_size(r["cells"]) for r in runs)
    estimate = grid_convergence if len(runs) == 3 else grid_convergence_two
    results = {}
    for k in runs[0]["values"]:
        if all(k in r["values"] for r in runs):
            phi = tuple(r["values"][k] for r in runs)
            try:
                results[k] = estimate(phi, h).as_dict()
            except ValueError as exc:
                results[k] = {"phi": phi, "condition": f"not estimated: {exc}"}
    report = {
        "gradings": [r["grading"] for r in runs],
        "cells": [r["cells"] for r in runs],
        "h_relative": [x / h[0] for x in h],
        "verdicts": [r["verdict"] for r in runs],
        "safety_factor": SAFETY_FACTOR if len(runs) == 3 else SAFETY_FACTOR_TWO_GRIDS,
        "method": method(len(runs)),
        "quantities": results,
    }
    out.mkdir(parents=True, exist_ok=True)
    finest = out / f"grading_{runs[0]['grading']}" / "ship.toml"
    report["ship_file"] = str(write_ship_with_uncertainty(finest, out / "ship.toml", report))
    (out / "grid_study.json").write_text(json.dumps(report, indent=1))
    (out / "grid_study.md").write_text(_markdown(report, study))
    if plots:
        _plot(report, out / "grid_convergence.png")
    return report


def method(grids: int) -> str:
    """The GCI variant of a study on ``grids`` grids, in one phrase for reports and the ship file."""
    if grids == 3:
        return (
            "grid convergence index, three grids, Celik et al. (2008), F_s = 1.25, order min(p, 2) (Roache); "
            "oscillatory: half the range (ITTC)"
        )
    return "grid convergence index, two grids, Roache (1998): order assumed 2 (formal), F_s = 3"


def relative_uncertainty(q: dict) -> float | None:
    """The numerical uncertainty of one quantity of a grid study as a fraction of its finest-grid value:
    GCI_fine (monotonic), half the range over |φ1| (oscillatory), 0 (no change); None when divergent."""
    phi1, u = q["phi"][0], q.get("uncertainty")
    if u is None or phi1 == 0:
        return None
    return abs(u / phi1)


def write_ship_with_uncertainty(src, dst, report: dict):
    """The finest grading's ship file ``src`` written again to ``dst`` with the grid study's uncertainty of
    every derivative in ``[source.provenance.grid_uncertainty]`` (the provenance table is free metadata of
    the ship-file schema), and one sentence in ``[source] notes``. Returns ``dst``."""
    from pathlib import Path  # noqa: PLC0415

    from .shipfile import tomllib, validate_ship, write_ship  # noqa: PLC0415

    src, dst = Path(src), Path(dst)
    text = src.read_text()
    ship = tomllib.loads(text)
    header = "\n".join(line[1:].strip() for line in text.splitlines() if line.startswith("#"))
    table: dict[str, object] = {
        "method": report["method"],
        "gradings": report["gradings"],
        "cells": report["cells"],
    }
    worst = []
    for k, q in report["quantities"].items():
        rel = relative_uncertainty(q)
        entry: dict[str, object] = {"condition": q["condition"], "fine": q["phi"][0]}
        if rel is not None:
            entry["relative"] = rel
            if k != "R_T_N":
                worst.append((rel, k))
        table[k] = entry
    source = ship.setdefault("source", {})
    source.setdefault("provenance", {})["grid_uncertainty"] = table
    divergent = [k for k, q in report["quantities"].items() if relative_uncertainty(q) is None]
    note = "Derived from CFD; grid uncertainty (GCI, gradings " + ", ".join(map(str, report["gradings"])) + "): "
    note += ", ".join(f"{k} ±{100 * r:.1f} %" for r, k in worst) or "none could be estimated"
    if divergent:
        note += "; no estimate (divergent on these grids) for " + ", ".join(divergent)
    source["notes"] = (str(source.get("notes", "")).rstrip() + "\n" + note + ".").lstrip()
    write_ship(dst, ship, header)
    problem = validate_ship(dst)
    if problem:
        raise ValueError(f"{dst}: {problem}")
    return dst


def ship_uncertainty(provenance: dict) -> dict[str, float | None]:
    """Per derivative, the relative grid uncertainty recorded by :func:`write_ship_with_uncertainty` in a
    ship file's provenance (None: divergent, no estimate); empty when the file has none."""
    table = provenance.get("grid_uncertainty") if isinstance(provenance, dict) else None
    if not isinstance(table, dict):
        return {}
    return {
        k: (float(v["relative"]) if "relative" in v else None)
        for k, v in table.items()
        if isinstance(v, dict) and k != "R_T_N"
    }


def _markdown(rep: dict, study) -> str:
    lines = [
        f"# Grid study: {study.name or study.hull}",
        "",
        f"Gradings {rep['gradings']} (finest first), cells {rep['cells']}, h/h1 "
        + ", ".join(f"{x:.3f}" for x in rep["h_relative"])
        + f" (h ∝ N^(-1/3)). Verification of each grading: {', '.join(rep['verdicts'])}.",
        (
            "Method: Celik et al. (2008) ASME J. Fluids Eng. 130 078001 (Roache's GCI, F_s = "
            f"{rep['safety_factor']}); convergence condition and oscillatory uncertainty as ITTC 7.5-03-01-01. "
            if len(rep["gradings"]) == 3
            else "Method: Roache's two-grid GCI (Roache 1998, Verification and Validation in Computational "
            f"Science and Engineering): the order assumed to be the formal 2, F_s = {rep['safety_factor']}; two "
            "grids cannot show the convergence condition or the observed order. "
        )
        + "R_T in N at the reference speed, derivatives in the study's prime system at model scale.",
        "",
        "| quantity | "
        + ("fine, medium, coarse" if len(rep["gradings"]) == 3 else "fine, coarse")
        + " | R | condition | p | p in GCI | extrapolated | e_a | GCI_fine | U |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]

    def f(x, pct=False):
        if x is None:
            return ""
        return f"{100 * x:.2f} %" if pct else f"{x:.5g}"

    for k, q in rep["quantities"].items():
        lines.append(
            f"| {k} | {', '.join(f'{x:.5g}' for x in q['phi'])} | {f(q.get('R'))} | {q['condition']} | "
            f"{f(q.get('p'))} | {f(q.get('p_gci'))} | {f(q.get('phi_ext'))} | {f(q.get('e_a'), True)} | {f(q.get('gci_fine'), True)} "
            f"| {f(q.get('uncertainty'))} |"
        )
    lines += [
        "",
        "Divergent quantities have no uncertainty estimate: refine further or check the set-up.",
        "",
    ]
    return "\n".join(lines)


def _plot(rep: dict, path) -> None:
    try:
        import matplotlib  # noqa: PLC0415 - optional dependency

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt  # noqa: PLC0415
    except ImportError:
        return
    h = rep["h_relative"]
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for k, q in rep["quantities"].items():
        phi1 = q["phi"][0]
        if phi1 == 0:
            continue
        (line,) = ax.plot(h, [x / phi1 for x in q["phi"]], "o-", label=f"{k} ({q['condition']})")
        if "phi_ext" in q:
            ax.plot([0.0], [q["phi_ext"] / phi1], "*", color=line.get_color(), ms=10)
    ax.set_xlabel("h / h_fine (h ∝ N^-1/3)")
    ax.set_ylabel("value / finest-grid value")
    ax.set_xlim(left=-0.05)
    ax.set_title("Grid convergence (stars: Richardson extrapolation)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
