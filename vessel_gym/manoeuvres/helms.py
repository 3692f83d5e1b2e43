"""Scripted reference helms: the rules a trials helmsman follows, as small stateful policies.

They read only heading change (rad, relative to the original course) and return a rudder order (rad); the
manoeuvre runners (:mod:`vessel_gym.manoeuvres.trials`) use them. The rule itself is not theirs: the
zig-zag execute is :func:`vessel_gym.control.zigzag.target_reached` and
:func:`~vessel_gym.control.zigzag.zigzag_execute`, the same compiled functions that the ZigZag task kernel
runs (whose target flips as the execute is due; its scripted policy,
:class:`vessel_gym.envs.policies.ZigZagRule`, puts the rudder to the side of that target).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from vessel_gym.control.zigzag import target_reached, zigzag_execute


@dataclass
class TurnHelm:
    """Turning circle: rudder hard over at the first execute and held (MSC.137(76) Annex §4.2.2)."""

    rudder_rad: float

    def order(self, heading_change_rad: float) -> float:
        return self.rudder_rad


@dataclass
class ZigZagHelm:
    """The zig-zag rule (MSC.137(76) Annex §4.2.4): rudder to +delta; when the heading has changed by psi
    to that side, reverse the rudder; repeat at psi on the other side.

    ``rudder_rad`` > 0 puts the first execute to starboard. ``executes`` records the heading change at
    every execute; ``side`` is +1 while the rudder is to starboard, ``target`` the heading change (rad) at
    which the next execute is due.
    """

    rudder_rad: float
    heading_rad: float
    side: int = 0
    target: float = 0.0
    executes: list[float] = field(default_factory=list)

    def __post_init__(self) -> None:
        if self.rudder_rad == 0.0 or self.heading_rad <= 0.0:
            raise ValueError("zig-zag needs a nonzero rudder angle and a positive heading change")
        self.side = 1 if self.rudder_rad > 0 else -1
        self.target = self.side * self.heading_rad
        self.executes = [0.0]

    @property
    def magnitude(self) -> float:
        return abs(self.rudder_rad)

    def order(self, heading_change_rad: float) -> float:
        if target_reached(self.side, heading_change_rad, self.target):
            side, self.target = zigzag_execute(0.0, self.side, self.heading_rad)
            self.side = int(side)
            self.executes.append(heading_change_rad)
        return self.side * self.magnitude
