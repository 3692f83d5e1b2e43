"""vessel-cfd: automated OpenFOAM captive tests (tow, static drift, pure sway, pure yaw) that
fit hydrodynamic derivatives and write a ship file for the vessel-gym simulator.

The fitting (:mod:`cfd.fitting`) and the Clarke (1983) regression (:mod:`cfd.clarke`) are pure
numpy and need no OpenFOAM.
"""

from .errors import CfdError, InputError

__version__ = "0.1.0"

__all__ = ["CfdError", "InputError", "__version__"]
