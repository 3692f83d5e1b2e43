"""The verification gate: can the numbers of a finished study be trusted as far as the numerics go?

Each case gets the checks that apply to it, each with its measured value, its limit and a verdict; a
derivative is *verified* when every case it comes from and every study-wide check pass. A check that
could not be made (output missing) does not pass. The limits are in :data:`LIMITS` and docs/cfd.md.

Study-wide: the hull STL closed below the waterline (open edges refuse the run before meshing, see
:func:`cfd.geometry.check_surface`) and the area of the meshed hull patch against the STL's wetted area.
Per case: y+ on the hull, the Reynolds number against the turbulence model's range, solver logs
(k bounded below zero late in the run, the Courant number), steady convergence (iteration cap, force
settling over the last window) and PMM periodicity (the last period against the one before).
"""

from __future__ import annotations

import math
import re
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .errors import CfdError
from .friction import wall_distance
from .jobs import FinishedStudy, Job
from .postprocess import body_forces, read_forces, read_yplus

LIMITS: dict[str, float] = {
    # nutUSpaldingWallFunction holds from the viscous sublayer through the log layer; the log layer ends at
    # y+ of a few hundred at model-scale Reynolds numbers, beyond which the first cell sits in the wake region.
    "yplus_mean_max": 300.0,  # mean y+ over the hull, at most
    "yplus_max": 1000.0,  # largest y+ on the hull (bow and keel corners), at most
    # k-omega SST is a fully turbulent model; below the flat-plate transition Reynolds number Re_x ~ 5e5
    # (Schlichting) most of the hull's boundary layer would be laminar, which the model cannot represent.
    "reynolds_min": 5.0e5,
    # steady runs: spread (max - min) of X and Y over the last window, relative to max(|X|, |Y|); N relative
    # to 0.1 L times that (the same scaling as the run's own stop rule, 5 x looser)
    "settling_rel": 0.01,
    "settling_window_fraction": 0.1,  # of the iterations, and at least 20 iterations
    # PMM runs: rms of F(t) - F(t - T) over the last period, relative to the rms of F over that period
    "periodicity_rel": 0.02,
    # PMM runs: largest Courant number in the field; the time step is sized for Co = 1 on the hull cells (small
    # cells by the stem, squeezed by the layer addition, reach 4-5), and PIMPLE with two outer correctors
    # stays time-accurate to about this
    "courant_max": 5.0,
    # hull patch area / STL wetted area: the snapped surface follows the STL to a few per cent; twice the area
    # means the inside of the hull was meshed too
    "hull_area_rel": 0.05,
    # prism layers: overall thickness snappyHexMesh reached on the hull, as a fraction of the designed one.
    # Where layers collapse the first cell is the snapped surface cell, several times the designed height, and
    # its y+ several times the target; below one half of the design the y+ sizing no longer describes the mesh.
    "layer_thickness_min": 0.5,
    # mean y+ on the hull against the y+ the first layer was sized for (flat-plate C_f at Re_L): the local
    # friction varies along the hull (high at the bow, low at the stern), so the mean lands near the target
    # on a layered mesh; a factor of 2 away means the sizing did not hold (layers collapsed, wrong speed)
    "yplus_target_factor": 2.0,
}
_BOUNDING_K = re.compile(r"^bounding k, min: (\S+)", re.M)
_TIME = re.compile(r"^Time = (\S+)", re.M)
_COURANT = re.compile(r"^Courant Number mean: \S+ max: (\S+)", re.M)


@dataclass(frozen=True)
class Check:
    """One check: what was measured, the limit, and whether it passed (None: could not be checked)."""

    name: str
    value: Any
    limit: str
    passed: bool | None
    note: str = ""

    @property
    def ok(self) -> bool:
        return self.passed is True


def _log_scan(log: Path, window_start: float) -> dict[str, Any]:
    """Bounded-k events (all, and at or after ``window_start``) and the largest Courant number of a log."""
    try:
        text = log.read_text(errors="replace")
    except OSError:
        return {}
    marks = sorted(
        [(m.start(), "t", m.group(1)) for m in _TIME.finditer(text)]
        + [(m.start(), "k", m.group(1)) for m in _BOUNDING_K.finditer(text)]
    )
    t, k_all, k_late = -math.inf, 0, 0
    for _, what, val in marks:
        if what == "t":
            try:
                t = float(val)
            except ValueError:
                continue
        else:
            k_all += 1
            k_late += t >= window_start
    co = [float(c) for c in _COURANT.findall(text) if c not in ("nan", "inf")]
    return {"bounding_k": k_all, "bounding_k_late": k_late, "courant_max": max(co) if co else None}


