"""Helm: action types that turn the agent's actions into rudder and shaft-speed orders for all N vessels."""

from __future__ import annotations

import abc
from typing import Any, Protocol

import numpy as np
from gymnasium import spaces
from numba import njit

from vessel_gym.envs.config import ShipEnvConfig
from vessel_gym.physics.schema import SpecError
from vessel_gym.physics.units import DEG


@njit(cache=True)
def continuous_orders(a_rudder, a_engine, limit, full_ahead, full_astern):
    """(rudder order rad, shaft-speed order rev/s) of one continuous action: each fraction clipped to [-1, 1],
    the rudder's times the rudder ``limit`` (rad), the engine's times the shaft speed at full ahead (>= 0) or
    full astern (< 0), rev/s."""
    a = min(max(a_rudder, -1.0), 1.0)
    e = min(max(a_engine, -1.0), 1.0)
    return a * limit, (e * full_ahead if e >= 0.0 else e * full_astern)


@njit(cache=True)
def clip_helm(actions, limit, full_ahead, full_astern, engine, rudder_order, rev_order):
    """Continuous helm: clip actions to [-1, 1] and scale to rudder (rad) and shaft-speed (rev/s) orders
    (:func:`continuous_orders` of each vessel).

    Returns False if any action is NaN (nothing is written then).
    """
    for k in range(actions.shape[0]):
        for j in range(actions.shape[1]):
            if actions[k, j] != actions[k, j]:
                return False
    for k in range(actions.shape[0]):
        rudder, rev = continuous_orders(
            actions[k, 0], actions[k, 1] if engine else 0.0, limit[k], full_ahead[k], full_astern[k]
        )
        rudder_order[k] = rudder
        if engine:
            rev_order[k] = rev
    return True


def real_values(action: Any, what: str) -> np.ndarray:
    """``action`` as float64 values, or a one-line ValueError: strings, complex numbers, booleans and
    objects are refused by name instead of reaching the compiled helm (where a str or complex action was a
    raw numba typing error) or being cast (complex -> real drops the imaginary part)."""
    try:
        raw = np.asarray(action)
    except (TypeError, ValueError) as exc:  # ragged nested lists
        raise ValueError(f"{what} must be real numbers: {exc}") from None
    if raw.dtype.kind not in "fiu":
        kind = {"U": "text", "S": "bytes", "c": "complex numbers", "b": "booleans", "O": "objects"}
        raise ValueError(
            f"{what} must be real numbers, got {kind.get(raw.dtype.kind, str(raw.dtype))}: {action!r}"
        )
    return raw.astype(np.float64, copy=False)


class Helmed(Protocol):
    """What a helm steers: a simulation, or a view of some of its vessels (CollisionAvoidance's own ships)."""

    n: int

    def ship(self, k: int = 0) -> Any: ...

    def telegraph_rev(self, telegraph: Any, k: int | None = None) -> Any: ...

    def set_helm(self, rudder_order_rad: Any = None, rev_order: Any = None, k: Any = None) -> None: ...


class Helm(abc.ABC):
    """Turns actions into rudder and shaft-speed orders for all N vessels (one ``set_helm`` call)."""

    space: spaces.Space
    engine: bool

    def __init__(self, config: ShipEnvConfig, sim: Helmed) -> None:
        self.sim = sim
        self.engine = config.engine_control
        n = sim.n
        self.rev_table = np.stack([sim.telegraph_rev(t) for t in range(-4, 5)], axis=1)  # (N, 9) rev/s
        self.telegraph = np.zeros(n, dtype=np.int64)  # last telegraph step (discrete helm), for the HUD

    @abc.abstractmethod
    def apply(self, actions: np.ndarray) -> None:
        """Set the orders of all N vessels from validated actions (N, ...)."""

    @abc.abstractmethod
    def batch(self, actions: Any, n: int) -> np.ndarray:
        """The actions of n vessels as an array, checked against the action space (ValueError)."""

    @abc.abstractmethod
    def single(self, action: Any) -> np.ndarray:
        """One vessel's action as a batch of one, checked (ValueError)."""

    def apply_single(self, action: Any) -> None:
        """Apply one action to vessel 0 of a one-vessel simulation."""
        self.apply(self.single(action))


