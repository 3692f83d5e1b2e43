"""Report: force-vs-motion plots with fitted lines, force convergence, and a Markdown summary.

Plots follow the seed report's Figs. 11–18 (force against v, v̇, r, ṙ with the fitted line), in
the study's non-dimensional system. matplotlib is imported only here; without it the summary is
still written.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from .fitting import FitResult, harmonic_fit
from .friction import ittc57
from .heel import summary_lines as heel_summary
from .jobs import FinishedStudy
from .pmm_sweep import summary_lines
from .postprocess import read_forces


def _scales(norm: str, rho: float, U: float, L: float) -> tuple[float, float]:
    c = 0.5 if norm == "half_rho_L2_U2" else 1.0
    return c * rho * U**2 * L**2, c * rho * U**2 * L**3


def write_report(
    report_dir: Path,
    p: FinishedStudy,
    *,
    plots: bool = True,
    fits: dict[str, FitResult],
    pmm_runs: dict[str, list],
    model_prime: dict[str, float],
    clarke: dict[str, float],
    origin: dict[str, str],
    provenance: dict[str, Any],
    verification: dict[str, Any] | None = None,
) -> list[Path]:
    """Write the plots (unless ``plots`` is false or matplotlib is missing) and ``summary.md`` into
    ``report_dir``; return the files written."""
    written: list[Path] = []
    plt = None
    if plots:
        try:
            import matplotlib  # noqa: PLC0415 - optional dependency

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt  # noqa: PLC0415
        except ImportError:
            plt = None
    if plt is not None:
        written += _plots(plt, report_dir, p, fits, pmm_runs)
    no_plots = (
        "plots switched off" if not plots else ("" if plt is not None else "matplotlib is not installed")
    )
    written.append(
        _summary(
            report_dir, p, model_prime, clarke, origin, provenance, written, no_plots, verification or {}
        )
    )
    return written


def _save(plt, fig, path: Path, written: list[Path]) -> None:
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    written.append(path)


def _plots(
    plt, out: Path, p: FinishedStudy, fits: dict[str, FitResult], pmm_runs: dict[str, list]
) -> list[Path]:
    s = p.study
    L, rho, U, norm = s.lpp, s.rho, s.U_ref, s.normalisation
    F0, M0 = _scales(norm, rho, U, L)
    written: list[Path] = []
    prime = f"' ({norm})"

    # tow: resistance and C_T against Fn
    tow = fits.get("tow")
    if tow is not None:
        u = np.asarray(tow.details["U_m_s"])
        X = np.asarray(tow.details["X_N"])
        S = p.hull.hydro.wetted_area_m2
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        ax[0].plot(u, -X, "o", label="CFD (double body)")
        if len(u) > 1:
            uu = np.linspace(u.min(), u.max(), 50)
            d = tow.derivatives
            fit = d["X_0"] + d.get("X_u", 0.0) * (uu - U) + d.get("X_uu", 0.0) * (uu - U) ** 2
            ax[0].plot(uu, -fit, "-", label="fit X_0 + X_u du + X_uu du^2")
        ax[0].set_xlabel("U (m/s)")
        ax[0].set_ylabel("R = -X (N)")
        ax[0].legend()
        fn = u / math.sqrt(9.81 * L)
        ct = -X / (0.5 * rho * S * u**2)
        cf = np.array([ittc57(x * L / s.nu) for x in u])
        ax[1].plot(fn, 1e3 * ct, "o", label="C_T CFD")
        ax[1].plot(fn, 1e3 * cf, "s--", label="C_F ITTC-57")
        ax[1].plot(fn, 1e3 * cf * np.mean(ct / cf), ":", label=f"(1+k) C_F, 1+k = {np.mean(ct / cf):.3f}")
        ax[1].set_xlabel("Fn")
        ax[1].set_ylabel("coefficient x 1e3")
        ax[1].legend()
        _save(plt, fig, out / "tow_resistance.png", written)

    # static drift (seed Figs. 11, 12)
    drift = fits.get("drift")
    if drift is not None:
        v = np.asarray(drift.details["v_m_s"])
        vv = np.linspace(min(v.min(), -v.max()), max(v.max(), -v.min()), 100)
        d = drift.derivatives
        for name, F, scale in (("Y", drift.details["Y_N"], F0), ("N", drift.details["N_Nm"], M0)):
            fig, ax = plt.subplots(figsize=(5.5, 4))
            ax.plot(
                v / U, np.asarray(F) / scale, "o", label="CFD static drift (beta = 0 bias removed, mirrored)"
            )
            fit = d[f"{name}_0"] + d[f"{name}_v"] * vv + d.get(f"{name}_vvv", 0.0) * vv**3
            ax.plot(vv / U, fit / scale, "-", label=f"fit: {name}'_v = {d[f'{name}_v'] * U / scale:.5f}")
            ax.axhline(0, color="0.7", lw=0.5)
            ax.axvline(0, color="0.7", lw=0.5)
            ax.set_xlabel("v' = v/U")
            ax.set_ylabel(name + prime)
            ax.set_title(f"Determination of {name}_v (static drift)")
            ax.legend()
            _save(plt, fig, out / f"drift_{name}_v.png", written)

    # PMM decompositions (seed Figs. 13, 15-18)
    for kind, (var, acc) in (("sway", ("v", "vdot")), ("yaw", ("r", "rdot"))):
        fit = fits.get(kind)
        runs = pmm_runs.get(kind, [])
        if fit is None or not runs:
            continue
        d = fit.derivatives
        sv = U if var == "v" else U / L  # velocity scale
        sa = U**2 / L if var == "v" else U**2 / L**2  # acceleration scale
        for name, scale in (("Y", F0), ("N", M0)):
            for x_name, other in ((var, acc), (acc, var)):
                fig, ax = plt.subplots(figsize=(5.5, 4))
                for r in runs:
                    h = harmonic_fit(r["t"], r["q"], r["omega"], 3)
                    k1, k2 = h.evaluate(r["t"], 1), h.evaluate(r["t"], 2)
                    sig = {var: k1, acc: k2}
                    F = np.asarray(r[name])
                    part = F - d[f"{name}_0"] - d[f"{name}_{other}"] * sig[other]
                    if f"{name}_{var * 3}" in d:
                        part = part - (d[f"{name}_{var * 3}"] * k1**3 if x_name == acc else 0.0)
                    xs = sig[x_name] / (sv if x_name == var else sa)
                    ax.plot(xs, part / scale, ".", ms=3, label=r["job"].label)
                xs_all = np.concatenate(
                    [
                        harmonic_fit(r["t"], r["q"], r["omega"], 3).evaluate(
                            r["t"], 1 if x_name == var else 2
                        )
                        for r in runs
                    ]
                )
                xl = np.linspace(xs_all.min(), xs_all.max(), 50)
                line = d[f"{name}_{x_name}"] * xl
                if x_name == var and f"{name}_{var * 3}" in d:
                    line = line + d[f"{name}_{var * 3}"] * xl**3
                coef = d[f"{name}_{x_name}"] * (sv if x_name == var else sa) / scale
                ax.plot(
                    xl / (sv if x_name == var else sa),
                    line / scale,
                    "k-",
                    label=f"fit: {name}'_{x_name} = {coef:.5f}",
                )
                lbl = {
                    "v": "v' = v/U",
                    "vdot": "v-dot' = v-dot L/U^2",
                    "r": "r' = rL/U",
                    "rdot": "r-dot' = r-dot L^2/U^2",
                }[x_name]
                ax.set_xlabel(lbl)
                ax.set_ylabel(f"{name}{prime} minus the other terms")
                ax.set_title(f"Determination of {name}_{x_name} (pure {kind})")
                ax.legend(fontsize=8)
                _save(plt, fig, out / f"{kind}_{name}_{x_name}.png", written)

    # convergence of the steady cases
    steady = [j for j in p.jobs.values() if j.kind in ("tow", "drift")]
    if steady:
        fig, ax = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
        for j in steady:
            h = read_forces(p.cases / j.name)
            for i, (lab, sig) in enumerate(
                (("X (N)", h.F[:, 0]), ("Y (N)", -h.F[:, 1]), ("N (N m)", -h.M[:, 2]))
            ):
                ax[i].plot(h.t, sig, lw=1, label=j.label)
                ax[i].set_ylabel(lab)
        ax[-1].set_xlabel("SIMPLE iteration")
        ax[0].legend(fontsize=7, ncol=2)
        ax[0].set_title("Force convergence, steady cases (standard body axes)")
        for a in ax:
            lo, hi = _robust_limits(a)
            a.set_ylim(lo, hi)
        _save(plt, fig, out / "convergence_steady.png", written)

    # PMM force histories with the fit window
    for runs in pmm_runs.values():
        for r in runs:
            fig, ax = plt.subplots(3, 1, figsize=(8, 7), sharex=True)
            t0 = r["t"][0]
            for i, (lab, key) in enumerate((("X (N)", "X"), ("Y (N)", "Y"), ("N (N m)", "N"))):
                ax[i].plot(r["t_all"], r[f"{key}_all"], lw=1)
                ax[i].axvspan(t0, r["t"][-1], color="0.9")
                ax[i].set_ylabel(lab)
            ax[-1].set_xlabel("t (s)")
            ax[0].set_title(f"{r['job'].label}: forces in body axes (grey: fit window)")
            _save(plt, fig, out / f"convergence_{r['job'].name}.png", written)
    return written


def _robust_limits(ax) -> tuple[float, float]:
    """Y limits ignoring the first 10 % of each line (start-up transients)."""
    vals = []
    for line in ax.get_lines():
        y = np.asarray(line.get_ydata(), dtype=float)
        vals.append(y[len(y) // 10 :])
    if not vals:
        return ax.get_ylim()
    v = np.concatenate(vals)
    lo, hi = float(np.min(v)), float(np.max(v))
    pad = 0.1 * max(hi - lo, 1e-9)
    return lo - pad, hi + pad


def _fmt(x: Any) -> str:
    if isinstance(x, float):
        return f"{x:.5g}"
    return str(x)


def _summary(
    out: Path,
    p: FinishedStudy,
    model_prime: dict[str, float],
    clarke: dict[str, float],
    origin: dict[str, str],
    provenance: dict[str, Any],
    plots: list[Path],
    no_plots: bool,
    verification: dict[str, Any],
) -> Path:
    s = p.study
    mesh = provenance["mesh"]
    lines = [
        f"# vessel-cfd report: {s.name or s.hull}",
        "",
        f"Hull: {provenance['hull']['source']}; Lpp {s.lpp:g} m, B {s.bwl:g} m, T {s.tm:g} m, "
        f"C_B {provenance['hull']['C_B']:.4f}, wetted area {provenance['hull']['wetted_area_m2']:.5g} m2.",
        f"Mesh: grading {s.grading} ({mesh['grading_name']}), {mesh['cells']} cells, "
        f"{mesh['hull_faces']} hull faces, checkMesh OK = {mesh['checkMesh_ok']}.",
        f"Reference speed {s.U_ref:g} m/s, Re = {provenance['solver']['Re_ref']:.4g}, "
        f"Fn = {provenance['solver']['Fn_ref']:.4f}; water rho {s.rho:g} kg/m3, nu {s.nu:g} m2/s.",
        f"Wall time: {provenance['wall_time_s'].get('total', float('nan')):.0f} s.",
        "",
        f"## Derivatives at model scale ({s.normalisation}, standard body axes)",
        "",
        "| derivative | value | Clarke (1983) | CFD / Clarke | from | verification |",
        "|---|---|---|---|---|---|",
    ]
    status = verification.get("derivatives", {})
    for k, v in model_prime.items():
        c = clarke.get(k)
        ratio = f"{v / c:.3f}" if c and origin.get(k, "").startswith(("static", "pure")) else ""
        lines.append(
            f"| {k} | {v:.6g} | {'' if c is None else f'{c:.6g}'} | {ratio} | {origin.get(k, '')} "
            f"| {status.get(k, '').split(' (')[0]} |"
        )
    if "dynamic_sway" in provenance:
        dyn = provenance["dynamic_sway"]
        lines += [
            "",
            f"Pure sway also gives dynamic Y_v = {dyn['Y_v']:.6g}, N_v = {dyn['N_v']:.6g} "
            "(frequency dependent; the ship file uses the static drift values when available).",
        ]
    sc = provenance["scale"]
    lines += [
        "",
        "## Ship file",
        "",
        f"Scale factor {sc['scale_factor']:.6g} (ship L = {sc['scale_factor'] * s.lpp:.5g} m), "
        f"U_ref = {sc['U_ref_ship_m_s']:.4g} m/s, resistance {sc['resistance_N']:.5g} N at that speed"
        + (f" (ITTC-1978 form factor method, k = {sc['form_factor_k']:.3f})" if "form_factor_k" in sc else "")
        + "; the sway/yaw derivatives above are scale-independent.",
    ]
    regression = provenance["tests"].get("drift", {}).get("regression")
    if regression:
        lines += _regression_lines(regression)
    lines += summary_lines(provenance.get("pmm_dependence", {}), s.normalisation)
    lines += heel_summary(provenance.get("heel", {}))
    if verification:
        lines += _verification_lines(verification)
    lines += ["", "## Fit residuals (rms residual / rms force)", ""]
    for name, res in provenance["fit_residuals"].items():
        lines.append(f"- {name}: " + ", ".join(f"{k} {v:.3g}" for k, v in res.items()))
    lines += ["", "## Plots", ""]
    if no_plots:
        lines.append(f"No plots: {no_plots} (plots need pip install 'vessel-gym[cfd]').")
    lines += [f"- [{pth.name}]({pth.name})" for pth in plots]
    lines += ["", "The ship file is ../ship.toml; derivatives.json holds every number above.", ""]
    path = out / "summary.md"
    path.write_text("\n".join(lines))
    return path


def _verification_lines(v: dict[str, Any]) -> list[str]:
    """The verification section of summary.md: verdict, then every check of the study and of each case."""

    def row(where: str, c: dict[str, Any]) -> str:
        verdict = {True: "pass", False: "**FAIL**", None: "**not checked**"}[c["passed"]]
        value = c["value"]
        if isinstance(value, dict):
            value = ", ".join(f"{k} {_fmt(x)}" for k, x in value.items())
        return f"| {where} | {c['name']} | {_fmt(value)} | {c['limit']} | {verdict} {c['note']} |"

    lines = [
        "",
        f"## Verification: {v['verdict']}",
        "",
        "Every derivative from a case that fails a check (or could not be checked) is marked unverified; "
        "limits in docs/cfd.md. " + (f"Failed: {'; '.join(v['failures'])}." if v["failures"] else ""),
        "",
        "| case | check | value | limit | result |",
        "|---|---|---|---|---|",
    ]
    lines += [row("study", c) for c in v["study"]]
    lines += [row(name, c) for name, checks in v["cases"].items() for c in checks]
    return lines


def _regression_lines(reg: dict[str, Any]) -> list[str]:
    """The static-drift regression forms: each term with its standard error, the residuals, the choice."""

    def term(f: dict[str, Any], k: str) -> str:
        se = f["std_error_SI"].get(k)
        return f"{f['terms_SI'][k]:.5g}" + (f" ± {se:.2g}" if se is not None else "")

    lines = [
        "",
        "## Static drift: regression forms (SI, model scale; ± one standard error)",
        "",
        "| form | Y_v | nonlinear Y term | N_v | nonlinear N term | residual Y, N | runs |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, f in reg["forms"].items():
        nl = [k for k in f["terms_SI"] if k not in ("Y_v", "N_v")]
        ynl = next((f"{k} {term(f, k)}" for k in nl if k.startswith("Y")), "")
        nnl = next((f"{k} {term(f, k)}" for k in nl if k.startswith("N")), "")
        lines.append(
            f"| {name} | {term(f, 'Y_v')} | {ynl} | {term(f, 'N_v')} | {nnl} | "
            f"{f['residuals']['Y']:.3g}, {f['residuals']['N']:.3g} | {f['runs']} |"
        )
    sp = reg["spread_SI"]
    lines += [
        "",
        f"Written to the ship file: **{reg['written']}** ({reg['reason']}; {reg['conversion']}). "
        f"Spread of the linear terms over the forms: Y_v {sp['Y_v']:.3g}, N_v {sp['N_v']:.3g}.",
    ]
    return lines