def _yplus_check(case: Path) -> Check:
    yp = read_yplus(case)
    limit = f"mean <= {LIMITS['yplus_mean_max']:g}, max <= {LIMITS['yplus_max']:g}"
    if yp is None:
        return Check("y+", None, limit, None, "no yPlus output")
    lo, hi, mean = yp
    ok = mean <= LIMITS["yplus_mean_max"] and hi <= LIMITS["yplus_max"]
    return Check("y+", {"min": lo, "max": hi, "mean": mean}, limit, ok)


def _yplus_target_check(case: Path, target: float) -> Check:
    """Did the prism layers give the y+ they were sized for? Mean y+ within a factor of the target."""
    f = LIMITS["yplus_target_factor"]
    limit = f"mean within [{target / f:.3g}, {target * f:.3g}] (target {target:g}, factor {f:g})"
    yp = read_yplus(case)
    if yp is None:
        return Check("y+ at the layer target", None, limit, None, "no yPlus output")
    ratio = yp[2] / target
    return Check("y+ at the layer target", {"mean": yp[2], "ratio": ratio}, limit, bool(1 / f <= ratio <= f))


def _steady_checks(p: FinishedStudy, job: Job, case: Path) -> list[Check]:
    s = p.study
    checks = []
    its = int(job.summary.get("iterations", 0))
    cap = its >= s.steady_iterations
    checks.append(
        Check(
            "converged before the iteration cap",
            its,
            f"< {s.steady_iterations} iterations (residualControl or settled-force stop)",
            not cap,
        )
    )
    h = read_forces(case)
    n = max(20, int(math.ceil(LIMITS["settling_window_fraction"] * len(h.t))))
    F, M = h.F[-n:], h.M[-n:]
    scale = max(abs(F[:, 0].mean()), abs(F[:, 1].mean()))
    if len(h.t) < n or scale == 0.0 or not np.all(np.isfinite(F)):
        checks.append(Check("force settling", None, "", None, f"fewer than {n} finite force samples"))
    else:
        spread = max(np.ptp(F[:, 0]), np.ptp(F[:, 1]), np.ptp(M[:, 2]) / (0.1 * s.lpp)) / scale
        checks.append(
            Check(
                "force settling",
                float(spread),
                f"spread over the last {n} iterations <= {LIMITS['settling_rel']:g} of max(|X|, |Y|)",
                bool(spread <= LIMITS["settling_rel"]),
            )
        )
    return checks


def _pmm_checks(p: FinishedStudy, job: Job, case: Path) -> list[Check]:
    motion, period, t_end = job.params["motion"], job.params["period"], job.params["t_end"]
    h = read_forces(case)
    _, Y, N = body_forces(h, motion.y(h.t), motion.psi(h.t))
    limit = f"rms(F(t) - F(t - T)) over the last period <= {LIMITS['periodicity_rel']:g} rms(F)"
    last = h.t >= t_end - period - 1e-9 * t_end
    if t_end - 2.0 * period < motion.t_ramp - 1e-9 or last.sum() < 8:
        return [Check("periodicity", None, limit, None, "needs two whole periods after the start ramp")]
    diff = {}
    for name, F in (("Y", Y), ("N", N)):
        prev = np.interp(h.t[last] - period, h.t, F)
        rms = float(np.sqrt(np.mean(F[last] ** 2)))
        diff[name] = float(np.sqrt(np.mean((F[last] - prev) ** 2)) / rms) if rms > 0 else math.inf
    ok = all(d <= LIMITS["periodicity_rel"] for d in diff.values())
    return [Check("periodicity", diff, limit, ok)]


def _case_checks(p: FinishedStudy, job: Job) -> list[Check]:
    s = p.study
    case = p.cases / job.name
    U = job.params.get("U", s.U_ref)
    re_L = U * s.lpp / s.nu
    checks = [_yplus_check(case)]
    if p.spec.yplus_target:
        # the layers were sized at U_ref; the same first cell has y+ in proportion to u_tau at this speed
        at_U = (
            p.spec.yplus_target
            * wall_distance(s.U_ref, s.lpp, s.nu, 1.0)
            / wall_distance(U, s.lpp, s.nu, 1.0)
        )
        checks.append(_yplus_target_check(case, at_U))
    checks += [
        Check(
            "Reynolds number",
            re_L,
            f">= {LIMITS['reynolds_min']:g} (k-omega SST, fully turbulent)",
            bool(re_L >= LIMITS["reynolds_min"]),
        ),
    ]
    steady = job.kind in ("tow", "drift", "heel")
    if steady:
        its = int(job.summary.get("iterations", 0))
        window_start = its - max(20, math.ceil(LIMITS["settling_window_fraction"] * its))
    else:
        window_start = job.params["t_end"] - job.params["period"]
    log = case / ("log.simpleFoam" if steady else "log.pimpleFoam")
    scan = _log_scan(log, window_start)
    if not scan:
        checks.append(Check("k >= 0", None, "no 'bounding k' in the last window", None, f"no log {log.name}"))
    else:
        checks.append(
            Check(
                "k >= 0",
                {"bounded_all": scan["bounding_k"], "bounded_last_window": scan["bounding_k_late"]},
                "no 'bounding k' (k < 0 clipped) in the last window",
                scan["bounding_k_late"] == 0,
            )
        )
    try:
        checks += _steady_checks(p, job, case) if steady else _pmm_checks(p, job, case)
    except CfdError as exc:
        checks.append(Check("forces", None, "", None, str(exc)))
    if not steady:
        co = scan.get("courant_max")
        checks.append(
            Check(
                "Courant number",
                co,
                f"max <= {LIMITS['courant_max']:g}",
                None if co is None else bool(co <= LIMITS["courant_max"]),
                "" if co is not None else "no Courant number in the log",
            )
        )
    return checks


