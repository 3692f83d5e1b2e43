"""Least-squares fits of captive-test forces to manoeuvring derivatives (pure numpy).

This module has no OpenFOAM, file or plotting dependency: the same functions fit CFD results
and a simulator's captive ("virtual PMM") runs.

Conventions for every function here
-----------------------------------
* Standard body axes: x forward, y starboard, z down; r > 0 turning to starboard; ψ > 0 bow to
  starboard. Moments are about the body-axes origin (midship for ship files).
* Inputs are dimensional SI: time s, position m, angle rad, speed m/s, force N, moment N·m.
  Forces are the *hydrodynamic* forces (no rigid-body inertia m·v̇ in them), in body axes.
* Derivative names are the literature names in ASCII: the letters after ``_`` are the motion
  variables whose product multiplies the coefficient, ``dot`` marks an acceleration and ``0`` a
  constant, e.g. ``Y = Y_0 + Y_v v + Y_vvv v³ + Y_vdot v̇``. Surge terms are a Taylor expansion
  about the reference speed, ``X = X_0 + X_u (u − U) + X_uu (u − U)² + X_vv v² + X_rr r²``.
* Results come as :class:`FitResult` whose ``derivatives`` dict is in the stated
  ``normalisation``:

  - ``"SI"``: dimensional (Y_v in N·s/m, Y_vdot in N·s²/m, N_r in N·m·s, ...);
  - ``"rho_L2_U2"`` (seed report eq. 5–9): force/(ρU²L²), moment/(ρU²L³), u' = v' = v/U, r' = rL/U,
    v̇' = v̇L/U², ṙ' = ṙL²/U²;
  - ``"half_rho_L2_U2"`` (SNAME prime system, Clarke 1983): as above with ½ρ instead of ρ;
  - ``"half_rho_L_d_U2"`` (MMG, Yasukawa & Yoshimura 2015): force/(½ρLdU²), moment/(½ρL²dU²) with the
    draught d; only through :func:`nondimensionalise` / :func:`dimensionalise` (pass ``T_m``).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

NORMALISATIONS = ("SI", "rho_L2_U2", "half_rho_L2_U2", "half_rho_L_d_U2")
SHIP_NORMALISATIONS = ("rho_L2_U2", "half_rho_L2_U2")  # the prime systems of ship files

_KEY = re.compile(r"^([XYNK])_(0|[uvrdp]+|[uvrp]dot)$")


# ---------------------------------------------------------------------------------- normalisation
def key_variables(key: str) -> tuple[str, tuple[str, ...]]:
    """Split a derivative name into its force letter and motion variables.

    ``"Y_vvr"`` -> ``("Y", ("v", "v", "r"))``, ``"N_rdot"`` -> ``("N", ("rdot",))``,
    ``"X_0"`` -> ``("X", ())``. ``d`` is the rudder angle δ (rad, scale 1).
    """
    m = _KEY.match(key)
    if not m:
        raise ValueError(f"not a derivative name: {key!r}")
    force, body = m.groups()
    if body == "0":
        return force, ()
    if body.endswith("dot"):
        return force, (body,)
    return force, tuple(body)


def scale_factor(
    key: str, *, rho_kg_m3: float, L_m: float, U_m_s: float, normalisation: str, T_m: float | None = None
) -> float:
    """Factor f with ``prime = f × SI`` for the derivative ``key``.

    With F = C·Πxᵢ and the scales F₀ (ρU²L² for X, Y; ρU²L³ for N and K; halved for
    ``half_rho_L2_U2``; ½ρU²L·d and ½ρU²L²·d for the MMG ``half_rho_L_d_U2``, which needs the
    draught ``T_m``) and x₀ (u, v: U; r, p: U/L; u̇, v̇: U²/L; ṙ, ṗ: U²/L²; δ: 1), C' = C·Πx₀ᵢ / F₀.
    """
    if normalisation not in NORMALISATIONS:
        raise ValueError(f"normalisation must be one of {NORMALISATIONS} (got {normalisation!r})")
    if normalisation == "SI":
        return 1.0
    if min(rho_kg_m3, L_m, U_m_s) <= 0:
        raise ValueError(f"rho, L and U must be > 0 (got {rho_kg_m3}, {L_m}, {U_m_s})")
    force, variables = key_variables(key)
    U, L = U_m_s, L_m
    f0 = rho_kg_m3 * U**2 * L**2 * (L if force in "NK" else 1.0)
    if normalisation == "half_rho_L2_U2":
        f0 *= 0.5
    elif normalisation == "half_rho_L_d_U2":
        if T_m is None or T_m <= 0:
            raise ValueError("the MMG normalisation half_rho_L_d_U2 needs the draught T_m > 0")
        f0 *= 0.5 * T_m / L
    var_scale = {
        "u": U,
        "v": U,
        "r": U / L,
        "p": U / L,
        "d": 1.0,
        "udot": U**2 / L,
        "vdot": U**2 / L,
        "rdot": U**2 / L**2,
        "pdot": U**2 / L**2,
    }
    prod = 1.0
    for v in variables:
        prod *= var_scale[v]
    return prod / f0


def nondimensionalise(
    derivatives: Mapping[str, float],
    *,
    rho_kg_m3: float,
    L_m: float,
    U_m_s: float,
    normalisation: str = "rho_L2_U2",
    T_m: float | None = None,
) -> dict[str, float]:
    """Convert dimensional (SI) derivatives to ``normalisation`` (see the module docstring)."""
    return {
        k: float(v)
        * scale_factor(k, rho_kg_m3=rho_kg_m3, L_m=L_m, U_m_s=U_m_s, normalisation=normalisation, T_m=T_m)
        for k, v in derivatives.items()
    }


def dimensionalise(
    derivatives: Mapping[str, float],
    *,
    rho_kg_m3: float,
    L_m: float,
    U_m_s: float,
    normalisation: str = "rho_L2_U2",
    T_m: float | None = None,
) -> dict[str, float]:
    """Inverse of :func:`nondimensionalise`: prime values in ``normalisation`` to SI."""
    return {
        k: float(v)
        / scale_factor(k, rho_kg_m3=rho_kg_m3, L_m=L_m, U_m_s=U_m_s, normalisation=normalisation, T_m=T_m)
        for k, v in derivatives.items()
    }


def convert_normalisation(derivatives: Mapping[str, float], source: str, target: str) -> dict[str, float]:
    """Convert prime values between ``"rho_L2_U2"`` and ``"half_rho_L2_U2"`` (a factor 2)."""
    for n in (source, target):
        if n not in SHIP_NORMALISATIONS:
            raise ValueError(f"normalisation must be one of {SHIP_NORMALISATIONS} (got {n!r})")
    f = 1.0 if source == target else (2.0 if target == "half_rho_L2_U2" else 0.5)
    return {k: float(v) * f for k, v in derivatives.items()}


# ---------------------------------------------------------------------------------- results
@dataclass(frozen=True)
class FitResult:
    """Fitted derivatives with fit quality.

    ``derivatives``: name -> value in ``normalisation``. ``residuals``: per force ("X", "Y", "N"),
    the rms of the fit residual divided by the rms of the force (0 = perfect fit).
    ``details``: quantities for plots and reports (amplitudes, harmonic components), SI units.
    """

    derivatives: dict[str, float]
    normalisation: str
    residuals: dict[str, float] = field(default_factory=dict)
    details: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Harmonic:
    """x(t) ≈ mean + Σₖ a[k]·sin(k ω t) + b[k]·cos(k ω t), k = 1..n."""

    omega: float
    mean: float
    a: np.ndarray  # sine coefficients, k = 1..n
    b: np.ndarray  # cosine coefficients
    rms_residual: float

    def evaluate(self, t: np.ndarray, derivative: int = 0) -> np.ndarray:
        """The fitted signal or its ``derivative``-th time derivative at times ``t``."""
        t = np.asarray(t, dtype=float)
        out = np.full_like(t, self.mean if derivative == 0 else 0.0)
        for k, (ak, bk) in enumerate(zip(self.a, self.b, strict=True), start=1):
            w = k * self.omega
            # d^n/dt^n of sin and cos cycle with period 4
            s, c = np.sin(w * t), np.cos(w * t)
            d = derivative % 4
            ds = (s, c, -s, -c)[d]
            dc = (c, -s, -c, s)[d]
            out = out + w**derivative * (ak * ds + bk * dc)
        return out

    @property
    def amplitude(self) -> float:
        """Amplitude of the first harmonic."""
        return float(np.hypot(self.a[0], self.b[0]))

    @property
    def phase(self) -> float:
        """φ with first harmonic = amplitude·sin(ωt + φ)."""
        return float(np.arctan2(self.b[0], self.a[0]))


def harmonic_fit(t_s: np.ndarray, x: np.ndarray, omega_rad_s: float, n_harmonics: int = 1) -> Harmonic:
    """Least-squares fit of a mean plus ``n_harmonics`` harmonics of ``omega_rad_s`` to x(t)."""
    t = np.asarray(t_s, dtype=float)
    x = np.asarray(x, dtype=float)
    _check_series(t, x, "x")
    if omega_rad_s <= 0:
        raise ValueError(f"omega must be > 0 rad/s (got {omega_rad_s})")
    cols = [np.ones_like(t)]
    for k in range(1, n_harmonics + 1):
        cols += [np.sin(k * omega_rad_s * t), np.cos(k * omega_rad_s * t)]
    A = np.column_stack(cols)
    coef, *_ = np.linalg.lstsq(A, x, rcond=None)
    res = x - A @ coef
    return Harmonic(
        float(omega_rad_s),
        float(coef[0]),
        coef[1::2].copy(),
        coef[2::2].copy(),
        float(np.sqrt(np.mean(res**2))),
    )


def _check_series(t: np.ndarray, x: np.ndarray, name: str) -> None:
    if t.ndim != 1 or x.shape != t.shape:
        raise ValueError(f"{name} must be a 1-D array of the same length as t ({x.shape} vs {t.shape})")
    if len(t) < 4 or not (np.all(np.isfinite(t)) and np.all(np.isfinite(x))):
        raise ValueError(f"{name}: need at least 4 finite samples")


def _lstsq(columns: Sequence[np.ndarray], y: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
    """Coefficients, relative rms residual and residual of y ≈ Σ cᵢ·columnsᵢ."""
    A = np.column_stack(columns)
    if A.shape[0] < A.shape[1]:
        raise ValueError(f"{A.shape[0]} samples cannot determine {A.shape[1]} coefficients")
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    res = y - A @ coef
    scale = float(np.sqrt(np.mean(y**2)))
    rel = float(np.sqrt(np.mean(res**2)) / scale) if scale > 0 else 0.0
    return coef, rel, res


def _as_runs(*arrays: Any) -> list[list[np.ndarray]]:
    """Accept one run (1-D arrays) or several runs (lists of 1-D arrays); return per-array run lists."""
    first = arrays[0]
    multi = isinstance(first, (list, tuple)) and len(first) > 0 and np.ndim(first[0]) == 1
    out = []
    for a in arrays:
        if a is None:
            out.append(None)
            continue
        runs = [np.asarray(r, dtype=float) for r in a] if multi else [np.asarray(a, dtype=float)]
        out.append(runs)
    n = len(out[0])
    for name, runs in zip("tabcde", out, strict=False):
        if runs is not None and len(runs) != n:
            raise ValueError(f"argument {name}: {len(runs)} runs where t has {n}")
    return out


def _finish(
    si: dict[str, float],
    normalisation: str,
    rho: float | None,
    L: float | None,
    U: float,
    residuals: dict[str, float],
    details: dict[str, Any],
) -> FitResult:
    if normalisation == "SI":
        derivs = dict(si)
    elif normalisation not in SHIP_NORMALISATIONS:
        raise ValueError(f"fits give SI or one of {SHIP_NORMALISATIONS}; use nondimensionalise() for MMG")
    else:
        if rho is None or L is None:
            raise ValueError(f"normalisation {normalisation!r} needs rho_kg_m3 and L_m")
        derivs = nondimensionalise(si, rho_kg_m3=rho, L_m=L, U_m_s=U, normalisation=normalisation)
    return FitResult(derivs, normalisation, residuals, details)


# ---------------------------------------------------------------------------------- steady tests
def fit_resistance(
    U_m_s: Sequence[float],
    X_N: Sequence[float],
    *,
    U_ref_m_s: float,
    L_m: float | None = None,
    rho_kg_m3: float | None = None,
    normalisation: str = "rho_L2_U2",
    order: int | None = None,
) -> FitResult:
    """Surge force of straight-ahead tows at several speeds: X = X_0 + X_u Δu + X_uu Δu², Δu = u − U_ref.

    ``X_N`` is the surge force on the hull (negative: resistance). ``order`` is the polynomial
    degree (default: number of distinct speeds − 1, at most 2). One speed gives X_0 only.
    """
    u = np.asarray(U_m_s, dtype=float)
    X = np.asarray(X_N, dtype=float)
    if u.ndim != 1 or u.shape != X.shape or len(u) == 0:
        raise ValueError("U_m_s and X_N must be 1-D arrays of the same non-zero length")
    if U_ref_m_s <= 0 or np.any(u <= 0):
        raise ValueError("speeds must be > 0 m/s")
    n_distinct = len(np.unique(np.round(u, 12)))
    deg = min(n_distinct - 1, 2) if order is None else order
    if deg > n_distinct - 1:
        raise ValueError(f"order {deg} needs at least {deg + 1} distinct speeds (got {n_distinct})")
    du = u - U_ref_m_s
    cols = [du**k for k in range(deg + 1)]
    coef, rel, _ = _lstsq(cols, X)
    names = ["X_0", "X_u", "X_uu"][: deg + 1]
    si = dict(zip(names, map(float, coef), strict=True))
    return _finish(si, normalisation, rho_kg_m3, L_m, U_ref_m_s, {"X": rel}, {"U_m_s": u, "X_N": X})


def fit_static_drift(
    v_m_s: Sequence[float],
    Y_N: Sequence[float],
    N_Nm: Sequence[float],
    *,
    U_m_s: float,
    L_m: float | None = None,
    rho_kg_m3: float | None = None,
    X_N: Sequence[float] | None = None,
    normalisation: str = "rho_L2_U2",
    cubic: bool | None = None,
    symmetric: bool = False,
) -> FitResult:
    """Static drift (oblique tow) at speed U: Y = Y_0 + Y_v v + Y_vvv v³, N likewise, X = X_0 + X_vv v².

    ``v_m_s`` is the body-axes sway velocity of each steady run (for drift angle β with the MMG
    convention β = −atan(v/u): v = −U sin β). ``cubic`` adds Y_vvv and N_vvv (default: when there are
    at least three distinct non-zero |v|). ``symmetric=True`` states that the hull is port-starboard
    symmetric: every run is mirrored (−v, −Y, −N, X), so Y_0 = N_0 = 0 and one-sided data cannot
    trade the offset against the slope. Returns Y_0, Y_v, N_0, N_v (+ Y_vvv, N_vvv, X_0, X_vv).
    """
    v = np.asarray(v_m_s, dtype=float)
    Y = np.asarray(Y_N, dtype=float)
    N = np.asarray(N_Nm, dtype=float)
    if v.ndim != 1 or Y.shape != v.shape or N.shape != v.shape:
        raise ValueError("v_m_s, Y_N and N_Nm must be 1-D arrays of the same length")
    X_in = None if X_N is None else np.asarray(X_N, dtype=float)
    if symmetric:
        v, Y, N = np.concatenate([v, -v]), np.concatenate([Y, -Y]), np.concatenate([N, -N])
        X_in = None if X_in is None else np.concatenate([X_in, X_in])
    n_distinct = len(np.unique(np.round(v, 12)))
    n_nonzero = len(np.unique(np.round(np.abs(v[v != 0]), 12)))
    if n_distinct < 2:
        raise ValueError("static drift needs at least two distinct sway velocities")
    use_cubic = (n_nonzero >= 3) if cubic is None else cubic
    if use_cubic and n_distinct < 3:
        raise ValueError("a cubic fit needs at least three distinct sway velocities")
    cols = [np.ones_like(v), v] + ([v**3] if use_cubic else [])
    si: dict[str, float] = {}
    residuals: dict[str, float] = {}
    for name, F in (("Y", Y), ("N", N)):
        coef, residuals[name], _ = _lstsq(cols, F)
        si[f"{name}_0"], si[f"{name}_v"] = float(coef[0]), float(coef[1])
        if use_cubic:
            si[f"{name}_vvv"] = float(coef[2])
    if X_in is not None:
        coef, residuals["X"], _ = _lstsq([np.ones_like(v), v**2], X_in)
        si["X_0"], si["X_vv"] = float(coef[0]), float(coef[1])
    details = {"v_m_s": v, "Y_N": Y, "N_Nm": N, "cubic": use_cubic}
    return _finish(si, normalisation, rho_kg_m3, L_m, U_m_s, residuals, details)


# ---------------------------------------------------------------------------------- dynamic tests
def _dynamic_fit(
    kind: str,
    t_runs,
    q_runs,
    Y_runs,
    N_runs,
    X_runs,
    *,
    omega: float,
    U: float,
    L,
    rho,
    normalisation: str,
    n_harmonics: int,
    cubic: bool,
    X_u: float,
) -> FitResult:
    var, acc = ("v", "vdot") if kind == "sway" else ("r", "rdot")
    cols: dict[str, list[np.ndarray]] = {"1": [], var: [], acc: [], "cube": [], "sq": []}
    Ys, Ns, Xs, runs = [], [], [], []
    for i, (t, q, Yf, Nf) in enumerate(zip(t_runs, q_runs, Y_runs, N_runs, strict=True)):
        _check_series(t, q, "motion")
        _check_series(t, Yf, "Y")
        _check_series(t, Nf, "N")
        h = harmonic_fit(t, q, omega, n_harmonics)
        x1, x2 = h.evaluate(t, 1), h.evaluate(t, 2)
        cols["1"].append(np.ones_like(t))
        cols[var].append(x1)
        cols[acc].append(x2)
        cols["cube"].append(x1**3)
        cols["sq"].append(x1**2)
        Ys.append(Yf)
        Ns.append(Nf)
        if X_runs is not None:
            Xf = np.asarray(X_runs[i], dtype=float)
            _check_series(t, Xf, "X")
            if kind == "yaw" and X_u:
                # on the tangent path of pure yaw the body surge speed is U / cos ψ
                Xf = Xf - X_u * U * (1.0 / np.cos(h.evaluate(t)) - 1.0)
            Xs.append(Xf)
        hY, hN = harmonic_fit(t, Yf, omega, 1), harmonic_fit(t, Nf, omega, 1)
        # first-harmonic force components in phase with the velocity (cos) and acceleration (−sin)
        ph = h.phase
        runs.append(
            {
                "amplitude": h.amplitude,
                f"{var}_amplitude": h.amplitude * omega,
                f"{acc}_amplitude": h.amplitude * omega**2,
                "motion_rms_residual": h.rms_residual,
                "Y_in_phase_velocity": _component(hY, ph, "cos"),
                "Y_in_phase_acceleration": _component(hY, ph, "-sin"),
                "N_in_phase_velocity": _component(hN, ph, "cos"),
                "N_in_phase_acceleration": _component(hN, ph, "-sin"),
            }
        )
    cat = {k: np.concatenate(v) for k, v in cols.items()}
    base = [cat["1"], cat[var], cat[acc]] + ([cat["cube"]] if cubic else [])
    si: dict[str, float] = {}
    residuals: dict[str, float] = {}
    for name, F in (("Y", np.concatenate(Ys)), ("N", np.concatenate(Ns))):
        coef, residuals[name], _ = _lstsq(base, F)
        si[f"{name}_0"], si[f"{name}_{var}"], si[f"{name}_{acc}"] = map(float, coef[:3])
        if cubic:
            si[f"{name}_{var * 3}"] = float(coef[3])
    if Xs:
        coef, residuals["X"], _ = _lstsq([cat["1"], cat["sq"]], np.concatenate(Xs))
        si["X_0"], si[f"X_{var * 2}"] = float(coef[0]), float(coef[1])
    return _finish(si, normalisation, rho, L, U, residuals, {"runs": runs, "omega_rad_s": omega})


def _component(h: Harmonic, phase: float, which: str) -> float:
    """Coefficient of cos(ωt+φ) (``"cos"``) or of −sin(ωt+φ) (``"-sin"``) in a first-harmonic fit."""
    # a sin ωt + b cos ωt = A sin(ωt+φ) + B cos(ωt+φ) with A = a cos φ + b sin φ, B = b cos φ − a sin φ
    a, b = h.a[0], h.b[0]
    if which == "cos":
        return float(b * np.cos(phase) - a * np.sin(phase))
    return float(-(a * np.cos(phase) + b * np.sin(phase)))


def fit_pure_sway(
    t_s,
    y_m,
    Y_N,
    N_Nm,
    *,
    omega_rad_s: float,
    U_m_s: float,
    L_m: float | None = None,
    rho_kg_m3: float | None = None,
    X_N=None,
    normalisation: str = "rho_L2_U2",
    n_harmonics: int = 3,
    cubic: bool = False,
) -> FitResult:
    """Pure sway at forward speed U: heading fixed, lateral position y(t) ≈ y₀ sin(ωt + φ).

    ``y_m`` (positive to starboard) is fitted with ``n_harmonics`` harmonics of ``omega_rad_s``;
    its derivatives give v and v̇, and the forces are regressed on them:
    Y = Y_0 + Y_v v + Y_vdot v̇ (+ Y_vvv v³ if ``cubic``; needs several amplitudes), N likewise,
    and X = X_0 + X_vv v² if ``X_N`` is given. Y_v from sway is the *dynamic* value (it depends on
    the frequency). Each argument may be one run (1-D arrays) or a list of runs; give whole
    periods after the start transient. ``details["runs"]`` holds each run's amplitudes and the
    first-harmonic force components in phase with v and with v̇ (for seed-style plots).
    """
    t, q, Y, N, X = _as_runs(t_s, y_m, Y_N, N_Nm, X_N)
    return _dynamic_fit(
        "sway",
        t,
        q,
        Y,
        N,
        X,
        omega=omega_rad_s,
        U=U_m_s,
        L=L_m,
        rho=rho_kg_m3,
        normalisation=normalisation,
        n_harmonics=n_harmonics,
        cubic=cubic,
        X_u=0.0,
    )


def fit_pure_yaw(
    t_s,
    psi_rad,
    Y_N,
    N_Nm,
    *,
    omega_rad_s: float,
    U_m_s: float,
    L_m: float | None = None,
    rho_kg_m3: float | None = None,
    X_N=None,
    normalisation: str = "rho_L2_U2",
    n_harmonics: int = 3,
    cubic: bool = False,
    X_u_N_s_m: float = 0.0,
) -> FitResult:
    """Pure yaw: the ship follows a sinusoidal path with its heading ψ(t) tangent to it (v = 0).

    ``psi_rad`` (positive bow to starboard) is fitted with harmonics of ``omega_rad_s``; its
    derivatives give r and ṙ, and the body-axes forces are regressed on them:
    Y = Y_0 + Y_r r + Y_rdot ṙ (+ Y_rrr r³ if ``cubic``), N likewise, X = X_0 + X_rr r² if ``X_N`` is
    given (after removing X_u·(u − U) of the speed rise u = U/cos ψ along the path when
    ``X_u_N_s_m`` is given). Runs and ``details`` as in :func:`fit_pure_sway`.
    """
    t, q, Y, N, X = _as_runs(t_s, psi_rad, Y_N, N_Nm, X_N)
    return _dynamic_fit(
        "yaw",
        t,
        q,
        Y,
        N,
        X,
        omega=omega_rad_s,
        U=U_m_s,
        L=L_m,
        rho=rho_kg_m3,
        normalisation=normalisation,
        n_harmonics=n_harmonics,
        cubic=cubic,
        X_u=X_u_N_s_m,
    )
