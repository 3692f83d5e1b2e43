"""The DTC towing-tank reference and the free-surface validation report (no OpenFOAM needed)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from cfd.cli import main
from cfd.errors import InputError
from cfd.tank import DTC, DTC_TANK, TARGET_REL, compare_with_tank, console_lines, report, validate_dtc


def test_the_tank_table_is_consistent_with_its_froude_numbers_and_the_dtc_study():
    # el Moctar, Shigunov & Zorn (2012): Fn = U / sqrt(g Lpp) with Lpp = 5.976 m, printed to 3 decimals
    assert len(DTC_TANK) == 6
    for p in DTC_TANK:
        assert p.U_m_s / math.sqrt(9.81 * DTC["lpp"]) == pytest.approx(p.Fn, abs=6e-4)
    # C_T = R_T / (1/2 rho S U^2) with the model's wetted surface 6.243 m2: 3.661e-3 at the lowest speed and
    # 3.669e-3 at the highest (the tank columns of docs/cfd-dtc-study.md)
    c_t = [p.R_T_N / (0.5 * DTC["rho"] * 6.243 * p.U_m_s**2) for p in DTC_TANK]
    assert c_t[0] == pytest.approx(3.661e-3, abs=2e-6) and c_t[-1] == pytest.approx(3.669e-3, abs=2e-6)
    assert [p.R_T_N for p in DTC_TANK] == sorted(p.R_T_N for p in DTC_TANK)


def _runs(factor: float) -> list[dict]:
    return [
        {"U_m_s": p.U_m_s, "Fn": p.Fn, "R_T_N": p.R_T_N * factor, "spread_rel": 0.001, "iterations": 4000}
        | {"wall_s": 3600.0}
        for p in DTC_TANK
    ]


def test_the_report_gives_each_speeds_error_and_the_verdict(tmp_path):
    result = {"mesh": {"cells": 129016, "hull_level": 4}, "grading": 1, "iterations": 4000, "procs": 1}
    rows = compare_with_tank(_runs(1.02))
    assert all(r["error_rel"] == pytest.approx(0.02) for r in rows)
    doc = report(result | {"runs": []}, rows, tmp_path)
    assert doc["verdict"] == "within 3 % at every speed" and doc["max_abs_error_rel"] == pytest.approx(0.02)
    text = (tmp_path / "validation.md").read_text()
    assert "| 1.668 | 0.218 | 31.83 | 32.47 | +2.00 |" in text and "el Moctar" in text
    assert json.loads((tmp_path / "validation.json").read_text())["target_rel"] == TARGET_REL
    lines = console_lines(doc, tmp_path)
    assert doc["passed"] and lines[-1] == "DTC free-surface resistance: within 3 % at every speed"
    assert "U = 1.335 m/s (Fn 0.174): CFD 20.75 N, tank 20.34 N, error +2.00 %" in lines[1]
    doc = report(result | {"runs": []}, compare_with_tank(_runs(0.95)), tmp_path)
    assert doc["verdict"].startswith("NOT within") and not doc["passed"]


def test_a_speed_the_tank_did_not_run_is_refused():
    with pytest.raises(InputError, match="speeds"):
        compare_with_tank([{"U_m_s": 1.5, "R_T_N": 25.0}])


def test_the_command_refuses_bad_input_before_any_work(tmp_path, capsys):
    out = str(tmp_path / "v")
    assert main(["dtc-validation", "--out", out, "--hull", str(tmp_path / "none.stl")]) == 2
    assert "hull" in capsys.readouterr().err
    stl = tmp_path / "hull.stl"
    stl.write_text("solid hull\nendsolid hull\n")
    assert main(["dtc-validation", "--out", out, "--hull", str(stl), "--speeds", "1.5"]) == 2
    err = capsys.readouterr().err
    assert "speeds" in err and "1.668" in err and len(err.strip().splitlines()) == 1
    assert main(["dtc-validation", "--out", out, "--hull", str(stl), "--grading", "7"]) == 2
    capsys.readouterr()
    for grid in ("4", "-1", "1.5", "fine"):
        assert main(["dtc-validation", "--out", out, "--hull", str(stl), "--grid", grid]) == 2
        err = capsys.readouterr().err
        assert "grid" in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not (tmp_path / "v").exists()  # refused before anything was written


def _ran_elsewhere(out, speeds_R: dict[float, float]) -> None:
    """A free-surface study whose cases ran elsewhere: a checkMesh log and each case's forces output."""
    import numpy as np
    from cfd_fake_foam import _forces_table

    (out / "cases" / "mesh").mkdir(parents=True)
    (out / "cases" / "mesh" / "log.checkMesh").write_text("    cells:            129016\nMesh OK.\n")
    for U, R in speeds_R.items():
        case = out / "cases" / f"vof_U{U:.4f}"
        (case / "system").mkdir(parents=True)
        (case / "system" / "controlDict").write_text("application interFoam;\nendTime 4000;\n")
        t = np.arange(1.0, 4001.0)
        F = np.column_stack([-0.5 * R * (1 + 0.5 * np.exp(-t / 300)), 1600 + 0 * t, 3900 + 0 * t])
        d = case / "postProcessing" / "forces" / "0"
        d.mkdir(parents=True)
        ftxt, mtxt = _forces_table(t, F, 0 * F)
        (d / "force.dat").write_text(ftxt)
        (d / "moment.dat").write_text(mtxt)
        # interFoam's CPU time, the last ExecutionTime of each log (a continued run has a log of its own)
        (case / "log.interFoam").write_text(
            "ExecutionTime = 10 s  ClockTime = 11 s\nExecutionTime = 1800 s\n"
        )
        if U > 1.5:  # continued on 2 processors: the log's ExecutionTime is one rank's
            (case / "log.interFoam.4000").write_text(
                "nProcs : 2\nExecutionTime = 900.25 s  ClockTime = 1000 s\nEnd\n"
            )


