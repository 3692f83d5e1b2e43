"""The single environment and its native vector twin over one task (N = 1 and N = num_envs vessels).

:class:`ShipEnv` is a task of N = 1; :class:`ShipVectorEnv` is the same task of N = num_envs, so single and
vector environments share every line of task code and vessel k of a vector environment seeded with s follows
exactly the trajectory of a single environment seeded with s + k.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any, ClassVar

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from vessel_gym.envs.generators import SeedRange, VesselGenerators
from vessel_gym.envs.task import PHASE_RESET, PHASE_STEP, Task, batch_info, reset_vessels, vessel_info


def task_overlay(task: Task, k: int) -> dict[str, Any]:
    """What the chart draws of vessel k besides the ship: the task's ``overlay(k)`` if it has one."""
    overlay = getattr(task, "overlay", None)
    return {} if overlay is None else overlay(k)


class _Renders:
    """The chart renderer an environment opens on its first render: closed with the environment, and left out
    of a pickled copy (a window or surface does not travel; the copy opens its own)."""

    _renderer: Any

    def _close_renderer(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    def __getstate__(self) -> dict:
        state = self.__dict__.copy()
        state["_renderer"] = None
        return state


def advance(sim: Any, nsub: int, ticks: int = 1, on_tick: Callable[[int], None] | None = None) -> None:
    """Advance ``sim`` one control step of ``nsub`` physics steps.

    With ``on_tick``, in ``ticks`` slices: after slice i (1..ticks) the physics has made ``i * nsub // ticks``
    of its steps and ``on_tick(i)`` is called (the same steps as one call, so the same states)."""
    if on_tick is None:
        sim.step(nsub)
        return
    done = 0
    for i in range(1, ticks + 1):
        due = i * nsub // ticks
        if due > done:
            sim.step(due - done)
            done = due
        on_tick(i)


class ShipEnv(_Renders, gym.Env):
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
        #: steps after which an episode is truncated, counted here (0: none; Gymnasium's TimeLimit may count)
        self._max_steps = 0
        self._elapsed = 0
        self._pacing: tuple[int, Callable[[int], None] | None] = (1, None)  # _advance's (ticks, on_tick)

    @classmethod
    def make_task(cls, config: Any, overrides: Mapping[str, Any], n: int) -> Task:
        return cls.Task.from_config(config, overrides, n)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self.task.rngs = (self.np_random,)
        self.task.reset_vessel(0, self.np_random, options)
        self.task.update(self._reset_phase)
        self._reset_done = True
        self._elapsed = 0
        if self.render_mode is not None:
            self._track = [(float(self.sim.north[0]), float(self.sim.east[0]))]
            if self.render_mode == "human":
                self.render()
        return self.task.obs[0].copy(), vessel_info(self.task, 0)

    def step(self, action: Any):
        if not self._reset_done:
            raise RuntimeError("call reset() before step()")
        task = self.task
        task.helm.apply_single(action)
        self._advance(*self._pacing)
        task.update(self._step_phase)
        if self.render_mode is not None:
            self._track.append((float(self.sim.north[0]), float(self.sim.east[0])))
            if self.render_mode == "human":
                self.render()
        terminated = task.terminated.item()
        self._elapsed += 1
        truncated = 0 < self._max_steps <= self._elapsed and not terminated
        return task.obs[0].copy(), task.reward.item(), terminated, truncated, vessel_info(task, 0)

    def _advance(self, ticks: int = 1, on_tick: Callable[[int], None] | None = None) -> None:
        """Advance the ship one control step (:func:`advance`)."""
        advance(self.sim, self.task.nsub, ticks, on_tick)

    def pace(self, ticks: int = 1, on_tick: Callable[[int], None] | None = None) -> None:
        """Run each step's physics in ``ticks`` slices and call ``on_tick(i)`` after slice i (1..ticks)
        (:meth:`_advance`): ``vessel-gym serve`` paces a control step to wall-clock time this way and services
        its link between slices. ``pace()`` steps at once again."""
        if ticks < 1:
            raise ValueError(f"ticks must be >= 1, got {ticks}")
        self._pacing = (int(ticks), on_tick)

    def __getstate__(self) -> dict:
        state = super().__getstate__()
        state["_pacing"] = (1, None)  # the pacer's clock and link stay with this environment
        return state

    def render(self):
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode='rgb_array' or 'human'")
            return None
        if self._renderer is None:
            from vessel_gym.ui.chart import task_renderer  # pygame is imported only here

            self._renderer = task_renderer(self.task, self.render_mode)
        return self._renderer.draw(
            self.sim,
            0,
            self._track,
            telegraph=self._telegraph(),
            overlay=task_overlay(self.task, 0),
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
        self._close_renderer()


# --- native vector environment ---------------------------------------------------------------------------------
class ShipVectorEnv(_Renders, VectorEnv):
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
        self._rngs: VesselGenerators | None = None
        self._steps = np.zeros(num_envs, dtype=np.int64)
        self._needs_reset = np.zeros(num_envs, dtype=np.bool_)
        self._all_reset = np.full(num_envs, PHASE_RESET, dtype=np.int8)
        self._renderer = None
        self._tracks: list[list[tuple[float, float]]] = [[] for _ in range(min(num_envs, 4))]
        self._reset_done = False

    def _reset_vessels(self, idx: np.ndarray, options: dict | None) -> None:
        reset_vessels(self.task, idx, options)
        self._steps[idx] = 0
        if self.render_mode is not None:
            for k in idx[idx < len(self._tracks)].tolist():
                self._tracks[k] = [(float(self.sim.north[k]), float(self.sim.east[k]))]

    def reset(self, *, seed: int | Sequence[int | None] | None = None, options: dict | None = None):
        super().reset(seed=seed if isinstance(seed, int) else None)
        n = self.num_envs
        if seed is None:
            seeds: Any = [None] * n
        elif isinstance(seed, int):
            seeds = SeedRange(seed, n)
        else:
            seeds = list(seed)
            if len(seeds) != n:
                raise ValueError(f"seed list must have {n} entries, got {len(seeds)}")
        if self._rngs is None:
            self._rngs = VesselGenerators(seeds)
        else:
            self._rngs.reseed(seeds)
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
        return self.task.obs.copy(), batch_info(self.task)

    def step(self, actions: Any):
        if not self._reset_done:
            raise RuntimeError("call reset() before step()")
        task = self.task
        n = self.num_envs
        a = task.helm.batch(actions, n)
        done_prev = self._needs_reset
        resets = bool(done_prev.any())
        if self.autoreset_mode == AutoresetMode.DISABLED and resets:
            raise RuntimeError("autoreset disabled: reset the finished sub-environments (options reset_mask)")
        task.helm.apply(a)
        self.sim.step(task.nsub)  # every vessel one control step
        if resets:
            self._reset_vessels(np.flatnonzero(done_prev), None)
            phase = np.where(done_prev, PHASE_RESET, PHASE_STEP).astype(np.int8)
        else:
            phase = task.phase
        task.update(phase)
        if resets:  # the vessels reset now took no step
            stepped = ~done_prev
            self._steps[stepped] += 1
            terminated = task.terminated & stepped
        else:  # every vessel stepped: no masks
            stepped = None
            self._steps += 1
            terminated = task.terminated.copy()
        if self.max_episode_steps:
            truncated = ~terminated & (self._steps >= self.max_episode_steps)
            if stepped is not None:
                truncated &= stepped
        else:
            truncated = np.zeros(n, dtype=np.bool_)
        rewards = task.reward.copy()
        obs = task.obs.copy()
        info = batch_info(task)
        done = terminated | truncated
        if self.render_mode is not None:
            for k in range(len(self._tracks)):
                if stepped is None or stepped[k]:
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
            obs[idx] = task.obs[idx]
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
            from vessel_gym.ui.chart import task_renderer  # pygame is imported only here

            self._renderer = task_renderer(self.task, "rgb_array")
        return tuple(
            self._renderer.draw(self.sim, k, self._tracks[k], telegraph=None, overlay=task_overlay(self.task, k))
            for k in range(len(self._tracks))
        )

    def close_extras(self, **kwargs: Any) -> None:
        self._close_renderer()
