"""cfd.fitting on synthetic captive-test data with known derivatives."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from cfd.fitting import (
    convert_normalisation,
    dimensionalise,
    fit_pure_sway,
    fit_pure_yaw,
    fit_resistance,
    fit_static_drift,
    harmonic_fit,
    key_variables,
    nondimensionalise,
    scale_factor,
)

RHO, L, U = 1025.0, 3.0, 1.5


def test_fitting_module_imports_only_numpy():
    code = (
        "import sys, cfd.fitting; bad = [m for m in ('foamlib', 'matplotlib', 'pandas', 'cfd.runner', "
        "'cfd.case') if m in sys.modules]; print(bad); sys.exit(1 if bad else 0)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr


@pytest.mark.parametrize(
    ("key", "expected"),
    [
        # seed eq. 5-9 written out by hand for each kind of term
        ("Y_v", U / (RHO * U**2 * L**2)),
        ("N_v", U / (RHO * U**2 * L**3)),
        ("Y_r", (U / L) / (RHO * U**2 * L**2)),
        ("N_r", (U / L) / (RHO * U**2 * L**3)),
        ("Y_vdot", (U**2 / L) / (RHO * U**2 * L**2)),
        ("N_rdot", (U**2 / L**2) / (RHO * U**2 * L**3)),
        ("Y_vvr", U**2 * (U / L) / (RHO * U**2 * L**2)),
        ("X_uu", U**2 / (RHO * U**2 * L**2)),
        ("Y_0", 1.0 / (RHO * U**2 * L**2)),
        ("N_d", 1.0 / (RHO * U**2 * L**3)),
    ],
)
def test_scale_factor_matches_seed_equations(key, expected):
    assert scale_factor(key, rho_kg_m3=RHO, L_m=L, U_m_s=U, normalisation="rho_L2_U2") == pytest.approx(
        expected
    )
    half = scale_factor(key, rho_kg_m3=RHO, L_m=L, U_m_s=U, normalisation="half_rho_L2_U2")
    assert half == pytest.approx(2 * expected)
    assert scale_factor(key, rho_kg_m3=RHO, L_m=L, U_m_s=U, normalisation="SI") == 1.0


def test_nondimensionalise_round_trip_and_conversion():
    si = {"Y_v": -120.0, "N_rdot": -3.5, "X_vv": 40.0, "Y_vvv": -900.0}
    for norm in ("rho_L2_U2", "half_rho_L2_U2"):
        prime = nondimensionalise(si, rho_kg_m3=RHO, L_m=L, U_m_s=U, normalisation=norm)
        back = dimensionalise(prime, rho_kg_m3=RHO, L_m=L, U_m_s=U, normalisation=norm)
        assert back == pytest.approx(si)
    a = nondimensionalise(si, rho_kg_m3=RHO, L_m=L, U_m_s=U, normalisation="rho_L2_U2")
    b = nondimensionalise(si, rho_kg_m3=RHO, L_m=L, U_m_s=U, normalisation="half_rho_L2_U2")
    assert convert_normalisation(a, "rho_L2_U2", "half_rho_L2_U2") == pytest.approx(b)
    assert convert_normalisation(b, "half_rho_L2_U2", "rho_L2_U2") == pytest.approx(a)


def test_key_variables_and_bad_names():
    assert key_variables("Y_vvr") == ("Y", ("v", "v", "r"))
    assert key_variables("N_rdot") == ("N", ("rdot",))
    assert key_variables("X_0") == ("X", ())
    for bad in ("Q_v", "Y_", "Y_vx", "Yv", "Y_vdotdot"):
        with pytest.raises(ValueError):
            key_variables(bad)
    with pytest.raises(ValueError, match="normalisation"):
        scale_factor("Y_v", rho_kg_m3=1, L_m=1, U_m_s=1, normalisation="mmg")


def test_harmonic_fit_recovers_coefficients_and_derivatives():
    t = np.linspace(0.3, 10.3, 501)
    w = 1.7
    x = 0.2 + 1.5 * np.sin(w * t) - 0.4 * np.cos(w * t) + 0.1 * np.sin(3 * w * t)
    h = harmonic_fit(t, x, w, 3)
    assert h.mean == pytest.approx(0.2)
    assert h.a == pytest.approx([1.5, 0.0, 0.1], abs=1e-12)
    assert h.b == pytest.approx([-0.4, 0.0, 0.0], abs=1e-12)
    xdot = 1.5 * w * np.cos(w * t) + 0.4 * w * np.sin(w * t) + 0.3 * w * np.cos(3 * w * t)
    assert h.evaluate(t, 1) == pytest.approx(xdot)
    xddot = -1.5 * w**2 * np.sin(w * t) + 0.4 * w**2 * np.cos(w * t) - 0.9 * w**2 * np.sin(3 * w * t)
    assert h.evaluate(t, 2) == pytest.approx(xddot)
    assert h.amplitude == pytest.approx(np.hypot(1.5, 0.4))


def _sway(t, y0, w, phase, d):
    y = y0 * np.sin(w * t + phase)
    v = y0 * w * np.cos(w * t + phase)
    vd = -y0 * w**2 * np.sin(w * t + phase)
    Y = d["Y_0"] + d["Y_v"] * v + d["Y_vdot"] * vd + d.get("Y_vvv", 0) * v**3
    N = d["N_0"] + d["N_v"] * v + d["N_vdot"] * vd + d.get("N_vvv", 0) * v**3
    X = -30.0 + d.get("X_vv", 0) * v**2
    return y, Y, N, X


def test_pure_sway_linear_si():
    d = {"Y_0": 0.3, "Y_v": -150.0, "Y_vdot": -80.0, "N_0": -0.1, "N_v": -60.0, "N_vdot": 4.0, "X_vv": 25.0}
    w = 2 * np.pi / 4.0
    t = np.linspace(8.0, 16.0, 801)  # two whole periods
    y, Y, N, X = _sway(t, 0.15, w, 0.7, d)
    fit = fit_pure_sway(t, y, Y, N, X_N=X, omega_rad_s=w, U_m_s=U, normalisation="SI")
    for k in ("Y_0", "Y_v", "Y_vdot", "N_0", "N_v", "N_vdot", "X_vv"):
        assert fit.derivatives[k] == pytest.approx(d[k], rel=1e-6, abs=1e-9), k
    assert fit.derivatives["X_0"] == pytest.approx(-30.0)
    assert max(fit.residuals.values()) < 1e-8
    run = fit.details["runs"][0]
    assert run["amplitude"] == pytest.approx(0.15)
    assert run["Y_in_phase_velocity"] == pytest.approx(d["Y_v"] * 0.15 * w)
    assert run["Y_in_phase_acceleration"] == pytest.approx(d["Y_vdot"] * 0.15 * w**2)


def test_pure_sway_several_amplitudes_cubic_and_prime():
    d = {
        "Y_0": 0.0,
        "Y_v": -150.0,
        "Y_vdot": -80.0,
        "Y_vvv": -2000.0,
        "N_0": 0.0,
        "N_v": -60.0,
        "N_vdot": 4.0,
        "N_vvv": 300.0,
    }
    w = 1.2
    t = np.linspace(0.0, 3 * 2 * np.pi / w, 1200)
    runs = [_sway(t, a, w, 0.0, d) for a in (0.05, 0.1, 0.2)]
    fit = fit_pure_sway(
        [t] * 3,
        [r[0] for r in runs],
        [r[1] for r in runs],
        [r[2] for r in runs],
        omega_rad_s=w,
        U_m_s=U,
        L_m=L,
        rho_kg_m3=RHO,
        normalisation="rho_L2_U2",
        cubic=True,
    )
    expected = nondimensionalise(
        {k: d[k] for k in ("Y_v", "Y_vdot", "Y_vvv", "N_v", "N_vvv")}, rho_kg_m3=RHO, L_m=L, U_m_s=U
    )
    for k, v in expected.items():
        assert fit.derivatives[k] == pytest.approx(v, rel=1e-6), k
    assert fit.normalisation == "rho_L2_U2"
    assert len(fit.details["runs"]) == 3


def test_pure_yaw_with_noise_and_surge_correction():
    rng = np.random.default_rng(1)
    d = {"Y_r": 90.0, "Y_rdot": -5.0, "N_r": -70.0, "N_rdot": -12.0, "X_rr": 15.0}
    w = 2 * np.pi / 5.0
    t = np.linspace(5.0, 15.0, 1001)
    psi = 0.08 * np.sin(w * t)
    r, rd = 0.08 * w * np.cos(w * t), -0.08 * w**2 * np.sin(w * t)
    Y = d["Y_r"] * r + d["Y_rdot"] * rd + rng.normal(0, 0.05, t.size)
    N = d["N_r"] * r + d["N_rdot"] * rd + rng.normal(0, 0.05, t.size)
    X_u = -40.0
    X = -30.0 + d["X_rr"] * r**2 + X_u * U * (1 / np.cos(psi) - 1)
    fit = fit_pure_yaw(t, psi, Y, N, X_N=X, omega_rad_s=w, U_m_s=U, normalisation="SI", X_u_N_s_m=X_u)
    for k in ("Y_r", "N_r"):
        assert fit.derivatives[k] == pytest.approx(d[k], rel=2e-3), k
    for k in ("Y_rdot", "N_rdot"):
        assert fit.derivatives[k] == pytest.approx(d[k], rel=2e-2), k
    assert fit.derivatives["X_rr"] == pytest.approx(d["X_rr"], rel=1e-6)
    assert 0 < fit.residuals["Y"] < 0.05


def test_static_drift_cubic_symmetric_and_si():
    v = -U * np.sin(np.radians([0, 2, 4, 6, 8, 10]))
    Y = -150 * v - 2000 * v**3 + 0.2  # a small offset, as CFD gives at beta = 0
    N = -60 * v + 300 * v**3
    X = -30 + 25 * v**2
    fit = fit_static_drift(v, Y, N, X_N=X, U_m_s=U, normalisation="SI")
    assert fit.details["cubic"]
    assert fit.derivatives["Y_v"] == pytest.approx(-150)
    assert fit.derivatives["Y_vvv"] == pytest.approx(-2000)
    assert fit.derivatives["Y_0"] == pytest.approx(0.2)
    assert fit.derivatives["N_vvv"] == pytest.approx(300)
    assert fit.derivatives["X_vv"] == pytest.approx(25)
    sym = fit_static_drift(v, Y - 0.2, N, U_m_s=U, normalisation="SI", symmetric=True)
    assert sym.derivatives["Y_0"] == pytest.approx(0, abs=1e-9)
    assert sym.derivatives["Y_v"] == pytest.approx(-150)
    lin = fit_static_drift(v[:3], Y[:3], N[:3], U_m_s=U, normalisation="SI")
    assert not lin.details["cubic"] and "Y_vvv" not in lin.derivatives
    prime = fit_static_drift(v, Y, N, U_m_s=U, L_m=L, rho_kg_m3=RHO, normalisation="half_rho_L2_U2")
    assert prime.derivatives["Y_v"] == pytest.approx(-150 * U / (0.5 * RHO * U**2 * L**2))


def test_resistance_taylor_expansion_about_reference_speed():
    u = np.array([1.0, 1.25, 1.5, 1.75, 2.0])
    X = -(10 * u**2)
    fit = fit_resistance(u, X, U_ref_m_s=1.5, normalisation="SI")
    assert fit.derivatives["X_0"] == pytest.approx(-22.5)
    assert fit.derivatives["X_u"] == pytest.approx(-30.0)  # dX/du = -20 U
    assert fit.derivatives["X_uu"] == pytest.approx(-10.0)
    one = fit_resistance([1.5], [-22.5], U_ref_m_s=1.5, normalisation="SI")
    assert set(one.derivatives) == {"X_0"}
    with pytest.raises(ValueError, match="distinct speeds"):
        fit_resistance([1.0, 1.0], [-1.0, -1.0], U_ref_m_s=1.0, order=1)


@pytest.mark.parametrize(
    "bad",
    [
        lambda: fit_static_drift([0.0, 0.0], [1, 1], [1, 1], U_m_s=1, normalisation="SI"),
        lambda: fit_pure_sway(np.arange(3.0), np.zeros(3), np.zeros(3), np.zeros(3), omega_rad_s=1, U_m_s=1),
        lambda: fit_pure_sway(
            np.arange(10.0), np.zeros(9), np.zeros(10), np.zeros(10), omega_rad_s=1, U_m_s=1
        ),
        lambda: fit_pure_yaw(
            np.arange(10.0), np.zeros(10), np.zeros(10), np.zeros(10), omega_rad_s=-1, U_m_s=1
        ),
        lambda: fit_static_drift([0.0, 0.1], [0, 1], [0, 1], U_m_s=1, normalisation="rho_L2_U2"),
    ],
)
def test_bad_inputs_raise_value_error(bad):
    with pytest.raises(ValueError):
        bad()
