"""Scripted reference helms: the rules a trials helmsman follows, as small stateful policies.

They read only heading change (rad, relative to the original course) and return a rudder order (rad),
so the same objects drive the manoeuvre runners here and the scripted policies of the environments.
"""

from __future__ import annotations

from dataclasses import dataclass, field


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

    ``rudder_rad`` > 0 puts the first execute to starboard. ``executes`` records (index, heading change)
    of every rudder reversal; ``side`` is +1 while the rudder is to starboard.
    """

    rudder_rad: float
    heading_rad: float
    side: int = 0
    executes: list[float] = field(default_factory=list)

    def __post_init__(self) -> None:
        if self.rudder_rad == 0.0 or self.heading_rad <= 0.0:
            raise ValueError("zig-zag needs a nonzero rudder angle and a positive heading change")
        self.side = 1 if self.rudder_rad > 0 else -1
        self.executes = [0.0]

    @property
    def magnitude(self) -> float:
        return abs(self.rudder_rad)

    def order(self, heading_change_rad: float) -> float:
        if self.side * heading_change_rad >= self.heading_rad:
            self.side = -self.side
            self.executes.append(heading_change_rad)
        return self.side * self.magnitude
