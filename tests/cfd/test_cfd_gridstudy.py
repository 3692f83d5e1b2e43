"""Grid study: Richardson extrapolation and GCI against Celik et al. (2008) and hand-computed values, and
the `vessel-cfd study` command on the fake-foam double with a known second-order grid error."""

from __future__ import annotations

import json
import math

import pytest
from cfd_fake_foam import C_R, TRUE_PRIME, FakeFoam, fake_environment
from test_cfd_pipeline import DATA

from cfd.gridstudy import TWO_GRIDS, grid_convergence, grid_convergence_two, grid_size

# Celik et al. (2008), ASME J. Fluids Eng. 130 078001, Table 1, first column (2-D grids, h = N^-1/2):
# N = 18000, 8000, 4500; phi = 6.063, 5.972, 5.863 -> r21 = 1.5, r32 = 1.333, p = 1.53, phi_ext = 6.1685,
# e_a = 1.5 %, e_ext = 1.7 %, GCI_fine = 2.2 % (the published values, rounded as printed)
CELIK_H = tuple(grid_size(n, dimensions=2) for n in (18000, 8000, 4500))


def test_celik_2008_worked_example():
    g = grid_convergence((6.063, 5.972, 5.863), CELIK_H)
    assert g.condition == "monotonic"
    assert g.r21 == pytest.approx(1.5) and g.r32 == pytest.approx(1.333, abs=5e-4)
    assert g.p == pytest.approx(1.53, abs=0.005)
    assert g.phi_ext == pytest.approx(6.1685, abs=5e-5)
    assert 100 * g.e_a == pytest.approx(1.5, abs=0.05) and 100 * g.e_ext == pytest.approx(1.7, abs=0.05)
    assert 100 * g.gci_fine == pytest.approx(2.2, abs=0.05)


def test_second_order_data_extrapolate_exactly():
    # phi = 1 + 0.3 h^2 on h = 1, 2, 4: eps21 = 0.9, eps32 = 3.6, R = 0.25, p = 2, phi_ext = 1,
    # e_a = 0.9 / 1.3, GCI = 1.25 e_a / (2^2 - 1)
    g = grid_convergence((1.3, 2.2, 5.8), (1.0, 2.0, 4.0))
    assert g.R == pytest.approx(0.25) and g.p == pytest.approx(2.0) and g.phi_ext == pytest.approx(1.0)
    assert g.gci_fine == pytest.approx(1.25 * (0.9 / 1.3) / 3.0)
    assert g.uncertainty == pytest.approx(g.gci_fine * 1.3)


def test_an_order_above_the_formal_one_is_capped_in_the_gci():
    # phi = 1 + 0.01 h^4 on h = 1, 2, 4: p = 4 and phi_ext = 1 exactly, but the GCI uses p = 2 (Roache):
    # 1.25 e_a / (2^2 - 1) with e_a = 0.15 / 1.01, where p = 4 would give 1.25 e_a / 15, five times less
    g = grid_convergence((1.01, 1.16, 3.56), (1.0, 2.0, 4.0))
    assert g.p == pytest.approx(4.0) and g.p_gci == 2.0 and g.phi_ext == pytest.approx(1.0)
    assert g.gci_fine == pytest.approx(1.25 * (0.15 / 1.01) / 3.0)


def test_oscillatory_and_divergent_data():
    osc = grid_convergence((6.0, 5.9, 6.2), (1.0, 1.5, 2.25))  # R = -0.1 / 0.3 < 0
    assert osc.condition == "oscillatory" and osc.R == pytest.approx(-1.0 / 3.0)
    assert osc.uncertainty == pytest.approx(0.5 * (6.2 - 5.9))  # ITTC: half the range
    assert osc.gci_fine is None
    div = grid_convergence((5.0, 5.5, 5.7), (1.0, 1.5, 2.25))  # R = 0.5 / 0.2 > 1
    assert div.condition == "divergent" and div.R == pytest.approx(2.5) and div.uncertainty is None
    same = grid_convergence((2.0, 2.0, 2.0), (1.0, 2.0, 4.0))
    assert same.condition == "converged" and same.uncertainty == 0.0
    with pytest.raises(ValueError, match="grid sizes"):
        grid_convergence((1.0, 2.0, 3.0), (2.0, 1.0, 4.0))