def test_tows_run_elsewhere_are_collected_and_reported(tmp_path, capsys):
    out = tmp_path / "v"
    _ran_elsewhere(out, {1.668: 31.83 * 1.01, 1.335: 20.34 * 0.98})
    stl = tmp_path / "hull.stl"
    stl.write_text("solid hull\nendsolid hull\n")
    argv = [
        "dtc-validation",
        "--out",
        str(out),
        "--hull",
        str(stl),
        "--speeds",
        "1.335,1.668",
        "--mode",
        "collect",
    ]
    assert main(argv) == 0
    printed = capsys.readouterr().out
    assert "error +1.00 %" in printed and "error -2.00 %" in printed and "within 3 %" in printed
    doc = json.loads((out / "validation.json").read_text())
    assert doc["mesh"]["cells"] == 129016 and doc["iterations"] == 4000 and doc["passed"]
    text = (out / "validation.md").read_text()
    assert (
        "; the cases were run outside this command; solver CPU time 1.50 h in all (interFoam's ExecutionTime)."
        in text
    )
    assert [r["cpu_s"] for r in doc["runs"]] == [1800.0, 3600.5] and doc["cpu_s_solvers"] == 5400.5
    # each speed's R_T every 10th iteration, one column per speed, in the order of the rows
    history = (out / "R_T_history.csv").read_text().splitlines()
    assert history[1] == "iteration,R_T_N_U1.335,R_T_N_U1.668" and len(history) == 2 + 400
    last = history[-1].split(",")
    assert last[0] == "4000" and float(last[2]) == pytest.approx(
        31.83 * 1.01 * (1 + 0.5 * math.exp(-4000 / 300)), abs=6e-4
    )
    assert "history" not in json.dumps(doc)
    # the grading and hull level come back from the record the meshing wrote (absent above: unknown)
    assert doc["grading"] is None
    (out / "cases" / "mesh" / "vof_mesh.json").write_text('{"grading": 2, "hull_level": 5}')
    assert main(argv) == 0
    assert "Mesh: grading 2, 129016 cells (half domain), hull level 5," in (out / "validation.md").read_text()
    # a grid of the sqrt(2) family and its hull cell are named (a record without a grid is grid 0)
    (out / "cases" / "mesh" / "vof_mesh.json").write_text(
        '{"grading": 1, "grid": 2, "hull_level": 4, "hull_cell_m": 0.02334}'
    )
    assert main(argv) == 0
    assert (
        "Mesh: grading 1, grid 2 (cells / 1.414^2), hull cell 23.3 mm, 129016 cells (half domain),"
        in (out / "validation.md").read_text()
    )
    assert json.loads((out / "validation.json").read_text())["mesh"]["grid"] == 2
    capsys.readouterr()
    # a damaged record is bad input: exit 2, one line naming the file, the report left as it was
    report_before = (out / "validation.md").read_text()
    for damaged in ('{"grading": 2}', "not json", '{"grading": "two", "hull_level": 5}'):
        (out / "cases" / "mesh" / "vof_mesh.json").write_text(damaged)
        assert main(argv) == 2
        err = capsys.readouterr().err.strip()
        assert "vof_mesh.json" in err and len(err.splitlines()) == 1 and "Traceback" not in err
    assert (out / "validation.md").read_text() == report_before
    # a speed not run yet, one still running, and a mode that does not exist, are bad input
    assert main(argv[:5] + ["--speeds", "1.401", "--mode", "collect"]) == 2
    assert "has not been run" in capsys.readouterr().err
    control = out / "cases" / "vof_U1.3350" / "system" / "controlDict"
    control.write_text(control.read_text().replace("endTime 4000;", "endTime 6000;"))
    assert main(argv[:5] + ["--speeds", "1.335", "--mode", "collect"]) == 2
    err = capsys.readouterr().err
    assert "1.335 m/s has run 4000 of 6000 iterations" in err and len(err.strip().splitlines()) == 1
    control.write_text(
        control.read_text().replace("endTime 6000;", "")
    )  # no endTime: cannot be told finished
    assert main(argv[:5] + ["--speeds", "1.335", "--mode", "collect"]) == 2
    err = capsys.readouterr().err
    assert "1.335 m/s has run 4000 of an unknown number of iterations" in err and len(err.splitlines()) == 1
    assert main(argv[:-1] + ["rerun"]) == 2
    assert "mode" in capsys.readouterr().err


