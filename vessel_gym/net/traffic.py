"""Former home of the scenarios' traffic, kept for existing imports: it lives in :mod:`vessel_gym.scenarios.traffic`."""

from vessel_gym.scenarios.traffic import *  # noqa: F403
