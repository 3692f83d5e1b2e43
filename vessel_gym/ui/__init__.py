"""What a person sees and drives: the pygame chart renderer (:mod:`vessel_gym.ui.chart`), keyboard play
(:mod:`vessel_gym.ui.play`) and the helm and viewer panels of the link (:mod:`vessel_gym.ui.panels`).

The network side of the panels (the UDP client, the protocol) lives in :mod:`vessel_gym.net`; nothing in
``net`` imports from here. pygame is imported only when something is drawn.
"""

from vessel_gym.ui.chart import ChartRenderer

__all__ = ["ChartRenderer"]
