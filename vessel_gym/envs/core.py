"""What every vessel-gym environment shares: helm (action types), observation layout, the batched task,
the single environment and its native vector twin.

A :class:`Task` owns one :class:`~vessel_gym.physics.simulation.Simulation` of N vessels and asks it for
named quantities; the per-step task arithmetic runs in one compiled call for all N
(:mod:`vessel_gym.envs.kernels`). :class:`ShipEnv` is a task of N = 1; :class:`ShipVectorEnv` is the same
task of N = num_envs, so single and vector environments share every line of task code and vessel k of a
vector environment seeded with s follows exactly the trajectory of a single environment seeded with s + k.
"""

from __future__ import annotations

import abc
import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from vessel_gym.envs import kernels as kn
from vessel_gym.envs.config import ShipEnvConfig, make_config
from vessel_gym.physics.linear import stable_step
from vessel_gym.physics.schema import SpecError
from vessel_gym.physics.shipfile import Ship, load_ship
from vessel_gym.physics.simulation import Simulation, steps_for
from vessel_gym.physics.units import DEG

PHASE_SKIP = 0  # vessel untouched this call
PHASE_STEP = 1  # vessel advanced one control step: update task state, reward terms, outcome
PHASE_RESET = 2  # vessel just reset: features only


# --- observations ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Feature:
    """One observation entry: name, unit (physical type), scale (normalized = value / scale), meaning."""

    name: str
    unit: str
    scale: float
    doc: str
    column: int = 0  # column in the task's feature array


class ObservationLayout:
    """Names, units and scales of the observation vector; decodes observations into physical units."""

    def __init__(self, features: Sequence[Feature], normalized: bool) -> None:
        self.features = tuple(features)
        self.normalized = normalized
        self.names = tuple(f.name for f in self.features)
        self.scale = np.array([f.scale for f in self.features], dtype=np.float64)
        self.columns = np.array([f.column for f in self.features], dtype=np.int64)
        self._index = {n: i for i, n in enumerate(self.names)}
        if len(self._index) != len(self.names) or not np.all(self.scale > 0.0):
            raise ValueError("observation features need unique names and positive scales")

    def __len__(self) -> int:
        return len(self.features)

    def index(self, name: str) -> int:
        """Position of feature ``name`` in the observation vector."""
        try:
            return self._index[name]
        except KeyError:
            raise KeyError(f"no observation feature {name!r} (have: {', '.join(self.names)})") from None

    def value(self, obs: np.ndarray, name: str) -> np.ndarray:
        """Feature ``name`` of an observation (or a batch) in physical units."""
        i = self.index(name)
        x = np.asarray(obs, dtype=np.float64)[..., i]
        return x * self.scale[i] if self.normalized else x

    def space(self) -> spaces.Box:
        hi = np.ones(len(self)) if self.normalized else self.scale
        return spaces.Box(-hi.astype(np.float32), hi.astype(np.float32), dtype=np.float32)

    def table(self) -> str:
        """Markdown table of the layout (for documentation)."""
        rows = ["| # | name | unit | scale | meaning |", "|---|---|---|---|---|"]
        rows += [
            f"| {i} | `{f.name}` | {f.unit} | {f.scale:.4g} | {f.doc} |" for i, f in enumerate(self.features)
        ]
        return "\n".join(rows)


