"""A stand-in for the OpenFOAM applications, for pipeline tests without OpenFOAM.

:class:`FakeFoam` replaces :func:`cfd.runner.run_app` in :mod:`cfd.pipeline`. It writes what the real
applications would (mesh boundary file, checkMesh log, time directories, ``forces`` output), with forces
from a known linear-plus-cubic hull model, so the fits must give back :data:`TRUE` exactly (steady tests)
or to within the finite-difference error of the fake's motion derivatives (PMM tests).

The forces are written in OpenFOAM's case frame (y to port, z up, moment about the fixed origin), so the
pipeline's frame conversions are exercised too.
"""

from __future__ import annotations

import hashlib
import re
import shutil
from pathlib import Path

import numpy as np

from cfd.errors import CfdError

# dimensional derivatives (standard body axes, SI) of the fake hull at any speed U (scaled with U as a
# real hull's would be: linear terms ∝ U, cubic terms ∝ 1/U, acceleration terms constant)
RHO, L = 1000.0, 1.0
TRUE_PRIME = {  # rho_L2_U2
    "Y_v": -0.009,
    "Y_vvv": -0.03,
    "N_v": -0.003,
    "N_vvv": -0.005,
    "X_vv": 0.001,
    "Y_vdot": -0.005,
    "N_vdot": 0.0001,
    "Y_r": 0.002,
    "N_r": -0.0019,
    "Y_rdot": -0.0001,
    "N_rdot": -0.00034,
    "X_rr": 0.00005,
}
# roll terms of the fake hull (SNAME prime, 1/2 rho L^2 U^2 and 1/2 rho L^3 U^2; K about the waterline
# axis): the heel-induced Y and N and the roll moment of the static-heel cases (cfd.heel)
TRUE_ROLL = {
    "Y_phi": 0.0021,
    "Y_vvphi": -0.04,
    "Y_vphiphi": 0.013,
    "N_phi": -0.0013,
    "N_vvphi": 0.011,
    "N_vphiphi": -0.007,
    "K_v": 0.0031,
    "K_vvv": 0.02,
    "K_phi": -0.0009,
    "K_vvphi": 0.006,
    "K_vphiphi": -0.004,
}
C_R = 0.35  # resistance R = C_R U^2 (N)
_SQUARE = ((0, 0), (1, 0), (1, 1), (0, 1))


def _coef(key: str, U: float) -> float:
    from cfd.fitting import dimensionalise

    return dimensionalise({key: TRUE_PRIME[key]}, rho_kg_m3=RHO, L_m=L, U_m_s=U)[key]


def _forces_table(t: np.ndarray, F: np.ndarray, M: np.ndarray) -> tuple[str, str]:
    def rows(V: np.ndarray, name: str) -> str:
        head = f"# {name}\n# CofR : (0 0 0)\n#\n# Time (total_x total_y total_z) (pressure_x ...) (viscous_x ...)\n"
        body = "".join(
            f"{ti:.10g}\t({v[0]:.10e} {v[1]:.10e} {v[2]:.10e})\t(0 0 0)\t(0 0 0)\n" for ti, v in zip(t, V)
        )
        return head + body

    return rows(F, "Force"), rows(M, "Moment")


