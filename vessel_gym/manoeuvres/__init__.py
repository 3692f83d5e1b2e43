"""Standard manoeuvres (turning circle, zig-zag, initial turning, stopping, pull-out) and the IMO
MSC.137(76) criteria, all running on the same physics as the environments."""

from vessel_gym.manoeuvres.helms import TurnHelm, ZigZagHelm
from vessel_gym.manoeuvres.imo import ImoReport, imo_report, zigzag10_limits
from vessel_gym.manoeuvres.trials import (
    ManoeuvreIncomplete,
    initial_turning,
    pull_out,
    stopping,
    trial_dt,
    turning_circle,
    zigzag,
)

__all__ = [
    "ImoReport",
    "ManoeuvreIncomplete",
    "TurnHelm",
    "ZigZagHelm",
    "imo_report",
    "initial_turning",
    "pull_out",
    "stopping",
    "trial_dt",
    "turning_circle",
    "zigzag",
    "zigzag10_limits",
]