def test_window_statistics_give_the_mean_its_uncertainty_and_drift():
    import numpy as np

    from cfd.tank import SETTLE_WINDOW, window_statistics

    t = np.arange(1.0, 4001.0)
    n = int(SETTLE_WINDOW * len(t))  # the window: the last quarter, 1000 iterations, 5 batches of 200
    # a force oscillating by +-10 % with a period of 40 iterations: every batch holds whole periods, so the
    # mean is exact and the batches agree
    s = window_statistics(-10.0 * (1 + 0.1 * np.sin(2 * np.pi * t / 40)))
    assert s["mean"] == pytest.approx(-10.0, rel=1e-12) and s["halfwidth_rel"] < 1e-12
    assert s["spread_rel"] == pytest.approx(0.2, rel=1e-3) and abs(s["drift_rel"]) < 1e-12
    # a force still falling linearly by 1e-4 of its value per iteration: the window mean is n iterations
    # later than the one before, so the drift is -n e-4 / (its mean); the batch means differ by n/5 e-4 each
    fx = 1.0 - 1e-4 * t
    s = window_statistics(fx)
    mean = fx[-n:].mean()
    assert s["drift_rel"] == pytest.approx(-n * 1e-4 / mean, rel=1e-9)
    size = n // 5
    half = 2.776 * np.std([fx[-n + size * k : -n + size * (k + 1) or None].mean() for k in range(5)], ddof=1)
    assert s["halfwidth_rel"] == pytest.approx(half / np.sqrt(5) / mean, rel=1e-9)
    # too short a history for batches (a window of one iteration) or for a window before: not estimated,
    # never a made-up number
    s = window_statistics(np.array([2.0, 2.0, 2.0]))
    assert s["mean"] == 2.0 and np.isnan(s["halfwidth_rel"]) and s["drift_rel"] == 0.0
    s = window_statistics(np.array([2.0]))
    assert np.isnan(s["halfwidth_rel"]) and np.isnan(s["drift_rel"])


