"""Many ships learning together: a task's own ships as the agents of a PettingZoo ``ParallelEnv``.

``vessel_gym.parallel_env(TASK_ID, agents=N, **config)`` makes one task of N own ships (the same task code as
the Gymnasium environments: its declaration, reset, step and ``info``) and gives every own ship its own
observation, reward, termination, truncation and ``info``: never one aggregated reward. For a task whose
configuration has an ``agents`` key (CollisionAvoidance) the N own ships share one encounter (they see each
other as targets; the encounter's remaining targets stay scripted, keeping course and speed); for any other
task they are N independent ships of one batch.

**A mix of ships.** ``driven={"ship_2": policy, ...}`` makes those own ships steered by a fixed policy
(``action = policy(observation)``, with ``reset()``, as :func:`vessel_gym.policy.load_policy` returns) from
their own observation, every control step: they take part as own ships (routes, COLREG records, leaving the
encounter when their episode ends) but are not agents of the environment (not in ``possible_agents``). The
encounter's remaining targets are scripted by the task's config: course and speed kept, or with
``targets_react=True`` the rules kept (a give-way target turns to starboard); with ``targets_observed="ais"``
every agent sees the others, agents and scripted ships alike, only as received over AIS. So one batch can hold
learning agents, policy-driven ships, rule-following scripted targets and AIS contacts, on the same task code.
:class:`OwnShipAmongAgents` is own ship 0 of such an environment as a Gymnasium environment, every other ship
driven by one policy (``vessel-gym serve --target-agent``).

An agent whose episode ends (arrival, collision, straying) leaves ``agents`` and its ship leaves the encounter;
all are truncated after ``max_cycles`` steps (default: the task's ``max_episode_steps``). ``state()`` is the
observation of every own ship in turn, agents and driven ships (zeros for one that has left), ``state_space``
its box.
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

from vessel_gym.envs.env import advance
from vessel_gym.envs.generators import SeedRange, VesselGenerators
from vessel_gym.envs.registration import declaration, task_class
from vessel_gym.envs.task import PHASE_RESET, PHASE_STEP, reset_vessels, task_config, vessel_info


class ShipParallelEnv(ParallelEnv):
    """N own ships of one task as the agents ``ship_0`` ... ``ship_<N-1>`` (module doc)."""

    metadata = {"name": "vessel_gym_parallel_v0", "render_modes": [], "is_parallelizable": True}

    def __init__(
        self,
        task_id: str,
        agents: int = 2,
        config: Any = None,
        driven: Mapping[str, Any] | None = None,
        **overrides: Any,
    ) -> None:
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
        self.agents: list[str] = []
        self.max_cycles = decl.max_episode_steps or 0
        self.render_mode = None
        self._index = {f"ship_{k}": k for k in range(agents)}
        self.drive(driven or {})
        self._pacing: tuple[int, Any] = (1, None)
        self._observation_space = self.task.layout.space()
        self._action_space = self.task.helm.space
        low = np.tile(self._observation_space.low, agents)
        high = np.tile(self._observation_space.high, agents)
        self.state_space = spaces.Box(low, high, dtype=self._observation_space.dtype)
        self._live = np.zeros(agents, dtype=np.bool_)
        self._steps = 0
        self._rngs: VesselGenerators | None = None

    def drive(self, driven: Mapping[str, Any]) -> None:
        """Steer the own ships named in ``driven`` by their policies (module doc); the others are the agents."""
        names = list(self._index)
        unknown = sorted(set(driven) - set(names))
        if unknown:
            raise ValueError(f"driven: no own ship {', '.join(unknown)} (have {', '.join(names)})")
        if len(driven) == len(names):
            raise ValueError("driven: every own ship is driven; at least one must be an agent")
        self.driven = {self._index[a]: policy for a, policy in driven.items()}  # own ship k: its policy
        self.possible_agents = [a for a in names if a not in driven]

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
        for policy in self.driven.values():
            policy.reset()
        obs = task.obs.copy()
        return {a: obs[self._index[a]] for a in self.agents}, {
            a: vessel_info(task, self._index[a]) for a in self.agents
        }

    def pace(self, ticks: int = 1, on_tick: Any = None) -> None:
        """Run each step's physics in ``ticks`` slices, ``on_tick(i)`` after slice i (as
        :meth:`ShipEnv.pace <vessel_gym.envs.env.ShipEnv.pace>`: ``vessel-gym serve`` paces a step this way)."""
        if ticks < 1:
            raise ValueError(f"ticks must be >= 1, got {ticks}")
        self._pacing = (int(ticks), on_tick)

    def step(self, actions: Mapping[str, Any]):
        task = self.task
        helm = task.helm
        batch = np.zeros((self.n, *np.shape(self._action_space.sample())), dtype=np.float64)
        for a, act in actions.items():
            k = self._index[a]
            if self._live[k] and a in self.possible_agents:
                batch[k] = helm.single(act)[0]
        for k, policy in self.driven.items():  # the driven ships act on their own observation
            if self._live[k]:
                batch[k] = helm.single(policy(task.obs[k].copy()))[0]
        helm.apply(helm.batch(batch, self.n))
        advance(task.sim, task.nsub, *self._pacing)  # every vessel one control step
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
        for k in self.driven:  # a driven ship leaves as an agent does
            if self._live[k] and (task.terminated[k] or timeout):
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
        self.num_envs = len(penv.possible_agents)  # the agents (ships driven by a fixed policy are not)
        self._pos = {a: i for i, a in enumerate(penv.possible_agents)}
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
            out[self._pos[a]] = o
        return out

    def reset(self, *, seed: Any = None, options: dict | None = None):
        if isinstance(seed, (list, tuple)):
            seed = seed[0]
        obs, _infos = self.penv.reset(seed=seed, options=options)
        return self._stack(obs), {}

    def step(self, actions: Any):
        penv = self.penv
        acts = {a: actions[self._pos[a]] for a in penv.agents}
        obs, rew, term, trunc, infos = penv.step(acts)
        n = self.num_envs
        o = self._stack(obs)
        r = np.zeros(n)
        te = np.zeros(n, dtype=np.bool_)
        tr = np.zeros(n, dtype=np.bool_)
        final_info = np.full(n, None, dtype=object)
        for a in obs:
            k = self._pos[a]
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


class OwnShipAmongAgents(gym.Env):
    """Own ship 0 of a task's encounter as a Gymnasium environment, every other ship of the encounter an own
    ship steered by a policy from its own observation: ``make_policy(env)`` is called once per driven ship
    (this environment given, whose spaces are one own ship's) and returns ``action = policy(obs)`` with
    ``reset()``. The encounter has ``1 + max_targets`` own ships (the task's config), so it draws only
    encounters of exactly ``max_targets`` targets. The task must put several own ships in one encounter (a
    config key ``agents``: CollisionAvoidance). ``max_episode_steps``: the time limit in control steps
    (default: the registered one). What ``vessel-gym serve --target-agent`` runs: a person (or the served
    agent) helms own ship 0 against the agents."""

    metadata = {"render_modes": []}

    def __init__(
        self,
        task_id: str,
        make_policy: Any,
        config: Any = None,
        max_episode_steps: int | None = None,
        **overrides: Any,
    ) -> None:
        cls = task_class(task_id)
        if "agents" not in {f.name for f in dataclasses.fields(cls.Config)}:
            raise ValueError(f"{task_id}: its ships do not share encounters (no agents key); no target agents")
        preset = task_id.split("/", 1)[-1]
        targets = task_config(cls, config, dict(overrides), preset).max_targets
        self.penv = ShipParallelEnv(task_id, 1 + targets, config, **overrides)
        self.task = self.penv.task
        self.config = self.task.config
        self.sim = self.task.sim
        self.observation_layout = self.task.layout
        self.observation_space = self.penv.observation_space("ship_0")
        self.action_space = self.penv.action_space("ship_0")
        self.render_mode = None
        if max_episode_steps is not None:
            self.penv.max_cycles = int(max_episode_steps)
        self.penv.drive({f"ship_{k}": make_policy(self) for k in range(1, 1 + targets)})

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        obs, infos = self.penv.reset(seed=seed, options=options)
        return obs["ship_0"], infos["ship_0"]

    def step(self, action: Any):
        obs, rewards, terms, truncs, infos = self.penv.step({"ship_0": action})
        return obs["ship_0"], rewards["ship_0"], terms["ship_0"], truncs["ship_0"], infos["ship_0"]

    def pace(self, ticks: int = 1, on_tick: Any = None) -> None:
        self.penv.pace(ticks, on_tick)


def parallel_env(
    task_id: str, agents: int = 2, config: Any = None, driven: Mapping[str, Any] | None = None, **overrides: Any
) -> ShipParallelEnv:
    """A PettingZoo ``ParallelEnv`` of ``agents`` own ships of the registered task ``task_id`` (module doc), those
    named in ``driven`` steered by their policies rather than being agents; ``config`` and ``overrides`` as for
    ``gymnasium.make``."""
    return ShipParallelEnv(task_id, agents, config, driven, **overrides)
