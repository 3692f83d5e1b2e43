"""vessel-gym: a Gymnasium environment suite for ship manoeuvring.

Importing the package registers the environment ids (``vessel_gym/ZigZag-v1``, ``vessel_gym/ZigZagRandom-v1``,
``vessel_gym/TurningCircle-v0``, ``vessel_gym/HarbourApproach-v0`` and the deprecated ``vessel_gym/ZigZag-v0``)
with Gymnasium; entry points are strings, so nothing heavy loads here.
"""

from vessel_gym.envs.registration import register_envs as _register_envs

__version__ = "0.1.0"

_register_envs()
