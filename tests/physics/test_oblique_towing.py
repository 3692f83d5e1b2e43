"""Oblique towing of the KVLCC2 over 0-180 deg of drift, deep water, against published captive data: the steady
current loads on a loaded VLCC of OCIMF (1994), "Prediction of Wind and Current Loads on VLCCs", as reproduced
in OCIMF MEG3 (2008) Annex A, Figures A5-A11 (tests/physics/ocimf_reference.py: source, sign convention,
digitisation). The hull forces come from the public captive rig (constraints.static_drift), i.e. the MMG
polynomial inside its fitted range and the Yoshimura, Nakao & Ishibashi (2009) cross-flow model outside it.

Tolerance, as a fraction of each curve's peak over 0-180 deg (ocimf_reference.TOLERANCE_FRACTION): the scatter
band OCIMF draws about its curves (MEG3 Fig. A12, half-width 16.7 % of the peak; the KVLCC2 is not one of the
tested hulls, so it cannot be expected closer) plus the digitising error of that coefficient (half the largest
difference between two independent readings of the published curves: 3.2 % in X', 6.8 % in Y', 5.4 % in N'),
so 19.9 %, 23.5 % and 22.1 % (0.0095, 0.138, 0.0176). Both parts come from the published data, not from the
model. X' is compared with the band between OCIMF's conventional-bow and cylindrical-bow curves, since
which one the KVLCC2's bulbous bow belongs to is not established.

The sweep is cut into ranges by the model's structure (not by the results): the published MMG polynomial
(flow angle chi <= 20 deg from ahead), the cross-flow model with the bow leading (30-80 deg), beam on (90 deg),
the stern leading (100-150 deg) and sternway at small drift (160-180 deg). Where the model misses the data by
more than the tolerance the case is an expected failure (strict: it must keep failing until the model
changes) with the measured gap; docs/physics.md discusses each.
"""

from __future__ import annotations

import numpy as np
import ocimf_reference as ref
import pytest

from vessel_gym.physics.constraints import static_drift
from vessel_gym.physics.shipfile import load_ship

#: tow speed, m/s (about 2 kn, a design current of OCIMF's); every coefficient here is independent of speed
#: (the cross-flow model is quadratic in the velocities, the MMG polynomial is non-dimensional above U_min)
U_TOW = 1.0

#: flow angle chi from the bow (deg) of each range, cut where the model changes form (crossflow.py blend limits
#: 22/35 deg; the cross-flow model is symmetric fore and aft about 90 deg)
RANGES = {
    "ahead_mmg_polynomial": (0.0, 10.0, 20.0),
    "bow_leading": (30.0, 40.0, 50.0, 60.0, 70.0, 80.0),
    "beam": (90.0,),
    "stern_leading": (100.0, 110.0, 120.0, 130.0, 140.0, 150.0),
    "sternway": (160.0, 170.0, 180.0),
}

#: measured gaps beyond the tolerance, as of this commit (docs/physics.md, "Hull at any drift angle")
GAPS = {
    ("X", "ahead_mmg_polynomial"): (
        "straight-ahead resistance: the KVLCC2's measured R'_0 = 0.022 against OCIMF's fleet C_Xc = 0.034; "
        "gap 0.014 at 20 deg (tolerance 0.0095)"
    ),
    ("X", "bow_leading"): (
        "OCIMF's surge force turns up-current (forward) at 50-80 deg, up to +0.042 (the hull's lift); the "
        "cross-flow model's X'_0(chi) u U is resistive at every angle: gap 0.053 at 60 deg"
    ),
    ("X", "stern_leading"): (
        "the same lift effect with the stern leading (OCIMF X' < 0 at 110-130 deg while the model's is > 0): "
        "gap 0.021 at 120 deg"
    ),
    ("Y", "bow_leading"): (
        "C_D = 0.9665 (Esso Osaka estimate) against OCIMF's deep-water 0.585 at 90 deg: Y' 0.955 against 0.536 "
        "at 70 deg, gap 0.42"
    ),
    ("Y", "beam"): "C_D = 0.9665 against OCIMF 0.585 (UFC 4-159-03: 0.594): gap 0.38 at 90 deg",
    ("Y", "stern_leading"): "C_D = 0.9665 against OCIMF 0.585: gap 0.43 at 110 deg",
    ("N", "bow_leading"): (
        "the cross-flow moment is symmetric fore and aft; OCIMF's centre of pressure moves aft towards the beam: "
        "N' -0.044 against -0.025 at 70 deg, gap 0.020"
    ),
    ("N", "beam"): (
        "OCIMF has a yaw moment beam-on (N' = +0.018, lateral centre of pressure 0.03 L aft of midships); the "
        "symmetric cross-flow integral has none: gap 0.0179, at the edge of the tolerance (0.0176)"
    ),
}

