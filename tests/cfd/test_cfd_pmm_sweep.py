"""Several PMM amplitudes and a frequency sweep: the runs the pipeline adds, the per-amplitude and
per-frequency fits, the spread per derivative, and that the ship file keeps the study's own frequency."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from cfd_fake_foam import TRUE_PRIME, FakeFoam, fake_environment
from test_cfd_pipeline import run, study

from cfd.errors import InputError
from cfd.pmm_sweep import dependence, spread, summary_lines


def test_spread_is_range_over_mean():
    assert spread([-0.010, -0.012, -0.011]) == pytest.approx(0.002 / 0.011)
    assert spread([1.0]) is None and spread([1.0, -1.0]) is None


def test_a_sweep_adds_runs_and_reports_each_derivative_against_amplitude_and_frequency(tmp_path, monkeypatch):
    fake = fake_environment(monkeypatch, FakeFoam())
    # base: period 2 s at U = 1 m/s, L = 1 m, so omega' = pi; the sweep adds omega' = 1 and 2
    s = study(tmp_path, sway_amplitude="0.02,0.03", yaw_deg="3,5", sweep_omega_prime="1,2", drift_deg="4,8")
    result = run(s, fake)
    solved = {c for a, c in fake.calls if a == "pimpleFoam"}
    assert solved == {
        f"{kind}_{amp}{suffix}"
        for kind, amps in (("sway", ("a0.02000", "a0.03000")), ("yaw", ("p03.00", "p05.00")))
        for amp in amps
        for suffix in ("", "_w1.00", "_w2.00")
    }
    prov = result.provenance
    # the ship file's fit uses the study's own period only
    assert prov["tests"]["sway"]["omega_prime"] == pytest.approx(math.pi)
    assert len(prov["tests"]["sway"]["amplitudes_m"]) == 2
    dep = prov["pmm_dependence"]
    freq = dep["sway"]["frequencies"]
    assert freq["values"] == pytest.approx([1.0, 2.0, math.pi])
    # the fake hull has frequency-independent derivatives: every omega' gives them back, spread ~ 0
    for k in ("Y_v", "Y_vdot", "N_v"):
        assert freq["derivatives"][k] == pytest.approx([TRUE_PRIME[k]] * 3, rel=0.03), k
        assert freq["spread"][k] < 0.03
    yaw_amp = dep["yaw"]["amplitudes"]
    assert yaw_amp["values"] == [3.0, 5.0] and yaw_amp["omega_prime"] == pytest.approx(math.pi)
    assert yaw_amp["derivatives"]["N_r"] == pytest.approx([TRUE_PRIME["N_r"]] * 2, rel=0.02)
    summary = (result.report_dir / "summary.md").read_text()
    assert "## PMM amplitude and frequency dependence" in summary and "Pure sway, by frequency" in summary
    saved = json.loads((result.report_dir / "derivatives.json").read_text())
    assert "pmm_dependence" in saved["provenance"]


def test_the_sway_amplitude_limit_holds_at_every_sweep_frequency(tmp_path):
    # 0.03 m at omega' = 5 (omega = 5 rad/s) is a sway velocity of 0.15 U: allowed; 0.15 m is 0.75 U: refused
    study(tmp_path, sweep_omega_prime="0.5,5")
    with pytest.raises(InputError, match="sway_amplitude"):
        study(tmp_path, sway_amplitude="0.15", sweep_omega_prime="5")
    with pytest.raises(InputError, match="sweep_omega_prime"):
        study(tmp_path, sweep_omega_prime="0.1")


def test_dependence_shows_a_frequency_dependent_derivative():
    # synthetic sway runs whose Y_v doubles from omega' = 0.5 to 2 (a memory effect), N_v constant
    U, L, rho = 1.0, 1.0, 1000.0
    runs = []
    for wp, yv in ((0.5, -0.010), (1.0, -0.015), (2.0, -0.020)):
        w = wp * U / L
        t = np.linspace(0.0, 4 * math.pi / w, 400, endpoint=False)
        y = 0.02 * np.sin(w * t)
        v, vd = 0.02 * w * np.cos(w * t), -0.02 * w * w * np.sin(w * t)
        Y = rho * U * L * (yv * v) + rho * L**2 * (-0.005 * vd) / 1.0
        N = rho * U * L**2 * (-0.003 * v)
        runs.append(
            {"t": t, "q": y, "Y": Y * U, "N": N * U, "omega": w, "amplitude": 0.02, "base": wp == 2.0}
        )
    dep = dependence({"sway": runs}, U=U, L=L, rho=rho, normalisation="rho_L2_U2")
    freq = dep["sway"]["frequencies"]
    assert freq["derivatives"]["Y_v"] == pytest.approx([-0.010, -0.015, -0.020], rel=1e-6)
    assert freq["spread"]["Y_v"] == pytest.approx(0.010 / 0.015) and freq["spread"]["N_v"] < 1e-9
    assert "amplitudes" not in dep["sway"]  # one amplitude at the base frequency
    lines = summary_lines(dep, "rho_L2_U2")
    assert lines[-1].startswith("| spread | 66.7 %")


def test_a_failed_sweep_run_leaves_the_ship_file_derivatives_status(tmp_path, monkeypatch):
    # the sweep's omega' = 1 runs (and only they: case names ending _w1.00) bound k < 0 to the end
    fake = FakeFoam()
    fake.bounding_k_in = "sway_a0.03000_w1"
    fake_environment(monkeypatch, fake)
    result = run(study(tmp_path, sweep_omega_prime="1", drift_deg="4,8"), fake)
    gate = result.verification
    assert gate["verdict"] == "UNVERIFIED" and "sway_a0.03000_w1.00: k >= 0" in gate["failures"]
    assert gate["derivatives"]["Y_vdot"] == "verified"
