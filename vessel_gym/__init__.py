"""vessel-gym: a Gymnasium environment suite for ship manoeuvring.

Importing the package registers the environment ids of the tasks in :mod:`vessel_gym.envs.tasks` (e.g.
``vessel_gym/HarbourApproach-v2``, ``vessel_gym/ZigZag-v1``; :func:`vessel_gym.envs.registration.registered`
lists them) with Gymnasium; the declarations are read from source and the entry points are strings, so nothing
heavy loads here.
"""

from vessel_gym.envs.registration import register_envs as _register_envs

__version__ = "0.1.0"

_register_envs()
