"""From finished cases to derivatives, the ship file and the report.

All fits run on model-scale SI data in standard body axes (see :mod:`cfd.postprocess`), at the
reference speed U_ref of the drift and PMM tests; derivatives are then made non-dimensional in
the study's normalisation. Only the surge resistance terms depend on scale (Reynolds number):
they are extrapolated with the ITTC-1978 form-factor method when the ship file is scaled to the
template's length.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from . import __version__
from .clarke import clarke83, soding_surge_added_mass
from .config import GRADINGS
from .errors import CfdError
from .fitting import (
    FitResult,
    convert_normalisation,
    fit_pure_sway,
    fit_pure_yaw,
    fit_resistance,
    fit_static_drift,
    nondimensionalise,
)
from .friction import ittc57
from .heel import roll_results
from .jobs import FinishedStudy
from .pmm_sweep import dependence
from .postprocess import body_forces, read_forces
from .regression import choose, fit_forms, spread
from .report import write_report
from .shipfile import (
    borrowed_note,
    build_ship,
    default_template,
    load_template,
    scale_factor_to,
    validate_ship,
    write_ship,
)
from .verification import verify

SEA_WATER_NU = 1.1892e-6  # m²/s, ITTC 7.5-02-01-03 sea water at 15 °C (full-scale friction)
SHIP_KEYS = (
    "X_u",
    "X_uu",
    "X_vv",
    "X_rr",
    "X_udot",
    "Y_v",
    "Y_r",
    "Y_vvv",
    "Y_rrr",
    "Y_vdot",
    "Y_rdot",
    "N_v",
    "N_r",
    "N_vvv",
    "N_rrr",
    "N_vdot",
    "N_rdot",
)
CLARKE_KEYS = ("Y_v", "Y_r", "N_v", "N_r", "Y_vdot", "Y_rdot", "N_vdot", "N_rdot")


@dataclass
class StudyResult:
    """What a finished study produced (paths and the derivative set)."""

    ship_file: Path
    report_dir: Path
    derivatives: dict[str, float]
    normalisation: str
    provenance: dict[str, Any]
    verification: dict[str, Any]
    borrowed: str = ""  # what the ship file took from its template, and how it was scaled

    @property
    def verified(self) -> bool:
        return self.verification["verdict"] == "VERIFIED"


def full_scale_resistance(
    U_m: np.ndarray,
    R_m: np.ndarray,
    *,
    S_m: float,
    L_m: float,
    nu_m: float,
    lam: float,
    nu_s: float,
    form_factor: float | None,
) -> tuple[np.ndarray, np.ndarray, float]:
    """ITTC-1978 form-factor extrapolation of double-body model resistance to scale λ.

    C_T,m = R/(½ρSU²) = (1+k) C_F,m (a double-body flow has no wave resistance), so
    k = mean(C_T,m / C_F,m) − 1 unless given. At the Froude-similar speed U_s = U_m √λ:
    C_T,s = (1+k) C_F,s + ΔC_F, ΔC_F = (105 (k_s/L_s)^(1/3) − 0.64)·10⁻³ with k_s = 150 µm.
    ``R_m`` is per unit density (N per kg/m³). Returns U_s, C_T,s and k.
    """
    ct_m = R_m / (0.5 * S_m * U_m**2)
    cf_m = np.array([ittc57(u * L_m / nu_m) for u in U_m])
    k = float(np.mean(ct_m / cf_m) - 1.0) if form_factor is None else float(form_factor)
    L_s = lam * L_m
    U_s = U_m * math.sqrt(lam)
    cf_s = np.array([ittc57(u * L_s / nu_s) for u in U_s])
    dcf = max(0.0, (105.0 * (150e-6 / L_s) ** (1.0 / 3.0) - 0.64) * 1e-3)
    return U_s, (1.0 + k) * cf_s + dcf, k


def _window(t: np.ndarray, t_end: float, span: float) -> np.ndarray:
    return t >= t_end - span - 1e-9 * max(1.0, t_end)


def _pmm_runs(p: FinishedStudy, kind: str, sweep: bool = False) -> list[dict[str, Any]]:
    """Body-axis force time series of each finished PMM run of ``kind`` (fit window and all); the runs of
    the frequency sweep only with ``sweep``."""
    s = p.study
    runs = []
    for job in p.jobs.values():
        if job.kind != kind or (job.params.get("sweep") and not sweep):
            continue
        motion, period, t_end = job.params["motion"], job.params["period"], job.params["t_end"]
        h = read_forces(p.cases / job.name)
        X, Y, N = body_forces(h, motion.y(h.t), motion.psi(h.t))
        sel = _window(h.t, t_end, s.fit_cycles * period)
        runs.append(
            {
                "job": job,
                "motion": motion,
                "t_all": h.t,
                "X_all": X,
                "Y_all": Y,
                "N_all": N,
                "t": h.t[sel],
                "X": X[sel],
                "Y": Y[sel],
                "N": N[sel],
                # standard axes: y and ψ change sign
                "q": -(motion.y(h.t[sel]) if kind == "sway" else motion.psi(h.t[sel])),
                "omega": motion.omega,
                "amplitude": job.params.get("amplitude"),
                "base": not job.params.get("sweep"),
            }
        )
    return runs


def _clean(obj: Any) -> Any:
    """JSON/TOML-friendly copy: numpy to Python, None dropped, tuples to lists."""
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items() if v is not None}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj if v is not None]
    if isinstance(obj, np.ndarray):
        return _clean(obj.tolist())
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else str(obj)
    return obj


def analyse(p: FinishedStudy, plots: bool = True) -> StudyResult:
    """Fit every test, write ``ship.toml`` and ``report/`` (with plots if ``plots``); return the
    :class:`StudyResult`."""
    s = p.study
    hydro = p.hull.hydro
    L, B, T, rho, U = s.lpp, s.bwl, s.tm, s.rho, s.U_ref
    C_B = hydro.volume_m3 / (L * B * T)
    norm = s.normalisation
    si: dict[str, float] = {}
    origin: dict[str, str] = {}
    fits: dict[str, FitResult] = {}
    prov_tests: dict[str, Any] = {}
    steady = {name: j for name, j in p.jobs.items() if j.kind in ("tow", "drift")}

    # -- straight tow: X(u) about U_ref
    tows = sorted((j for j in steady.values() if j.kind == "tow"), key=lambda j: j.params["U"])
    tow_U = np.array([j.params["U"] for j in tows])
    tow_X = np.array([j.summary["X_N"] for j in tows])
    fits["tow"] = fit_resistance(tow_U, tow_X, U_ref_m_s=U, normalisation="SI")
    si.update(fits["tow"].derivatives)
    origin.update({k: "tow" for k in fits["tow"].derivatives})
    if "X_u" not in si:
        si["X_u"] = 2.0 * si["X_0"] / U
        origin["X_u"] = "estimate: resistance proportional to u^2 (one tow speed)"
    ct = -tow_X / (0.5 * rho * hydro.wetted_area_m2 * tow_U**2)
    cf = np.array([ittc57(u * L / s.nu) for u in tow_U])
    prov_tests["tow"] = {
        "speeds_m_s": tow_U,
        "X_N": tow_X,
        "C_T": ct,
        "C_F_ITTC57": cf,
        "Fn": tow_U / math.sqrt(9.81 * L),
        "Re": tow_U * L / s.nu,
        "iterations": [j.summary.get("iterations") for j in tows],
        "converged": [bool(j.summary.get("converged")) for j in tows],
        "yplus_min_max_mean": [j.summary.get("yplus_min_max_mean") for j in tows],
    }

    # -- static drift (β = 0 is the base tow)
    drift = [j for j in steady.values() if j.kind == "drift"]
    if drift:
        base = next(j for j in tows if math.isclose(j.params["U"], U))
        pts = [(0.0, base)] + sorted(((j.params["beta"], j) for j in drift), key=lambda x: x[0])
        beta = np.radians([b for b, _ in pts])
        v = -U * np.sin(beta)  # MMG drift angle: β = −atan(v/u)
        Y = np.array([j.summary["Y_N"] for _, j in pts])
        N = np.array([j.summary["N_Nm"] for _, j in pts])
        X = np.array([j.summary["X_N"] for _, j in pts])
        # A symmetric hull has Y = N = 0 at beta = 0; what the CFD gives there is a numerical bias of the
        # (not exactly symmetric) mesh, removed from every angle before the mirrored fit.
        fit = fit_static_drift(v, Y - Y[0], N - N[0], X_N=X, U_m_s=U, normalisation="SI", symmetric=True)
        fits["drift"] = fit
        # the form written to the ship file is the study's choice (cfd.regression); the others are reported
        forms = fit_forms(v, Y - Y[0], N - N[0], U_m_s=U)
        chosen, why = choose(forms, s.drift_form)
        terms, how = chosen.ship_terms(v[v != 0.0])
        for k, val in {**terms, "X_vv": fit.derivatives.get("X_vv")}.items():
            if val is not None:
                si[k] = val
                origin[k] = "static drift"
        prov_tests["drift"] = {
            "speed_m_s": U,
            "beta_deg": np.degrees(beta),
            "v_m_s": v,
            "X_N": X,
            "Y_N": Y,
            "N_Nm": N,
            "cubic_fit": bool(fit.details["cubic"]),
            "fit": "beta = 0 bias removed, then mirrored about v = 0 (symmetric hull): Y_0 = N_0 = 0",
            "regression": {
                "written": chosen.form,
                "reason": why,
                "conversion": how,
                "spread_SI": spread(forms),
                "forms": {
                    name: {
                        "terms_SI": f.terms,
                        "std_error_SI": f.std_error,
                        "residuals": f.residuals,
                        "runs": f.points,
                    }
                    for name, f in forms.items()
                },
            },
        }

    # -- pure sway and pure yaw
    pmm_runs: dict[str, list[dict[str, Any]]] = {}
    for kind in ("sway", "yaw"):
        runs = _pmm_runs(p, kind)
        if not runs:
            continue
        pmm_runs[kind] = runs
        args = (
            [r["t"] for r in runs],
            [r["q"] for r in runs],
            [r["Y"] for r in runs],
            [r["N"] for r in runs],
        )
        if kind == "sway":
            fit = fit_pure_sway(
                *args, X_N=[r["X"] for r in runs], omega_rad_s=runs[0]["omega"], U_m_s=U, normalisation="SI"
            )
            take = ["Y_vdot", "N_vdot"] + ([] if "drift" in fits else ["Y_v", "N_v"])
        else:
            fit = fit_pure_yaw(
                *args,
                X_N=[r["X"] for r in runs],
                omega_rad_s=runs[0]["omega"],
                U_m_s=U,
                normalisation="SI",
                cubic=len(runs) >= 3,
                X_u_N_s_m=si.get("X_u", 0.0),
            )
            take = ["Y_r", "N_r", "Y_rdot", "N_rdot", "X_rr"] + (["Y_rrr", "N_rrr"] if len(runs) >= 3 else [])
        fits[kind] = fit
        for k in take:
            si[k] = fit.derivatives[k]
            origin[k] = f"pure {kind}" + (" (dynamic)" if k in ("Y_v", "N_v") else "")
        jobs = [r["job"] for r in runs]
        prov_tests[kind] = {
            "speed_m_s": U,
            "period_s": jobs[0].summary.get("period_s"),
            "omega_prime": runs[0]["omega"] * L / U,
            "amplitudes_m": [j.summary.get("y0_m") for j in jobs],
            "cycles": s.cycles,
            "fit_cycles": s.fit_cycles,
            "dt_s": jobs[0].summary.get("dt_s"),
            "fit_SI": {k: v for k, v in fit.derivatives.items()},
        }
        if kind == "yaw":
            prov_tests[kind]["yaw_amplitudes_deg"] = [j.summary.get("psi0_deg") for j in jobs]

    # -- non-dimensional set at model scale
    prime = nondimensionalise(si, rho_kg_m3=rho, L_m=L, U_m_s=U, normalisation=norm)
    clarke = convert_normalisation(clarke83(L, B, T, C_B), "half_rho_L2_U2", norm)
    for k in CLARKE_KEYS:
        if k not in prime:
            prime[k] = clarke[k]
            origin[k] = "Clarke et al. (1983) regression (test not run)"
    x_udot = -soding_surge_added_mass(hydro.volume_m3, L, rho)
    prime["X_udot"] = nondimensionalise(
        {"X_udot": x_udot}, rho_kg_m3=rho, L_m=L, U_m_s=U, normalisation=norm
    )["X_udot"]
    origin["X_udot"] = "Soding (1982) estimate, A11 = 2.7 rho V^(5/3) / L^2"
    model_prime = dict(prime)

    # -- scale and ship file
    template_path = s.template or default_template()
    template = load_template(template_path)
    tparts = template.get("particulars", {})
    lam = scale_factor_to(template, L, s.scale_to)
    rho_out = float(tparts.get("rho_kg_m3", rho)) if lam != 1.0 else rho
    U_out = U * math.sqrt(lam)
    scale_info: dict[str, Any] = {"scale_factor": lam, "U_ref_model_m_s": U, "U_ref_ship_m_s": U_out}
    if lam != 1.0:
        U_res, ct_s, k_form = full_scale_resistance(
            tow_U,
            -tow_X / rho,
            S_m=hydro.wetted_area_m2,
            L_m=L,
            nu_m=s.nu,
            lam=lam,
            nu_s=SEA_WATER_NU,
            form_factor=None if s.form_factor < 0 else s.form_factor,
        )
        R_res = ct_s * 0.5 * rho_out * hydro.wetted_area_m2 * lam**2 * U_res**2
        scale_info.update({"form_factor_k": k_form, "C_T_ship": ct_s, "U_ship_m_s": U_res, "R_ship_N": R_res})
        how = "tow, extrapolated to ship scale (ITTC-1978 form factor method)"
    else:
        U_res, R_res, how = tow_U, -tow_X, "tow"
    # The simulator's resistance law is R0 (u/U_ref)|u/U_ref| (resistance_N, resistance_speed_m_s); X_u and
    # X_uu carry what the CFD curve adds to it: dX/du = -2 R0/U_ref and (1/2) d2X/du2 = -R0/U_ref^2 for that law.
    res = fit_resistance(U_res, -R_res, U_ref_m_s=U_out, normalisation="SI").derivatives
    R0 = -res["X_0"]
    corr = {}
    if "X_u" in res:
        corr["X_u"] = res["X_u"] + 2.0 * R0 / U_out
    if "X_uu" in res:
        corr["X_uu"] = res["X_uu"] + R0 / U_out**2
    for k in ("X_0", "X_u", "X_uu"):
        prime.pop(k, None)
    prime.update(nondimensionalise(corr, rho_kg_m3=rho_out, L_m=L * lam, U_m_s=U_out, normalisation=norm))
    ship_origin = {**origin, **{k: how + ", beyond the u|u| resistance law" for k in corr}}
    if tparts.get("k_zz_m") and tparts.get("L_m"):
        kzz_ratio = float(tparts["k_zz_m"]) / float(tparts["L_m"])
    elif tparts.get("I_zG_kgm2") and tparts.get("L_m"):
        mass_t = float(
            tparts.get("mass_kg") or tparts.get("displacement_m3", 0) * tparts.get("rho_kg_m3", 1025.0)
        )
        kzz_ratio = math.sqrt(float(tparts["I_zG_kgm2"]) / mass_t) / float(tparts["L_m"]) if mass_t else 0.25
    else:
        kzz_ratio = 0.25
    k_zz = s.k_zz or kzz_ratio * L
    particulars = {
        "L_m": L * lam,
        "B_m": B * lam,
        "T_m": T * lam,
        "displacement_m3": hydro.volume_m3 * lam**3,
        "x_G_m": hydro.lcb_m * lam,
        "k_zz_m": k_zz * lam,
        "rho_kg_m3": rho_out,
        "C_b": C_B,
    }
    if lam == 1.0 or "test_speed_kn" not in tparts:
        particulars["test_speed_kn"] = U_out * 3600.0 / 1852.0
    derivatives = {k: float(prime[k]) for k in SHIP_KEYS if k in prime}

    borrowed, borrowed_info = borrowed_note(template, template_path, L, lam)
    gate = verify(p, {k: ship_origin.get(k, origin.get(k, "")) for k in {**origin, **derivatives}})
    spec = p.spec
    mesh = p.jobs["mesh"].summary
    hull_src = "wigley (generated, parabolic Wigley)" if s.hull == "wigley" else str(s.hull)
    hull_sha = hashlib.sha256((p.cases / "hull.stl").read_bytes()).hexdigest()
    provenance = {
        "tool": f"vessel-cfd {__version__}",
        "openfoam": "OpenFOAM v1912 (openfoam.com), Debian package",
        "hull": {
            "source": hull_src,
            "case_stl_sha256": hull_sha,
            "Lpp_m": L,
            "B_m": B,
            "T_m": T,
            "C_B": C_B,
            "volume_m3": hydro.volume_m3,
            "wetted_area_m2": hydro.wetted_area_m2,
            "lcb_m": hydro.lcb_m,
            "mirrored_half_hull": p.hull.mirrored,
        },
        "mesh": {
            "grading": s.grading,
            "grading_name": GRADINGS[s.grading],
            "cells": mesh.get("cells"),
            "hull_faces": mesh.get("hull_faces"),
            "checkMesh_ok": mesh.get("ok"),
            "checkMesh_warnings": mesh.get("warnings", []),
            "max_non_orthogonality": mesh.get("max_non_orthogonality"),
            "max_skewness": mesh.get("max_skewness"),
            "background_cell_m": spec.h0,
            "hull_cell_m": spec.h_hull,
            "hull_level": spec.hull_level,
            "boxes": {b.name: b.level for b in spec.boxes},
            "boundary_layers": spec.n_layers,
            "first_layer_m": spec.first_layer_m,
            "sizing": s.sizing,
        },
        "solver": {
            "flow": "double body (symmetry plane at the waterline), incompressible RANS, k-omega SST, "
            "nutUSpaldingWallFunction",
            "steady": f"simpleFoam SIMPLEC, linearUpwind U, upwind k/omega, at most {s.steady_iterations} "
            "iterations, residualControl p 1e-5",
            "transient": "pimpleFoam, Euler, 2 outer x 2 pressure correctors, solid-body mesh motion "
            "(tabulated6DoFMotion), start from the converged tow",
            "rho_kg_m3": rho,
            "nu_m2_s": s.nu,
            "Re_ref": U * L / s.nu,
            "Fn_ref": U / math.sqrt(9.81 * L),
        },
        "tests": prov_tests,
        "fit_residuals": {name: f.residuals for name, f in fits.items()},
        "derivative_origin": {k: ship_origin.get(k, "") for k in derivatives},
        "model_scale_derivatives": {k: model_prime[k] for k in derivatives if k in model_prime},
        "clarke83": {k: clarke[k] for k in CLARKE_KEYS},
        "scale": {**scale_info, "resistance_N": R0, "resistance_speed_m_s": U_out},
        "template": str(template_path) if template_path else "none (hull-only ship file)",
        "borrowed": borrowed_info,
        "wall_time_s": {k: round(v, 1) for k, v in p.wall_s.items()},
        "verification": {k: gate[k] for k in ("verdict", "failures", "derivatives")},
    }
    if "sway" in fits:
        dyn = nondimensionalise(
            {k: fits["sway"].derivatives[k] for k in ("Y_v", "N_v")},
            rho_kg_m3=rho,
            L_m=L,
            U_m_s=U,
            normalisation=norm,
        )
        provenance["dynamic_sway"] = {"Y_v": dyn["Y_v"], "N_v": dyn["N_v"]}
    # each amplitude on its own and each frequency of the sweep (cfd.pmm_sweep): the spread per derivative
    dep = dependence(
        {kind: _pmm_runs(p, kind, sweep=True) for kind in pmm_runs}, U=U, L=L, rho=rho, normalisation=norm
    )
    if dep:
        provenance["pmm_dependence"] = dep
    name = s.name or (
        f"{Path(s.hull).name.split('.')[0]} (vessel-cfd)" if s.hull != "wigley" else "Wigley (vessel-cfd)"
    )
    source = {
        "citation": "Derivatives from double-body RANS captive tests (OpenFOAM v1912, k-omega SST) run by "
        f"vessel-cfd {__version__}, after the seed report's PMM method (static drift, pure sway, "
        "pure yaw); estimates: Clarke, Gedling & Hine (1983) Trans. RINA 125, Soding (1982).",
        "notes": (
            "Standard body axes x forward, y starboard, z down; r > 0 to starboard; origin at midship "
            "(half-way between the perpendiculars) in the waterplane. "
            f"Normalisation {norm}. Surge terms are a Taylor expansion about U_ref: "
            "X = X_0 + X_u (u-U) + X_uu (u-U)^2 + X_vv v^2 + X_rr r^2. "
            f"Verification gate: {gate['verdict']}"
            + (
                f" ({len(gate['failures'])} checks failed, see [source.provenance.verification]). "
                if gate["failures"]
                else ". "
            )
            + "Double-body flow: no wave resistance or free-surface effects. "
            + (
                f"Hull scaled by {lam:.6g} from the CFD model (L = {L:g} m) to the template's length; "
                "non-dimensional sway/yaw derivatives kept, resistance extrapolated with the ITTC-1978 "
                "form factor method. "
                if lam != 1.0
                else ""
            )
            + "x_G is the centre of buoyancy of the hull. "
            + borrowed
            + " [source.provenance] says which test gave each derivative."
        ),
        "sign_convention": "Standard body axes (x forward, y starboard, z down). OpenFOAM's case frame (y to port, "
        "z up) is converted with Y = -Fy, N = -Mz, v = -v_case, r = -r_case; Y_v, N_v, N_r < 0 and Y_r > 0 "
        "come out of the CFD, not from a convention.",
        "provenance": _clean(provenance),
    }
    hull_table = {
        "model": "abkowitz",
        "normalisation": norm,
        "U_ref_m_s": U_out,
        "coriolis": "separate",
        "resistance_N": R0,
        "resistance_speed_m_s": U_out,
        "derivatives": derivatives,
    }
    ship = build_ship(template, name=name, source=source, particulars=particulars, hull=hull_table)
    if "heel" in s.tests:  # the roll terms of a 4-DOF ship (cfd.heel)
        ship["roll"], provenance["heel"] = roll_results(p.jobs, template, particulars, s, lam)
        ship["source"]["provenance"]["heel"] = _clean(provenance["heel"])
    ship_file = write_ship(
        p.out / "ship.toml", ship, header=f"Ship file written by vessel-cfd {__version__}."
    )
    problem = validate_ship(ship_file)

    report_dir = p.out / "report"
    report_dir.mkdir(parents=True, exist_ok=True)
    (report_dir / "derivatives.json").write_text(
        json.dumps(
            _clean(
                {
                    "normalisation": norm,
                    "U_ref_m_s": U,
                    "L_m": L,
                    "rho_kg_m3": rho,
                    "model_scale": model_prime,
                    "ship_file": derivatives,
                    "SI_model_scale": si,
                    "mmg_half_rho_L_d_U2": nondimensionalise(
                        {**si, "X_udot": x_udot},
                        rho_kg_m3=rho,
                        L_m=L,
                        U_m_s=U,
                        normalisation="half_rho_L_d_U2",
                        T_m=T,
                    ),
                    "clarke83": clarke,
                    "origin": origin,
                    "fit_residuals": {k: f.residuals for k, f in fits.items()},
                    "dynamic_sway": provenance.get("dynamic_sway"),
                    "verification": gate,
                    "provenance": provenance,
                }
            ),
            indent=1,
        )
    )
    write_report(
        report_dir,
        p,
        plots=plots,
        fits=fits,
        pmm_runs=pmm_runs,
        model_prime=model_prime,
        clarke=clarke,
        origin=origin,
        provenance=provenance,
        verification=gate,
    )
    if problem:
        raise CfdError("ship file check", f"vessel-gym cannot load the ship file: {problem}", ship_file)
    return StudyResult(ship_file, report_dir, derivatives, norm, provenance, gate, borrowed)