class ContinuousHelm(Helm):
    """Box(-1, 1): a[0] rudder order as a fraction of the rudder limit (+ starboard); with engine control
    a[1] shaft-speed order as a fraction of full ahead (a > 0) or full astern (a < 0) telegraph rpm.
    Out-of-range values are clipped; NaN raises ValueError."""

    def __init__(self, config: ShipEnvConfig, sim: Helmed) -> None:
        super().__init__(config, sim)
        limit = config.rudder_limit_deg
        self.rudder_limit_rad = np.array(
            [
                (s.steering_gear.max_angle_deg if limit is None else limit) * DEG
                for s in (sim.ship(k) for k in range(sim.n))
            ]
        )
        self.dim = 2 if self.engine else 1
        self._shape = (self.dim,)
        self.space = spaces.Box(-1.0, 1.0, shape=(self.dim,), dtype=np.float32)
        self.full_ahead = self.rev_table[:, 8].copy()
        self.full_astern = -self.rev_table[:, 0]
        self._rudder = np.zeros(sim.n)
        self._rev = np.zeros(sim.n)
        self._lim0 = float(self.rudder_limit_rad[0])
        self._fa0 = float(self.full_ahead[0])
        self._fs0 = float(self.full_astern[0])

    def single(self, action: Any) -> np.ndarray:
        a = real_values(action, "action")
        if a.size != self.dim:
            raise ValueError(f"action must have {self.dim} values, got shape {a.shape}")
        return a.reshape(1, self.dim)

    def _fractions(self, action: Any) -> tuple[float, float]:
        """One vessel's action, checked: the rudder's and the engine's fractions (the rudder's twice without
        engine control)."""
        if type(action) is np.ndarray and action.shape == self._shape and action.dtype.kind in "fiu":
            a = action.tolist()
        else:
            a = self.single(action).tolist()[0]
        return a[0], a[-1]

    def apply_single(self, action: Any) -> None:
        # scalar path: the one-vessel environment's step should cost little beside the physics
        x, e = self._fractions(action)
        if x != x or e != e:
            raise ValueError(f"action contains NaN: {action!r}")
        rudder, rev = continuous_orders(x, e, self._lim0, self._fa0, self._fs0)
        self.sim.set_helm(
            rudder_order_rad=rudder, rev_order=rev if self.engine else None, k=0
        )  # k=0: scalars

    def batch(self, actions: Any, n: int) -> np.ndarray:
        a = real_values(actions, "actions")
        if a.shape != (n, self.dim):
            raise ValueError(f"actions must have shape ({n}, {self.dim}), got {a.shape}")
        return a

    def apply(self, actions: np.ndarray) -> None:
        if not clip_helm(
            actions,
            self.rudder_limit_rad,
            self.full_ahead,
            self.full_astern,
            self.engine,
            self._rudder,
            self._rev,
        ):
            raise ValueError(f"action contains NaN: {actions.tolist()!r}")
        self.sim.set_helm(rudder_order_rad=self._rudder, rev_order=self._rev if self.engine else None)


class DiscreteHelm(Helm):
    """Helm orders from ``rudder_orders_deg`` (Discrete) or helm order x telegraph step (MultiDiscrete).
    An index out of range raises ValueError (a discrete order cannot be clipped meaningfully)."""

    def __init__(self, config: ShipEnvConfig, sim: Helmed) -> None:
        super().__init__(config, sim)
        self.orders_rad = np.asarray(config.rudder_orders_deg, dtype=np.float64) * DEG
        self.steps = np.asarray(config.telegraph_steps, dtype=np.int64)
        if len(self.orders_rad) < 2 or (self.engine and len(self.steps) < 2):
            raise SpecError(
                "discrete helm: rudder_orders_deg and telegraph_steps need at least 2 entries each"
            )
        self.nvec = np.array(
            [len(self.orders_rad), len(self.steps)] if self.engine else [len(self.orders_rad)]
        )
        self.space = spaces.MultiDiscrete(self.nvec) if self.engine else spaces.Discrete(int(self.nvec[0]))
        self.dim = len(self.nvec)

    def _check(self, a: np.ndarray, raw: Any) -> np.ndarray:
        if a.dtype.kind == "f":
            if np.isnan(a).any():
                raise ValueError(f"action contains NaN: {raw!r}")
            if not np.all(a == np.round(a)):
                raise ValueError(f"discrete action must be integers, got {raw!r}")
        a = a.astype(np.int64)
        if np.any(a < 0) or np.any(a >= self.nvec):
            raise ValueError(f"discrete action {raw!r} out of range (sizes {self.nvec.tolist()})")
        return a

    def single(self, action: Any) -> np.ndarray:
        a = real_values(action, "action")
        if a.size != self.dim:
            raise ValueError(f"action must have {self.dim} values, got shape {a.shape}")
        return self._check(a.reshape(1, self.dim), action)

    def batch(self, actions: Any, n: int) -> np.ndarray:
        a = real_values(actions, "actions")
        a = a.reshape(n, -1) if a.size == n * self.dim else None
        if a is None:
            raise ValueError(f"actions must have {n} x {self.dim} entries, got shape {np.shape(actions)}")
        return self._check(a, "actions")

    def apply(self, actions: np.ndarray) -> None:
        rev = None
        if self.engine:
            step = self.steps[actions[:, 1]]
            self.telegraph[:] = step
            rev = self.rev_table[np.arange(self.sim.n), step + 4]
        self.sim.set_helm(rudder_order_rad=self.orders_rad[actions[:, 0]], rev_order=rev)


def make_helm(config: ShipEnvConfig, sim: Helmed) -> Helm:
    return ContinuousHelm(config, sim) if config.action_type == "continuous" else DiscreteHelm(config, sim)
