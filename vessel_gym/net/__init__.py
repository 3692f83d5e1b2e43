"""Networking: the UDP link (NMEA 0183 + AIS out, JSON state out, helm commands in), pacing and clients.

The pygame clients live in :mod:`vessel_gym.net.clients` and import pygame only when they draw.
"""

from vessel_gym.net.link import HelmState, LinkConfig, UdpLink
from vessel_gym.net.nmea import Talkers
from vessel_gym.net.pacing import RealTimePacer
from vessel_gym.net.protocol import HelmCommand, Limits, ProtocolError, Target

__all__ = [
    "HelmCommand",
    "HelmState",
    "Limits",
    "LinkConfig",
    "ProtocolError",
    "RealTimePacer",
    "Talkers",
    "Target",
    "UdpLink",
]