def _coverage(signals, true_mean: float) -> tuple[float, float]:
    """How often the window's 95 % interval holds the true mean, and the median half-width (relative)."""
    import numpy as np

    from cfd.tank import window_statistics

    stats = [window_statistics(y) for y in signals]
    hits = [abs(s["mean"] - true_mean) <= s["halfwidth_rel"] * abs(s["mean"]) for s in stats]
    return float(np.mean(hits)), float(np.median([s["halfwidth_rel"] for s in stats]))


def _red_noise(rng, shape, phi: float, sd: float):
    """AR(1) noise x_k = phi x_(k-1) + e_k, started from its stationary distribution."""
    import numpy as np

    e = rng.normal(0.0, sd, shape)
    x = np.empty(shape)
    x[:, 0] = e[:, 0] / np.sqrt(1.0 - phi**2)
    for k in range(1, shape[1]):
        x[:, k] = phi * x[:, k - 1] + e[:, k]
    return x


def test_the_half_width_covers_the_true_mean_of_signals_like_the_free_surface_tows():
    # Monte-Carlo check of the batch-means interval on 4000-iteration signals shaped like the DTC tows'
    # R_T (cfd/studies/dtc_vof_grading1/R_T_history.csv: oscillations of +-5-15 % with periods of 100-500
    # iterations, plus correlated noise), true mean 1: a "95 %" interval should hold it about 95 % of the time
    import numpy as np

    rng = np.random.default_rng(20261207)
    t = np.arange(4000.0)
    runs = 300
    # slowly correlated noise alone (correlation time ~50 iterations)
    cover, _ = _coverage(1.0 + _red_noise(rng, (runs, 4000), 0.98, 0.01), 1.0)
    assert cover >= 0.9
    # an oscillation of 150 iterations, random phase, with correlated noise
    phase = rng.uniform(0, 2 * np.pi, (runs, 1))
    y = 1.0 + 0.1 * np.sin(2 * np.pi * t / 150 + phase) + _red_noise(rng, (runs, 4000), 0.9, 0.02)
    cover, half = _coverage(y, 1.0)
    assert cover >= 0.9 and half < 0.03  # it covers, and is not so wide as to say nothing
    # a slow oscillation of 520 iterations (the 1.668 m/s tow's): still covered
    phase = rng.uniform(0, 2 * np.pi, (runs, 1))
    cover, half = _coverage(1.0 + 0.1 * np.sin(2 * np.pi * t / 520 + phase), 1.0)
    assert cover >= 0.9


def test_a_tow_whose_forces_diverged_is_an_error_not_a_number(tmp_path):
    import numpy as np
    from cfd_fake_foam import _forces_table

    from cfd.errors import CfdError
    from cfd.tank import _result

    t = np.arange(1.0, 101.0)
    F = np.column_stack([-10.0 + 0 * t, 0 * t, 0 * t])
    F[-3, 0] = np.nan  # in the last quarter, which the resistance is the mean of
    d = tmp_path / "vof_U1.6680" / "postProcessing" / "forces" / "0"
    d.mkdir(parents=True)
    ftxt, mtxt = _forces_table(t, F, 0 * F)
    (d / "force.dat").write_text(ftxt)
    (d / "moment.dat").write_text(mtxt)
    with pytest.raises(CfdError, match="non-finite forces: the solution diverged"):
        _result(tmp_path / "vof_U1.6680", 1.668, 5.976)


def test_the_snapped_hull_probe_refuses_bad_input_before_any_work(tmp_path):
    # cfd/studies/dtc_snapped_probe/probe.sh: one line and exit code 2, nothing copied or overwritten
    import subprocess

    probe = Path(__file__).parents[2] / "cfd" / "studies" / "dtc_snapped_probe" / "probe.sh"
    existing = tmp_path / "mine"
    existing.mkdir()
    (existing / "keep.txt").write_text("a user's file")
    cases = [
        ([], {}, "usage"),
        ([str(tmp_path / "p"), "turbulent"], {}, "unknown variant 'turbulent'"),
        ([str(tmp_path / "p")], {"ITERATIONS": "ten"}, "ITERATIONS must be a whole number"),
        ([str(existing)], {}, "exists; give a new folder"),
    ]
    for args, env, message in cases:
        done = subprocess.run(
            ["bash", str(probe), *args], capture_output=True, text=True, env={"PATH": "/usr/bin:/bin"} | env
        )
        assert done.returncode == 2 and message in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "p").exists() and [p.name for p in existing.iterdir()] == ["keep.txt"]


