"""Static-drift regression forms: exact recovery, standard errors by hand, the choice and its ship-file terms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from cfd_fake_foam import FakeFoam, fake_environment
from test_cfd_pipeline import run, study

from cfd.errors import InputError
from cfd.regression import choose, fit_forms, spread


def _drift(beta_deg, U=1.0):
    return -U * np.sin(np.radians(beta_deg))


def test_each_form_recovers_its_own_data_exactly():
    v = _drift([0, 3, 6, 9, 12])
    cubic = fit_forms(v, -0.2 * v - 3.0 * v**3, -0.05 * v - 0.4 * v**3, U_m_s=1.0)
    assert cubic["abkowitz"].terms == pytest.approx({"Y_v": -0.2, "Y_vvv": -3.0, "N_v": -0.05, "N_vvv": -0.4})
    assert cubic["abkowitz"].residuals["Y"] < 1e-12 and cubic["mmg"].residuals["Y"] > 1e-4
    quad = fit_forms(v, -0.2 * v - 0.8 * v * abs(v), -0.05 * v + 0.1 * v * abs(v), U_m_s=1.0)
    assert quad["mmg"].terms == pytest.approx({"Y_v": -0.2, "Y_v|v|": -0.8, "N_v": -0.05, "N_v|v|": 0.1})
    chosen, why = choose(quad, "auto")
    assert chosen.form == "mmg" and "lowest residual" in why
    assert choose(cubic, "auto")[0].form == "abkowitz"
    assert choose(quad, "abkowitz")[0].form == "abkowitz"  # the default, whatever the residuals
    assert quad["linear"].points == 1  # only 3 deg is a small angle (<= 5 deg)
    assert spread(quad)["Y_v"] > 0.0


def test_standard_error_and_cubic_conversion_by_hand():
    # y = b v through the origin, v = (1, 2), y = (1, 3): b = 7/5, residuals (-0.4, 0.2), s^2 = 0.2 / 1,
    # se(b) = sqrt(s^2 / sum v^2) = sqrt(0.2 / 5) = 0.2
    f = fit_forms([1.0, 2.0], [1.0, 3.0], [1.0, 3.0], U_m_s=100.0)["linear"]
    assert f.terms["Y_v"] == pytest.approx(1.4) and f.std_error["Y_v"] == pytest.approx(0.2)
    # v|v| written as c v^3 with c = sum v^5 / sum v^6 = (1 + 32 + 243) / (1 + 64 + 729) over v = 1, 2, 3
    v = np.array([1.0, 2.0, 3.0])
    mmg = fit_forms(v, 2.0 * v * abs(v), v * abs(v), U_m_s=10.0)["mmg"]
    terms, how = mmg.ship_terms(v)
    assert terms["Y_vvv"] == pytest.approx(2.0 * 276 / 794) and terms["N_vvv"] == pytest.approx(276 / 794)
    assert terms["Y_v"] == pytest.approx(0.0, abs=1e-9) and "least-squares cubic" in how


def test_too_few_angles_fall_back_to_the_linear_fit():
    forms = fit_forms(_drift([0, 4, 8]), [0.0, 1.0, 2.1], [0.0, 0.5, 1.0], U_m_s=1.0)
    assert set(forms) == {"linear"}
    assert choose(forms, "mmg")[0].form == "linear"
    with pytest.raises(ValueError, match="drift_form"):
        choose(forms, "quartic")


def test_the_option_selects_the_ship_file_terms(tmp_path, monkeypatch):
    fake = fake_environment(monkeypatch, FakeFoam())
    result = run(
        study(tmp_path, tests="drift", speeds="1.0", drift_deg="3,6,9,12", drift_form="linear"), fake
    )
    reg = result.provenance["tests"]["drift"]["regression"]
    assert reg["written"] == "linear" and set(reg["forms"]) == {"abkowitz", "mmg", "linear"}
    assert "Y_vvv" not in result.derivatives  # linear: no cubic term in the ship file
    # the fake hull is exactly cubic, so the small-angle (3 deg) slope sits slightly above Y_v
    assert result.derivatives["Y_v"] == pytest.approx(
        -0.009 - 0.03 * math.sin(math.radians(3)) ** 2, rel=1e-6
    )
    summary = (result.report_dir / "summary.md").read_text()
    assert (
        "## Static drift: regression forms" in summary and "Written to the ship file: **linear**" in summary
    )
    with pytest.raises(InputError, match="drift_form"):
        study(tmp_path, drift_form="quadratic")
