"""Former home of the pygame chart renderer, kept for existing imports: it lives in :mod:`vessel_gym.ui.chart`."""

from vessel_gym.ui.chart import *  # noqa: F403
