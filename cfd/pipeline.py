"""The study pipeline: hull -> mesh -> steady and PMM cases -> fits -> ship file and report.

Layout of ``out/``::

    ship.toml                the ship file
    report/                  plots, summary.md, derivatives.json
    cases/hull.stl           the hull in the case frame
    cases/mesh/              blockMesh + snappyHexMesh + checkMesh
    cases/tow_U1.0000/       simpleFoam straight tow at 1 m/s
    cases/drift_b06.00/      simpleFoam static drift at 6 deg
    cases/sway_a0.03000/     pimpleFoam pure sway, amplitude 0.03 m
    cases/yaw_p05.00/        pimpleFoam pure yaw, yaw amplitude 5 deg
    cases/mesh_heel10.00/    the mesh of the hull heeled 10 deg (tests "heel", cfd.heel)
    cases/heel_p10.00_b+06.00/  simpleFoam heeled drift, heel 10 deg, drift 6 deg

Every finished case holds a marker ``vessel-cfd.done.json`` with a hash of its inputs. A rerun
skips cases whose marker matches and redoes the others (a changed mesh redoes everything).
"""

from __future__ import annotations

import hashlib
import json
import math
import shutil
import threading
import time
from concurrent.futures import FIRST_EXCEPTION, ThreadPoolExecutor, wait
from pathlib import Path
from typing import Any

import numpy as np

from . import __version__
from .analysis import StudyResult, analyse
from .case import (
    HULL_PATCH,
    FlowSpec,
    MeshSpec,
    Motion,
    mesh_spec,
    pmm_time_step,
    request_stop,
    write_free_surface_case,
    write_mesh_case,
    write_pmm_case,
    write_steady_case,
)
from .config import Study
from .errors import CfdError
from .geometry import PlacedHull, place_hull, read_stl, wigley_hull, wigley_hull_with_freeboard, write_stl
from .heel import MESH_NAME, check_freeboard, heel_triangles
from .jobs import FinishedStudy, Job
from .postprocess import body_forces, forces_settled, read_forces, read_yplus, steady_forces
from .runner import (
    STOP,
    Progress,
    check_openfoam,
    mpi_available,
    parse_check_mesh,
    parse_layers,
    patch_area,
    read_boundary,
    run_app,
    stop_all,
)

DONE = "vessel-cfd.done.json"
PARALLEL_CELLS = 200_000  # above this, each case runs MPI-parallel on all procs instead of side by side


def _hash(obj: Any) -> str:
    return hashlib.sha256(json.dumps(obj, sort_keys=True, default=str).encode()).hexdigest()[:16]


def _latest_time(case: Path) -> Path:
    times = []
    for p in case.iterdir():
        try:
            times.append((float(p.name), p))
        except ValueError:
            continue
    times = [tp for tp in times if tp[0] > 0]
    if not times:
        raise CfdError(f"results ({case.name})", "no time directory was written", case)
    return max(times)[1]


