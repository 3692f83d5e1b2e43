"""Targets as received over AIS (``targets_observed="ais"``): the target list of CollisionAvoidance built from
position reports instead of the truth.

Each target transmits position reports at the rate ITU-R M.1371-5 (Technical characteristics for an
automatic identification system using TDMA in the VHF maritime mobile band), Annex 1, **Table 1** sets for
a Class A shipborne mobile station under way by its speed over ground and whether it is changing course:

=====================  ================  =====================
speed over ground      keeping course    changing course
=====================  ================  =====================
0-14 kn                10 s              3 1/3 s
14-23 kn               6 s               2 s
above 23 kn            2 s               2 s
=====================  ================  =====================

(a ship at anchor or moored: 3 min, not simulated: every target is under way), or, for ``ais_class="B"``,
the rate of a Class B "CS" station, **Table 2** of the same annex: 30 s above 2 kn, 3 min at or below.
The table names "changing course" without a number; here a target is changing course while its rate of
turn exceeds ``ais_turning_deg_min`` (deg/min, our choice).

A report is received with probability 1 - ``ais_dropout`` (each reception drawn independently: a lost slot,
a collision on the channel), and carries the target's position, SOG and COG with Gaussian errors (standard
deviations ``ais_position_sigma_m``, ``ais_sog_sigma_kn``, ``ais_cog_sigma_deg``), rounded to the message's
resolution (SOG 0.1 kn, COG 0.1 deg). Between reports the receiver **dead-reckons** the last one: position
+ (time since the report) x the reported velocity. So the observed target lags a manoeuvre by up to a
reporting interval (more after a dropout) and steps when a report arrives.

Reports fall between control steps: the task sees the ships only at its steps, so a report due at time
t_r inside the last step carries the position the target had then, taken back from the step's end along
its velocity (exact for a target keeping course and speed). At a reset every target is known from one
report at time 0 (noisy, never dropped), and its next transmission is drawn uniformly within its interval,
so the ships' report phases differ.

Only the observation is affected: the rule records, the contact test, the closest range and the reward
read the truth (they are the referee's), and the situation flags of a slot are those the rule record
classified at detection. Every draw comes from a generator per own ship seeded from the reset's, so an
episode is reproducible from its seed.
"""

from __future__ import annotations

import math

import numpy as np

from vessel_gym.physics.units import KNOT_M_S

#: ITU-R M.1371-5 Annex 1 Table 1, Class A under way: (SOG upper bound kn, interval s keeping course,
#: interval s changing course), the first row whose bound exceeds the SOG applies
CLASS_A = ((14.0, 10.0, 10.0 / 3.0), (23.0, 6.0, 2.0), (math.inf, 2.0, 2.0))
#: ITU-R M.1371-5 Annex 1 Table 2, Class B "CS": (SOG upper bound kn, interval s) - 2 kn or less: 3 min
CLASS_B = ((2.0, 180.0), (math.inf, 30.0))
SOG_RESOLUTION_KN = 0.1  # kn, the position report's SOG field
COG_RESOLUTION_DEG = 0.1  # deg, its COG field

#: the columns of a received report: position (m), velocity over ground (m/s) and time (s)
REP_N, REP_E, REP_VN, REP_VE, REP_T = range(5)


def reporting_interval(sog_kn: float, turning: bool, cls: str = "A") -> float:
    """Seconds between position reports of a ship under way at ``sog_kn`` kn, ``turning`` or not
    (ITU-R M.1371-5 Annex 1, Table 1 for Class A, Table 2 for Class B "CS")."""
    if cls == "A":
        for bound, keep, change in CLASS_A:
            if sog_kn < bound:
                return change if turning else keep
    for bound, interval in CLASS_B:
        if sog_kn <= bound:
            return interval
    raise AssertionError("unreachable: the last row's bound is infinite")


class AisReceiver:
    """What each own ship has received of each other ship of its encounter (by slot), and when the next
    transmission of each is due."""

    def __init__(
        self,
        n_own: int,
        slots: int,
        cls: str,
        dropout: float,
        sigma_pos_m: float,
        sigma_sog_kn: float,
        sigma_cog_deg: float,
        turning_deg_min: float,
    ) -> None:
        self.cls = cls
        self.dropout = dropout
        self.sigma_pos = sigma_pos_m
        self.sigma_sog = sigma_sog_kn
        self.sigma_cog = sigma_cog_deg
        self.turning = math.radians(turning_deg_min) / 60.0  # rad/s
        self.rep = np.zeros((n_own, slots, 5))
        self.due = np.full((n_own, slots), math.nan)  # s, next transmission (NaN: not yet heard)
        self.rngs = [np.random.default_rng(k) for k in range(n_own)]

    def reset(self, k: int, rng: np.random.Generator) -> None:
        """Own ship k starts an episode: nothing heard yet; its draws seeded from the reset's ``rng``."""
        self.due[k] = math.nan
        self.rngs[k] = np.random.default_rng(int(rng.integers(2**63)))

    def _interval(self, vn: float, ve: float, r: float) -> float:
        return reporting_interval(math.hypot(vn, ve) / KNOT_M_S, abs(r) > self.turning, self.cls)

    def _receive(self, k: int, slot: int, t: float, n: float, e: float, vn: float, ve: float) -> None:
        g = self.rngs[k]
        sog = math.hypot(vn, ve) / KNOT_M_S + self.sigma_sog * g.standard_normal()
        cog = math.degrees(math.atan2(ve, vn)) + self.sigma_cog * g.standard_normal()
        sog = max(0.0, round(sog / SOG_RESOLUTION_KN) * SOG_RESOLUTION_KN) * KNOT_M_S
        cog = math.radians(round(cog / COG_RESOLUTION_DEG) * COG_RESOLUTION_DEG)
        row = self.rep[k, slot]
        row[REP_N] = n + self.sigma_pos * g.standard_normal()
        row[REP_E] = e + self.sigma_pos * g.standard_normal()
        row[REP_VN], row[REP_VE] = sog * math.cos(cog), sog * math.sin(cog)
        row[REP_T] = t

    def observe(
        self, k: int, slot: int, t: float, n: float, e: float, vn: float, ve: float, r: float
    ) -> tuple[float, float, float, float]:
        """Own ship k's picture at time ``t`` (s) of the ship in ``slot``, whose truth is position (``n``, ``e``)
        m, velocity over ground (``vn``, ``ve``) m/s and rate of turn ``r`` rad/s: (north, east, vn, ve) of
        its last received report, dead-reckoned to ``t``. Receives the transmissions due up to ``t``."""
        due = self.due[k, slot]
        if math.isnan(due):  # first sight at the reset: one report now, the next one at a random phase
            self._receive(k, slot, t, n, e, vn, ve)
            due = t + self.rngs[k].random() * self._interval(vn, ve, r)
        g = self.rngs[k]
        while due <= t:
            back = t - due  # s: the report was sent that long before this step's end
            if g.random() >= self.dropout:
                self._receive(k, slot, due, n - vn * back, e - ve * back, vn, ve)
            due += self._interval(vn, ve, r)
        self.due[k, slot] = due
        row = self.rep[k, slot]
        age = t - row[REP_T]
        return row[REP_N] + row[REP_VN] * age, row[REP_E] + row[REP_VE] * age, row[REP_VN], row[REP_VE]