COEFFICIENTS = ("X", "Y", "N")


@pytest.fixture(scope="module")
def sweep():
    """Model and data over chi = 0-180 deg (ship moving to starboard through the water), non-dimensional on
    1/2 rho L d U^2 (X', Y') and 1/2 rho L^2 d U^2 (N')."""
    ship = load_ship("kvlcc2")
    p = ship.particulars
    chi, X_data, Y_data, N_data = ref.ship_axes(ref.THETA_DEG)
    # MMG drift angle beta = atan(-v/u): beta = -chi gives u = U cos(chi), v = +U sin(chi)
    rec = static_drift(ship, U_TOW, -chi)
    q = 0.5 * p.rho_kg_m3 * p.L_m * p.T_m * U_TOW**2
    model = {"X": rec.X / q, "Y": rec.Y / q, "N": rec.N / (q * p.L_m)}
    band_lo, band_hi = X_data.min(axis=0), X_data.max(axis=0)
    gap = {
        "X": np.maximum(0.0, np.maximum(band_lo - model["X"], model["X"] - band_hi)),
        "Y": np.abs(model["Y"] - Y_data),
        "N": np.abs(model["N"] - N_data),
    }
    tol = {
        k: ref.TOLERANCE_FRACTION[k] * np.abs(d).max()
        for k, d in (("X", X_data), ("Y", Y_data), ("N", N_data))
    }
    return chi, gap, tol


def _case(coef, name):
    reason = GAPS.get((coef, name))
    marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
    return pytest.param(coef, name, marks=marks, id=f"{coef}-{name}")


@pytest.mark.parametrize("coef, name", [_case(c, n) for n in RANGES for c in COEFFICIENTS])
def test_oblique_towing_forces_against_ocimf(sweep, coef, name):
    chi, gap, tol = sweep
    idx = [int(np.flatnonzero(chi == c)[0]) for c in RANGES[name]]
    worst = int(idx[int(np.argmax(gap[coef][idx]))])
    assert gap[coef][worst] <= tol[coef], (
        f"{coef}' misses OCIMF by {gap[coef][worst]:.4f} at chi = {chi[worst]:g} deg (tolerance {tol[coef]:.4f})"
    )


def test_reference_data_convention_and_digitisation():
    """The OCIMF curves read as documented (ocimf_reference): drag along the current at 0 and 180 deg, the
    lateral centre of pressure at the leading end at small angles (the Munk moment, as the KVLCC2's published
    N'_v/Y'_v > 0 has it moving ahead), two independent readings of the same published curves agree to within
    16 % of their peak, and the scatter band is the 17 % the tolerance uses. The UFC 4-159-03 formula
    (other model tests) gives OCIMF's beam-on lateral force for the KVLCC2 within the tolerance."""
    chi, X, Y, N = ref.ship_axes(ref.THETA_DEG)
    ahead, astern = int(np.flatnonzero(chi == 0.0)[0]), int(np.flatnonzero(chi == 180.0)[0])
    assert np.all(X[:, ahead] < 0.0) and np.all(X[:, astern] > 0.0)
    for c, sign in ((10.0, 1.0), (20.0, 1.0), (160.0, -1.0), (170.0, -1.0)):
        i = int(np.flatnonzero(chi == c)[0])
        assert sign * N[i] / Y[i] > 0.1, c  # centre of pressure at least 0.1 L towards the leading end
    hull = load_ship("kvlcc2").hull
    assert hull.N_v / hull.Y_v > 0.0
    assert all(ref.digitising_fraction(k) < 0.08 for k in ("X", "Y", "N"))
    assert 0.1 < ref.scatter_band_fraction() < 0.2
    p = load_ship("kvlcc2").particulars
    ufc = ref.ufc_deep_water_lateral(
        p.L_m, p.B_m, p.T_m, p.displacement_m3, ref.KVLCC2_L_WL_M, ref.KVLCC2_C_M
    )
    beam = int(np.flatnonzero(chi == 90.0)[0])
    assert abs(ufc - (-Y[beam])) <= ref.TOLERANCE_FRACTION["Y"] * np.abs(Y).max()