class Pipeline:
    """Runs a :class:`~cfd.config.Study` end to end. ``run()`` returns a :class:`StudyResult`."""

    def __init__(
        self, study: Study, progress: Progress | None = None, plots: bool = True, ray: str | None = None
    ) -> None:
        self.study = study
        self.ray = ray  # a Ray cluster's address ("local": one on this machine) for the independent cases
        self.cpus = study.procs  # CPUs the cases share (a Ray cluster's, with ray)
        self.plots = plots
        self.progress = progress or Progress()
        self.out = Path(study.out)
        self.cases = self.out / "cases"
        self.hull: PlacedHull | None = None
        self.spec: MeshSpec | None = None
        self.mesh_key = ""
        self.mesh_keys: dict[str, str] = {}  # mesh case name -> its key hash (the upright and each heel)
        self.per_case_procs = 1
        self.jobs: dict[str, Job] = {}
        self.wall: dict[str, float] = {}
        self._count = threading.Lock()
        self._reached = 0  # cases started or found done, for "case k of n"
        self._solved: list[float] = []  # wall times of the solver cases run so far (for the ETA)

    def __getstate__(self) -> dict[str, Any]:
        """Sent to a Ray task (cfd.raycases) without its lock; it gets a new one on arrival."""
        state = dict(self.__dict__)
        del state["_count"]
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._count = threading.Lock()

    # ------------------------------------------------------------------ hull and mesh
    def prepare_hull(self) -> PlacedHull:
        s = self.study
        if s.hull == "wigley":
            tris = wigley_hull(s.lpp, s.bwl, s.tm)
        else:
            tris = read_stl(s.hull)
        placed = place_hull(tris, s.lpp, s.bwl, s.tm, x_ap=s.x_ap, z_keel=s.z_keel)
        self.cases.mkdir(parents=True, exist_ok=True)
        stl = self.cases / "hull.stl"
        write_stl(stl, placed.triangles, name=HULL_PATCH)
        self.hull = placed
        return placed

    def _mesh_job(self, phi: float = 0.0) -> Job:
        """The mesh of the upright hull, or with ``phi`` (deg) of the hull heeled by phi (cfd.heel)."""
        s = self.study
        spec = self.spec
        assert spec is not None and self.hull is not None
        stl = self.cases / "hull.stl"
        name = "mesh"
        if phi:
            check_freeboard(self.hull.triangles, s.bwl, phi)
            name = MESH_NAME.format(phi)
            stl = write_stl(self.cases / f"hull_heel{phi:05.2f}.stl", heel_triangles(self.hull.triangles, phi))
        stl_hash = hashlib.sha256(stl.read_bytes()).hexdigest()[:16]
        key = {"stl": stl_hash, "spec": repr(spec), "mesh_procs": s.mesh_procs, "version": __version__}
        self.mesh_keys[name] = _hash(key)
        if not phi:
            self.mesh_key = self.mesh_keys[name]

        def action(job: Job, case: Path, procs: int) -> dict[str, Any]:
            write_mesh_case(case, spec, stl, procs=s.mesh_procs)
            run_app(["blockMesh"], case, "blockMesh (mesh)", progress=self.progress)
            run_app(["surfaceFeatureExtract"], case, "surfaceFeatureExtract (mesh)", progress=self.progress)
            if s.mesh_procs > 1:
                run_app(["decomposePar", "-force"], case, "decomposePar (mesh)", progress=self.progress)
                run_app(
                    ["snappyHexMesh", "-overwrite"],
                    case,
                    "snappyHexMesh (mesh)",
                    procs=s.mesh_procs,
                    progress=self.progress,
                )
                run_app(
                    ["reconstructParMesh", "-constant"],
                    case,
                    "reconstructParMesh (mesh)",
                    progress=self.progress,
                )
                for p in case.glob("processor*"):
                    shutil.rmtree(p)
            else:
                run_app(["snappyHexMesh", "-overwrite"], case, "snappyHexMesh (mesh)", progress=self.progress)
            log = run_app(["checkMesh"], case, "checkMesh (mesh)", progress=self.progress)
            check = parse_check_mesh(log)
            patches = read_boundary(case)
            hull = patches.get(HULL_PATCH)
            if hull is None or int(hull.get("nFaces", "0")) == 0:
                raise CfdError(
                    "snappyHexMesh (mesh)",
                    f"the mesh has no faces on patch '{HULL_PATCH}', so all "
                    "forces would be zero; check that the STL is closed, in metres, bow to +x",
                    case / "log.snappyHexMesh",
                )
            if check["fatal"] or (not check["ok"] and not check["warnings"]):
                reason = "; ".join(check["fatal"]) or "checkMesh did not report 'Mesh OK'"
                raise CfdError("checkMesh (mesh)", f"unusable mesh: {reason}", log)
            for w in check["warnings"]:
                self.progress("checkMesh", f"warning: {w}")
            layers = parse_layers(case / "log.snappyHexMesh").get(HULL_PATCH)
            if spec.n_layers and layers:
                self.progress(
                    "snappyHexMesh",
                    f"{layers['layers']:.2f} of {spec.n_layers} layers on the hull, "
                    f"{layers['thickness_pct']:.0f} % of the layer thickness asked for",
                )
            return {
                **check,
                "layers": layers,
                "hull_faces": int(hull["nFaces"]),
                "hull_area_m2": patch_area(case, hull),
                "patches": sorted(patches),
            }

        label = f"mesh heel {phi:g} deg" if phi else "mesh"
        return Job(name, "mesh", label, key, action, params={"phi": phi})

    # ------------------------------------------------------------------ cases
    def _steady_job(self, kind: str, U: float, beta: float, phi: float = 0.0, base: Job | None = None) -> Job:
        """A straight tow, a static drift or (kind "heel") a heeled tow or drift on the heel-``phi`` mesh.

        ``base``: a finished steady case on the same mesh whose converged fields this one starts from
        (cfd.case.flow.start_fields); the drift cases start from the straight tow at their speed."""
        s = self.study
        name = f"tow_U{U:.4f}" if kind == "tow" else f"drift_b{beta:05.2f}"
        label = f"tow U={U:g} m/s" if kind == "tow" else f"drift beta={beta:g} deg"
        mesh = "mesh"
        if kind == "heel":
            mesh = MESH_NAME.format(phi)
            name = f"heel_p{phi:05.2f}_b{beta:+06.2f}"
            label = f"heel phi={phi:g} deg beta={beta:g} deg"
        flow = FlowSpec(U=U, beta_deg=beta, rho=s.rho, nu=s.nu)
        key = {"mesh": self.mesh_keys[mesh], "flow": repr(flow), "iterations": s.steady_iterations}
        if base is not None:
            key["start"] = _hash(base.key)

        def action(job: Job, case: Path, procs: int) -> dict[str, Any]:
            start = None if base is None else (_latest_time(self.cases / base.name), FlowSpec(**base.params["flow"]))
            started = write_steady_case(
                case, self.cases / mesh, flow, s.steady_iterations, procs=procs, start=start
            )
            stopped: list[int] = []

            def settle() -> None:
                if stopped or not (case / "postProcessing" / "forces").is_dir():
                    return
                try:
                    history = read_forces(case)
                except CfdError:
                    return
                if forces_settled(history, s.lpp) and request_stop(case):
                    stopped.append(int(history.t[-1]))
                    self.progress(job.label, f"forces settled at iteration {stopped[0]}: stopping")

            self._solve(case, "simpleFoam", job.label, procs, end_time=s.steady_iterations, on_tick=settle)
            sf = steady_forces(read_forces(case))
            self._sanity(sf.X, sf.Y, sf.N, U, job.label, case)
            summary = {
                "X_N": sf.X,
                "Y_N": sf.Y,
                "N_Nm": sf.N,
                "K_Nm": sf.K,  # about the waterline axis (cfd.heel moves it to G)
                "Fy_case_N": sf.Fy,
                "iterations": sf.iterations,
                # converged: residualControl ended the run, or the forces settled (request_stop
                # may take effect some iterations later, so the cap is judged on settled_at)
                "converged": bool(stopped) or sf.iterations < s.steady_iterations,
                "stopped_on_settled_forces": bool(stopped),
                "settled_at": stopped[0] if stopped else None,
                "band": sf.band,
                "initial_fields": started,
            }
            yplus = read_yplus(case, HULL_PATCH)
            if yplus is not None:
                summary["yplus_min_max_mean"] = list(yplus)
            return summary

        flow_params = {"U": U, "beta_deg": beta, "rho": s.rho, "nu": s.nu}
        return Job(name, kind, label, key, action, params={"U": U, "beta": beta, "phi": phi, "flow": flow_params})

    def _pmm_job(self, kind: str, amplitude: float, base: Job, omega_prime: float | None = None) -> Job:
        """Sway: amplitude = y0 (m). Yaw: amplitude = ψ0 (deg), y0 = U tan ψ0 / ω (pure yaw).
        ``omega_prime``: a run of the frequency sweep at ω' = ωL/U instead of the study's period."""
        s = self.study
        assert self.spec is not None
        U = s.U_ref
        period = s.sway_period if kind == "sway" else s.yaw_period
        if omega_prime is not None:
            period = 2.0 * math.pi * s.lpp / (omega_prime * U)
        omega = 2.0 * math.pi / period
        y0 = amplitude if kind == "sway" else U * math.tan(math.radians(amplitude)) / omega
        motion = Motion(kind, y0, omega, U, 0.5 * period)
        dt = pmm_time_step(self.spec, U, period, courant=s.courant)
        t_end = s.cycles * period
        flow = FlowSpec(U=U, rho=s.rho, nu=s.nu)
        name = f"sway_a{amplitude:.5f}" if kind == "sway" else f"yaw_p{amplitude:05.2f}"
        if omega_prime is not None:
            name += f"_w{omega_prime:.2f}"
        label = f"sway y0={amplitude:g} m" if kind == "sway" else f"yaw psi0={amplitude:g} deg"
        key = {
            "mesh": self.mesh_key,
            "base": _hash(base.key),
            "motion": repr(motion),
            "dt": dt,
            "t_end": t_end,
            "flow": repr(flow),
            "time_scheme": s.time_scheme,
        }

        def action(job: Job, case: Path, procs: int) -> dict[str, Any]:
            start = _latest_time(self.cases / base.name)
            write_pmm_case(
                case,
                self.cases / "mesh",
                start,
                flow,
                motion,
                t_end,
                dt,
                procs=procs,
                time_scheme=s.time_scheme,
            )
            self._solve(case, "pimpleFoam", job.label, procs, end_time=t_end)
            h = read_forces(case)
            if len(h.t) == 0 or not np.all(np.isfinite(h.F)):
                raise CfdError(
                    f"pimpleFoam ({job.label})",
                    "non-finite forces: the solution diverged",
                    case / "log.pimpleFoam",
                )
            X, Y, N = body_forces(h, motion.y(h.t), motion.psi(h.t))
            self._sanity(
                float(np.max(np.abs(X))),
                float(np.max(np.abs(Y))),
                float(np.max(np.abs(N))),
                U,
                job.label,
                case,
                allow_zero_side=False,
            )
            return {
                "y0_m": y0,
                "omega_rad_s": omega,
                "period_s": period,
                "dt_s": dt,
                "t_end_s": t_end,
                "steps": len(h.t),
                "psi0_deg": math.degrees(math.atan(y0 * omega / U)) if kind == "yaw" else 0.0,
            }

        if omega_prime is not None:
            label += f" omega'={omega_prime:g}"
        params = {"motion": motion, "t_end": t_end, "period": period, "amplitude": amplitude}
        return Job(name, kind, label, key, action, params=params | {"sweep": omega_prime is not None})

    def _solve(self, case: Path, app: str, label: str, procs: int, end_time: float, on_tick=None) -> None:
        step = f"{app} ({label})"
        if procs > 1:
            run_app(["decomposePar", "-force"], case, f"decomposePar ({label})", progress=self.progress)
            run_app(
                [app], case, step, procs=procs, progress=self.progress, end_time=end_time, on_tick=on_tick
            )
            run_app(
                ["reconstructPar", "-latestTime"], case, f"reconstructPar ({label})", progress=self.progress
            )
            for p in case.glob("processor*"):
                shutil.rmtree(p)
        else:
            run_app([app], case, step, progress=self.progress, end_time=end_time, on_tick=on_tick)

    def _sanity(
        self, X: float, Y: float, N: float, U: float, label: str, case: Path, allow_zero_side: bool = True
    ) -> None:
        s = self.study
        assert self.hull is not None
        log = next(iter(sorted(case.glob("log.*Foam"))), case)
        if not all(math.isfinite(v) for v in (X, Y, N)):
            raise CfdError(f"solver ({label})", "non-finite forces: the solution diverged", log)
        if X == 0.0:
            raise CfdError(
                f"solver ({label})", f"zero force on patch '{HULL_PATCH}' (missing hull patch?)", log
            )
        scale = 0.5 * s.rho * U**2 * self.hull.hydro.wetted_area_m2
        if max(abs(X), abs(Y)) > 50.0 * scale:
            raise CfdError(
                f"solver ({label})",
                f"force {max(abs(X), abs(Y)):.3g} N is more than 50 x 1/2 rho U^2 S: the solution diverged",
                log,
            )

    def skip(self, job: Job) -> dict[str, Any] | None:
        """The summary of ``job`` if its case finished before with the same inputs (done marker), else None."""
        case = self.cases / job.name
        marker = case / DONE
        if not marker.is_file():
            return None
        try:
            done = json.loads(marker.read_text())
        except (OSError, json.JSONDecodeError):
            return None
        if done.get("key") != _hash(job.key):
            return None
        self.progress(job.label, f"{self.case_number()} already done ({case.name}), skipped")
        self.wall[job.name] = float(done.get("wall_s", 0.0))
        return done.get("summary", {})

    def execute(self, job: Job, procs: int) -> tuple[dict[str, Any], float]:
        """Run ``job`` in a fresh case folder and write its done marker: (summary, wall time in s). The whole
        of a case's work, so that it can run in a thread here or as a task elsewhere (cfd.raycases)."""
        case = self.cases / job.name
        if case.exists():
            shutil.rmtree(case)
        case.mkdir(parents=True)
        t0 = time.monotonic()
        summary = job.action(job, case, procs)
        wall = time.monotonic() - t0
        (case / DONE).write_text(
            json.dumps(
                {
                    "key": _hash(job.key),
                    "wall_s": wall,
                    "finished": time.strftime("%Y-%m-%d %H:%M:%S"),
                    "summary": summary,
                },
                indent=1,
                default=str,
            )
        )
        return summary, wall

    def finished(self, job: Job, number: str, wall: float) -> None:
        """Book a finished case: its wall time, the ETA, the progress line."""
        self.wall[job.name] = wall
        if job.kind != "mesh":
            with self._count:
                self._solved.append(wall)
        self.progress(job.label, f"{number} finished in {wall:.0f} s{self._eta()}")

    def _run_job(self, job: Job, procs: int) -> dict[str, Any]:
        done = self.skip(job)
        if done is not None:
            return done
        number = self.case_number()
        self.progress(job.label, f"{number} started in {self.cases / job.name}")
        summary, wall = self.execute(job, procs)
        self.finished(job, number, wall)
        return summary

    def case_number(self) -> str:
        with self._count:
            self._reached += 1
            return f"case {self._reached} of {len(self.jobs)}"

    def _eta(self) -> str:
        """Remaining cases x mean wall time of the solver cases run so far / cases side by side."""
        with self._count:
            left = len(self.jobs) - self._reached
            if not left or not self._solved:
                return ""
            side_by_side = max(1, self.cpus // self.per_case_procs)
            eta = left * (sum(self._solved) / len(self._solved)) / min(side_by_side, left)
        return f"; {left} to go, ETA {eta / 60.0:.1f} min"

    def _run_parallel(self, jobs: list[Job]) -> None:
        s = self.study
        per = self.per_case_procs
        workers = max(1, s.procs // per)
        with ThreadPoolExecutor(max_workers=workers) as pool:
            futures: dict = {}
            try:
                for j in jobs:
                    futures[pool.submit(self._run_job, j, per)] = j
                done, pending = wait(futures, return_when=FIRST_EXCEPTION)
            except KeyboardInterrupt:  # Ctrl-C or SIGTERM: stop the running solvers, keep finished cases
                stop_all()
                for f in futures:
                    f.cancel()
                wait(futures)
                raise
            errors = [f.exception() for f in done if f.exception() is not None]
            if errors:
                for f in pending:
                    f.cancel()
                wait(pending)
                raise errors[0]
            for f, j in futures.items():
                j.summary = f.result()

    # ------------------------------------------------------------------ run
    def plan(self) -> list[Job]:
        """All jobs of the study in run order (mesh first, then the base tow)."""
        s = self.study
        assert self.hull is not None
        self.spec = mesh_spec(
            s.lpp,
            s.bwl,
            s.tm,
            s.grading,
            U=s.U_ref,
            nu=s.nu,
            layers=s.layers,
            yplus=s.yplus,
            sizing=s.sizing,
            wake_deg=self.wake_angles() if s.wake else (),
        )
        mesh = self._mesh_job()
        base = self._steady_job("tow", s.U_ref, 0.0)
        jobs = [mesh, base]
        later: list[Job] = []
        for kind, amplitudes in (("sway", s.sway_amplitude), ("yaw", s.yaw_deg)):
            if kind not in s.tests:
                continue
            later += [self._pmm_job(kind, a, base) for a in amplitudes]
            own = 2.0 * math.pi * s.lpp / ((s.sway_period if kind == "sway" else s.yaw_period) * s.U_ref)
            for w in s.sweep_omega_prime:  # the frequency sweep, at every amplitude
                if not math.isclose(w, own, rel_tol=1e-6):
                    later += [self._pmm_job(kind, a, base, omega_prime=w) for a in amplitudes]
        if "drift" in s.tests:
            later += [self._steady_job("drift", s.U_ref, b, base=base) for b in s.drift_deg]
        if "tow" in s.tests:
            later += [self._steady_job("tow", u, 0.0) for u in s.speeds if not math.isclose(u, s.U_ref)]
        if "heel" in s.tests:  # one mesh per heel angle, then the heeled tow and the heeled drift at ±angle
            for phi in s.heel_deg:
                later.append(self._mesh_job(phi))
                betas = (0.0, s.heel_drift_deg, -s.heel_drift_deg) if s.heel_drift_deg else (0.0,)
                later += [self._steady_job("heel", s.U_ref, b, phi) for b in betas]
        return jobs + later

    def wake_angles(self) -> tuple[float, ...]:
        """Inflow angles (deg, case frame) whose wakes the one shared mesh refines: the straight tow, every
        drift angle, and ± the largest drift angle of the hull's path in each sway and yaw run (v/U = y0 ω/U
        in sway; the heading amplitude ψ0 in yaw, where the wake trails along the curved path)."""
        s = self.study
        drift = list(s.drift_deg) if "drift" in s.tests else []
        if "heel" in s.tests and s.heel_drift_deg:
            drift += [s.heel_drift_deg, -s.heel_drift_deg]
        pmm = []
        if "sway" in s.tests:
            omegas = [s.sway_omega()] + [w * s.U_ref / s.lpp for w in s.sweep_omega_prime]
            pmm += [math.degrees(math.atan(a * w / s.U_ref)) for a in s.sway_amplitude for w in omegas]
        if "yaw" in s.tests:
            pmm += list(s.yaw_deg)
        return (0.0, *drift, *pmm, *(-a for a in pmm))

    def run(self) -> StudyResult:
        s = self.study
        t0 = time.monotonic()
        STOP.clear()
        # the hull first, silently: a bad STL or particulars is an input error (exit 2, its one line only)
        # whether or not OpenFOAM is here
        hull = self.prepare_hull()
        check_openfoam(parallel=s.mesh_procs > 1)
        if self.ray is not None:  # connected before the mesh: a wrong address fails at once
            from .raycases import connect  # noqa: PLC0415 - Ray is an optional extra

            self.cpus = connect(self.ray, s.procs)
            self.progress("ray", f"connected to {self.ray}: {self.cpus} CPUs for the cases")
        h = hull.hydro
        self.progress(
            "hull",
            f"{s.hull}: V = {h.volume_m3:.4g} m3, S = {h.wetted_area_m2:.4g} m2, "
            f"C_B = {h.volume_m3 / (s.lpp * s.bwl * s.tm):.3f}, mirrored = {hull.mirrored}",
        )
        jobs = self.plan()
        self.jobs = {j.name: j for j in jobs}
        assert self.spec is not None
        if s.free_surface:
            fs = self.cases / "free_surface_tow"
            if fs.exists():
                shutil.rmtree(fs)
            stl = self.cases / "hull.stl"
            if s.hull == "wigley":  # wall-sided topsides up to a deck at T, not the mirrored double body
                stl = write_stl(
                    self.cases / "hull_freeboard.stl", wigley_hull_with_freeboard(s.lpp, s.bwl, s.tm, s.tm)
                )
            # LTS iterations: the DTCHull tutorial's 4000
            write_free_surface_case(fs, self.spec, stl, FlowSpec(U=s.U_ref, rho=s.rho, nu=s.nu), 4000)
            self.progress("free surface", f"interFoam case written to {fs} (not run; see docs/cfd.md)")
        mesh, base, *later = jobs
        mesh.summary = self._run_job(mesh, s.mesh_procs)
        cells = int(mesh.summary.get("cells", 0))
        self.progress("mesh", f"{cells} cells, {mesh.summary.get('hull_faces')} faces on the hull")
        self.per_case_procs = s.procs if (cells >= PARALLEL_CELLS and s.procs > 1) else 1
        if self.per_case_procs > 1 and not mpi_available():
            self.progress("solver", "mpirun/decomposePar not found: cases run serially side by side")
            self.per_case_procs = 1
        base.summary = self._run_job(base, self.per_case_procs)
        for m in [j for j in later if j.kind == "mesh"]:  # the heel meshes, before their cases
            m.summary = self._run_job(m, s.mesh_procs)
        later = [j for j in later if j.kind != "mesh"]
        if later and self.ray is not None:
            from .raycases import run_on_ray  # noqa: PLC0415

            run_on_ray(self, later)
        elif later:
            self._run_parallel(later)
        self.wall["total"] = time.monotonic() - t0
        return self.finish()

    def finish(self) -> StudyResult:
        """Fit, write the ship file and the report from the finished cases."""
        assert self.hull is not None and self.spec is not None, "finish() follows run()"
        done = FinishedStudy(self.study, self.hull, self.spec, dict(self.jobs), self.cases, dict(self.wall))
        return analyse(done, plots=self.plots)
