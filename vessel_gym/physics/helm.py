"""The helm of a simulation: the orders each vessel runs on (rudder, shaft speed), the telegraph's table, and
the override that gives one vessel's helm to a helmsman outside the simulation's owner (a panel on the network).

A mixin of :class:`~vessel_gym.physics.simulation.Simulation`: it reads and writes the simulation's input rows
``inputs`` (N, NU), of ``n`` vessels of ``ships`` indexed by ``ship_index``.
"""

from __future__ import annotations

import math

import numpy as np

from vessel_gym.physics import layout as lo


class Helm:
    """Orders and helm override of a batch of vessels (see the module docstring)."""

    n: int
    inputs: np.ndarray
    ships: list
    ship_index: np.ndarray

    # Orders of vessels whose helm is overridden (override_helm), by vessel: (rudder rad, shaft rev/s), None for
    # an order not overridden. None while no helm is overridden, so that set_helm then pays one test.
    _helm_override: dict[int, tuple[float | None, float | None]] | None = None

    def set_helm(
        self,
        rudder_order_rad: float | np.ndarray | None = None,
        rev_order: float | np.ndarray | None = None,
        k: int | slice | None = None,
    ) -> None:
        """Rudder order (rad, positive starboard) and propeller shaft-speed order (rev/s, negative astern).

        An order of a vessel whose helm is overridden (:meth:`override_helm`) stays as the override set it.
        """
        sl = slice(None) if k is None else k
        if rudder_order_rad is not None:
            self.inputs[sl, lo.U_DELTA_C] = rudder_order_rad
        if rev_order is not None:
            self.inputs[sl, lo.U_REV_C] = rev_order
        if self._helm_override is not None:
            self._hold_override()

    def override_helm(
        self, k: int = 0, rudder_order_rad: float | None = None, rev_order: float | None = None
    ) -> None:
        """Give vessel k's helm to a helmsman outside the simulation's owner (a helm panel on the network).

        The orders given, rudder (rad, positive starboard) and shaft speed (rev/s, negative astern), apply at
        once and win over :meth:`set_helm` (an agent's or an autopilot's orders) until the next call for vessel
        k; an order left None is not overridden. A call with neither order hands the helm back: the orders in
        force stay until set_helm changes them, as on a ship when the helmsman lets go of the wheel.
        """
        if not 0 <= k < self.n:
            raise ValueError(f"override_helm: vessel {k} is not in [0, {self.n - 1}]")
        for name, value in (("rudder_order_rad", rudder_order_rad), ("rev_order", rev_order)):
            if value is not None and not math.isfinite(value):
                raise ValueError(f"override_helm: {name} must be a finite number, got {value!r}")
        held = dict(self._helm_override or {})
        if rudder_order_rad is None and rev_order is None:
            held.pop(k, None)
        else:
            held[k] = (
                None if rudder_order_rad is None else float(rudder_order_rad),
                None if rev_order is None else float(rev_order),
            )
        self._helm_override = held or None
        self._hold_override()

    def _hold_override(self) -> None:
        for j, (rudder, rev) in (self._helm_override or {}).items():
            if rudder is not None:
                self.inputs[j, lo.U_DELTA_C] = rudder
            if rev is not None:
                self.inputs[j, lo.U_REV_C] = rev

    def telegraph_rev(self, telegraph: int | np.ndarray, k: int | None = None) -> np.ndarray:
        """Propeller rev/s for a telegraph step (-4..4) from each ship's ``telegraph_rpm`` table."""
        table = np.zeros((len(self.ships), 9))  # rev/s by ship and step; 0 for a ship without an engine
        for i, s in enumerate(self.ships):
            if s.engine is not None:
                table[i] = np.asarray(s.engine.telegraph_rpm, dtype=float) / 60.0
        tg = np.clip(np.asarray(telegraph, dtype=np.int64), -4, 4) + 4
        if k is not None:
            return table[self.ship_index[k], np.broadcast_to(tg, (self.n,))[k]]
        return table[self.ship_index, np.broadcast_to(tg, (self.n,))]
