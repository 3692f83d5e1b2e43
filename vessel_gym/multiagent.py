"""Many ships learning together: a task's own ships as the agents of a PettingZoo ``ParallelEnv``.

``vessel_gym.parallel_env(TASK_ID, agents=N, **config)`` makes one task of N own ships (the same task code as
the Gymnasium environments: its declaration, reset, step and ``info``) and gives every own ship its own
observation, reward, termination, truncation and ``info``: never one aggregated reward. For a task whose
configuration has an ``agents`` key (CollisionAvoidance) the N own ships share one encounter (they see each
other as targets; the encounter's remaining targets stay scripted, keeping course and speed); for any other
task they are N independent ships of one batch.

An agent whose episode ends (arrival, collision, straying) leaves ``agents`` and its ship leaves the encounter;
all are truncated after ``max_cycles`` steps (default: the task's ``max_episode_steps``). ``state()`` is the
observation of every possible agent in turn (zeros for one that has left), ``state_space`` its box.
``reset(seed=s)`` seeds own ship k with ``s + k`` as the vector environments do; a reset without a seed
continues the ships' streams. ``options``: the task's reset
options (CollisionAvoidance: ``scenario``, ``heading_deg``); other keys are left to wrappers and not read.

Needs the ``marl`` extra (pettingzoo).
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Mapping
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

try:
    from pettingzoo import ParallelEnv
except ImportError as exc:  # pragma: no cover - the extra is installed in CI
    raise ImportError(
        "vessel_gym.parallel_env needs the 'marl' extra (pettingzoo): pip install 'vessel-gym[marl]'"
    ) from exc

from vessel_gym.envs.generators import SeedRange, VesselGenerators
from vessel_gym.envs.registration import declaration, task_class
from vessel_gym.envs.task import PHASE_RESET, PHASE_STEP, reset_vessels, vessel_info


class ShipParallelEnv(ParallelEnv):
    """N own ships of one task as the agents ``ship_0`` ... ``ship_<N-1>`` (module doc)."""

    metadata = {"name": "vessel_gym_parallel_v0", "render_modes": [], "is_parallelizable": True}

    def __init__(self, task_id: str, agents: int = 2, config: Any = None, **overrides: Any) -> None:
        if agents < 1:
            raise ValueError(f"agents must be >= 1, got {agents}")
        decl = declaration(task_id)
        cls = task_class(task_id)
        preset = task_id.split("/", 1)[-1]
        over = dict(overrides, preset=preset)
        if "agents" in {f.name for f in dataclasses.fields(cls.Config)}:
            over["agents"] = agents
        self.task = cls.from_config(config, over, agents)
        self.task_id = decl.ids[list(decl.presets).index(preset)]
        self.n = agents
        self.possible_agents = [f"ship_{k}" for k in range(agents)]
        self.agents: list[str] = []
        self.max_cycles = decl.max_episode_steps or 0
        self.render_mode = None
        self._index = {a: k for k, a in enumerate(self.possible_agents)}
        self._observation_space = self.task.layout.space()
        self._action_space = self.task.helm.space
        low = np.tile(self._observation_space.low, agents)
        high = np.tile(self._observation_space.high, agents)
        self.state_space = spaces.Box(low, high, dtype=self._observation_space.dtype)
        self._live = np.zeros(agents, dtype=np.bool_)
        self._steps = 0
        self._rngs: VesselGenerators | None = None

    @functools.cache  # noqa: B019 (one space per agent for the env's life, as the API asks)
    def observation_space(self, agent: str) -> spaces.Space:
        self._index[agent]  # an unknown agent raises KeyError
        return self._observation_space

    @functools.cache  # noqa: B019
    def action_space(self, agent: str) -> spaces.Space:
        self._index[agent]
        return self._action_space

    def reset(self, seed: int | None = None, options: Mapping | None = None):
        if self._rngs is None:
            self._rngs = VesselGenerators(SeedRange(seed, self.n) if seed is not None else [None] * self.n)
        elif seed is not None:  # without a seed the ships' streams go on, as a Gymnasium environment's does
            self._rngs.reseed(SeedRange(seed, self.n))
        task = self.task
        task.rngs = self._rngs
        known = getattr(task, "reset_options", ())
        opts = {k: v for k, v in (options or {}).items() if k in known} or None
        reset_vessels(task, np.arange(self.n), opts)
        task.update(np.full(self.n, PHASE_RESET, dtype=np.int8))
        self.agents = list(self.possible_agents)
        self._live[:] = True
        self._steps = 0
        obs = task.obs.copy()
        return {a: obs[k] for k, a in enumerate(self.possible_agents)}, {
            a: vessel_info(task, k) for k, a in enumerate(self.possible_agents)
        }

    def step(self, actions: Mapping[str, Any]):
        task = self.task
        helm = task.helm
        batch = np.zeros((self.n, *np.shape(self._action_space.sample())), dtype=np.float64)
        for a, act in actions.items():
            k = self._index[a]
            if self._live[k]:
                batch[k] = helm.single(act)[0]
        helm.apply(helm.batch(batch, self.n))
        task.sim.step(task.nsub)  # every vessel one control step
        phase = np.where(self._live, PHASE_STEP, 0).astype(np.int8)
        task.update(phase)
        self._steps += 1
        obs_all = task.obs.copy()
        live = [a for a in self.agents]
        obs, rewards, terms, truncs, infos = {}, {}, {}, {}, {}
        timeout = 0 < self.max_cycles <= self._steps
        for a in live:
            k = self._index[a]
            obs[a] = obs_all[k]
            rewards[a] = float(task.reward[k])
            terms[a] = bool(task.terminated[k])
            truncs[a] = timeout and not terms[a]
            infos[a] = vessel_info(task, k)
            if terms[a] or truncs[a]:
                self._live[k] = False
        self.agents = [a for a in live if self._live[self._index[a]]]
        return obs, rewards, terms, truncs, infos

    def state(self) -> np.ndarray:
        obs = self.task.obs.copy()
        obs[~self._live] = 0.0
        return obs.reshape(-1)

    def close(self) -> None:
        pass


class SharedPolicyVectorEnv(gym.vector.VectorEnv):
    """The agents of a :class:`ShipParallelEnv` as the sub-environments of one Gymnasium ``VectorEnv``, so that
    one policy learns from every ship's experience (parameter sharing). Same-step autoreset, as
    :class:`vessel_gym.sb3.VectorEnvAdapter` takes it::

        from stable_baselines3 import PPO
        from vessel_gym.sb3 import VectorEnvAdapter

        penv = vessel_gym.parallel_env("vessel_gym/CollisionAvoidance-v0", agents=3)
        PPO("MlpPolicy", VectorEnvAdapter(SharedPolicyVectorEnv(penv))).learn(1_000_000)

    A ship whose episode ends reports it (``final_obs``, ``final_info``) and then, until every ship's episode
    has ended and a new encounter starts for all, observes zeros with reward 0 ("black death", as
    PettingZoo's SuperSuit does): those steps are in the training data. ``reset(seed=s)`` (an int or the
    list of per-ship seeds of which the first counts) seeds ship k with s + k; later encounters continue the
    ships' streams."""

    def __init__(self, penv: ShipParallelEnv) -> None:
        self.penv = penv
        self.num_envs = penv.n
        first = penv.possible_agents[0]
        self.single_observation_space = penv.observation_space(first)
        self.single_action_space = penv.action_space(first)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.metadata = {"autoreset_mode": AutoresetMode.SAME_STEP}
        self.render_mode = None

    def _stack(self, obs: Mapping[str, np.ndarray]) -> np.ndarray:
        out = np.zeros((self.num_envs, *self.single_observation_space.shape), dtype=np.float32)
        for a, o in obs.items():
            out[self.penv._index[a]] = o
        return out

    def reset(self, *, seed: Any = None, options: dict | None = None):
        if isinstance(seed, (list, tuple)):
            seed = seed[0]
        obs, _infos = self.penv.reset(seed=seed, options=options)
        return self._stack(obs), {}

    def step(self, actions: Any):
        penv = self.penv
        acts = {a: actions[penv._index[a]] for a in penv.agents}
        obs, rew, term, trunc, infos = penv.step(acts)
        n = self.num_envs
        o = self._stack(obs)
        r = np.zeros(n)
        te = np.zeros(n, dtype=np.bool_)
        tr = np.zeros(n, dtype=np.bool_)
        final_info = np.full(n, None, dtype=object)
        for a in obs:
            k = penv._index[a]
            r[k], te[k], tr[k], final_info[k] = rew[a], term[a], trunc[a], infos[a]
        done = te | tr
        info: dict[str, Any] = {}
        if done.any():
            final_obs = np.full(n, None, dtype=object)
            for k in np.flatnonzero(done):
                final_obs[k] = o[k].copy()
                o[k] = 0.0  # a ship that has left observes zeros until the next encounter
            info = {"final_obs": final_obs, "_final_obs": done, "final_info": final_info, "_final_info": done}
        if not penv.agents:  # every ship's episode has ended: a new encounter for all
            new, _ = penv.reset()
            o = self._stack(new)
        return o, r, te, tr, info


def parallel_env(task_id: str, agents: int = 2, config: Any = None, **overrides: Any) -> ShipParallelEnv:
    """A PettingZoo ``ParallelEnv`` of ``agents`` own ships of the registered task ``task_id`` (module doc);
    ``config`` and ``overrides`` as for ``gymnasium.make``."""
    return ShipParallelEnv(task_id, agents, config, **overrides)
