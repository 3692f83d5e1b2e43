"""Regression forms of the static-drift side force and yaw moment (pure numpy).

The same oblique-tow data fit three ways, each with its residual and the standard error of every term:

- ``abkowitz``: Y = Y_v v + Y_vvv v³ (Abkowitz 1964; odd polynomial);
- ``mmg``: Y = Y_v v + Y_v|v| v|v| (the quadratic cross-flow form of the early MMG model, Inoue et al.
  1981, and of Norrbin's); the key of the |v| term here is ``Y_v|v|``;
- ``linear``: Y = Y_v v from the small drift angles only (|β| ≤ :data:`SMALL_ANGLE_DEG`), the linear
  derivative without any nonlinear term to trade against.

N likewise. Inputs are the one-sided drift runs with the β = 0 bias already removed (so the fits pass
through the origin, as the mirrored fit of :func:`cfd.fitting.fit_static_drift` does).

The simulator's hull models hold polynomials only, so a ``mmg`` fit is written to a ship file as its
linear term and the cubic that matches c·v|v| best, in least squares over the tested sway velocities:
Y_vvv = Y_v|v| Σ v|v|·v³ / Σ v⁶. The relative rms difference of that cubic from the quadratic term is
reported with it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

FORMS = ("abkowitz", "mmg", "linear")
CHOICES = (*FORMS, "auto")  # auto: the nonlinear form with the lower residual
DEFAULT = "abkowitz"  # the ship file's hull model is the Abkowitz polynomial: Y_vvv goes in without change
SMALL_ANGLE_DEG = 5.0  # deg; drift angles of the linear fit (where v³ is under 1 % of v at U = 1)


@dataclass(frozen=True)
class FormFit:
    """One regression form of the static drift, in SI (Y_v in N·s/m, Y_vvv in N·s³/m³, Y_v|v| in N·s²/m²)."""

    form: str
    terms: dict[str, float]
    std_error: dict[str, float | None]  # 1 sigma of each term; None when the fit has no degree of freedom
    residuals: dict[str, float]  # rms residual / rms force, Y and N
    points: int  # drift runs used

    def ship_terms(self, v_m_s: np.ndarray) -> tuple[dict[str, float], str]:
        """The polynomial terms the ship file can hold, and how they were made from this form."""
        if self.form != "mmg":
            return dict(self.terms), "as fitted"
        v = np.asarray(v_m_s, dtype=float)
        quad, cube = v * np.abs(v), v**3
        c = float(np.sum(quad * cube) / np.sum(cube * cube))
        mismatch = float(np.sqrt(np.mean((quad - c * cube) ** 2) / np.mean(quad**2)))
        out = {}
        for F in ("Y", "N"):
            out[f"{F}_v"] = self.terms[f"{F}_v"]
            out[f"{F}_vvv"] = c * self.terms[f"{F}_v|v|"]
        return out, (
            f"v|v| terms written as the least-squares cubic over the tested v (Y_vvv = {c:.6g} Y_v|v| in SI; "
            f"rms difference {100 * mismatch:.1f} % of the quadratic term)"
        )


def _fit(columns: list[np.ndarray], names: list[str], v: np.ndarray, Y: np.ndarray, N: np.ndarray, form: str):
    A = np.column_stack(columns)
    terms: dict[str, float] = {}
    errors: dict[str, float | None] = {}
    residuals: dict[str, float] = {}
    dof = A.shape[0] - A.shape[1]
    for F, y in (("Y", Y), ("N", N)):
        coef, *_ = np.linalg.lstsq(A, y, rcond=None)
        res = y - A @ coef
        scale = float(np.sqrt(np.mean(y**2)))
        residuals[F] = float(np.sqrt(np.mean(res**2)) / scale) if scale > 0 else 0.0
        cov = np.linalg.pinv(A.T @ A) * (float(res @ res) / dof) if dof > 0 else None
        for i, name in enumerate(names):
            terms[f"{F}_{name}"] = float(coef[i])
            errors[f"{F}_{name}"] = float(np.sqrt(cov[i, i])) if cov is not None else None
    return FormFit(form, terms, errors, residuals, len(v))


def fit_forms(v_m_s, Y_N, N_Nm, *, U_m_s: float) -> dict[str, FormFit]:
    """Every form that the data determine: the nonlinear ones need three drift angles (one degree of
    freedom), the linear one at least one angle (the smallest when none is at or under SMALL_ANGLE_DEG)."""
    v, Y, N = (np.asarray(a, dtype=float) for a in (v_m_s, Y_N, N_Nm))
    keep = v != 0.0  # the beta = 0 run is the origin of every form
    v, Y, N = v[keep], Y[keep], N[keep]
    if len(v) == 0:
        raise ValueError("static drift needs at least one non-zero drift angle")
    forms: dict[str, FormFit] = {}
    if len(v) >= 3:
        forms["abkowitz"] = _fit([v, v**3], ["v", "vvv"], v, Y, N, "abkowitz")
        forms["mmg"] = _fit([v, v * np.abs(v)], ["v", "v|v|"], v, Y, N, "mmg")
    beta = np.degrees(np.arcsin(np.clip(np.abs(v) / U_m_s, 0.0, 1.0)))
    small = beta <= SMALL_ANGLE_DEG + 1e-9
    if not small.any():
        small = beta == beta.min()
    forms["linear"] = _fit([v[small]], ["v"], v[small], Y[small], N[small], "linear")
    return forms


def choose(forms: dict[str, FormFit], option: str) -> tuple[FormFit, str]:
    """The form written to the ship file for ``option`` (one of :data:`CHOICES`) and why."""
    if option == "auto":
        nonlinear = [f for f in forms.values() if f.form != "linear"]
        if not nonlinear:
            return forms["linear"], "auto: fewer than three drift angles, so the linear fit"
        best = min(nonlinear, key=lambda f: f.residuals["Y"] + f.residuals["N"])
        return best, "auto: the nonlinear form with the lowest residual (Y + N)"
    if option in forms:
        reason = (
            "default: the ship file's Abkowitz hull holds Y_vvv as fitted" if option == DEFAULT else "chosen"
        )
        return forms[option], reason
    if option in ("abkowitz", "mmg"):  # too few angles for a nonlinear fit
        return forms["linear"], f"{option} needs three drift angles; the linear fit is written"
    raise ValueError(f"drift_form must be one of {', '.join(CHOICES)} (got {option!r})")


def spread(forms: dict[str, FormFit]) -> dict[str, float]:
    """max − min of the linear derivatives Y_v and N_v over the forms (SI): how much the choice matters."""
    return {k: float(np.ptp([f.terms[k] for f in forms.values()])) for k in ("Y_v", "N_v")}