def _grid_folder(root, grid: int, R: float, speeds=(1.668,), grading: int = 1):
    """A dtc-validation folder of grid ``grid``: tows run elsewhere and collected into its report."""
    out = root / f"g{grid}"
    _ran_elsewhere(out, {U: R for U in speeds})
    cell = 0.0466875 / math.sqrt(2) ** grid
    (out / "cases" / "mesh" / "vof_mesh.json").write_text(
        json.dumps({"grading": grading, "grid": grid, "hull_level": 4, "hull_cell_m": cell})
    )
    validate_dtc(out / "hull.stl", out, speeds=tuple(speeds), mode="collect")  # collect reads no hull
    return out


def test_a_grid_study_gives_the_grid_uncertainty_and_the_tank_error(tmp_path, capsys):
    # three grids of the sqrt(2) family converging monotonically, 36 -> 34 -> 33 N: with a constant ratio
    # r = sqrt(2), eps32 / eps21 = 2 gives the apparent order p = ln 2 / ln r = 2 exactly, so (Celik et al.
    # 2008) phi_ext = (r^2 33 - 34) / (r^2 - 1) = 32 N and GCI_fine = 1.25 (1/33) / (r^2 - 1) = 3.79 %
    folders = [_grid_folder(tmp_path, g, R) for g, R in ((0, 36.0), (2, 33.0), (1, 34.0))]
    out = tmp_path / "study"
    argv = ["dtc-grid-study", "--grids", ",".join(map(str, folders)), "--out", str(out)]
    assert main(argv) == 3  # 33 N is 3.7 % above the tank's 31.83 N: within the seed's 5.69 %, not 3 %
    printed = capsys.readouterr().out
    assert "U = 1.668 m/s: R_T 33.00 / 34.00 / 36.00 N (finest first), monotonic, U_grid 3.79 %" in printed
    doc = json.loads((out / "grid_study.json").read_text())
    row = doc["rows"][0]
    assert [g["grid"] for g in doc["grids"]] == [2, 1, 0]
    assert row["grid"]["p"] == pytest.approx(2.0, rel=1e-9)
    # (the fake forces settle to R within 2.3e-5 by the last quarter, the same factor on every grid)
    assert row["grid"]["phi_ext"] == pytest.approx(32.0, rel=1e-4)
    assert row["u_grid_rel"] == pytest.approx(1.25 / 33.0, rel=1e-9)
    assert row["error_rel"] == pytest.approx(33.0 / 31.83 - 1.0, rel=1e-3)
    # the settled fake forces have no statistical spread, so U_SN is the grid uncertainty
    assert row["u_sn_rel"] == pytest.approx(row["u_grid_rel"], rel=1e-6)
    assert row["within_seed"] and not row["within_target"] and not doc["passed"]
    text = (out / "grid_study.md").read_text()
    assert "| 1.668 | 0.218 | 31.83 | 33.00 / 34.00 / 36.00 |" in text and "Celik" in text
    assert "Verdict: within 5.69 % (not 3 %) at every speed." in text
    # two grids: Roache's variant, order 2 assumed, F_s = 3: GCI = 3 (1/33) / (r^2 - 1) = 9.09 %
    assert main(["dtc-grid-study", "--grids", f"{folders[1]},{folders[2]}", "--out", str(out)]) == 3
    row = json.loads((out / "grid_study.json").read_text())["rows"][0]
    assert row["grid"]["condition"] == "two grids, order assumed"
    assert (
        row["u_grid_rel"] == pytest.approx(3.0 / 33.0, rel=1e-9)
        and "Roache" in (out / "grid_study.md").read_text()
    )


