"""A simulation's Python components evaluated on its whole batch of vessels, with the states they own.

Each component acts on every vessel of the simulation, or (one named in a ship file) on the vessels of its ship
only: its outputs are zero elsewhere and its states hold still there. The components' own states are columns
of one array ``Z`` (N, NZ), a component's columns in the order of its ``states``; the integrator
(:func:`vessel_gym.physics.integrate.run_with_components`) integrates them with the vessel's state. Every call
takes the whole batch, so a component written with numpy array operations costs O(N).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import name_of, slot_of, states_of


class ComponentBatch:
    """The Python components of a simulation of ``n`` vessels (:meth:`add` each with its vessel mask)."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.components: list[Any] = []
        self.masks: list[np.ndarray | None] = []  # None: every vessel
        self.columns: list[slice] = []  # each component's columns of Z
        self.state_names: list[str] = []  # "Component.state" for every column of Z
        self.state_units: list[str] = []

    def add(self, component: Any, mask: np.ndarray | None = None) -> None:
        """Take ``component`` on the vessels of ``mask`` (None: all)."""
        states = states_of(component)
        start = len(self.state_names)
        self.components.append(component)
        self.masks.append(mask)
        self.columns.append(slice(start, start + len(states)))
        self.state_names += [f"{name_of(component)}.{st.name}" for st in states]
        self.state_units += [st.unit for st in states]

    @property
    def nz(self) -> int:
        """Number of states the components own (columns of Z)."""
        return len(self.state_names)

    def initial_states(self) -> np.ndarray:
        """Z (N, NZ) with every state at its declared initial value."""
        row = [st.initial for c in self.components for st in states_of(c)]
        return np.tile(np.asarray(row, dtype=float), (self.n, 1))

    def _masked(self, j: int, value: np.ndarray) -> np.ndarray:
        mask = self.masks[j]
        if mask is None:
            return value
        return np.where(mask.reshape((-1,) + (1,) * (value.ndim - 1)), value, 0.0)

    def _call(self, j: int, method: str, sim: Any, x: np.ndarray, z: np.ndarray, shape: tuple) -> np.ndarray:
        """A component's ``method`` on the batch, as floats of ``shape``, zero on vessels not its own."""
        c, cols = self.components[j], self.columns[j]
        fn = getattr(c, method)
        out = fn(sim, x, z[:, cols]) if (cols.stop > cols.start or method != "forces") else fn(sim, x)
        return self._masked(j, np.asarray(out, dtype=float).reshape(shape))

    def forces_each(self, sim: Any, x: np.ndarray, z: np.ndarray) -> list[tuple[str, np.ndarray]]:
        """(name, forces (N, 3)) of each component at the states ``x`` and own states ``z``."""
        return [(name_of(c), self._call(j, "forces", sim, x, z, (self.n, 3))) for j, c in enumerate(self.components)]

    def forces(self, sim: Any, x: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Sum of the components' forces (N, 3)."""
        F = np.zeros((self.n, 3))
        for _, f in self.forces_each(sim, x, z):
            F += f
        return F

    def shaft_torque(self, sim: Any, x: np.ndarray, z: np.ndarray) -> np.ndarray:
        """(N,) drive torque of the user engines at the propeller shaft, N m (0 where the engine is built in)."""
        Q = np.zeros(self.n)
        for j, c in enumerate(self.components):
            if slot_of(c) == "engine":
                Q += self._call(j, "shaft_torque", sim, x, z, (self.n,))
        return Q

    def evaluate(self, sim: Any, x: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """What the components give the kernel at one integration stage, (N, NF) (layout F_*), and the rates
        of their own states (N, NZ)."""
        F = np.zeros((self.n, lo.NF))
        zdot = np.zeros((self.n, self.nz))
        for j, c in enumerate(self.components):
            slot, cols = slot_of(c), self.columns[j]
            F[:, : lo.F_N + 1] += self._call(j, "forces", sim, x, z, (self.n, 3))
            if slot == "engine":
                F[:, lo.F_Q_SHAFT] += self._call(j, "shaft_torque", sim, x, z, (self.n,))
            elif slot == "steering_gear":
                F[:, lo.F_DELTA_RATE] += self._call(j, "rudder_rate", sim, x, z, (self.n,))
            if cols.stop > cols.start:
                zdot[:, cols] = self._call(j, "rates", sim, x, z, (self.n, cols.stop - cols.start))
        return F, zdot

    def steady_states(self, sim: Any, x: np.ndarray, Q_hold: np.ndarray, z: np.ndarray, idx: list[int]) -> None:
        """Set the own states of the vessels ``idx`` for a steady run at the states ``x`` (N, NX): an engine's
        from its ``steady_states`` with the drive torques ``Q_hold`` (N,) N m, every other state at its
        initial value."""
        z[idx] = self.initial_states()[idx]
        for j, c in enumerate(self.components):
            cols = self.columns[j]
            if cols.stop == cols.start or not callable(getattr(c, "steady_states", None)):
                continue
            steady = np.asarray(c.steady_states(sim, x, Q_hold), dtype=float).reshape(self.n, -1)
            mask = self.masks[j]
            own = idx if mask is None else [k for k in idx if mask[k]]
            z[own, cols] = steady[own]
