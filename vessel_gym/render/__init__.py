"""Former home of the pygame chart viewer, kept for existing imports: it lives in :mod:`vessel_gym.ui.chart`."""

from vessel_gym.ui.chart import ChartRenderer  # noqa: F401