class FakeFoam:
    """Callable with run_app's signature; counts calls; failure switches for the error tests."""

    def __init__(
        self,
        hull_faces: int = 120,
        nan_in: str | None = None,
        fail_app: str | None = None,
        check_finding: str = "",
        yplus: tuple[float, float, float] = (40.0, 250.0, 120.0),
        courant: float = 1.8,
        hull_area_factor: float = 1.0,
        bounding_k_in: str | None = None,
        settle: bool = True,
        grid_error: float | None = None,
        layer_fraction: float = 0.8,
    ) -> None:
        # grid_error c: forces times (1 + c h^2), h = 2^-H the hull cell size in units of the background
        # cell for hull level H, and 100 x 8^H cells: a second-order grid convergence (p = 2, r = 2)
        self.grid_error = grid_error
        self.level = 0
        self.hull_faces = hull_faces
        self.layer_fraction = layer_fraction  # prism-layer thickness reached / designed, in the snappy log
        self.yplus = yplus  # (min, max, mean) written by the yPlus function object
        self.courant = courant  # largest Courant number in the PMM logs
        self.hull_area_factor = hull_area_factor  # hull patch area / STL wetted area (2: inside meshed too)
        self.bounding_k_in = bounding_k_in  # a case-name prefix whose log bounds k < 0 to the end
        self.settle = settle  # False: steady forces keep drifting to the last iteration
        self.check_finding = check_finding  # a "***" line for the checkMesh log
        self.nan_in = nan_in  # a case-name prefix whose solver produces NaN forces
        self.fail_app = fail_app  # an application that "crashes"
        self.calls: list[tuple[str, str]] = []

    def __call__(self, argv, case: Path, step: str, **kw) -> Path:
        app = argv[0]
        case = Path(case)
        self.calls.append((app, case.name))
        log = case / f"log.{app}"
        if app == self.fail_app:
            log.write_text("--> FOAM FATAL ERROR: \nfake failure for the test\n")
            raise CfdError(step, f"{app} exited with code 1: FOAM FATAL ERROR: fake failure", log)
        log.write_text(f"fake {app}\nEnd\n")
        getattr(self, "_" + app, lambda c: None)(case)
        return log

    # ---------------------------------------------------------------- meshing
    def _snappyHexMesh(self, case: Path) -> None:
        poly = case / "constant" / "polyMesh"
        poly.mkdir(parents=True, exist_ok=True)
        patches = [
            ("farfield", "patch", 100),
            ("bottom", "symmetryPlane", 50),
            ("waterline", "symmetryPlane", 50),
        ]
        if self.hull_faces:
            patches.append(("hull", "wall", self.hull_faces))
        body = "".join(
            f"    {n}\n    {{\n        type {t};\n        nFaces {f};\n        startFace 0;\n    }}\n"
            for n, t, f in patches
        )
        (poly / "boundary").write_text(
            f"FoamFile\n{{\n    object boundary;\n}}\n\n{len(patches)}\n(\n{body})\n"
        )
        for name in ("owner", "neighbour"):
            (poly / name).write_text("fake\n")
        # the hull patch: hull_faces squares whose total area is the STL's wetted area (x hull_area_factor)
        from cfd.geometry import hydrostatics, read_stl

        wetted = hydrostatics(read_stl(case / "constant" / "triSurface" / "hull.stl")).wetted_area_m2
        n = max(self.hull_faces, 1)
        side = float(np.sqrt(wetted * self.hull_area_factor / n))
        pts = "".join(
            f"({(i + dx) * side:.12g} {dy * side:.12g} 0)\n" for i in range(n) for dx, dy in _SQUARE
        )
        faces = "".join(f"4({4 * i} {4 * i + 1} {4 * i + 2} {4 * i + 3})\n" for i in range(n))
        head = "FoamFile\n{{\n    format ascii;\n    class {};\n}}\n\n"
        stl = hashlib.sha256((case / "constant" / "triSurface" / "hull.stl").read_bytes()).hexdigest()
        (poly / "points").write_text(head.format("vectorField") + f"// hull.stl {stl}\n{4 * n}\n(\n{pts})\n")
        (poly / "faces").write_text(head.format("faceList") + f"{n}\n(\n{faces})\n")
        asked = re.search(r"nSurfaceLayers\s+(\d+);", (case / "system" / "snappyHexMeshDict").read_text())
        if asked and int(asked.group(1)) > 0 and self.hull_faces:  # snappyHexMesh's layer table
            n_asked = int(asked.group(1))
            (case / "log.snappyHexMesh").write_text(
                "patch faces    layers   overall thickness\n"
                "                       [m]       [%]\n"
                "----- -----    ------   ---       ---\n"
                f"hull {self.hull_faces}      {self.layer_fraction * n_asked:.3g}     0.0171    "
                f"{100 * self.layer_fraction:.3g}\n\nLayer mesh : cells:14896\nEnd\n"
            )

    def _checkMesh(self, case: Path) -> None:
        levels = re.findall(
            r"level\s+\(\s*(\d+)\s+\d+\s*\)", (case / "system" / "snappyHexMeshDict").read_text()
        )
        self.level = max(map(int, levels))
        cells = 1234 if self.grid_error is None else 100 * 8**self.level
        verdict = (
            f" ***{self.check_finding}\n\nFailed 1 mesh checks.\n" if self.check_finding else "\nMesh OK.\n"
        )
        (case / "log.checkMesh").write_text(
            f"Mesh stats\n    cells:            {cells}\n    Max skewness = 0.5 OK.\n"
            "    Mesh non-orthogonality Max: 30 average: 5\n" + verdict + "\nEnd\n"
        )

    # ---------------------------------------------------------------- solvers
    def _simpleFoam(self, case: Path) -> None:
        text = (case / "0" / "U").read_text()
        ux, uy, _ = map(float, re.search(r"internalField\s+uniform\s+\(([^)]*)\)", text).group(1).split())
        U = float(np.hypot(ux, uy))
        beta = float(np.arctan2(-uy, -ux))
        v = -U * np.sin(beta)
        X = -C_R * U**2 + _coef("X_vv", U) * v**2
        Y = _coef("Y_v", U) * v + _coef("Y_vvv", U) * v**3
        N = _coef("N_v", U) * v + _coef("N_vvv", U) * v**3
        heel = re.match(r"heel_p([0-9.]+)_", case.name)
        phi = np.radians(float(heel.group(1))) if heel else 0.0
        q, vp, T = 0.5 * RHO * U**2, v / U, TRUE_ROLL
        Y += q * L**2 * (T["Y_phi"] * phi + T["Y_vvphi"] * vp**2 * phi + T["Y_vphiphi"] * vp * phi**2)
        N += q * L**3 * (T["N_phi"] * phi + T["N_vvphi"] * vp**2 * phi + T["N_vphiphi"] * vp * phi**2)
        K = q * L**3 * (
            T["K_v"] * vp
            + T["K_vvv"] * vp**3
            + T["K_phi"] * phi
            + T["K_vvphi"] * vp**2 * phi
            + T["K_vphiphi"] * vp * phi**2
        )
        n = 100
        it = np.arange(1, n + 1, dtype=float)
        relax = (
            1.0 - np.exp(-it / 3.0) if self.settle else 0.5 + 0.5 * it / n
        )  # drifting: 5 % over the last 10
        F = np.column_stack([X * relax, -Y * relax, np.zeros(n)])
        M = np.column_stack([K * relax, np.zeros(n), -N * relax])
        if self.nan_in and case.name.startswith(self.nan_in):
            F[-5:] = np.nan
        self._write_forces(case, it, F, M)
        self._logs(case, "simpleFoam", it)
        final = case / str(n)
        final.mkdir()
        for f in (case / "0").iterdir():
            shutil.copyfile(f, final / f.name)

    def _pimpleFoam(self, case: Path) -> None:
        table = (case / "constant" / "6DoF.dat").read_text()
        rows = re.findall(r"\(([-0-9.eE+]+) \(\(0 ([-0-9.eE+]+) 0\) \(0 0 ([-0-9.eE+]+)\)\)\)", table)
        data = np.array(rows, dtype=float)
        t_end = float(
            re.search(r"endTime\s+([-0-9.eE+]+);", (case / "system" / "controlDict").read_text()).group(1)
        )
        U = float(
            np.hypot(
                *map(
                    float,
                    re.search(r"internalField\s+uniform\s+\(([^)]*)\)", (case / "0" / "U").read_text())
                    .group(1)
                    .split()[:2],
                )
            )
        )
        t, y_case, psi_case = data[:, 0], data[:, 1], np.radians(data[:, 2])
        y, psi = -y_case, -psi_case  # standard axes
        v, r = np.gradient(y, t, edge_order=2), np.gradient(psi, t, edge_order=2)
        vd, rd = np.gradient(v, t, edge_order=2), np.gradient(r, t, edge_order=2)
        if np.any(psi != 0):  # pure yaw: v = 0 and u = U / cos(psi) in body axes
            X = -C_R * (U / np.cos(psi)) ** 2 + _coef("X_rr", U) * r**2
            Y = _coef("Y_r", U) * r + _coef("Y_rdot", U) * rd
            N = _coef("N_r", U) * r + _coef("N_rdot", U) * rd
        else:
            X = -C_R * U**2 + 0 * v
            Y = _coef("Y_v", U) * v + _coef("Y_vdot", U) * vd
            N = _coef("N_v", U) * v + _coef("N_vdot", U) * vd
        # body forces -> case frame, moment about the fixed origin
        Fxb, Fyb = X, -Y
        c, s = np.cos(psi_case), np.sin(psi_case)
        Fx, Fy = c * Fxb - s * Fyb, s * Fxb + c * Fyb
        Mz = -N - y_case * Fx
        keep = (t > 0) & (t <= t_end + 1e-9)
        z = np.zeros(keep.sum())
        self._write_forces(
            case, t[keep], np.column_stack([Fx[keep], Fy[keep], z]), np.column_stack([z, z, Mz[keep]])
        )
        self._logs(case, "pimpleFoam", t[keep])
        final = case / f"{t_end:g}"
        final.mkdir()

    def _logs(self, case: Path, app: str, times: np.ndarray) -> None:
        """Solver log lines the verification reads (time, Courant number, bounded k) and the y+ output."""
        late = bool(self.bounding_k_in and case.name.startswith(self.bounding_k_in))
        lines = []
        for i, ti in enumerate(times):
            lines.append(f"Time = {ti:.10g}\n")
            if app == "pimpleFoam":
                lines.append(
                    f"Courant Number mean: 0.05 max: {self.courant * (0.5 + 0.5 * i / len(times)):.6g}\n"
                )
            if late and i > 0.5 * len(times):
                lines.append("bounding k, min: -1.2e-06 max: 0.01 average: 0.001\n")
        with open(case / f"log.{app}", "a") as fh:
            fh.write("".join(lines))
        d = case / "postProcessing" / "yPlus" / "0"
        d.mkdir(parents=True, exist_ok=True)
        lo, hi, mean = self.yplus
        (d / "yPlus.dat").write_text(
            f"# y+ ()\n# Time\tpatch\tmin\tmax\taverage\n{times[-1]:.10g}\thull\t{lo}\t{hi}\t{mean}\n"
        )

    def _write_forces(self, case: Path, t: np.ndarray, F: np.ndarray, M: np.ndarray) -> None:
        if self.grid_error is not None:
            F, M = (A * (1.0 + self.grid_error * 4.0**-self.level) for A in (F, M))
        d = case / "postProcessing" / "forces" / "0"
        d.mkdir(parents=True, exist_ok=True)
        ftxt, mtxt = _forces_table(t, F, M)
        (d / "force.dat").write_text(ftxt)
        (d / "moment.dat").write_text(mtxt)


def fake_environment(monkeypatch, fake: FakeFoam) -> FakeFoam:
    """Route the pipeline's OpenFOAM calls to ``fake`` and skip the installation check."""
    import cfd.pipeline as pipeline

    monkeypatch.setattr(pipeline, "run_app", fake)
    monkeypatch.setattr(pipeline, "check_openfoam", lambda parallel=False: None)
    return fake