def test_a_grid_study_refuses_reports_that_are_not_one_family(tmp_path, capsys):
    g0 = _grid_folder(tmp_path, 0, 36.0, speeds=(1.668, 1.535, 1.401))
    g1 = _grid_folder(tmp_path, 1, 34.0)
    other = _grid_folder(tmp_path / "other", 1, 34.0, grading=2)
    remeshed = _grid_folder(tmp_path / "remeshed", 1, 34.0, speeds=(1.401,))
    doc = json.loads((remeshed / "validation.json").read_text())
    (remeshed / "validation.json").write_text(json.dumps(doc | {"mesh": doc["mesh"] | {"cells": 300000}}))
    before_grids = tmp_path / "before_grids"  # a report written before the grid was recorded
    before_grids.mkdir()
    (before_grids / "validation.json").write_text(json.dumps(doc | {"mesh": {"cells": 129016}}))
    out = tmp_path / "study"
    bad = [
        ([g0], "two or three different grids"),
        ([g0, g0], "1.668 m/s of grid 0 is in two reports"),
        ([g0, other], "one grading"),
        ([g0, tmp_path / "none"], "holds no dtc-validation report (missing validation.json"),
        ([g0, g1, remeshed], "are both grid 1 but have different meshes (300000 and 129016 cells)"),
        ([g0, before_grids], "validation.json: not a dtc-validation report with a grid"),
    ]
    for folders, message in bad:
        assert main(["dtc-grid-study", "--grids", ",".join(map(str, folders)), "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    # 1.535 m/s is reported on grid 0 only; 1.5 m/s is no tank speed
    for speeds, message in (
        ("1.535", "1.535 m/s: no finished tow in the reports of grid 1"),
        ("1.5", "not a tank speed"),
    ):
        assert main(["dtc-grid-study", "--grids", f"{g0},{g1}", "--out", str(out), "--speeds", speeds]) == 2
        assert message in capsys.readouterr().err
    slow = _grid_folder(tmp_path / "slow", 1, 34.0, speeds=(1.335,))
    assert main(["dtc-grid-study", "--grids", f"{g0},{slow}", "--out", str(out)]) == 2
    assert "no speed has been reported on every grid" in capsys.readouterr().err
    assert not out.exists()  # nothing written on bad input
    # by default, the speeds reported on every grid: 1.668 only
    assert main(["dtc-grid-study", "--grids", f"{g0},{g1}", "--out", str(out)]) in (0, 3)
    assert [r["U_m_s"] for r in json.loads((out / "grid_study.json").read_text())["rows"]] == [1.668]
    # a grid's speeds may be collected in more than one folder: grid 1 at 1.401 m/s in a later one
    later = _grid_folder(tmp_path / "later", 1, 34.0, speeds=(1.401,))
    assert main(["dtc-grid-study", "--grids", f"{g0},{g1},{later}", "--out", str(out)]) in (0, 3)
    doc = json.loads((out / "grid_study.json").read_text())
    assert [r["U_m_s"] for r in doc["rows"]] == [1.401, 1.668]
    assert doc["grids"][0]["folders"] == [str(g1), str(later)] and doc["grids"][0]["grid"] == 1


def test_the_committed_grid_study_is_what_its_reports_give(tmp_path, monkeypatch):
    """cfd/studies/dtc_vof_grid/grid_study.md and .json are regenerated from the committed reports their
    JSON names alone (the case folders are not kept)."""

    root = Path(__file__).parents[2]
    study = root / "cfd" / "studies" / "dtc_vof_grid"
    committed = json.loads((study / "grid_study.json").read_text())
    folders = [f for g in committed["grids"] for f in g["folders"]]
    assert all(not Path(f).is_absolute() and (root / f / "validation.json").is_file() for f in folders)
    monkeypatch.chdir(root)
    assert main(["dtc-grid-study", "--grids", ",".join(folders), "--out", str(tmp_path)]) in (0, 3)
    assert (tmp_path / "grid_study.md").read_text() == (study / "grid_study.md").read_text()
    assert json.loads((tmp_path / "grid_study.json").read_text()) == committed
