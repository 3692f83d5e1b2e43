"""Former home of keyboard play, kept for existing imports: it lives in :mod:`vessel_gym.ui.play`."""

from vessel_gym.ui.play import *  # noqa: F403