def test_two_grids_assume_the_formal_order_with_roaches_safety_factor_3():
    # phi = 1 + 0.3 h^2 on h = 1, 2: with p = 2 assumed the extrapolation is exact (phi_ext = 1), and
    # GCI = 3 e_a / (2^2 - 1) with e_a = 0.9 / 1.3 (Roache 1998: F_s = 3 when the order is not observed)
    g = grid_convergence_two((1.3, 2.2), (1.0, 2.0))
    assert g.condition == TWO_GRIDS and g.R is None and g.r32 is None and g.p is None and g.p_gci == 2.0
    assert g.phi_ext == pytest.approx(1.0)
    assert g.gci_fine == pytest.approx(3.0 * (0.9 / 1.3) / 3.0) and g.uncertainty == pytest.approx(0.9)
    # against three grids on the same data the two-grid GCI is the more conservative: F_s 3 / 1.25
    three = grid_convergence((1.3, 2.2, 5.8), (1.0, 2.0, 4.0))
    assert g.gci_fine == pytest.approx(three.gci_fine * 3.0 / 1.25)
    # Celik et al.'s finest two grids: r = 1.5, e_a = 0.091 / 6.063, GCI = 3 e_a / 1.25
    c = grid_convergence_two((6.063, 5.972), CELIK_H[:2])
    assert c.gci_fine == pytest.approx(3.0 * (0.091 / 6.063) / 1.25)
    with pytest.raises(ValueError, match="grid sizes"):
        grid_convergence_two((1.0, 2.0), (2.0, 1.0))
    with pytest.raises(ValueError, match="finest-grid value is 0"):
        grid_convergence_two((0.0, 2.0), (1.0, 2.0))


def test_study_command_recovers_the_fake_hull_by_richardson_extrapolation(tmp_path, monkeypatch, capsys):
    from cfd.cli import main

    fake_environment(monkeypatch, FakeFoam(grid_error=5.0))
    out = tmp_path / "grid"
    args = ["study", "--gradings", "1,2,3", "--hull", "wigley", "--lpp", "1", "--bwl", "0.1"]
    args += ["--tm", "0.0625"]
    args += ["--tests", "tow,drift", "--speeds", "1.0", "--pmm-speed", "1.0", "--drift-deg", "3,6,9"]
    args += ["--rho", "1000", "--nu", "1e-6", "--out", str(out), "--template", str(DATA / "small_ship.toml")]
    args += ["--scale-to", "cfd", "--quiet"]
    assert main(args) == 0
    assert "R_T_N: monotonic, GCI" in capsys.readouterr().out
    rep = json.loads((out / "grid_study.json").read_text())
    assert rep["gradings"] == [3, 2, 1] and rep["h_relative"] == pytest.approx([1.0, 2.0, 4.0])
    rt = rep["quantities"]["R_T_N"]
    assert rt["p"] == pytest.approx(2.0) and rt["phi_ext"] == pytest.approx(C_R * 1.0**2)
    for k in ("Y_v", "N_v", "Y_vvv"):
        assert rep["quantities"][k]["phi_ext"] == pytest.approx(TRUE_PRIME[k], rel=1e-6), k
    assert (out / "grid_study.md").read_text().count("| monotonic |") >= 4
    assert (out / "grid_convergence.png").is_file() and (out / "grading_2" / "ship.toml").is_file()
    assert not math.isnan(rt["gci_fine"])
    # the ship file of the finest grading again, with each derivative's uncertainty, shown by the IMO report
    from vessel_gym.manoeuvres.imo import cfd_uncertainty_line
    from vessel_gym.physics.shipfile import load_ship

    assert rep["ship_file"] == str(out / "ship.toml")
    ship = load_ship(out / "ship.toml")
    table = ship.source.provenance["grid_uncertainty"]
    assert table["gradings"] == [3, 2, 1]
    for k in ("Y_v", "N_v"):
        q = rep["quantities"][k]
        assert table[k]["relative"] == pytest.approx(q["gci_fine"]) and table[k]["condition"] == "monotonic"
    worst = max(table[k]["relative"] for k in ("Y_v", "N_v"))  # the linear ones of a tow-and-drift study
    line = cfd_uncertainty_line(ship)
    assert line.startswith(f"Derived from CFD, ±{100 * worst:.1f} % (largest grid uncertainty of the linear")
    assert f"Y_vvv ±{100 * table['Y_vvv']['relative']:.1f} %" in line
    assert f"Y_v ±{100 * table['Y_v']['relative']:.1f} %" in line
    assert "grid uncertainty (GCI, gradings 3, 2, 1)" in ship.source.notes
    assert cfd_uncertainty_line(load_ship(out / "grading_3" / "ship.toml")) == ""