def _study_checks(p: FinishedStudy) -> list[Check]:
    mesh = p.jobs["mesh"].summary if "mesh" in p.jobs else {}
    stl_area = p.hull.hydro.wetted_area_m2
    checks = [Check("hull STL closed below the waterline", 0, "no open or non-manifold edges", True)]
    area = mesh.get("hull_area_m2")
    limit = f"|A_patch / A_STL - 1| <= {LIMITS['hull_area_rel']:g}"
    if area is None:
        checks.append(Check("hull patch area", None, limit, None, "patch area not read from the mesh"))
    else:
        rel = area / stl_area - 1.0
        checks.append(
            Check(
                "hull patch area",
                {"patch_m2": area, "stl_wetted_m2": stl_area, "relative": rel},
                limit,
                bool(abs(rel) <= LIMITS["hull_area_rel"]),
            )
        )
    if p.spec.n_layers:
        checks.append(_layer_check(mesh.get("layers"), p.spec.n_layers))
    return checks


def _layer_check(layers: dict[str, Any] | None, asked: int) -> Check:
    limit = f"overall thickness >= {LIMITS['layer_thickness_min']:g} of the designed ({asked} layers asked)"
    if not layers:
        return Check("prism layers", None, limit, None, "no layer table in log.snappyHexMesh")
    frac = layers["thickness_pct"] / 100.0
    return Check(
        "prism layers",
        {"layers_mean": layers["layers"], "layers_asked": asked, "thickness_fraction": frac},
        limit,
        bool(frac >= LIMITS["layer_thickness_min"]),
    )


# which cases each derivative comes from, by the origin the analysis gives it
_SOURCES = {"static drift": ("drift", "base"), "pure sway": ("sway",), "pure yaw": ("yaw",), "tow": ("tow",)}


def verify(p: FinishedStudy, origin: dict[str, str]) -> dict[str, Any]:
    """The gate of a finished study: study-wide and per-case checks, each derivative's status and the verdict
    (``VERIFIED`` when every check of every case passed, else ``UNVERIFIED``). JSON-ready."""
    study = _study_checks(p)
    cases = {
        name: _case_checks(p, job)
        for name, job in p.jobs.items()
        if job.kind in ("tow", "drift", "heel", "sway", "yaw")
    }
    base = next(
        (n for n, j in p.jobs.items() if j.kind == "tow" and j.params.get("U") == p.study.U_ref), None
    )
    failed_study = [c.name for c in study if not c.ok]
    status: dict[str, str] = {}
    for key, where in origin.items():
        kinds = next((v for k, v in _SOURCES.items() if where.startswith(k)), None)
        if kinds is None:
            status[key] = "estimate (no CFD test; not verified)"
            continue
        # the frequency sweep's runs feed the reported spread, not the ship file's derivatives
        names = [n for n, j in p.jobs.items() if j.kind in kinds and not j.params.get("sweep")] + (
            [base] if "base" in kinds and base else []
        )
        bad = failed_study + [f"{n}: {c.name}" for n in names for c in cases.get(n, []) if not c.ok]
        status[key] = "verified" if not bad else "unverified (" + "; ".join(dict.fromkeys(bad)) + ")"
    failures = failed_study + [f"{n}: {c.name}" for n, cs in cases.items() for c in cs if not c.ok]
    return {
        "verdict": "UNVERIFIED" if failures else "VERIFIED",
        "failures": failures,
        "limits": dict(LIMITS),
        "study": [asdict(c) for c in study],
        "cases": {n: [asdict(c) for c in cs] for n, cs in cases.items()},
        "derivatives": status,
    }
