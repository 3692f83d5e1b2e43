"""The zig-zag rule and the overshoot tracker (IMO MSC.137(76) Annex §4.2.4 and MSC/Circ.1053 §3.4).

The zig-zag test: rudder to +delta; when the heading has changed by psi to that side of the original course
(the "execute"), the rudder goes to -delta; when it has changed by psi to the other side, back again. The
overshoot angle is the heading excursion beyond the execute heading (the target) at the following extreme of
heading, where the yaw rate changes sign.

The rule, as compiled scalar functions that the trials (:func:`vessel_gym.manoeuvres.trials.zigzag`), the
trials helm (:class:`vessel_gym.manoeuvres.helms.ZigZagHelm`), the ZigZag task kernel
(:mod:`vessel_gym.envs.tasks.zigzag`, :mod:`~vessel_gym.envs.tasks.zigzag_v1`) and the evaluation metrics (:mod:`agents.common`) all call:

* :func:`target_reached`: the heading has reached or passed the target on its side (an execute is due);
* :func:`zigzag_execute`: the target moves to psi on the other side of the original course;
* :func:`overshoot_excursion` and :func:`overshoot_step`: the excursion past the target and one step of the
  tracker that finds its extreme.

The tracker has two modes, because an environment's reward needs a measurement per course change that the
trial's does not give:

* :data:`OVERSHOOT_IMO` (the trial): the extreme is the last sample at which the excursion still grew (within
  :data:`PEAK_TOL_RAD`); the measurement ends at the first sample after it at which the yaw rate has strictly
  reversed.
* :data:`OVERSHOOT_V1` (ZigZag-v1 and ZigZagRandom-v1): the overshoot of a course change is the largest
  excursion past its target from the sample at which the target is reached until the measurement is closed
  from outside, when the next course change starts (in the IMO schedule, where a change starts at the very
  sample its predecessor's target is reached, when the change after that starts); the yaw rate does not end
  it, so a ship that swings past, turns back and swings past again is charged its largest excursion. A
  measurement still open at the end of an episode counts with what it has. For a ship that turns back once
  before the next target, it is the IMO overshoot sampled at the control steps.
"""

from __future__ import annotations

from numba import njit

OVERSHOOT_IMO = 0
OVERSHOOT_V1 = 1
#: tolerance of the trial's "excursion still growing" test, rad (a sample equal to the peak to rounding
#: keeps the measurement open)
PEAK_TOL_RAD = 1e-12


@njit(cache=True)
def target_reached(side, heading, target):
    """True when ``heading`` (rad) has reached or passed ``target`` (rad, same branch) on ``side`` (+1 a
    target to starboard of the previous one, -1 to port)."""
    return side * (heading - target) >= 0.0


@njit(cache=True)
def zigzag_execute(original_course, side, psi_z):
    """The execute: (new side, new target) with the target ``psi_z`` (rad) to the other side of the original
    course (rad)."""
    side = -side
    return side, original_course + side * psi_z


@njit(cache=True)
def overshoot_excursion(sign, target, heading):
    """Heading excursion (rad) past ``target`` to the side ``sign`` (+1 starboard) of the swing."""
    return sign * (heading - target)


@njit(cache=True)
def overshoot_step(sign, target, peak, heading, r, mode):
    """One sample of the overshoot tracker: (peak, rose, finished).

    ``peak`` (rad) is the largest excursion past ``target`` so far (start it with the excursion at the
    execute); ``rose`` tells that this sample set it; ``finished`` that the extreme has passed (``peak`` is
    then the overshoot angle). ``r`` is the yaw rate, rad/s; ``mode`` :data:`OVERSHOOT_IMO`
    or :data:`OVERSHOOT_V1` (module docstring; in V1 ``finished`` is always False: the
    caller closes the measurement when the next course change starts).
    """
    exc = overshoot_excursion(sign, target, heading)
    if mode == OVERSHOOT_IMO:
        if exc > peak - PEAK_TOL_RAD:
            return exc, True, False
        return peak, False, sign * r < 0.0
    if exc > peak:
        return exc, True, False
    return peak, False, False


class OvershootTracker:
    """The overshoot measurements of one zig-zag (Python state around :func:`overshoot_step`).

    :meth:`start` at every execute; :meth:`update` at every sample after it. ``overshoots_rad`` and
    ``times_s`` collect the finished overshoots and the times of their extremes.
    """

    def __init__(self, mode: int = OVERSHOOT_IMO) -> None:
        self.mode = mode
        self.active = False
        self.sign = 0.0
        self.target = 0.0
        self.peak = 0.0
        self.peak_t = 0.0
        self.overshoots_rad: list[float] = []
        self.times_s: list[float] = []

    def start(self, sign: float, target_rad: float, heading_rad: float, t_s: float) -> None:
        """A new measurement: the swing goes on to side ``sign`` past ``target_rad``."""
        self.active = True
        self.sign = float(sign)
        self.target = float(target_rad)
        self.peak = overshoot_excursion(self.sign, self.target, float(heading_rad))
        self.peak_t = t_s

    def update(self, heading_rad: float, r_rad_s: float, t_s: float) -> bool:
        """One sample; True when an overshoot has just been completed."""
        if not self.active:
            return False
        self.peak, rose, finished = overshoot_step(
            self.sign, self.target, self.peak, float(heading_rad), float(r_rad_s), self.mode
        )
        if rose:
            self.peak_t = t_s
        if finished:
            self.close()
        return finished

    def close(self) -> None:
        """Count the open measurement as it stands and end it (how :data:`OVERSHOOT_V1` measurements end:
        when the next course change starts, or at the end of the episode)."""
        if self.active:
            self.overshoots_rad.append(self.peak)
            self.times_s.append(self.peak_t)
            self.active = False


__all__ = [
    "OVERSHOOT_IMO",
    "OVERSHOOT_V1",
    "PEAK_TOL_RAD",
    "OvershootTracker",
    "overshoot_excursion",
    "overshoot_step",
    "target_reached",
    "zigzag_execute",
]
