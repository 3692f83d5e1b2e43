"""Amplitude and frequency dependence of the pure sway and pure yaw derivatives.

A linear derivative from a PMM test should not depend on the amplitude (or the test is outside the linear
range) and, for a quasi-steady manoeuvring model, not on the frequency; at ω' = ωL/U of order 1 and above
it does, through the memory of the shed vorticity and the free-surface waves (the frequency dependence
the PMM literature reports for Y_v and N_v). This module fits every run of a test on its own (the spread
over amplitudes at the base frequency) and every frequency with all its amplitudes (the spread over ω'),
so the report shows how far a derivative moves with the test's own choices.

The spread of a derivative over a set of values is (max − min) / |mean|.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .fitting import fit_pure_sway, fit_pure_yaw

KEYS = {"sway": ("Y_v", "Y_vdot", "N_v", "N_vdot"), "yaw": ("Y_r", "Y_rdot", "N_r", "N_rdot")}


def spread(values: Sequence[float]) -> float | None:
    """(max − min) / |mean| of two or more values (None for fewer, or a zero mean)."""
    v = np.asarray(values, dtype=float)
    if len(v) < 2 or v.mean() == 0.0:
        return None
    return float(np.ptp(v) / abs(v.mean()))


def _fit(
    kind: str, runs: list[dict[str, Any]], U: float, L: float, rho: float, norm: str
) -> dict[str, float]:
    fit = fit_pure_sway if kind == "sway" else fit_pure_yaw
    result = fit(
        [r["t"] for r in runs],
        [r["q"] for r in runs],
        [r["Y"] for r in runs],
        [r["N"] for r in runs],
        omega_rad_s=runs[0]["omega"],
        U_m_s=U,
        L_m=L,
        rho_kg_m3=rho,
        normalisation=norm,
    )
    return {k: result.derivatives[k] for k in KEYS[kind]}


def _table(labels: list[float], fits: list[dict[str, float]], kind: str) -> dict[str, Any]:
    derivs = {k: [f[k] for f in fits] for k in KEYS[kind]}
    return {"values": labels, "derivatives": derivs, "spread": {k: spread(v) for k, v in derivs.items()}}


def dependence(
    runs: dict[str, list[dict[str, Any]]], *, U: float, L: float, rho: float, normalisation: str
) -> dict[str, Any]:
    """Per test kind (``sway``, ``yaw``) with runs: the linear derivatives (in ``normalisation``) of each
    amplitude at the base frequency and of each frequency with all its amplitudes, and their spreads.

    ``runs[kind]`` are the analysis' run records (``t``, ``q``, ``Y``, ``N``, ``omega``, ``amplitude``,
    ``base``: True for the study's own period). Amplitudes are y0 (m) for sway and ψ0 (deg) for yaw.
    """
    out: dict[str, Any] = {}
    for kind, recs in runs.items():
        if not recs:
            continue
        entry: dict[str, Any] = {"keys": list(KEYS[kind])}
        base = sorted((r for r in recs if r["base"]), key=lambda r: r["amplitude"])
        if len(base) >= 2:
            amps = [r["amplitude"] for r in base]
            entry["amplitudes"] = _table(
                amps, [_fit(kind, [r], U, L, rho, normalisation) for r in base], kind
            )
            entry["amplitudes"]["omega_prime"] = base[0]["omega"] * L / U
        omegas = sorted({round(r["omega"], 9) for r in recs})
        if len(omegas) >= 2:
            groups = [[r for r in recs if round(r["omega"], 9) == w] for w in omegas]
            fits = [_fit(kind, g, U, L, rho, normalisation) for g in groups]
            entry["frequencies"] = _table([w * L / U for w in omegas], fits, kind)
        if len(entry) > 1:
            out[kind] = entry
    return out


def summary_lines(dep: dict[str, Any], normalisation: str) -> list[str]:
    """The report's section: one table per kind and sweep, derivatives against amplitude or ω'."""
    if not dep:
        return []
    lines = [
        "",
        f"## PMM amplitude and frequency dependence ({normalisation}; spread = (max − min) / |mean|)",
    ]
    for kind, entry in dep.items():
        keys = entry["keys"]
        for what, label, by in (
            ("amplitudes", "y0 (m)" if kind == "sway" else "psi0 (deg)", "amplitude"),
            ("frequencies", "omega'", "frequency"),
        ):
            if what not in entry:
                continue
            tab = entry[what]
            at = f" at omega' = {tab['omega_prime']:.3g}" if what == "amplitudes" else " (all amplitudes)"
            lines += ["", f"Pure {kind}, by {by}{at}:", "", f"| {label} | " + " | ".join(keys) + " |"]
            lines.append("|---" * (len(keys) + 1) + "|")
            for i, x in enumerate(tab["values"]):
                lines.append(
                    f"| {x:.4g} | " + " | ".join(f"{tab['derivatives'][k][i]:.5g}" for k in keys) + " |"
                )
            lines.append(
                "| spread | "
                + " | ".join(
                    "" if tab["spread"][k] is None else f"{100 * tab['spread'][k]:.1f} %" for k in keys
                )
                + " |"
            )
    return lines
