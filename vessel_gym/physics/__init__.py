"""The physics core: components, composition, integration. Imports no gymnasium, pygame or sockets.

The compiled kernels are cached in a directory keyed by a hash of their sources, set up here before any
kernel module is imported (:mod:`vessel_gym.physics.jitcache`).
"""

from vessel_gym.physics import jitcache as _jitcache

_jitcache.install()