def test_study_command_on_two_gradings_writes_the_two_grid_gci(tmp_path, monkeypatch, capsys):
    from cfd.cli import main
    from vessel_gym.manoeuvres.imo import cfd_uncertainty_line
    from vessel_gym.physics.shipfile import load_ship

    fake_environment(monkeypatch, FakeFoam(grid_error=5.0))
    out = tmp_path / "grid2"
    args = ["study", "--gradings", "2,1", "--hull", "wigley", "--lpp", "1", "--bwl", "0.1", "--tm", "0.0625"]
    args += ["--tests", "tow,drift", "--speeds", "1.0", "--pmm-speed", "1.0", "--drift-deg", "3,6,9"]
    args += ["--rho", "1000", "--nu", "1e-6", "--out", str(out), "--template", str(DATA / "small_ship.toml")]
    args += ["--scale-to", "cfd", "--quiet"]
    assert main(args) == 0
    assert f"R_T_N: {TWO_GRIDS}, GCI" in capsys.readouterr().out
    rep = json.loads((out / "grid_study.json").read_text())
    assert rep["gradings"] == [2, 1] and rep["safety_factor"] == 3.0 and "two grids" in rep["method"]
    # the fake's grid error is exactly second order, so the assumed order extrapolates it exactly
    assert rep["quantities"]["R_T_N"]["phi_ext"] == pytest.approx(C_R * 1.0**2)
    for k in ("Y_v", "N_v"):
        assert rep["quantities"][k]["phi_ext"] == pytest.approx(TRUE_PRIME[k], rel=1e-6), k
    assert "two-grid GCI" in (out / "grid_study.md").read_text()
    ship = load_ship(out / "ship.toml")
    table = ship.source.provenance["grid_uncertainty"]
    assert "two grids" in table["method"] and table["Y_v"]["condition"] == TWO_GRIDS
    worst = max(table[k]["relative"] for k in ("Y_v", "N_v"))
    assert cfd_uncertainty_line(ship).startswith(f"Derived from CFD, ±{100 * worst:.1f} %")


@pytest.mark.parametrize("gradings", ["1", "2,2", "1,2,3,4", "1,2.5"])
def test_study_command_needs_two_or_three_gradings(capsys, gradings):
    from cfd.cli import main

    assert main(["study", "--gradings", gradings, "--hull", "wigley"]) == 2
    assert "gradings: two or three different whole gradings" in capsys.readouterr().err


@pytest.mark.parametrize("study", ["wigley_grid", "wigley_pmm_grid", "dtc_grid"])
def test_the_committed_grid_studies_follow_the_procedure(study):
    """Each committed study's GCI recomputed from its own values and cell counts, and its ship-file table."""
    from pathlib import Path

    from cfd.gridstudy import relative_uncertainty
    from cfd.shipfile import tomllib

    folder = Path(__file__).resolve().parents[2] / "cfd" / "studies" / study
    rep = json.loads((folder / "grid_study.json").read_text())
    table = tomllib.loads((folder / "grid_uncertainty.toml").read_text())["source"]["provenance"]
    table = table["grid_uncertainty"]
    h = tuple(grid_size(n) for n in rep["cells"])
    estimate = grid_convergence if len(h) == 3 else grid_convergence_two
    assert table["gradings"] == rep["gradings"] and table["cells"] == rep["cells"]
    for k, q in rep["quantities"].items():
        g = estimate(tuple(q["phi"]), h)
        assert g.condition == q["condition"], k
        if g.gci_fine is not None:
            assert g.gci_fine == pytest.approx(q["gci_fine"], rel=1e-9), k
        assert table[k]["relative"] == pytest.approx(relative_uncertainty(q), rel=1e-9), k
