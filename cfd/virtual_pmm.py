"""Virtual PMM: the simulator's captive mode on a ship file, analysed by the same fits as the CFD runs.

Running the planar-motion-mechanism programme on a ship model whose derivatives are known closes the loop of
the CFD tool: the fits in :mod:`cfd.fitting` must recover that file's derivatives. It is also a quick way to
compare two ship files in the captive-test language of a towing tank.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cfd.fitting import FitResult, fit_pure_sway, fit_pure_yaw, fit_static_drift
from vessel_gym.physics.constraints import pure_sway, pure_yaw, static_drift
from vessel_gym.physics.shipfile import Ship, load_ship


@dataclass(frozen=True)
class VirtualPmmResult:
    drift: FitResult
    sway: FitResult
    yaw: FitResult

    @property
    def derivatives(self) -> dict[str, float]:
        """Linear derivatives: Y_v, N_v from static drift; Y_vdot, N_vdot from pure sway; Y_r, N_r, Y_rdot,
        N_rdot from pure yaw (the usual PMM programme)."""
        d = {k: self.drift.derivatives[k] for k in ("Y_v", "N_v")}
        d.update({k: self.sway.derivatives[k] for k in ("Y_vdot", "N_vdot")})
        d.update({k: self.yaw.derivatives[k] for k in ("Y_r", "N_r", "Y_rdot", "N_rdot")})
        return d


def virtual_pmm(
    ship: str | Ship,
    speed_m_s: float | None = None,
    drift_deg=(-4.0, -2.0, -1.0, 1.0, 2.0, 4.0),
    sway_amplitude_L: float = 0.01,
    yaw_amplitude_deg: float = 3.0,
    period_L_over_U: float = 6.0,
    normalisation: str = "rho_L2_U2",
) -> VirtualPmmResult:
    """Static drift, pure sway and pure yaw on ``ship`` in captive mode, fitted by :mod:`cfd.fitting`.

    Small amplitudes keep the runs in the linear range (the fits are linear unless asked otherwise); the
    period is given in units of L/U (a typical PMM nondimensional frequency omega' = 2 pi / 6 ~ 1).
    """
    s = load_ship(ship)
    U = s.test_speed_m_s if speed_m_s is None else speed_m_s
    L = s.particulars.L_m
    rho = s.particulars.rho_kg_m3
    T = period_L_over_U * L / U
    w = 2.0 * math.pi / T
    d = static_drift(s, U, np.asarray(drift_deg))
    drift = fit_static_drift(
        d.v, d.Y, d.N, U_m_s=U, L_m=L, rho_kg_m3=rho, normalisation=normalisation, cubic=False
    )
    sw = pure_sway(s, U, sway_amplitude_L * L, T)
    sway = fit_pure_sway(
        sw.t, sw.y, sw.Y, sw.N, omega_rad_s=w, U_m_s=U, L_m=L, rho_kg_m3=rho, normalisation=normalisation
    )
    yw = pure_yaw(s, U, yaw_amplitude_deg, T)
    yaw = fit_pure_yaw(
        yw.t, yw.psi, yw.Y, yw.N, omega_rad_s=w, U_m_s=U, L_m=L, rho_kg_m3=rho, normalisation=normalisation
    )
    return VirtualPmmResult(drift, sway, yaw)
