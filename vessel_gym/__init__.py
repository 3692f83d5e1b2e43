"""vessel-gym: a Gymnasium environment suite for ship manoeuvring, on validated MMG and Abkowitz physics.

Importing the package registers every environment id (``vessel_gym/<Task>-v<N>``, listed by :func:`env_ids`) with
Gymnasium, so that ``gymnasium.make("vessel_gym/HarbourApproach-v2")`` and ``gymnasium.make_vec(..., num_envs=N)``
work; the entry points are strings, so nothing heavy loads here. The names below are the public API: each one
loads its module on first use (numba compiles the physics kernels on the first simulation, not on import).

Ships
    :func:`load_ship` (a built-in name or a ship file, ``docs/ship-file.md``), :func:`builtin_ships`, :class:`Ship`.
Simulation
    :class:`Simulation` (N ships in one batch, fixed-step RK4), :class:`Environment` (wind, current, waves,
    depth).
Manoeuvres and the IMO criteria
    :func:`imo_report` (all IMO MSC.137(76) criteria, :class:`ImoReport`), the trials :func:`turning_circle`,
    :func:`zigzag`, :func:`initial_turning`, :func:`stopping`, :func:`pull_out`; a trial that cannot finish
    raises :class:`ManoeuvreIncomplete`.
Environments
    :func:`env_ids`, :func:`load_scenario`, :func:`builtin_scenarios`, :class:`Scenario` (harbour charts, start
    and goal regions, weather, traffic) and :func:`load_policy` (the classical pilots and saved SB3 agents as
    ``policy(obs) -> action``); the task classes are in :mod:`vessel_gym.envs`.
Link
    :class:`UdpLink` and :class:`LinkConfig` (NMEA 0183 and JSON over UDP, ``docs/protocol.md``),
    :class:`UdpLinkWrapper` (an environment on the link) and :func:`serve` (a scenario in real time).
Many ships learning together
    :func:`parallel_env` (a task's own ships as the agents of a PettingZoo ``ParallelEnv``; the ``marl``
    extra).

The command line is ``vessel-gym`` (:mod:`vessel_gym.cli`); the agents' training and evaluation are the
``agents`` package, installed alongside (``vessel-gym train``, ``vessel-gym evaluate``).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from vessel_gym.envs.registration import register_envs as _register_envs

__version__ = "0.1.0"

#: public name -> the module that is its one home
_HOMES = {
    "Ship": "vessel_gym.physics.shipfile",
    "load_ship": "vessel_gym.physics.shipfile",
    "builtin_ships": "vessel_gym.physics.shipfile",
    "Simulation": "vessel_gym.physics.simulation",
    "Environment": "vessel_gym.physics.environment",
    "imo_report": "vessel_gym.manoeuvres.imo",
    "ImoReport": "vessel_gym.manoeuvres.imo",
    "turning_circle": "vessel_gym.manoeuvres.trials",
    "zigzag": "vessel_gym.manoeuvres.trials",
    "initial_turning": "vessel_gym.manoeuvres.trials",
    "stopping": "vessel_gym.manoeuvres.trials",
    "pull_out": "vessel_gym.manoeuvres.trials",
    "ManoeuvreIncomplete": "vessel_gym.manoeuvres.trials",
    "Scenario": "vessel_gym.scenarios.scenario",
    "load_scenario": "vessel_gym.scenarios.scenario",
    "builtin_scenarios": "vessel_gym.scenarios.scenario",
    "load_policy": "vessel_gym.policy",
    "UdpLink": "vessel_gym.net.link",
    "LinkConfig": "vessel_gym.net.link_config",
    "UdpLinkWrapper": "vessel_gym.net.wrapper",
    "serve": "vessel_gym.net.serve",
    "parallel_env": "vessel_gym.multiagent",
}

__all__ = [
    "__version__",
    "env_ids",
    "Ship",
    "load_ship",
    "builtin_ships",
    "Simulation",
    "Environment",
    "imo_report",
    "ImoReport",
    "turning_circle",
    "zigzag",
    "initial_turning",
    "stopping",
    "pull_out",
    "ManoeuvreIncomplete",
    "Scenario",
    "load_scenario",
    "builtin_scenarios",
    "load_policy",
    "UdpLink",
    "LinkConfig",
    "UdpLinkWrapper",
    "serve",
    "parallel_env",
]

if TYPE_CHECKING:  # what the lazy names are, for type checkers and editors
    from vessel_gym.manoeuvres.imo import ImoReport, imo_report
    from vessel_gym.manoeuvres.trials import (
        ManoeuvreIncomplete,
        initial_turning,
        pull_out,
        stopping,
        turning_circle,
        zigzag,
    )
    from vessel_gym.multiagent import parallel_env
    from vessel_gym.net.link import UdpLink
    from vessel_gym.net.link_config import LinkConfig
    from vessel_gym.net.serve import serve
    from vessel_gym.net.wrapper import UdpLinkWrapper
    from vessel_gym.physics.environment import Environment
    from vessel_gym.physics.shipfile import Ship, builtin_ships, load_ship
    from vessel_gym.physics.simulation import Simulation
    from vessel_gym.policy import load_policy
    from vessel_gym.scenarios.scenario import Scenario, builtin_scenarios, load_scenario


def env_ids() -> list[str]:
    """The registered vessel-gym environment ids (``vessel_gym/<Task>-v<N>``), sorted."""
    import gymnasium

    return sorted(i for i in gymnasium.registry if i.startswith("vessel_gym/"))


def __getattr__(name: str) -> Any:
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module 'vessel_gym' has no attribute {name!r}")
    value = getattr(importlib.import_module(home), name)
    globals()[name] = value  # the next access does not come here
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


_register_envs()
