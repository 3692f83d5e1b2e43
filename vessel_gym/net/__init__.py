"""Networking: the UDP link (NMEA 0183 + AIS out, JSON state out, helm commands in), pacing and clients.

The network client of the panels is :class:`vessel_gym.net.clients.ServerConnection`; the pygame helm and
viewer panels that draw with it live in :mod:`vessel_gym.ui.panels` (nothing here imports from ``ui``).
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