# --- helm (action types) ---------------------------------------------------------------------------------------
class Helm(abc.ABC):
    """Turns actions into rudder and shaft-speed orders for all N vessels (one ``set_helm`` call)."""

    space: spaces.Space
    engine: bool

    def __init__(self, config: ShipEnvConfig, sim: Simulation) -> None:
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

    def __init__(self, config: ShipEnvConfig, sim: Simulation) -> None:
        super().__init__(config, sim)
        limit = config.rudder_limit_deg
        self.rudder_limit_rad = np.array(
            [
                (s.steering_gear.max_angle_deg if limit is None else limit) * DEG
                for s in (sim.ship(k) for k in range(sim.n))
            ]
        )
        self.dim = 2 if self.engine else 1
        self.space = spaces.Box(-1.0, 1.0, shape=(self.dim,), dtype=np.float32)
        self.full_ahead = self.rev_table[:, 8].copy()
        self.full_astern = -self.rev_table[:, 0]
        self._rudder = np.zeros(sim.n)
        self._rev = np.zeros(sim.n)
        self._lim0 = float(self.rudder_limit_rad[0])
        self._fa0 = float(self.full_ahead[0])
        self._fs0 = float(self.full_astern[0])

    def single(self, action: Any) -> np.ndarray:
        a = np.asarray(action, dtype=np.float64)
        if a.size != self.dim:
            raise ValueError(f"action must have {self.dim} values, got shape {a.shape}")
        return a.reshape(1, self.dim)

    def apply_single(self, action: Any) -> None:
        # scalar fast path: the one-vessel environment's step should cost little beside the physics
        if type(action) is np.ndarray and action.shape == (self.dim,):
            a = action.tolist()
        else:
            a = self.single(action).tolist()[0]
        x = a[0]
        if x != x or a[-1] != a[-1]:
            raise ValueError(f"action contains NaN: {action!r}")
        x = -1.0 if x < -1.0 else (1.0 if x > 1.0 else x)
        rev = None
        if self.engine:
            e = a[1]
            e = -1.0 if e < -1.0 else (1.0 if e > 1.0 else e)
            rev = e * self._fa0 if e >= 0.0 else e * self._fs0
        self.sim.set_helm(
            rudder_order_rad=x * self._lim0, rev_order=rev, k=0
        )  # k=0: scalar stores, no slices

    def batch(self, actions: Any, n: int) -> np.ndarray:
        a = np.asarray(actions, dtype=np.float64)
        if a.shape != (n, self.dim):
            raise ValueError(f"actions must have shape ({n}, {self.dim}), got {a.shape}")
        return a

    def apply(self, actions: np.ndarray) -> None:
        if not kn.clip_helm(
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

    def __init__(self, config: ShipEnvConfig, sim: Simulation) -> None:
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
        a = np.asarray(action)
        if a.size != self.dim:
            raise ValueError(f"action must have {self.dim} values, got shape {a.shape}")
        return self._check(a.reshape(1, self.dim), action)

    def batch(self, actions: Any, n: int) -> np.ndarray:
        a = np.asarray(actions).reshape(n, -1) if np.asarray(actions).size == n * self.dim else None
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


def make_helm(config: ShipEnvConfig, sim: Simulation) -> Helm:
    return ContinuousHelm(config, sim) if config.action_type == "continuous" else DiscreteHelm(config, sim)


# --- task ------------------------------------------------------------------------------------------------------
# The default physics step keeps the ship's fastest mode at the steady run (on small models the shaft's, the
# steering gear being solved exactly) within 0.7 of the integrator's stability limit. Over the operating
# envelope (astern, low speed, hard over, shaft overspeed) that mode is up to 1.1x faster on kvlcc2_l7, so the
# step stays within 0.77 of the limit everywhere. Stability is not accuracy: the rudder's path within a step
# (slewing, then settling) is forcing the step must also resolve, so the ship travels at most 5 % of its length
# per step at its test speed (the Mariner, stable to 22 s steps, converges at 0.06 L and is off by 0.07 deg at
# 0.12 L). docs/envs.md, "Physics step", has the envelope and the convergence studies.
STEP_MARGIN = 0.7
STEP_TRAVEL_L = 0.05  # ship lengths travelled per default step, at most


def physics_step(config: ShipEnvConfig, ship: Ship) -> float:
    """``config.dt_s``, or the default: the longest control_interval_s / k within STEP_MARGIN x the stable step
    and STEP_TRAVEL_L ship lengths of travel at the test speed.

    An explicit ``dt_s`` beyond the stable step raises SpecError (the integration would diverge).
    """
    limit = stable_step(ship, config.method)
    if config.dt_s is None:
        longest = min(STEP_MARGIN * limit, STEP_TRAVEL_L * ship.particulars.L_m / ship.test_speed_m_s)
        return config.control_interval_s / math.ceil(config.control_interval_s / longest - 1e-9)
    if config.dt_s > limit:
        raise SpecError(
            f"dt_s = {config.dt_s:g} s is beyond the stable {config.method} step of ship {ship.name!r}, "
            f"{limit:.3g} s (set by its fastest mode); use a shorter dt_s or leave it unset"
        )
    return float(config.dt_s)


class Task(abc.ABC):
    """A task over one simulation of N vessels: start states, observations, reward terms, episode end.

    Subclasses define ``Config`` (a :class:`ShipEnvConfig` subclass with a ``reward`` weights table), their
    compiled ``kernel`` and its ``kernel_args()``, ``observation_features()``, ``reset_vessel()`` and ``info()``.
    """

    Config: ClassVar[type[ShipEnvConfig]] = ShipEnvConfig
    n_features: ClassVar[int] = 0
    kernel: ClassVar[Any]  # compiled update, batched over vessels: kernel(phase, *kernel_args())

    def __init__(
        self,
        config: Any,
        n: int,
        ship: str | Ship | None = None,
        reference_latlon_deg: tuple[float, float] = (0.0, 0.0),
    ) -> None:
        self.config = config
        self.n = n
        ship = load_ship(ship if ship is not None else config.ship)
        self.dt = physics_step(config, ship)
        try:
            self.nsub = steps_for(config.control_interval_s, self.dt)
        except ValueError:
            raise SpecError(
                f"control_interval_s = {config.control_interval_s:g} s is not a whole multiple of "
                f"dt_s = {self.dt:g} s"
            ) from None
        self.sim = Simulation(
            ship,
            n=n,
            dt=self.dt,
            method=config.method,
            reference_latlon_deg=reference_latlon_deg,
        )
        self.ship: Ship = self.sim.ship(0)
        self.helm = make_helm(config, self.sim)
        self.U_T = self.ship.test_speed_m_s
        self.L = self.ship.particulars.L_m
        self.delta_max = float(self.ship.steering_gear.max_angle_deg * DEG)
        self.rev_full = float(np.max(np.abs(self.helm.rev_table[0]))) or 1.0
        self.layout = ObservationLayout(self.observation_features(), config.observation_type == "normalized")
        self.term_names = tuple(f.name for f in dataclasses.fields(config.reward))
        self.weights = np.array([getattr(config.reward, t) for t in self.term_names], dtype=np.float64)
        self.feat = np.zeros((n, self.n_features))
        self.terms = np.zeros((n, len(self.term_names)))  # weighted reward terms (they sum to the reward)
        self.reward = np.zeros(n)
        self.terminated = np.zeros(n, dtype=np.bool_)
        self.phase = np.full(n, PHASE_STEP, dtype=np.int8)
        self.rngs: Sequence[np.random.Generator] = ()  # per-vessel generators, set by the environment
        self.enc = np.stack(
            [
                self.layout.columns.astype(np.float64),
                self.layout.scale,
                np.full(len(self.layout), 1.0 if self.layout.normalized else 0.0),
            ],
            axis=1,
        )
        self.obs = np.zeros((n, len(self.layout)), dtype=np.float32)
        self._kernel_args: tuple | None = None

    # subclass interface
    @abc.abstractmethod
    def observation_features(self) -> list[Feature]:
        """The observation entries, in order (see :meth:`motion_observation`)."""

    @abc.abstractmethod
    def reset_vessel(self, k: int, rng: np.random.Generator, options: Mapping | None) -> None:
        """Put vessel k at a new start drawn with ``rng`` (``options`` as the environment's reset)."""

    def motion_observation(self, rev: bool) -> list[Feature]:
        """The observation entries every task begins with (feature columns kn.F_U..F_REV): motion through the
        water and the helm; the shaft speed only if ``rev``."""
        U, L, d = self.U_T, self.L, self.delta_max
        f = [
            Feature("u", "m/s", 1.5 * U, "surge velocity through the water", kn.F_U),
            Feature("v", "m/s", 0.5 * U, "sway velocity through the water (+ starboard)", kn.F_V),
            Feature("r", "rad/s", 2.0 * U / L, "rate of turn (+ starboard)", kn.F_R),
            Feature("rudder", "rad", d, "actual rudder angle (+ starboard)", kn.F_DELTA),
            Feature("rudder_order", "rad", d, "rudder order", kn.F_DELTA_C),
        ]
        if rev:
            f.append(
                Feature("rev", "rev/s", 1.5 * self.rev_full, "propeller shaft speed (tachometer)", kn.F_REV)
            )
        return f

    @abc.abstractmethod
    def kernel_args(self) -> tuple:
        """The arguments of the task's compiled ``kernel`` after ``phase``: arrays that live as long as the task.

        Bound once, on the first update: a step then costs one call with no attribute look-ups.
        """

    def update(self, phase: np.ndarray) -> None:
        """Run the task kernel; fill ``feat``, ``terms`` and ``terminated`` for the vessels in ``phase``."""
        args = self._kernel_args
        if args is None:
            args = self._kernel_args = self.kernel_args()
        self.kernel(phase, *args)

    @abc.abstractmethod
    def info(self, k: int) -> dict[str, Any]:
        """Vessel k's ``info`` dict (Python scalars; the one-ship environment's step returns it)."""

    @abc.abstractmethod
    def batch_info(self) -> dict[str, Any]:
        """The ``info`` of all vessels, each entry an array over the vessels (the vector environment's)."""

    def renderer(self, mode: str) -> Any:
        """A chart renderer of this task's ship and chart (pygame is imported only here)."""
        from vessel_gym.ui.chart import ChartRenderer

        return ChartRenderer(
            mode,
            ship=self.ship,
            scenario=getattr(self, "scenario", None),
            fps=1.0 / self.config.control_interval_s,
        )

    def overlay(self, k: int) -> dict[str, Any]:
        """What the chart draws besides the ship (target heading, goal, ...)."""
        return {}

    # shared
    def advance(self) -> None:
        self.sim.step(self.nsub)

    def observe(self) -> np.ndarray:
        """A new array of the current observations (N, obs_dim)."""
        return self.obs.copy()

    def weighted_terms(self, k: int) -> dict[str, float]:
        return dict(zip(self.term_names, self.terms[k].tolist()))

    def batch_weighted_terms(self) -> dict[str, np.ndarray]:
        cols = self.terms.T.copy()  # one copy; its rows are the terms, contiguous
        return dict(zip(self.term_names, cols))

    def task_columns(self) -> np.ndarray:
        """A new (n_columns, N) copy of the task state: row j is column j of ``ts`` for all vessels (for the
        batched ``info``: one copy instead of one per entry)."""
        return self.ts.T.copy()


def _uniform(rng: np.random.Generator, rng_range: Sequence[float]) -> float:
    lo, hi = float(rng_range[0]), float(rng_range[1])
    return lo if hi <= lo else float(rng.uniform(lo, hi))


# --- single environment ----------------------------------------------------------------------------------------
class ShipEnv(gym.Env):
    """Base of the single environments (see each subclass's docstring for its spec sheet)."""

    metadata: ClassVar[dict[str, Any]] = {"render_modes": ["human", "rgb_array"], "render_fps": 4}
    Task: ClassVar[type[Task]]
    env_name: ClassVar[str] = "ShipEnv"

    def __init__(self, render_mode: str | None = None, config: Any = None, **overrides: Any) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(
                f"render_mode must be one of {self.metadata['render_modes']}, got {render_mode!r}"
            )
        self.render_mode = render_mode
        self.task = self.make_task(config, overrides, 1)
        self.config = self.task.config
        self.sim = self.task.sim
        self.observation_layout = self.task.layout
        self.action_space = self.task.helm.space
        self.observation_space = self.task.layout.space()
        self._renderer = None
        self._track: list[tuple[float, float]] = []
        self._traffic: Any = None  # the scenario's traffic, simulated only for frames (first render)
        self._step_phase = np.full(1, PHASE_STEP, dtype=np.int8)
        self._reset_phase = np.full(1, PHASE_RESET, dtype=np.int8)
        self._reset_done = False

    @classmethod
    def make_task(cls, config: Any, overrides: Mapping[str, Any], n: int) -> Task:
        cfg = make_config(cls.Task.Config, config, where=f"{cls.env_name} config", **overrides)
        return cls.Task(cfg, n)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self.task.rngs = (self.np_random,)
        self.task.reset_vessel(0, self.np_random, options)
        self.task.update(self._reset_phase)
        self._reset_done = True
        if self.render_mode is not None:
            self._track = [(float(self.sim.north[0]), float(self.sim.east[0]))]
            if self.render_mode == "human":
                self.render()
        return self.task.obs[0].copy(), self.task.info(0)

    def step(self, action: Any):
        if not self._reset_done:
            raise RuntimeError("call reset() before step()")
        task = self.task
        task.helm.apply_single(action)
        task.advance()
        task.update(self._step_phase)
        if self.render_mode is not None:
            self._track.append((float(self.sim.north[0]), float(self.sim.east[0])))
            if self.render_mode == "human":
                self.render()
        return task.obs[0].copy(), float(task.reward[0]), bool(task.terminated[0]), False, task.info(0)

    def render(self):
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode='rgb_array' or 'human'")
            return None
        if self._renderer is None:
            self._renderer = self.task.renderer(self.render_mode)
        return self._renderer.draw(
            self.sim,
            0,
            self._track,
            telegraph=self._telegraph(),
            overlay=self.task.overlay(0),
            targets=self._traffic_targets(),
        )

    def _traffic_targets(self) -> Any:
        """The scenario's ``[[traffic]]`` ships at this step, simulated only when a frame is drawn (the task, its
        observations and reward never see them)."""
        scenario = getattr(self.task, "scenario", None)
        if scenario is None or not scenario.traffic:
            return ()
        if self._traffic is None:
            from vessel_gym.scenarios.traffic import Traffic

            self._traffic = Traffic.from_scenario(scenario, self.task.dt, self.config.control_interval_s)
        steps = max(len(self._track) - 1, 0)  # one track point per step since the reset
        if steps < self._traffic.steps:  # a new episode
            self._traffic.reset()
        return self._traffic.lazy_targets(steps)

    def _telegraph(self) -> int | None:
        return (
            int(self.task.helm.telegraph[0])
            if self.config.action_type == "discrete" and self.config.engine_control
            else None
        )

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    def __getstate__(self) -> dict:
        state = self.__dict__.copy()
        state["_renderer"] = None
        return state


# --- native vector environment ---------------------------------------------------------------------------------
class ShipVectorEnv(VectorEnv):
    """Base of the native vector environments: N vessels in one simulation, stepped in one batched call.

    Autoreset modes: next-step (default, as Gymnasium's SyncVectorEnv), same-step (``info["final_obs"]``,
    ``info["final_info"]``) and disabled (reset with ``options={"reset_mask": mask}``). Vessel k seeded
    with ``seed + k`` reproduces a single environment reset with that seed.
    """

    metadata: ClassVar[dict[str, Any]] = {
        "render_modes": ["rgb_array"],
        "render_fps": 4,
        "autoreset_mode": AutoresetMode.NEXT_STEP,
    }
    Env: ClassVar[type[ShipEnv]]

    def __init__(
        self,
        num_envs: int = 1,
        max_episode_steps: int | None = None,
        render_mode: str | None = None,
        config: Any = None,
        autoreset_mode: str | AutoresetMode = AutoresetMode.NEXT_STEP,
        **overrides: Any,
    ) -> None:
        if num_envs < 1:
            raise ValueError(f"num_envs must be >= 1, got {num_envs}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(
                f"render_mode must be one of {self.metadata['render_modes']}, got {render_mode!r}"
            )
        self.autoreset_mode = AutoresetMode(autoreset_mode)
        self.metadata = {**type(self).metadata, "autoreset_mode": self.autoreset_mode}
        self.num_envs = num_envs
        self.max_episode_steps = max_episode_steps
        self.render_mode = render_mode
        self.task = self.Env.make_task(config, overrides, num_envs)
        self.config = self.task.config
        self.sim = self.task.sim
        self.observation_layout = self.task.layout
        self.single_action_space = self.task.helm.space
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.single_observation_space = self.task.layout.space()
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self._rngs: list[np.random.Generator] | None = None
        self._steps = np.zeros(num_envs, dtype=np.int64)
        self._needs_reset = np.zeros(num_envs, dtype=np.bool_)
        self._all_reset = np.full(num_envs, PHASE_RESET, dtype=np.int8)
        self._renderer = None
        self._tracks: list[list[tuple[float, float]]] = [[] for _ in range(min(num_envs, 4))]
        self._reset_done = False

    def _reset_vessels(self, idx: np.ndarray, options: dict | None) -> None:
        for k in idx:
            self.task.reset_vessel(int(k), self._rngs[k], options)
            self._steps[k] = 0
            if self.render_mode is not None and k < len(self._tracks):
                self._tracks[k] = [(float(self.sim.north[k]), float(self.sim.east[k]))]

    def reset(self, *, seed: int | Sequence[int | None] | None = None, options: dict | None = None):
        super().reset(seed=seed if isinstance(seed, int) else None)
        n = self.num_envs
        if seed is None:
            seeds: list = [None] * n
        elif isinstance(seed, int):
            seeds = [seed + i for i in range(n)]
        else:
            seeds = list(seed)
            if len(seeds) != n:
                raise ValueError(f"seed list must have {n} entries, got {len(seeds)}")
        if self._rngs is None:
            self._rngs = [seeding.np_random(s)[0] for s in seeds]
        else:
            for i, s in enumerate(seeds):
                if s is not None:
                    self._rngs[i] = seeding.np_random(s)[0]
        self.task.rngs = self._rngs
        opts = dict(options) if options else {}
        mask = opts.pop("reset_mask", None)
        if mask is not None:
            mask = np.asarray(mask)
            if mask.shape != (n,) or mask.dtype != np.bool_ or not mask.any():
                raise ValueError(f"options['reset_mask'] must be a boolean array of shape ({n},) with a True")
            phase = np.where(mask, PHASE_RESET, 0).astype(np.int8)
        else:
            mask = np.ones(n, dtype=np.bool_)
            phase = self._all_reset
        self._reset_vessels(np.flatnonzero(mask), opts or None)
        self._needs_reset[mask] = False
        self.task.update(phase)
        self._reset_done = True
        return self.task.observe(), self.task.batch_info()

    def step(self, actions: Any):
        if not self._reset_done:
            raise RuntimeError("call reset() before step()")
        task = self.task
        n = self.num_envs
        a = task.helm.batch(actions, n)
        done_prev = self._needs_reset
        if self.autoreset_mode == AutoresetMode.DISABLED and done_prev.any():
            raise RuntimeError("autoreset disabled: reset the finished sub-environments (options reset_mask)")
        task.helm.apply(a)
        task.advance()
        if done_prev.any():
            self._reset_vessels(np.flatnonzero(done_prev), None)
            phase = np.where(done_prev, PHASE_RESET, PHASE_STEP).astype(np.int8)
        else:
            phase = task.phase
        task.update(phase)
        stepped = ~done_prev
        self._steps[stepped] += 1
        terminated = task.terminated & stepped
        truncated = (
            stepped & ~terminated & (self._steps >= self.max_episode_steps)
            if self.max_episode_steps
            else np.zeros(n, dtype=np.bool_)
        )
        rewards = task.reward.copy()
        obs = task.observe()
        info = task.batch_info()
        done = terminated | truncated
        if self.render_mode is not None:
            for k in range(len(self._tracks)):
                if stepped[k]:
                    self._tracks[k].append((float(self.sim.north[k]), float(self.sim.east[k])))
        if self.autoreset_mode == AutoresetMode.SAME_STEP and done.any():
            idx = np.flatnonzero(done)
            final_obs = np.full(n, None, dtype=object)
            final_info = np.full(n, None, dtype=object)
            for k in idx:
                final_obs[k] = obs[k].copy()
                final_info[k] = {
                    key: (val[k] if isinstance(val, np.ndarray) else {t: v[k] for t, v in val.items()})
                    for key, val in info.items()
                    if not key.startswith("_")
                }
            self._reset_vessels(idx, None)
            phase2 = np.where(done, PHASE_RESET, 0).astype(np.int8)
            task.update(phase2)
            obs[idx] = task.observe()[idx]
            info["final_obs"] = final_obs
            info["_final_obs"] = done.copy()
            info["final_info"] = final_info
            info["_final_info"] = done.copy()
            self._needs_reset = np.zeros(n, dtype=np.bool_)
        else:
            self._needs_reset = done
        return obs, rewards, terminated, truncated, info

    def render(self):
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode='rgb_array'")
            return None
        if self._renderer is None:
            self._renderer = self.task.renderer("rgb_array")
        return tuple(
            self._renderer.draw(self.sim, k, self._tracks[k], telegraph=None, overlay=self.task.overlay(k))
            for k in range(len(self._tracks))
        )

    def close_extras(self, **kwargs: Any) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    def __getstate__(self) -> dict:
        state = self.__dict__.copy()
        state["_renderer"] = None
        return state
