"""FMI 2.0 co-simulation (docs/fmi.md): the whole ship exported as an FMU for other simulators
(:mod:`~vessel_gym.fmi.export`, ``vessel-gym fmu``), and FMUs imported as components of a ship
(:mod:`~vessel_gym.fmi.component`).

Needs the ``fmi`` extra (``pip install 'vessel-gym[fmi]'``: pythonfmu to write FMUs, fmpy to run them); the
rest of vessel-gym never imports this package.
"""

from __future__ import annotations

EXTRA_HINT = "needs the 'fmi' extra: pip install 'vessel-gym[fmi]'"


def require(module: str) -> None:
    """Import ``module`` (pythonfmu or fmpy) or raise ValueError saying which extra installs it."""
    import importlib

    try:
        importlib.import_module(module)
    except ImportError:
        raise ValueError(f"FMI support {EXTRA_HINT} ({module} is not installed)") from None
